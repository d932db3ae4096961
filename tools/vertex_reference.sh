#!/usr/bin/env bash
# Per-vertex Monte Carlo reference for the accuracy yardstick (issue 13).
#
#   tools/vertex_reference.sh SCENE OUTDIR [--samples N] [--target-se F] [--pilot N]
#                             [--threads T] [--lit max|median] [--build DIR]
#
# Writes into OUTDIR:
#   vertices.probes  one probe per vertex of the scene's meshes (per plane where faces with
#                    different normals share it), nudged 1e-4 x the scene's diagonal into its own
#                    face, normal = the face's (tools/vertex_probes.cpp says how);
#   pilot.csv        reference_mc with --pilot paths per probe (default 1024), unless --samples;
#   reference.csv    reference_mc with N paths per probe: N = --samples, or else the pilot's count
#                    scaled so that the RMS relative standard error over lit vertices
#                    (tools/vertex_error.py's definition) comes to --target-se (default 0.005).
# Then score a bake made on the same probe file:
#   build/src/radbake bake SCENE --probes OUTDIR/vertices.probes --no-lightmaps -o BAKE
#   python3 tools/vertex_error.py BAKE OUTDIR/reference.csv --probes OUTDIR/vertices.probes
# reference_mc takes material reflectances only: no textures, no colours per face or vertex (its header).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
usage() { sed -n '4,5p' "$0" | sed 's/^# *//' >&2; exit 2; }
[ $# -ge 2 ] || usage
scene="$1"; out="$2"; shift 2
samples=""; target="0.005"; pilot=1024; threads=0; lit="max"; build="$here/../build"
while [ $# -gt 0 ]; do
  case "$1" in
    --samples) samples="$2"; shift 2 ;;
    --target-se) target="$2"; shift 2 ;;
    --pilot) pilot="$2"; shift 2 ;;
    --threads) threads="$2"; shift 2 ;;
    --lit) lit="$2"; shift 2 ;;
    --build) build="$2"; shift 2 ;;
    *) usage ;;
  esac
done
for tool in vertex_probes reference_mc; do
  [ -x "$build/tools/$tool" ] || { echo "vertex_reference: $build/tools/$tool missing: build with tools/build.sh" >&2; exit 1; }
done
mkdir -p "$out"
"$build/tools/vertex_probes" "$scene" "$out/vertices.probes"
if [ -z "$samples" ]; then
  "$build/tools/reference_mc" "$scene" "$out/vertices.probes" --samples "$pilot" --threads "$threads" --seed 2 \
    -o "$out/pilot.csv"
  samples=$(VERTEX_TOOLS="$here" python3 -c '
import math, os, sys
sys.path.insert(0, os.environ["VERTEX_TOOLS"])
import vertex_error
rows = vertex_error.read_csv_rows(sys.argv[1])
pilot, target = int(sys.argv[2]), float(sys.argv[3])
mask, _ = vertex_error.lit_mask(rows, sys.argv[4])
noise = vertex_error.reference_noise(rows, mask)
# The standard error falls as 1/sqrt(paths): scale the pilot, round up to 256 paths.
need = pilot * (noise / target) ** 2
print(max(256, int(math.ceil(need / 256.0)) * 256))
sys.stderr.write("vertex_reference: pilot of %d paths: RMS relative standard error %.3f %% over %d lit probes; "
                 "%.3f %% needs about %d paths\n" % (pilot, 100 * noise, sum(mask), 100 * target, need))
' "$out/pilot.csv" "$pilot" "$target" "$lit")
fi
"$build/tools/reference_mc" "$scene" "$out/vertices.probes" --samples "$samples" --threads "$threads" --seed 1 \
  -o "$out/reference.csv"
VERTEX_TOOLS="$here" python3 -c '
import os, sys
sys.path.insert(0, os.environ["VERTEX_TOOLS"])
import vertex_error
rows = vertex_error.read_csv_rows(sys.argv[1])
mask, floor = vertex_error.lit_mask(rows, sys.argv[2])
print("vertex_reference: %s: %d probes, %d lit, %s paths each, RMS relative standard error %.3f %%" % (
    sys.argv[1], len(rows), sum(mask), sys.argv[3], 100 * vertex_error.reference_noise(rows, mask)))
' "$out/reference.csv" "$lit" "$samples"
