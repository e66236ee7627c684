// Caliper's virtual mirror (Pujades et al. 2019, Fig. 1 and §4.3): the user steps into their own
// measured avatar in WebXR. The headset and the two controllers drive it (embodiment.js), the
// first-person view shows the body when looking down (its head hidden there), and a mirror ahead
// shows all of it. The experimenter's body-image tasks (show a weight change, or let the
// participant adjust the body with the thumbstick) are polled from the server (mirror-body.js).
// Notes for experimenters and the IK's choices: docs/mirror.md.
import * as THREE from 'three';
import { Reflector } from 'three/addons/objects/Reflector.js';
import { BodyDriver, XR_HAND_JOINTS, eyeOffsetFromBody } from './embodiment.js';
import {
  ApiError, sessionModel, setModel, importSet, glbModel, blendBodies, currentTask, answerTask,
  localTasks, startLocalTask,
} from './mirror-body.js';
import { setVertexNormals } from './shared.js';

const $ = (id) => document.getElementById(id);

const state = {
  ready: false,
  sessionId: null,
  code: null,
  source: null,            // 'session' | 'set' | 'glb'
  model: null,             // mirror model (mirror-body.js)
  pct: 0,                  // the weight change the body shows now
  task: null,              // the running body-image task (or null)
  taskShownAt: null,       // s (page clock) when the task's body was first shown
  adjustments: 0,
  answering: false,
  answers: [],             // tasks answered from this page (for the test and the curious)
  inXR: false,
  mirrorTexture: [0, 0],   // the mirror's texture size, pixels (fitMirrorTexture)
  xrFrames: 0,
  frames: 0,
  frameMs: new Float64Array(600),   // ring of per-frame times of the callback: IK, bones, both renders' submission
  frameInterval: new Float64Array(600),   // ring of times between frames (everything, the rasterizer too)
  localTasks,
  handTracked: { left: false, right: false },   // this frame's hands came from hand tracking
};
window.mirror = state;

function setStatus(text, error = false) {
  $('status').textContent = text;
  $('status').classList.toggle('error', error);
}
function showError(e) {
  const box = $('error');
  box.textContent = e.status === 403 && e.field === 'pairing_code' ? `${e.message} (type the session's pairing code)` : e.message;
  box.hidden = false;
  setStatus(e.message, true);
}
const clearError = () => { $('error').hidden = true; };
const clock = () => performance.now() / 1000;     // the page's clock for task times, seconds

// ---------------------------------------------------------------------------------------------
// Scene: a floor, the mirror ahead (1.4 m, facing the user's starting direction), a small panel.

const renderer = new THREE.WebGLRenderer({ antialias: true });
renderer.setPixelRatio(Math.min(window.devicePixelRatio || 1, 2));
renderer.outputColorSpace = THREE.SRGBColorSpace;
renderer.xr.enabled = true;
renderer.xr.setReferenceSpaceType('local-floor');
renderer.info.autoReset = false;     // counted per frame over both passes (the mirror renders inside the frame)
$('preview-host').appendChild(renderer.domElement);

const scene = new THREE.Scene();
scene.background = new THREE.Color(0x2a3038);
const camera = new THREE.PerspectiveCamera(80, 4 / 3, 0.05, 50);
scene.add(new THREE.HemisphereLight(0xffffff, 0x5a6470, 1.7));
const keyLight = new THREE.DirectionalLight(0xffffff, 1.5);
keyLight.position.set(0.6, 3, 1.5);
scene.add(keyLight);
const MIRROR = { width: 1.3, height: 2.1, distance: 1.2 };
// The room: a floor from the mirror's wall back to the wall behind the user (a floor reaching
// behind the mirror was drawn over the mirror's lower half in SwiftShader).
const ROOM_BACK = 2.5;
const floor = new THREE.Mesh(new THREE.PlaneGeometry(8, MIRROR.distance + ROOM_BACK), new THREE.MeshStandardMaterial({ color: 0x4a5360, roughness: 0.95 }));
floor.rotation.x = -Math.PI / 2;
floor.position.z = (ROOM_BACK - MIRROR.distance) / 2;
scene.add(floor);
const grid = new THREE.GridHelper(8, 16, 0x7d8894, 0x5f6975);   // 50 cm cells: scale cues in the mirror
grid.position.y = 0.002;
scene.add(grid);
// A back wall behind the user, so the mirror shows a room and not the void.
const wall = new THREE.Mesh(new THREE.PlaneGeometry(8, 3), new THREE.MeshStandardMaterial({ color: 0x6b7480, roughness: 1 }));
wall.position.set(0, 1.5, ROOM_BACK);
wall.rotation.y = Math.PI;
scene.add(wall);

