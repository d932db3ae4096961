// MOZ_lightmap for glTF Transform (https://gltf-transform.dev), so that `gltf-transform copy`,
// `optimize` and scripts keep radbake's lightmaps: without it the extension is dropped, its
// atlas orphaned and pruned, and TEXCOORD_1 removed as unused. The texture is referenced from
// the material as a texture info, so pruning keeps it and the UV set it reads.
//
//   gltf-transform --config examples/web/gltf_transform_moz_lightmap.mjs optimize in.glb out.glb \
//       --texture-compress false
//
// (run from a folder whose node_modules holds @gltf-transform/core and /extensions, as the
// CLI's own). --texture-compress false: the atlas's alpha is an exponent (rgbe8), which a lossy
// or resized re-encoding destroys. In a script: io.registerExtensions([MozLightmap]).
import { Extension, ExtensionProperty, PropertyType, TextureChannel, TextureInfo } from '@gltf-transform/core';
import { ALL_EXTENSIONS } from '@gltf-transform/extensions';

const NAME = 'MOZ_lightmap';

export class Lightmap extends ExtensionProperty {
  static EXTENSION_NAME = NAME;
  init() {
    this.extensionName = NAME;
    this.propertyType = 'Lightmap';
    this.parentTypes = [PropertyType.MATERIAL];
  }
  getDefaults() {
    return Object.assign(super.getDefaults(), { intensity: 1, texture: null, textureInfo: new TextureInfo(this.graph, 'textureInfo') });
  }
  getIntensity() { return this.get('intensity'); }
  setIntensity(intensity) { return this.set('intensity', intensity); }
  getTexture() { return this.getRef('texture'); }
  getTextureInfo() { return this.getRef('texture') ? this.getRef('textureInfo') : null; }
  setTexture(texture) {
    return this.setRef('texture', texture, { channels: TextureChannel.R | TextureChannel.G | TextureChannel.B | TextureChannel.A });
  }
}

export class MozLightmap extends Extension {
  static EXTENSION_NAME = NAME;
  extensionName = NAME;
  prereadTypes = [PropertyType.MESH];
  prewriteTypes = [PropertyType.MESH];

  read() { return this; }
  write() { return this; }

  preread(context) {
    const json = context.jsonDoc.json;
    (json.materials ?? []).forEach((materialDef, index) => {
      const def = materialDef.extensions?.[NAME];
      if (!def) return;
      const lightmap = new Lightmap(this.document.getGraph());
      if (def.intensity !== undefined) lightmap.setIntensity(def.intensity);
      lightmap.setTexture(context.textures[json.textures[def.index].source]);
      context.setTextureInfo(lightmap.getTextureInfo(), def);
      context.materials[index].setExtension(NAME, lightmap);
    });
    return this;
  }

  prewrite(context) {
    const json = context.jsonDoc.json;
    for (const material of this.document.getRoot().listMaterials()) {
      const lightmap = material.getExtension(NAME);
      if (!lightmap?.getTexture()) continue;
      const materialDef = json.materials[context.materialIndexMap.get(material)];
      materialDef.extensions = materialDef.extensions ?? {};
      materialDef.extensions[NAME] = {
        ...context.createTextureInfoDef(lightmap.getTexture(), lightmap.getTextureInfo()),
        intensity: lightmap.getIntensity(),
      };
    }
    return this;
  }
}

// The CLI's --config: every extension it knows, and this one.
export default { extensions: [...ALL_EXTENSIONS, MozLightmap] };
