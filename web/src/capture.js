// Caliper capture page (paper §3.1, §5): the WebXR side of the Virtual Caliper. The person holds
// two controllers and touches landmarks with the tip of a handle, holding the trigger for a
// second per point. This page only streams what the controllers do; the C++ protocol engine on
// the server decides what is a point (hold ≥ 1 s, tip still), calibrates the floor, applies the
// ISAK repetition rule and says what comes next. The HTTP contract is in docs/capture.md;
// this page's own notes are in docs/capture-page.md.
import * as THREE from 'three';
import qrcode from 'qrcode-generator';
import { ApiError, api as request, decodeBase64, setVertexNormals } from './shared.js';

// ---------------------------------------------------------------------------------------------
// API

// Writes always need the code; reads of a session need it too from any device but the server's
// own machine (docs/api.md "Pairing"), so it goes with every request once known.
const api = (path, { write = false, ...rest } = {}) => request(path, { ...rest, code: write ? state.code ?? '' : state.code });

const FRIENDLY = {
  floor: 'Floor', stature: 'Height', weight: 'Weight', span: 'Arm span', crotch_height: 'Inseam',
  hip_breadth: 'Hip width', arm_length: 'Arm length', biacromial_breadth: 'Shoulder width',
  chest_height: 'Nipple height', waist_height: 'Navel height', chest_breadth: 'Chest width',
  waist_breadth: 'Waist width', waist_depth: 'Torso depth', wrist_span: 'Wrist span',
  forearm_length: 'Forearm length',
};
const friendly = (name) => FRIENDLY[name] ?? name.replaceAll('_', ' ').replace(/^./, (c) => c.toUpperCase());

// ---------------------------------------------------------------------------------------------
// State

const state = {
  session: null,            // the server's Session (docs/capture.md)
  code: null,               // pairing code: needed for every write
  profiles: {},             // profile id → { tip_offset_m }
  defaultProfile: null,
  events: [],               // every event the server sent, oldest first (for the e2e test)
  samplesSent: 0,
  batchesSent: 0,
  message: null,            // { text, tone: 'ok' | 'bad' | 'info' } shown on the panel
  flashUntil: 0,            // performance.now() until which the panel and tips flash
  flashTone: 'ok',
  inXR: false,
  entryDraft: { sex: null, weight: null },  // what the VR entry form shows
  avatarKey: null,          // measurement set the avatar was built from
  avatar: null,             // { mesh, stature }
  catalogue: null,          // names /api/avatar accepts
  weightRange: { min: 10, max: 300 },  // replaced at start by the catalogue's accepted range
  headsetUrl: null,         // what the QR code on the 2-D page encodes
  headset: null,            // GET /api/capture/headset: { urls, other_devices }
};
window.capture = state;     // for the end-to-end test and the curious

const $ = (id) => document.getElementById(id);

function setStatus(text, error = false) {
  const s = $('status');
  s.textContent = text;
  s.classList.toggle('error', error);
}

function showError(e) {
  const box = $('error');
  // 423: the session is locked after too many wrong codes; the message says to ask for a new one.
  box.textContent = e.status === 403 && e.field === 'pairing_code' ? `${e.message} (check the pairing code)` : e.message;
  box.hidden = false;
  setMessage(e.message, 'bad');
}
const clearError = () => { $('error').hidden = true; };

function setMessage(text, tone = 'info') {
  state.message = text ? { text, tone } : null;
  drawPanel();
}

// ---------------------------------------------------------------------------------------------
// Sound (WebAudio, generated: no audio files) and flash

let audio = null;
function unlockAudio() {
  try {
    audio ??= new (window.AudioContext || window.webkitAudioContext)();
    if (audio.state === 'suspended') audio.resume();
  } catch { audio = null; }
}

function tone(freq, start, duration, type = 'sine', gain = 0.18) {
  if (!audio) return;
  const t0 = audio.currentTime + start;
  const osc = audio.createOscillator();
  const amp = audio.createGain();
  osc.type = type;
  osc.frequency.value = freq;
  amp.gain.setValueAtTime(0, t0);
  amp.gain.linearRampToValueAtTime(gain, t0 + 0.01);
  amp.gain.exponentialRampToValueAtTime(0.001, t0 + duration);
  osc.connect(amp).connect(audio.destination);
  osc.start(t0);
  osc.stop(t0 + duration + 0.02);
}

const sounds = {
  accepted: () => { tone(880, 0, 0.12); tone(1320, 0.09, 0.16); },
  rejected: () => tone(196, 0, 0.28, 'square', 0.08),
  stepDone: () => { tone(660, 0, 0.1); tone(880, 0.1, 0.1); tone(1100, 0.2, 0.2); },
  done: () => [523, 659, 784, 1046].forEach((f, i) => tone(f, i * 0.12, 0.3)),
};

function flash(toneName) {
  state.flashUntil = performance.now() + 350;
  state.flashTone = toneName;
  drawPanel();
  setTimeout(drawPanel, 380);
}

// ---------------------------------------------------------------------------------------------
// Illustrations: a front-view figure drawn with canvas paths, the landmarks of the step marked.
// Coordinates: figure units, feet at y = 0, top of the head at y = 1, x to the figure's left.

const FIGURE = {
  head_top: [0, 1.0], head: [0, 0.935], neck: [0, 0.865], acromion: [0.11, 0.82],
  nipple: [0.06, 0.725], chest_side: [0.1, 0.725], navel: [0, 0.6], waist_side: [0.085, 0.6],
  hip: [0.1, 0.5], crotch: [0, 0.47], knee: [0.06, 0.27], ankle: [0.06, 0.04], toe: [0.1, 0.0],
  // Arms hanging.
  elbow: [0.15, 0.62], wrist: [0.17, 0.48], fingertip: [0.18, 0.39],
  // Arms out (T-pose, for spans).
  t_elbow: [0.27, 0.82], t_wrist: [0.41, 0.82], t_fingertip: [0.5, 0.82],
};

