#!/usr/bin/env python3
"""Speed/accuracy harness (issue 6): run `radbake bake` over a ladder of settings on one scene,
measure time, memory, links and rays, compare the probes with a reference, write a CSV and draw
error against time (and memory) as SVG, one curve per visibility mode.

    python3 tools/harness.py --radbake build/src/radbake \\
        --scene scenes/analytic/furnace_rho_0.9.wrl \\
        --probes scenes/analytic/furnace_rho_0.9.probes \\
        --reference scenes/analytic/furnace_rho_0.9.expected.csv --out harness-out/furnace

The reference is either an analytic `NAME.expected.csv` (x,y,z,nx,ny,nz,r,g,b,rel_tol) or the
output of tools/reference_mc (x,y,z,nx,ny,nz,r,g,b,se_r,se_g,se_b). Errors, per run:
  - l2_rel:  sqrt(sum_i w_i |H_i - R_i|^2) / sqrt(sum_i w_i |R_i|^2), over probes i and the three
             channels, w_i = the reference's `area` column when present, else 1 (every probe file
             here is a uniform grid per surface, so equal weights are area weights there);
  - max_rel: max_i |H_i - R_i| / max(|R_i|, floor), max over channels; floor = 1e-3 x the mean
             |R| keeps probes in full shadow from dividing by ~0;
  - within_tol: probes whose max channel relative error is within the reference's rel_tol
             (analytic references only).
For a Monte Carlo reference, `ref_noise_l2` is the same L2 norm of its standard errors: errors
below about twice it are not resolved.
Time is the median over --repeats runs of timings.json "seconds"; memory the median of its
"peak_rss_mb" (counts come from stats.json). Python standard library only.
"""
import argparse
import csv
import json
import math
import os
import statistics
import subprocess
import sys

MODES = ["rays", "aabb", "obb", "exact"]
COLOURS = {"rays": "#1f77b4", "aabb": "#d62728", "obb": "#2ca02c", "exact": "#9467bd"}


def read_csv_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def vec(row, keys):
    return [float(row[k]) for k in keys]


def compare(probes_csv, reference_rows):
    """Errors of a run's probes.csv against the reference rows (same order)."""
    rows = read_csv_rows(probes_csv)
    if len(rows) != len(reference_rows):
        raise ValueError("%s has %d probes, the reference %d" % (probes_csv, len(rows), len(reference_rows)))
    refs = [vec(r, "rgb") for r in reference_rows]
    mean_ref = sum(sum(abs(c) for c in r) for r in refs) / (3.0 * max(1, len(refs)))
    floor = max(1e-3 * mean_ref, 1e-300)
    num = den = 0.0
    max_rel = 0.0
    within = 0
    has_tol = "rel_tol" in reference_rows[0] if reference_rows else False
    for row, ref, ref_row in zip(rows, refs, reference_rows):
        if max(abs(float(row[k]) - float(ref_row[k])) for k in ("x", "y", "z")) > 1e-6 * (1.0 + abs(float(ref_row["x"]))):
            raise ValueError("probe position differs from the reference: %s" % row)
        got = vec(row, "rgb")
        w = float(ref_row.get("area", 1.0) or 1.0)
        rel = 0.0
        for g, r in zip(got, ref):
            num += w * (g - r) ** 2
            den += w * r * r
            rel = max(rel, abs(g - r) / max(abs(r), floor))
        max_rel = max(max_rel, rel)
        if has_tol and rel <= float(ref_row["rel_tol"]):
            within += 1
    return {"l2_rel": math.sqrt(num / den) if den > 0 else float("nan"), "max_rel": max_rel,
            "within_tol": within if has_tol else ""}


def reference_noise(reference_rows):
    if not reference_rows or "se_r" not in reference_rows[0]:
        return ""
    num = sum(sum(float(r[k]) ** 2 for k in ("se_r", "se_g", "se_b")) for r in reference_rows)
    den = sum(sum(float(r[k]) ** 2 for k in "rgb") for r in reference_rows)
    return math.sqrt(num / den) if den > 0 else ""


def ladder(args):
    """(visibility, label, extra radbake options) for every run."""
    runs = []
    for mode in args.visibility:
        for quality in args.qualities:
            runs.append((mode, "quality=" + quality, ["--quality", quality]))
        for t in args.thresholds:
            runs.append((mode, "threshold=%g" % t, ["--quality", args.base_quality, "--error-threshold", "%g" % t]))
    return runs


