#!/usr/bin/env node
// End-to-end test of the WebXR capture page in headless Chromium with the iwer WebXR
// emulator (from web/node_modules; injected by this test only: the page itself never loads it).
//
// A scripted person measures themselves. Their body is a known avatar: the test builds one
// (POST /api/avatar), takes its landmark vertices (ids from `caliper model info --json`) and
// the hip section's extreme points, and drives iwer's two controllers so that the handle tips
// (grip pose + the server's tip offset for the profile) touch those points, plus noise, holding
// the trigger ~1.2 s per point, after one short press that must be rejected. It also undoes and
// redoes a point with the A and B buttons, enters sex and weight in the headset, and checks that
// the session's measurement set matches the avatar's own measurements within the noise bound.
//
//   node tests/e2e/capture.spec.mjs --caliper build/bin/caliper [--screenshots DIR] [--base URL]
//
// --screenshots DIR writes capture-vr.png (in the headset, panel visible), capture-mirror.png
// (the avatar at the end) and capture-page.png (the 2-D page). --base URL uses a running server.
// Exit: 0 pass, 1 fail, 77 skipped (no browser, no playwright-core/iwer or no body model).
import { spawnSync } from 'node:child_process';
import { readFileSync, mkdirSync, mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, join } from 'node:path';
import {
  caliper, screenshots, option, webRequire, skip, loadChromium, prepare, check, fail, finish, startServer,
  launchBrowser, placeTipSource,
} from './harness.mjs';

const givenBase = option('--base', null);
const chromium = loadChromium();
let iwerSource;
try {
  iwerSource = readFileSync(join(dirname(webRequire.resolve('iwer/package.json')), 'build', 'iwer.js'), 'utf8');
} catch {
  skip('iwer is not installed in web/ (run `npm ci` in web/)');
}
const modelsDir = prepare();
const dataDir = mkdtempSync(join(tmpdir(), 'caliper-capture-e2e-'));

// Seeded random numbers (mulberry32): the same scripted person every run.
function rng(seed) {
  let a = seed >>> 0;
  return () => {
    a = (a + 0x6d2b79f5) >>> 0;
    let t = a;
    t = Math.imul(t ^ (t >>> 15), t | 1);
    t ^= t + Math.imul(t ^ (t >>> 7), t | 61);
    return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
  };
}
const random = rng(20261121);
// A uniform point in a ball of radius r (metres).
function inBall(r) {
  for (;;) {
    const v = [random() * 2 - 1, random() * 2 - 1, random() * 2 - 1];
    if (v[0] ** 2 + v[1] ** 2 + v[2] ** 2 <= 1) return v.map((x) => x * r);
  }
}
const add = (a, b) => a.map((x, i) => x + b[i]);
const dist = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
// Quaternion [x, y, z, w] from an axis (unit) and an angle.
const axisAngle = (axis, angle) => [...axis.map((c) => c * Math.sin(angle / 2)), Math.cos(angle / 2)];

// The noise of the scripted person, and the bound it implies on every captured value:
// each touch lands within POINT_NOISE of the landmark (fixed during a hold), and each frame adds
// up to JITTER more. A height is a tip height minus the floor (the median of 5 taps, each within
// the same bounds); a distance is the distance between two tips. Either way a single value is off
// by at most 2·(POINT_NOISE + JITTER) = 7 mm, and ISAK's mean of two or median of three stays
// within that. Add 0.5 mm for the engine's rounding of cm values: tolerance 7.5 mm. Any error in
// the tip offset, the floor, the hold's median or the step order is centimetres, so it fails.
const POINT_NOISE = 0.003, JITTER = 0.0005;
const TOLERANCE_CM = 0.75;
const FLOOR_SHIFT = 0.015;    // local-floor's y = 0 is 1.5 cm below the real floor: calibration must remove it

async function json(base, path, init) {
  const res = await fetch(base + path, init);
  const text = await res.text();
  let body = null;
  try { body = JSON.parse(text); } catch { /* not JSON */ }
  return { status: res.status, body, text };
}

