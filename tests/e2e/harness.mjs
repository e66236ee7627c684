// What the browser tests share: options, the skip/fail protocol ctest reads (exit 77 = skipped),
// the prerequisites (Chromium, playwright-core, a caliper binary, a body model, the built page),
// a `caliper serve` on a free port with a scratch data folder, and headless Chromium launched
// the way TOOLBOX.md says works on these machines.
import { spawn, spawnSync } from 'node:child_process';
import { existsSync, readdirSync } from 'node:fs';
import { dirname, join, resolve } from 'node:path';
import { createRequire } from 'node:module';
import { fileURLToPath } from 'node:url';

export const root = resolve(dirname(fileURLToPath(import.meta.url)), '..', '..');
export const webRequire = createRequire(join(root, 'web', 'package.json'));
export const chromiumPath = process.env.CALIPER_CHROMIUM ?? '/usr/bin/chromium';

const args = process.argv.slice(2);
export const hasFlag = (name) => args.includes(name);
export function option(name, fallback) {
  const i = args.indexOf(name);
  return i >= 0 && i + 1 < args.length ? args[i + 1] : fallback;
}
export const caliper = resolve(option('--caliper', join(root, 'build', 'bin', 'caliper')));
export const screenshots = option('--screenshots', null);

// A missing tool skips the test (77), or fails it when CALIPER_REQUIRE_TOOLS=1 (the release suite).
export function skip(why) {
  if (process.env.CALIPER_REQUIRE_TOOLS === '1') {
    console.log(`FAIL: ${why} (CALIPER_REQUIRE_TOOLS=1)`);
    process.exit(1);
  }
  console.log(`SKIP: ${why}`);
  process.exit(77);
}

// playwright-core's chromium, or a skip when web/node_modules lacks it.
export function loadChromium() {
  try {
    return webRequire('playwright-core').chromium;
  } catch {
    return skip('playwright-core is not installed in web/ (run scripts/install-deps.sh)');
  }
}

// Checks the browser, the binary and a body model, and builds the current web/src into
// web/dist (the pages under test). Returns the models folder the server should use.
export function prepare() {
  if (!existsSync(chromiumPath)) skip(`no Chromium at ${chromiumPath}`);
  if (!existsSync(caliper)) {
    console.error(`FAIL: no caliper binary at ${caliper}`);
    process.exit(1);
  }
  const modelsDir = process.env.CALIPER_MODELS_DIR ?? join(root, 'models');
  if (!existsSync(modelsDir) || !readdirSync(modelsDir).some((f) => /^mannequin-.*\.npz$/.test(f)))
    skip(`no mannequin model in ${modelsDir} (commit models/ or set CALIPER_MODELS_DIR)`);
  const build = spawnSync(process.execPath, [join(root, 'web', 'build.mjs')], { encoding: 'utf8' });
  if (build.status !== 0) {
    console.error(`FAIL: web/build.mjs: ${build.stderr}`);
    process.exit(1);
  }
  return modelsDir;
}

let failures = 0;
// Prints ok/FAIL for one check and counts failures; returns ok so a test can stop on it.
export function check(ok, what, detail = '') {
  if (ok) console.log(`ok   ${what}${detail ? ` (${detail})` : ''}`);
  else {
    failures += 1;
    console.log(`FAIL ${what}${detail ? `: ${detail}` : ''}`);
  }
  return ok;
}
export function fail(message) {
  failures += 1;
  console.log(`FAIL ${message}`);
}
export function finish() {
  console.log(failures ? `${failures} check(s) failed` : 'all checks passed');
  process.exit(failures ? 1 : 0);
}

// The desktop tool's page: waits until it has finished at least `n` updates (window.caliper.updates)
// and no further one follows within `pauseMs`.
export async function settle(page, n, pauseMs = 300) {
  await page.waitForFunction((k) => (window.caliper?.updates ?? 0) >= k, n, { timeout: 60000 });
  let last = -1;
  for (let i = 0; i < 50; ++i) {
    const u = await page.evaluate(() => window.caliper?.updates ?? 0);
    if (u === last) break;
    last = u;
    await page.waitForTimeout(pauseMs);
  }
}

// `caliper serve` on a free port; capture sessions go to `dataDir`, never the user's own folder.
// The server on `port` (0: any free one); resolves to {child, base} once it listens.
export function startServer(modelsDir, dataDir, port = 0) {
  return new Promise((resolvePromise, reject) => {
    const child = spawn(caliper, ['serve', '--port', String(port), '--web-root', join(root, 'web', 'dist'), '--quiet', '--data', dataDir],
      { env: { ...process.env, CALIPER_MODELS_DIR: modelsDir }, stdio: ['ignore', 'pipe', 'pipe'] });
    let out = '', err = '';
    const timer = setTimeout(() => reject(new Error(`server did not start: ${out}${err}`)), 120000);
    child.stdout.on('data', (d) => {
      out += d;
      const m = /https?:\/\/([\d.]+):(\d+)\//.exec(out);
      if (m) {
        clearTimeout(timer);
        resolvePromise({ child, base: `http://${m[1]}:${m[2]}` });
      }
    });
    child.stderr.on('data', (d) => { err += d; });
    child.on('exit', (code) => { clearTimeout(timer); reject(new Error(`server exited (${code}): ${err}`)); });
  });
}

// Headless Chromium with software WebGL (SwiftShader) and no background network traffic.
export function launchBrowser(chromium, extraArgs = []) {
  return chromium.launch({
    executablePath: chromiumPath,
    headless: true,
    args: ['--no-sandbox', '--disable-quic', '--no-first-run', '--disable-background-networking',
           '--disable-component-update', '--disable-sync', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
           ...extraArgs],
  });
}

// Page-side source (inside an iwer init script that has `device`, an IWER.XRDevice for the Quest 3):
// window.__placeTip(hand, target, q, offset) puts a controller so that the point `offset` of its
// grip space (a handle's tip, a wrist) is at `target`, the target ray turned by quaternion q.
// iwer poses the target-ray space; grip = target ray · gripOffsetMatrix (column-major).
export const placeTipSource = `
      const config = IWER.metaQuest3.controllerConfig;
      window.__placeTip = (hand, target, q, offset) => {
        const G = config.layout[hand].gripOffsetMatrix;
        const v = [0, 1, 2].map((r) => G[12 + r] + G[r] * offset[0] + G[4 + r] * offset[1] + G[8 + r] * offset[2]);
        const [x, y, z, w] = q;
        const t = [2 * (y * v[2] - z * v[1]), 2 * (z * v[0] - x * v[2]), 2 * (x * v[1] - y * v[0])];
        const rv = [v[0] + w * t[0] + (y * t[2] - z * t[1]), v[1] + w * t[1] + (z * t[0] - x * t[2]), v[2] + w * t[2] + (x * t[1] - y * t[0])];
        const c = device.controllers[hand];
        c.position.set(target[0] - rv[0], target[1] - rv[1], target[2] - rv[2]);
        c.quaternion.set(x, y, z, w);
      };`;
