// Where the mirror's bodies and body-image tasks come from: the one place that talks to the
// server for the mirror page (docs/mirror.md "Sources"). A "mirror model" is the contract's
// mirror-body answer (docs/api.md): one topology and rig, and bodies at several weight changes
// that the page blends between:
//   { sex, jointNames, parents, faces: Uint32Array (3 per face), skinIndex: Uint16Array (4 per
//     vertex), skinWeight: Float32Array (4 per vertex), bodies: [{ pct, weightKg, vertices:
//     Float32Array (metres, rest T-pose, facing +Z), joints: Float32Array }] (sorted by pct) }
//
// The mirror-body and body-image-task endpoints belong to the server side of the mirror. Where a
// server does not have them yet (it answers 404 "no such endpoint", field `path`), this module
// falls back — and only here — to what every server has: the session's measurement set, one rigged
// GLB per weight change from POST /api/export/glb (the same estimator, stature and lengths kept,
// the weight changed), and a task list kept in the page (`localTasks`), marked as such.
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { Matrix4, Vector3 } from 'three';
import { ApiError, api } from './shared.js';

export const DEFAULT_WEIGHTS = [-30, -20, -10, 0, 10, 20, 30];

export { ApiError, api };

// The server has no such route (an older server, or the mirror's server side not merged yet).
const missingEndpoint = (e) => e instanceof ApiError && e.status === 404 && e.field === 'path';

// ---------------------------------------------------------------------------------------------
// Bodies

// The bodies of a capture session (its measurement set, at several weight changes).
export async function sessionModel(id, code, weights = DEFAULT_WEIGHTS) {
  const sid = encodeURIComponent(id);
  try {
    return fromContract(await api(`/api/sessions/${sid}/mirror-body?weights=${weights.join(',')}`, { code }));
  } catch (e) {
    if (!missingEndpoint(e)) throw e;
  }
  const { session } = await api(`/api/sessions/${sid}`, { code });
  if (session.state !== 'done') throw new ApiError(409, { message: `session ${id} is not finished yet (${session.state}): measure first`, field: 'session' });
  return modelFromExports(session.sex ?? 'female', session.measurement_set ?? {}, weights);
}

// The bodies of any measurement set (a saved file read by POST /api/measurement-set/import).
export async function setModel(sex, measurements, weights = DEFAULT_WEIGHTS) {
  try {
    return fromContract(await api('/api/mirror-body', { method: 'POST', body: { measurements, sex, weights } }));
  } catch (e) {
    if (!missingEndpoint(e)) throw e;
  }
  return modelFromExports(sex, measurements, weights);
}

// A file the user picked: its text through the server's one measurement-set reader.
export async function importSet(text) {
  return api('/api/measurement-set/import', { method: 'POST', body: text });
}

// An uploaded .glb: shown as it is, one body, no weight variation.
export async function glbModel(buffer) {
  const body = await parseGlb(buffer);
  return { ...body.rig, bodies: [{ pct: 0, weightKg: null, vertices: body.vertices, joints: body.joints }] };
}

// The contract's JSON (docs/api.md "mirror-body") → a mirror model.
export function fromContract(r) {
  const flat = (a, Type) => (a instanceof Array && a.length && a[0] instanceof Array ? Type.from(a.flat()) : Type.from(a));
  const model = {
    sex: r.sex,
    jointNames: r.joint_names,
    parents: r.parents,
    faces: flat(r.faces, Uint32Array),
    skinIndex: flat(r.skin.joints, Uint16Array),
    skinWeight: flat(r.skin.weights, Float32Array),
    bodies: r.bodies.map((b) => ({ pct: b.weight_change_pct, weightKg: b.weight_kg, bmi: b.bmi,
      vertices: Float32Array.from(b.vertices), joints: Float32Array.from(b.joints) })).sort((a, b) => a.pct - b.pct),
  };
  return checkModel(model);
}

// Fallback: one rigged GLB per weight change, built by the server's estimator with the weight
// changed and every other value kept (the lengths); only those weights the server accepts.
async function modelFromExports(sex, measurements, weights) {
  // Only the names the estimator takes (a session's set can hold others, e.g. the floor).
  const { measurements: catalogue } = await api('/api/measurements');
  const known = new Set(catalogue.map((m) => m.name));
  const given = Object.fromEntries(Object.entries(measurements).filter(([n, v]) => known.has(n) && v !== null && v !== undefined));
  const base = given.weight;
  const grid = Number.isFinite(base) ? weights : [0];
  const bodies = await Promise.all(grid.map(async (pct) => {
    const set = { ...given };
    if (Number.isFinite(base)) set.weight = Math.round(base * (1 + pct / 100) * 10) / 10;
    const buffer = await (await api('/api/export/glb', { method: 'POST', body: { sex, regressor: 'auto', measurements: set, force: true }, raw: true })).arrayBuffer();
    return { pct, weightKg: set.weight ?? null, parsed: await parseGlb(buffer) };
  }));
  const { rig } = bodies[0].parsed;
  return checkModel({ ...rig, sex, bodies: bodies.map((b) => ({ pct: b.pct, weightKg: b.weightKg, vertices: b.parsed.vertices, joints: b.parsed.joints })) });
}