// The hip section: all points where triangle edges cross the plane y = h; the extremes along X.
function hipSides(positions, faces, h) {
  let min = null, max = null;
  const P = (i) => [positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]];
  for (let f = 0; f < faces.length; f += 3) {
    const tri = [P(faces[f]), P(faces[f + 1]), P(faces[f + 2])];
    for (let e = 0; e < 3; ++e) {
      const a = tri[e], b = tri[(e + 1) % 3];
      if ((a[1] - h) * (b[1] - h) > 0 || a[1] === b[1]) continue;
      const s = (h - a[1]) / (b[1] - a[1]);
      const p = [a[0] + s * (b[0] - a[0]), h, a[2] + s * (b[2] - a[2])];
      if (!min || p[0] < min[0]) min = p;
      if (!max || p[0] > max[0]) max = p;
    }
  }
  return { left: max, right: min };   // +X is the body's left
}

// ---------------------------------------------------------------------------------------------

let server = null;
let base = givenBase;
if (!base) ({ child: server, base } = await startServer(modelsDir, dataDir));
const browser = await launchBrowser(chromium, ['--autoplay-policy=no-user-gesture-required']);

try {
  // --- The server side must be there.
  const profiles = await json(base, '/api/capture/profiles');
  if (!check(profiles.status === 200 && profiles.body?.profiles, 'GET /api/capture/profiles answers', `${profiles.status} ${profiles.text.slice(0, 200)}`))
    throw new Error('the server has no capture endpoints');

  // --- The scripted person: a known avatar and its landmarks.
  const SEX = 'female';
  const requested = { stature: 166, weight: 63, span: 168, crotch_height: 76, hip_breadth: 37 };
  const avatar = await json(base, '/api/avatar', { method: 'POST', headers: { 'Content-Type': 'application/json' },
    body: JSON.stringify({ sex: SEX, measurements: requested }) });
  const topo = await json(base, `/api/topology?sex=${SEX}`);
  const info = spawnSync(caliper, ['model', 'info', 'mannequin', '--sex', SEX, '--json'],
    { encoding: 'utf8', env: { ...process.env, CALIPER_MODELS_DIR: modelsDir } });
  const landmarks = JSON.parse(info.stdout).landmarks;
  const positions = new Float32Array(Buffer.from(avatar.body.mesh.positions, 'base64').buffer.slice(0));
  const faces = new Uint32Array(Buffer.from(topo.body.faces, 'base64').buffer.slice(0));
  let minY = Infinity;
  for (let i = 1; i < positions.length; i += 3) minY = Math.min(minY, positions[i]);
  // Body coordinates → local-floor: feet on the real floor, which is FLOOR_SHIFT above y = 0.
  const world = (p) => [p[0], p[1] - minY + FLOOR_SHIFT, p[2]];
  const vertex = (name) => {
    const i = landmarks[name];
    return world([positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]]);
  };
  const hipY = positions[3 * landmarks.hip_left + 1];
  const hips = hipSides(positions, faces, hipY);
  const lm = {
    head_top: vertex('vertex'),
    fingertip_left: vertex('dactylion_left'), fingertip_right: vertex('dactylion_right'),
    crotch: vertex('crotch'),
    hip_left: world(hips.left), hip_right: world(hips.right),
    acromion_right: vertex('acromion_right'), wrist_right: vertex('stylion_right'),
  };
  // The avatar's own measurements (the model's code, rest pose) are the truth. Arm length is the
  // one exception: the model's is the acromion–radiale–stylion polyline through the elbow, while
  // controllers measure straight from acromion to wrist (paper §3.1), so the truth is the
  // straight distance between the same two landmark vertices (a few mm shorter; checked close).
  const ms = avatar.body.report.measurements;
  const straightArm = dist(lm.acromion_right, lm.wrist_right) * 100;
  const truth = {
    stature: ms.stature.achieved_cm, span: ms.span.achieved_cm, crotch_height: ms.crotch_height.achieved_cm,
    hip_breadth: ms.hip_breadth.achieved_cm, arm_length: straightArm,
  };
  // The polyline on the body itself: the report's rest-pose value (its achieved_cm is the arm as a
  // person measures it, through the model's real → virtual map; docs/cli.md "Arm length").
  const polylineArm = ms.arm_length.rest_pose_cm ?? ms.arm_length.achieved_cm;
  check(straightArm <= polylineArm + 1e-6 && polylineArm - straightArm < 1.0,
    'the straight arm is within 1 cm of the model\'s polyline arm length', `${straightArm.toFixed(2)} vs ${polylineArm.toFixed(2)} cm`);
  check(Math.abs(dist(lm.hip_left, lm.hip_right) * 100 - truth.hip_breadth) < 0.2, 'the hip points span the hip breadth',
    `${(dist(lm.hip_left, lm.hip_right) * 100).toFixed(2)} vs ${truth.hip_breadth.toFixed(2)} cm`);
  const weightKg = Math.round(ms.weight.achieved_kg * 2) / 2;   // the VR form steps by 0.5 kg

  // Where each step's tips go: [right hand, left hand]; the right trigger takes the point.
  // The hand not touching anything hangs still at the side.
  const rest = { left: add(vertex('hip_left'), [0.12, -0.05, 0.05]), right: add(vertex('hip_right'), [-0.12, -0.05, 0.05]) };
  const targets = {
    stature: { right: lm.head_top, left: rest.left },
    span: { right: lm.fingertip_right, left: lm.fingertip_left },
    crotch_height: { right: lm.crotch, left: rest.left },
    hip_breadth: { right: lm.hip_right, left: lm.hip_left },
    arm_length: { right: lm.wrist_right, left: lm.acromion_right },
  };
  const floorTaps = [[0.3, 0, 0.35], [-0.3, 0, 0.35], [0.35, 0, -0.2], [-0.35, 0, -0.25], [0, 0, 0.45]]
    .map((p) => [p[0], FLOOR_SHIFT, p[2]]);
  // Controller orientations: tilted handles, different per hand, so a tip offset applied in the
  // wrong frame shows up as centimetres.
  const quats = { right: axisAngle([0.6, 0.64, 0.48], 0.9), left: axisAngle([-0.48, 0.8, 0], -0.7) };

  // --- The browser: iwer installed before the page's scripts run; nothing from outside.
  // Software-rendered XR frames cost tens of ms each, more with more pixels, and the engine voids
  // a hold whose samples are more than 0.3 s apart; so the person measures in a small window and
  // the window grows only for the screenshots.
  const SMALL = { width: 480, height: 300 }, LARGE = { width: 960, height: 600 };
  const context = await browser.newContext({ viewport: SMALL });
  const pageErrors = [];
  const outside = [];
  const served = [];
  const watch = async (page) => {
    page.on('pageerror', (e) => pageErrors.push(String(e)));
    page.on('crash', () => pageErrors.push(`the page ${page.url()} crashed`));
    page.on('console', (m) => {
      if (m.type() === 'error' && !/Failed to load resource: the server responded with a status of 4\d\d/.test(m.text()))
        pageErrors.push(m.text());
    });
    await page.route('**/*', (route) => {
      const url = route.request().url();
      if (url.startsWith(base)) { served.push(url); return route.continue(); }
      if (url.startsWith('data:') || url.startsWith('blob:')) return route.continue();
      outside.push(url);
      return route.abort();
    });
  };
  const page = await context.newPage();
  await watch(page);
  await page.addInitScript(`${iwerSource}
    ;(() => {
      const device = new IWER.XRDevice(IWER.metaQuest3, { stereoEnabled: false });
      device.installRuntime({ forceInstall: true });
      device.position.set(0, 1.62, 0.45);
      device.quaternion.set(...${JSON.stringify(axisAngle([1, 0, 0], -0.3))});
      window.__xr = device;
      ${placeTipSource}
      const frame = () => new Promise((r) => requestAnimationFrame(() => r()));
      // Resolves after the page has handled one more XR frame.
      const xrFrame = async () => { const n = window.capture.xrFrames ?? 0; while ((window.capture.xrFrames ?? 0) <= n) await frame(); };
      const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
      // Holds both tips still (plus per-frame jitter) and the trigger of 'hand' for 'seconds'.
      window.__hold = async ({ hand, tips, quats, offset, seconds, jitter, seed }) => {
        let a = seed >>> 0;
        const rnd = () => { a = (a * 1664525 + 1013904223) >>> 0; return a / 4294967296; };
        const jit = () => { for (;;) { const v = [rnd() * 2 - 1, rnd() * 2 - 1, rnd() * 2 - 1];
          if (v[0] ** 2 + v[1] ** 2 + v[2] ** 2 <= 1) return v.map((x) => x * jitter); } };
        const place = () => { for (const h of ['left', 'right']) {
          const j = jit(); window.__placeTip(h, tips[h].map((x, i) => x + j[i]), quats[h], offset); } };
        place();
        for (let i = 0; i < 2; ++i) { await xrFrame(); place(); }
        // The hold is timed in XR frame time, the clock of the samples the engine sees, from the
        // first frame that reports the trigger down, so a slow machine (few frames per second)
        // still gives the engine a hold of 'seconds' (a long one) or at most 'seconds' + a frame.
        device.controllers[hand].updateButtonValue('trigger', 1);
        await xrFrame(); place();
        const t0 = window.capture.xrTime;
        while (window.capture.xrTime - t0 < seconds * 1000) { await xrFrame(); place(); }
        device.controllers[hand].updateButtonValue('trigger', 0);
        for (let i = 0; i < 2; ++i) { await xrFrame(); place(); }
        await sleep(50);
      };
      window.__press = async (hand, button) => {
        device.controllers[hand].updateButtonValue(button, 1);
        for (let i = 0; i < 2; ++i) await xrFrame();
        device.controllers[hand].updateButtonValue(button, 0);
        for (let i = 0; i < 2; ++i) await xrFrame();
      };
      // Pushes a thumbstick for one XR frame (one step of the VR entry form), then lets go.
      window.__stick = async (hand, x, y) => {
        device.controllers[hand].updateAxes('thumbstick', x, y);
        await xrFrame();
        device.controllers[hand].updateAxes('thumbstick', 0, 0);
        for (let i = 0; i < 2; ++i) await xrFrame();
        await sleep(200);   // the form repeats a held stick every 180 ms
      };
    })();`);

  await page.goto(`${base}/capture.html`);
  await page.waitForFunction(() => window.capture?.ready === true, null, { timeout: 30000 });
  check(await page.title() === 'Caliper — capture', 'the capture page loads');
  check(await page.locator('#enter-vr').isDisabled(), 'Enter VR waits for a session');
  const profile = await page.evaluate(() => window.capture.defaultProfile);
  const tipOffset = profiles.body.profiles['meta-quest-touch-plus']?.tip_offset_m ?? profiles.body.profiles[profile].tip_offset_m;

  // --- Create a session on the page (self, core steps; sex and weight later, in the headset).
  await page.click('#create');
  await page.waitForFunction(() => window.capture.session?.id, null, { timeout: 10000 });
  const sessionId = await page.evaluate(() => window.capture.session.id);
  const code = (await page.locator('#pairing-code').innerText()).trim();
  check(/^\d{6}$/.test(code), 'the page shows a six-digit pairing code', code);
  check(await page.evaluate(() => window.capture.session.state) === 'floor', 'a new session starts with the floor');
  check(await page.locator('#result-links').isHidden(), 'no result buttons before anything is measured');
  // The weight fields take what the server takes (the catalogue's accepted range).
  const catalogue = await json(base, '/api/measurements');
  const weightRange = catalogue.body.measurements.find((m) => m.name === 'weight').accepted_range;
  const mins = await page.evaluate(() => ['new-weight', 'weight'].map((id) => [document.getElementById(id).min, document.getElementById(id).max]));
  check(mins.every(([lo, hi]) => Number(lo) === weightRange.min && Number(hi) === weightRange.max), 'the weight fields accept the server\'s range',
    `${JSON.stringify(mins)} vs ${weightRange.min}–${weightRange.max}`);
  // The headset address as a QR code: decoded, it is this page with the session.
  const qrPixels = await page.evaluate(() => {
    const c = document.getElementById('headset-qr');
    return { w: c.width, h: c.height, data: Array.from(c.getContext('2d').getImageData(0, 0, c.width, c.height).data) };
  });
  const decoded = webRequire('jsqr')(Uint8ClampedArray.from(qrPixels.data), qrPixels.w, qrPixels.h);
  check(decoded?.data === `${base}/capture.html?session=${sessionId}`, 'the QR code holds the headset address with the session', decoded?.data);

  // Writes need the code (the page sends it; a stranger without it is refused).
  const stranger = await json(base, `/api/sessions/${sessionId}/undo`, { method: 'POST', headers: { 'X-Caliper-Pairing': code === '000000' ? '111111' : '000000' } });
  check(stranger.status === 403 && stranger.body?.error?.field === 'pairing_code', 'a wrong pairing code is refused (403)', `${stranger.status}`);

  // Joining from a second device (its own browser context, like another machine, so the first
  // page stays a visible foreground page: hidden pages get no animation frames, hence no XR
  // frames): wrong code refused, right code accepted.
  const otherContext = await browser.newContext({ viewport: { width: 1440, height: 1000 } });
  const other = await otherContext.newPage();
  await watch(other);
  await other.goto(`${base}/capture.html`);
  await other.waitForFunction(() => window.capture?.ready === true, null, { timeout: 30000 });
  await other.click('#refresh');
  await other.waitForFunction((id) => [...document.querySelectorAll('#join-session option')].some((o) => o.value === id), sessionId, { timeout: 10000 });
  await other.selectOption('#join-session', sessionId);
  await other.fill('#join-code', code === '000000' ? '111111' : '000000');
  await other.click('#join');
  await other.locator('#error').waitFor({ state: 'visible', timeout: 10000 });
  check(!(await other.evaluate(() => !!window.capture.session)), 'joining with a wrong code fails', await other.locator('#error').innerText());
  await other.fill('#join-code', code);
  await other.click('#join');
  await other.waitForFunction((id) => window.capture.session?.id === id, sessionId, { timeout: 10000 });
  check(true, 'joining with the right code works');

  // --- Enter VR with a real click.
  await page.bringToFront();
  check(await page.locator('#enter-vr').isEnabled(), 'Enter VR is offered (WebXR immersive-vr supported)');
  await page.click('#enter-vr');
  await page.waitForFunction(() => window.capture.inXR === true, null, { timeout: 15000 });
  check(true, 'the page enters immersive VR (local-floor)');

  // A screenshot in the large window, after a few XR frames have been drawn at that size.
  // iwer sizes its canvas to the window once, when the session starts; follow the window here.
  async function resize(size) {
    await page.setViewportSize(size);
    await page.evaluate(({ width, height }) => {
      const c = document.querySelector('[data-webxr_runtime] canvas');
      if (c) { c.width = width; c.height = height; }
    }, size);
    const n = await page.evaluate(() => window.capture.xrFrames);
    await page.waitForFunction((k) => window.capture.xrFrames > k + 2, n, { timeout: 15000 });
  }
  async function bigShot(path) {
    await resize(LARGE);
    await page.screenshot({ path });
    await resize(SMALL);
  }
  const session = () => page.evaluate(() => window.capture.session);
  const eventCount = () => page.evaluate(() => window.capture.events.length);
  async function hold(hand, tips, seconds) {
    const n = await eventCount();
    await page.evaluate((a) => window.__hold(a), {
      hand, tips, quats, offset: tipOffset, seconds, jitter: JITTER, seed: Math.floor(random() * 2 ** 31),
    });
    // The engine answers within a batch or two.
    await page.waitForFunction((k) => window.capture.events.slice(k).some((e) => e.type === 'point_accepted' || e.type === 'point_rejected'),
      n, { timeout: 30000 }).catch(() => {});
    return page.evaluate((k) => window.capture.events.slice(k), n);
  }

  let shortPressDone = false, undoDone = false, vrShot = false;
  let misses = 0;   // holds in a row that were not accepted: three mean something is wrong
  // A hold the engine voids because the emulated tracking paused (XR frames more than 0.3 s apart:
  // software rendering on a busy machine) is done again, as the engine asks a person to; that is
  // the machine, not the page. Counted and reported; too many of them fail the test.
  let retries = 0;
  const MAX_RETRIES = 60;
  const trackingGap = (evs) => evs.some((e) => e.type === 'point_rejected' && /tracking stopped/.test(e.reason ?? ''))
    && !evs.some((e) => e.type === 'point_accepted');
  for (let guard = 0; guard < 40 + MAX_RETRIES && misses < 3 && retries <= MAX_RETRIES; ++guard) {
    const s = await session();
    if (s.state !== 'floor' && s.state !== 'measuring') break;
    const step = s.step;
    if (step.kind === 'floor') {
      const tap = add(floorTaps[step.points_done % 5], inBall(POINT_NOISE));
      const evs = await hold('right', { right: tap, left: rest.left }, 1.2);
      if (trackingGap(evs)) { retries += 1; continue; }
      if (!evs.some((e) => e.type === 'point_accepted')) {
        misses += 1;
        check(false, `floor tap ${step.points_done + 1} accepted`, JSON.stringify(evs));
      } else misses = 0;
      continue;
    }
    const t = targets[step.name];
    if (!t) { check(false, `a target for step ${step.name}`); break; }
    if (step.name === 'stature' && !shortPressDone) {
      shortPressDone = true;
      const evs = await hold('right', { right: t.right, left: t.left }, 0.4);
      if (trackingGap(evs)) { retries += 1; shortPressDone = false; continue; }
      const rej = evs.find((e) => e.type === 'point_rejected');
      check(!!rej && !evs.some((e) => e.type === 'point_accepted'), 'a 0.4 s press is rejected', JSON.stringify(evs));
      await page.waitForTimeout(200);
      const panelText = (await page.evaluate(() => window.capture.panelText)).join(' ');   // wrapped lines rejoined
      check(!!rej && panelText.includes(rej.reason), 'the panel shows the rejection reason', panelText.slice(0, 240));
      if (screenshots) {
        mkdirSync(screenshots, { recursive: true });
        await bigShot(join(screenshots, 'capture-vr-rejected.png'));
      }
      continue;
    }
    const tips = { right: add(t.right, inBall(POINT_NOISE)), left: step.kind === 'distance' ? add(t.left, inBall(POINT_NOISE)) : t.left };
    if (screenshots && !vrShot && step.name === 'hip_breadth') {
      // In the headset mid-hold: the panel, both controllers at the hips, the trigger held.
      vrShot = true;
      await resize(LARGE);
      const shot = page.evaluate((a) => window.__hold(a), { hand: 'right', tips, quats, offset: tipOffset, seconds: 0.6, jitter: JITTER, seed: 7 });
      await page.waitForFunction(() => window.__xr.controllers.right.getButtonValue('trigger') > 0, null, { timeout: 10000 });
      await page.waitForFunction((n) => window.capture.xrFrames > n + 1, await page.evaluate(() => window.capture.xrFrames), { timeout: 10000 });
      await page.screenshot({ path: join(screenshots, 'capture-vr.png') });
      await shot;   // a 0.6 s press: rejected, and the real hold follows
      await resize(SMALL);
      await page.waitForTimeout(300);
    }
    const evs = await hold('right', tips, 1.25);
    if (trackingGap(evs)) { retries += 1; continue; }
    const acc = evs.find((e) => e.type === 'point_accepted');
    check(!!acc, `${step.name} repetition ${step.repetition} accepted`, acc ? `${acc.value_cm?.toFixed(2)} cm` : JSON.stringify(evs));
    misses = acc ? 0 : misses + 1;
    if (acc && step.name === 'stature' && !undoDone) {
      // Undo with A, redo with B: the repetition goes and comes back.
      undoDone = true;
      const reps = async () => (await session()).values?.stature?.repetitions_cm?.length ?? 0;
      await page.evaluate(() => window.__press('right', 'a-button'));
      await page.waitForFunction(() => (window.capture.session.values?.stature?.repetitions_cm?.length ?? 0) === 0, null, { timeout: 5000 }).catch(() => {});
      check(await reps() === 0, 'A (undo) takes the point back');
      await page.evaluate(() => window.__press('right', 'b-button'));
      await page.waitForFunction(() => (window.capture.session.values?.stature?.repetitions_cm?.length ?? 0) === 1, null, { timeout: 5000 }).catch(() => {});
      check(await reps() === 1, 'B (redo) puts it back');
    }
  }

  const fps = await page.evaluate(() => window.capture.xrFrames / ((window.capture.xrTime - window.capture.xrStart) / 1000));
  console.log(`info XR frames in the emulator: ${fps.toFixed(1)} per second; ${retries} hold(s) redone after a tracking pause`);
  check(retries <= MAX_RETRIES, `at most ${MAX_RETRIES} holds redone because the emulator paused`, String(retries));
  let s = await session();
  check(s.state === 'entries', 'after the last step the session asks for sex and weight', s.state);

  // --- Sex and weight in the headset: left stick right picks a sex, up/down moves the weight.
  await page.evaluate(() => window.__stick('left', 1, 0));
  if ((await page.evaluate(() => window.capture.entryDraft.sex)) !== SEX) await page.evaluate(() => window.__stick('left', 1, 0));
  for (let i = 0; i < 200; ++i) {
    const w = await page.evaluate(() => window.capture.entryDraft.weight ?? 70);
    const draft = await page.evaluate(() => window.capture.entryDraft.weight);
    if (draft !== null && Math.abs(draft - weightKg) < 0.01) break;
    await page.evaluate((up) => window.__stick('right', 0, up ? -1 : 1), weightKg > w || draft === null);
  }
  const draft = await page.evaluate(() => window.capture.entryDraft);
  check(draft.sex === SEX && Math.abs(draft.weight - weightKg) < 0.01, 'the thumbsticks set sex and weight in VR', JSON.stringify(draft));
  await page.evaluate((a) => window.__hold(a), { hand: 'right', tips: rest, quats, offset: tipOffset, seconds: 1.3, jitter: 0, seed: 1 });
  await page.waitForFunction(() => window.capture.session.state === 'done', null, { timeout: 8000 }).catch(() => {});
  s = await session();
  check(s.state === 'done', 'holding a trigger saves them: the session is done', s.state);

  // --- The result against the avatar's own measurements.
  const exported = await json(base, `/api/sessions/${sessionId}/export?format=json`);
  const set = exported.body?.measurements ?? {};
  check(exported.status === 200 && exported.body?.sex === SEX, 'the session exports as a measurement set', exported.text.slice(0, 200));
  for (const [name, want] of Object.entries(truth)) {
    const got = set[name];
    check(typeof got === 'number' && Math.abs(got - want) <= TOLERANCE_CM,
      `${name} matches the avatar within ${TOLERANCE_CM} cm`, `${got?.toFixed?.(2)} vs ${want.toFixed(2)} cm, Δ ${(got - want).toFixed(2)}`);
  }
  check(Math.abs((set.weight ?? 0) - weightKg) < 0.05, 'the weight is the one entered', String(set.weight));
  check(Math.abs(s.floor_m - FLOOR_SHIFT) <= POINT_NOISE + JITTER, 'the floor is found where the taps were', `${(s.floor_m * 100).toFixed(2)} cm`);

  // --- The mirror and the link.
  await page.waitForFunction(() => !!window.capture.avatar, null, { timeout: 30000 }).catch(() => {});
  check(await page.evaluate(() => !!window.capture.avatar), 'the avatar is built from the captured values');
  await page.waitForTimeout(500);
  if (screenshots) await bigShot(join(screenshots, 'capture-mirror.png'));
  const mirrorLink = await page.locator('#open-mirror').getAttribute('href');
  check(mirrorLink === `/mirror.html?session=${encodeURIComponent(sessionId)}`, 'the page offers the mirror for the session', mirrorLink);
  const link = await page.locator('#open-desktop').getAttribute('href');
  check(link === `/?session=${sessionId}`, 'the page links to the desktop tool', link);
  check(await page.locator('#open-desktop').isVisible(), 'the result buttons show once the session is done');

  // The 2-D page of the other device followed along.
  await other.waitForFunction(() => window.capture.session?.state === 'done', null, { timeout: 10000 }).catch(() => {});
  check(await other.evaluate(() => window.capture.session?.state) === 'done', 'the other device sees the finished session');
  if (screenshots) {
    await other.bringToFront();
    await other.waitForTimeout(500);
    await other.screenshot({ path: join(screenshots, 'capture-page.png') });
  }

  // The desktop tool opens the session's values.
  const desk = await otherContext.newPage();
  await watch(desk);
  await desk.goto(`${base}${link}`);
  await desk.waitForFunction((v) => Math.abs(parseFloat(document.querySelector('#in-stature')?.value) - v) < 0.051, set.stature, { timeout: 30000 }).catch(() => {});
  check(Math.abs(parseFloat(await desk.inputValue('#in-stature')) - set.stature) < 0.051, 'the desktop tool loads the session (?session=)',
    `${await desk.inputValue('#in-stature')} vs ${set.stature}`);
  check(Math.abs(parseFloat(await desk.inputValue('#in-span')) - set.span) < 0.051, 'with its arm span', await desk.inputValue('#in-span'));

  // The experimenter issues a new code on the page: the old one stops working, the new
  // one writes (an empty batch of samples changes nothing).
  await page.evaluate(() => document.getElementById('new-code').click());  // the XR overlay covers the page
  await page.waitForFunction((old) => document.querySelector('#pairing-code')?.innerText.trim() !== old, code, { timeout: 10000 }).catch(() => {});
  const newCode = (await page.locator('#pairing-code').innerText()).trim();
  check(/^\d{6}$/.test(newCode) && newCode !== code, 'New code shows another six-digit code', `${code} → ${newCode}`);
  const emptyBatch = (c) => json(base, `/api/sessions/${sessionId}/samples`, { method: 'POST',
    headers: { 'X-Caliper-Pairing': c, 'Content-Type': 'application/json' }, body: JSON.stringify({ samples: [] }) });
  const oldRefused = await emptyBatch(code);
  check(oldRefused.status === 403, 'the old code is refused after New code', `${oldRefused.status}`);
  const newAccepted = await emptyBatch(newCode);
  check(newAccepted.status === 200, 'the new code writes', `${newAccepted.status} ${newAccepted.text.slice(0, 200)}`);

  check(!served.some((u) => /iwer/i.test(u)), 'the page never loads iwer from the server');
  check(outside.length === 0, 'nothing is fetched from outside the server', outside.join(', '));
  check(pageErrors.length === 0, 'no errors in the pages', pageErrors.join('\n'));
} catch (e) {
  fail(e.stack ?? e);
} finally {
  await browser.close();
  server?.kill('SIGTERM');
  rmSync(dataDir, { recursive: true, force: true });
}

finish();