const mirror = new Reflector(new THREE.PlaneGeometry(MIRROR.width, MIRROR.height), {
  textureWidth: 1024, textureHeight: 1024 * (MIRROR.height / MIRROR.width), color: 0xc8ccd0,
});
// The mirror spans most of the view's height from where the user stands, so its texture gets as
// many rows as the display (one eye's buffer in VR, the canvas outside), checked every frame:
// more pixels than that are never seen, and fill rate is the mirror's whole cost
// (docs/performance.md "Mirror").
function fitMirrorTexture(xrFrame) {
  const layer = xrFrame ? renderer.xr.getBaseLayer() : null;   // an XRWebGLLayer or a projection layer
  const displayRows = layer ? layer.framebufferHeight ?? layer.textureHeight : renderer.domElement.height;
  const rows = Math.min(2048, Math.max(256, Math.round(displayRows) || 1024));
  if (rows === state.mirrorTexture[1]) return;
  state.mirrorTexture = [Math.round(rows * (MIRROR.width / MIRROR.height)), rows];
  mirror.getRenderTarget().setSize(...state.mirrorTexture);
}
mirror.position.set(0, MIRROR.height / 2 + 0.05, -MIRROR.distance);
state.mirrorPlane = MIRROR;      // for the e2e test: where the mirror is
scene.add(mirror);
const frameMesh = new THREE.Mesh(new THREE.BoxGeometry(MIRROR.width + 0.08, MIRROR.height + 0.08, 0.04),
  new THREE.MeshStandardMaterial({ color: 0x1c2026, roughness: 0.5 }));
frameMesh.position.set(0, MIRROR.height / 2 + 0.05, -MIRROR.distance - 0.025);
scene.add(frameMesh);

// The head is drawn only in the mirror: the first-person camera sits inside it.
const bodyMaterial = new THREE.MeshStandardMaterial({ color: 0xcdbba8, roughness: 0.62 });
const headMaterial = bodyMaterial.clone();
headMaterial.visible = false;
const reflect = mirror.onBeforeRender;
state.headDrawn = { firstPerson: null, mirror: null };   // as last rendered (for the e2e test)
mirror.onBeforeRender = function (...args) {
  headMaterial.visible = true;
  state.headDrawn.mirror = headMaterial.visible;
  reflect.apply(this, args);
  headMaterial.visible = false;
};

// The task panel beside the mirror: instructions only, never a number.
const panelCanvas = document.createElement('canvas');
panelCanvas.width = 512;
panelCanvas.height = 320;
const panelTexture = new THREE.CanvasTexture(panelCanvas);
panelTexture.colorSpace = THREE.SRGBColorSpace;
const panel = new THREE.Mesh(new THREE.PlaneGeometry(0.6, 0.375), new THREE.MeshBasicMaterial({ map: panelTexture, toneMapped: false }));
panel.position.set(1.05, 1.45, -1.2);
panel.rotation.y = -0.45;
scene.add(panel);
state.panelText = [];

