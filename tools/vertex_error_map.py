#!/usr/bin/env python3
"""Where the vertex error of the tessellated Cornell box sits (issue 13): a false-colour map, as SVG.

    python3 tools/vertex_error_map.py [--label TEXT] ERRORS.csv [[--label TEXT] ERRORS.csv ...]
                                      [-o OUT.svg] [--scale 0.1] [--title TEXT]

Each ERRORS.csv is what `tools/vertex_error.py BAKE REFERENCE --csv ERRORS.csv` writes
(x,y,z,reference,bake,rel_error, one row per lit probe) for the scene of
tools/gen_cornell_tessellated.py. Every input is one row of the picture, in the order given (so
`--label before A.csv --label after B.csv` puts the two one above the other); the i-th --label
names the i-th CSV (give one per CSV or none: the file's name is the default).

Layout of a row:
  - the room [0,1]^3 unfolded as a cross, seen from inside: the floor in the centre (back wall
    up, the red wall x=0 left), the four walls folded out around it, each hinged on its edge
    with the floor (red x=0 left, green x=1 right, back z=0 above, front z=1 below), and the
    ceiling folded on beyond the back wall (hinged on the back wall's top edge, so the lamp is in
    its middle). The blocks' footprints are outlined on the floor, the lamp on the ceiling;
  - at twice the scale, each block's four sides unrolled in one strip as seen from outside, feet
    down, in the order front, right, back, left (each side is named after the room wall it faces,
    to within the blocks' 17 degrees; neighbours in the strip share their vertical edge), then
    its top seen from above (front edge down); and the lamp's underside seen from below like the
    ceiling (its probes, if lit, are off the ceiling's plane by 1 cm).
A probe belongs to the surface nearest to it among the six room planes, the lamp and the
blocks' ten faces (the probes sit on their face, nudged along it, so a block's foot probes,
1.7e-4 above the floor, go to the block, not the floor); one more than 1e-3 from every surface
is left out and counted. Each probe is a square at its unfolded position (pulled inside its
panel at the panel's edge), coloured by its relative error on a diverging scale: blue below the
reference, white on it, red above, saturating at +-SCALE (0.1 = 10 %). The worst probe of each
panel is outlined in black. Above each panel: its name, the RMS of its probes' relative errors,
its worst error and its probe count; above each row, the row's RMS and bias over all its probes
(vertex_error.py's figures). The same input gives the same bytes. Python standard library only.
"""
import argparse
import csv
import math
import os
import sys

TOLERANCE = 1e-3  # metres: a probe further than this from every surface is left out
BLOCKS = (  # name, centre x, centre z, width (x), height, depth (z), degrees about +y: as tools/gen_cornell_tessellated.py
    ("tall block", 0.337, 0.372, 0.3, 0.6, 0.3, 17.0),
    ("short block", 0.666, 0.698, 0.3, 0.3, 0.3, -17.0),
)
LAMP = (0.4, 0.6, 0.99)  # x and z from 0.4 to 0.6, at y = 0.99, facing down

ROOM_SCALE = 170.0   # px per metre in the room's cross
BLOCK_SCALE = 340.0  # px per metre on the blocks and the lamp
SQUARE = 8.0         # px, one probe
GAP = 12.0           # px between panels side by side
SIDE_GAP = 6.0       # px between a block's sides in its strip
LABEL_BAND = 42.0    # px above every panel: its three label lines
BLOCK_HEADER = 16.0  # px above a block's strip: its name
MARGIN = 20.0
POSITIVE = (178, 24, 43)  # +SCALE and beyond
NEGATIVE = (33, 102, 172)  # -SCALE and beyond
PANEL_FILL = "#c8c8c8"


class Block:
    def __init__(self, name, cx, cz, width, height, depth, degrees):
        self.name, self.cx, self.cz = name, cx, cz
        self.w, self.h, self.d = width, height, depth
        a = math.radians(degrees)
        self.ex = (math.cos(a), -math.sin(a))  # R_y(a) applied to +x, as (x, z)
        self.ez = (math.sin(a), math.cos(a))   # R_y(a) applied to +z

    def local(self, x, z):
        dx, dz = x - self.cx, z - self.cz
        return dx * self.ex[0] + dz * self.ex[1], dx * self.ez[0] + dz * self.ez[1]

    def footprint(self):
        """The four foot corners (x, z), counter-clockwise seen from above."""
        out = []
        for sx, sz in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
            lx, lz = sx * self.w / 2, sz * self.d / 2
            out.append((self.cx + lx * self.ex[0] + lz * self.ez[0], self.cz + lx * self.ex[1] + lz * self.ez[1]))
        return out


