// Caliper desktop tool (paper §4.3, §5): set measurements hierarchically, see the avatar update
// live, check the shape's plausibility and the measurements, export. Everything goes through the
// documented JSON API (docs/api.md); three.js is served locally (see build.mjs).
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/OrbitControls.js';
import { decodeBase64 } from './shared.js';

// ---------------------------------------------------------------------------------------------
// API

class ApiError extends Error {
  constructor(status, error) {
    super(error?.message ?? `HTTP ${status}`);
    this.status = status;
    this.field = error?.field ?? null;
    this.range = error?.accepted_range ?? null;
    this.kind = error?.kind ?? null;
    this.suspects = error?.suspects ?? [];  // kind "suspect_values": values that look mistyped
  }
}

async function api(path, { method = 'GET', body, contentType = 'application/json', raw = false, headers = {} } = {}) {
  const init = { method, headers: { ...headers } };
  if (body !== undefined) {
    init.body = typeof body === 'string' ? body : JSON.stringify(body);
    init.headers['Content-Type'] = contentType;
  }
  let res;
  try {
    res = await fetch(path, init);
  } catch (e) {
    throw new ApiError(0, { message: 'the Caliper server is not reachable (is `caliper serve` still running?)' });
  }
  if (!res.ok) {
    let payload = null;
    try { payload = await res.json(); } catch { /* not JSON */ }
    throw new ApiError(res.status, payload?.error ?? { message: `HTTP ${res.status}` });
  }
  return raw ? res : res.json();
}

// ---------------------------------------------------------------------------------------------
// Names shown to people: the paper's words for its inputs, the catalogue's for the rest.

const FRIENDLY = {
  stature: 'Height', weight: 'Weight', span: 'Arm span', crotch_height: 'Inseam',
  hip_breadth: 'Hip width', arm_length: 'Arm length', biacromial_breadth: 'Shoulder width',
};
const LEVEL_TITLES = { 1: 'Height and weight', 2: 'Arm span and inseam', 3: 'Hip width and arm length' };
const friendly = (name) => FRIENDLY[name] ?? name.replaceAll('_', ' ').replace(/^./, (c) => c.toUpperCase());
const fmt = (v, digits = 1) => (v === null || v === undefined ? '—' : Number(v).toFixed(digits));

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
  values: {},               // input name → cm / kg
  use: {},                  // input name → sent or not
  extra: {},                // other imported measurements (e.g. a taped chest circumference), sent as requested
  topology: new Map(),      // "model/sex" → { faces: Uint32Array, vertexCount }
  last: null,               // last /api/avatar response
  updates: 0,
  lastRoundTripMs: null,
};
window.caliper = state;     // for the end-to-end test and the curious

const $ = (id) => document.getElementById(id);

// ---------------------------------------------------------------------------------------------
// Viewer: orbit controls, floor grid (10 cm cells), height ruler in cm, camera presets.

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
    const target = new THREE.Vector3(0, (height + 0.2) * 0.5, 0);
    const fitH = (height + 0.5) / 2 / Math.tan(THREE.MathUtils.degToRad(camera.fov / 2));
    const fitW = 2.3 / 2 / Math.tan(THREE.MathUtils.degToRad(camera.fov / 2)) / Math.max(camera.aspect, 0.3);
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
    mesh.geometry.computeVertexNormals();
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

  return { setView, setBody, setHeat, render, renders: 0, hasBody: false, heat: false, canvas: renderer.domElement };
})();
state.viewer = viewer;

document.querySelectorAll('.view-presets button').forEach((b) => {
  b.addEventListener('click', () => {
    document.querySelectorAll('.view-presets button').forEach((x) => x.classList.toggle('active', x === b));
    viewer.setView(b.dataset.view);
  });
});

// ---------------------------------------------------------------------------------------------
// Inputs