def run_once(args, mode, options, out_dir):
    command = [args.radbake, "bake", args.scene, "-o", out_dir, "--probes", args.probes, "--visibility", mode,
               "--threads", str(args.threads), "--quiet"] + options + args.extra
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode != 0:
        sys.stderr.write("harness: failed (%d): %s\n%s" % (result.returncode, " ".join(command), result.stderr))
        return None
    return read_bake_stats(out_dir)


def read_bake_stats(out_dir):
    """stats.json (counts, knobs) and timings.json (seconds, phases, peak_rss_mb, threads) as one dict."""
    with open(os.path.join(out_dir, "stats.json")) as f:
        stats = json.load(f)
    with open(os.path.join(out_dir, "timings.json")) as f:
        stats.update(json.load(f))
    return stats


def log_ticks(lo, hi):
    ticks = []
    e = math.floor(math.log10(lo))
    while 10 ** e <= hi * 1.0001:
        if 10 ** e >= lo / 1.0001:
            ticks.append(10 ** e)
        e += 1
    return ticks


def svg_plot(path, title, results, x_key, x_label, y_key, y_label):
    """Log-log plot, one polyline per visibility mode, hand-written SVG."""
    points = [r for r in results if r.get(x_key, 0) > 0 and r.get(y_key, 0) > 0]
    width, height, left, right, top, bottom = 720, 480, 80, 150, 40, 60
    pw, ph = width - left - right, height - top - bottom
    if not points:
        return
    xs = [r[x_key] for r in points]
    ys = [r[y_key] for r in points]
    x0, x1 = 10 ** math.floor(math.log10(min(xs))), 10 ** math.ceil(math.log10(max(xs)))
    y0, y1 = 10 ** math.floor(math.log10(min(ys))), 10 ** math.ceil(math.log10(max(ys)))
    if x1 <= x0: x1 = x0 * 10
    if y1 <= y0: y1 = y0 * 10

    def px(x): return left + pw * (math.log10(x) - math.log10(x0)) / (math.log10(x1) - math.log10(x0))
    def py(y): return top + ph * (1 - (math.log10(y) - math.log10(y0)) / (math.log10(y1) - math.log10(y0)))

    out = ['<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" font-family="sans-serif" font-size="12">' % (width, height),
           '<rect width="100%" height="100%" fill="white"/>',
           '<text x="%d" y="24" font-size="14">%s</text>' % (left, escape(title)),
           '<rect x="%d" y="%d" width="%d" height="%d" fill="none" stroke="black"/>' % (left, top, pw, ph)]
    for t in log_ticks(x0, x1):
        out.append('<line x1="%.1f" y1="%d" x2="%.1f" y2="%d" stroke="#ddd"/>' % (px(t), top, px(t), top + ph))
        out.append('<text x="%.1f" y="%d" text-anchor="middle">%g</text>' % (px(t), top + ph + 16, t))
    for t in log_ticks(y0, y1):
        out.append('<line x1="%d" y1="%.1f" x2="%d" y2="%.1f" stroke="#ddd"/>' % (left, py(t), left + pw, py(t)))
        out.append('<text x="%d" y="%.1f" text-anchor="end">%g</text>' % (left - 6, py(t) + 4, t))
    out.append('<text x="%d" y="%d" text-anchor="middle">%s</text>' % (left + pw // 2, height - 16, escape(x_label)))
    out.append('<text x="18" y="%d" text-anchor="middle" transform="rotate(-90 18 %d)">%s</text>' % (top + ph // 2, top + ph // 2, escape(y_label)))
    legend_y = top + 10
    for mode in MODES:
        series = sorted((r for r in points if r["visibility"] == mode), key=lambda r: r[x_key])
        if not series:
            continue
        colour = COLOURS[mode]
        out.append('<polyline fill="none" stroke="%s" stroke-width="1.5" points="%s"/>' % (
            colour, " ".join("%.1f,%.1f" % (px(r[x_key]), py(r[y_key])) for r in series)))
        for r in series:
            out.append('<circle cx="%.1f" cy="%.1f" r="3" fill="%s"><title>%s %s</title></circle>' % (
                px(r[x_key]), py(r[y_key]), colour, mode, escape(r["setting"])))
        out.append('<line x1="%d" y1="%d" x2="%d" y2="%d" stroke="%s" stroke-width="2"/>' % (
            left + pw + 12, legend_y, left + pw + 36, legend_y, colour))
        out.append('<text x="%d" y="%d">%s</text>' % (left + pw + 42, legend_y + 4, mode))
        legend_y += 18
    out.append("</svg>\n")
    with open(path, "w") as f:
        f.write("\n".join(out))


def escape(text):
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--radbake", required=True, help="the radbake program")
    p.add_argument("--scene", required=True)
    p.add_argument("--probes", required=True)
    p.add_argument("--reference", required=True, help="NAME.expected.csv or a reference_mc CSV")
    p.add_argument("--out", required=True, help="directory for runs, results.csv and the plots")
    p.add_argument("--visibility", default=",".join(MODES), type=lambda s: s.split(","))
    p.add_argument("--qualities", default="draft,medium,high", type=lambda s: [q for q in s.split(",") if q])
    p.add_argument("--thresholds", default="1e-2,3e-3,1e-3,3e-4,1e-4",
                   type=lambda s: [float(t) for t in s.split(",") if t], help="raw --error-threshold ladder")
    p.add_argument("--base-quality", default="medium", help="preset the raw thresholds are applied over")
    p.add_argument("--repeats", type=int, default=3, help="runs per setting (median time and memory)")
    p.add_argument("--threads", type=int, default=0)
    p.add_argument("--extra", default="", type=lambda s: s.split() if s else [], help="more radbake bake options")
    args = p.parse_args()

    os.makedirs(args.out, exist_ok=True)
    reference_rows = read_csv_rows(args.reference)
    noise = reference_noise(reference_rows)
    scene_name = os.path.splitext(os.path.basename(args.scene))[0]
    results = []
    for index, (mode, label, options) in enumerate(ladder(args)):
        run_dir = os.path.join(args.out, "run%02d_%s_%s" % (index, mode, label.replace("=", "_")))
        stats = []
        for _ in range(max(1, args.repeats)):
            s = run_once(args, mode, options, run_dir)
            if s is None:
                break
            stats.append(s)
        if not stats:
            continue
        errors = compare(os.path.join(run_dir, "probes.csv"), reference_rows)
        row = {"scene": scene_name, "visibility": mode, "setting": label,
               "seconds": statistics.median(s["seconds"] for s in stats),
               "seconds_min": min(s["seconds"] for s in stats),
               "peak_rss_mb": statistics.median(s.get("peak_rss_mb", 0.0) for s in stats),
               "links": stats[0].get("links", ""), "rays": stats[0].get("rays", ""),
               "elements": stats[0].get("elements", ""), "repeats": len(stats),
               "probes": len(reference_rows), "ref_noise_l2": noise}
        row.update(errors)
        results.append(row)
        print("%-6s %-18s %8.3f s %8.1f MB  links %-9s rays %-10s l2 %.3e  max %.3e%s" % (
            mode, label, row["seconds"], row["peak_rss_mb"], row["links"], row["rays"], row["l2_rel"], row["max_rel"],
            "  within tol %s/%d" % (row["within_tol"], len(reference_rows)) if row["within_tol"] != "" else ""))
        sys.stdout.flush()

    fields = ["scene", "visibility", "setting", "seconds", "seconds_min", "peak_rss_mb", "links", "rays", "elements",
              "l2_rel", "max_rel", "within_tol", "probes", "ref_noise_l2", "repeats"]
    with open(os.path.join(args.out, "results.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=fields, extrasaction="ignore")
        writer.writeheader()
        writer.writerows(results)
    svg_plot(os.path.join(args.out, "error_vs_time.svg"), "%s: L2 relative error against time" % scene_name,
             results, "seconds", "wall time (s, median of %d)" % args.repeats, "l2_rel", "area-weighted L2 relative error")
    svg_plot(os.path.join(args.out, "error_vs_memory.svg"), "%s: L2 relative error against peak memory" % scene_name,
             results, "peak_rss_mb", "peak RSS (MB)", "l2_rel", "area-weighted L2 relative error")
    return 0 if results else 1


if __name__ == "__main__":
    sys.exit(main())
