#!/usr/bin/env bash
# Sets up, builds, and runs radbake's main job on the bundled default scene.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh
bash tools/build.sh
./build/src/radbake bake scenes/cornell_box.wrl -o out/cornell_box
