#!/usr/bin/env python3
"""ctest `texel_probes`: tools/texel_probes finds the texels a bake evaluated, and
tools/texel_error.py scores them (issue 27's texel yardstick; a few seconds).

    python3 tools/test_texel_probes.py RADBAKE TEXEL_PROBES

On the shipped Cornell Box baked at 32 texels per unit:
- texel_probes writes 400 probes, 40 from each brightness decile, edge and inside texels both,
  the same bytes twice for one seed and others for another; with another --texel-density
  (another layout) it refuses the bake;
- every probe lies on a face of the bake's .ply with that face's normal;
- radbake reads its own solution at those probes (`--probes`, the saved solution) and finds the
  lightmap values the comments hold (what a bilinear lookup reads at each probe), within the
  tolerances below for inside texels and for edge texels;
- texel_error.py scores that probes.csv as a reference with the same figures, and exact ones on
  a literal probe file and reference.
Python standard library only.
"""
import json
import math
import os
import struct
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import texel_error  # noqa: E402
from harness import read_csv_rows  # noqa: E402

SCENE = os.path.join(HERE, "..", "scenes", "cornell_box.wrl")
DENSITY = "32"
# Inside texels, max channel, lightmap value against radbake's probe at the same point. The two
# read one solution at one point, the texel through the link reconstruction (and, where its
# block is smooth, bilinear interpolation within --texel-tolerance 0.02 of the medium preset,
# then half-float rounding), the probe through the exhaustive gather. Measured over all 1052
# inside texels of this bake: median 0.23 %, p95 0.8 %, worst 7 % (a floor texel beside the
# short block's foot, where the light changes fastest); over the 400 drawn: 0.21 %, 0.74 %,
# 1.5 %. A lookup one texel off moves the walls' values by several percent, the wrong row
# order or point by far more.
INSIDE_MEDIAN, INSIDE_P95, INSIDE_WORST = 0.01, 0.03, 0.10
# Edge texels: the bilinear lookup at the texel's sample point (where its centre lies off the
# chart, a point inside it) against the probe there. The seam fit moves edge texels and their
# padding so that lookups along the chart's edges give the light there, which these bounds leave
# room for; a lookup at the wrong point or with the wrong weights is off by several percent at the
# median. Measured on the 400 drawn: median 0.3 %, p95 2.3 %.
EDGE_MEDIAN, EDGE_P95 = 0.01, 0.05

failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAIL: " + message)


def run(command, expect=0):
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode != expect:
        raise RuntimeError("%s exited %d, not %d: %s" % (" ".join(command), result.returncode, expect, result.stderr))
    return result