def inside(value, lo, hi):
    return lo - TOLERANCE <= value <= hi + TOLERANCE


def clamp01(t):
    return min(1.0, max(0.0, t))


def surfaces(blocks):
    """(panel name, function (x, y, z) -> (distance, u, v) or None): u right, v down in the panel."""
    out = [
        ("ceiling", lambda x, y, z: (abs(y - 1.0), x, 1.0 - z) if inside(x, 0, 1) and inside(z, 0, 1) else None),
        ("back wall (z=0)", lambda x, y, z: (abs(z), x, 1.0 - y) if inside(x, 0, 1) and inside(y, 0, 1) else None),
        ("red wall (x=0)", lambda x, y, z: (abs(x), 1.0 - y, z) if inside(y, 0, 1) and inside(z, 0, 1) else None),
        ("floor", lambda x, y, z: (abs(y), x, z) if inside(x, 0, 1) and inside(z, 0, 1) else None),
        ("green wall (x=1)", lambda x, y, z: (abs(x - 1.0), y, z) if inside(y, 0, 1) and inside(z, 0, 1) else None),
        ("front wall (z=1)", lambda x, y, z: (abs(z - 1.0), x, y) if inside(x, 0, 1) and inside(y, 0, 1) else None),
    ]
    lo, hi, height = LAMP
    out.append(("lamp", lambda x, y, z: (abs(y - height), (x - lo) / (hi - lo), (hi - z) / (hi - lo))
                if inside(x, lo, hi) and inside(z, lo, hi) else None))
    for b in blocks:
        out.extend(block_surfaces(b))
    return out


def block_surfaces(b):
    w, h, d = b.w / 2, b.h, b.d / 2

    def side(kind):
        def f(x, y, z):
            lx, lz = b.local(x, z)
            if not inside(y, 0, h):
                return None
            v = (h - y) / h
            if kind == "front" and inside(lx, -w, w):
                return abs(lz - d), (lx + w) / b.w, v
            if kind == "right" and inside(lz, -d, d):
                return abs(lx - w), (d - lz) / b.d, v
            if kind == "back" and inside(lx, -w, w):
                return abs(lz + d), (w - lx) / b.w, v
            if kind == "left" and inside(lz, -d, d):
                return abs(lx + w), (lz + d) / b.d, v
            return None
        return f

    def top(x, y, z):
        lx, lz = b.local(x, z)
        if inside(lx, -w, w) and inside(lz, -d, d):
            return abs(y - h), (lx + w) / b.w, (lz + d) / b.d
        return None

    return [(b.name + " " + k, side(k)) for k in ("front", "right", "back", "left")] + [(b.name + " top", top)]


def classify(points, blocks):
    """The panel name and (u, v) in [0,1]^2 of every point, or None when it is on no surface."""
    table = surfaces(blocks)
    out = []
    for x, y, z in points:
        best = None
        for name, f in table:
            hit = f(x, y, z)
            if hit is not None and hit[0] <= TOLERANCE and (best is None or hit[0] < best[0]):
                best = (hit[0], name, clamp01(hit[1]), clamp01(hit[2]))
        out.append(None if best is None else (best[1], best[2], best[3]))
    return out


