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
  RGBAFormat, ShaderChunk } from 'three';
import { EXRLoader } from 'three/addons/loaders/EXRLoader.js';
import { decodeRadbakeLightmap, isRadbakeLightmap } from './radbake_lightmap_decode.js';

// Each material's direction texture, for code that copies materials (a clone loses the shading).
export const radbakeDirectionsOf = new WeakMap();

// Shades the light map's irradiance by the normal map: g is in world space, the normals in view space.
export function shadeWithDirections(material, directions) {
  const previous = material.onBeforeCompile;
  material.onBeforeCompile = (shader, renderer) => {
    previous?.call(material, shader, renderer);
    shader.uniforms.radbakeDirections = { value: directions };
    shader.fragmentShader = shader.fragmentShader
      .replace('#include <lightmap_pars_fragment>', '#include <lightmap_pars_fragment>\nuniform sampler2D radbakeDirections;')
      .replace('#include <lights_fragment_maps>', ShaderChunk.lights_fragment_maps.replace(
        'vec3 lightMapIrradiance = lightMapTexel.rgb * lightMapIntensity;',
        'vec3 lightMapIrradiance = lightMapTexel.rgb * lightMapIntensity;\n' +
        '\tvec3 radbakeG = ( viewMatrix * vec4( texture2D( radbakeDirections, vLightMapUv ).xyz, 0.0 ) ).xyz;\n' +
        '\tlightMapIrradiance *= max( 0.0, 1.0 + dot( radbakeG, normal - nonPerturbedNormal ) );'));
  };
  const key = material.customProgramCacheKey.bind(material);
  material.customProgramCacheKey = () => key() + '|radbake-directions';
  material.needsUpdate = true;
}

export class RadbakeLightmapPlugin {
  constructor(parser, { keepSpecular = false, directional = true } = {}) {
    this.parser = parser;
    this.keepSpecular = keepSpecular;
    this.directional = directional;
    this.directions = new Map(); // EXR file -> Promise<DataTexture>
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
  // A directional atlas shades the normal map (shadeWithDirections).
  async afterRoot(gltf) {
    const pending = [];
    gltf.scene.traverse((object) => {
      const materials = Array.isArray(object.material) ? object.material : object.material ? [object.material] : [];
      for (const material of materials) {
        if (!material.lightMap) continue;
        if (material.userData?.radbake_lightmap_quantity === 'radiance') {
          material.color.setRGB(1, 1, 1);
          material.map = null;
          material.needsUpdate = true;
        }
        const file = material.userData?.radbake_lightmap_direction;
        if (this.directional && file && !radbakeDirectionsOf.has(material)) {
          radbakeDirectionsOf.set(material, null);  // a material on several meshes: once
          if (!this.directions.has(file)) this.directions.set(file, this.directionTexture(file));
          pending.push(this.directions.get(file).then((texture) => {
            texture.channel = material.lightMap.channel;
            radbakeDirectionsOf.set(material, texture);
            shadeWithDirections(material, texture);
          }));
        }
      }
    });
    await Promise.all(pending);
  }

  // The direction EXR as half floats, row 0 at the top as glTF's UVs read it (EXRLoader's rows run bottom-up).
  async directionTexture(file) {
    const url = new URL(file, new URL(this.parser.options.path || './', globalThis.location?.href)).href;
    const exr = await new EXRLoader().setDataType(HalfFloatType).loadAsync(url);
    const { width, height, data } = exr.image;
    const row = data.length / height;
    const flipped = new Uint16Array(data.length);
    for (let y = 0; y < height; ++y) flipped.set(data.subarray((height - 1 - y) * row, (height - y) * row), y * row);
    const texture = new DataTexture(flipped, width, height, exr.format, HalfFloatType);
    texture.flipY = false;
    texture.wrapS = texture.wrapT = ClampToEdgeWrapping;
    texture.magFilter = texture.minFilter = LinearFilter;
    texture.generateMipmaps = false;
    texture.colorSpace = LinearSRGBColorSpace;
    texture.needsUpdate = true;
    exr.dispose();
    return texture;
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
