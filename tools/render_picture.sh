#!/usr/bin/env bash
# The picture of docs/lightmap_blender.png: the Cornell Box with a textured floor (a checker
# written here, as an ImageTexture on the floor), baked with lightmaps, rendered in Blender
# from the glb alone (tools/blender/render_lightmapped.py): base colour texture through
# TEXCOORD_0 times the lightmap PNG through TEXCOORD_1.
#
#   tools/render_picture.sh [OUT.png] [radbake]      (default docs/lightmap_blender.png)
#
# Needs Blender (Debian: apt-get install blender python3-numpy: its glTF importer needs numpy); runs headless on the CPU (Cycles).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="$(realpath -m "${1:-$root/docs/lightmap_blender.png}")"
radbake="${2:-$root/build/src/radbake}"
command -v blender >/dev/null || { echo "render_picture: needs blender (apt-get install blender python3-numpy)" >&2; exit 2; }
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# An 8 x 8 checker of two greys (sRGB 200 and 90), 64 x 64 pixels, as PNG.
python3 - "$work/checker.png" <<'PY'
import struct, sys, zlib
size, cells = 64, 8
rows = b"".join(b"\0" + bytes(200 if ((x * cells // size) + (y * cells // size)) % 2 else 90
                              for x in range(size) for _ in range(3)) for y in range(size))
def chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
png = (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", size, size, 8, 2, 0, 0, 0))
       + chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b""))
open(sys.argv[1], "wb").write(png)
PY

# The shipped Cornell Box, its floor given the checker (an RGB ImageTexture replaces the
# diffuse colour; VRML's default texture coordinates span the floor); 'White' stays
# defined for the shapes that USE it.
python3 - "$root/scenes/cornell_box.wrl" "$work/cornell_textured.wrl" <<'PY'
import sys
text = open(sys.argv[1]).read()
white = "appearance DEF White Appearance { material Material { diffuseColor 0.738 0.736 0.737 } }"
assert text.count(white) == 1 and text.count("appearance USE White") >= 1
text = text.replace(white, 'appearance DEF Checker Appearance { material Material { diffuseColor 1 1 1 }\n'
                    '    texture ImageTexture { url "checker.png" } }', 1)
text = text.replace("appearance USE White", white, 1)
open(sys.argv[2], "w").write(text)
PY

"$radbake" bake "$work/cornell_textured.wrl" --quality draft --texel-density 64 --quiet -o "$work/baked"
nice -n 10 blender -b --factory-startup -noaudio --python-exit-code 1 -P "$root/tools/blender/render_lightmapped.py" -- \
    "$work/baked/cornell_textured.glb" "$out" 400 400 >"$work/blender.log" 2>&1 ||
    { cat "$work/blender.log" >&2; exit 1; }
grep "render_lightmapped:" "$work/blender.log" || true
