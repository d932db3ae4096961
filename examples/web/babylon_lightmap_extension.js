// A Babylon.js glTF loader extension for radbake's lightmaps (MOZ_lightmap). Babylon adds a
// material's lightmap to its lit colour, or, as a shadow map, multiplies that colour by it;
// a baked lightmap holds all of the light, so each lightmapped material is made unlit (its
// colour is the albedo) with the atlas as a shadow-map lightmap: shown = albedo x H/pi, plus
// the emission, which is what the texels mean. The atlas is decoded to linear half floats
// and read through TEXCOORD_1. Babylon.js 7 or later (@babylonjs/core, @babylonjs/loaders).
//
//   import { registerRadbakeLightmaps } from './babylon_lightmap_extension.js';
//   registerRadbakeLightmaps();   // before loading: then SceneLoader / ImportMeshAsync as usual
//
// Dynamic lights do not light the lightmapped materials (the bake holds the scene's light).
import { Constants } from '@babylonjs/core/Engines/constants.js';
import { Color3 } from '@babylonjs/core/Maths/math.color.js';
import { RawTexture } from '@babylonjs/core/Materials/Textures/rawTexture.js';
import { Texture } from '@babylonjs/core/Materials/Textures/texture.js';
import { ToHalfFloat } from '@babylonjs/core/Misc/halfFloat.js';
import { GLTFLoader } from '@babylonjs/loaders/glTF/2.0/glTFLoader.js';
import { registerGLTFExtension, unregisterGLTFExtension } from '@babylonjs/loaders/glTF/2.0/glTFLoaderExtensionRegistry.js';
import { decodeRadbakeLightmap, isRadbakeLightmap } from './radbake_lightmap_decode.js';

const NAME = 'MOZ_lightmap';

class RadbakeLightmapExtension {
  constructor(loader) {
    this.name = NAME;
    this.order = 200;
    this._loader = loader;
    this.enabled = loader.isExtensionUsed(NAME);
    this._textures = new Map(); // one decoded texture per atlas
  }

  dispose() {
    this._loader = null;
    this._textures.clear();
  }

  loadMaterialPropertiesAsync(context, material, babylonMaterial) {
    return GLTFLoader.LoadExtensionAsync(context, material, this.name, async (extensionContext, extension) => {
      await this._loader.loadMaterialPropertiesAsync(context, material, babylonMaterial);
      if (!isRadbakeLightmap(material)) return; // not a radbake atlas: left as the loader made it
      const key = extension.index;
      if (!this._textures.has(key)) this._textures.set(key, this._decodedTexture(extensionContext, key));
      const texture = await this._textures.get(key);
      texture.coordinatesIndex = extension.texCoord ?? 0; // a texture info: TEXCOORD_0 unless it says
      if (material.extras?.radbake_lightmap_quantity === 'radiance') {
        // The atlas holds the albedo already (--lightmap-quantity radiance): shown on white.
        babylonMaterial.albedoColor = Color3.White();
        babylonMaterial.albedoTexture = null;
      }
      babylonMaterial.unlit = true;
      babylonMaterial.lightmapTexture = texture;
      babylonMaterial.useLightmapAsShadowmap = true;
    });
  }

  async _decodedTexture(context, textureIndex) {
    const gltf = this._loader.gltf;
    const image = gltf.images[gltf.textures[textureIndex].source];
    const bytes = await this._loader.loadImageAsync(`${context}/image`, image);
    const decoded = await decodeRadbakeLightmap(bytes);
    const halves = new Uint16Array(decoded.data.length);
    for (let i = 0; i < halves.length; ++i) halves[i] = ToHalfFloat(decoded.data[i]);
    const texture = RawTexture.CreateRGBATexture(halves, decoded.width, decoded.height, this._loader.babylonScene,
      false /* no mipmaps: they would blend charts */, false /* row 0 at v = 0, as glTF */,
      Texture.BILINEAR_SAMPLINGMODE, Constants.TEXTURETYPE_HALF_FLOAT);
    texture.wrapU = texture.wrapV = Texture.CLAMP_ADDRESSMODE;
    texture.gammaSpace = false; // linear light, not sRGB colours
    texture.name = image.name ?? 'radbake lightmap';
    return texture;
  }
}

// Registers the extension with Babylon's glTF loader (safe to call more than once).
export function registerRadbakeLightmaps() {
  unregisterGLTFExtension(NAME);
  registerGLTFExtension(NAME, true, (loader) => new RadbakeLightmapExtension(loader));
}
