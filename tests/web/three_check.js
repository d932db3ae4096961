// three.js: the baked glb through GLTFLoader and examples/web's plugin; each lightmapped
// primitive is drawn with its own material into a float target laid out as its atlas
// (the vertex shader places each vertex at its light map UV, TEXCOORD_1 as radbake writes it; the fragment shader is three.js's
// own), no lights, no tone mapping. At a texel centre the light map is read exactly at
// that texel, so the target holds what the shader shows there.
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { MeshoptDecoder } from 'three/addons/libs/meshopt_decoder.module.js';
import { RadbakeLightmapPlugin } from '/examples/web/three_lightmap_plugin.js';
import { loadCodes, loadExr, surfaceReport } from './check_common.js';

function lightmapSpace(material) {
  const copy = material.clone();
  copy.side = THREE.DoubleSide; // charts may be mirrored in the atlas
  copy.onBeforeCompile = (shader) => {
    shader.vertexShader = shader.vertexShader.replace(
      '#include <project_vertex>',
      '#include <project_vertex>\n\tgl_Position = vec4( vLightMapUv * 2.0 - 1.0, 0.0, 1.0 );');
  };
  copy.customProgramCacheKey = () => 'radbake-lightmap-space';
  return copy;
}

function drawInLightmapSpace(renderer, geometry, material, width, height) {
  const target = new THREE.WebGLRenderTarget(width, height, {
    type: THREE.FloatType, minFilter: THREE.NearestFilter, magFilter: THREE.NearestFilter, depthBuffer: false });
  const scene = new THREE.Scene();
  const mesh = new THREE.Mesh(geometry, material);
  mesh.frustumCulled = false;
  scene.add(mesh);
  renderer.setRenderTarget(target);
  renderer.setClearColor(0x000000, 0);
  renderer.clear();
  renderer.render(scene, new THREE.Camera());
  const pixels = new Float32Array(width * height * 4);
  renderer.readRenderTargetPixels(target, 0, 0, width, height, pixels);
  renderer.setRenderTarget(null);
  target.dispose();
  return pixels;
}

export async function checkThree(bakeUrl, glbName) {
  const renderer = new THREE.WebGLRenderer({ canvas: document.createElement('canvas') });
  renderer.toneMapping = THREE.NoToneMapping;
  const loader = new GLTFLoader().setMeshoptDecoder(MeshoptDecoder); // glTF Transform's optimize output
  loader.register((parser) => new RadbakeLightmapPlugin(parser));
  const gltf = await loader.loadAsync(`${bakeUrl}/${glbName}`);
  const json = gltf.parser.json;
  const exrs = new Map();
  const surfaces = [];
  const meshes = [];
  gltf.scene.traverse((object) => { if (object.isMesh) meshes.push(object); });
  for (const mesh of meshes) {
    const material = mesh.material;
    if (!material.lightMap) continue;
    const association = gltf.parser.associations.get(material);
    const materialDef = json.materials[association.materials];
    const exrFile = materialDef.extras.radbake_lightmap;
    if (!exrs.has(exrFile))
      exrs.set(exrFile, { exr: await loadExr(`${bakeUrl}/${exrFile}`),
                          codes: await loadCodes(`${bakeUrl}/${materialDef.extras.radbake_lightmap_png}`) });
    const { exr, codes } = exrs.get(exrFile);
    const { width, height } = exr;
    const shown = drawInLightmapSpace(renderer, mesh.geometry, lightmapSpace(material), width, height);
    // What the material shows with the EXR's exact texels as its light map, filtered as
    // the decoded PNG is (half floats, linear) and unfiltered.
    const halves = new Uint16Array(width * height * 4);
    for (let y = 0; y < height; ++y)
      for (let x = 0; x < width; ++x)
        halves.set([...exr.at(x, y), 1].map((v) => THREE.DataUtils.toHalfFloat(v)), 4 * (y * width + x));
    const exact = new THREE.DataTexture(halves, width, height, THREE.RGBAFormat, THREE.HalfFloatType);
    exact.channel = material.lightMap.channel;
    const renderExact = (filter) => {
      exact.minFilter = exact.magFilter = filter;
      exact.needsUpdate = true;
      const withExact = lightmapSpace(material);
      withExact.lightMap = exact;
      return drawInLightmapSpace(renderer, mesh.geometry, withExact, width, height);
    };
    const linear = renderExact(THREE.LinearFilter), nearest = renderExact(THREE.NearestFilter);
    exact.dispose();
    surfaces.push(surfaceReport(mesh.name || material.name, materialDef, exr, shown, linear, nearest, codes));
  }
  renderer.dispose();
  return { engine: 'three.js', version: THREE.REVISION, surfaces };
}
