#!/usr/bin/env bash
# Scale yardstick (issue 11): the solve of every scene of the scale ladder, as
#   bench_solver SCENE --modes aabb --threads 2 --runs 1
# prints it, each under a timeout and a memory cap; one markdown table on stdout, a row printed
# as each scene finishes: scene, triangles, median_s, links, rays, rss_mb, status
#
#   tools/bench_scale.sh [RADBAKE_BUILD_DIR] [--timeout S] [--mem-gb G] [--scenes LIST|small|all]
#                        [--quality Q] [--threads N] [--runs N] [--work DIR] [--csv FILE]
#                        [--mode aabb|exact|obb|rays]
#
# RADBAKE_BUILD_DIR (default build/) holds src/radbake and tools/bench_solver. The scenes, by name:
#   cornell_tessellated  tools/gen_cornell_tessellated.py (2,448 quads, 4,896 triangles)
#   house, water, graz, classroom, office   ../shared/scenes: vrml-threejs-house-vrml97/house.wrl,
#       cornell-mcguire/CornellBox-Water.obj, vrml-castle-demo-models/lights_materials/raytracer/
#       graz.wrl and office.wrl, vrml-student-classroom/room.wrl (skipped when missing)
#   building_1k, _3k, _20k, _200k, _1m   tools/gen_building.py (arguments in docs/scale.md)
# --scenes small = cornell_tessellated,house,building_1k,building_3k; all (the default) = every one.
# Generated scenes are written once into --work (default RADBAKE_BUILD_DIR/scale_scenes).
# --timeout: seconds per scene (default 600); --mem-gb: address-space cap per scene (prlimit --as;
# default the smaller of 20 GB and 3/4 of the machine's memory). A scene that runs out of time
# or memory is a row with status `timeout` or `out of memory`, not a failure of the script; rss_mb
# is then the peak when it was stopped, and the status gives the wall time until then (GNU time).
# --mode: the visibility mode (default aabb, the solver's default).
# Exit status 0 unless the script itself fails.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
repo="$(cd "$here/.." && pwd)"
build="$repo/build"
if [ $# -gt 0 ] && [ "${1#-}" = "$1" ]; then build="$(cd "$1" && pwd)"; shift; fi
timeout_s=600
mem_kb=$(awk '/^MemTotal:/ {print int($2 * 3 / 4)}' /proc/meminfo)
((mem_kb > 20 * 1024 * 1024)) && mem_kb=$((20 * 1024 * 1024))
scenes="all"; quality="medium"; threads=2; runs=1; work=""; csv_out=""; mode="aabb"
while [ $# -gt 0 ]; do
  case "$1" in
    --timeout) timeout_s="$2"; shift 2 ;;
    --mem-gb) mem_kb=$(python3 -c "print(int(float('$2') * 1024 * 1024))"); shift 2 ;;
    --scenes) scenes="$2"; shift 2 ;;
    --quality) quality="$2"; shift 2 ;;
    --threads) threads="$2"; shift 2 ;;
    --runs) runs="$2"; shift 2 ;;
    --work) work="$2"; shift 2 ;;
    --csv) csv_out="$2"; shift 2 ;;
    --mode) mode="$2"; shift 2 ;;
    *) sed -n '6,9p' "$0" | sed 's/^# *//' >&2; exit 2 ;;
  esac
done
radbake="$build/src/radbake"
bench="$build/tools/bench_solver"
for program in "$radbake" "$bench"; do
  [ -x "$program" ] || { echo "bench_scale: $program missing: build with tools/build.sh" >&2; exit 1; }
done
work="${work:-$build/scale_scenes}"
mkdir -p "$work"
shared="$repo/../shared/scenes"
# The shared collection is one tree whose scenes may reach beside their folders (../textures/...).
read_root=()
[ -d "$shared" ] && read_root=(--read-root "$shared")

# name -> file; generated scenes are made on first use.
declare -A building_args=(
  [building_1k]="--rooms 2 1 --panels 6" [building_3k]="--rooms 2 2 --panels 7"
  [building_20k]="--rooms 4 4 --panels 9" [building_200k]="--rooms 10 10 --panels 12"
  [building_1m]="--rooms 20 20 --panels 13")