// A skinned GLB → rig (names, parents, faces, skin) and rest vertices and joint positions.
async function parseGlb(buffer) {
  const gltf = await new GLTFLoader().parseAsync(buffer, '');
  let mesh = null;
  gltf.scene.traverse((o) => { if (!mesh && o.isSkinnedMesh) mesh = o; });
  if (!mesh) throw new ApiError(400, { message: 'the .glb has no skinned mesh (export it from Caliper with its rig)', field: 'file' });
  gltf.scene.updateMatrixWorld(true);
  const g = mesh.geometry, bones = mesh.skeleton.bones, n = g.attributes.position.count;
  // Vertices in the skeleton's bind space (the mesh's bind matrix is the identity in Caliper's files).
  const vertices = new Float32Array(3 * n), v = new Vector3();
  for (let i = 0; i < n; ++i) v.fromBufferAttribute(g.attributes.position, i).applyMatrix4(mesh.bindMatrix).toArray(vertices, 3 * i);
  const joints = new Float32Array(3 * bones.length), m = new Matrix4();
  mesh.skeleton.boneInverses.forEach((inv, i) => v.setFromMatrixPosition(m.copy(inv).invert()).toArray(joints, 3 * i));
  const skinIndex = new Uint16Array(4 * n), skinWeight = new Float32Array(4 * n);
  for (let i = 0; i < n; ++i) {
    for (let k = 0; k < 4; ++k) {
      skinIndex[4 * i + k] = g.attributes.skinIndex.getComponent(i, k);
      skinWeight[4 * i + k] = g.attributes.skinWeight.getComponent(i, k);
    }
  }
  const faces = g.index ? Uint32Array.from(g.index.array) : Uint32Array.from({ length: n }, (_, i) => i);
  const rig = {
    jointNames: bones.map((b) => b.name),
    parents: bones.map((b) => bones.indexOf(b.parent)),
    faces, skinIndex, skinWeight,
  };
  return { rig, vertices, joints };
}

function checkModel(model) {
  const nv = model.bodies[0]?.vertices.length ?? 0, nj = model.jointNames.length;
  if (!model.bodies.length || nv % 3 || model.skinIndex.length !== (4 * nv) / 3 || model.skinWeight.length !== (4 * nv) / 3 ||
      model.parents.length !== nj || model.bodies.some((b) => b.vertices.length !== nv || b.joints.length !== 3 * nj))
    throw new ApiError(0, { message: 'the mirror bodies disagree in size (vertices, skin or joints)', field: 'bodies' });
  return model;
}

// Blends the bodies at a weight change (pct) into `vertices` and `joints` (preallocated):
// linear between the two neighbouring bodies, clamped to the grid's ends. Returns the pct used.
export function blendBodies(model, pct, vertices, joints) {
  const b = model.bodies;
  pct = Math.min(Math.max(pct, b[0].pct), b[b.length - 1].pct);
  let i = 0;
  while (i < b.length - 2 && b[i + 1].pct < pct) ++i;
  const lo = b[i], hi = b[Math.min(i + 1, b.length - 1)];
  const t = hi.pct === lo.pct ? 0 : (pct - lo.pct) / (hi.pct - lo.pct);
  for (let k = 0; k < vertices.length; ++k) vertices[k] = lo.vertices[k] + t * (hi.vertices[k] - lo.vertices[k]);
  for (let k = 0; k < joints.length; ++k) joints[k] = lo.joints[k] + t * (hi.joints[k] - lo.joints[k]);
  return pct;
}

// ---------------------------------------------------------------------------------------------
// Body-image tasks (participant side)

// Local tasks for a server without the task endpoints: the page's own list, started from the
// page (or a test) with startLocalTask; answers stay in the page and are marked local.
export const localTasks = { tasks: [], current: null, answers: [] };
export function startLocalTask(task) {
  if (localTasks.current) localTasks.current.state = 'abandoned';
  const t = { id: `local-${localTasks.tasks.length + 1}`, kind: 'adjust', instruction: 'how_i_look', start_weight_change_pct: 0,
    range_pct: [-30, 30], ...task, state: 'running', created: new Date().toISOString(), answer: null, local: true };
  localTasks.tasks.push(t);
  localTasks.current = t;
  return t;
}

// The running task, or null. {local: true} on the fallback.
export async function currentTask(sessionId, code) {
  if (!sessionId) return localTasks.current;
  try {
    const r = await api(`/api/sessions/${encodeURIComponent(sessionId)}/body-image-tasks`, { code });
    return r.current ?? null;
  } catch (e) {
    if (!missingEndpoint(e)) throw e;
    return localTasks.current;
  }
}

// Posts an answer; the server's Task comes back once it is stored.
export async function answerTask(sessionId, code, task, answer) {
  if (task.local) {
    if (task.state !== 'running') throw new ApiError(409, { message: `task ${task.id} is not running`, field: 'task' });
    Object.assign(task, { state: 'answered', answer: { ...answer, answered: new Date().toISOString() } });
    localTasks.answers.push(task.answer);
    if (localTasks.current === task) localTasks.current = null;
    return task;
  }
  const r = await api(`/api/sessions/${encodeURIComponent(sessionId)}/body-image-tasks/${encodeURIComponent(task.id)}/answer`,
    { method: 'POST', body: answer, code });
  return r.task;
}
