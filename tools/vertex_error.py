#!/usr/bin/env python3
"""Per-vertex error of a bake against a Monte Carlo reference (the accuracy yardstick of issue 13).

    python3 tools/vertex_error.py BAKE_DIR REFERENCE.csv [--probes FILE] [--lit max|median]
                                  [--worst N] [--csv OUT.csv] [--json]

BAKE_DIR is a `radbake bake SCENE --probes FILE` output folder (its probes.csv; a probes.csv
path works too); with --vertices its .ply is read instead: the baked value of the output
vertex each probe was made from (the vertex with the probe's normal nearest to it), times pi:
what a vertex bake gives, where probes.csv is the solution read at the nudged points, REFERENCE.csv is `reference_mc SCENE FILE` on the same probe file
(tools/vertex_reference.sh writes both the probe file, one probe per vertex nudged into its own
face, and the reference). Rows are matched by order and their positions checked, as
tools/harness.py does.

On the grey irradiance g = (r + g + b) / 3 of each probe (H, W/m^2):
  - lit: the reference's g above 1 % of the maximum reference g (`--lit median`: 1 % of the
    median, issue 13's wording); the figures are over lit probes only;
  - e_i = (bake_i - ref_i) / ref_i, the relative error of probe i;
  - rms = sqrt(mean e_i^2); p95 = the 95th percentile of |e_i| (nearest rank); max = max |e_i|;
    bias = mean e_i;
  - ref_noise_rms = sqrt(mean (se_i / ref_i)^2), se_i = the mean of the reference's three
    channel standard errors (an upper bound on the grey's, the channels share their paths):
    the reference's own contribution to rms, which adds in quadrature.
With --probes (the probe file both were made from) the worst probes are named by the
`# mesh M vertex V` comments tools/vertex_probes writes. Python standard library only.
"""
import argparse
import glob
import json
import math
import os
import struct
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from harness import read_csv_rows, vec  # noqa: E402  (one CSV reader for every scoring tool)


def grey(row):
    return sum(vec(row, "rgb")) / 3.0


def same_position(row, ref_row):
    # harness.compare's criterion: the probe file both were made from, printed with %.9g.
    return max(abs(float(row[k]) - float(ref_row[k])) for k in ("x", "y", "z")) <= 1e-6 * (1.0 + abs(float(ref_row["x"])))


