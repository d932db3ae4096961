// Bakes a scene (or takes a bake folder), shows its glb in three.js and Babylon.js in headless
// Chromium through examples/web's loaders, and checks that lit surfaces show the light the
// EXR holds (issue 33): each surface's median luminance within --tolerance of the same
// material with the EXR's exact texels as its light map, and, where the albedo is one colour,
// of albedo x H/pi + emission; and no decoded step between neighbouring codes above 2 % of the
// texel's value.
// Surfaces whose lightmap (median H/pi) is darker than --min-brightness of the brightest
// surface's are reported, not judged.
//
//   node tests/web/lightmap_check.mjs --radbake build/src/radbake --scene scenes/cornell_box.wrl
//   node tests/web/lightmap_check.mjs --bake OUT_DIR [--engines three,babylon] [--json OUT.json]
//
// Exit 0 when every judged surface passes, 1 when one does not, 2 when it cannot run.
import { spawnSync } from 'node:child_process';
import { createServer } from 'node:http';
import { existsSync, mkdtempSync, readFileSync, readdirSync, rmSync, statSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, extname, join, normalize, resolve, sep } from 'node:path';
import { fileURLToPath } from 'node:url';

const here = dirname(fileURLToPath(import.meta.url));
const root = resolve(here, '..', '..');

function parseArgs(argv) {
  const args = { engines: 'three,babylon', tolerance: 0.03, 'min-brightness': 0.01, step: 0.02,
                 chromium: process.env.CHROMIUM ?? '/usr/bin/chromium', quality: 'draft' };
  for (let i = 0; i < argv.length; ++i) {
    const key = argv[i].replace(/^--/, '');
    if (!argv[i].startsWith('--') || i + 1 >= argv.length) throw new Error(`unexpected argument ${argv[i]}`);
    args[key] = argv[++i];
  }
  return args;
}

function bakeScene(args) {
  const out = mkdtempSync(join(tmpdir(), 'radbake-web-'));
  const run = spawnSync(args.radbake, ['bake', args.scene, '-o', join(out, 'bake'), '--quality', args.quality, '--quiet',
                                       ...(args['bake-args'] ? args['bake-args'].split(' ') : [])], { encoding: 'utf8' });
  if (run.status !== 0) throw new Error(`radbake bake failed (${run.status}): ${run.stderr}`);
  return { dir: join(out, 'bake'), cleanup: () => rmSync(out, { recursive: true, force: true }) };
}

const types = { '.js': 'text/javascript', '.mjs': 'text/javascript', '.html': 'text/html', '.json': 'application/json',
                '.glb': 'model/gltf-binary', '.png': 'image/png', '.exr': 'application/octet-stream' };

// Serves the page, the loaders, node_modules and the bake, nothing else.
function serve(bakeDir) {
  const mounts = [['/tests/web/', here], ['/examples/', join(root, 'examples')],
                  ['/node_modules/', join(here, 'node_modules')], ['/bake/', bakeDir]];
  const server = createServer((request, response) => {
    const path = decodeURIComponent(new URL(request.url, 'http://localhost').pathname);
    for (const [prefix, dir] of mounts) {
      if (!path.startsWith(prefix)) continue;
      const file = normalize(join(dir, path.slice(prefix.length)));
      if (!file.startsWith(dir + sep) || !existsSync(file) || !statSync(file).isFile()) break;
      response.writeHead(200, { 'Content-Type': types[extname(file)] ?? 'application/octet-stream' });
      response.end(readFileSync(file));
      return;
    }
    response.writeHead(404);
    response.end();
  });
  return new Promise((done) => server.listen(0, '127.0.0.1', () => done(server)));
}

