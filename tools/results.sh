#!/usr/bin/env bash
# Regenerates docs/results.md (issue 6: the paper's AABB/OBB table, reproduced for all four
# visibility modes) and the error-vs-time plots docs/error_vs_time_<scene>.svg.
#
#   bash tools/results.sh
#   env: BUILD (build directory, default build), RADBAKE, REFERENCE_MC (programs, default
#        $BUILD/src/radbake and $BUILD/tools/reference_mc), SAMPLES (reference_mc paths per
#        probe, default 65536), REFRESH_REFERENCE=1 (recompute docs/reference/*.csv even when
#        present), RUNS (bakes per table cell, median time, default 3), THREADS (default 1, as
#        the paper's single CPU), PLOTS=0 (skip the harness plots), PLOT_REPEATS (default 1),
#        PLOT_QUALITIES (default draft,medium,high), PLOT_THRESHOLDS (default 1e-2,3e-3,1e-3,3e-4,1e-4).
#
# The table bakes every scene at the default quality once per visibility mode; its errors are
# against docs/reference/<scene>.csv (tools/reference_mc), error formulas as in tools/harness.py.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${BUILD:-build}
radbake=${RADBAKE:-$build/src/radbake}
reference_mc=${REFERENCE_MC:-$build/tools/reference_mc}
samples=${SAMPLES:-65536}
runs=${RUNS:-3}
threads=${THREADS:-1}
for p in "$radbake" "$reference_mc"; do
  [ -x "$p" ] || { echo "results.sh: $p not built (set BUILD, RADBAKE or REFERENCE_MC)" >&2; exit 1; }
done

declare -A scene_file=(
  [cornell_box]=scenes/cornell_box
  [duplex]=scenes/paper/duplex [geometry]=scenes/paper/geometry
  [shadow]=scenes/paper/shadow [secondary]=scenes/paper/secondary)
scenes=(cornell_box duplex geometry shadow secondary)
modes=(rays aabb obb exact)

mkdir -p docs/reference
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# 1. Monte Carlo references (kept in docs/reference: slow to make, small to keep).
for s in "${scenes[@]}"; do
  ref=docs/reference/$s.csv
  if [ ! -s "$ref" ] || [ "${REFRESH_REFERENCE:-0}" = 1 ]; then
    echo "reference_mc $s ($samples paths per probe)" >&2
    "$reference_mc" "${scene_file[$s]}.wrl" "${scene_file[$s]}.probes" --samples "$samples" -o "$ref" \
      2> "$work/ref_$s.log" || { cat "$work/ref_$s.log" >&2; exit 1; }
    cat "$work/ref_$s.log" >&2
    cp "$work/ref_$s.log" "docs/reference/$s.log"
  fi
done

# 2. The table: RUNS bakes per scene and mode at the default quality.
rows=$work/table.tsv
: > "$rows"
for s in "${scenes[@]}"; do
  for m in "${modes[@]}"; do
    for ((i = 0; i < runs; ++i)); do
      out=$work/$s.$m.$i
      "$radbake" bake "${scene_file[$s]}.wrl" --probes "${scene_file[$s]}.probes" --visibility "$m" \
        --threads "$threads" --quiet -o "$out" >/dev/null
      printf '%s\t%s\t%s\n' "$s" "$m" "$out" >> "$rows"
    done
    echo "baked $s $m" >&2
  done
done

# 3. The plots: tools/harness.py over a ladder of settings, one curve per visibility mode.
plot_scenes=(cornell_box shadow)
if [ "${PLOTS:-1}" != 0 ]; then
  for s in "${plot_scenes[@]}"; do
    python3 tools/harness.py --radbake "$radbake" --scene "${scene_file[$s]}.wrl" \
      --probes "${scene_file[$s]}.probes" --reference "docs/reference/$s.csv" --out "$work/harness_$s" \
      --repeats "${PLOT_REPEATS:-1}" --threads "$threads" \
      --qualities "${PLOT_QUALITIES:-draft,medium,high}" --thresholds "${PLOT_THRESHOLDS:-1e-2,3e-3,1e-3,3e-4,1e-4}" >&2
    cp "$work/harness_$s/error_vs_time.svg" "docs/error_vs_time_$s.svg"
    cp "$work/harness_$s/error_vs_memory.svg" "docs/error_vs_memory_$s.svg"
    cp "$work/harness_$s/results.csv" "docs/harness_$s.csv"
  done
fi

# 4. docs/results.md: the table (the prose below it is kept from the previous docs/results.md).
python3 - "$rows" "$runs" "$threads" "$samples" <<'EOF'
import collections, json, os, statistics, sys
sys.path.insert(0, "tools")
import harness

rows_path, runs, threads, samples = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
runs_by = collections.OrderedDict()
for line in open(rows_path):
    scene, mode, out = line.rstrip("\n").split("\t")
    runs_by.setdefault((scene, mode), []).append(out)

names = {"cornell_box": "Cornell Box", "duplex": "Duplex", "geometry": "Geometry", "shadow": "Shadow",
         "secondary": "Secondary"}
paper = {("cornell_box", "aabb"): "8.89 s / 21.7 MB", ("cornell_box", "obb"): "8.97 s / 20.9 MB"}
table = ["| scene | visibility | time s (median of %d) | peak MB | elements | links | shafts | occluded links | rays "
         "| L2 rel. error | max rel. error | MC noise (L2) | paper (PIII 600 MHz) |" % runs,
         "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- |"]
for (scene, mode), outs in runs_by.items():
    stats = [harness.read_bake_stats(o) for o in outs]  # stats.json with timings.json
    ref_rows = harness.read_csv_rows("docs/reference/%s.csv" % scene)
    err = harness.compare(os.path.join(outs[-1], "probes.csv"), ref_rows)
    noise = harness.reference_noise(ref_rows)
    s0 = stats[0]
    table.append("| %s | %s | %.3f | %.1f | %s | %s | %s | %s | %s | %.2f %% | %.1f %% | %.2f %% | %s |" % (
        names[scene], mode, statistics.median(s["seconds"] for s in stats),
        statistics.median(s.get("peak_rss_mb", 0.0) for s in stats), s0.get("elements", ""), s0.get("links", ""),
        s0.get("shafts", ""), s0.get("occluded_links", ""), s0.get("rays", ""), 100 * err["l2_rel"],
        100 * err["max_rel"], 100 * noise if noise != "" else float("nan"), paper.get((scene, mode), "")))
quality = json.load(open(os.path.join(next(iter(runs_by.values()))[0], "stats.json"))).get("quality", "default")

begin, end = "<!-- table: begin (tools/results.sh) -->", "<!-- table: end -->"
generated = "\n".join([begin,
    "Default quality (`%s`), `--threads %d`, %d bakes per row (time and memory: medians; counts and "
    "errors: one run, they do not vary). Errors against `docs/reference/<scene>.csv` (tools/reference_mc, "
    "%d paths per probe); errors below about twice the MC noise column are not resolved." % (quality, threads, runs, samples),
    "", *table, end])
path = "docs/results.md"
text = open(path).read() if os.path.exists(path) else begin + "\n" + end + "\n"
head, rest = text.split(begin, 1)
tail = rest.split(end, 1)[1]
open(path, "w").write(head + generated + tail)
print("\n".join(table))
EOF
