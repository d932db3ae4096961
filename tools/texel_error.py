#!/usr/bin/env python3
"""A bake's lightmap at its texels against a reference (issue 27's texel yardstick).

    python3 tools/texel_error.py TEXEL.probes REFERENCE.csv [--channel max|grey|r|g|b] [--bake PROBES.csv]
                                 [--json]

TEXEL.probes is what tools/texel_probes wrote for a bake: one probe at the sample point of each
chosen texel, its comment holding the lightmap's value there (H = pi x its bilinear lookup at the
point, W/m^2), its atlas texel, edge or inside, its brightness decile and its mesh. REFERENCE.csv is
`reference_mc SCENE TEXEL.probes -o REFERENCE.csv` (x..nz, r, g, b, se_r, se_g, se_b), or any
probes.csv of the same probe file (no se columns: no noise figure). Rows are matched by order
and their positions checked. With --bake, the values scored are that probes.csv's instead of the
lightmap's (`radbake bake --probes TEXEL.probes --solution ...`: the same solution read at the same
points by the probe read-out), which tells the solution's error from the lightmap's.

On one channel of each probe's H (`max`, the default: the largest of r, g, b, a luminance-like
figure that a dark colour channel cannot blow up; `grey` the mean; or r, g or b):
  - lit: the reference above 1 % of the median of the references above 0 (the faces no path
    brings light to, such as a closed room's outsides, would otherwise set the scale); every
    figure is over lit texels;
  - e = (bake - ref) / ref; bias = mean e (a few texels far too bright dominate it, so the
    signed median of e is printed beside it); median and p95 (nearest rank) of |e|;
  - noise = mean se / ref, the reference's own standard error relative to its value (for max:
    the se of the channel the max is taken on; for grey: the mean of the three, an upper bound);
split by edge / inside texel, by brightness class of the reference (shadow below 0.1 x the
median, mid up to 2 x the median, bright above), by decile of the bake's brightness (the
stratum texel_probes drew it from), and the 10 meshes, and the 10 mesh families (the name without
its trailing _N and " (back)": a scene's 40 shelf boards are one family), with the largest mean |e|.
Python standard library only.
"""
import argparse
import json
import math
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from harness import read_csv_rows  # noqa: E402  (one CSV reader for every scoring tool)
from vertex_error import percentile  # noqa: E402

LABEL = re.compile(r"#\s*atlas (\d+) texel (\d+) (\d+) (edge|inside) decile (\d+) "
                   r"H (\S+) (\S+) (\S+) mesh (\d+) (.*)$")
CHANNELS = ("max", "grey", "r", "g", "b")
SHADOW, BRIGHT = 0.1, 2.0  # brightness classes, in medians of the reference


def read_texel_probes(path):
    """Each probe line of a texel_probes file as a dict; lines without a probe are skipped."""
    texels = []
    with open(path) as f:
        for number, line in enumerate(f, 1):
            body, _, comment = line.partition("#")
            if not body.split():
                continue
            label = LABEL.match("#" + comment.rstrip("\n"))
            if not label:
                raise ValueError("%s:%d: no texel_probes comment" % (path, number))
            g = label.groups()
            texels.append({"position": [float(v) for v in body.split()[:3]], "atlas": int(g[0]),
                           "texel": (int(g[1]), int(g[2])), "edge": g[3] == "edge", "decile": int(g[4]),
                           "h": [float(v) for v in g[5:8]], "mesh": "%s %s" % (g[8], g[9].strip())})
    return texels


def pick(rgb, se, channel):
    """The channel's value and standard error (None without se columns)."""
    if channel == "max":
        k = max(range(3), key=lambda c: rgb[c])
        return rgb[k], se[k] if se else None
    if channel == "grey":
        return sum(rgb) / 3.0, sum(se) / 3.0 if se else None
    k = "rgb".index(channel)
    return rgb[k], se[k] if se else None


def reference_values(rows, channel):
    has_se = bool(rows) and "se_r" in rows[0]
    out = []
    for row in rows:
        rgb = [float(row[k]) for k in ("r", "g", "b")]
        se = [float(row[k]) for k in ("se_r", "se_g", "se_b")] if has_se else None
        out.append(pick(rgb, se, channel))
    return out


def check_positions(texels, rows):
    if len(texels) != len(rows):
        raise ValueError("the probe file has %d probes, the reference %d rows" % (len(texels), len(rows)))
    for i, (t, row) in enumerate(zip(texels, rows)):
        ref = [float(row[k]) for k in "xyz"]
        if max(abs(a - b) for a, b in zip(t["position"], ref)) > 1e-6 * (1.0 + max(abs(v) for v in ref)):
            raise ValueError("probe %d: at %s in the probe file, %s in the reference" % (i, t["position"], ref))


def with_values(texels, rows):
    """The texels with H taken from probes.csv rows of the same probe file."""
    check_positions(texels, rows)
    return [dict(t, h=[float(row[k]) for k in "rgb"]) for t, row in zip(texels, rows)]