const rows = new Map();  // name → { row, slider, number, use }

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
    for (const m of inputEntries().filter((x) => x.input.level === level)) {
      const row = document.createElement('div');
      row.className = 'row';
      row.dataset.name = m.name;
      const r = m.accepted_range;
      const s = m.input.slider;
      row.innerHTML = `
        <input type="checkbox" class="use" title="use this measurement" ${level === 1 ? 'checked disabled' : ''}>
        <div class="head"><span class="label">${friendly(m.name)}</span><span class="sub" title="${m.label}">${m.label}</span></div>
        <div class="controls">
          <input type="range" min="${s.min}" max="${s.max}" step="${s.step}" aria-label="${friendly(m.name)} slider">
          <input type="number" min="${r.min}" max="${r.max}" step="${s.step}" id="in-${m.name}" aria-label="${friendly(m.name)} in ${m.unit}">
          <span class="unit">${m.unit}</span>
        </div>`;
      const slider = row.querySelector('input[type=range]');
      const number = row.querySelector('input[type=number]');
      const use = row.querySelector('.use');
      number.title = `accepted ${r.min}–${r.max} ${m.unit}; slider ${s.min}–${s.max} ${m.unit}`;
      slider.addEventListener('input', () => {
        number.value = slider.value;
        state.values[m.name] = Number(slider.value);
        changed();
      });
      number.addEventListener('input', () => {
        if (number.value === '' || !Number.isFinite(Number(number.value))) return;
        state.values[m.name] = Number(number.value);
        slider.value = number.value;
        changed();
      });
      use.addEventListener('change', () => {
        state.use[m.name] = use.checked;
        // A preset's inputs are fixed: choosing others means auto (it takes whatever is checked).
        if (state.regressor !== 'auto') selectRegressor('auto');
        refreshRows();
        changed();
      });
      rows.set(m.name, { row, slider, number, use, info: m });
      box.appendChild(row);
    }
    host.appendChild(box);
  }
}

function setDefaults(sex) {
  for (const m of inputEntries()) state.values[m.name] = m.input.default[sex] ?? m.input.default.female;
  for (const m of inputEntries()) state.use[m.name] = m.name !== 'arm_length';  // R5: the paper's best
}

function refreshRows() {
  for (const [name, r] of rows) {
    r.number.value = state.values[name];
    r.slider.value = state.values[name];
    r.use.checked = !!state.use[name];
    r.row.classList.toggle('off', !state.use[name]);
  }
}

function presetInputs(name) {
  return state.regressors.find((r) => r.name === name)?.inputs ?? null;
}

// Which inputs go to the server: the checked ones (auto), or exactly a preset's.
function requestBody() {
  const measurements = { ...state.extra };
  for (const [name, used] of Object.entries(state.use)) if (used) measurements[name] = state.values[name];
  const body = { sex: state.sex, model: state.model, regressor: state.regressor, measurements };
  if (state.regressor === 'auto') body.noise = state.noise;
  // "Keep mine": these exact values were confirmed after the server doubted them.
  if (state.confirmed === JSON.stringify(measurements)) body.force = true;
  return body;
}

// Auto weighs values by who measured them; the paper's presets take them as exact.
function selectRegressor(name) {
  state.regressor = name;
  $('regressor').value = name;
  $('noise-row').hidden = name !== 'auto';
}

// ---------------------------------------------------------------------------------------------
// Live updates: at most one request in flight; the newest values win.

let inFlight = false;
let pending = false;

function changed() {
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
  const topo = await topologyFor(body.model, body.sex);
  const t0 = performance.now();
  const res = await api('/api/avatar', { method: 'POST', body });
  const roundTrip = performance.now() - t0;
  const positions = decodeBase64(res.mesh.positions, Float32Array);
  const report = res.report;
  const stature = report.measurements.stature?.achieved_cm ?? 170;
  viewer.setBody(positions, topo.faces, stature / 100);
  state.vertexSd = res.mesh.vertex_sd ? decodeBase64(res.mesh.vertex_sd, Float32Array) : null;
  applyHeat();
  state.last = res;
  state.lastRoundTripMs = roundTrip;
  state.updates += 1;
  document.body.dataset.updates = String(state.updates);
  clearError();
  renderPlausibility(report);
  renderTable(report);
  renderWarnings(report);
  $('regressor-used').textContent = `${report.regressor} · ${report.inputs.length} inputs`;
  $('regressor-hint').textContent = hintFor(report);
  const status = $('status');
  status.classList.remove('error');
  status.textContent = `${topo.name} · ${topo.vertexCount.toLocaleString('en')} vertices · round trip ${roundTrip.toFixed(0)} ms (server ${res.timing_ms.total.toFixed(0)} ms)`;
}