// name → what to mark: points ('name' or 'name_r' / 'name_l' for one side) and how.
const ILLUSTRATIONS = {
  floor: { floor: true },
  stature: { points: ['head_top'], kind: 'height' },
  chest_height: { points: ['nipple_r'], kind: 'height' },
  waist_height: { points: ['navel'], kind: 'height' },
  crotch_height: { points: ['crotch'], kind: 'height' },
  span: { points: ['t_fingertip_r', 't_fingertip_l'], kind: 'distance', tpose: true },
  wrist_span: { points: ['t_wrist_r', 't_wrist_l'], kind: 'distance', tpose: true },
  hip_breadth: { points: ['hip_r', 'hip_l'], kind: 'distance' },
  biacromial_breadth: { points: ['acromion_r', 'acromion_l'], kind: 'distance' },
  chest_breadth: { points: ['chest_side_r', 'chest_side_l'], kind: 'distance' },
  waist_breadth: { points: ['waist_side_r', 'waist_side_l'], kind: 'distance' },
  waist_depth: { points: ['navel'], kind: 'depth' },
  arm_length: { points: ['acromion_r', 'wrist_r'], kind: 'distance' },
  forearm_length: { points: ['elbow_r', 'wrist_r'], kind: 'distance' },
};

function figurePoint(key) {
  const side = /_([lr])$/.exec(key)?.[1];
  const base = side ? key.slice(0, -2) : key;
  const p = FIGURE[base];
  if (!p) return null;
  // Seen from the front, the figure's right side is on the viewer's left.
  return [side === 'r' ? -p[0] : p[0], p[1]];
}

function drawIllustration(ctx, name, kind, x0, y0, w, h) {
  const spec = ILLUSTRATIONS[name] ?? { kind, points: [] };
  // As large as the box allows: spans need the arms' width, heights room for the arrow.
  const extent = Math.max(spec.tpose ? 0.53 : 0.21, spec.kind === 'height' ? 0.34 : 0, spec.floor ? 0.4 : 0);
  const scale = Math.min(h * 0.86, (w * 0.94) / (2 * extent));
  const cx = x0 + w / 2, floorY = y0 + h * 0.93;
  const P = (p) => [cx + p[0] * scale, floorY - p[1] * scale];
  const line = (pts, width) => {
    ctx.lineWidth = width;
    ctx.beginPath();
    pts.forEach((p, i) => { const [x, y] = P(p); if (i) ctx.lineTo(x, y); else ctx.moveTo(x, y); });
    ctx.stroke();
  };
  const F = (k) => figurePoint(k);

  ctx.save();
  ctx.fillStyle = '#f4f6f8';
  ctx.fillRect(x0, y0, w, h);
  ctx.strokeStyle = '#9aa5b1';
  ctx.lineWidth = 2;
  ctx.beginPath(); ctx.moveTo(x0 + 10, floorY); ctx.lineTo(x0 + w - 10, floorY); ctx.stroke();

  // The figure: body lines and a head.
  ctx.strokeStyle = '#5b6673';
  ctx.lineCap = 'round';
  ctx.lineJoin = 'round';
  const arm = spec.tpose ? ['t_elbow', 't_wrist', 't_fingertip'] : ['elbow', 'wrist', 'fingertip'];
  for (const s of ['l', 'r']) {
    line([F(`acromion_${s}`), ...arm.map((a) => F(`${a}_${s}`))], scale * 0.035);
    line([F(`hip_${s}`), F(`knee_${s}`), F(`ankle_${s}`), F(`toe_${s}`)], scale * 0.045);
  }
  line([F('acromion_l'), F('acromion_r')], scale * 0.05);
  ctx.fillStyle = '#5b6673';
  ctx.beginPath();
  const [a, b, c, d] = [P(F('acromion_l')), P(F('acromion_r')), P(F('hip_r')), P(F('hip_l'))];
  ctx.moveTo(...a); ctx.lineTo(...b); ctx.lineTo(c[0], c[1]); ctx.lineTo(d[0], d[1]); ctx.closePath();
  ctx.globalAlpha = 0.85; ctx.fill(); ctx.globalAlpha = 1;
  line([F('neck'), [0, 0.82]], scale * 0.04);
  const [hx, hy] = P(F('head'));
  ctx.beginPath(); ctx.arc(hx, hy, scale * 0.062, 0, Math.PI * 2); ctx.fill();

  // What to touch, and what is measured.
  ctx.strokeStyle = '#e07a1f';
  ctx.fillStyle = '#e07a1f';
  if (spec.floor) {
    for (const fx of [-0.36, -0.18, 0.2, 0.36, 0.0]) {
      const [px, py] = P([fx, 0]);
      ctx.beginPath(); ctx.arc(px, py - 1, scale * 0.022, 0, Math.PI * 2); ctx.fill();
    }
  }
  const pts = (spec.points ?? []).map(F).filter(Boolean);
  if (spec.kind === 'height' && pts.length) {
    const p = pts[0];
    const side = 0.3;
    ctx.setLineDash([8, 6]);
    line([p, [side, p[1]]], 2.5);
    ctx.setLineDash([]);
    line([[side, 0], [side, p[1]]], 3);
    arrowHead(ctx, P([side, p[1]]), -Math.PI / 2, 12);
    arrowHead(ctx, P([side, 0]), Math.PI / 2, 12);
  } else if (spec.kind === 'distance' && pts.length === 2) {
    ctx.setLineDash([8, 6]);
    line(pts, 3);
    ctx.setLineDash([]);
  }
  for (const p of pts) {
    const [px, py] = P(p);
    ctx.beginPath(); ctx.arc(px, py, scale * 0.03, 0, Math.PI * 2); ctx.fill();
    ctx.strokeStyle = '#ffffff'; ctx.lineWidth = 2; ctx.stroke(); ctx.strokeStyle = '#e07a1f';
  }
  ctx.restore();
}

function arrowHead(ctx, [x, y], angle, size) {
  ctx.beginPath();
  ctx.moveTo(x, y);
  ctx.lineTo(x - size * Math.cos(angle - 0.45), y - size * Math.sin(angle - 0.45));
  ctx.lineTo(x - size * Math.cos(angle + 0.45), y - size * Math.sin(angle + 0.45));
  ctx.closePath();
  ctx.fill();
}