const INSTRUCTIONS = {
  how_i_look: 'Change the body until it looks like you.',
  how_i_would_like_to_look: 'Change the body until it looks how you would like to look.',
};
function drawPanel() {
  const ctx = panelCanvas.getContext('2d');
  const texts = [];
  ctx.fillStyle = '#ffffff';
  ctx.fillRect(0, 0, panelCanvas.width, panelCanvas.height);
  ctx.fillStyle = '#1e2630';
  const line = (t, y, font) => { ctx.font = font; ctx.fillText(t, 24, y); texts.push(t); };
  const t = state.task;
  if (!state.model) line('Loading your avatar…', 60, '600 30px system-ui, sans-serif');
  else if (!t) {
    line('Look at yourself', 60, '600 32px system-ui, sans-serif');
    line('Move, look down, raise your arms.', 110, '24px system-ui, sans-serif');
  } else if (t.kind === 'show') {
    line('Look at the body in the mirror', 60, '600 30px system-ui, sans-serif');
  } else {
    const text = INSTRUCTIONS[t.instruction] ?? t.instruction;
    ctx.font = '600 28px system-ui, sans-serif';
    let y = 56;
    for (const l of wrap(ctx, text, panelCanvas.width - 48).slice(0, 3)) { line(l, y, '600 28px system-ui, sans-serif'); y += 38; }
    line('Thumbstick up: fuller · down: thinner', y + 24, '22px system-ui, sans-serif');
    line('Trigger: this is my answer', y + 58, '22px system-ui, sans-serif');
    if (state.answering) line('Saving…', y + 110, '600 24px system-ui, sans-serif');
  }
  state.panelText = texts;
  panelTexture.needsUpdate = true;
}
function wrap(ctx, text, maxWidth) {
  const lines = [];
  let lineText = '';
  for (const w of String(text).split(/\s+/)) {
    const next = lineText ? `${lineText} ${w}` : w;
    if (ctx.measureText(next).width > maxWidth && lineText) { lines.push(lineText); lineText = w; } else lineText = next;
  }
  if (lineText) lines.push(lineText);
  return lines;
}

// ---------------------------------------------------------------------------------------------
// The avatar: one skinned mesh. Its bones have identity rest rotations (each at its joint), so
// the driver's world rotations apply as they are; the bodies' shapes blend into its buffers.

let avatar = null;   // { mesh, bones, vertices, joints, driver }

function buildAvatar(model) {
  if (avatar) { scene.remove(avatar.mesh); avatar.mesh.geometry.dispose(); }
  const n = model.jointNames.length, nv = model.bodies[0].vertices.length / 3;
  const vertices = new Float32Array(3 * nv), joints = new Float32Array(3 * n);
  state.pct = blendBodies(model, 0, vertices, joints);
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(vertices, 3));
  geometry.setAttribute('skinIndex', new THREE.Uint16BufferAttribute(model.skinIndex, 4));
  geometry.setAttribute('skinWeight', new THREE.Float32BufferAttribute(model.skinWeight, 4));
  setFacesHeadLast(geometry, model);
  setVertexNormals(geometry);
  const bones = model.jointNames.map((name) => Object.assign(new THREE.Bone(), { name }));
  const mesh = new THREE.SkinnedMesh(geometry, [bodyMaterial, headMaterial]);
  model.parents.forEach((p, i) => (p >= 0 ? bones[p] : mesh).add(bones[i]));
  const skeleton = new THREE.Skeleton(bones, bones.map(() => new THREE.Matrix4()));
  mesh.bind(skeleton, new THREE.Matrix4());
  mesh.frustumCulled = false;     // the bounding box is the rest pose's, not the posed body's
  scene.add(mesh);
  const headJoint = model.jointNames.indexOf('head');
  const driver = new BodyDriver({ jointNames: model.jointNames, parents: model.parents, restJoints: joints },
    eyeOffsetFromBody(vertices, Array.from(joints.subarray(3 * headJoint, 3 * headJoint + 3))));
  avatar = { mesh, bones, vertices, joints, driver, headJoint, invParent: new THREE.Quaternion() };
  setRest();
  state.eyeOffset = driver.eyeOffset.toArray();
}

