#!/usr/bin/env python3
"""ctest `vertex_error_map`: tools/vertex_error_map.py draws what it is given (under a second).

    python3 tools/test_vertex_error_map.py

On a literal CSV of vertex_error.py's columns with one probe on each room wall, one on a block's
top and one at a block's foot (1.7e-4 above the floor):
  - the SVG parses, with one square per CSV row, and two inputs give two rows' worth;
  - the +5 % probe (on the floor) is drawn red-ish, the -5 % one (on the ceiling) blue-ish, a 0 %
    one white, and --scale 0.05 saturates the +5 % one to the scale's full red;
  - each probe lands in its panel (the panel's label counts it): the foot probe on the block's
    side, not the floor; a probe in mid-air is left out and said so;
  - two runs on the same input give the same bytes;
  - the blocks the tool draws are those tools/gen_cornell_tessellated.py builds.
Python standard library only.
"""
import os
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import gen_cornell_tessellated  # noqa: E402
import vertex_error_map  # noqa: E402

SVG = "{http://www.w3.org/2000/svg}"
TOOL = os.path.join(HERE, "vertex_error_map.py")

failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAIL: " + message)


# (x, y, z, rel_error, the panel it belongs to)
PROBES = [
    (0.5, 0.0, 0.5, 0.05, "floor"),
    (0.25, 1.0, 0.75, -0.05, "ceiling"),
    (0.5, 0.5, 0.0, 0.0, "back wall (z=0)"),
    (0.5, 0.5, 1.0, 0.01, "front wall (z=1)"),
    (0.0, 0.5, 0.5, -0.01, "red wall (x=0)"),
    (1.0, 0.5, 0.5, 0.02, "green wall (x=1)"),
    (0.337, 0.6, 0.372, -0.02, "top"),       # the tall block's top, at its centre
    (0.666 + 0.15 * 0.956304756, 0.000165, 0.698 + 0.15 * 0.292371705, 0.03, "right"),  # the short block's right side, at its foot
]


def write_csv(path, probes):
    with open(path, "w", newline="\n") as f:
        f.write("x,y,z,reference,bake,rel_error\n")
        for x, y, z, e, _ in probes:
            f.write("%.9g,%.9g,%.9g,1,%.9g,%.6g\n" % (x, y, z, 1 + e, e))


def run(args):
    result = subprocess.run([sys.executable, TOOL] + args, capture_output=True, text=True)
    return result.returncode, result.stdout, result.stderr


def squares(root):
    groups = [g for g in root.iter(SVG + "g") if g.get("class") == "probes"]
    return [r for g in groups for r in g.iter(SVG + "rect")]


def rgb(fill):
    return tuple(int(fill[i:i + 2], 16) for i in (1, 3, 5))


def texts(root):
    return [t.text for t in root.iter(SVG + "text")]


def test_map(tmp):
    one = os.path.join(tmp, "one.csv")
    write_csv(one, PROBES)
    a, b = os.path.join(tmp, "a.svg"), os.path.join(tmp, "b.svg")
    for out in (a, b):
        code, _, err = run([one, "-o", out])
        check(code == 0, "map: exit %d: %s" % (code, err))
    with open(a, "rb") as fa, open(b, "rb") as fb:
        check(fa.read() == fb.read(), "map: two runs give different bytes")
    root = ET.parse(a).getroot()
    rects = squares(root)
    check(len(rects) == len(PROBES), "map: %d squares for %d rows" % (len(rects), len(PROBES)))
    fills = [rgb(r.get("fill")) for r in rects]
    reds = [f for f in fills if f[0] > f[2] + 60 and f[0] > f[1] + 60]
    blues = [f for f in fills if f[2] > f[0] + 60]
    whites = [f for f in fills if f == (255, 255, 255)]
    check(len(reds) == 1, "map: %d red-ish squares, want 1 (the +5 %% floor probe): %s" % (len(reds), fills))
    check(len(blues) == 1, "map: %d blue-ish squares, want 1 (the -5 %% ceiling probe): %s" % (len(blues), fills))
    check(len(whites) == 1, "map: %d white squares, want 1 (the 0 %% probe): %s" % (len(whites), fills))
    check(vertex_error_map.colour(0.05, 0.1) in [r.get("fill") for r in rects], "map: no square has +5 %%'s colour")
    # Every probe in its panel: a panel's name is followed by its "RMS ..., n N" line.
    lines = texts(root)
    for x, y, z, e, panel in PROBES:
        want = "RMS %.2f %%, n 1" % (100 * abs(e))
        got = [lines[i + 1] for i, t in enumerate(lines[:-1]) if t == panel]
        check(want in got, "map: panel %s: %s, want %r" % (panel, got, want))
    check(not any("on no surface" in (t or "") for t in lines), "map: a probe left out")
    # --scale 0.05: +5 % is the full red.
    code, _, err = run([one, "-o", a, "--scale", "0.05"])
    fills = [r.get("fill") for r in squares(ET.parse(a).getroot())]
    check(code == 0 and "#%02x%02x%02x" % vertex_error_map.POSITIVE in fills, "map: --scale 0.05 does not saturate +5 %%: %s" % fills)
    # Two labelled inputs: two rows; a probe in mid-air is left out and counted.
    two = os.path.join(tmp, "two.csv")
    write_csv(two, PROBES + [(0.5, 0.5, 0.5, 0.0, None)])
    code, _, err = run(["--label", "before", one, "--label", "after", two, "-o", b])
    check(code == 0, "map: two inputs: exit %d: %s" % (code, err))
    root = ET.parse(b).getroot()
    check(len(squares(root)) == 2 * len(PROBES), "map: two rows: %d squares, want %d" % (len(squares(root)), 2 * len(PROBES)))
    heads = [t for t in texts(root) if t and (t.startswith("before:") or t.startswith("after:"))]
    check(len(heads) == 2 and heads[0].startswith("before:") and "1 on no surface, left out" in heads[1],
          "map: row headings %s" % heads)
    check("on no surface" in err, "map: the left-out probe is not reported: %r" % err)
    code, _, err = run(["--label", "only one", one, two, "-o", b])
    check(code != 0, "map: one --label for two CSVs is accepted")


def test_blocks_match_generator():
    faces = {f.name: f for f in gen_cornell_tessellated.build()}
    for block, prefix in zip(vertex_error_map.BLOCKS, ("tall_box", "short_box")):
        b = vertex_error_map.Block(*block)
        top = faces[prefix + "_top"]
        heights = {round(p[1], 9) for p in top.vertices}
        check(heights == {round(b.h, 9)}, "blocks: %s top at %s, the tool's at %g" % (prefix, heights, b.h))
        corners = {(round(p[0], 6), round(p[2], 6)) for p in top.vertices}
        for x, z in b.footprint():
            check((round(x, 6), round(z, 6)) in corners, "blocks: %s: corner %.6f %.6f not the generator's" % (prefix, x, z))
    lamp = faces["light"]
    xs = sorted({p[0] for p in lamp.vertices})
    check(abs(xs[0] - vertex_error_map.LAMP[0]) < 1e-9 and abs(xs[-1] - vertex_error_map.LAMP[1]) < 1e-9
          and all(abs(p[1] - vertex_error_map.LAMP[2]) < 1e-9 for p in lamp.vertices), "blocks: the lamp differs")


def main(argv):
    if len(argv) != 1:
        sys.stderr.write("usage: test_vertex_error_map.py\n")
        return 2
    with tempfile.TemporaryDirectory() as tmp:
        test_map(tmp)
    test_blocks_match_generator()
    print("%d failure(s)" % len(failures))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
