// Decodes radbake's lightmap PNG ("rgbe8": 8-bit RGBA, the three channels sharing the
// exponent in alpha) to linear RGBA floats an engine samples as it samples any light map:
// bilinear filtering then blends light, not codes. Shared by the three.js plugin and the
// Babylon.js extension.
//
//   value = 0                         for alpha = 0
//   value = channel * 2^(alpha - 136)  for alpha >= 1
//
// The values are the EXR's (H/pi, linear). The PNG is read here, not by the browser's image
// decoder: a canvas would premultiply the alpha (it is an exponent, not coverage) and might
// convert colours.

// True when a material's extras say its lightmap PNG is rgbe8.
export function isRadbakeLightmap(materialDef) {
  return materialDef.extras?.radbake_lightmap_encoding === 'rgbe8';
}

async function inflate(blob) {
  const stream = blob.stream().pipeThrough(new DecompressionStream('deflate'));
  return new Uint8Array(await new Response(stream).arrayBuffer());
}

// PNG bytes (8-bit RGBA, not interlaced, as radbake writes them) -> rows of RGBA bytes.
export async function readPngRgba8(bytes) {
  const data = new Uint8Array(bytes.buffer ?? bytes, bytes.byteOffset ?? 0, bytes.byteLength);
  const view = new DataView(data.buffer, data.byteOffset, data.byteLength);
  const signature = [137, 80, 78, 71, 13, 10, 26, 10];
  if (!signature.every((b, i) => data[i] === b)) throw new Error('radbake lightmap: not a PNG');
  let width = 0, height = 0;
  const idat = [];
  for (let at = 8; at + 8 <= data.length;) {
    const length = view.getUint32(at);
    const type = String.fromCharCode(...data.subarray(at + 4, at + 8));
    const body = data.subarray(at + 8, at + 8 + length);
    if (type === 'IHDR') {
      width = view.getUint32(at + 8);
      height = view.getUint32(at + 12);
      if (body[8] !== 8 || body[9] !== 6 || body[12] !== 0) throw new Error('radbake lightmap: not 8-bit RGBA');
    } else if (type === 'IDAT') idat.push(body);
    else if (type === 'IEND') break;
    at += 12 + length;
  }
  const raw = await inflate(new Blob(idat)); // the zlib stream, split over the IDAT chunks
  const stride = width * 4;
  if (raw.length < height * (stride + 1)) throw new Error('radbake lightmap: truncated PNG');
  const out = new Uint8Array(height * stride);
  for (let y = 0; y < height; ++y) {
    const filter = raw[y * (stride + 1)];
    const line = raw.subarray(y * (stride + 1) + 1, (y + 1) * (stride + 1));
    const row = y * stride, above = row - stride;
    for (let i = 0; i < stride; ++i) {
      const a = i >= 4 ? out[row + i - 4] : 0;
      const b = y > 0 ? out[above + i] : 0;
      const c = i >= 4 && y > 0 ? out[above + i - 4] : 0;
      let predictor = 0;
      if (filter === 1) predictor = a;
      else if (filter === 2) predictor = b;
      else if (filter === 3) predictor = (a + b) >> 1;
      else if (filter === 4) {
        const p = a + b - c, pa = Math.abs(p - a), pb = Math.abs(p - b), pc = Math.abs(p - c);
        predictor = pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
      }
      out[row + i] = (line[i] + predictor) & 0xff;
    }
  }
  return { width, height, rgba: out };
}

// PNG bytes -> { width, height, data: Float32Array RGBA (alpha 1), row 0 at the top }.
export async function decodeRadbakeLightmap(bytes) {
  const { width, height, rgba } = await readPngRgba8(bytes);
  const data = new Float32Array(width * height * 4);
  for (let i = 0; i < width * height; ++i) {
    const exponent = rgba[4 * i + 3];
    const unit = exponent ? Math.pow(2, exponent - 136) : 0;
    data[4 * i] = rgba[4 * i] * unit;
    data[4 * i + 1] = rgba[4 * i + 1] * unit;
    data[4 * i + 2] = rgba[4 * i + 2] * unit;
    data[4 * i + 3] = 1;
  }
  return { width, height, data };
}