// Triangles mostly skinned to the head (and joints under it) go last, as the second group: the
// head material draws them, only in the mirror.
function setFacesHeadLast(geometry, model) {
  const head = model.jointNames.indexOf('head');
  const under = new Uint8Array(model.jointNames.length);
  for (let i = 0; i < under.length; ++i) for (let j = i; j >= 0; j = model.parents[j]) if (j === head) { under[i] = 1; break; }
  const headWeight = (v) => {
    let w = 0;
    for (let k = 0; k < 4; ++k) if (under[model.skinIndex[4 * v + k]]) w += model.skinWeight[4 * v + k];
    return w;
  };
  const f = model.faces, body = [], headFaces = [];
  for (let t = 0; t < f.length; t += 3) {
    const w = (headWeight(f[t]) + headWeight(f[t + 1]) + headWeight(f[t + 2])) / 3;
    (w > 0.5 ? headFaces : body).push(f[t], f[t + 1], f[t + 2]);
  }
  geometry.setIndex(new THREE.BufferAttribute(Uint32Array.from([...body, ...headFaces]), 1));
  geometry.clearGroups();
  geometry.addGroup(0, body.length, 0);
  geometry.addGroup(body.length, headFaces.length, 1);
  state.headTriangles = headFaces.length / 3;
}

// The rest skeleton of the current blend: bind matrices, and the driver's bone lengths and eyes.
function setRest() {
  const { joints, vertices, driver, bones, mesh, headJoint } = avatar;
  const inverses = mesh.skeleton.boneInverses;
  for (let i = 0; i < bones.length; ++i) inverses[i].makeTranslation(-joints[3 * i], -joints[3 * i + 1], -joints[3 * i + 2]);
  driver.setRest(joints, eyeOffsetFromBody(vertices, [joints[3 * headJoint], joints[3 * headJoint + 1], joints[3 * headJoint + 2]]));
}

// Shows the body at a weight change (percent), blending the two neighbouring bodies.
function showWeightChange(pct) {
  if (!avatar) return;
  state.pct = blendBodies(state.model, pct, avatar.vertices, avatar.joints);
  const g = avatar.mesh.geometry;
  g.attributes.position.needsUpdate = true;
  setVertexNormals(g);
  setRest();
}

// The driver's world rotations and positions → bone-local transforms (allocation-free).
function applyPose() {
  const { bones, driver } = avatar, P = driver.positions, R = driver.rotations, parents = driver.parents;
  const inv = avatar.invParent;
  for (let i = 0; i < bones.length; ++i) {
    const b = bones[i], p = parents[i];
    if (p < 0) { b.position.copy(P[i]); b.quaternion.copy(R[i]); continue; }
    inv.copy(R[p]).invert();
    b.quaternion.copy(inv).multiply(R[i]);
    b.position.copy(P[i]).sub(P[p]).applyQuaternion(inv);
  }
}

// World position of a joint as three.js skins it (for the e2e test): [x, y, z].
state.jointWorld = (name) => {
  const i = avatar?.driver.jointIndex(name) ?? -1;
  if (i < 0) return null;
  avatar.mesh.updateMatrixWorld(true);
  return avatar.bones[i].getWorldPosition(new THREE.Vector3()).toArray();
};

// A joint of the rest skeleton the body now shows: [x, y, z] (for the e2e test's reach).
state.restJoint = (name) => {
  const i = avatar?.driver.jointIndex(name) ?? -1;
  return i < 0 ? null : Array.from(avatar.joints.subarray(3 * i, 3 * i + 3));
};
state.avatarMesh = () => avatar?.mesh ?? null;
// The rest body's width across the waist (60 % of its height), metres: how a weight change shows.
state.waistWidth = () => {
  const v = avatar.vertices;
  let top = -Infinity;
  for (let i = 1; i < v.length; i += 3) top = Math.max(top, v[i]);
  let lo = Infinity, hi = -Infinity;
  for (let i = 0; i < v.length; i += 3) {
    if (Math.abs(v[i + 1] - 0.6 * top) < 0.01 && Math.abs(v[i]) < 0.25) { lo = Math.min(lo, v[i]); hi = Math.max(hi, v[i]); }
  }
  return hi - lo;
};