// ---------------------------------------------------------------------------------------------
// The panel: one canvas, shown on the 2-D page and as a texture in the headset.

const panelCanvas = document.createElement('canvas');
panelCanvas.width = 1024;
panelCanvas.height = 600;
panelCanvas.className = 'panel-canvas';
panelCanvas.setAttribute('aria-label', 'the headset panel');
let panelTexture = null;
state.panelText = [];       // the texts last drawn (for the e2e test)

function wrap(ctx, text, maxWidth) {
  const words = String(text).split(/\s+/);
  const lines = [];
  let line = '';
  for (const w of words) {
    const next = line ? `${line} ${w}` : w;
    if (ctx.measureText(next).width > maxWidth && line) { lines.push(line); line = w; } else line = next;
  }
  if (line) lines.push(line);
  return lines;
}

const TONES = { ok: '#2f8a55', bad: '#c43d2f', info: '#2d6a88' };

function drawPanel() {
  const ctx = panelCanvas.getContext('2d');
  const W = panelCanvas.width, H = panelCanvas.height;
  const s = state.session;
  const texts = [];
  const text = (t, x, y, font, color = '#1e2630') => {
    ctx.font = font; ctx.fillStyle = color; ctx.fillText(t, x, y); texts.push(t);
  };
  ctx.fillStyle = '#ffffff';
  ctx.fillRect(0, 0, W, H);
  const flashing = performance.now() < state.flashUntil;
  ctx.strokeStyle = flashing ? TONES[state.flashTone] : '#d5dbe1';
  ctx.lineWidth = flashing ? 24 : 6;
  ctx.strokeRect(0, 0, W, H);
  ctx.textBaseline = 'alphabetic';

  if (!s) {
    text('Caliper capture', 40, 90, '600 52px system-ui, sans-serif');
    text('Create or join a session on the page first.', 40, 160, '32px system-ui, sans-serif', '#66717e');
    finishPanel(texts);
    return;
  }

  const step = s.step;
  const illus = step?.illustration ?? (s.state === 'done' ? null : null);
  const left = step ? 330 : 40;
  if (step) drawIllustration(ctx, illus ?? step.name, step.kind, 24, 24, 280, H - 48);

  const done = s.progress?.done ?? 0, total = s.progress?.total ?? 0;
  if (s.state === 'entries') {
    text('Almost done: sex and weight', left, 84, '600 46px system-ui, sans-serif');
    const d = state.entryDraft;
    text(`Sex: ${d.sex ?? '—'}`, left, 170, '40px system-ui, sans-serif');
    text('thumbstick ← → to choose', left + 420, 170, '26px system-ui, sans-serif', '#66717e');
    text(`Weight: ${d.weight === null ? '—' : `${d.weight.toFixed(1)} kg`}`, left, 240, '40px system-ui, sans-serif');
    text('thumbstick ↑ ↓: ±0.5 kg', left + 420, 240, '26px system-ui, sans-serif', '#66717e');
    text('Hold a trigger for 1 s to save, or use the page.', left, 320, '30px system-ui, sans-serif', '#2d6a88');
  } else if (s.state === 'done') {
    text('Done — your avatar is in front of you', left, 84, '600 44px system-ui, sans-serif');
    text('Step into it: exit VR, then Enter mirror on the page', left, 128, '600 28px system-ui, sans-serif', '#2d6a88');
    const ms = s.measurement_set ?? {};
    let y = 180;
    for (const [name, v] of Object.entries(ms)) {
      if (y > H - 110) break;
      text(`${friendly(name)}`, left, y, '30px system-ui, sans-serif', '#66717e');
      text(`${Number(v).toFixed(1)} ${name === 'weight' ? 'kg' : 'cm'}`, left + 360, y, '600 30px system-ui, sans-serif');
      y += 42;
    }
    text(`Open in the desktop tool: /?session=${s.id}`, left, H - 60, '26px system-ui, sans-serif', '#2d6a88');
  } else if (step) {
    text(step.title ?? friendly(step.name), left, 84, '600 50px system-ui, sans-serif');
    ctx.font = '31px system-ui, sans-serif';
    let y = 140;
    for (const l of wrap(ctx, step.instruction ?? '', W - left - 40).slice(0, 4)) {
      text(l, left, y, '31px system-ui, sans-serif', '#38424d');
      y += 42;
    }
    const rep = step.kind === 'floor'
      ? `Point ${Math.min(step.points_done + 1, step.points_needed)} of ${step.points_needed}`
      : `Repetition ${step.repetition} of ${step.repetitions_needed}`;
    text(rep, left, 340, '600 34px system-ui, sans-serif', '#2d6a88');
    const v = s.values?.[step.name];
    if (v?.repetitions_cm?.length)
      text(`so far: ${v.repetitions_cm.map((x) => x.toFixed(1)).join(', ')} cm`, left + 330, 340, '28px system-ui, sans-serif', '#66717e');
  }

  // Progress bar.
  const barX = left, barY = H - 150, barW = W - left - 40;
  ctx.fillStyle = '#e6eaee';
  ctx.fillRect(barX, barY, barW, 16);
  ctx.fillStyle = '#2d6a88';
  ctx.fillRect(barX, barY, total ? (barW * done) / total : 0, 16);
  text(`step ${Math.min(done + 1, total)} of ${total}${s.floor_m !== null && s.floor_m !== undefined ? ` · floor ${(s.floor_m * 100).toFixed(1)} cm` : ''}`,
    barX, barY - 12, '24px system-ui, sans-serif', '#66717e');

  if (state.message) {
    ctx.font = '600 32px system-ui, sans-serif';
    const lines = wrap(ctx, state.message.text, barW).slice(0, 2);
    lines.forEach((l, i) => text(l, left, H - 92 + i * 38, '600 32px system-ui, sans-serif', TONES[state.message.tone]));
  }
  text('A / X: undo   B / Y: redo', W - 330, H - 14, '22px system-ui, sans-serif', '#9aa5b1');
  finishPanel(texts);
}

function finishPanel(texts) {
  state.panelText = texts;
  if (panelTexture) panelTexture.needsUpdate = true;
  requestPreview();
}

