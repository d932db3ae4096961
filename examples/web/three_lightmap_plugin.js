// A three.js GLTFLoader plugin for radbake's lightmaps (MOZ_lightmap): each lightmapped
// material gets its atlas as `lightMap`, decoded to linear half floats, read through
// TEXCOORD_1, at the extension's intensity (pi: three.js adds a light map to the irradiance
// and shades it with albedo / pi, and the texels hold H/pi). Needs three.js r151 or later
// (texture.channel picks the UV set).
//
//   import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
//   import { RadbakeLightmapPlugin } from './three_lightmap_plugin.js';
//   const loader = new GLTFLoader();
//   loader.register((parser) => new RadbakeLightmapPlugin(parser));
//
// Show the scene with no lights (the bake holds them), tone mapping as you like.
//
// The bake models Lambertian surfaces: shown = albedo x H/pi. three.js's standard material
// takes the light its specular layer reflects from the light map's share of the diffuse
// (4 to 10 % by the view angle for a dielectric), so lightmapped materials are made
// MeshPhysicalMaterial with specularIntensity 0 and show what the bake means. Pass
// { keepSpecular: true } to keep the glTF's specular layer instead.
import { ClampToEdgeWrapping, DataTexture, DataUtils, HalfFloatType, LinearFilter, LinearSRGBColorSpace, MeshPhysicalMaterial,
  RGBAFormat } from 'three';
import { decodeRadbakeLightmap, isRadbakeLightmap } from './radbake_lightmap_decode.js';

export class RadbakeLightmapPlugin {
  constructor(parser, { keepSpecular = false } = {}) {
    this.parser = parser;
    this.keepSpecular = keepSpecular;
    this.name = 'MOZ_lightmap';
    this.textures = new Map(); // texture index -> Promise<DataTexture>, one per atlas
  }

  lightmapOf(materialIndex) {
    return this.parser.json.materials[materialIndex].extensions?.[this.name];
  }

  getMaterialType(materialIndex) {
    return this.lightmapOf(materialIndex) && !this.keepSpecular ? MeshPhysicalMaterial : null;
  }

  async extendMaterialParams(materialIndex, params) {
    const materialDef = this.parser.json.materials[materialIndex];
    const extension = this.lightmapOf(materialIndex);
    if (!extension) return;
    if (!this.keepSpecular) params.specularIntensity = 0;
    let map;
    if (isRadbakeLightmap(materialDef)) {
      const key = extension.index;
      if (!this.textures.has(key)) this.textures.set(key, this.decodedTexture(key));
      map = await this.textures.get(key);
    } else {
      map = await this.parser.getDependency('texture', extension.index); // a plain linear light map
    }
    map.channel = extension.texCoord ?? 0; // a texture info: TEXCOORD_0 unless it says (radbake writes 1)
    params.lightMap = map;
    params.lightMapIntensity = extension.intensity ?? 1;
  }

  // A radiance atlas (--lightmap-quantity radiance) holds the albedo already: its materials
  // show it on white, without their base colour texture.
  afterRoot(gltf) {
    gltf.scene.traverse((object) => {
      const materials = Array.isArray(object.material) ? object.material : object.material ? [object.material] : [];
      for (const material of materials)
        if (material.lightMap && material.userData?.radbake_lightmap_quantity === 'radiance') {
          material.color.setRGB(1, 1, 1);
          material.map = null;
          material.needsUpdate = true;
        }
    });
  }

  async decodedTexture(textureIndex) {
    const json = this.parser.json;
    const imageDef = json.images[json.textures[textureIndex].source];
    let bytes;
    if (imageDef.bufferView !== undefined) {
      bytes = await this.parser.getDependency('bufferView', imageDef.bufferView);
    } else {
      const url = new URL(imageDef.uri, new URL(this.parser.options.path || './', globalThis.location?.href));
      bytes = await (await fetch(url)).arrayBuffer();
    }
    const image = await decodeRadbakeLightmap(bytes);
    const halves = new Uint16Array(image.data.length);
    for (let i = 0; i < halves.length; ++i) halves[i] = DataUtils.toHalfFloat(image.data[i]);
    const texture = new DataTexture(halves, image.width, image.height, RGBAFormat, HalfFloatType);
    texture.flipY = false; // glTF's UVs: v down from the image's top row
    texture.wrapS = texture.wrapT = ClampToEdgeWrapping;
    texture.magFilter = texture.minFilter = LinearFilter; // no mipmaps: they would blend charts
    texture.generateMipmaps = false;
    texture.colorSpace = LinearSRGBColorSpace;
    texture.name = imageDef.name ?? 'radbake lightmap';
    texture.needsUpdate = true;
    return texture;
  }
}
