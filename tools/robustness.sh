#!/usr/bin/env bash
# Robustness run: `radbake info` over every scene file in ../shared/scenes (beside the
# repository). Each file must either succeed (exit 0 with output) or fail with exit 1 and a
# located `...: error: ...` line on stderr. A crash, a hang (over 10 s), a silent success or
# an error without location fails the run.
#
#   tools/robustness.sh [path/to/radbake] [scenes-dir]
#
# Exit 0 when nothing is bad, 1 otherwise, 77 (ctest SKIP) when the scenes folder is absent.
set -u

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
radbake="${1:-$root/build/src/radbake}"
scenes="${2:-$root/../shared/scenes}"
limit_seconds=10

if [[ ! -d "$scenes" ]]; then
    echo "robustness: no scenes folder at $scenes, skipped"
    exit 77
fi
if [[ ! -x "$radbake" ]]; then
    echo "robustness: $radbake is not an executable" >&2
    exit 1
fi

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# Scene files: VRML (also gzipped), X3D classic, and what Assimp reads. Side files (.mtl,
# docs, Mitsuba .xml) are not scenes.
is_scene() {
    local name="${1,,}"
    case "$name" in
        *.wrl | *.wrl.gz | *.vrml | *.x3dv | *.x3d | *.obj | *.gltf | *.glb | *.ply | *.fbx | *.dae | *.3ds | \
            *.stl | *.off | *.blend | *.ase | *.lwo | *.lws | *.ms3d | *.ac | *.3mf | *.x | *.b3d | *.md2 | *.md3 | *.smd)
            return 0 ;;
    esac
    return 1
}

ok=0
located=0
bad=0
while IFS= read -r -d '' file; do
    is_scene "$file" || continue
    start=$(date +%s%N)
    # The collection is one tree: its scenes reach beside their folders (../textures/...).
    timeout "$limit_seconds" "$radbake" info "$file" --read-root "$scenes" >"$work/out" 2>"$work/err"
    rc=$?
    elapsed_ms=$((($(date +%s%N) - start) / 1000000))
    seconds="$((elapsed_ms / 1000)).$(printf '%03d' $((elapsed_ms % 1000)))"
    # A located error names at least a file before ": error: "; an unlocated one starts with "error:".
    first_error="$(grep -m1 -E '^.+: error: ' "$work/err")"
    unlocated="$(grep -m1 -E '^error: ' "$work/err")"
    if [[ $rc -eq 0 && -s "$work/out" ]]; then
        status=ok
        ok=$((ok + 1))
    elif [[ $rc -eq 1 && -n "$first_error" && -z "$unlocated" ]]; then
        status=error
        located=$((located + 1))
    else
        if [[ $rc -eq 124 ]]; then
            status="BAD(timeout)"
        elif [[ $rc -gt 128 ]]; then
            status="BAD(signal $((rc - 128)))"
        elif [[ $rc -eq 0 ]]; then
            status="BAD(no output)"
        elif [[ -n "$unlocated" ]]; then
            status="BAD(unlocated)"
            first_error="$unlocated"
        else
            status="BAD(exit $rc)"
            first_error="$(head -n1 "$work/err")"
        fi
        bad=$((bad + 1))
    fi
    first_error="${first_error#"$file"}"  # the path is already on the line
    printf '%-16s %7ss  %s  %s\n' "$status" "$seconds" "${file#"$scenes"/}" "${first_error:0:200}"
done < <(find "$scenes" -type f -print0 | sort -z)

echo "robustness: $ok ok, $located located errors, $bad bad"
[[ $bad -eq 0 ]]
