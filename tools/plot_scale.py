#!/usr/bin/env python3
"""Plot how the radiosity solve grows with scene size (issue 11, docs/results.md).

Reads the CSV files written by `tools/bench_scale.sh --csv FILE` (columns scene, triangles,
median_s, links, rays, rss_mb, status; older files without rays too) and writes one self-contained SVG with three log-log panels:
solve time (s), peak memory (MB) and links, each against triangles. The building_* scenes (the
generated ladder) are joined by a line; the other (real) scenes are separate labelled markers.
A dotted line of slope 1 (linear growth) passes through the smallest building point of each panel.
Rows whose status is not ok (timeout, out of memory, ...) are hollow markers at the wall time and
peak memory when they were stopped (when known) and are listed in a note; rows without a triangle
count (missing scenes) are skipped and listed. When several CSVs hold the same scene, the last
one read wins. Standard library only; the same input gives the same bytes.

    python3 tools/plot_scale.py CSV [CSV...] [--out docs/scale_growth.svg] [--title TEXT]
"""
import argparse
import csv
import math
import os
import re
from xml.sax.saxutils import escape

PANEL_W, PANEL_H = 380, 340
LEFT, RIGHT, TOP, BOTTOM = 62, 18, 44, 48  # plot-area margins inside a panel
BUILDING, REAL = "#1f77b4", "#d62728"


def number(text):
    try:
        value = float(text)
    except (TypeError, ValueError):
        return None
    return value if value > 0 and math.isfinite(value) else None


def read_rows(paths):
    rows = {}  # scene -> row; dicts keep the first-seen order, a later CSV replaces the values
    for path in paths:
        with open(path, newline="") as f:
            for r in csv.DictReader(f):
                rows[r["scene"]] = r
    return list(rows.values())


def points(rows):
    """(scene, triangles, {panel key: value}, ok, status) per plottable row; and skipped rows."""
    out, skipped = [], []
    for r in rows:
        status = (r.get("status") or "").strip()
        tri = number(r.get("triangles"))
        if tri is None:
            skipped.append("%s: %s" % (r["scene"], status or "no triangle count"))
            continue
        ok = status == "ok"
        if ok:
            values = {"time": number(r.get("median_s")), "mem": number(r.get("rss_mb")),
                      "links": number(r.get("links"))}
        else:
            wall = re.search(r"after ([0-9.]+) s", status)
            values = {"time": number(wall.group(1)) if wall else None,
                      "mem": number(r.get("rss_mb")), "links": None}
        out.append((r["scene"], tri, values, ok, status))
    return out, skipped


def tick_label(k):
    if k < 0:
        return "%.*f" % (-k, 10.0 ** k)
    for exp, suffix in ((9, "G"), (6, "M"), (3, "k")):
        if k >= exp:
            return "%d%s" % (10 ** (k - exp), suffix)
    return "%d" % 10 ** k


def decades(values):
    """Whole decades around the values, keeping points at least 0.15 decade off the edges."""
    lo = math.floor(math.log10(min(values)) - 0.15)
    hi = math.ceil(math.log10(max(values)) + 0.15)
    return lo, max(hi, lo + 1)