function hintFor(report) {
  const names = report.inputs.map(friendly).join(', ');
  if (report.regressor === 'map') {
    const noise = report.uncertainty?.noise ?? state.noise;
    const how = noise === 'exact' ? 'reproduces every given value' : `weighs every given value by its expected error (${noise}-measured)`;
    return `auto ${how}: ${names}. ± SD is the avatar's uncertainty.`;
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
  // In words a person can read: how rare, among whom, and why (issue 14).
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
  const unitOf = (name) => state.info.get(name)?.unit ?? 'cm';
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
    const u = unitOf(name);
    const tr = document.createElement('tr');
    tr.className = cls;
    tr.dataset.name = name;
    const dcls = diff === null ? '' : Math.abs(diff) < 0.5 ? 'small' : Math.abs(diff) >= 1 ? 'large' : '';
    // A real → virtual map (paper §3.3) turns e.g. a hanging-arm length into its rest-pose
    // equivalent; the regressor aims at that, so the difference is taken from it.
    const target = value(m, 'virtual_target');
    // For a mapped measurement that was not requested, show what a person would measure (the
    // real equivalent), with the avatar's own rest-pose value in the note.
    const real = value(m, 'real_equivalent');
    const shownAch = req === null && real !== null ? real : ach;
    const note = target !== null
      ? `<span class="note">rest-pose target ${fmt(target)} ${u} (§3.3 map)</span>`
      : req === null && real !== null ? `<span class="note">as measured on a person; ${fmt(ach)} ${u} in the rest pose (§3.3 map)</span>` : '';
    tr.innerHTML = `<td title="${state.info.get(name)?.label ?? name}">${friendly(name)}${note}</td>
      <td>${req === null ? '—' : `${fmt(req)} ${u}`}</td>
      <td>${shownAch === null ? '—' : `${fmt(shownAch)} ${u}`}</td>
      <td class="delta ${dcls}">${diff === null ? '' : `${diff >= 0 ? '+' : '−'}${Math.abs(diff).toFixed(2)}`}</td>
      <td class="sd">${sdCell(value(m, 'uncertainty'))}</td>`;
    tbody.appendChild(tr);
  };
  const inputs = report.inputs;
  section('inputs (requested → avatar)');
  inputs.forEach((n) => add(n, 'input'));
  const otherRequested = Object.keys(ms).filter((n) => !inputs.includes(n) && value(ms[n], 'requested') !== null);
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
function sdCell(sd) {
  if (sd === null) return '';
  const half = Math.min(50, (sd / 3) * 50);
  return `<span class="errbar" title="avatar value ± ${sd.toFixed(2)} (posterior SD)"><span class="whisker" style="left:${50 - half}%;width:${2 * half}%"></span><span class="dot"></span></span><span class="sd-value">±${sd.toFixed(2)}</span>`;
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
  let text = e.message;
  if (e.range) text += ` — accepted ${e.range.min}–${e.range.max} ${e.range.unit}`;
  box.textContent = text;
  box.hidden = false;
  for (const [name, r] of rows) r.row.classList.toggle('invalid', name === e.field);
  const status = $('status');
  status.textContent = e.status === 0 ? e.message : 'not updated: fix the highlighted value';
  status.classList.add('error');
}
// Values that look swapped or in the wrong unit (issue 14): ask in place, as the CLI does with
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
    for (const s of e.suspects) state.values[s.field] = s.suggested;
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
  for (const [name, r] of rows) r.row.classList.toggle('invalid', e.suspects.some((s) => s.field === name));
  const status = $('status');
  status.textContent = 'not updated: check the highlighted values';
  status.classList.add('error');
}
function clearError() {
  $('error').hidden = true;
  for (const r of rows.values()) r.row.classList.remove('invalid');
}

$('show-all').addEventListener('change', () => { if (state.last) renderTable(state.last.report); });
$('heatmap').addEventListener('change', applyHeat);