def lit_mask(reference_rows, lit="max"):
    values = [grey(r) for r in reference_rows]
    if not values:
        return [], 0.0
    ordered = sorted(values)
    basis = ordered[-1] if lit == "max" else ordered[len(ordered) // 2]
    floor = 0.01 * basis
    return [v > floor for v in values], floor


def reference_noise(reference_rows, mask):
    """sqrt(mean (se/ref)^2) over the masked rows, or None without se columns."""
    if not reference_rows or "se_r" not in reference_rows[0]:
        return None
    terms = []
    for row, keep in zip(reference_rows, mask):
        if keep:
            se = sum(float(row[k]) for k in ("se_r", "se_g", "se_b")) / 3.0
            terms.append((se / grey(row)) ** 2)
    return math.sqrt(sum(terms) / len(terms)) if terms else None


def percentile(sorted_values, q):
    """Nearest-rank percentile of an ascending list."""
    if not sorted_values:
        return float("nan")
    rank = max(1, int(math.ceil(q / 100.0 * len(sorted_values))))
    return sorted_values[rank - 1]


def score(bake_rows, reference_rows, lit="max"):
    if len(bake_rows) != len(reference_rows):
        raise ValueError("the bake has %d probes, the reference %d" % (len(bake_rows), len(reference_rows)))
    mask, floor = lit_mask(reference_rows, lit)
    errors = []  # (relative error, index)
    for i, (row, ref_row, keep) in enumerate(zip(bake_rows, reference_rows, mask)):
        if not same_position(row, ref_row):
            raise ValueError("probe %d: position differs from the reference: %s" % (i, row))
        if keep:
            ref = grey(ref_row)
            errors.append(((grey(row) - ref) / ref, i))
    magnitudes = sorted(abs(e) for e, _ in errors)
    n = len(errors)
    result = {
        "probes": len(reference_rows), "lit": n, "lit_floor": floor, "lit_rule": "1% of the " + lit,
        "rms": math.sqrt(sum(e * e for e, _ in errors) / n) if n else float("nan"),
        "p95": percentile(magnitudes, 95.0),
        "max": magnitudes[-1] if magnitudes else float("nan"),
        "bias": sum(e for e, _ in errors) / n if n else float("nan"),
        "ref_noise_rms": reference_noise(reference_rows, mask),
    }
    return result, errors


def read_ply_vertices(path):
    """(x, y, z, nx, ny, nz, red, green, blue) of every vertex of a radbake .ply (binary, floats)."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii").splitlines()
    count = next(int(line.split()[2]) for line in header if line.startswith("element vertex"))
    start = next(i for i, line in enumerate(header) if line.startswith("element vertex")) + 1
    properties = []  # (type, name) of the vertex element's properties, up to the next element
    for line in header[start:]:
        if not line.startswith("property"):
            break
        properties.append((line.split()[1], line.split()[-1]))
    wanted = ("x", "y", "z", "nx", "ny", "nz", "red", "green", "blue")
    if tuple(properties[:9]) != tuple(("float", n) for n in wanted):
        raise ValueError("%s: expected float vertex properties %s, found %s" % (path, wanted, properties))
    # A lightmapped bake adds u1 v1 and a uchar atlas index after them.
    sizes = {"char": 1, "uchar": 1, "short": 2, "ushort": 2, "int": 4, "uint": 4, "float": 4, "double": 8}
    stride = sum(sizes[t] for t, _ in properties)
    return [struct.unpack_from("<9f", data, end + i * stride) for i in range(count)]


def vertex_rows(bake_dir, reference_rows):
    """Bake rows for the reference's probes from the .ply's vertices: pi x the value of the vertex
    with the probe's normal nearest to the probe (the nudge is 1e-4 of the diagonal)."""
    plys = sorted(glob.glob(os.path.join(bake_dir, "*.ply")))
    if len(plys) != 1:
        raise ValueError("%s: expected one .ply, found %d" % (bake_dir, len(plys)))
    vertices = read_ply_vertices(plys[0])
    lo = [min(v[k] for v in vertices) for k in range(3)]
    hi = [max(v[k] for v in vertices) for k in range(3)]
    cell = max(1e-12, 1e-3 * math.sqrt(sum((b - a) ** 2 for a, b in zip(lo, hi))))
    grid = {}
    for i, v in enumerate(vertices):
        grid.setdefault(tuple(int(math.floor(v[k] / cell)) for k in range(3)), []).append(i)
    rows = []
    for ref in reference_rows:
        q = [float(ref[k]) for k in ("x", "y", "z")]
        n = [float(ref[k]) for k in ("nx", "ny", "nz")]
        key = [int(math.floor(q[k] / cell)) for k in range(3)]
        best, best_d = None, float("inf")
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                for dz in (-1, 0, 1):
                    for i in grid.get((key[0] + dx, key[1] + dy, key[2] + dz), ()):
                        v = vertices[i]
                        if sum(v[3 + k] * n[k] for k in range(3)) < 0.999:
                            continue
                        d = sum((v[k] - q[k]) ** 2 for k in range(3))
                        if d < best_d:
                            best, best_d = v, d
        if best is None:
            raise ValueError("no output vertex with normal %s near probe at %s" % (n, q))
        row = dict(ref)
        row["r"], row["g"], row["b"] = (math.pi * best[6], math.pi * best[7], math.pi * best[8])
        rows.append(row)
    return rows


def probe_labels(path):
    """The comment of every probe line of a probe file, in order (what vertex_probes writes)."""
    labels = []
    with open(path) as f:
        for line in f:
            body, _, comment = line.partition("#")
            if body.strip():
                labels.append(comment.strip())
    return labels


def main(argv):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("bake", help="a radbake bake folder (its probes.csv is read) or a probes.csv")
    p.add_argument("reference", help="reference_mc's CSV for the same probe file")
    p.add_argument("--probes", help="the probe file, to name the worst probes")
    p.add_argument("--vertices", action="store_true", help="score the .ply's output vertices, not probes.csv")
    p.add_argument("--lit", choices=("max", "median"), default="max", help="lit: reference above 1%% of this")
    p.add_argument("--worst", type=int, default=5, help="how many of the worst probes to list")
    p.add_argument("--csv", help="write every lit probe's x,y,z,reference,bake,rel_error here")
    p.add_argument("--json", action="store_true", help="print the figures as one JSON object")
    args = p.parse_args(argv[1:])

    reference_rows = read_csv_rows(args.reference)
    try:
        if args.vertices:
            bake_rows = vertex_rows(args.bake, reference_rows)
        else:
            bake_csv = os.path.join(args.bake, "probes.csv") if os.path.isdir(args.bake) else args.bake
            bake_rows = read_csv_rows(bake_csv)
        result, errors = score(bake_rows, reference_rows, args.lit)
    except ValueError as e:
        sys.stderr.write("vertex_error: error: %s\n" % e)
        return 1
    labels = probe_labels(args.probes) if args.probes else []
    if args.csv:
        with open(args.csv, "w", newline="\n") as f:
            f.write("x,y,z,reference,bake,rel_error\n")
            for e, i in errors:
                r = reference_rows[i]
                f.write("%s,%s,%s,%.9g,%.9g,%.6g\n" % (r["x"], r["y"], r["z"], grey(r), grey(bake_rows[i]), e))
    if args.json:
        print(json.dumps(result, sort_keys=True))
        return 0
    noise = result["ref_noise_rms"]
    print("probes %d, lit %d (reference grey > %.4g W/m^2, %s)" % (
        result["probes"], result["lit"], result["lit_floor"], result["lit_rule"]))
    print("rms %.2f %%   p95 %.2f %%   max %.2f %%   bias %+.2f %%   reference noise rms %s" % (
        100 * result["rms"], 100 * result["p95"], 100 * result["max"], 100 * result["bias"],
        "%.2f %%" % (100 * noise) if noise is not None else "n/a"))
    for e, i in sorted(errors, key=lambda t: -abs(t[0]))[:max(0, args.worst)]:
        r = reference_rows[i]
        label = labels[i] if i < len(labels) else "probe %d" % i
        print("  %+7.2f %%  at %s %s %s (normal %s %s %s)  reference %.5g  bake %.5g  %s" % (
            100 * e, r["x"], r["y"], r["z"], r["nx"], r["ny"], r["nz"], grey(r), grey(bake_rows[i]), label))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