// ---------------------------------------------------------------------------------------------
// The frame: poses in, IK, task input, render. The same loop runs on the page (a standing user
// looking at the mirror) and in the headset.

const DESK_HEAD = { position: new THREE.Vector3(), orientation: new THREE.Quaternion().setFromEuler(new THREE.Euler(-0.12, 0, 0)) };
const grips = { left: { seen: false, trigger: false, stick: false }, right: { seen: false, trigger: false, stick: false } };
let lastTime = null;
let stickY = 0;        // this frame's thumbstick (up = −1), either hand

function frame(time, xrFrame) {
  const t0 = performance.now();
  const dt = lastTime === null ? 1 / 72 : (time - lastTime) / 1000;
  state.frameInterval[state.frames % state.frameInterval.length] = dt * 1000;
  lastTime = time;
  stickY = 0;
  if (avatar) {
    if (xrFrame) readXR(xrFrame);
    else {
      DESK_HEAD.position.set(0, avatar.joints[3 * avatar.headJoint + 1] + avatar.driver.eyeOffset.y, 0);
      avatar.driver.setHead(DESK_HEAD.position, DESK_HEAD.orientation);
      avatar.driver.setHand('left', null, null);
      avatar.driver.setHand('right', null, null);
      camera.position.copy(DESK_HEAD.position);
      camera.quaternion.copy(DESK_HEAD.orientation);
      stickY = keyStick;
    }
    adjust(dt);
    avatar.driver.update(dt);
    applyPose();
  }
  state.headDrawn.firstPerson = headMaterial.visible;
  fitMirrorTexture(xrFrame);
  renderer.info.reset();
  renderer.render(scene, camera);
  state.drawn = { calls: renderer.info.render.calls, triangles: renderer.info.render.triangles };  // both passes
  state.frameMs[state.frames % state.frameMs.length] = performance.now() - t0;
  state.frames += 1;
}

function readXR(xrFrame) {
  state.xrFrames += 1;
  const ref = renderer.xr.getReferenceSpace();
  const viewer = xrFrame.getViewerPose(ref);
  if (viewer) avatar.driver.setHead(viewer.transform.position, viewer.transform.orientation);
  grips.left.seen = grips.right.seen = false;
  state.handTracked.left = state.handTracked.right = false;
  const sources = xrFrame.session.inputSources;
  for (let i = 0; i < sources.length; ++i) {
    const source = sources[i], hand = source.handedness;
    if (hand !== 'left' && hand !== 'right') continue;
    if (source.hand && readHandJoints(xrFrame, source, ref)) {
      grips[hand].seen = state.handTracked[hand] = true;
    } else {
      const pose = source.gripSpace ? xrFrame.getPose(source.gripSpace, ref) : null;
      if (!pose) continue;
      grips[hand].seen = true;
      avatar.driver.setHand(hand, pose.transform.position, pose.transform.orientation);
    }
    const pad = source.gamepad;
    if (!pad) continue;
    const y = pad.axes.length >= 4 ? pad.axes[3] : pad.axes[1] ?? 0;
    if (Math.abs(y) > Math.abs(stickY)) stickY = y;
    // The trigger by polling its value, never the `select` event (emulators fire it at press,
    // headsets at release): an answer is one press.
    const down = (pad.buttons[0]?.value ?? 0) > 0.5;
    if (down && !grips[hand].trigger) confirm();
    grips[hand].trigger = down;
  }
  if (!grips.left.seen) avatar.driver.setHand('left', null, null);
  if (!grips.right.seen) avatar.driver.setHand('right', null, null);
}

