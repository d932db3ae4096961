# Wires radbake's lightmaps into the materials Blender's glTF importer made from a baked glb,
# so the viewport and renders show the bake: each lightmapped material becomes
#     shown = base colour x lightmap + emission
# on an emission shader (the bake holds all of the scene's light, so no lamp is needed).
# Blender's importer reads neither MOZ_lightmap nor its image; this script reads what radbake
# writes beside it: each material's extras (custom properties after import) name the atlas's
# EXR (radbake_lightmap, relative to the glb: exact linear H/pi), and the lightmap UVs are the
# mesh's second UV map (TEXCOORD_1).
#
#   blender -b --factory-startup -P examples/blender/radbake_lightmaps.py -- BAKE.glb OUT.blend
#
# or, from Blender's Python console or another script, after importing the glb:
#   wire_radbake_lightmaps(glb_path)       # returns the materials it wired
import os
import sys

import bpy
import numpy

# Debian 12's Blender 3.4 glTF importer uses numpy.bool, which its numpy 1.24 no longer has.
if "bool" not in numpy.__dict__:
    numpy.bool = bool


def _base_colour(material):
    """The socket feeding the Principled BSDF's base colour, or its constant colour."""
    bsdf = next(n for n in material.node_tree.nodes if n.type == "BSDF_PRINCIPLED")
    base = bsdf.inputs["Base Color"]
    return bsdf, (base.links[0].from_socket if base.is_linked else tuple(base.default_value)[:3])


def _wire(material, glb_dir, lightmap_uv):
    exr = material.get("radbake_lightmap")
    if exr is None:
        return False
    nodes, links = material.node_tree.nodes, material.node_tree.links
    bsdf, base = _base_colour(material)
    output = next(n for n in nodes if n.type == "OUTPUT_MATERIAL")

    image = bpy.data.images.load(os.path.join(glb_dir, exr), check_existing=True)
    image.colorspace_settings.name = "Non-Color"  # linear light, not colours
    uv = nodes.new("ShaderNodeUVMap")
    uv.uv_map = lightmap_uv
    texture = nodes.new("ShaderNodeTexImage")
    texture.image = image
    texture.interpolation = "Linear"  # no mipmaps across charts
    texture.extension = "EXTEND"
    links.new(uv.outputs["UV"], texture.inputs["Vector"])

    reflected = nodes.new("ShaderNodeVectorMath")  # base colour x H/pi
    reflected.operation = "MULTIPLY"
    if isinstance(base, tuple):
        reflected.inputs[0].default_value = base
    else:
        links.new(base, reflected.inputs[0])
    links.new(texture.outputs["Color"], reflected.inputs[1])

    radiance = nodes.new("ShaderNodeVectorMath")  # + emission
    radiance.operation = "ADD"
    links.new(reflected.outputs["Vector"], radiance.inputs[0])
    emission = bsdf.inputs["Emission"]
    strength = bsdf.inputs["Emission Strength"].default_value if "Emission Strength" in bsdf.inputs else 1.0
    if emission.is_linked:
        scaled = nodes.new("ShaderNodeVectorMath")
        scaled.operation = "SCALE"
        links.new(emission.links[0].from_socket, scaled.inputs[0])
        scaled.inputs["Scale"].default_value = strength
        links.new(scaled.outputs["Vector"], radiance.inputs[1])
    else:
        radiance.inputs[1].default_value = tuple(c * strength for c in tuple(emission.default_value)[:3])

    shader = nodes.new("ShaderNodeEmission")
    links.new(radiance.outputs["Vector"], shader.inputs["Color"])
    shader.inputs["Strength"].default_value = 1.0
    links.new(shader.outputs["Emission"], output.inputs["Surface"])
    return True


def wire_radbake_lightmaps(glb_path, scene=None):
    """Wires every lightmapped material of the imported glb's meshes; returns those materials."""
    scene = scene or bpy.context.scene
    glb_dir = os.path.dirname(os.path.abspath(glb_path))
    wired = {}
    for obj in scene.objects:
        if obj.type != "MESH" or len(obj.data.uv_layers) < 2:
            continue  # no lightmap UVs: shown as imported
        for slot in obj.material_slots:
            material = slot.material
            if material is not None and material.name not in wired and _wire(material, glb_dir, obj.data.uv_layers[1].name):
                wired[material.name] = material
    return list(wired.values())


def _main(argv):
    args = argv[argv.index("--") + 1:] if "--" in argv else []
    if len(args) != 2:
        sys.exit("usage: blender -b -P radbake_lightmaps.py -- BAKE.glb OUT.blend")
    glb, out = os.path.abspath(args[0]), os.path.abspath(args[1])
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=glb)
    wired = wire_radbake_lightmaps(glb)
    if not wired:
        sys.exit("radbake_lightmaps: no material names a radbake lightmap (bake with lightmaps)")
    world = bpy.data.worlds.new("black")  # the bake is the light: no world light
    world.color = (0, 0, 0)
    bpy.context.scene.world = world
    bpy.ops.wm.save_as_mainfile(filepath=out)
    print(f"radbake_lightmaps: wired {len(wired)} materials, wrote {out}")


if __name__ == "__main__":
    _main(sys.argv)