def panel(index, key, title, ylabel, pts, xrange):
    """SVG elements of one panel, its origin at x = index * PANEL_W."""
    x0, y0 = index * PANEL_W + LEFT, TOP
    w, h = PANEL_W - LEFT - RIGHT, PANEL_H - TOP - BOTTOM
    have = [p for p in pts if p[2][key] is not None]
    cx = x0 + w / 2
    out = ['<text x="%.1f" y="%d" text-anchor="middle" font-size="14">%s</text>' % (cx, TOP - 14, escape(title)),
           '<rect x="%d" y="%d" width="%d" height="%d" fill="none" stroke="black"/>' % (x0, y0, w, h),
           '<text x="%.1f" y="%d" text-anchor="middle">triangles</text>' % (cx, y0 + h + 36),
           '<text x="%d" y="%.1f" text-anchor="middle" transform="rotate(-90 %d %.1f)">%s</text>'
           % (x0 - 46, y0 + h / 2, x0 - 46, y0 + h / 2, escape(ylabel))]
    if not have:
        return out + ['<text x="%.1f" y="%.1f" text-anchor="middle">no data</text>' % (cx, y0 + h / 2)]
    xlo, xhi = xrange  # the same for the three panels
    ylo, yhi = decades([p[2][key] for p in have])
    sx = lambda v: x0 + (math.log10(v) - xlo) / (xhi - xlo) * w
    sy = lambda v: y0 + h - (math.log10(v) - ylo) / (yhi - ylo) * h
    for k in range(xlo, xhi + 1):
        out.append('<line x1="%.1f" y1="%d" x2="%.1f" y2="%d" stroke="#ddd"/>' % (sx(10.0 ** k), y0, sx(10.0 ** k), y0 + h))
        out.append('<text x="%.1f" y="%d" text-anchor="middle">%s</text>' % (sx(10.0 ** k), y0 + h + 16, tick_label(k)))
    for k in range(ylo, yhi + 1):
        out.append('<line x1="%d" y1="%.1f" x2="%d" y2="%.1f" stroke="#ddd"/>' % (x0, sy(10.0 ** k), x0 + w, sy(10.0 ** k)))
        out.append('<text x="%d" y="%.1f" text-anchor="end">%s</text>' % (x0 - 5, sy(10.0 ** k) + 4, tick_label(k)))
    out.append('<clipPath id="clip%d"><rect x="%d" y="%d" width="%d" height="%d"/></clipPath>' % (index, x0, y0, w, h))
    building = sorted((p for p in have if p[0].startswith("building_")), key=lambda p: (p[1], p[0]))
    if building:
        bx, by = building[0][1], building[0][2][key]  # slope 1 through the smallest building point
        ends = [(10.0 ** xlo, by * 10.0 ** xlo / bx), (10.0 ** xhi, by * 10.0 ** xhi / bx)]
        out.append('<line x1="%.1f" y1="%.1f" x2="%.1f" y2="%.1f" stroke="#555" stroke-dasharray="2,3" '
                   'clip-path="url(#clip%d)"/>' % (sx(ends[0][0]), sy(ends[0][1]), sx(ends[1][0]), sy(ends[1][1]), index))
        out.append('<polyline fill="none" stroke="%s" stroke-width="1.5" points="%s"/>'
                   % (BUILDING, " ".join("%.1f,%.1f" % (sx(p[1]), sy(p[2][key])) for p in building)))
    for name, tri, values, ok, status in sorted(have, key=lambda p: (p[1], p[0])):
        colour = BUILDING if name.startswith("building_") else REAL
        px, py = sx(tri), sy(values[key])
        fill = colour if ok else "white"
        out.append('<circle cx="%.1f" cy="%.1f" r="3.5" fill="%s" stroke="%s" stroke-width="1.5"><title>%s</title></circle>'
                   % (px, py, fill, colour, escape("%s: %d triangles, %g (%s)" % (name, tri, values[key], status))))
        # labels toward the middle of the panel; building labels off the rising line (below
        # right in the left half, above left in the right half), real scenes beside the marker
        left = px < x0 + w / 2
        dy = (13 if left else -6) if name.startswith("building_") else 4
        out.append('<text x="%.1f" y="%.1f" text-anchor="%s" font-size="10" fill="%s">%s</text>'
                   % (px + 6 if left else px - 6, py + dy, "start" if left else "end", colour, escape(name)))
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("csv", nargs="+", help="CSV files of tools/bench_scale.sh --csv")
    parser.add_argument("--out", default="docs/scale_growth.svg")
    parser.add_argument("--title", default="radbake: growth of the radiosity solve with scene size")
    args = parser.parse_args()
    pts, skipped = points(read_rows(args.csv))
    notes = ["not ok (hollow marker at the wall time / peak memory when stopped, where known): %s: %s" % (p[0], p[4])
             for p in pts if not p[3]]
    notes += ["skipped (no triangle count): %s" % s for s in skipped]
    legend = ("blue line: building_* ladder (generated); red: real scenes; hollow: not ok; "
              "dotted: slope 1 (linear growth) through the smallest building point")
    caption = "data: " + ", ".join(os.path.basename(p) for p in args.csv)
    width, top = 3 * PANEL_W, 34
    height = top + PANEL_H + 16 * (2 + len(notes)) + 10
    out = ['<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" font-family="sans-serif" font-size="12">' % (width, height),
           '<rect width="100%" height="100%" fill="white"/>',
           '<text x="%d" y="22" text-anchor="middle" font-size="16">%s</text>' % (width // 2, escape(args.title)),
           '<g transform="translate(0,%d)">' % top]
    xrange = decades([p[1] for p in pts]) if pts else (3, 6)
    for i, (key, title, ylabel) in enumerate((("time", "solve time", "median solve time (s)"),
                                              ("mem", "peak memory", "peak RSS (MB)"),
                                              ("links", "links", "links"))):
        out += panel(i, key, title + " vs triangles", ylabel, pts, xrange)
    out.append("</g>")
    y = top + PANEL_H + 12
    for line in [legend, caption] + notes:
        out.append('<text x="12" y="%d">%s</text>' % (y, escape(line)))
        y += 16
    out.append("</svg>\n")
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    with open(args.out, "w", newline="\n") as f:
        f.write("\n".join(out))


if __name__ == "__main__":
    main()