function verdict(result, args) {
  const surfaces = result.surfaces;
  const brightest = Math.max(...surfaces.map((s) => s.lightmap_median).filter(Number.isFinite));
  let failed = 0;
  const lines = [];
  for (const s of surfaces) {
    const encoding = s.shown_median / s.expected_median - 1;
    const physical = s.physical_median ? s.material_median / s.physical_median - 1 : null;
    const judged = s.lightmap_median > args['min-brightness'] * brightest;
    const ok = !judged || (Math.abs(encoding) <= args.tolerance && (physical === null || Math.abs(physical) <= args.tolerance) &&
                           s.largest_step <= args.step);
    // A directional bake: the normal-mapped shading against albedo x lightmap x the factor.
    const directional = s.directional ? s.directional.median_ratio - 1 : null;
    const directional_ok = directional === null || Math.abs(directional) <= 0.01;
    if (!ok || !directional_ok) ++failed;
    lines.push(`  ${ok ? (judged ? 'ok  ' : 'dark') : 'FAIL'} ${s.name.padEnd(28)} texels ${String(s.texels).padStart(7)}` +
               `  shown ${s.shown_median.toPrecision(4).padStart(9)}  vs EXR ${(100 * encoding).toFixed(2).padStart(6)} %` +
               (physical === null ? '' : `  material vs albedo x H/pi ${(100 * physical).toFixed(2).padStart(6)} %`) +
               `  step ${(100 * s.largest_step).toFixed(2)} %` +
               (directional === null ? '' : `  tilted 20 deg vs factor ${(100 * directional).toFixed(2)} %${directional_ok ? '' : ' FAIL'}`));
  }
  if ((args['bake-args'] ?? '').includes('--directional') && result.engine === 'three.js' &&
      !surfaces.some((s) => s.directional)) {
    ++failed;
    lines.push('  FAIL a directional bake, but no surface was shaded with its directions');
  }
  // A tiny primitive may cover no texel centre; most must.
  const undrawn = surfaces.filter((s) => !(s.texels > 0)).length;
  if (!(surfaces.length > 0) || undrawn > 0.25 * surfaces.length) {
    ++failed;
    lines.push(`  FAIL ${undrawn} of ${surfaces.length} lightmapped surfaces cover no texel centre`);
  }
  return { failed, lines };
}

async function main() {
  const args = parseArgs(process.argv.slice(2));
  for (const key of ['tolerance', 'min-brightness', 'step']) args[key] = Number(args[key]);
  if (!existsSync(join(here, 'node_modules', 'playwright-core')))
    throw new Error(`${join(here, 'node_modules')} is missing: run tools/setup_web.sh`);
  if (!existsSync(args.chromium)) throw new Error(`no Chromium at ${args.chromium}: run tools/setup_web.sh`);
  const baked = args.bake ? { dir: resolve(args.bake), cleanup: () => {} } : bakeScene(args);
  const glb = readdirSync(baked.dir).find((f) => f.endsWith('.glb'));
  if (!glb) throw new Error(`no .glb in ${baked.dir}`);
  const { chromium } = await import('playwright-core');
  const server = await serve(baked.dir);
  const browser = await chromium.launch({ executablePath: args.chromium,
    args: ['--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist'] });
  let failed = 0;
  const results = [];
  try {
    for (const engine of args.engines.split(',')) {
      const page = await browser.newPage();
      page.on('pageerror', (error) => console.error(`${engine} page error: ${error}`));
      const url = `http://127.0.0.1:${server.address().port}/tests/web/page.html?engine=${engine}&bake=/bake&glb=${glb}`;
      await page.goto(url);
      await page.waitForFunction(() => window.radbakeResult !== undefined, null, { timeout: 300000 });
      const result = await page.evaluate(() => window.radbakeResult);
      await page.close();
      if (result.error) throw new Error(`${engine}: ${result.error}`);
      const judged = verdict(result, args);
      console.log(`${result.engine} ${result.version}: ${glb}, ${result.surfaces.length} lightmapped surfaces`);
      for (const line of judged.lines) console.log(line);
      failed += judged.failed;
      results.push(result);
    }
  } finally {
    await browser.close();
    server.close();
    baked.cleanup();
  }
  if (args.json) writeFileSync(args.json, JSON.stringify(results, null, 1));
  console.log(failed ? `lightmap check: ${failed} failures` : 'lightmap check: every judged surface within tolerance');
  process.exit(failed ? 1 : 0);
}

main().catch((error) => { console.error(`lightmap check: ${error.message ?? error}`); process.exit(2); });
