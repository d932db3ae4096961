#!/usr/bin/env bash
# The read-out split into shards against one bake (issue 29): the shards' CPU time summed
# (each loading the scene and the solution) over one process's read-out, the merge's wall
# time over one whole bake's, and whether the merged outputs are one bake's bytes.
#
#   tools/bench_shards.sh SCENE [N] [radbake options...]     (N shards, default 7)
#
# Prints one line per step and the ratios; exit 1 when the bytes differ. Run from the
# repository root after tools/build.sh; CPU times are user + system (GNU time).
set -euo pipefail
scene="$1"; shift
shards="${1:-7}"; [[ $# -gt 0 ]] && shift
radbake="${RADBAKE:-build/src/radbake}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cpu() { awk '{print $1 + $2}' "$1"; }
wall() { awk '{print $3}' "$1"; }
run() {  # run NAME COMMAND...: GNU time's user, system and wall seconds into $work/NAME.time
    local name="$1"; shift
    /usr/bin/time -f "%U %S %e" -o "$work/$name.time" "$@" > /dev/null 2> "$work/$name.err" || { cat "$work/$name.err" >&2; return 1; }
}
run solve "$radbake" solve "$scene" --solution "$work/s.sol" -q "$@"
run whole "$radbake" bake "$scene" --solution "$work/s.sol" -q -o "$work/whole" "$@"
readout=$(python3 -c "
import json, sys
p = json.load(open('$work/whole/timings.json'))['phases']
print(sum(v for k, v in p.items() if k in ('vertices', 'lightmaps', 'probes')))")
threads=$(python3 -c "import json; print(json.load(open('$work/whole/timings.json'))['threads'])")
parts=()
total=0
for k in $(seq 1 "$shards"); do
    run "gather$k" "$radbake" gather "$scene" --solution "$work/s.sol" --shard "$k/$shards" -o "$work/p$k" \
        --threads 1 -q "$@"
    parts+=("$work/p$k")
    total=$(python3 -c "print($total + $(cpu "$work/gather$k.time"))")
done
run merge "$radbake" merge "${parts[@]}" -q -o "$work/merged"
same=yes
while IFS= read -r f; do
    cmp -s "$work/whole/$f" "$work/merged/$f" || { echo "differs: $f"; same=no; }
done < <(cd "$work/whole" && find . -type f ! -name timings.json | sort)
python3 - <<PY
readout_wall = $readout
threads = $threads
whole_cpu, whole_wall = $(cpu "$work/whole.time"), $(wall "$work/whole.time")
solve_wall = $(wall "$work/solve.time")
merge_wall = $(wall "$work/merge.time")
shard_cpu = $total
# A one-process read-out's CPU: its phases' wall time times the CPU/wall ratio of that bake
# (the bake reads a saved solution, so nearly all of its time is the read-out).
readout_cpu = readout_wall * whole_cpu / whole_wall
print(f"solve wall {solve_wall:.2f} s; one bake from the solution: wall {whole_wall:.2f} s, CPU {whole_cpu:.2f} s, read-out phases {readout_wall:.2f} s wall on {threads} threads")
print(f"$shards shards: CPU summed {shard_cpu:.2f} s = {shard_cpu / readout_cpu:.2f} x the one-process read-out's CPU (about {readout_cpu:.2f} s)")
print(f"merge: wall {merge_wall:.2f} s = {merge_wall / (solve_wall + whole_wall):.3f} x a whole bake's wall (solve + read-out)")
print("merged outputs: " + ("$same" == "yes" and "the same bytes as one bake (timings.json aside)" or "DIFFER"))
PY
[[ "$same" == yes ]]