def layout(blocks):
    """Panel name -> (x, y, width, height) in px within a row; block name -> (x, y) of its header;
    the row's width and height."""
    s = ROOM_SCALE
    panels = {}
    x0, y0 = MARGIN, LABEL_BAND
    col = [x0, x0 + s + GAP, x0 + 2 * (s + GAP)]
    row = [y0 + i * (s + LABEL_BAND) for i in range(4)]
    panels["ceiling"] = (col[1], row[0], s, s)
    panels["back wall (z=0)"] = (col[1], row[1], s, s)
    panels["red wall (x=0)"] = (col[0], row[2], s, s)
    panels["floor"] = (col[1], row[2], s, s)
    panels["green wall (x=1)"] = (col[2], row[2], s, s)
    panels["front wall (z=1)"] = (col[1], row[3], s, s)
    room_right = col[2] + s
    bx = room_right + 4 * GAP
    by = 0.0
    right = room_right
    headers = {}
    for b in blocks:
        headers[b.name] = (bx, by + 11)
        by += BLOCK_HEADER + LABEL_BAND
        x = bx
        for kind, width in (("front", b.w), ("right", b.d), ("back", b.w), ("left", b.d)):
            panels[b.name + " " + kind] = (x, by, width * BLOCK_SCALE, b.h * BLOCK_SCALE)
            x += width * BLOCK_SCALE + SIDE_GAP
        x += 3 * GAP
        panels[b.name + " top"] = (x, by + (b.h - b.d) * BLOCK_SCALE, b.w * BLOCK_SCALE, b.d * BLOCK_SCALE)
        right = max(right, x + b.w * BLOCK_SCALE)
        by += b.h * BLOCK_SCALE + 2 * GAP
    lamp = (LAMP[1] - LAMP[0]) * BLOCK_SCALE
    by += LABEL_BAND
    panels["lamp"] = (bx, by, lamp, lamp)
    by += lamp
    height = max(row[3] + s, by) + GAP
    return panels, headers, right + MARGIN, height


def outlines(panels, blocks):
    """Block footprints on the floor, the lamp on the ceiling: (x, y) polygons in px."""
    fx, fy, fw, fh = panels["floor"]
    out = [[(fx + x * fw, fy + z * fh) for x, z in b.footprint()] for b in blocks]
    cx, cy, cw, ch = panels["ceiling"]
    lo, hi, _ = LAMP
    out.append([(cx + x * cw, cy + (1.0 - z) * ch) for x, z in ((lo, lo), (hi, lo), (hi, hi), (lo, hi))])
    return out


def colour(e, scale):
    t = max(-1.0, min(1.0, e / scale))
    end = POSITIVE if t >= 0 else NEGATIVE
    t = abs(t)
    return "#%02x%02x%02x" % tuple(int(round(255 + (c - 255) * t)) for c in end)


def read_errors(path):
    with open(path, newline="") as f:
        reader = csv.DictReader(f)
        missing = {"x", "y", "z", "rel_error"} - set(reader.fieldnames or ())
        if missing:
            raise ValueError("%s: no column %s (expected vertex_error.py --csv output)" % (path, ", ".join(sorted(missing))))
        return [(float(r["x"]), float(r["y"]), float(r["z"]), float(r["rel_error"])) for r in reader]


def worst_index(items):
    """The first of the items (e, u, v) with the largest |e|."""
    return max(range(len(items)), key=lambda j: (abs(items[j][0]), -j))


def rms(values):
    return math.sqrt(sum(e * e for e in values) / len(values)) if values else float("nan")


def pct(e, signed=False):
    return ("%+.2f %%" if signed else "%.2f %%") % (100.0 * e)


def esc(text):
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


def num(v):
    text = "%.1f" % v
    return "0.0" if text == "-0.0" else text


def text(x, y, body, size=11, anchor="start", bold=False):
    return '<text x="%s" y="%s" font-size="%d"%s%s>%s</text>' % (
        num(x), num(y), size, ' text-anchor="%s"' % anchor if anchor != "start" else "",
        ' font-weight="bold"' if bold else "", esc(body))


def caption(scale):
    """The caption's paragraphs."""
    s = pct(scale).replace(".00", "")
    return [
        "Each square is one lit probe (one row of the CSV) at its unfolded position, coloured by its relative error"
        " (bake - reference) / reference: blue below the reference, white on it, red above, saturating at -%s and +%s;"
        " the worst probe of each panel is outlined in black. Above each panel: its RMS relative error, its probe count"
        " and its worst error; above each row: the row's RMS and bias over all its probes." % (s, s),
        "Room (left, 1 m = %d px), seen from inside: the floor in the centre (back wall up, red wall left), the four"
        " walls folded out around it, each hinged on its edge with the floor (red x=0 left, green x=1 right, back z=0"
        " above, front z=1 below), and the ceiling folded on beyond the back wall (hinged on the back wall's top edge)."
        " Dashed: the blocks' footprints on the floor, the lamp on the ceiling." % ROOM_SCALE,
        "Blocks (right, 1 m = %d px): each block's four sides unrolled in one strip, seen from outside, feet down, in the"
        " order front, right, back, left (each named after the room wall it faces, to within 17 degrees; neighbours in"
        " the strip share their vertical edge), then its top seen from above, front edge down. Lamp: the emitter's"
        " underside, seen from below like the ceiling." % BLOCK_SCALE,
        "A probe belongs to the surface nearest to it (a room plane, the lamp or a block face) within 1 mm, else it is"
        " left out and counted.",
    ]


