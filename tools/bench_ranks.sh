#!/usr/bin/env bash
# One bake shared between MPI ranks against one process (issue 29): the whole bake's wall time,
# one process of one thread against `mpirun -np N` ranks of one thread each (bound to cores),
# medians over runs taken in turn; each rank's peak memory against the one process's; whether
# the outputs are the same bytes; what the lead exchanged (timings.json's exchanged_mb).
#
#   tools/bench_ranks.sh SCENE [N] [RUNS] [radbake options...]    (N ranks, default 2; RUNS, default 3)
#
# Run from the repository root after tools/build.sh (radbake built with MPI: libopenmpi-dev).
set -euo pipefail
scene="$1"; shift
ranks="${1:-2}"; [[ $# -gt 0 ]] && shift
runs="${1:-3}"; [[ $# -gt 0 ]] && shift
radbake="${RADBAKE:-build/src/radbake}"
mpi=(mpirun -np "$ranks")
[[ $(id -u) -eq 0 ]] && mpi+=(--allow-run-as-root)
# A rank per core; more ranks than cores (a check of the bytes, not of speed) share them unbound.
if (( ranks > $(nproc) )); then mpi+=(--oversubscribe --bind-to none); else mpi+=(--bind-to core --map-by core); fi
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
median() { sort -g | awk '{a[NR] = $1} END {print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2}'; }
for run in $(seq 1 "$runs"); do
    /usr/bin/time -f "%e %M" -o "$work/one$run.time" "$radbake" bake "$scene" -q --threads 1 -o "$work/one" "$@" \
        > /dev/null 2> "$work/one.err" || { cat "$work/one.err" >&2; exit 1; }
    "${mpi[@]}" /usr/bin/time -f "%e %M" -o "$work/ranks$run.%q{OMPI_COMM_WORLD_RANK}.time" \
        "$radbake" bake "$scene" -q --threads 1 -o "$work/ranks" "$@" > /dev/null 2> "$work/ranks.err" \
        || { cat "$work/ranks.err" >&2; exit 1; }
    echo "run $run: one $(cut -d' ' -f1 "$work/one$run.time") s, ranks $(cat "$work"/ranks$run.*.time | cut -d' ' -f1 | sort -g | tail -1) s" >&2
done
one_wall=$(cat "$work"/one*.time | cut -d' ' -f1 | median)
ranks_wall=$(for run in $(seq 1 "$runs"); do cat "$work"/ranks$run.*.time | cut -d' ' -f1 | sort -g | tail -1; done | median)
one_rss=$(cat "$work"/one*.time | cut -d' ' -f2 | sort -g | tail -1)
rank_rss=$(cat "$work"/ranks*.time | cut -d' ' -f2 | sort -g | tail -1)
same=yes
while IFS= read -r f; do
    cmp -s "$work/one/$f" "$work/ranks/$f" || { echo "differs: $f"; same=no; }
done < <(cd "$work/one" && find . -type f ! -name timings.json | sort)
[[ $(cd "$work/one" && find . -type f | wc -l) == $(cd "$work/ranks" && find . -type f | wc -l) ]] || same=no
exchanged=$(python3 -c "
import json; t = json.load(open('$work/ranks/timings.json'))
print('%.1f MiB in %d exchanges (%.1f s, waits included); its share of the work %.1f s' % (
    t.get('exchanged_mb', 0), t.get('exchanges', 0), t.get('exchange_s', 0), t.get('shared_s', 0)))")
phases=$(python3 -c "
import json; t = json.load(open('$work/ranks/timings.json'))['phases']
print(', '.join('%s %.2f' % (k, v) for k, v in t.items()))")
python3 - "$one_wall" "$ranks_wall" "$one_rss" "$rank_rss" <<PY
import sys
one, many, one_rss, rank_rss = map(float, sys.argv[1:])
print(f"scene: $scene, $ranks ranks of 1 thread against 1 process of 1 thread, median of $runs")
print(f"wall: one process {one:.2f} s, ranks {many:.2f} s: speed-up {one / many:.2f} x")
print(f"peak memory: one process {one_rss / 1024:.0f} MiB, largest rank {rank_rss / 1024:.0f} MiB: {rank_rss / one_rss:.2f} x")
print(f"lead exchanged: $exchanged; same bytes: $same")
print(f"last ranks run's phases (s): $phases")
PY
cp "$work/ranks/timings.json" "${RANKS_TIMINGS:-/dev/null}"  # for tools/scale_model.py
[[ $same == yes ]]
