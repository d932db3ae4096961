#!/usr/bin/env bash
# Fuzzing run: builds the libFuzzer targets of tools/fuzz/ (clang, ASan + UBSan) in a build
# folder of their own and runs each for a set time, two at a time, each on a scratch copy of
# its seeds (the committed seeds never grow). Prints per target the executions, exec/s,
# coverage (libFuzzer's cov: and ft:), the corpus size and every crash, leak, timeout or OOM
# input saved.
#
#   tools/fuzz.sh [--minutes N] [--targets vrml,obj,ply,gltf] [--jobs J] [--build-dir DIR]
#                 [--work DIR] [--timeout S] [--rss-limit-mb MB] [--no-build]
#
# Exit 0 when no target found anything, 1 on a finding, 2 on a bad command line or build.
# The run's folder (logs, grown corpora, findings) is printed; --work DIR reuses one, so a
# second run starts from the corpus the first grew.
set -uo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
minutes=30
targets="vrml,obj,ply,gltf"
jobs=2
build="$root/build-fuzz"
work=""
timeout_s=10
rss_mb=2048
do_build=1

usage() { sed -n '2,13p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; exit "${1:-2}"; }
while [[ $# -gt 0 ]]; do
    case "$1" in
        --minutes) minutes="${2:-}"; shift 2 ;;
        --targets) targets="${2:-}"; shift 2 ;;
        --jobs) jobs="${2:-}"; shift 2 ;;
        --build-dir) build="${2:-}"; shift 2 ;;
        --work) work="${2:-}"; shift 2 ;;
        --timeout) timeout_s="${2:-}"; shift 2 ;;
        --rss-limit-mb) rss_mb="${2:-}"; shift 2 ;;
        --no-build) do_build=0; shift ;;
        -h|--help) usage 0 ;;
        *) echo "fuzz.sh: unknown argument '$1'" >&2; usage ;;
    esac
done
build="$(realpath -m "$build")"  # the targets run from their own folders
for value in "$minutes" "$jobs" "$timeout_s" "$rss_mb"; do
    [[ "$value" =~ ^[1-9][0-9]*$ ]] || { echo "fuzz.sh: '$value' is not a positive whole number" >&2; exit 2; }
done

# target name -> binary, seeds, dictionary (empty: none)
binary_of() { case "$1" in vrml) echo fuzz_vrml ;; obj|ply|gltf) echo "fuzz_assimp_$1" ;; *) return 1 ;; esac; }
dict_of() { [[ -f "$root/tools/fuzz/$1.dict" ]] && echo "$root/tools/fuzz/$1.dict"; return 0; }
IFS=, read -r -a names <<< "$targets"
binaries=()
for name in "${names[@]}"; do
    binary="$(binary_of "$name")" || { echo "fuzz.sh: unknown target '$name' (vrml, obj, ply, gltf)" >&2; exit 2; }
    [[ -d "$root/tools/fuzz/corpus_$name" ]] || { echo "fuzz.sh: no seeds in tools/fuzz/corpus_$name" >&2; exit 2; }
    binaries+=("$binary")
done

if [[ $do_build == 1 ]]; then
    CC=clang CXX=clang++ cmake -S "$root" -B "$build" -G Ninja -DRADBAKE_FUZZ=ON -DRADBAKE_BENCHMARKS=OFF \
        >/dev/null || exit 2
    nice -n 10 cmake --build "$build" --target "${binaries[@]}" || exit 2
fi

[[ -n "$work" ]] || work="$build/runs/$(date +%Y%m%d-%H%M%S)"
mkdir -p "$work" || exit 2
work="$(cd "$work" && pwd)"
echo "fuzz.sh: $minutes minute(s) per target, $jobs at a time, in $work"

# One target: a scratch corpus seeded from the committed one, its own TMPDIR (the harness's
# scratch folders live there and are removed with it), findings under artifacts/.
run_target() {
    local name="$1" binary="$2" dir="$work/$1"
    mkdir -p "$dir/corpus" "$dir/artifacts" "$dir/tmp"
    cp -n "$root/tools/fuzz/corpus_$name"/* "$dir/corpus/"
    local dict; dict="$(dict_of "$name")"
    local args=(-fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1
                -max_total_time=$((minutes * 60)) -timeout="$timeout_s" -rss_limit_mb="$rss_mb"
                -artifact_prefix="$dir/artifacts/" -print_final_stats=1)
    [[ -n "$dict" ]] && args+=(-dict="$dict")
    # The outer limit only catches a stuck parent; libFuzzer stops itself at max_total_time.
    (cd "$dir" && TMPDIR="$dir/tmp" timeout -k 30 $((minutes * 60 + 300)) \
        nice -n 15 "$build/tools/$binary" "${args[@]}" "$dir/corpus" >"$dir/log" 2>&1)
    echo $? >"$dir/exit"
    rm -rf "$dir/tmp"
}

running=0
for i in "${!names[@]}"; do
    if (( running >= jobs )); then wait -n; running=$((running - 1)); fi
    run_target "${names[$i]}" "${binaries[$i]}" &
    running=$((running + 1))
done
wait

# The last status line of a -fork run: "#N: cov: C ft: F corp: K exec/s: E oom/timeout/crash: ..."
field() { sed -n "s/.* $1: *\([0-9]*\).*/\1/p" <<< "$2"; }
status=0
printf '%-6s %8s %12s %8s %8s %8s %8s %s\n' target minutes executions exec/s cov ft corpus findings
for name in "${names[@]}"; do
    dir="$work/$name"
    line="$(grep -E '^#[0-9]+: cov:' "$dir/log" | tail -n 1)"
    execs="$(sed -n 's/^#\([0-9]*\):.*/\1/p' <<< "$line")"
    seconds="$(field time "$line")"
    rate="-"; [[ -n "$execs" && -n "$seconds" && "$seconds" -gt 0 ]] && rate=$((execs / seconds))
    findings=("$dir"/artifacts/*)
    [[ -e "${findings[0]}" ]] || findings=()
    printf '%-6s %8s %12s %8s %8s %8s %8s %s\n' "$name" "$(awk "BEGIN{printf \"%.1f\", ${seconds:-0}/60}")" \
        "${execs:--}" "$rate" "$(field cov "$line")" "$(field ft "$line")" "$(ls "$dir/corpus" | wc -l)" \
        "${#findings[@]}"
    for finding in "${findings[@]}"; do echo "    $finding"; done
    if (( ${#findings[@]} > 0 )) || [[ -z "$line" ]] || [[ "$(cat "$dir/exit")" != 0 ]]; then
        status=1
        [[ -z "$line" ]] && echo "    no status line: see $dir/log"
        [[ "$(cat "$dir/exit")" != 0 ]] && echo "    libFuzzer exited $(cat "$dir/exit"): see $dir/log"
    fi
done
exit $status