def wrap(paragraph, chars):
    lines, line = [], ""
    for word in paragraph.split(" "):
        if line and len(line) + 1 + len(word) > chars:
            lines.append(line)
            line = word
        else:
            line = line + " " + word if line else word
    return lines + [line]


def draw(rows, scale, title):
    """rows: [(label, [(x, y, z, e)])]. The SVG text."""
    blocks = [Block(*b) for b in BLOCKS]
    panels, headers, width, row_height = layout(blocks)
    order = list(panels)  # drawing order: the room, then the blocks and the lamp
    header_h = 84.0
    row_title_h = 22.0
    width = max(width, 1000.0)
    lines = []  # (y offset, text)
    for paragraph in caption(scale):
        for line in wrap(paragraph, int((width - 2 * MARGIN) / 5.6)):
            lines.append(((lines[-1][0] + 14.0) if lines else 12.0, line))
        lines.append((lines[-1][0] + 4.0, None))
    height = header_h + len(rows) * (row_title_h + row_height) + lines[-1][0] + MARGIN
    out = ['<?xml version="1.0" encoding="UTF-8"?>',
           '<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" viewBox="0 0 %d %d" font-family="sans-serif">' % (
               math.ceil(width), math.ceil(height), math.ceil(width), math.ceil(height)),
           '<rect width="100%" height="100%" fill="#ffffff"/>',
           text(MARGIN, 24, title, 15, bold=True)]
    # Colour bar: 41 steps from -scale to +scale.
    bar_x, bar_y, bar_w, bar_h, steps = MARGIN + 30, 40.0, 400.0, 14.0, 41
    for i in range(steps):
        e = scale * (2.0 * i / (steps - 1) - 1.0)
        out.append('<rect x="%s" y="%s" width="%s" height="%s" fill="%s"/>' % (
            num(bar_x + i * bar_w / steps), num(bar_y), num(bar_w / steps + 0.5), num(bar_h), colour(e, scale)))
    out.append('<rect x="%s" y="%s" width="%s" height="%s" fill="none" stroke="#000000" stroke-width="0.5"/>' % (
        num(bar_x), num(bar_y), num(bar_w), num(bar_h)))
    for k in range(5):
        e = scale * (k / 2.0 - 1.0)
        x = bar_x + bar_w * (k / 4.0) + (bar_w / steps / 2.0) * (1 - k / 2.0)
        label = ("%+.1f %%" % (100.0 * e)).replace("+0.0", "0")
        if k == 0:
            label = "<= " + label
        elif k == 4:
            label = ">= " + label
        out.append('<line x1="%s" y1="%s" x2="%s" y2="%s" stroke="#000000" stroke-width="0.5"/>' % (
            num(x), num(bar_y + bar_h), num(x), num(bar_y + bar_h + 4)))
        out.append(text(x, bar_y + bar_h + 15, label, 10, anchor="middle"))
    out.append(text(bar_x + bar_w + 16, bar_y + 11, "relative error of each probe: blue = bake below the reference, red = above", 11))

    y = header_h
    for label, data in rows:
        placed = classify([(p[0], p[1], p[2]) for p in data], blocks)
        errors = [p[3] for p in data]
        left_out = sum(1 for c in placed if c is None)
        if errors:
            head = "%s: %d probes, RMS %s, bias %s" % (label, len(data), pct(rms(errors)), pct(sum(errors) / len(errors), True))
        else:
            head = "%s: no probes" % label
        if left_out:
            head += "; %d on no surface, left out" % left_out
            sys.stderr.write("vertex_error_map: %s: %d probes on no surface (more than %g from every one), left out\n" % (
                label, left_out, TOLERANCE))
        out.append(text(MARGIN, y + 15, head, 13, bold=True))
        top = y + row_title_h
        members = {name: [] for name in order}
        for p, c in zip(data, placed):
            if c is not None:
                members[c[0]].append((p[3], c[1], c[2]))
        out.append('<g>')
        for name in order:
            px, py, pw, ph = panels[name]
            py += top
            items = members[name]
            out.append('<rect x="%s" y="%s" width="%s" height="%s" fill="%s" stroke="#606060" stroke-width="0.5"/>' % (
                num(px), num(py), num(pw), num(ph), PANEL_FILL))
            shown = name
            for b in blocks:
                if name.startswith(b.name + " "):
                    shown = name[len(b.name) + 1:]
            out.append(text(px, py - 29, shown, 10, bold=True))
            if items:
                worst = items[worst_index(items)][0]
                out.append(text(px, py - 17, "RMS %s, n %d" % (pct(rms([t[0] for t in items])), len(items)), 10))
                out.append(text(px, py - 5, "worst %s" % pct(worst, True), 10))
            else:
                out.append(text(px, py - 17, "no probes", 10))
        for name, (hx, hy) in headers.items():
            out.append(text(hx, top + hy, name, 12, bold=True))
        out.append('</g>')
        for poly in outlines(panels, blocks):
            out.append('<polygon points="%s" fill="none" stroke="#000000" stroke-width="0.8" stroke-dasharray="3,2"/>' % (
                " ".join("%s,%s" % (num(px), num(py + top)) for px, py in poly)))
        out.append('<g class="probes" stroke="none">')
        worst_marks = []
        for name in order:
            px, py, pw, ph = panels[name]
            py += top
            items = members[name]
            half = SQUARE / 2.0
            for e, u, v in items:
                cx = min(px + pw - half, max(px + half, px + u * pw))
                cy = min(py + ph - half, max(py + half, py + v * ph))
                out.append('<rect x="%s" y="%s" width="%g" height="%g" fill="%s"/>' % (
                    num(cx - half), num(cy - half), SQUARE, SQUARE, colour(e, scale)))
            if items:
                e, u, v = items[worst_index(items)]
                cx = min(px + pw - half, max(px + half, px + u * pw))
                cy = min(py + ph - half, max(py + half, py + v * ph))
                worst_marks.append('<rect class="worst" x="%s" y="%s" width="%s" height="%s" fill="none" stroke="#000000" stroke-width="1.5"/>' % (
                    num(cx - half - 1), num(cy - half - 1), num(SQUARE + 2), num(SQUARE + 2)))
        out.append('</g>')
        out.extend(worst_marks)
        y = top + row_height
    for dy, line in lines:
        if line is not None:
            out.append(text(MARGIN, y + dy, line, 10))
    out.append("</svg>")
    return "\n".join(out) + "\n"