// A tracked hand (WebXR Hand Input, where the headset offers it): its 25 joint poses in one call
// into a buffer kept per hand, handed to the driver. False when some joint has no pose.
const handPoses = { left: new Float32Array(16 * XR_HAND_JOINTS.length), right: new Float32Array(16 * XR_HAND_JOINTS.length) };
const handSpaces = new WeakMap();   // XRHand → its joint spaces in XR_HAND_JOINTS order, or null if some is missing
function readHandJoints(xrFrame, source, ref) {
  let spaces = handSpaces.get(source.hand);
  if (spaces === undefined) {      // once per hand, not per frame
    spaces = XR_HAND_JOINTS.map((name) => source.hand.get(name));
    if (spaces.some((space) => !space)) spaces = null;
    handSpaces.set(source.hand, spaces);
  }
  if (!spaces || !xrFrame.fillPoses?.(spaces, ref, handPoses[source.handedness])) return false;
  avatar.driver.setHandJoints(source.handedness, handPoses[source.handedness]);
  return avatar.driver.hands[source.handedness].fromJoints;
}
// The tracked joints' positions of a hand this frame (for the e2e test): flat x,y,z, or null.
state.trackedHandJoints = (side) => (state.handTracked[side] ? Array.from(avatar.driver.hands[side].joints) : null);

// ---------------------------------------------------------------------------------------------
// Body-image tasks

const STICK_DEADZONE = 0.2;
const ADJUST_RATE = 12;       // % of body weight per second at full deflection
let stickActive = false;
let keyStick = 0;

function adjust(dt) {
  const t = state.task;
  const active = Math.abs(stickY) > STICK_DEADZONE;
  if (t?.kind === 'adjust' && t.state === 'running' && !state.answering && active) {
    if (!stickActive) state.adjustments += 1;       // one push of the stick = one adjustment
    const [lo, hi] = t.range_pct;
    const pct = Math.min(hi, Math.max(lo, state.pct - stickY * ADJUST_RATE * dt));
    if (pct !== state.pct) showWeightChange(pct);
  }
  stickActive = active;
}

async function confirm() {
  const t = state.task;
  if (!t || t.kind !== 'adjust' || t.state !== 'running' || state.answering) return;
  state.answering = true;
  drawPanel();
  const answer = {
    chosen_weight_change_pct: Math.round(state.pct * 10) / 10,
    shown_at_s: Math.round(state.taskShownAt * 1000) / 1000,
    answered_at_s: Math.round(clock() * 1000) / 1000,
    adjustments: state.adjustments,
  };
  try {
    const stored = await answerTask(state.sessionId, state.code, t, answer);
    state.answers.push(stored);
    state.task = null;
    setStatus('answer saved');
  } catch (e) {
    showError(e);
  } finally {
    state.answering = false;
    drawPanel();
  }
}

// The headset asks for the running task about once a second.
async function pollTask() {
  if (!state.model || state.source === 'glb') return;
  let t;
  try { t = await currentTask(state.source === 'session' ? state.sessionId : null, state.code); } catch { return; }
  if (state.answering) return;
  if ((t?.id ?? null) !== (state.task?.id ?? null)) startTask(t);
}
setInterval(pollTask, 1000);
// The page's own stand-in task list (mirror-body.js), for a server without the task endpoints.
state.startLocalTask = (task) => { const t = startLocalTask(task); pollTask(); return t; };

function startTask(t) {
  state.task = t && t.state === 'running' ? t : null;
  state.adjustments = 0;
  state.taskShownAt = clock();
  showWeightChange(state.task ? state.task.start_weight_change_pct : 0);
  drawPanel();
}

// ---------------------------------------------------------------------------------------------
// Loading a body

async function load(what) {
  clearError();
  setStatus('building the bodies…');
  try {
    const model = await what();
    state.model = model;
    buildAvatar(model);
    state.task = null;
    drawPanel();
    const b = model.bodies;
    $('body-text').textContent = b.length > 1
      ? `${model.sex ?? ''} · ${b.length} bodies from ${b[0].pct}% to +${b[b.length - 1].pct}% body weight`
      : 'one body (no weight changes)';
    $('enter-vr').disabled = !state.xrSupported;
    setStatus('ready: look into the mirror');
    await pollTask();
  } catch (e) {
    showError(e);
  }
}