def summary(samples):
    """bias, median |e|, p95 |e| and noise over samples [(e, noise or None)]."""
    if not samples:
        return {"n": 0}
    magnitudes = sorted(abs(e) for e, _ in samples)
    noises = [s for _, s in samples if s is not None]
    return {"n": len(samples), "bias": sum(e for e, _ in samples) / len(samples),
            "median_signed": percentile(sorted(e for e, _ in samples), 50.0),
            "median": percentile(magnitudes, 50.0), "p95": percentile(magnitudes, 95.0),
            "noise": sum(noises) / len(noises) if noises else None}


def brightness_class(ref, median):
    return "shadow" if ref < SHADOW * median else "bright" if ref >= BRIGHT * median else "mid"


def grouped(samples, key):
    groups = {}
    for s in samples:
        groups.setdefault(key(s), []).append((s["e"], s["noise"]))
    return {k: summary(v) for k, v in groups.items()}


def family(mesh):
    """'12 shelf_wood_3 (back)' -> 'shelf_wood'."""
    name = mesh.split(" ", 1)[1] if " " in mesh else mesh
    return re.sub(r"(_\d+)?( \(back\))?$", "", name)


def worst(samples, key, count=10):
    groups = grouped(samples, key)
    for name, g in groups.items():
        g["mean_abs"] = sum(abs(s["e"]) for s in samples if key(s) == name) / g["n"]
    ranked = sorted(groups.items(), key=lambda kv: (-kv[1]["mean_abs"], kv[0]))[:count]
    return [dict(name=name, **g) for name, g in ranked]


def score(texels, rows, channel="max"):
    check_positions(texels, rows)
    refs = reference_values(rows, channel)
    ordered = sorted(v for v, _ in refs if v > 0.0)
    median = ordered[len(ordered) // 2] if ordered else 0.0
    floor = 0.01 * median
    samples = []
    for t, (ref, se) in zip(texels, refs):
        if not ref > floor:
            continue
        bake, _ = pick(t["h"], None, channel)
        samples.append({"e": (bake - ref) / ref, "noise": se / ref if se is not None else None, "edge": t["edge"],
                        "class": brightness_class(ref, median), "decile": t["decile"], "mesh": t["mesh"]})
    return {"channel": channel, "probes": len(texels), "lit": len(samples), "median_ref": median, "floor": floor,
            "all": summary([(s["e"], s["noise"]) for s in samples]),
            "by_edge": grouped(samples, lambda s: "edge" if s["edge"] else "inside"),
            "by_class": grouped(samples, lambda s: s["class"]),
            "by_decile": grouped(samples, lambda s: s["decile"]),
            "worst_meshes": worst(samples, lambda s: s["mesh"]),
            "worst_families": worst(samples, lambda s: family(s["mesh"]))}


def line(name, s):
    if not s.get("n"):
        return "  %-36s n=0" % name
    noise = "%.4f" % s["noise"] if s.get("noise") is not None else "-"
    return "  %-36s n=%-4d bias %+9.4f  median e %+.4f  median |e| %.4f  p95 |e| %8.4f  noise %s" % (
        name, s["n"], s["bias"], s["median_signed"], s["median"], s["p95"], noise)


def report(r):
    out = ["channel %s; %d probes, %d lit (reference above %.4g W/m^2, 1%% of the median lit reference %.4g)" %
           (r["channel"], r["probes"], r["lit"], r["floor"], r["median_ref"]),
           "e = (bake - ref) / ref; bias = mean e; noise = mean se / ref (the reference's own error)",
           line("all", r["all"])]
    out += [line(k, r["by_edge"][k]) for k in ("inside", "edge") if k in r["by_edge"]]
    out.append("by reference brightness (shadow < %g x median <= mid < %g x median <= bright):" % (SHADOW, BRIGHT))
    out += [line(k, r["by_class"][k]) for k in ("shadow", "mid", "bright") if k in r["by_class"]]
    out.append("by decile of the bake's brightness:")
    out += [line("decile %d" % d, r["by_decile"][d]) for d in sorted(r["by_decile"])]
    for title, key in (("meshes", "worst_meshes"), ("mesh families", "worst_families")):
        out.append("worst %s by mean |e|:" % title)
        out += [line(m["name"][:36], m) + "  mean|e| %.4f" % m["mean_abs"] for m in r[key]]
    return "\n".join(out)


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("probes", help="texel_probes output")
    parser.add_argument("reference", help="reference_mc CSV (or a probes.csv) of that probe file")
    parser.add_argument("--channel", choices=CHANNELS, default="max")
    parser.add_argument("--bake", help="score this probes.csv of the same probes instead of the lightmap values")
    parser.add_argument("--json", action="store_true", help="print the figures as one JSON object")
    args = parser.parse_args(argv)
    try:
        texels = read_texel_probes(args.probes)
        if args.bake:
            texels = with_values(texels, read_csv_rows(args.bake))
        result = score(texels, read_csv_rows(args.reference), args.channel)
    except (OSError, ValueError, KeyError) as e:
        print("texel_error: error: %s" % e, file=sys.stderr)
        return 1
    if args.json:
        result["by_decile"] = {str(k): v for k, v in result["by_decile"].items()}
        print(json.dumps(result, indent=1, sort_keys=True))
    else:
        print(report(result))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
