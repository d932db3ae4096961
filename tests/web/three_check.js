// three.js: the baked glb through GLTFLoader and examples/web's plugin; each lightmapped
// primitive is drawn with its own material into a float target laid out as its atlas
// (the vertex shader places each vertex at its light map UV, TEXCOORD_1 as radbake writes it; the fragment shader is three.js's
// own), no lights, no tone mapping. At a texel centre the light map is read exactly at
// that texel, so the target holds what the shader shows there.
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { MeshoptDecoder } from 'three/addons/libs/meshopt_decoder.module.js';
import { RadbakeLightmapPlugin, radbakeDirectionsOf, shadeWithDirections } from '/examples/web/three_lightmap_plugin.js';
import { atlasOf, loadExr, median, surfaceReport } from './check_common.js';

// A copy of `material` drawn in lightmap space (with its directional shading, which a clone
// loses); `normal`, when given, replaces the shading normal (world space = view space here).
function lightmapSpace(material, normal = null, surfaceNormal = null) {
  const copy = material.clone();
  copy.side = THREE.DoubleSide; // charts may be mirrored in the atlas
  copy.onBeforeCompile = (shader) => {
    shader.vertexShader = shader.vertexShader.replace(
      '#include <project_vertex>',
      '#include <project_vertex>\n\tgl_Position = vec4( vLightMapUv * 2.0 - 1.0, 0.0, 1.0 );');
  };
  copy.customProgramCacheKey = () => 'radbake-lightmap-space' + (normal ? normal.toArray().join(',') : '');
  const directions = radbakeDirectionsOf.get(material);
  if (directions) shadeWithDirections(copy, directions);
  if (normal) {
    const previous = copy.onBeforeCompile;
    copy.onBeforeCompile = (shader, renderer) => {
      previous.call(copy, shader, renderer);
      shader.fragmentShader = shader.fragmentShader.replace('#include <normal_fragment_maps>',
        // Both normals set: a chart mirrored in the atlas draws back-facing, which flips them.
        `#include <normal_fragment_maps>\n\tnormal = normalize( vec3( ${normal.x}, ${normal.y}, ${normal.z} ) );\n` +
        `\tnonPerturbedNormal = vec3( ${surfaceNormal.x}, ${surfaceNormal.y}, ${surfaceNormal.z} );`);
    };
  }
  return copy;
}

// The one normal of a flat primitive (world space), or null.
function flatNormal(geometry) {
  const normals = geometry.attributes.normal;
  if (!normals) return null;
  const first = new THREE.Vector3().fromBufferAttribute(normals, 0);
  for (let i = 1; i < normals.count; ++i)
    if (new THREE.Vector3().fromBufferAttribute(normals, i).dot(first) < 0.9999) return null;
  return first.normalize();
}

// A directional bake: a flat primitive drawn with its normal tilted 20 degrees against
// albedo x lightmap x max(0, 1 + g . (n - n0)) with g from the direction EXR, texel by texel.
function directionalFigure(renderer, mesh, material, exr, directions, width, height, materialDef) {
  const n0 = flatNormal(mesh.geometry);
  if (!n0 || !directions) return null;
  const side = new THREE.Vector3().crossVectors(n0, Math.abs(n0.y) < 0.9 ? new THREE.Vector3(0, 1, 0) : new THREE.Vector3(1, 0, 0)).normalize();
  const tilt = (20 * Math.PI) / 180;
  const n = n0.clone().multiplyScalar(Math.cos(tilt)).addScaledVector(side, Math.sin(tilt));
  const shown = drawInLightmapSpace(renderer, mesh.geometry, lightmapSpace(material, n, n0), width, height);
  const flat = drawInLightmapSpace(renderer, mesh.geometry, lightmapSpace(material), width, height);
  const ratios = [];
  const d = n.clone().sub(n0);
  for (let y = 0; y < height; ++y)
    for (let x = 0; x < width; ++x) {
      const i = 4 * (y * width + x);
      if (!(shown[i + 3] > 0.5) || !(flat[i + 1] > 0)) continue;
      const [gx, gy, gz] = directions.at(x, y);
      const factor = Math.max(0, 1 + gx * d.x + gy * d.y + gz * d.z);
      const emission = (materialDef.emissiveFactor ?? [0, 0, 0])[1] *
        (materialDef.extensions?.KHR_materials_emissive_strength?.emissiveStrength ?? 1);
      if (emission > 0) return null;
      ratios.push(shown[i + 1] / (flat[i + 1] * factor));
    }
  return ratios.length ? { texels: ratios.length, median_ratio: median(ratios) } : null;
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
    const { exr, codes } = await atlasOf(bakeUrl, materialDef, exrs);
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
    const report = surfaceReport(mesh.name || material.name, materialDef, exr, shown, linear, nearest, codes);
    const directionFile = materialDef.extras.radbake_lightmap_direction;
    if (directionFile) {
      if (!exrs.has(directionFile)) exrs.set(directionFile, { exr: await loadExr(`${bakeUrl}/${directionFile}`, false) });
      report.directional = directionalFigure(renderer, mesh, material, exr, exrs.get(directionFile).exr, width, height, materialDef);
    }
    surfaces.push(report);
  }
  renderer.dispose();
  return { engine: 'three.js', version: THREE.REVISION, surfaces };
}
