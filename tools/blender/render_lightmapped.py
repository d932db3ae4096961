# Renders a radbake .glb in Blender (headless) with its lightmaps, as an engine would show
# it: outgoing radiance = base colour * lightmap + emission, on an emission shader (no
# lights: everything the scene shows is the bake).
#
#   blender -b --factory-startup -P tools/blender/render_lightmapped.py -- BAKE.glb OUT.png [WIDTH HEIGHT]
#
# Blender's glTF importer does not read MOZ_lightmap, so the script reads what radbake puts
# beside it: each lightmapped material's extras (custom properties after import) name the
# atlas PNG (radbake_lightmap_png, relative to the glb) and its scale (radbake_lightmap_scale:
# value = sample / 65535 * scale, linear 16-bit); the lightmap UVs are the second UV map (TEXCOORD_1).
# The view is the glb's first camera; Filmic tone mapping, exposure from the brightest atlas.
import math
import os
import sys

import bpy
import numpy

# Debian 12's Blender 3.4 glTF importer uses numpy.bool, which its numpy 1.24 no longer has.
if "bool" not in numpy.__dict__:
    numpy.bool = bool

args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
if len(args) not in (2, 4):
    sys.exit("usage: blender -b -P render_lightmapped.py -- BAKE.glb OUT.png [WIDTH HEIGHT]")
glb, out = os.path.abspath(args[0]), os.path.abspath(args[1])
width, height = (int(args[2]), int(args[3])) if len(args) == 4 else (480, 480)

bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.gltf(filepath=glb)
scene = bpy.context.scene


def lightmap_material(material, mesh_uv):
    png = material.get("radbake_lightmap_png")
    scale = material.get("radbake_lightmap_scale")
    if png is None or scale is None:
        return False
    nodes, links = material.node_tree.nodes, material.node_tree.links
    bsdf = next(n for n in nodes if n.type == "BSDF_PRINCIPLED")
    output = next(n for n in nodes if n.type == "OUTPUT_MATERIAL")

    image = bpy.data.images.load(os.path.join(os.path.dirname(glb), png), check_existing=True)
    image.colorspace_settings.name = "Non-Color"  # linear bytes, not sRGB
    uv = nodes.new("ShaderNodeUVMap")
    uv.uv_map = mesh_uv
    texture = nodes.new("ShaderNodeTexImage")
    texture.image = image
    texture.interpolation = "Linear"
    texture.extension = "EXTEND"
    links.new(uv.outputs["UV"], texture.inputs["Vector"])

    light = nodes.new("ShaderNodeVectorMath")  # sample / 65535 * scale = H/pi
    light.operation = "SCALE"
    links.new(texture.outputs["Color"], light.inputs[0])
    light.inputs["Scale"].default_value = float(scale)

    reflected = nodes.new("ShaderNodeVectorMath")  # albedo * H/pi
    reflected.operation = "MULTIPLY"
    base = bsdf.inputs["Base Color"]
    if base.is_linked:
        links.new(base.links[0].from_socket, reflected.inputs[0])
    else:
        reflected.inputs[0].default_value = tuple(base.default_value)[:3]
    links.new(light.outputs["Vector"], reflected.inputs[1])

    radiance = nodes.new("ShaderNodeVectorMath")  # + emission
    radiance.operation = "ADD"
    links.new(reflected.outputs["Vector"], radiance.inputs[0])
    emission_in = bsdf.inputs["Emission"]
    strength = bsdf.inputs["Emission Strength"].default_value if "Emission Strength" in bsdf.inputs else 1.0
    if emission_in.is_linked:
        links.new(emission_in.links[0].from_socket, radiance.inputs[1])
    else:
        radiance.inputs[1].default_value = tuple(c * strength for c in tuple(emission_in.default_value)[:3])

    shader = nodes.new("ShaderNodeEmission")
    links.new(radiance.outputs["Vector"], shader.inputs["Color"])
    shader.inputs["Strength"].default_value = 1.0
    links.new(shader.outputs["Emission"], output.inputs["Surface"])
    return True


scales = []
done = set()
for obj in scene.objects:
    if obj.type != "MESH":
        continue
    if len(obj.data.uv_layers) < 2:
        print(f"render_lightmapped: {obj.name} has no lightmap UVs, shown as imported")
        continue
    lightmap_uv = obj.data.uv_layers[1].name
    for slot in obj.material_slots:
        material = slot.material
        if material is None or material.name in done:
            continue
        done.add(material.name)
        if lightmap_material(material, lightmap_uv):
            scales.append(float(material["radbake_lightmap_scale"]))
if not scales:
    sys.exit("render_lightmapped: no material names a radbake lightmap (bake with lightmaps)")

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
# The brightest atlas's scale (times a white albedo) two stops over middle grey, under Filmic's white.
scene.view_settings.exposure = -math.log2(max(scales)) + 2.0
scene.render.filepath = out
bpy.ops.render.render(write_still=True)
print(f"render_lightmapped: wrote {out}")
