// Caliper desktop tool (paper §4.3, §5): set measurements hierarchically, see the avatar update
// live, check the shape's plausibility and the measurements, export. Everything goes through the
// documented JSON API (docs/api.md); three.js is served locally (see build.mjs).
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/OrbitControls.js';
import { ApiError, api, decodeBase64, setVertexNormals } from './shared.js';

// ---------------------------------------------------------------------------------------------
// API


// ---------------------------------------------------------------------------------------------
// Names shown to people: the paper's words for its inputs, the catalogue's for the rest.

const FRIENDLY = {
  stature: 'Height', weight: 'Weight', span: 'Arm span', crotch_height: 'Inseam',
  hip_breadth: 'Hip width', arm_length: 'Arm length', biacromial_breadth: 'Shoulder width',
};
const LEVEL_TITLES = { 1: 'Height and weight', 2: 'Arm span and inseam', 3: 'Hip width and arm length' };
const friendly = (name) => FRIENDLY[name] ?? name.replaceAll('_', ' ').replace(/^./, (c) => c.toUpperCase());

// ---------------------------------------------------------------------------------------------
// State

const state = {
  catalogue: [],            // GET /api/measurements
  info: new Map(),          // name → catalogue entry
  regressors: [],           // GET /api/models
  sex: 'female',
  model: 'mannequin',
  regressor: 'auto',
  noise: 'exact',           // for auto: who measured (exact | self | other)
  vertexSd: null,           // Float32Array of per-vertex SD (m) from "map", else null
  values: {},               // input name → cm / kg, only for values the user gave
  given: new Set(),         // the inputs the user set (typed, slid, imported, from a session): only these are sent
  extra: {},                // other imported measurements (e.g. a taped chest circumference), sent as requested
  predicted: {},            // input name → the avatar's value (cm / kg), shown for values not given
  fieldErrors: new Map(),   // input name → what is wrong with the text typed there (not sent)
  doubted: new Set(),       // inputs the server questioned as probably mistyped, until answered
  units: 'metric',          // metric (cm, kg) | imperial (in, lb): display only, the API gets cm and kg
  participant: '',          // carried into exported file names
  pose: 't',                // the viewer's pose: t (rest), a, stride; exports stay in the rest pose
  compare: null,            // { positions, faces, label } of a kept avatar, shown beside or over this one
  averageBody: false,       // nothing given: the page shows the population's average body
  blocked: false,           // a session link that failed: nothing is built until the user decides
  topology: new Map(),      // "model/sex" → { faces: Uint32Array, vertexCount }
  last: null,               // last /api/avatar response
  updates: 0,
  requests: [],             // bodies of the last /api/avatar requests (for the end-to-end test)
  lastRoundTripMs: null,
};
window.caliper = state;     // for the end-to-end test and the curious

const $ = (id) => document.getElementById(id);

// Display units. Values are kept and sent in the catalogue's units (cm, kg); only what is shown
// and typed is converted.
const DISPLAY_UNITS = {
  metric: { cm: { unit: 'cm', factor: 1 }, kg: { unit: 'kg', factor: 1 } },
  imperial: { cm: { unit: 'in', factor: 1 / 2.54 }, kg: { unit: 'lb', factor: 1 / 0.45359237 } },
};
const baseUnit = (name) => state.info.get(name)?.unit ?? 'cm';
const displayUnit = (name) => DISPLAY_UNITS[state.units][baseUnit(name)] ?? { unit: baseUnit(name), factor: 1 };
const toDisplay = (name, v) => v * displayUnit(name).factor;
const fromDisplay = (name, v) => v / displayUnit(name).factor;
const shown = (name, v, digits = 1) => (v === null || v === undefined ? '—' : toDisplay(name, v).toFixed(digits));

// ---------------------------------------------------------------------------------------------
// Viewer: orbit controls, floor grid (10 cm cells), height ruler in cm, camera presets.

