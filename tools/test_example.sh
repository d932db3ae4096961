#!/usr/bin/env bash
# The installed package at work (ctest 'example'): installs the build tree into a temporary
# prefix, builds examples/bake_scene against it with find_package(radbake), bakes the
# Cornell Box with it and with `radbake bake`, and requires the same glb, PLY and EXR bytes.
# Usage: test_example.sh BUILD_DIR
set -euo pipefail
build=$(cd "$1" && pwd)
source_dir=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

cmake --install "$build" --prefix "$work/prefix" >/dev/null
cmake -S "$source_dir/examples/bake_scene" -B "$work/example" -G Ninja -DCMAKE_BUILD_TYPE=Release \
      -DCMAKE_PREFIX_PATH="$work/prefix" >/dev/null
cmake --build "$work/example" >/dev/null

scene="$source_dir/scenes/cornell_box.wrl"
"$work/example/bake_scene" "$scene" "$work/library"
"$work/prefix/bin/radbake" bake "$scene" -o "$work/program" -q
for file in cornell_box.glb cornell_box.ply lightmaps/cornell_box_0.exr; do
  cmp "$work/library/$file" "$work/program/$file"
done
"$work/prefix/bin/radbake" compare "$work/library" "$work/program" --rel-tol 0 --abs-tol 0 >/dev/null
echo "example: bake_scene and radbake bake wrote the same glb, PLY and EXR bytes"