// ---------------------------------------------------------------------------------------------
// Scene: floor, panel, controllers with their tips, the avatar at the end.

const renderer = new THREE.WebGLRenderer({ antialias: true });
renderer.setPixelRatio(Math.min(window.devicePixelRatio || 1, 2));
renderer.outputColorSpace = THREE.SRGBColorSpace;
renderer.xr.enabled = true;
renderer.xr.setReferenceSpaceType('local-floor');
$('preview-host').appendChild(renderer.domElement);

const scene = new THREE.Scene();
scene.background = new THREE.Color(0x1d232b);
const camera = new THREE.PerspectiveCamera(70, 4 / 3, 0.02, 50);
camera.position.set(0, 1.6, 0.35);
camera.lookAt(0, 1.05, -1.2);

scene.add(new THREE.HemisphereLight(0xffffff, 0x5a6470, 1.8));
const key = new THREE.DirectionalLight(0xffffff, 1.6);
key.position.set(1, 3, 2);
scene.add(key);
const floorDisc = new THREE.Mesh(new THREE.CircleGeometry(3, 64), new THREE.MeshStandardMaterial({ color: 0x39424d, roughness: 0.9 }));
floorDisc.rotation.x = -Math.PI / 2;
floorDisc.position.y = -0.01;   // under the grid: XR depth ranges are coarse near the floor
scene.add(floorDisc);
const grid = new THREE.GridHelper(6, 30, 0x8793a0, 0x56616d);   // 20 cm cells
grid.position.y = 0.002;
scene.add(grid);

panelTexture = new THREE.CanvasTexture(panelCanvas);
panelTexture.colorSpace = THREE.SRGBColorSpace;
panelTexture.anisotropy = 4;
const panel = new THREE.Mesh(
  new THREE.PlaneGeometry(0.9, (0.9 * panelCanvas.height) / panelCanvas.width),
  new THREE.MeshBasicMaterial({ map: panelTexture, toneMapped: false }));
panel.position.set(-0.25, 1.35, -0.9);
panel.rotation.y = 0.2;
scene.add(panel);

// One visual per hand: the controller's head, a handle from the grip to the tip, and a bright
// sphere at the tip (the point that is measured).
function makeControllerVisual(color) {
  const group = new THREE.Group();
  group.matrixAutoUpdate = false;
  group.visible = false;
  const dark = new THREE.MeshStandardMaterial({ color: 0x2b3138, roughness: 0.6 });
  const head = new THREE.Mesh(new THREE.CylinderGeometry(0.026, 0.02, 0.06, 20), dark);
  head.rotation.x = Math.PI / 2;   // the ring and buttons sit on the grip's −Z side
  head.position.z = -0.04;
  group.add(head);
  const handle = new THREE.Mesh(new THREE.CylinderGeometry(0.013, 0.016, 1, 16),
    new THREE.MeshStandardMaterial({ color: 0x444c56, roughness: 0.5 }));
  group.add(handle);
  const tip = new THREE.Mesh(new THREE.SphereGeometry(0.012, 24, 14),
    new THREE.MeshBasicMaterial({ color, toneMapped: false }));
  group.add(tip);
  scene.add(group);
  return { group, handle, tip, color: new THREE.Color(color), offset: null };
}
const visuals = { left: makeControllerVisual(0x52b4e8), right: makeControllerVisual(0xf3b23c) };

function setTipOffset(v, offset) {
  if (v.offset && v.offset.every((x, i) => x === offset[i])) return;
  v.offset = offset;
  const to = new THREE.Vector3(...offset);
  v.tip.position.copy(to);
  // The handle: a unit cylinder along Y, stretched from the grip to just short of the tip.
  const len = Math.max(to.length() - 0.008, 0.001);
  v.handle.scale.set(1, len, 1);
  v.handle.position.copy(to).multiplyScalar(0.5 * len / Math.max(to.length(), 1e-6));
  if (to.lengthSq() > 1e-12) v.handle.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), to.clone().normalize());
  v.handle.visible = to.lengthSq() > 1e-6;
}

// Preview (2-D page): render on demand.
let previewQueued = false;
function requestPreview() {
  if (state.inXR || previewQueued) return;
  previewQueued = true;
  requestAnimationFrame(() => {
    previewQueued = false;
    if (!state.inXR) renderer.render(scene, camera);
  });
}
function resizePreview() {
  const host = $('preview-host');
  const w = host.clientWidth || 320;
  const h = Math.round(w * 0.75);
  if (!renderer.xr.isPresenting) renderer.setSize(w, h, false);
  camera.aspect = w / h;
  camera.updateProjectionMatrix();
  requestPreview();
}
new ResizeObserver(resizePreview).observe($('preview-host'));

// ---------------------------------------------------------------------------------------------
// Controllers: per-frame polling of the grip pose and button 0 (the trigger). Never the `select`
// event: emulators fire it at press, headsets at release (see docs/capture-page.md).

const SEND_INTERVAL_MS = 100;
const MAX_QUEUE = 6000;           // about 30 s of two controllers at 90 Hz while the server is away
let queue = [];
let sending = false;
let lastSend = 0;
let placed = false;               // panel placed in front of the user for this XR session
const buttonsDown = new Map();    // "hand:index" → pressed last frame
const holdStart = { left: null, right: null };
let stickRepeat = 0;
let entryHold = null;

function profileFor(source) {
  return source.profiles.find((p) => p in state.profiles) ?? state.defaultProfile;
}

function measuring() {
  const st = state.session?.state;
  return st === 'floor' || st === 'measuring';
}

function edge(hand, index, pressed) {
  const k = `${hand}:${index}`;
  const was = buttonsDown.get(k) ?? false;
  buttonsDown.set(k, pressed);
  return pressed && !was;
}

