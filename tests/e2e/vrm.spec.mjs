#!/usr/bin/env node
// Loads a Caliper .vrm with @pixiv/three-vrm (npm, web/node_modules) in headless Chromium and
// checks what a VRM application gets: a VRM 1.0 with every required humanoid bone and the
// fingers resolved to the right nodes, meta carrying the body model's licence, and a look-at
// origin near the eyes; then renders the avatar (three.js) for a screenshot.
//
//   node tests/e2e/vrm.spec.mjs --caliper build/bin/caliper [--screenshots DIR]
//
// Exit: 0 pass, 1 fail, 77 skipped (no browser, playwright-core or three-vrm).
import { spawnSync } from 'node:child_process';
import { existsSync, mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, extname } from 'node:path';
import { root, caliper, screenshots, loadChromium, check, fail, finish, launchBrowser, skip } from './harness.mjs';

const chromium = loadChromium();
const modules = join(root, 'web', 'node_modules');
if (!existsSync(join(modules, '@pixiv', 'three-vrm'))) skip('@pixiv/three-vrm is not installed in web/ (run scripts/install-deps.sh)');

const tmp = mkdtempSync(join(tmpdir(), 'caliper-vrm-'));
const vrmPath = join(tmp, 'avatar.vrm');
const made = spawnSync(caliper, ['avatar', '--sex', 'female', '--height', '165', '--weight', '62', '-o', vrmPath, '-q'],
  { encoding: 'utf8' });
if (made.status !== 0) fail(`caliper avatar -o avatar.vrm failed: ${made.stdout}${made.stderr}`);

const page_html = `<!doctype html><html><body style="margin:0;background:#f4f4f4">
<script type="importmap">{"imports": {
  "three": "/m/three/build/three.module.js",
  "three/addons/": "/m/three/examples/jsm/",
  "@pixiv/three-vrm": "/m/@pixiv/three-vrm/lib/three-vrm.module.js"}}</script>
<script type="module">
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { VRMLoaderPlugin } from '@pixiv/three-vrm';
try {
  const loader = new GLTFLoader();
  loader.register((parser) => new VRMLoaderPlugin(parser));
  const gltf = await loader.loadAsync('/avatar.vrm');
  const vrm = gltf.userData.vrm;
  const bones = {};
  for (const name of Object.keys(vrm.humanoid.humanBones)) bones[name] = vrm.humanoid.getRawBoneNode(name)?.name ?? null;
  const head = new THREE.Vector3();
  vrm.humanoid.getRawBoneNode('head').getWorldPosition(head);
  const eye = new THREE.Vector3();
  vrm.lookAt.getLookAtWorldPosition(eye);
  const box = new THREE.Box3().setFromObject(vrm.scene);
  const renderer = new THREE.WebGLRenderer({ antialias: true });
  renderer.setSize(480, 720);
  renderer.outputColorSpace = THREE.SRGBColorSpace;
  document.body.appendChild(renderer.domElement);
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0xf4f4f4);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x886655, 2.2));
  const sun = new THREE.DirectionalLight(0xffffff, 1.6);
  sun.position.set(1, 2, 3);
  scene.add(sun);
  scene.add(vrm.scene);
  // Bend the left elbow through the normalized humanoid: the VRM path an app animates.
  vrm.humanoid.getNormalizedBoneNode('leftLowerArm').rotation.z = 1.0;
  vrm.update(0);
  const camera = new THREE.PerspectiveCamera(30, 480 / 720, 0.1, 20);
  camera.position.set(0, 0.9, 4.8);
  camera.lookAt(0, 0.85, 0);
  renderer.render(scene, camera);
  window.result = { ok: true, metaVersion: vrm.meta.metaVersion, meta: vrm.meta, bones,
    head: head.toArray(), eye: eye.toArray(), height: box.max.y - box.min.y };
} catch (e) {
  window.result = { ok: false, error: String(e && e.stack || e) };
}
</script></body></html>`;

const types = { '.js': 'text/javascript', '.mjs': 'text/javascript', '.vrm': 'model/gltf-binary' };
const browser = await launchBrowser(chromium);
try {
  const page = await browser.newPage({ viewport: { width: 480, height: 720 } });
  await page.route('http://vrm.test/**', (route) => {
    const path = new URL(route.request().url()).pathname;
    if (path === '/') return route.fulfill({ contentType: 'text/html', body: page_html });
    if (path === '/avatar.vrm') return route.fulfill({ contentType: types['.vrm'], body: readFileSync(vrmPath) });
    if (path.startsWith('/m/') && !path.includes('..')) {
      const file = join(modules, decodeURIComponent(path.slice(3)));
      if (existsSync(file)) return route.fulfill({ contentType: types[extname(file)] ?? 'application/octet-stream', body: readFileSync(file) });
    }
    return route.fulfill({ status: 404, body: 'not found' });
  });
  await page.goto('http://vrm.test/');
  await page.waitForFunction(() => window.result !== undefined, null, { timeout: 60000 });
  const r = await page.evaluate(() => window.result);
  check(r.ok, 'three-vrm loads the .vrm', r.error ?? '');
  if (r.ok) {
    check(r.metaVersion === '1', 'it is a VRM 1.0', r.metaVersion);
    const required = ['hips', 'spine', 'head', 'leftUpperLeg', 'leftLowerLeg', 'leftFoot', 'rightUpperLeg', 'rightLowerLeg',
      'rightFoot', 'leftUpperArm', 'leftLowerArm', 'leftHand', 'rightUpperArm', 'rightLowerArm', 'rightHand'];
    const missing = required.filter((b) => !r.bones[b]);
    check(missing.length === 0, 'every required humanoid bone resolves to a node', missing.join(', '));
    // SMPL's one-off names: the VRM bone must land on the joint that starts it.
    const expected = { hips: 'pelvis', leftUpperArm: 'left_shoulder', leftShoulder: 'left_collar', leftHand: 'left_wrist',
      leftFoot: 'left_ankle', leftToes: 'left_foot', chest: 'spine2', upperChest: 'spine3', leftThumbMetacarpal: 'left_thumb1',
      rightLittleDistal: 'right_pinky3' };
    for (const [bone, node] of Object.entries(expected)) check(r.bones[bone] === node, `${bone} is ${node}`, String(r.bones[bone]));
    const fingers = Object.keys(r.bones).filter((b) => /Thumb|Index|Middle|Ring|Little/.test(b));
    check(fingers.length === 30, 'all 30 finger bones resolve', String(fingers.length));
    check(r.meta.licenseUrl === 'https://vrm.dev/licenses/1.0/', 'meta has the VRM licence URL', r.meta.licenseUrl);
    check(r.meta.commercialUsage === 'corporation', 'the built-in body allows commercial use', r.meta.commercialUsage);
    check(/mannequin-female/.test(r.meta.thirdPartyLicenses ?? ''), 'meta names the body model', r.meta.thirdPartyLicenses);
    check(Math.abs(r.height - 1.65) < 0.01, 'the avatar is 1.65 m tall', String(r.height));
    // Eye height is about 93 % of stature; the look-at origin sits above the head joint, in front of it.
    check(Math.abs(r.eye[1] - 0.933 * 1.65) < 0.02 && r.eye[1] > r.head[1] && r.eye[2] > r.head[2],
      'the look-at origin is at eye height, in front of the head joint', JSON.stringify({ eye: r.eye, head: r.head }));
    if (screenshots) await page.screenshot({ path: join(screenshots, 'vrm-three.png') });
  }
} finally {
  await browser.close();
  rmSync(tmp, { recursive: true, force: true });
}
finish();
