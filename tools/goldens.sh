#!/usr/bin/env bash
# Golden bakes of the shipped scenes (baked/<name>/), for the golden-file regression test.
#
#   tools/goldens.sh update [radbake]   re-bake every shipped scene into baked/
#   tools/goldens.sh check  [radbake]   re-bake into a temporary folder and `radbake compare`
#                                       each against baked/ (exit 1 on any difference)
#
# Every .wrl under scenes/ is baked at draft quality (fast), with its .probes file when it
# has one; the Cornell Box also gets --preview, so baked/cornell_box/preview/ holds a picture.
# Both modes run Embree on SSE4.2 (RADBAKE_EMBREE_CONFIG), so a golden is the same bytes on
# any x86-64 machine.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
mode="${1:-}"
radbake="${2:-$root/build/src/radbake}"
if [[ "$mode" != update && "$mode" != check ]]; then
    echo "usage: tools/goldens.sh update|check [path/to/radbake]" >&2
    exit 2
fi
if [[ ! -x "$radbake" ]]; then
    echo "goldens: $radbake is not an executable" >&2
    exit 2
fi

radbake="$(cd "$(dirname "$radbake")" && pwd)/$(basename "$radbake")"
# Embree's traversal differs between SSE, AVX2 and AVX-512 builds (rays grazing an edge can
# land either way): goldens are baked and checked with one instruction set on every machine.
export RADBAKE_EMBREE_CONFIG="isa=sse4.2"
cd "$root"  # scene paths are given relative to the repository, as stats.json records them
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
failed=0
count=0
while IFS= read -r scene; do
    name="$(basename "$scene" .wrl)"
    args=(bake "$scene" --quality draft --quiet)
    [[ -f "${scene%.wrl}.probes" ]] && args+=(--probes "${scene%.wrl}.probes")
    [[ "$name" == cornell_box ]] && args+=(--preview)
    count=$((count + 1))
    if [[ "$mode" == update ]]; then
        rm -rf "$root/baked/$name"
        "$radbake" "${args[@]}" -o "$root/baked/$name" >/dev/null
        rm -f "$root/baked/$name/timings.json"  # what depends on the run (time, memory) is no golden
        echo "goldens: baked/$name"
    else
        if ! "$radbake" "${args[@]}" -o "$work/$name" >"$work/$name.log" 2>&1; then
            echo "goldens: FAILED to bake $scene:" >&2
            cat "$work/$name.log" >&2
            failed=$((failed + 1))
            continue
        fi
        if "$radbake" compare "$root/baked/$name" "$work/$name" >"$work/$name.compare" 2>&1; then
            echo "goldens: $name matches"
        else
            echo "goldens: $name DIFFERS from baked/$name:" >&2
            cat "$work/$name.compare" >&2
            failed=$((failed + 1))
        fi
    fi
done < <(find scenes -name '*.wrl' | LC_ALL=C sort)

if [[ "$mode" == check ]]; then
    echo "goldens: $((count - failed)) of $count scenes match their golden bakes"
    ((failed == 0)) || exit 1
fi
