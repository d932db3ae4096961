// Babylon.js: the baked glb through Babylon's glTF loader and examples/web's extension; each
// lightmapped primitive drawn with its own material (a material plugin places each vertex at
// its TEXCOORD_1) into a float target laid out as its atlas, image processing off.
import { Engine } from '@babylonjs/core/Engines/engine.js';
import { Constants } from '@babylonjs/core/Engines/constants.js';
import { Scene } from '@babylonjs/core/scene.js';
import { FreeCamera } from '@babylonjs/core/Cameras/freeCamera.js';
import { Vector3 } from '@babylonjs/core/Maths/math.vector.js';
import { Color4 } from '@babylonjs/core/Maths/math.color.js';
import { RawTexture } from '@babylonjs/core/Materials/Textures/rawTexture.js';
import { Texture } from '@babylonjs/core/Materials/Textures/texture.js';
import { ToHalfFloat } from '@babylonjs/core/Misc/halfFloat.js';
import { RenderTargetTexture } from '@babylonjs/core/Materials/Textures/renderTargetTexture.js';
import { MaterialPluginBase } from '@babylonjs/core/Materials/materialPluginBase.js';
import { LoadAssetContainerAsync } from '@babylonjs/core/Loading/sceneLoader.js';
import { registerBuiltInLoaders } from '@babylonjs/loaders/dynamic.js';
import { registerRadbakeLightmaps } from '/examples/web/babylon_lightmap_extension.js';
import { atlasOf, surfaceReport } from './check_common.js';

class LightmapSpace extends MaterialPluginBase {
  constructor(material) {
    super(material, 'LightmapSpace', 300, { RADBAKE_LIGHTMAP_SPACE: false });
    this._uv = material.lightmapTexture.coordinatesIndex === 1 ? 'uv2' : 'uv';
    this._enable(true);
  }
  prepareDefines(defines) { defines.RADBAKE_LIGHTMAP_SPACE = true; }
  getClassName() { return 'LightmapSpace'; }
  getCustomCode(shaderType) {
    return shaderType === 'vertex' ? { CUSTOM_VERTEX_MAIN_END: `gl_Position = vec4(${this._uv} * 2.0 - 1.0, 0.0, 1.0);` } : null;
  }
}

function lightmapSpace(material, name) {
  const copy = material.clone(name);
  new LightmapSpace(copy);
  copy.backFaceCulling = false; // charts may be mirrored in the atlas
  return copy;
}

async function drawInLightmapSpace(scene, mesh, material, width, height) {
  const target = new RenderTargetTexture('lightmap space', { width, height }, scene,
    { generateMipMaps: false, type: Constants.TEXTURETYPE_FLOAT, samplingMode: Texture.NEAREST_SAMPLINGMODE,
      generateDepthBuffer: false });
  target.clearColor = new Color4(0, 0, 0, 0);
  target.renderList = [mesh];
  target.setMaterialForRendering(mesh, material);
  target.activeCamera = scene.activeCamera;
  mesh.alwaysSelectAsActiveMesh = true;
  target.render();
  const pixels = new Float32Array((await target.readPixels()).buffer.slice(0));
  target.dispose();
  return pixels;
}

function materialIndexOf(material) {
  const pointer = material._internalMetadata?.gltf?.pointers?.find((p) => p.startsWith('/materials/'));
  return pointer === undefined ? -1 : Number(pointer.split('/')[2]);
}

export async function checkBabylon(bakeUrl, glbName, json) {
  registerBuiltInLoaders();
  registerRadbakeLightmaps();
  const canvas = document.createElement('canvas');
  const engine = new Engine(canvas, false, { preserveDrawingBuffer: true });
  const scene = new Scene(engine);
  // Image processing left to a post process that the lightmap-space targets never run: the
  // materials write linear light, no tone mapping, no gamma.
  scene.imageProcessingConfiguration.applyByPostProcess = true;
  scene.imageProcessingConfiguration.skipFinalColorClamp = true;
  scene.activeCamera = new FreeCamera('camera', new Vector3(0, 0, -1), scene);
  const container = await LoadAssetContainerAsync(`${bakeUrl}/${glbName}`, scene);
  container.addAllToScene();
  await scene.whenReadyAsync();
  const exrs = new Map();
  const surfaces = [];
  for (const mesh of scene.meshes) {
    const material = mesh.material;
    if (!material || !material.lightmapTexture || !mesh.getTotalVertices()) continue;
    const materialDef = json.materials[materialIndexOf(material)];
    const { exr, codes } = await atlasOf(bakeUrl, materialDef, exrs);
    const { width, height } = exr;
    const drawn = lightmapSpace(material, `${material.name} (lightmap space)`);
    const shown = await drawInLightmapSpace(scene, mesh, drawn, width, height);
    // The same material with the EXR's exact texels as its light map, filtered as the
    // decoded PNG is (half floats, bilinear) and unfiltered.
    const halves = new Uint16Array(width * height * 4);
    for (let y = 0; y < height; ++y)
      for (let x = 0; x < width; ++x) halves.set([...exr.at(x, y), 1].map(ToHalfFloat), 4 * (y * width + x));
    const renderExact = async (sampling) => {
      const exact = RawTexture.CreateRGBATexture(halves, width, height, scene, false, false, sampling,
        Constants.TEXTURETYPE_HALF_FLOAT);
      exact.coordinatesIndex = material.lightmapTexture.coordinatesIndex;
      exact.gammaSpace = false;
      exact.wrapU = exact.wrapV = Texture.CLAMP_ADDRESSMODE;
      const withExact = lightmapSpace(material, `${material.name} (exact lightmap)`);
      withExact.lightmapTexture = exact;
      const pixels = await drawInLightmapSpace(scene, mesh, withExact, width, height);
      exact.dispose();
      return pixels;
    };
    const linear = await renderExact(Texture.BILINEAR_SAMPLINGMODE);
    const nearest = await renderExact(Texture.NEAREST_SAMPLINGMODE);
    surfaces.push(surfaceReport(mesh.name, materialDef, exr, shown, linear, nearest, codes));
  }
  engine.dispose();
  return { engine: 'Babylon.js', version: Engine.Version, surfaces };
}