function onXRFrame(time, frame) {
  if (!frame) return;
  state.xrFrames = (state.xrFrames ?? 0) + 1;
  state.xrTime = time;
  state.xrStart ??= time;
  const ref = renderer.xr.getReferenceSpace();
  const xrSession = frame.session;
  const now = performance.now();
  const viewer = frame.getViewerPose(ref);
  if (!placed && viewer) { placeInFront(viewer.transform); placed = true; }

  const seen = new Set();
  for (const source of xrSession.inputSources) {
    const hand = source.handedness;
    if ((hand !== 'left' && hand !== 'right') || !source.gripSpace || !source.gamepad) continue;
    const pose = frame.getPose(source.gripSpace, ref);
    const v = visuals[hand];
    if (!pose) { v.group.visible = false; continue; }
    seen.add(hand);
    const profile = profileFor(source);
    setTipOffset(v, state.profiles[profile]?.tip_offset_m ?? [0, 0, 0]);
    v.group.matrix.fromArray(pose.transform.matrix);
    v.group.visible = true;
    const buttons = source.gamepad.buttons;
    const trigger = buttons[0]?.value ?? 0;
    const p = pose.transform.position, o = pose.transform.orientation;
    if (measuring()) {
      queue.push({ t: time / 1000, hand, position: [p.x, p.y, p.z], orientation: [o.x, o.y, o.z, o.w], trigger, _profile: profile });
      if (queue.length > MAX_QUEUE) queue.splice(0, queue.length - MAX_QUEUE);
    }
    // Hold feedback at the tip: grows and warms up over the second the engine needs.
    if (trigger > 0.5) holdStart[hand] ??= now; else holdStart[hand] = null;
    const held = holdStart[hand] === null ? 0 : Math.min(1, (now - holdStart[hand]) / 1000);
    const flashing = now < state.flashUntil;
    v.tip.scale.setScalar(1 + held * 0.8 + (flashing ? 1.2 : 0));
    v.tip.material.color.copy(flashing ? new THREE.Color(TONES[state.flashTone]) : held > 0
      ? v.color.clone().lerp(new THREE.Color(0xffffff), held) : v.color);

    // Undo / redo: A or X (button 4), B or Y (button 5); controllers without them (Vive) use the
    // touchpad press (button 2), left half undo, right half redo.
    if (edge(hand, 4, !!buttons[4]?.pressed)) undo();
    if (edge(hand, 5, !!buttons[5]?.pressed)) redo();
    if (!buttons[4] && edge(hand, 2, !!buttons[2]?.pressed)) {
      const x = source.gamepad.axes[0] ?? 0;
      if (x < -0.3) undo(); else if (x > 0.3) redo();
    }
    if (state.session?.state === 'entries') vrEntries(hand, source.gamepad, trigger, now);
  }
  for (const hand of ['left', 'right']) if (!seen.has(hand)) visuals[hand].group.visible = false;
  if (!seen.size) entryHold = null;

  if (queue.length && !sending && now - lastSend >= SEND_INTERVAL_MS) sendSamples();
  if (state.flashUntil && now > state.flashUntil + 50) { state.flashUntil = 0; drawPanel(); }
}

function placeInFront(transform) {
  // The panel ~1 m ahead of where the user looks when entering VR, a little left and below eye
  // height, turned to face them.
  const head = new THREE.Vector3(transform.position.x, transform.position.y, transform.position.z);
  const q = new THREE.Quaternion(transform.orientation.x, transform.orientation.y, transform.orientation.z, transform.orientation.w);
  const fwd = new THREE.Vector3(0, 0, -1).applyQuaternion(q);
  fwd.y = 0;
  if (fwd.lengthSq() < 1e-6) fwd.set(0, 0, -1);
  fwd.normalize();
  state.userFrame = { head, fwd };
  placePanel();
  if (state.avatar) placeAvatar();
}

// While measuring the panel is ahead, a little left; at the end it moves aside for the mirror.
function placePanel() {
  const u = state.userFrame ?? { head: new THREE.Vector3(0, 1.6, 0), fwd: new THREE.Vector3(0, 0, -1) };
  const leftDir = new THREE.Vector3(u.fwd.z, 0, -u.fwd.x);
  const aside = state.session?.state === 'done';
  panel.position.copy(u.head).addScaledVector(u.fwd, aside ? 1.2 : 0.9).addScaledVector(leftDir, aside ? 0.75 : 0.3);
  panel.position.y = Math.max(0.9, u.head.y - (aside ? 0.1 : 0.25));
  panel.lookAt(u.head);   // facing the eyes, tilted back a little
  requestPreview();
}

async function sendSamples() {
  const profile = queue[0]._profile;
  // One request per profile (both hands share one in practice).
  const batch = [];
  const rest = [];
  for (const s of queue) (s._profile === profile ? batch : rest).push(s);
  queue = rest;
  sending = true;
  lastSend = performance.now();
  const samples = batch.map(({ _profile, ...s }) => s);
  try {
    const res = await api(`/api/sessions/${state.session.id}/samples`, { method: 'POST', body: { profile, samples }, write: true });
    state.samplesSent += samples.length;
    state.batchesSent += 1;
    applySession(res.session, res.events ?? []);
    clearError();
  } catch (e) {
    if (e.status === 0) {
      queue = batch.concat(queue);          // keep them: the server may come back
      setStatus(e.message, true);
    } else {
      showError(e);
    }
  } finally {
    sending = false;
  }
}

// Sex and weight in the headset: thumbstick left/right picks the sex, up/down changes the weight
// by 0.5 kg (repeating while held), a trigger held for a second saves.
function vrEntries(hand, gamepad, trigger, now) {
  const axes = gamepad.axes;
  const x = axes.length >= 4 ? axes[2] : axes[0] ?? 0;
  const y = axes.length >= 4 ? axes[3] : axes[1] ?? 0;
  const d = state.entryDraft;
  if (edge(hand, 'x+', x > 0.6) || edge(hand, 'x-', x < -0.6)) {
    d.sex = d.sex === 'female' ? 'male' : 'female';
    drawPanel();
  }
  if (Math.abs(y) > 0.6 && now >= stickRepeat) {
    const { min, max } = state.weightRange;
    d.weight = Math.min(max, Math.max(min, (d.weight ?? 70) + (y < 0 ? 0.5 : -0.5)));   // stick up is −y
    stickRepeat = now + 180;
    drawPanel();
  }
  if (trigger > 0.5) {
    entryHold ??= { hand, start: now };
    if (entryHold.hand === hand && now - entryHold.start >= 1000 && !entryHold.sent) {
      entryHold.sent = true;
      if (d.sex && d.weight !== null) saveEntries({ sex: d.sex, weight_kg: d.weight });
      else setMessage('Choose the sex and the weight first', 'bad');
    }
  } else if (entryHold?.hand === hand) {
    entryHold = null;
  }
}

