#!/usr/bin/env bash
# Benchmarks `radbake bake` on one thread: median wall time over RUNS runs (hyperfine when
# installed, else a timed loop) and peak memory (timings.json's peak_rss_mb, and the whole
# process's maximum resident set from /usr/bin/time when present). Issue 4's targets for the
# shipped Cornell Box at the default quality: < 2 s wall, < 200 MB.
# Then, unless MODES=0, one bake per --visibility mode with its stats side by side.
#
#   tools/bench_bake.sh [SCENE] [extra bake options...]
#   env: RADBAKE (program, default build/src/radbake), RUNS (default 5), MODES (default 1)
set -euo pipefail
cd "$(dirname "$0")/.."
scene=${1:-scenes/cornell_box.wrl}
shift $(( $# > 0 ? 1 : 0 ))
extra=("$@")
radbake=${RADBAKE:-build/src/radbake}
runs=${RUNS:-5}
if [ ! -x "$radbake" ]; then
  bash tools/build.sh >/dev/null
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

bake() { "$radbake" bake "$scene" --threads 1 --quiet -o "$work/out" "${extra[@]}" "$@" >/dev/null; }
field() { python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])' "$1" "$2"; }

bake  # warm the file cache; also fails early on a bad scene
if command -v hyperfine >/dev/null; then
  quoted_extra=""
  ((${#extra[@]})) && quoted_extra=$(printf ' %q' "${extra[@]}")
  hyperfine --runs "$runs" --warmup 1 --style none --export-json "$work/hyperfine.json" \
    "$(printf '%q' "$radbake") bake $(printf '%q' "$scene") --threads 1 --quiet -o $(printf '%q' "$work/out")$quoted_extra" >/dev/null
  median=$(python3 -c 'import json,sys; r=json.load(open(sys.argv[1]))["results"][0]; print("%.3f %.3f %.3f" % (r["median"], r["min"], r["max"]))' "$work/hyperfine.json")
else
  times=()
  for ((i = 0; i < runs; ++i)); do
    start=$(date +%s.%N); bake; end=$(date +%s.%N)
    times+=("$(python3 -c "print($end - $start)")")
  done
  median=$(printf '%s\n' "${times[@]}" | python3 -c 'import sys,statistics; t=[float(x) for x in sys.stdin]; print("%.3f %.3f %.3f" % (statistics.median(t), min(t), max(t)))')
fi
read -r med lo hi <<<"$median"
echo "scene           $scene (threads 1${extra[*]:+, ${extra[*]}})"
echo "wall median     $med s over $runs runs (min $lo, max $hi)   target < 2 s"
echo "bake seconds    $(field "$work/out/timings.json" seconds) s (timings.json of the last run)"
echo "peak_rss_mb     $(field "$work/out/timings.json" peak_rss_mb) MB (timings.json)   target < 200 MB"
if [ -x /usr/bin/time ]; then
  /usr/bin/time -f '%M' -o "$work/rss" "$radbake" bake "$scene" --threads 1 --quiet -o "$work/out" "${extra[@]}" >/dev/null
  echo "max RSS         $(python3 -c "print('%.1f' % ($(cat "$work/rss") / 1024))") MB (/usr/bin/time, whole process)"
fi

if [ "${MODES:-1}" != 0 ]; then
  echo
  printf '%-10s %9s %9s %10s %15s %10s %9s %12s\n' visibility seconds elements links occluded_links rays shafts peak_rss_mb
  for mode in rays aabb obb exact; do
    bake --visibility "$mode" 2>/dev/null
    python3 - "$work/out/stats.json" "$work/out/timings.json" "$mode" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
s.update(json.load(open(sys.argv[2])))  # seconds and peak_rss_mb
print("%-10s %9.3f %9d %10d %15d %10d %9d %12.1f" % (sys.argv[3], s["seconds"], s["elements"], s["links"],
      s["occluded_links"], s["rays"], s["shafts"], s["peak_rss_mb"]))
PY
  done
fi
