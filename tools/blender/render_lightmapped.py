# Renders a radbake .glb in Blender (headless) with its lightmaps, as an engine would show
# it: outgoing radiance = base colour * lightmap + emission, on an emission shader (no
# lights: everything the scene shows is the bake).
#
#   blender -b --factory-startup -P tools/blender/render_lightmapped.py -- BAKE.glb OUT.png [WIDTH HEIGHT]
#
# The materials are wired by examples/blender/radbake_lightmaps.py (base colour x the atlas EXR
# through TEXCOORD_1 + emission, on an emission shader). The view is the glb's first camera;
# Filmic tone mapping, exposure from the brightest lit texel.
import math
import os
import sys

import bpy

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "examples", "blender"))
from radbake_lightmaps import wire_radbake_lightmaps  # noqa: E402  (also fixes numpy.bool)

args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
if len(args) not in (2, 4):
    sys.exit("usage: blender -b -P render_lightmapped.py -- BAKE.glb OUT.png [WIDTH HEIGHT]")
glb, out = os.path.abspath(args[0]), os.path.abspath(args[1])
width, height = (int(args[2]), int(args[3])) if len(args) == 4 else (480, 480)

bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.gltf(filepath=glb)
scene = bpy.context.scene


wired = wire_radbake_lightmaps(glb, scene)
if not wired:
    sys.exit("render_lightmapped: no material names a radbake lightmap (bake with lightmaps)")
peak = 0.0
for image in {n.image.name: n.image for m in wired for n in m.node_tree.nodes if n.type == "TEX_IMAGE"}.values():
    if image.filepath.endswith(".exr"):
        pixels = list(image.pixels)
        peak = max(peak, max(max(pixels[i], pixels[i + 1], pixels[i + 2]) for i in range(0, len(pixels), 4)))

world = bpy.data.worlds.new("black")
world.color = (0, 0, 0)
scene.world = world
cameras = [o for o in scene.objects if o.type == "CAMERA"]
if not cameras:
    sys.exit("render_lightmapped: the glb has no camera (a Viewpoint)")
scene.camera = cameras[0]
scene.render.engine = "CYCLES"
scene.cycles.device = "CPU"
scene.cycles.samples = 16  # emission only: the samples only anti-alias
scene.cycles.use_denoising = False
scene.render.resolution_x, scene.render.resolution_y = width, height
scene.render.resolution_percentage = 100
scene.render.image_settings.file_format = "PNG"
scene.render.image_settings.color_mode = "RGB"
scene.render.image_settings.compression = 100
scene.view_settings.view_transform = "Filmic"
# The brightest texel (times a white albedo) two stops over middle grey, under Filmic's white.
scene.view_settings.exposure = -math.log2(peak if peak > 0 else 1.0) + 2.0
scene.render.filepath = out
bpy.ops.render.render(write_still=True)
print(f"render_lightmapped: wrote {out}")