function loadSession() {
  const id = $('session-id').value.trim();
  const code = $('code').value.trim() || null;
  if (!id) { showError(new ApiError(400, { message: 'type the session id', field: 'session' })); return; }
  if (code && !/^\d{6}$/.test(code)) { showError(new ApiError(400, { message: 'the pairing code has six digits', field: 'pairing_code' })); return; }
  state.sessionId = id;
  state.code = code;
  state.source = 'session';
  const url = new URL(location.href);
  url.searchParams.set('session', id);
  history.replaceState(null, '', url);
  return load(() => sessionModel(id, code));
}

async function loadFile(file) {
  if (!file) return;
  state.sessionId = null;
  state.code = null;
  if (/\.glb$/i.test(file.name)) {
    state.source = 'glb';
    return load(async () => glbModel(await file.arrayBuffer()));
  }
  state.source = 'set';
  return load(async () => {
    const set = await importSet(await file.text());
    return setModel(set.sex ?? $('file-sex').value, set.measurements);
  });
}

// ---------------------------------------------------------------------------------------------
// Entering VR

async function enterVR() {
  if (!navigator.xr || !state.model) return;
  try {
    const session = await navigator.xr.requestSession('immersive-vr', { requiredFeatures: ['local-floor'], optionalFeatures: ['hand-tracking'] });
    await renderer.xr.setSession(session);
    state.inXR = true;
    document.body.dataset.xr = 'on';
    session.addEventListener('end', () => { state.inXR = false; document.body.dataset.xr = 'off'; resize(); });
  } catch (e) {
    showError(new ApiError(0, { message: `could not enter VR: ${e.message}` }));
  }
}

async function checkXR() {
  let ok = false;
  try { ok = !!navigator.xr && await navigator.xr.isSessionSupported('immersive-vr'); } catch { ok = false; }
  state.xrSupported = ok;
  $('enter-vr').disabled = !ok || !state.model;
  $('xr-hint').textContent = ok ? 'Put the headset on, then Enter mirror.'
    : 'No WebXR headset here: open this page in the headset\'s browser (HTTPS or adb reverse, see docs/capture-page.md). The mirror below shows what it will see.';
}

function resize() {
  const host = $('preview-host');
  const w = host.clientWidth || 480, h = Math.round(w * 0.75);
  if (!renderer.xr.isPresenting) renderer.setSize(w, h, false);
  camera.aspect = w / h;
  camera.updateProjectionMatrix();
}
new ResizeObserver(resize).observe($('preview-host'));

// The page's own keys do what the thumbstick and trigger do (a desktop mirror, and tests).
addEventListener('keydown', (e) => {
  if (e.target instanceof HTMLInputElement) return;
  if (e.key === 'ArrowUp') keyStick = -1;
  else if (e.key === 'ArrowDown') keyStick = 1;
  else if (e.key === 'Enter') confirm();
});
addEventListener('keyup', (e) => { if (e.key === 'ArrowUp' || e.key === 'ArrowDown') keyStick = 0; });

// ---------------------------------------------------------------------------------------------
// Start

async function start() {
  drawPanel();
  $('load-session').addEventListener('click', loadSession);
  $('file').addEventListener('change', (e) => loadFile(e.target.files?.[0]));
  $('enter-vr').addEventListener('click', enterVR);
  await checkXR();
  navigator.xr?.addEventListener?.('devicechange', checkXR);
  renderer.setAnimationLoop(frame);
  const wanted = new URLSearchParams(location.search).get('session');
  if (wanted) {
    $('session-id').value = wanted;
    // A code the capture page remembered for this session (same browser), else none: the
    // server's own machine reads sessions without one; elsewhere the form asks for it.
    try { $('code').value = sessionStorage.getItem(`caliper-pairing-${wanted}`) ?? ''; } catch { /* private mode */ }
    await loadSession();
  } else {
    setStatus('load a session or a file');
  }
  state.ready = true;
}

start().catch((e) => { showError(e); setStatus(e.message, true); });