// ---------------------------------------------------------------------------------------------
// Session

function applySession(session, events = []) {
  const before = state.session;
  state.session = session;
  if (before?.id !== session.id) {
    state.entryDraft = { sex: session.sex ?? null, weight: session.weight_kg ?? null };
  } else {
    state.entryDraft.sex = state.entryDraft.sex ?? session.sex ?? null;
    if (session.weight_kg !== null && session.weight_kg !== undefined && state.entryDraft.weight === null) state.entryDraft.weight = session.weight_kg;
  }
  for (const ev of events) {
    state.events.push(ev);
    const what = friendly(ev.step ?? '');
    if (ev.type === 'point_accepted') {
      sounds.accepted();
      flash('ok');
      setMessage(ev.value_cm !== undefined && ev.value_cm !== null ? `✓ ${what}: ${ev.value_cm.toFixed(1)} cm` : `✓ point recorded`, 'ok');
    } else if (ev.type === 'point_rejected') {
      sounds.rejected();
      flash('bad');
      setMessage(`✗ ${ev.reason ?? 'point rejected'}`, 'bad');
    } else if (ev.type === 'step_done') {
      sounds.stepDone();
      setMessage(ev.value_cm !== undefined && ev.value_cm !== null ? `${what} done: ${ev.value_cm.toFixed(1)} cm` : `${what} done`, 'ok');
    } else if (ev.type === 'session_done') {
      sounds.done();
    }
  }
  renderSession();
  if (!measuring()) queue = [];
}

function renderSession() {
  const s = state.session;
  $('session-card').hidden = !s;
  if (!s) return;
  $('session-id').textContent = s.id;
  $('enter-vr').disabled = !state.xrSupported;
  $('pairing-code').textContent = state.code ?? '······';
  $('progress-text').textContent = `${s.state}${s.progress ? ` · ${s.progress.done} of ${s.progress.total} steps` : ''}`;
  const tbody = $('values').querySelector('tbody');
  tbody.textContent = '';
  for (const [name, v] of Object.entries(s.values ?? {})) {
    const tr = document.createElement('tr');
    tr.dataset.name = name;
    tr.innerHTML = `<td>${friendly(name)}</td><td>${v.value_cm === null || v.value_cm === undefined ? '—' : `${v.value_cm.toFixed(1)} cm`}</td>
      <td>${(v.repetitions_cm ?? []).map((x) => x.toFixed(1)).join(', ')}</td>`;
    tbody.appendChild(tr);
  }
  for (const [label, value] of [['Sex', s.sex], ['Weight', s.weight_kg === null || s.weight_kg === undefined ? null : `${s.weight_kg.toFixed(1)} kg`]]) {
    const tr = document.createElement('tr');
    tr.innerHTML = `<td>${label}</td><td>${value ?? '—'}</td><td></td>`;
    tbody.appendChild(tr);
  }
  if (document.activeElement !== $('sex') && s.sex) $('sex').value = s.sex;
  if (document.activeElement !== $('weight') && s.weight_kg !== null && s.weight_kg !== undefined) $('weight').value = s.weight_kg;
  const finished = s.state === 'done';
  // The result links only when there is something to take away.
  const measured = Object.values(s.values ?? {}).some((v) => v.value_cm !== null && v.value_cm !== undefined);
  $('result-links').hidden = !(finished && measured);
  drawHeadsetQr();
  $('open-desktop').href = `/?session=${encodeURIComponent(s.id)}`;
  $('open-mirror').href = `/mirror.html?session=${encodeURIComponent(s.id)}`;
  $('export-json').href = `/api/sessions/${encodeURIComponent(s.id)}/export?format=json`;
  $('export-csv').href = `/api/sessions/${encodeURIComponent(s.id)}/export?format=csv`;
  document.body.dataset.state = s.state;
  drawPanel();
  placePanel();
  avatarGroup.visible = finished;   // an undo after the end takes the mirror away again
  if (finished) buildAvatar().catch(showError);
}

async function undo() {
  if (!state.session) return;
  try {
    const res = await api(`/api/sessions/${state.session.id}/undo`, { method: 'POST', body: {}, write: true });
    queue = [];
    applySession(res.session);
    setMessage('Undone: the last point or step is taken back', 'info');
  } catch (e) { showError(e); }
}

async function redo() {
  if (!state.session) return;
  try {
    const res = await api(`/api/sessions/${state.session.id}/redo`, { method: 'POST', body: {}, write: true });
    queue = [];
    applySession(res.session);
    setMessage('Redone', 'info');
  } catch (e) { showError(e); }
}

async function saveEntries(body) {
  try {
    const res = await api(`/api/sessions/${state.session.id}/entries`, { method: 'POST', body, write: true });
    applySession(res.session);
    clearError();
    setMessage(res.session.state === 'done' ? 'Saved. Building your avatar…' : 'Saved', 'ok');
  } catch (e) { showError(e); }
}

function rememberSession(id, code) {
  state.code = code;
  try { sessionStorage.setItem(`caliper-pairing-${id}`, code); } catch { /* private mode */ }
  const url = new URL(location.href);
  url.searchParams.set('session', id);
  history.replaceState(null, '', url);
}

async function createSession() {
  clearError();
  const body = {
    mode: document.querySelector('input[name=mode]:checked').value,
    steps: $('steps').value,
  };
  if ($('new-sex').value) body.sex = $('new-sex').value;
  if ($('new-weight').value !== '') body.weight_kg = Number($('new-weight').value);
  if (state.defaultProfile) body.profile = state.defaultProfile;
  try {
    const res = await api('/api/sessions', { method: 'POST', body });
    rememberSession(res.session.id, res.pairing_code);
    applySession(res.session);
    $('pairing-hint').textContent = 'type it on the headset (Join a session) to measure into this session';
    setStatus(`session ${res.session.id} created`);
    refreshList();
  } catch (e) { showError(e); }
}