def read_ply_polygons(path):
    """The faces of a radbake .ply as lists of (x, y, z) corners."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii").splitlines()
    counts = {line.split()[1]: int(line.split()[2]) for line in header if line.startswith("element")}
    sizes = {"float": 4, "uchar": 1}
    vertex_props = []
    in_vertex = False
    for line in header:
        if line.startswith("element"):
            in_vertex = line.split()[1] == "vertex"
        elif line.startswith("property") and in_vertex:
            vertex_props.append(line.split()[1])
    stride = sum(sizes[t] for t in vertex_props)
    positions = [struct.unpack_from("<3f", data, end + i * stride) for i in range(counts["vertex"])]
    at = end + stride * counts["vertex"]
    polygons = []
    for _ in range(counts["face"]):
        n = data[at]
        indices = struct.unpack_from("<%di" % n, data, at + 1)
        at += 1 + 4 * n
        polygons.append([positions[i] for i in indices])
    return polygons


def sub(a, b):
    return [x - y for x, y in zip(a, b)]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def on_triangle(p, n, a, b, c, tolerance):
    """p lies on triangle abc (within tolerance) and n is its front normal."""
    normal = cross(sub(b, a), sub(c, a))
    length = math.sqrt(dot(normal, normal))
    if length == 0.0 or dot(normal, n) < 0.999 * length:
        return False
    unit = [v / length for v in normal]
    if abs(dot(sub(p, a), unit)) > tolerance:
        return False
    edges = ((a, b), (b, c), (c, a))
    return all(dot(cross(sub(q, o), sub(p, o)), unit) >= -tolerance * math.sqrt(dot(sub(q, o), sub(q, o)))
               for o, q in edges)


def on_surface(probe, polygons, tolerance):
    p, n = probe["position"], probe["normal"]
    return any(on_triangle(p, n, poly[0], poly[k], poly[k + 1], tolerance)
               for poly in polygons for k in range(1, len(poly) - 1))


def read_normals(path):
    normals = []
    with open(path) as f:
        for line in f:
            body = line.partition("#")[0].split()
            if body:
                normals.append([float(v) for v in body[3:6]])
    return normals


def test_probes(radbake, texel_probes, tmp):
    bake, solution = os.path.join(tmp, "bake"), os.path.join(tmp, "cornell.sol")
    run([radbake, "bake", SCENE, "-o", bake, "--texel-density", DENSITY, "--quiet", "--threads", "1",
         "--solution", solution])
    probes = os.path.join(tmp, "texels.probes")
    run([texel_probes, SCENE, bake, probes, "--texel-density", DENSITY])
    texels = texel_error.read_texel_probes(probes)
    check(len(texels) == 400, "%d texel probes, want 400" % len(texels))
    for d in range(10):
        got = sum(1 for t in texels if t["decile"] == d)
        check(got == 40, "decile %d has %d probes, want 40" % (d, got))
    edges = sum(1 for t in texels if t["edge"])
    check(0 < edges < len(texels), "%d of %d probes are edge texels: want both kinds" % (edges, len(texels)))
    again, other = os.path.join(tmp, "again.probes"), os.path.join(tmp, "other.probes")
    run([texel_probes, SCENE, bake, again, "--texel-density", DENSITY])
    run([texel_probes, SCENE, bake, other, "--texel-density", DENSITY, "--seed", "2"])
    with open(probes, "rb") as a, open(again, "rb") as b, open(other, "rb") as c:
        first = a.read()
        check(first == b.read(), "one seed gives other bytes")
        check(first != c.read(), "another seed gives the same bytes")
    # --same-texels: the texels another probe file lists, in its order, whatever the seed.
    same = os.path.join(tmp, "same.probes")
    run([texel_probes, SCENE, bake, same, "--texel-density", DENSITY, "--seed", "7", "--same-texels", other])
    with open(other) as a, open(same) as b:
        listed = [l for l in a if not l.startswith("#")]
        check(listed == [l for l in b if not l.startswith("#")], "--same-texels: other texels than the file lists")
    with open(os.path.join(tmp, "bad.probes"), "w") as f:
        f.write("0 0 0 0 1 0 # atlas 0 texel 100000 5 edge decile 0 H 0 0 0 mesh 0 x\n")
    unknown = run([texel_probes, SCENE, bake, os.path.join(tmp, "none.probes"), "--texel-density", DENSITY,
                   "--same-texels", os.path.join(tmp, "bad.probes")], expect=1)
    check("bad.probes:1" in unknown.stderr, "--same-texels, a texel not in the bake: not located: %r" % unknown.stderr)
    refused = run([texel_probes, SCENE, bake, os.path.join(tmp, "no.probes"), "--texel-density", "30"], expect=1)
    check("error" in refused.stderr, "another layout: no error said: %r" % refused.stderr)
    check(not os.path.exists(os.path.join(tmp, "no.probes")), "another layout: a probe file was written")
    return bake, solution, probes, texels


def test_on_surfaces(bake, probes, texels):
    polygons = read_ply_polygons(os.path.join(bake, "cornell_box.ply"))
    xs = [v for poly in polygons for corner in poly for v in corner]
    tolerance = 1e-5 * (max(xs) - min(xs))
    normals = read_normals(probes)
    off = [i for i, t in enumerate(texels)
           if not on_surface({"position": t["position"], "normal": normals[i]}, polygons, tolerance)]
    check(not off, "%d probes off the bake's surfaces, the first %s" % (len(off), texels[off[0]] if off else None))


def test_read_back(radbake, tmp, solution, probes, texels):
    probed = os.path.join(tmp, "probed")
    run([radbake, "bake", SCENE, "-o", probed, "--texel-density", DENSITY, "--quiet", "--threads", "1",
         "--solution", solution, "--probes", probes])
    rows = read_csv_rows(os.path.join(probed, "probes.csv"))
    inside = sorted(abs(max(t["h"]) / max(float(r[k]) for k in "rgb") - 1.0)
                    for t, r in zip(texels, rows) if not t["edge"])
    median, p95, worst = texel_error.percentile(inside, 50), texel_error.percentile(inside, 95), inside[-1]
    print("inside texels against radbake's probes: median %.4f p95 %.4f worst %.4f" % (median, p95, worst))
    check(median <= INSIDE_MEDIAN, "inside texels: median |e| %.4f above %g" % (median, INSIDE_MEDIAN))
    check(p95 <= INSIDE_P95, "inside texels: p95 |e| %.4f above %g" % (p95, INSIDE_P95))
    check(worst <= INSIDE_WORST, "inside texels: worst |e| %.4f above %g" % (worst, INSIDE_WORST))
    edge = sorted(abs(max(t["h"]) / max(float(r[k]) for k in "rgb") - 1.0)
                  for t, r in zip(texels, rows) if t["edge"])
    edge_median, edge_p95 = texel_error.percentile(edge, 50), texel_error.percentile(edge, 95)
    print("edge texels against radbake's probes: median %.4f p95 %.4f worst %.4f" % (edge_median, edge_p95, edge[-1]))
    check(edge_median <= EDGE_MEDIAN, "edge texels: median |e| %.4f above %g" % (edge_median, EDGE_MEDIAN))
    check(edge_p95 <= EDGE_P95, "edge texels: p95 |e| %.4f above %g" % (edge_p95, EDGE_P95))
    scored = texel_error.score(texels, rows)
    check(scored["lit"] == len(texels), "texel_error: %d of %d lit" % (scored["lit"], len(texels)))
    check(abs(scored["by_edge"]["inside"]["median"] - median) < 1e-12,
          "texel_error's inside median %s, this test's %s" % (scored["by_edge"]["inside"]["median"], median))
    check(scored["all"]["noise"] is None, "texel_error: a noise figure without se columns")
    itself = texel_error.score(texel_error.with_values(texels, rows), rows)  # --bake: the probes scored
    check(itself["all"]["p95"] == 0.0, "texel_error --bake: probes.csv against itself %s" % itself["all"])


LITERAL_PROBES = """# fabricated
0 0 0 0 0 1 # atlas 0 texel 1 2 inside decile 0 H 1.1 0.5 0.5 mesh 3 floor
1 0 0 0 0 1 # atlas 0 texel 2 2 inside decile 1 H 0.9 0.1 0.1 mesh 3 floor
2 0 0 0 0 1 # atlas 0 texel 3 2 edge decile 2 H 3 3 3 mesh 4 wall one
3 0 0 0 0 1 # atlas 1 texel 0 0 edge decile 3 H 1 1 1 mesh 5 box
"""
LITERAL_REFERENCE = """x,y,z,nx,ny,nz,r,g,b,se_r,se_g,se_b
0,0,0,0,0,1,1,0.5,0.5,0.1,0.1,0.1
1,0,0,0,0,1,1,0.1,0.1,0.2,0.1,0.1
2,0,0,0,0,1,2,2,2,0.1,0.1,0.4
3,0,0,0,0,1,0.001,0,0,0,0,0
"""


def test_literal(tmp):
    probes, reference = os.path.join(tmp, "literal.probes"), os.path.join(tmp, "literal.csv")
    with open(probes, "w") as f:
        f.write(LITERAL_PROBES)
    with open(reference, "w") as f:
        f.write(LITERAL_REFERENCE)
    # Max channel: references 1, 1, 2 (median 1, floor 0.01: the fourth, 0.001, is not lit);
    # errors +0.1, -0.1, +0.5; se/ref 0.1, 0.2, 0.05 (the se of the max's channel, r).
    r = texel_error.score(texel_error.read_texel_probes(probes), read_csv_rows(reference))
    close = lambda a, b: abs(a - b) < 1e-9  # noqa: E731
    check(r["lit"] == 3 and close(r["median_ref"], 1.0), "literal: lit %d, median %s" % (r["lit"], r["median_ref"]))
    check(close(r["all"]["bias"], 0.5 / 3) and close(r["all"]["p95"], 0.5) and close(r["all"]["median"], 0.1),
          "literal: all %s" % r["all"])
    check(close(r["all"]["noise"], 0.35 / 3), "literal: noise %s" % r["all"]["noise"])
    check(r["by_edge"]["edge"]["n"] == 1 and close(r["by_edge"]["inside"]["bias"], 0.0), "literal: %s" % r["by_edge"])
    check(r["by_class"]["bright"]["n"] == 1 and r["by_class"]["mid"]["n"] == 2, "literal: %s" % r["by_class"])
    check(r["worst_meshes"][0]["name"] == "4 wall one", "literal: worst mesh %s" % r["worst_meshes"][0])
    check([m["name"] for m in r["worst_families"]] == ["wall one", "floor"], "literal: %s" % r["worst_families"])
    out = subprocess.run([sys.executable, os.path.join(HERE, "texel_error.py"), probes, reference, "--json"],
                         capture_output=True, text=True)
    check(out.returncode == 0 and json.loads(out.stdout)["lit"] == 3, "texel_error.py --json: %s" % out.stderr)


def main(argv):
    if len(argv) != 2:
        print(__doc__)
        return 2
    radbake, texel_probes = argv
    with tempfile.TemporaryDirectory() as tmp:
        bake, solution, probes, texels = test_probes(radbake, texel_probes, tmp)
        test_on_surfaces(bake, probes, texels)
        test_read_back(radbake, tmp, solution, probes, texels)
        test_literal(tmp)
    print("%d failure(s)" % len(failures))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