scene_file() {
  case "$1" in
    cornell_tessellated)
      [ -f "$work/cornell_tessellated.obj" ] || python3 "$here/gen_cornell_tessellated.py" "$work/cornell_tessellated.obj" >&2
      echo "$work/cornell_tessellated.obj" ;;
    building_*)
      [ -n "${building_args[$1]:-}" ] || return 1
      [ -f "$work/$1.wrl" ] || python3 "$here/gen_building.py" "$work/$1.wrl" ${building_args[$1]} >&2
      echo "$work/$1.wrl" ;;
    house) echo "$shared/vrml-threejs-house-vrml97/house.wrl" ;;
    water) echo "$shared/cornell-mcguire/CornellBox-Water.obj" ;;
    graz) echo "$shared/vrml-castle-demo-models/lights_materials/raytracer/graz.wrl" ;;
    classroom) echo "$shared/vrml-student-classroom/room.wrl" ;;
    office) echo "$shared/vrml-castle-demo-models/lights_materials/raytracer/office.wrl" ;;
    *) return 1 ;;
  esac
}
case "$scenes" in
  all) scenes="cornell_tessellated,house,water,graz,classroom,office,building_1k,building_3k,building_20k,building_200k,building_1m" ;;
  small) scenes="cornell_tessellated,house,building_1k,building_3k" ;;
esac

rows=()
# One row per scene, printed as soon as it is known (a long ladder shows its results as it goes).
add_row() {
  rows+=("$1")
  echo "| ${1//|/ | } |"
}
echo "bench_scale: $(date -u +%FT%TZ), $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg) at start;" \
     "bench_solver --modes $mode --threads $threads --runs $runs --quality $quality;" \
     "timeout ${timeout_s} s, memory cap $((mem_kb / 1024)) MB per scene" >&2
IFS=',' read -r -a names <<< "$scenes"
echo "| scene | triangles | median_s | links | rays | rss_mb | status |"
echo "|---|---:|---:|---:|---:|---:|---|"
for name in "${names[@]}"; do
  if ! file=$(scene_file "$name"); then echo "bench_scale: unknown scene $name" >&2; exit 2; fi
  if [ ! -f "$file" ]; then
    add_row "$name|-|-|-|-|-|missing ($file)"
    continue
  fi
  triangles=$("$radbake" info "$file" --json "${read_root[@]}" 2>/dev/null | python3 -c 'import json, sys; print(json.load(sys.stdin)["triangles"])' 2>/dev/null || echo "?")
  log="$work/$name.bench.log"
  set +e
  # GNU time reports the peak RSS even of a run that the timeout or the cap stops.
  /usr/bin/time -f "%e %M" -o "$work/$name.time" \
    timeout -k 10 "$timeout_s" prlimit --as=$((mem_kb * 1024)) \
    "$bench" "$file" --modes "$mode" --threads "$threads" --runs "$runs" --quality "$quality" "${read_root[@]}" > "$log" 2> "$log.err"
  rc=$?
  set -e
  peak_kb=$(grep -Eo '^[0-9.]+ [0-9]+$' "$work/$name.time" | tail -1 | cut -d' ' -f2 || true)
  wall=$(grep -Eo '^[0-9.]+ [0-9]+$' "$work/$name.time" | tail -1 | cut -d' ' -f1 || true)
  row=$(awk -v m="$mode" '$1 == m {print $3, $6, $9, $11}' "$log" | tail -1)
  if [ "$rc" -eq 0 ] && [ -n "$row" ]; then
    read -r median links rays rss <<< "$row"
    add_row "$name|$triangles|$median|$links|$rays|$rss|ok"
  else
    rss="-"; [ -n "$peak_kb" ] && rss=$(awk -v k="$peak_kb" 'BEGIN {printf "%.1f", k / 1024}')
    timed_out=$(awk -v w="${wall:-0}" -v t="$timeout_s" 'BEGIN {print (w + 0 >= t) ? 1 : 0}')
    if [ "$rc" -eq 124 ] || { [ "$rc" -eq 137 ] && [ "$timed_out" -eq 1 ]; }; then
      status="timeout (${timeout_s} s)"
    elif [ "$rc" -eq 137 ]; then
      status="killed (SIGKILL before the timeout: the kernel out of memory?)"
    elif grep -qiE "bad_alloc|out of memory|cannot allocate|memory budget" "$log.err"; then
      status="out of memory (cap $((mem_kb / 1024)) MB)"
    else
      status="failed (exit $rc: $(grep -v '^$' "$log.err" | tail -1 | cut -c1-80))"
    fi
    [ -n "$wall" ] && status="$status after ${wall} s"
    add_row "$name|$triangles|-|-|-|$rss|$status"
  fi
  echo "bench_scale: $name done (exit $rc, ${wall:-?} s wall, load $(cut -d' ' -f1-3 /proc/loadavg))" >&2
done

if [ -n "$csv_out" ]; then
  { echo "scene,triangles,median_s,links,rays,rss_mb,status"
    for row in "${rows[@]}"; do IFS='|' read -r a b c d e f g <<< "$row"; echo "$a,$b,$c,$d,$e,$f,\"$g\""; done
  } > "$csv_out"
fi