// The experimenter's desktop issues a new code (a session locked by wrong codes, or a code seen by
// someone it should not have been): the old code stops working, paired devices must join again.
async function newCode() {
  const s = state.session;
  if (!s) return;
  clearError();
  try {
    const res = await api(`/api/sessions/${encodeURIComponent(s.id)}/pairing`, { method: 'POST', body: {} });
    rememberSession(res.session.id, res.pairing_code);
    applySession(res.session);
    $('pairing-hint').textContent = 'new code: type it on the headset (Join a session); the old one no longer works';
    setStatus(`new pairing code for ${s.id}`);
  } catch (e) { showError(e); }
}

// Export links: a plain link carries no header, and a headset needs the code to read the session.
async function download(e) {
  e.preventDefault();
  const a = e.currentTarget;
  try {
    const res = await api(a.href, { raw: true });
    const url = URL.createObjectURL(await res.blob());
    const tmp = document.createElement('a');
    tmp.href = url;
    tmp.download = (res.headers.get('Content-Disposition') ?? '').match(/filename="([^"]+)"/)?.[1] ?? 'caliper-measurements';
    document.body.appendChild(tmp);
    tmp.click();
    tmp.remove();
    setTimeout(() => URL.revokeObjectURL(url), 10000);
  } catch (err) { showError(err); }
}

async function joinSession(id, code) {
  clearError();
  if (!id) { showError(new ApiError(400, { message: 'pick a session to join' })); return false; }
  if (!/^\d{6}$/.test(code)) { showError(new ApiError(400, { message: 'the pairing code has six digits' })); return false; }
  try {
    state.code = code;  // reading the session from a headset already needs it
    const { session } = await api(`/api/sessions/${encodeURIComponent(id)}`);
    // Check the code with a harmless write too: an empty batch of samples.
    try {
      await api(`/api/sessions/${encodeURIComponent(id)}/samples`, { method: 'POST', body: { profile: state.defaultProfile, samples: [] }, write: true });
    } catch (e) {
      if (e.status === 403 || e.status === 423 || e.status === 429) throw e;  // others are about the empty batch, not the code
    }
    rememberSession(id, code);
    applySession(session);
    $('pairing-hint').textContent = 'this device is paired with the session';
    setStatus(`joined session ${id}`);
    return true;
  } catch (e) {
    state.code = null;
    showError(e);
    return false;
  }
}

async function refreshList(select) {
  try {
    const { sessions } = await api('/api/sessions');
    const sel = $('join-session');
    const keep = select ?? sel.value;
    sel.textContent = '';
    sel.appendChild(new Option('—', ''));
    for (const s of sessions) {
      const when = (s.created ?? '').replace('T', ' ').replace(/:\d\dZ$/, ' UTC');
      sel.appendChild(new Option(`${s.id} · ${s.mode} · ${s.state} · ${when}`, s.id));
    }
    if ([...sel.options].some((o) => o.value === keep)) sel.value = keep;
  } catch (e) { showError(e); }
}

// When nothing streams (2-D page, or the other device measures), poll the session.
let lastPoll = 0;
setInterval(async () => {
  const s = state.session;
  if (!s || sending || performance.now() - lastSend < 1000 || performance.now() - lastPoll < 1000) return;
  lastPoll = performance.now();
  try {
    const res = await api(`/api/sessions/${encodeURIComponent(s.id)}`);
    if (JSON.stringify(res.session) !== JSON.stringify(state.session)) applySession(res.session);
  } catch { /* shown on the next write */ }
}, 500);

// ---------------------------------------------------------------------------------------------
// The avatar at the end: built as the desktop tool builds it (POST /api/avatar, faces from
// /api/topology), standing 1.5 m in front of the user, facing them, like a mirror.

const avatarMaterial = new THREE.MeshStandardMaterial({ color: 0xcdbba8, roughness: 0.62 });
const avatarGroup = new THREE.Group();
scene.add(avatarGroup);

async function buildAvatar() {
  const s = state.session;
  const set = { ...(s.measurement_set ?? {}) };
  const key = JSON.stringify([s.sex, set]);
  if (state.avatarKey === key) return;
  state.avatarKey = key;
  if (!state.catalogue) {
    const { measurements } = await api('/api/measurements');
    state.catalogue = new Set(measurements.map((m) => m.name));
  }
  const measurements = Object.fromEntries(Object.entries(set).filter(([n]) => state.catalogue.has(n)));
  const sex = s.sex ?? 'female';
  const [res, topo] = await Promise.all([
    // The noise-aware estimator: it weighs each captured value by how well people measure it
    // (self or other measurer, paper Table 2) and keeps the body plausible if one value is off.
    api('/api/avatar', { method: 'POST', body: { sex, regressor: 'auto', noise: s.mode === 'other' ? 'other' : 'self', measurements } }),
    api(`/api/topology?sex=${encodeURIComponent(sex)}`),
  ]);
  if (state.avatarKey !== key) return;      // a newer set arrived meanwhile
  const positions = decodeBase64(res.mesh.positions, Float32Array);
  const faces = decodeBase64(topo.faces, Uint32Array);
  const g = new THREE.BufferGeometry();
  g.setIndex(new THREE.BufferAttribute(faces, 1));
  g.setAttribute('position', new THREE.BufferAttribute(positions, 3));
  setVertexNormals(g);
  for (const c of [...avatarGroup.children]) { avatarGroup.remove(c); c.geometry.dispose(); }
  avatarGroup.add(new THREE.Mesh(g, avatarMaterial));
  state.avatar = { report: res.report, regressor: res.report.regressor };
  placeAvatar();
  setMessage(`Your avatar (${res.report.regressor}) stands in front of you`, 'ok');
}