def main(argv):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("csv", nargs="+", help="vertex_error.py --csv output, one row of the picture each")
    p.add_argument("--label", action="append", default=[], help="the next CSV's name (one per CSV, in order)")
    p.add_argument("-o", "--out", default="vertex_error_map.svg", help="the SVG to write")
    p.add_argument("--scale", type=float, default=0.1, help="the relative error at which the colours saturate (0.1 = 10 %%)")
    p.add_argument("--title", default="Relative error of the tessellated Cornell box's vertices against the Monte Carlo reference")
    args = p.parse_intermixed_args(argv[1:])
    if args.label and len(args.label) != len(args.csv):
        p.error("%d --label for %d CSV files: give one per CSV, or none" % (len(args.label), len(args.csv)))
    if not args.scale > 0:
        p.error("--scale must be positive")
    labels = args.label or [os.path.basename(c) for c in args.csv]
    try:
        rows = [(label, read_errors(path)) for label, path in zip(labels, args.csv)]
    except (OSError, ValueError, KeyError) as e:
        sys.stderr.write("vertex_error_map: error: %s\n" % e)
        return 1
    svg = draw(rows, args.scale, args.title)
    with open(args.out, "w", newline="\n") as f:
        f.write(svg)
    print("%s: %d row(s), %d probes" % (args.out, len(rows), sum(len(r[1]) for r in rows)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
