// What the engines' checks share: the EXR atlases (the truth), per-surface statistics and
// the verdict. A "surface" is one lightmapped primitive; its texels are those the engine's
// render of it in lightmap space covers.
import { FloatType } from 'three';
import { EXRLoader } from 'three/addons/loaders/EXRLoader.js';
import { readPngRgba8 } from '/examples/web/radbake_lightmap_decode.js';

export const luminance = (r, g, b) => 0.2126 * r + 0.7152 * g + 0.0722 * b;

export function median(values) {
  if (!values.length) return NaN;
  const sorted = Float64Array.from(values).sort();
  const mid = sorted.length >> 1;
  return sorted.length % 2 ? sorted[mid] : 0.5 * (sorted[mid - 1] + sorted[mid]);
}

// The atlas EXR as { width, height, at(x, y) -> [r, g, b], negative } with y = 0 the image's
// top row (EXRLoader's rows run bottom-up). Negative light (a solve's error the EXR keeps) is
// read as 0, as any display shows it and as the PNG holds it; `negative` counts such texels.
// `light` false: signed data (a direction EXR), read as it is.
export async function loadExr(url, light = true) {
  const texture = await new EXRLoader().setDataType(FloatType).loadAsync(url);
  const { width, height, data } = texture.image;
  const channels = data.length / (width * height);
  let negative = 0;
  for (let i = 0; i < width * height && light; ++i)
    if (data[i * channels] < 0 || data[i * channels + 1] < 0 || data[i * channels + 2] < 0) ++negative;
  return {
    width,
    height,
    negative,
    at(x, y) {
      const i = ((height - 1 - y) * width + x) * channels;
      if (!light) return [data[i], data[i + 1], data[i + 2]];  // not light: signed data (directions)
      return [Math.max(data[i], 0), Math.max(data[i + 1], 0), Math.max(data[i + 2], 0)];
    },
  };
}

// Compares one surface's render (and, with `exr`, the lightmap's own median there) (Float32Array RGBA, row 0 at v = 0, alpha > 0 where drawn)
// with the truth at each covered texel, truth(x, y) -> [r, g, b] or null to skip the texel.
export function surfaceFigures(pixels, width, height, truth, exr, codes) {
  const shown = [], expected = [], lightmap = [];
  let worst = 0, step = 0;
  for (let y = 0; y < height; ++y)
    for (let x = 0; x < width; ++x) {
      const i = 4 * (y * width + x);
      if (!(pixels[i + 3] > 0.5)) continue;
      const want = truth(x, y);
      if (!want) continue;
      const a = luminance(pixels[i], pixels[i + 1], pixels[i + 2]);
      const b = luminance(want[0], want[1], want[2]);
      shown.push(a);
      expected.push(b);
      if (exr) lightmap.push(luminance(...exr.at(x, y)));
      if (codes) {
        // One code's worth at this texel's exponent, against its brightest channel's value.
        const j = 4 * (y * width + x), peak = Math.max(codes[j], codes[j + 1], codes[j + 2]);
        if (codes[j + 3] && peak) step = Math.max(step, 1 / peak);
      }
      if (b > 0) worst = Math.max(worst, Math.abs(a - b) / b);
    }
  return { texels: shown.length, shown_median: median(shown), expected_median: median(expected),
           lightmap_median: median(lightmap), worst_texel: worst, largest_step: step };
}

// The truth the physics gives where a material's albedo and emission are single colours:
// shown = albedo x (the EXR's H/pi) + emission (the EXR + emission for a radiance atlas).
// Null for textured materials.
export function physicalTruth(materialDef, exr) {
  const pbr = materialDef.pbrMetallicRoughness ?? {};
  if (pbr.baseColorTexture || materialDef.emissiveTexture) return null;
  // A radiance atlas holds the albedo already.
  const albedo = materialDef.extras?.radbake_lightmap_quantity === 'radiance' ? [1, 1, 1, 1] : pbr.baseColorFactor ?? [1, 1, 1, 1];
  const strength = materialDef.extensions?.KHR_materials_emissive_strength?.emissiveStrength ?? 1;
  const emission = (materialDef.emissiveFactor ?? [0, 0, 0]).map((v) => v * strength);
  return (x, y) => {
    const [r, g, b] = exr.at(x, y);
    return [albedo[0] * r + emission[0], albedo[1] * g + emission[1], albedo[2] * b + emission[2]];
  };
}

// One surface's report, from three renders of it in lightmap space: `shown` (the loader's
// decoded PNG), `linear` (the EXR's exact texels, filtered as the PNG is) and `nearest` (the
// EXR's texels unfiltered). shown against linear is what the 8-bit encoding and its decode
// cost; nearest against albedo x H/pi + emission (where those are single colours) checks
// the engine's material applies the light map as the bake means it.
export function surfaceReport(name, materialDef, exr, shown, linear, nearest, codes) {
  const { width, height } = exr;
  const pixelsOf = (render) => (x, y) => {
    const i = 4 * (y * width + x);
    return render[i + 3] > 0.5 ? [render[i], render[i + 1], render[i + 2]] : null;
  };
  const encoding = surfaceFigures(shown, width, height, pixelsOf(linear), exr, codes);
  const truth = physicalTruth(materialDef, exr);
  const physical = truth ? surfaceFigures(nearest, width, height, truth) : null;
  return { name, atlas: materialDef.extras.radbake_lightmap, ...encoding,
           material_median: physical ? physical.shown_median : null,
           physical_median: physical ? physical.expected_median : null,
           physical_worst_texel: physical ? physical.worst_texel : null };
}

// A material's atlas: its EXR (the truth) and its PNG's bytes, each loaded once into `cache`.
export async function atlasOf(bakeUrl, materialDef, cache) {
  const file = materialDef.extras.radbake_lightmap;
  if (!cache.has(file))
    cache.set(file, { exr: await loadExr(`${bakeUrl}/${file}`),
                      codes: await loadCodes(`${bakeUrl}/${materialDef.extras.radbake_lightmap_png}`) });
  return cache.get(file);
}

// The lightmap PNG's RGBA bytes, as the loaders read them.
export async function loadCodes(url) {
  return (await readPngRgba8(await (await fetch(url)).arrayBuffer())).rgba;
}

// The JSON chunk of a glb.
export async function glbJson(url) {
  const bytes = new Uint8Array(await (await fetch(url)).arrayBuffer());
  const view = new DataView(bytes.buffer);
  const length = view.getUint32(12, true);
  return JSON.parse(new TextDecoder().decode(bytes.subarray(20, 20 + length)));
}