function placeAvatar() {
  // The body faces +Z; turn it to face the user, 1.5 m ahead of where they looked.
  const u = state.userFrame ?? { head: new THREE.Vector3(0, 1.6, 0), fwd: new THREE.Vector3(0, 0, -1) };
  avatarGroup.position.set(u.head.x + 1.5 * u.fwd.x, 0, u.head.z + 1.5 * u.fwd.z);
  avatarGroup.rotation.y = Math.atan2(-u.fwd.x, -u.fwd.z);
  if (!state.inXR) {
    camera.position.set(u.head.x - 0.2 * u.fwd.x, 1.45, u.head.z - 0.2 * u.fwd.z + 0.6);
    camera.lookAt(avatarGroup.position.x, 1.0, avatarGroup.position.z);
  }
  requestPreview();
}

// ---------------------------------------------------------------------------------------------
// Entering VR

async function enterVR() {
  unlockAudio();
  if (!navigator.xr) return;
  try {
    const xrSession = await navigator.xr.requestSession('immersive-vr', { requiredFeatures: ['local-floor'] });
    placed = false;
    buttonsDown.clear();
    await renderer.xr.setSession(xrSession);
    state.inXR = true;
    document.body.dataset.xr = 'on';
    xrSession.addEventListener('end', () => {
      state.inXR = false;
      document.body.dataset.xr = 'off';
      renderer.setAnimationLoop(null);
      resizePreview();
    });
    renderer.setAnimationLoop((time, frame) => {
      const t0 = performance.now();
      onXRFrame(time, frame);
      renderer.render(scene, camera);
      state.frameMs = (state.frameMs ?? 0) * 0.9 + (performance.now() - t0) * 0.1;   // shown in the status line
    });
  } catch (e) {
    showError(new ApiError(0, { message: `could not enter VR: ${e.message}` }));
  }
}

async function checkXR() {
  const button = $('enter-vr');
  let ok = false;
  try { ok = !!navigator.xr && await navigator.xr.isSessionSupported('immersive-vr'); } catch { ok = false; }
  state.xrSupported = ok;
  button.disabled = !ok || !state.session;
  $('xr-hint').textContent = ok
    ? 'Put the headset on, then Enter VR. Hold each point for a second with the trigger.'
    : 'No WebXR headset here: open this page in the headset\'s browser (HTTPS or adb reverse, see docs/capture-page.md). You can still create the session here and type its code there.';
}

// The weight fields accept what the server accepts: the catalogue's range, not a copy of it.
async function useWeightRange() {
  const { measurements } = await api('/api/measurements');
  const r = measurements.find((m) => m.name === 'weight')?.accepted_range;
  if (!r) return;
  state.weightRange = { min: r.min, max: r.max };
  for (const id of ['new-weight', 'weight']) { $(id).min = String(r.min); $(id).max = String(r.max); }
}

// The address for the headset's browser, as a QR code to scan and as text to type: the server's
// (its LAN address when it listens on all interfaces; else this page's own), with the session, so
// the headset lands on that session's Join form.
function headsetUrl() {
  const url = new URL(state.headset?.urls?.[0] ?? new URL('/capture.html', location.href).href);
  if (state.session) url.searchParams.set('session', state.session.id);
  return url.href;
}

function drawHeadsetQr() {
  const href = headsetUrl();
  if (href === state.headsetUrl) return;
  state.headsetUrl = href;
  const qr = qrcode(0, 'M');
  qr.addData(href);
  qr.make();
  const modules = qr.getModuleCount(), quiet = 4, scale = 6;
  const canvas = $('headset-qr');
  canvas.width = canvas.height = (modules + 2 * quiet) * scale;
  const ctx = canvas.getContext('2d');
  ctx.fillStyle = '#fff';
  ctx.fillRect(0, 0, canvas.width, canvas.height);
  ctx.fillStyle = '#000';
  for (let r = 0; r < modules; ++r)
    for (let c = 0; c < modules; ++c) if (qr.isDark(r, c)) ctx.fillRect((c + quiet) * scale, (r + quiet) * scale, scale, scale);
  canvas.setAttribute('aria-label', `QR code of ${href}`);
  $('headset-url').textContent = href;
  $('headset-url').href = href;
  const others = (state.headset?.urls ?? []).slice(1);
  const port = new URL(href).port || (href.startsWith('https') ? '443' : '80');
  $('headset-hint').textContent = state.headset && !state.headset.other_devices
    ? `This server listens on this computer only: a headset reaches it over USB (adb reverse tcp:${port} tcp:${port}). For the network, start caliper serve --https --host 0.0.0.0; the code then holds the computer's LAN address.`
    : `Scan it with the headset (or type the address in its browser), accept the certificate warning once, then join with the pairing code.${others.length ? ` Other addresses of this computer: ${others.join(', ')}.` : ''}`;
}

// ---------------------------------------------------------------------------------------------
// Start

async function start() {
  drawPanel();
  $('panel-host').appendChild(panelCanvas);
  $('create').addEventListener('click', createSession);
  $('join').addEventListener('click', () => joinSession($('join-session').value, $('join-code').value.trim()));
  $('refresh').addEventListener('click', () => refreshList());
  $('enter-vr').addEventListener('click', enterVR);
  $('undo').addEventListener('click', undo);
  $('redo').addEventListener('click', redo);
  $('new-code').addEventListener('click', newCode);
  $('export-json').addEventListener('click', download);
  $('export-csv').addEventListener('click', download);
  $('save-entries').addEventListener('click', () => {
    const body = {};
    if ($('sex').value) body.sex = $('sex').value;
    if ($('weight').value !== '') body.weight_kg = Number($('weight').value);
    saveEntries(body);
  });

  await useWeightRange();
  state.headset = await api('/api/capture/headset');
  drawHeadsetQr();
  const prof = await api('/api/capture/profiles');
  state.profiles = prof.profiles;
  state.defaultProfile = prof.default;
  await checkXR();
  navigator.xr?.addEventListener?.('devicechange', checkXR);

  const wanted = new URLSearchParams(location.search).get('session');
  await refreshList(wanted ?? undefined);
  if (wanted) {
    let code = null;
    try { code = sessionStorage.getItem(`caliper-pairing-${wanted}`); } catch { /* private mode */ }
    if (code) await joinSession(wanted, code);
  }
  setStatus(state.session ? `session ${state.session.id}` : 'ready');
  state.ready = true;
}

start().catch((e) => { showError(e); setStatus(e.message, true); });