const SIDE_OFFSET = 2.0;  // metres between two bodies side by side
const viewer = (() => {
  const host = $('canvas-host');
  const renderer = new THREE.WebGLRenderer({ antialias: true, alpha: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(Math.min(window.devicePixelRatio || 1, 2));
  renderer.outputColorSpace = THREE.SRGBColorSpace;
  host.appendChild(renderer.domElement);

  const scene = new THREE.Scene();
  const camera = new THREE.PerspectiveCamera(30, 1, 0.05, 50);
  const controls = new OrbitControls(camera, renderer.domElement);
  controls.minDistance = 0.6;
  controls.maxDistance = 12;
  controls.maxPolarAngle = Math.PI * 0.58;
  controls.zoomToCursor = true;  // the wheel zooms toward what is under the pointer (a face, a hand)

  scene.add(new THREE.HemisphereLight(0xffffff, 0x9aa3ad, 1.9));
  const key = new THREE.DirectionalLight(0xffffff, 1.7);
  key.position.set(-1.5, 3, 3);
  scene.add(key);
  const rim = new THREE.DirectionalLight(0xdfe8ff, 0.9);
  rim.position.set(2, 2.5, -3);
  scene.add(rim);

  // Floor grid: 4 m square, 10 cm cells, stronger lines every 50 cm.
  const fine = new THREE.GridHelper(4, 40, 0xc9ced5, 0xdde1e6);
  const coarse = new THREE.GridHelper(4, 8, 0xaeb5be, 0xaeb5be);
  coarse.position.y = 0.0005;
  scene.add(fine, coarse);

  function label(text, color = '#4b5563', height = 0.045) {
    const canvas = document.createElement('canvas');
    const ctx = canvas.getContext('2d');
    const px = 64;
    ctx.font = `500 ${px}px system-ui, sans-serif`;
    canvas.width = Math.ceil(ctx.measureText(text).width) + 16;
    canvas.height = px + 16;
    ctx.font = `500 ${px}px system-ui, sans-serif`;
    ctx.fillStyle = color;
    ctx.textBaseline = 'middle';
    ctx.fillText(text, 8, canvas.height / 2);
    const tex = new THREE.CanvasTexture(canvas);
    tex.colorSpace = THREE.SRGBColorSpace;
    const sprite = new THREE.Sprite(new THREE.SpriteMaterial({ map: tex, depthTest: false, transparent: true }));
    sprite.scale.set((height * canvas.width) / canvas.height, height, 1);
    sprite.renderOrder = 2;
    return sprite;
  }

  // Height ruler beside the body (to its right and a little behind, so front and side views show
  // it): ticks every 5 cm, labels every 20 cm, up to a little above the head.
  const ruler = new THREE.Group();
  const rulerX = -1.0, rulerZ = -0.3;
  ruler.position.set(rulerX, 0, rulerZ);
  scene.add(ruler);
  const scale = new THREE.Group();
  ruler.add(scale);
  let rulerTopCm = 0;
  function buildRuler(topCm) {
    if (topCm === rulerTopCm) return;
    rulerTopCm = topCm;
    for (const c of [...scale.children]) {
      scale.remove(c);
      c.geometry?.dispose();
      c.material?.map?.dispose();
      c.material?.dispose();
    }
    const pts = [0, 0, 0, 0, topCm / 100, 0];
    for (let cm = 0; cm <= topCm; cm += 5) {
      const w = cm % 10 === 0 ? 0.05 : 0.025;
      pts.push(0, cm / 100, 0, w, cm / 100, 0);
      if (cm % 20 === 0) {
        const s = label(String(cm));
        s.center.set(0, 0.5);
        s.position.set(0.065, cm / 100, 0);
        scale.add(s);
      }
    }
    const geom = new THREE.BufferGeometry();
    geom.setAttribute('position', new THREE.Float32BufferAttribute(pts, 3));
    scale.add(new THREE.LineSegments(geom, new THREE.LineBasicMaterial({ color: 0x6b7480 })));
    const unit = label('cm', '#6b7480', 0.04);
    unit.center.set(0.5, 0);
    unit.position.set(0, topCm / 100 + 0.03, 0);
    scale.add(unit);
  }
  buildRuler(200);

  // The stature marker: a line from the ruler to the top of the head, with the value.
  const markerGeom = new THREE.BufferGeometry();
  markerGeom.setAttribute('position', new THREE.Float32BufferAttribute([rulerX, 0, rulerZ, 0, 0, 0], 3));
  const marker = new THREE.Line(markerGeom, new THREE.LineDashedMaterial({ color: 0x2d6a88, dashSize: 0.03, gapSize: 0.02 }));
  scene.add(marker);
  let markerLabel = null;

  const material = new THREE.MeshStandardMaterial({ color: 0xcdbba8, roughness: 0.62, metalness: 0.0 });
  let mesh = null;
  let height = 1.7;
  let view = 'front';

  function render() {
    renderer.render(scene, camera);
    viewer.renders += 1;
  }
  controls.addEventListener('change', render);

  function resize() {
    const w = host.clientWidth, h = host.clientHeight;
    if (!w || !h) return;
    renderer.setSize(w, h, false);
    camera.aspect = w / h;
    camera.updateProjectionMatrix();
    render();
  }
  new ResizeObserver(resize).observe(host);

  function setView(name) {
    view = name;
    // Aim between the floor and the ruler's top; fit that height plus room for the preset bar.
    // Side by side, the kept body stands SIDE_OFFSET to the right: frame both.
    const side = viewer.compareMode === 'side' && viewer.ghost;
    const target = new THREE.Vector3(side ? SIDE_OFFSET / 2 - 0.1 : 0, (height + 0.2) * 0.5, 0);
    const fitH = (height + 0.5) / 2 / Math.tan(THREE.MathUtils.degToRad(camera.fov / 2));
    const fitW = (side ? 2.3 + SIDE_OFFSET : 2.3) / 2 / Math.tan(THREE.MathUtils.degToRad(camera.fov / 2)) / Math.max(camera.aspect, 0.3);
    const d = Math.max(fitH, fitW);
    const dir = { front: [0, 0, 1], back: [0, 0, -1], side: [1, 0, 0], 'three-quarter': [0.72, 0, 0.7] }[name] ?? [0, 0, 1];
    camera.position.set(target.x + dir[0] * d, target.y + 0.12 * d, target.z + dir[2] * d);
    controls.target.copy(target);
    controls.update();
    render();
  }

  function setBody(positions, faces, stature) {
    if (!mesh || mesh.geometry.index.count !== faces.length || mesh.userData.faces !== faces) {
      if (mesh) { scene.remove(mesh); mesh.geometry.dispose(); }
      const g = new THREE.BufferGeometry();
      g.setIndex(new THREE.BufferAttribute(faces, 1));
      g.setAttribute('position', new THREE.BufferAttribute(positions, 3));
      mesh = new THREE.Mesh(g, material);
      mesh.userData.faces = faces;
      scene.add(mesh);
    } else {
      mesh.geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
    }
    setVertexNormals(mesh.geometry);
    mesh.geometry.computeBoundingSphere();
    const first = !viewer.hasBody;
    height = stature;
    buildRuler(Math.max(180, Math.ceil((stature * 100 + 12) / 20) * 20));
    viewer.hasBody = true;
    const p = markerGeom.attributes.position;
    p.setXYZ(0, rulerX, stature, rulerZ);
    p.setXYZ(1, 0, stature, 0);
    p.needsUpdate = true;
    marker.computeLineDistances();
    if (markerLabel) { ruler.remove(markerLabel); markerLabel.material.map.dispose(); }
    markerLabel = label(`${(stature * 100).toFixed(1)} cm`, '#2d6a88', 0.05);
    markerLabel.center.set(0.5, 0);
    markerLabel.position.set(0.45, stature + 0.012, 0);
    ruler.add(markerLabel);
    if (first) setView(view);
    render();
  }

  // Heat map of a per-vertex value (the map estimator's SD): blue = certain, red = the most
  // uncertain at `maxValue`; null restores the plain skin colour.
  function setHeat(values, maxValue) {
    if (!mesh) return;
    if (!values) {
      mesh.geometry.deleteAttribute('color');
      if (material.vertexColors) { material.vertexColors = false; material.color.set(0xcdbba8); material.needsUpdate = true; }
    } else {
      const colors = new Float32Array(values.length * 3);
      const c = new THREE.Color();
      for (let i = 0; i < values.length; ++i) {
        const t = Math.max(0, Math.min(1, values[i] / maxValue));
        c.setHSL((1 - t) * 0.66, 0.7, 0.52, THREE.SRGBColorSpace);
        colors[3 * i] = c.r; colors[3 * i + 1] = c.g; colors[3 * i + 2] = c.b;
      }
      mesh.geometry.setAttribute('color', new THREE.BufferAttribute(colors, 3));
      if (!material.vertexColors) { material.vertexColors = true; material.color.set(0xffffff); material.needsUpdate = true; }
    }
    viewer.heat = !!values;
    render();
  }

  // A second body to compare with (before/after, two estimators): a kept copy of an earlier
  // avatar, drawn translucent blue over the current one or standing beside it.
  const ghostMaterial = new THREE.MeshStandardMaterial({
    color: 0x3f7fb0, roughness: 0.5, transparent: true, opacity: 0.4, depthWrite: false,
  });
  let ghost = null;
  function setGhost(positions, faces) {
    if (ghost) { scene.remove(ghost); ghost.geometry.dispose(); ghost = null; }
    if (positions) {
      const g = new THREE.BufferGeometry();
      g.setIndex(new THREE.BufferAttribute(faces, 1));
      g.setAttribute('position', new THREE.BufferAttribute(positions, 3));
      setVertexNormals(g);
      ghost = new THREE.Mesh(g, ghostMaterial);
      ghost.renderOrder = 1;
      scene.add(ghost);
    }
    viewer.ghost = !!ghost;
    setView(view);
  }
  // overlaid: in the same place; side: SIDE_OFFSET to the body's left (the viewer's right), far
  // enough for two T-posed bodies' arms, nearly opaque.
  function setCompareMode(mode) {
    viewer.compareMode = mode;
    if (!ghost) return;
    ghost.position.x = mode === 'side' ? SIDE_OFFSET : 0;
    ghostMaterial.opacity = mode === 'side' ? 0.85 : 0.4;
    ghostMaterial.depthWrite = mode === 'side';
    ghostMaterial.needsUpdate = true;
    setView(view);
  }

  return {
    setView, setBody, setHeat, setGhost, setCompareMode, render,
    renders: 0, hasBody: false, heat: false, ghost: false, compareMode: 'overlay', canvas: renderer.domElement,
  };
})();
state.viewer = viewer;

document.querySelectorAll('.view-presets button').forEach((b) => {
  b.addEventListener('click', () => {
    document.querySelectorAll('.view-presets button').forEach((x) => x.classList.toggle('active', x === b));
    viewer.setView(b.dataset.view);
  });
});

// ---------------------------------------------------------------------------------------------
// Inputs. A value is an input only when the user gave it (typed, slid, imported, from a capture
// session); every other field shows what the avatar predicts, marked "predicted", and is not sent.

const rows = new Map();  // name → { row, slider, number, use, tag, info }

function inputEntries() {
  return state.catalogue.filter((m) => m.input).sort((a, b) => a.input.level - b.input.level);
}

function buildInputs() {
  const host = $('inputs');
  host.textContent = '';
  for (const level of [1, 2, 3]) {
    const box = document.createElement('div');
    box.className = 'level';
    box.innerHTML = `<p class="level-title"><span class="num">${level}</span>${LEVEL_TITLES[level]}</p>`;
    for (const m of inputEntries().filter((x) => x.input.level === level)) box.appendChild(buildRow(m));
    host.appendChild(box);
    if (level === 1) {
      const bmi = document.createElement('p');
      bmi.className = 'bmi';
      bmi.id = 'bmi';
      host.appendChild(bmi);
    }
  }
}

function buildRow(m) {
  const row = document.createElement('div');
  row.className = 'row';
  row.dataset.name = m.name;
  const name = friendly(m.name);
  row.innerHTML = `
    <input type="checkbox" class="use" aria-label="use my ${name}" title="checked: your value is sent; unchecked: the avatar's prediction is shown and nothing is sent">
    <div class="head"><label class="label" for="in-${m.name}">${name}</label><span class="tag"></span><span class="sub" title="${m.label}">${m.label}</span></div>
    <div class="controls">
      <input type="range" aria-label="${name} slider">
      <input type="text" inputmode="decimal" autocomplete="off" spellcheck="false" id="in-${m.name}">
      <span class="unit"></span>
    </div>`;
  const r = {
    row, info: m, slider: row.querySelector('input[type=range]'), number: row.querySelector('input[type=text]'),
    use: row.querySelector('.use'), tag: row.querySelector('.tag'), unit: row.querySelector('.unit'),
  };
  r.slider.addEventListener('input', () => giveValue(m.name, fromDisplay(m.name, Number(r.slider.value)), { slider: true }));
  r.number.addEventListener('input', () => typing(m.name));
  r.number.addEventListener('change', () => commitText(m.name));
  r.number.addEventListener('keydown', (e) => { if (e.key === 'Enter') commitText(m.name); });
  r.use.addEventListener('change', () => {
    if (r.use.checked) giveValue(m.name, state.values[m.name] ?? state.predicted[m.name] ?? m.input.default[state.sex] ?? m.input.default.female);
    else forgetValue(m.name);
  });
  rows.set(m.name, r);
  return row;
}

// Slider ends and the number field's hints follow the display units.
function applyUnits() {
  for (const [name, r] of rows) {
    const s = r.info.input.slider, a = r.info.accepted_range, u = displayUnit(name);
    r.slider.min = String(Math.floor(toDisplay(name, s.min)));
    r.slider.max = String(Math.ceil(toDisplay(name, s.max)));
    r.slider.step = '0.1';
    r.unit.textContent = u.unit;
    r.number.setAttribute('aria-label', `${friendly(name)} in ${u.unit}`);
    r.number.title = `accepted ${rangeText(name, a)}; a decimal comma is fine (172,5)`;
  }
  for (const th of document.querySelectorAll('[data-unit-note]')) th.textContent = state.units === 'metric' ? 'cm · kg' : 'in · lb';
}

// A range as people write it: 50–250 cm, 19.7–98.4 in.
const plain = (x) => String(Math.round(x * 10) / 10);
const rangeText = (name, r) => `${plain(toDisplay(name, r.min))}–${plain(toDisplay(name, r.max))} ${displayUnit(name).unit}`;

// Shows every row: the user's value, or the avatar's prediction in grey. A field being typed in
// keeps its text.
function refreshRows() {
  for (const [name, r] of rows) {
    const given = state.given.has(name);
    const v = given ? state.values[name] : state.predicted[name];
    if (r.number.dataset.dirty !== '1' && !state.fieldErrors.has(name)) r.number.value = v === undefined ? '' : shown(name, v);
    if (v !== undefined) r.slider.value = String(toDisplay(name, v));
    r.use.checked = given;
    const average = !given && state.averageBody && name === 'stature';
    r.tag.textContent = given ? 'your value' : average ? 'average' : 'predicted';
    r.row.classList.toggle('given', given);
    r.row.classList.toggle('predicted', !given);
    r.row.classList.toggle('invalid', state.fieldErrors.has(name));
  }
  renderBmi();
}

// BMI from the height and weight used: the user's values, else the avatar's.
function renderBmi() {
  const host = $('bmi');
  if (!host) return;
  const value = (name) => (state.given.has(name) ? state.values[name] : state.predicted[name]);
  const h = value('stature'), w = value('weight');
  if (!h || !w) { host.textContent = ''; return; }
  // A BMI from a height typed in inches or a weight in pounds would be a confident wrong number.
  if (state.doubted.has('stature') || state.doubted.has('weight')) { host.textContent = 'BMI: check the height and weight first'; return; }
  const bmi = w / (h / 100) ** 2;
  const whose = state.given.has('stature') && state.given.has('weight') ? 'from your height and weight' : 'from the avatar\'s height and weight';
  host.textContent = `BMI ${bmi.toFixed(1)} kg/m² · ${whose}`;
}

// Text as people type it: "175.5" or "175,5" (decimal comma); nothing else.
function parseDecimal(text) {
  const t = text.trim();
  if (!/^[+-]?(\d+([.,]\d*)?|[.,]\d+)$/.test(t)) return NaN;
  return Number(t.replace(',', '.'));
}

// Checks the text in a field: { value } in cm / kg, { empty: true }, or { error }.
function readField(name) {
  const text = rows.get(name).number.value;
  if (text.trim() === '') return { empty: true };
  const typed = parseDecimal(text);
  const u = displayUnit(name).unit;
  if (!Number.isFinite(typed)) return { error: `${friendly(name)}: “${text.trim()}” is not a number; type e.g. 172.5 or 172,5 (${u})` };
  const value = fromDisplay(name, typed);
  const r = state.info.get(name).accepted_range;
  if (value < r.min || value > r.max) return { error: `${friendly(name)} ${typed} ${u} is outside the accepted range ${rangeText(name, r)}` };
  return { value: Math.round(value * 1000) / 1000 };
}

// While typing: nothing is sent per keystroke. A valid value goes after a short pause; anything
// else waits for Enter, leaving the field, or a longer pause, so "1" on the way to "180" never
// flashes an error.
const typingTimers = new Map();
function typing(name) {
  const r = rows.get(name);
  r.number.dataset.dirty = '1';
  clearTimeout(typingTimers.get(name));
  const ok = readField(name).value !== undefined;
  typingTimers.set(name, setTimeout(() => commitText(name), ok ? 350 : 1500));
}

function commitText(name) {
  clearTimeout(typingTimers.get(name));
  const r = rows.get(name);
  if (r.number.dataset.dirty !== '1' && !state.fieldErrors.has(name)) return;
  r.number.dataset.dirty = '';
  const field = readField(name);
  if (field.error) {
    state.fieldErrors.set(name, field.error);
    refreshRows();
    showFieldErrors();
    return;
  }
  state.fieldErrors.delete(name);
  if (field.empty) forgetValue(name);
  else giveValue(name, field.value);
}

// The user gave a value (typed, slid, ticked).
function giveValue(name, value, { slider = false } = {}) {
  remember(slider ? `slide:${name}` : null);
  state.values[name] = value;
  state.given.add(name);
  state.fieldErrors.delete(name);
  refreshRows();
  changed();
}

// The user took a value back: the avatar predicts it again.
function forgetValue(name) {
  remember();
  state.given.delete(name);
  delete state.values[name];
  state.fieldErrors.delete(name);
  refreshRows();
  changed();
}

function presetInputs(name) {
  return state.regressors.find((r) => r.name === name)?.inputs ?? null;
}

// What goes to the server: the values the user gave, and nothing else. With none at all the page
// shows the population's average body (its mean height as the one value), said so on the page.
function requestBody() {
  const measurements = { ...state.extra };
  for (const name of state.given) measurements[name] = state.values[name];
  state.averageBody = Object.keys(measurements).length === 0;
  if (state.averageBody) measurements.stature = averageOf('stature');
  const body = { sex: state.sex, model: state.model, regressor: state.regressor, measurements };
  if (state.regressor === 'auto') body.noise = state.noise;
  // "Keep mine": these exact values were confirmed after the server doubted them.
  if (state.confirmed === JSON.stringify(measurements)) body.force = true;
  return body;
}

function averageOf(name) {
  const d = state.info.get(name).input.default;
  return d[state.sex] ?? d.female;
}

// A paper preset needs its inputs given; say which are missing instead of asking the server.
function checkPreset(body) {
  const needed = presetInputs(body.regressor);
  const missing = (needed ?? []).filter((n) => !(n in body.measurements) || (state.averageBody && n === 'stature'));
  if (!missing.length) return;
  throw new ApiError(422, {
    message: `paper ${body.regressor} needs ${missing.map(friendly).join(', ')}: type or slide ${missing.length > 1 ? 'them' : 'it'}, or choose auto`,
    field: missing[0], kind: 'unsupported',
  });
}

// Auto weighs values by who measured them; the paper's presets take them as exact.
function selectRegressor(name) {
  state.regressor = name;
  $('regressor').value = name;
  $('noise-row').hidden = name !== 'auto';
}

// ---------------------------------------------------------------------------------------------
// Undo (Ctrl+Z, Ctrl+Shift+Z / Ctrl+Y) and values kept across a reload (localStorage).

const undoStack = [];
const redoStack = [];
let lastRememberKey = null, lastRememberAt = 0;

function snapshot() {
  return {
    sex: state.sex, model: state.model, regressor: state.regressor, noise: state.noise,
    values: { ...state.values }, given: [...state.given], extra: { ...state.extra },
  };
}

// Called before every change the user makes. A slider drag is one step, not one per pixel.
function remember(key = null) {
  const now = performance.now();
  if (key && key === lastRememberKey && now - lastRememberAt < 1000) { lastRememberAt = now; return; }
  lastRememberKey = key;
  lastRememberAt = now;
  undoStack.push(snapshot());
  if (undoStack.length > 200) undoStack.shift();
  redoStack.length = 0;
}

function restore(s) {
  state.sex = s.sex;
  $('sex').value = s.sex;
  if ([...$('model').options].some((o) => o.value === s.model)) { state.model = s.model; $('model').value = s.model; }
  selectRegressor(s.regressor);
  state.noise = s.noise;
  $('noise').value = s.noise;
  state.values = { ...s.values };
  state.given = new Set(s.given.filter((n) => rows.has(n) && Number.isFinite(s.values[n])));
  state.extra = { ...s.extra };
  state.fieldErrors.clear();
  for (const r of rows.values()) r.number.dataset.dirty = '';
  refreshRows();
  changed();
}

function undo() {
  if (!undoStack.length) return false;
  redoStack.push(snapshot());
  restore(undoStack.pop());
  lastRememberKey = null;
  return true;
}

function redo() {
  if (!redoStack.length) return false;
  undoStack.push(snapshot());
  restore(redoStack.pop());
  lastRememberKey = null;
  return true;
}

// In a field with text not yet committed, Ctrl+Z is the browser's own text undo.
document.addEventListener('keydown', (e) => {
  if (!(e.ctrlKey || e.metaKey) || e.altKey) return;
  const key = e.key.toLowerCase();
  if (key !== 'z' && key !== 'y') return;
  const active = document.activeElement;
  if (active?.id === 'participant' || active?.dataset?.dirty === '1') return;
  const done = key === 'y' || e.shiftKey ? redo() : undo();
  if (done) e.preventDefault();
});

const STORAGE_KEY = 'caliper-desktop-tool';

function save() {
  if (state.blocked) return;
  try {
    localStorage.setItem(STORAGE_KEY, JSON.stringify({ ...snapshot(), units: state.units, participant: state.participant }));
  } catch { /* private mode or full: the page works without */ }
}

// What an earlier visit left, checked field by field (it may come from an older page or be
// edited by hand): anything unknown falls back to the default.
function loadSaved() {
  let s = null;
  try { s = JSON.parse(localStorage.getItem(STORAGE_KEY) ?? 'null'); } catch { return null; }
  if (!s || typeof s !== 'object') return null;
  const option = (id, v) => ([...$(id).options].some((o) => o.value === v) ? v : $(id).options[0]?.value);
  const numbers = (o) => Object.fromEntries(Object.entries(o && typeof o === 'object' ? o : {})
    .filter(([n, v]) => state.info.has(n) && Number.isFinite(v)));
  const values = numbers(s.values);
  return {
    sex: option('sex', s.sex), model: option('model', s.model), regressor: option('regressor', s.regressor),
    noise: option('noise', s.noise), values, extra: numbers(s.extra),
    given: Array.isArray(s.given) ? s.given.filter((n) => rows.has(n) && n in values) : [],
    units: s.units === 'imperial' ? 'imperial' : 'metric',
    participant: typeof s.participant === 'string' ? s.participant.slice(0, 60) : '',
  };
}

// ---------------------------------------------------------------------------------------------
// Live updates: at most one request in flight; the newest values win.

let inFlight = false;
let pending = false;

function changed() {
  save();
  if (state.blocked) return;
  pending = true;
  if (!inFlight) pump();
}

async function pump() {
  inFlight = true;
  while (pending) {
    pending = false;
    try {
      await update();
    } catch (e) {
      showError(e);
    }
  }
  inFlight = false;
}

async function topologyFor(model, sex) {
  const key = `${model}/${sex}`;
  if (!state.topology.has(key)) {
    const t = await api(`/api/topology?model=${encodeURIComponent(model)}&sex=${encodeURIComponent(sex)}`);
    state.topology.set(key, { faces: decodeBase64(t.faces, Uint32Array), vertexCount: t.vertex_count, name: t.name });
  }
  return state.topology.get(key);
}

async function update() {
  const body = requestBody();
  checkPreset(body);
  const topo = await topologyFor(body.model, body.sex);
  const t0 = performance.now();
  state.requests.push(body);
  if (state.requests.length > 50) state.requests.shift();
  const res = await api('/api/avatar', { method: 'POST', body: { ...body, pose: state.pose } });
  const roundTrip = performance.now() - t0;
  const positions = decodeBase64(res.mesh.positions, Float32Array);
  const report = res.report;
  const stature = report.measurements.stature?.achieved_cm ?? 170;
  viewer.setBody(positions, topo.faces, stature / 100);
  state.lastPositions = positions;
  state.lastFaces = topo.faces;
  state.vertexSd = res.mesh.vertex_sd ? decodeBase64(res.mesh.vertex_sd, Float32Array) : null;
  applyHeat();
  state.last = res;
  state.lastRoundTripMs = roundTrip;
  state.predicted = predictedInputs(report);
  clearError();
  refreshRows();
  renderPlausibility(report);
  renderTable(report);
  renderWarnings(report);
  const count = state.averageBody ? 'no values given' : `${report.inputs.length} inputs`;
  $('regressor-used').textContent = `${report.regressor} · ${count}`;
  $('regressor-hint').textContent = hintFor(report);
  const status = $('status');
  status.classList.remove('error');
  status.textContent = `${topo.name} · ${topo.vertexCount.toLocaleString('en')} vertices · round trip ${roundTrip.toFixed(0)} ms (server ${res.timing_ms.total.toFixed(0)} ms)`;
  showFieldErrors();
  state.updates += 1;
  document.body.dataset.updates = String(state.updates);
}

// The avatar's value of each input, as a person would measure it (a hanging arm's length, not
// the rest pose's).
function predictedInputs(report) {
  const out = {};
  for (const name of rows.keys()) {
    const m = report.measurements[name];
    const v = m?.real_equivalent_cm ?? m?.achieved_cm ?? m?.achieved_kg;
    if (v !== undefined) out[name] = v;
  }
  return out;
}

function hintFor(report) {
  if (state.averageBody) return `No values given yet: this is the population's average ${state.sex === 'neutral' ? 'person' : state.sex === 'male' ? 'man' : 'woman'}. Type or slide any value; only the values you give are used.`;
  const names = report.inputs.map(friendly).join(', ');
  if (report.regressor === 'map') {
    const noise = report.uncertainty?.noise ?? state.noise;
    const how = noise === 'exact' ? 'reproduces every given value' : `weighs every given value by its expected error (${noise}-measured)`;
    return `auto ${how}: ${names}. The rest is predicted. ± SD is the avatar's uncertainty.`;
  }
  return `the paper's ${report.regressor} uses ${names}.`;
}

// ---------------------------------------------------------------------------------------------
// Results

const capitalise = (text) => text.charAt(0).toUpperCase() + text.slice(1);

function renderPlausibility(report) {
  const p = report.plausibility;
  const v = $('verdict');
  v.textContent = p.verdict;
  v.className = `verdict ${p.verdict}`;
  // In words a person can read: how rare, among whom, and why.
  const why = p.drivers?.length ? ` Mostly because ${p.drivers.slice(0, 2).join('; ')}.` : '';
  $('explanation').textContent = `${capitalise(p.rarity ?? '')}.${why}`;
  $('explanation').title = `${p.population ? `Population: ${p.population}. ` : ''}Shape values: ${p.explanation}`;
  $('population').textContent = p.population ? `Population: ${p.population}.` : '';
  const host = $('beta-bars');
  host.textContent = '';
  report.beta.forEach((b, k) => {
    const cls = p.per_value[k] ?? 'plausible';
    const row = document.createElement('div');
    row.className = `beta ${cls}`;
    const clamped = Math.max(-4, Math.min(4, b));
    const left = 50 + Math.min(0, clamped) * 12.5;
    const width = Math.abs(clamped) * 12.5;
    row.innerHTML = `<span class="name">β${k + 1}</span>
      <span class="track"><span class="bar" style="left:${left}%;width:${Math.max(width, 0.6)}%"></span></span>
      <span class="value">${b >= 0 ? '+' : '−'}${Math.abs(b).toFixed(2)}</span>`;
    row.title = `β${k + 1} = ${b.toFixed(3)}: ${cls}`;
    host.appendChild(row);
  });
}

function renderTable(report) {
  const tbody = $('measurements').querySelector('tbody');
  tbody.textContent = '';
  const all = $('show-all').checked;
  const ms = report.measurements;
  const value = (m, kind) => m[`${kind}_cm`] ?? m[`${kind}_kg`] ?? null;
  const section = (title) => {
    const tr = document.createElement('tr');
    tr.className = 'section';
    tr.innerHTML = `<td colspan="5">${title}</td>`;
    tbody.appendChild(tr);
  };
  const add = (name, cls) => {
    const m = ms[name];
    if (!m) return;
    const req = value(m, 'requested'), ach = value(m, 'achieved'), diff = value(m, 'difference');
    const u = displayUnit(name).unit;
    const f = displayUnit(name).factor;
    const tr = document.createElement('tr');
    tr.className = cls;
    tr.dataset.name = name;
    const dcls = diff === null ? '' : Math.abs(diff) < 0.5 ? 'small' : Math.abs(diff) >= 1 ? 'large' : '';
    // Values are as a person measures them; a real → virtual map (paper §3.3) makes the avatar's
    // own rest-pose value differ (arm length): shown once, as a note.
    const restPose = value(m, 'rest_pose');
    const note = restPose === null ? '' : `<span class="note">as measured on a person; ${shown(name, restPose)} ${u} in the T-pose rest pose (§3.3 map)</span>`;
    const shownReq = cls === 'predicted' ? null : req;
    tr.innerHTML = `<td title="${state.info.get(name)?.label ?? name}">${friendly(name)}${note}</td>
      <td>${shownReq === null ? '—' : `${shown(name, shownReq)} ${u}`}</td>
      <td>${ach === null ? '—' : `${shown(name, ach)} ${u}`}</td>
      <td class="delta ${dcls}">${diff === null || cls === 'predicted' ? '' : `${diff >= 0 ? '+' : '−'}${Math.abs(diff * f).toFixed(2)}`}</td>
      <td class="sd">${sdCell(value(m, 'uncertainty'), f, u)}</td>`;
    tbody.appendChild(tr);
  };
  // Nothing given: the average body's one value is not the user's, so it is listed as predicted.
  const inputs = state.averageBody ? [] : report.inputs;
  section(inputs.length ? 'your values (requested → avatar)' : 'your values: none given yet');
  inputs.forEach((n) => add(n, 'input'));
  const otherRequested = state.averageBody ? [] : Object.keys(ms).filter((n) => !inputs.includes(n) && value(ms[n], 'requested') !== null);
  if (otherRequested.length) {
    section('given, not used by the regressor');
    otherRequested.forEach((n) => add(n, 'requested'));
  }
  section('predicted by the avatar (not inputs)');
  const predicted = state.catalogue
    .map((m) => m.name)
    .filter((n) => ms[n] && !inputs.includes(n) && !otherRequested.includes(n) && (all || state.info.get(n)?.highlight || state.info.get(n)?.input));
  predicted.forEach((n) => add(n, 'predicted'));
}

// An error bar: ± SD as text over a bar whose half-width grows with the SD (full at 3 cm / kg).
function sdCell(sd, factor, unit) {
  if (sd === null) return '';
  const half = Math.min(50, (sd / 3) * 50);
  const v = (sd * factor).toFixed(2);
  return `<span class="errbar" title="avatar value ± ${v} ${unit} (posterior SD)"><span class="whisker" style="left:${50 - half}%;width:${2 * half}%"></span><span class="dot"></span></span><span class="sd-value">±${v}</span>`;
}

function renderWarnings(report) {
  const list = $('warnings');
  list.textContent = '';
  for (const w of report.warnings ?? []) {
    const li = document.createElement('li');
    li.textContent = w;
    list.appendChild(li);
  }
  list.hidden = !(report.warnings ?? []).length;
  $('measurements').classList.toggle('with-sd', Object.values(report.measurements).some((m) => m.uncertainty_cm !== undefined || m.uncertainty_kg !== undefined));
}

// The per-vertex SD heat map: shown while the toggle is on and the estimator gave one; the
// legend's top is the largest SD on this body.
function applyHeat() {
  const sd = state.vertexSd;
  $('heatmap-bar').hidden = !sd;
  if (sd && $('heatmap').checked) {
    let max = 0;
    for (const v of sd) max = Math.max(max, v);
    viewer.setHeat(sd, max || 1);
    $('heat-legend').querySelector('.hi').textContent = `${(max * 100).toFixed(1)} cm SD`;
  } else if (viewer.heat) {
    viewer.setHeat(null);
  }
}

function showError(e) {
  const box = $('error');
  if (e.kind === 'suspect_values') return askAboutSuspects(e);
  box.textContent = withRange(e);
  box.hidden = false;
  for (const [name, r] of rows) r.row.classList.toggle('invalid', name === e.field || state.fieldErrors.has(name));
  const status = $('status');
  status.textContent = e.status === 0 ? e.message : 'not updated: fix the highlighted value';
  status.classList.add('error');
}

// The server's message, with the accepted range added only when the message does not give it.
function withRange(e) {
  const r = e.range;
  if (!r || (e.message.includes(String(r.min)) && e.message.includes(String(r.max)))) return e.message;
  return `${e.message} (accepted ${r.min}–${r.max} ${r.unit})`;
}

// Text that is not a usable value stays in its field, marked, and is explained here; the avatar
// keeps its last shape.
function showFieldErrors() {
  if (!state.fieldErrors.size) return;
  const box = $('error');
  box.textContent = [...state.fieldErrors.values()].join('. ') + '.';
  box.hidden = false;
  const status = $('status');
  status.textContent = 'not updated: fix the highlighted value';
  status.classList.add('error');
}
// Values that look swapped or in the wrong unit: ask in place, as the CLI does with
// its "did you mean" and --force.
function askAboutSuspects(e) {
  const box = $('error');
  box.textContent = '';
  const text = document.createElement('p');
  text.textContent = e.suspects.map((s) => s.reason).filter((r, i, all) => all.indexOf(r) === i).join('; ') + '.';
  const use = document.createElement('button');
  use.id = 'use-suggested';
  use.textContent = `Use ${e.suspects.map((s) => `${friendly(s.field)} ${s.suggested}`).join(', ')}`;
  use.addEventListener('click', () => {
    remember();
    for (const s of e.suspects) { state.values[s.field] = s.suggested; state.given.add(s.field); }
    refreshRows();
    changed();
  });
  const keep = document.createElement('button');
  keep.id = 'keep-mine';
  keep.textContent = 'Keep mine';
  keep.addEventListener('click', () => {
    state.confirmed = JSON.stringify(requestBody().measurements);
    changed();
  });
  box.append(text, use, keep);
  box.hidden = false;
  state.doubted = new Set(e.suspects.map((s) => s.field));
  renderBmi();
  for (const [name, r] of rows) r.row.classList.toggle('invalid', e.suspects.some((s) => s.field === name));
  const status = $('status');
  status.textContent = 'not updated: check the highlighted values';
  status.classList.add('error');
}
function clearError() {
  $('error').hidden = true;
  if (state.doubted.size) { state.doubted = new Set(); renderBmi(); }
  for (const [name, r] of rows) r.row.classList.toggle('invalid', state.fieldErrors.has(name));
}

$('show-all').addEventListener('change', () => { if (state.last) renderTable(state.last.report); });
$('heatmap').addEventListener('change', applyHeat);

// ---------------------------------------------------------------------------------------------
// Export and measurement sets

// The participant id as a file-name prefix: letters, digits, '-', '_' and '.' only.
function filePrefix() {
  const id = state.participant.trim().replace(/[^A-Za-z0-9._-]+/g, '_').replace(/^[._]+/, '').slice(0, 40);
  return id ? `${id}-` : '';
}

function saveBlob(blob, name) {
  const a = document.createElement('a');
  a.href = URL.createObjectURL(blob);
  a.download = filePrefix() + name;
  a.hidden = true;
  document.body.appendChild(a);
  a.click();
  setTimeout(() => { URL.revokeObjectURL(a.href); a.remove(); }, 1000);
}

async function download(path, body, fallbackName) {
  try {
    const res = await api(path, { method: 'POST', body, raw: true });
    const blob = await res.blob();
    const cd = res.headers.get('Content-Disposition') ?? '';
    saveBlob(blob, /filename="([^"]+)"/.exec(cd)?.[1] ?? fallbackName);
  } catch (e) {
    showError(e);
  }
}

// The rigged files, with the model's shape directions as blend shapes when that box is ticked,
// and the bone names chosen (SMPL's unless the user picks engine names).
function exportRigged(format) {
  const body = requestBody();
  if ($('export-morphs').checked) body.morphs = true;
  if ($('export-skeleton').value !== 'smpl') body.skeleton = $('export-skeleton').value;
  download(`/api/export/${format}`, body, `avatar.${format}`);
}
for (const format of ['glb', 'vrm', 'fbx']) $(`export-${format}`).addEventListener('click', () => exportRigged(format));
$('export-obj').addEventListener('click', () => download('/api/export/obj', requestBody(), 'avatar.obj'));
$('export-report').addEventListener('click', () => download('/api/export/report', requestBody(), 'avatar-report.json'));
const setBody = () => { const b = requestBody(); delete b.regressor; delete b.noise; delete b.force; return b; };
$('export-set-json').addEventListener('click', () => download('/api/measurement-set/export?format=json', setBody(), 'measurements.json'));
$('export-set-csv').addEventListener('click', () => download('/api/measurement-set/export?format=csv', setBody(), 'measurements.csv'));
$('screenshot').addEventListener('click', () => {
  viewer.render();  // the canvas keeps its drawing buffer, so this frame is what is copied
  viewer.canvas.toBlob((blob) => { if (blob) saveBlob(blob, `caliper-${state.model}-${state.sex}-view.png`); }, 'image/png');
});

// A real button (keyboard, screen readers) that opens the hidden file input.
$('import').addEventListener('click', () => $('import-file').click());
$('import-file').addEventListener('change', async (ev) => {
  const file = ev.target.files?.[0];
  ev.target.value = '';
  if (!file) return;
  try {
    const text = await file.text();
    const isJson = /\.json$/i.test(file.name) || text.trim().startsWith('{');
    const set = await api('/api/measurement-set/import', {
      method: 'POST', body: text, contentType: isJson ? 'application/json' : 'text/csv',
    });
    applySet(set);
  } catch (e) {
    showError(e);
  }
});

// An imported set (or a capture session) is the person's values: exactly these are given.
function applySet(set) {
  remember();
  if (set.sex) { state.sex = set.sex; $('sex').value = set.sex; }
  if (set.model && [...$('model').options].some((o) => o.value === set.model)) { state.model = set.model; $('model').value = set.model; }
  state.extra = {};
  state.values = {};
  state.given.clear();
  state.fieldErrors.clear();
  for (const [name, v] of Object.entries(set.measurements)) {
    if (rows.has(name)) { state.values[name] = v; state.given.add(name); } else state.extra[name] = v;
  }
  for (const r of rows.values()) r.number.dataset.dirty = '';
  selectRegressor('auto');
  // A capture session's values say who measured them: auto weighs them accordingly.
  if (set.measured_by) { state.noise = set.measured_by; $('noise').value = set.measured_by; }
  refreshRows();
  changed();
}

// ---------------------------------------------------------------------------------------------
// Body-image tasks (docs/mirror-tasks.md): with a capture session open, the experimenter shows
// the participant's mirror body with its weight changed, or starts an adjust task, and sees the
// answers as the headset sends them (polled every 2 s). The server takes task starts from the
// desktop only; reads and exports carry the session's code when this tab has one.

const INSTRUCTION_WORDS = { how_i_look: 'how I look', how_i_would_like_to_look: 'how I would like to look' };
const TASK_POLL_MS = 2000;
const taskPanel = { id: null, code: null, timer: null, tasks: null, polls: 0 };
state.taskPanel = taskPanel;  // for the end-to-end test

const sessionHeaders = () => (taskPanel.code ? { 'X-Caliper-Pairing': taskPanel.code } : {});
const sessionPath = (rest) => `/api/sessions/${encodeURIComponent(taskPanel.id)}/${rest}`;
const signedPct = (v) => `${v > 0 ? '+' : v < 0 ? '−' : '±'}${Math.abs(v)} %`;
const taskWords = (t) => (t.kind === 'show' ? 'show' : `adjust to “${INSTRUCTION_WORDS[t.instruction] ?? t.instruction}”`);

function openTaskPanel(id, code) {
  taskPanel.id = id;
  taskPanel.code = code;
  $('task-card').hidden = false;
  pollTasks();
  clearInterval(taskPanel.timer);
  taskPanel.timer = setInterval(() => { if (!document.hidden) pollTasks(); }, TASK_POLL_MS);
}

async function pollTasks() {
  try {
    const r = await api(sessionPath('body-image-tasks'), { headers: sessionHeaders() });
    taskPanel.polls += 1;
    renderTasks(r.tasks, r.current);
  } catch (e) {
    showTaskError(e);
  }
}

// The table, newest first, redrawn only when a task changed (focus and selection stay put).
function renderTasks(tasks, current) {
  if (JSON.stringify(tasks) === JSON.stringify(taskPanel.tasks)) return;
  taskPanel.tasks = tasks;
  const rowsOut = tasks.slice().reverse().map((t) => {
    const tr = document.createElement('tr');
    tr.className = t.state;
    tr.dataset.task = t.id;
    const a = t.answer;
    const chosen = !a ? '—' : `${signedPct(a.chosen_weight_change_pct)}${a.chosen_weight_kg == null ? '' : ` · ${a.chosen_weight_kg.toFixed(1)} kg`}` +
      ` · ${(a.answered_at_s - a.shown_at_s).toFixed(1)} s`;
    for (const text of [t.created.slice(11, 19), taskWords(t), signedPct(t.start_weight_change_pct), chosen, t.state]) {
      const td = document.createElement('td');
      td.textContent = text;
      tr.appendChild(td);
    }
    return tr;
  });
  $('task-table').tBodies[0].replaceChildren(...rowsOut);
  $('task-status').textContent = current
    ? `Running: ${taskWords(current)}, starting at ${signedPct(current.start_weight_change_pct)}` +
      (current.kind === 'adjust' ? `, range ${signedPct(current.range_pct[0])} to ${signedPct(current.range_pct[1])}.` : '.')
    : tasks.length ? 'No task running.' : 'No task yet.';
}

function showTaskError(e) {
  const box = $('task-error');
  box.textContent = withRange(e);
  box.hidden = false;
}

async function startTask(task) {
  $('task-error').hidden = true;
  try {
    await api(sessionPath('body-image-tasks'), { method: 'POST', body: task, headers: sessionHeaders() });
    await pollTasks();
    return true;
  } catch (e) {
    showTaskError(e);
    return false;
  }
}

// The body the participant is shown, drawn here as the comparison body (the mirror's T pose).
async function previewMirrorBody(pct) {
  try {
    const r = await api(sessionPath(`mirror-body?weights=${pct}`), { headers: sessionHeaders() });
    const body = r.bodies.find((b) => b.weight_change_pct === pct);
    $('compare-mode').value = 'side';  // a thinner body would hide inside hers when overlaid
    showComparison({ positions: new Float32Array(body.vertices), faces: new Uint32Array(r.faces),
      label: `the mirror body at ${signedPct(pct)}, ${body.weight_kg.toFixed(1)} kg, BMI ${body.bmi.toFixed(1)}` }, 'T');
  } catch (e) {
    showTaskError(e);
  }
}

$('task-show-form').addEventListener('submit', async (e) => {
  e.preventDefault();
  const pct = Number($('task-show-pct').value);
  if (await startTask({ kind: 'show', instruction: 'how_i_look', start_weight_change_pct: pct, range_pct: [-50, 100] }))
    await previewMirrorBody(pct);
});
$('task-instruction').addEventListener('change', (e) => {
  $('task-free-row').hidden = e.target.value !== 'other';
  if (e.target.value === 'other') $('task-free').focus();
});
$('task-adjust-form').addEventListener('submit', (e) => {
  e.preventDefault();
  const choice = $('task-instruction').value;
  startTask({
    kind: 'adjust',
    instruction: choice === 'other' ? $('task-free').value.trim() : choice,
    start_weight_change_pct: Number($('task-start').value),
    range_pct: [Number($('task-min').value), Number($('task-max').value)],
  });
});

async function downloadSessionFile(format, name) {
  try {
    const res = await api(sessionPath(`export?format=${format}`), { raw: true, headers: sessionHeaders() });
    saveBlob(await res.blob(), name);
  } catch (e) {
    showTaskError(e);
  }
}
$('task-export-csv').addEventListener('click', () => downloadSessionFile('tasks-csv', 'body-image-tasks.csv'));
$('task-export-json').addEventListener('click', () => downloadSessionFile('json', 'session.json'));

// ---------------------------------------------------------------------------------------------
// Start

async function start() {
  const [catalogue, models] = await Promise.all([api('/api/measurements'), api('/api/models')]);
  state.catalogue = catalogue.measurements;
  for (const m of state.catalogue) state.info.set(m.name, m);
  state.regressors = models.regressors;
  const modelSelect = $('model');
  for (const m of models.models) {
    const o = document.createElement('option');
    o.value = m.name;
    o.textContent = m.name;
    modelSelect.appendChild(o);
  }
  state.model = models.models.some((m) => m.name === models.default_model) ? models.default_model : models.models[0]?.name;
  modelSelect.value = state.model;
  if (!state.model) throw new ApiError(0, { message: 'no body model found in the server\'s models folder (see docs/desktop-tool.md)' });
  buildInputs();
  wireControls();

  const sessionId = new URLSearchParams(location.search).get('session');
  if (sessionId) return openSession(sessionId);
  const saved = loadSaved();
  if (saved) {
    setUnits(saved.units);
    setParticipant(saved.participant);
    restore(saved);
  } else {
    setUnits('metric');
    refreshRows();
    changed();
  }
}

function wireControls() {
  // Switching sex keeps every value the user gave; only the predictions change.
  $('sex').addEventListener('change', (e) => { remember(); state.sex = e.target.value; changed(); });
  $('model').addEventListener('change', (e) => { remember(); state.model = e.target.value; changed(); });
  $('regressor').addEventListener('change', (e) => { remember(); selectRegressor(e.target.value); changed(); });
  $('noise').addEventListener('change', (e) => { remember(); state.noise = e.target.value; changed(); });
  $('units').addEventListener('change', (e) => { setUnits(e.target.value); save(); });
  $('participant').addEventListener('input', (e) => { state.participant = e.target.value; save(); });
  $('pose').addEventListener('change', (e) => { state.pose = e.target.value; changed(); });
  $('compare-keep').addEventListener('click', keepForComparison);
  $('compare-clear').addEventListener('click', clearComparison);
  $('compare-mode').addEventListener('change', (e) => viewer.setCompareMode(e.target.value));
}

// Keeps the avatar on screen as the comparison body; the next changes build the other one.
function keepForComparison() {
  if (!state.lastPositions) return;
  const given = [...state.given].map((n) => `${friendly(n)} ${shown(n, state.values[n])} ${displayUnit(n).unit}`).join(', ');
  showComparison({ positions: state.lastPositions, faces: state.lastFaces, label: `${state.sex}, ${given || 'average'}` },
    state.pose === 't' ? 'T' : state.pose);
}

// Draws `compare` (positions, faces, label) as the second body; `pose` names the pose it stands in.
function showComparison(compare, pose) {
  state.compare = compare;
  viewer.setGhost(compare.positions, compare.faces);
  viewer.setCompareMode($('compare-mode').value);
  $('compare-label').textContent = `Kept: ${compare.label} (${pose} pose)`;
  $('compare-mode').disabled = false;
  $('compare-clear').disabled = false;
}

function clearComparison() {
  state.compare = null;
  viewer.setGhost(null);
  $('compare-label').textContent = 'Keep the avatar on screen, then change values to compare.';
  $('compare-mode').disabled = true;
  $('compare-clear').disabled = true;
}

function setUnits(units) {
  state.units = units;
  $('units').value = units;
  for (const r of rows.values()) r.number.dataset.dirty = '';
  state.fieldErrors.clear();
  applyUnits();
  refreshRows();
  if (state.last) renderTable(state.last.report);
}

function setParticipant(id) {
  state.participant = id;
  $('participant').value = id;
}

// `/?session=<id>`: the capture page's "Open in the desktop tool" link. The session's values go
// through the same import as a file would (validated by the server), then load like one. On the
// server's machine no code is needed; elsewhere (a headset) the capture page left the session's
// pairing code in this tab's sessionStorage, and the server wants it (docs/api.md "Pairing").
// If the session cannot be read, the page says so and builds nothing: a default body must not
// pass for the participant.
async function openSession(id) {
  setUnits('metric');
  let code = null;
  try { code = sessionStorage.getItem(`caliper-pairing-${id}`); } catch { /* private mode */ }
  try {
    const res = await api(`/api/sessions/${encodeURIComponent(id)}/export?format=json`,
      { raw: true, headers: code ? { 'X-Caliper-Pairing': code } : {} });
    const set = await api('/api/measurement-set/import', { method: 'POST', body: await res.text(), contentType: 'application/json' });
    setParticipant(id);
    applySet(set);
    undoStack.length = 0;  // the session's values are where this page starts
    openTaskPanel(id, code);
  } catch (e) {
    sessionFailed(id, e);
  }
}

function sessionFailed(id, e) {
  state.blocked = true;
  $('session-error-text').textContent = `Could not open capture session “${id}”: ${e.message}. No avatar is shown: nothing on this page is that participant's.`;
  $('session-error').hidden = false;
  $('main').inert = true;
  const status = $('status');
  status.textContent = 'capture session not opened';
  status.classList.add('error');
}

$('session-retry').addEventListener('click', () => location.reload());
$('session-dismiss').addEventListener('click', () => {
  const url = new URL(location.href);
  url.searchParams.delete('session');
  history.replaceState(null, '', url);
  state.blocked = false;
  $('session-error').hidden = true;
  $('main').inert = false;
  refreshRows();
  changed();
});

start().catch(showError);