// ---------------------------------------------------------------------------------------------
// Export and measurement sets

async function download(path, body, fallbackName) {
  try {
    const res = await api(path, { method: 'POST', body, raw: true });
    const blob = await res.blob();
    const cd = res.headers.get('Content-Disposition') ?? '';
    const name = /filename="([^"]+)"/.exec(cd)?.[1] ?? fallbackName;
    const a = document.createElement('a');
    a.href = URL.createObjectURL(blob);
    a.download = name;
    document.body.appendChild(a);
    a.click();
    setTimeout(() => { URL.revokeObjectURL(a.href); a.remove(); }, 1000);
  } catch (e) {
    showError(e);
  }
}

$('export-glb').addEventListener('click', () => download('/api/export/glb', requestBody(), 'avatar.glb'));
$('export-vrm').addEventListener('click', () => download('/api/export/vrm', requestBody(), 'avatar.vrm'));
$('export-fbx').addEventListener('click', () => download('/api/export/fbx', requestBody(), 'avatar.fbx'));
$('export-obj').addEventListener('click', () => download('/api/export/obj', requestBody(), 'avatar.obj'));
$('export-report').addEventListener('click', () => download('/api/export/report', requestBody(), 'avatar-report.json'));
const setBody = () => { const b = requestBody(); delete b.regressor; delete b.noise; return b; };
$('export-set-json').addEventListener('click', () => download('/api/measurement-set/export?format=json', setBody(), 'measurements.json'));
$('export-set-csv').addEventListener('click', () => download('/api/measurement-set/export?format=csv', setBody(), 'measurements.csv'));

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

function applySet(set) {
  if (set.sex) { state.sex = set.sex; $('sex').value = set.sex; }
  if (set.model && [...$('model').options].some((o) => o.value === set.model)) { state.model = set.model; $('model').value = set.model; }
  state.extra = {};
  for (const [name, v] of Object.entries(set.measurements)) {
    if (rows.has(name)) state.values[name] = v;
    else state.extra[name] = v;
  }
  for (const [name, r] of rows) {
    if (r.info.input.level === 1) continue;
    state.use[name] = name in set.measurements;
  }
  selectRegressor('auto');
  // A capture session's values say who measured them: auto weighs them accordingly.
  if (set.measured_by) { state.noise = set.measured_by; $('noise').value = set.measured_by; }
  refreshRows();
  changed();
}

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
  setDefaults(state.sex);
  refreshRows();

  $('sex').addEventListener('change', (e) => {
    state.sex = e.target.value;
    setDefaults(state.sex);
    for (const [name, r] of rows) state.use[name] = r.use.checked;  // keep the user's choice of inputs
    refreshRows();
    changed();
  });
  $('model').addEventListener('change', (e) => { state.model = e.target.value; changed(); });
  $('regressor').addEventListener('change', (e) => {
    selectRegressor(e.target.value);
    const inputs = presetInputs(state.regressor);
    if (inputs) for (const name of rows.keys()) state.use[name] = inputs.includes(name);
    refreshRows();
    changed();
  });
  $('noise').addEventListener('change', (e) => { state.noise = e.target.value; changed(); });
  changed();
  await openSessionFromUrl();
}

// `/?session=<id>`: the capture page's "Open in the desktop tool" link. The session's values go
// through the same import as a file would (validated by the server), then load like one. On the
// server's machine no code is needed; elsewhere (a headset) the capture page left the session's
// pairing code in this tab's sessionStorage, and the server wants it (docs/api.md "Pairing").
async function openSessionFromUrl() {
  const id = new URLSearchParams(location.search).get('session');
  if (!id) return;
  let code = null;
  try { code = sessionStorage.getItem(`caliper-pairing-${id}`); } catch { /* private mode */ }
  const res = await api(`/api/sessions/${encodeURIComponent(id)}/export?format=json`,
    { raw: true, headers: code ? { 'X-Caliper-Pairing': code } : {} });
  const set = await api('/api/measurement-set/import', { method: 'POST', body: await res.text(), contentType: 'application/json' });
  applySet(set);
}

start().catch(showError);
