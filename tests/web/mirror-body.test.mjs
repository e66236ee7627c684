// Unit tests of the mirror's body source (web/src/mirror-body.js) under plain node: reading the
// contract's mirror-body answer (nested or flat arrays), refusing bodies that disagree in size,
// blending between neighbouring weight changes, and the page's local task stand-in.
// Expected values are written by hand from the tiny bodies below, not taken from the code.
import { webSource } from './web-source.mjs';
const { fromContract, blendBodies, startLocalTask, answerTask, currentTask, localTasks } =
  await webSource('mirror-body.js');

let failures = 0;
function check(ok, what, detail = '') {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}${detail ? ` (${detail})` : ''}`);
  if (!ok) failures += 1;
}
const same = (a, b) => a.length === b.length && Array.from(a).every((x, i) => Math.abs(x - b[i]) < 1e-6);

// Two vertices, one (degenerate) face, two joints; three bodies at −10, 0 and +20 %.
const answer = {
  sex: 'female', stature_cm: 170, weight_kg: 60, rest_pose: 'T',
  joint_names: ['pelvis', 'spine1'], parents: [-1, 0],
  faces: [[0, 1, 1]],
  skin: { joints: [[0, 1, 0, 0], [1, 0, 0, 0]], weights: [[0.5, 0.5, 0, 0], [1, 0, 0, 0]] },
  bodies: [
    { weight_change_pct: 20, weight_kg: 72, bmi: 24.9, vertices: [2, 0, 0, 0, 2, 0], joints: [0, 1, 0, 0, 2, 0] },
    { weight_change_pct: -10, weight_kg: 54, bmi: 18.7, vertices: [0.5, 0, 0, 0, 0.5, 0], joints: [0, 1, 0, 0, 1.5, 0] },
    { weight_change_pct: 0, weight_kg: 60, bmi: 20.8, vertices: [1, 0, 0, 0, 1, 0], joints: [0, 1, 0, 0, 1.6, 0] },
  ],
};

{
  const m = fromContract(answer);
  check(same(m.faces, [0, 1, 1]) && m.faces instanceof Uint32Array, 'nested faces flattened to Uint32Array');
  check(same(m.skinIndex, [0, 1, 0, 0, 1, 0, 0, 0]) && m.skinIndex instanceof Uint16Array, 'skin joints flattened');
  check(same(m.skinWeight, [0.5, 0.5, 0, 0, 1, 0, 0, 0]), 'skin weights flattened');
  check(m.bodies.map((b) => b.pct).join() === '-10,0,20', 'bodies sorted by weight change');
  const flat = fromContract({ ...answer, faces: [0, 1, 1], skin: { joints: [0, 1, 0, 0, 1, 0, 0, 0], weights: [0.5, 0.5, 0, 0, 1, 0, 0, 0] } });
  check(same(flat.faces, [0, 1, 1]) && same(flat.skinWeight, m.skinWeight), 'flat arrays read the same');

  const v = new Float32Array(6), j = new Float32Array(6);
  check(blendBodies(m, 0, v, j) === 0 && same(v, [1, 0, 0, 0, 1, 0]) && same(j, [0, 1, 0, 0, 1.6, 0]), 'a grid point gives its body exactly');
  blendBodies(m, -5, v, j);
  check(same(v, [0.75, 0, 0, 0, 0.75, 0]) && same(j, [0, 1, 0, 0, 1.55, 0]), 'half-way between −10 and 0: the mean of the two');
  blendBodies(m, 15, v, j);
  check(same(v, [1.75, 0, 0, 0, 1.75, 0]), 'three quarters of the way from 0 to +20');
  check(blendBodies(m, 50, v, j) === 20 && same(v, [2, 0, 0, 0, 2, 0]), 'beyond the grid: clamped to its end');
  check(blendBodies(m, -99, v, j) === -10 && same(v, [0.5, 0, 0, 0, 0.5, 0]), 'below the grid: clamped to its start');

  let field = null;
  try { fromContract({ ...answer, bodies: [answer.bodies[0], { ...answer.bodies[1], vertices: [1, 2, 3] }] }); } catch (e) { field = e.field; }
  check(field === 'bodies', 'bodies of different sizes are refused, naming the field', String(field));
  field = null;
  try { fromContract({ ...answer, skin: { joints: [[0, 0, 0, 0]], weights: [[1, 0, 0, 0]] } }); } catch (e) { field = e.field; }
  check(field === 'bodies', 'a skin that does not cover every vertex is refused', String(field));
}

// The local stand-in for the task endpoints: one running task, answered once.
{
  const first = startLocalTask({ kind: 'show', start_weight_change_pct: -20 });
  const t = startLocalTask({ kind: 'adjust', start_weight_change_pct: 10, range_pct: [-20, 20] });
  check(first.state === 'abandoned' && t.state === 'running', 'starting a task abandons the running one');
  check(await currentTask(null, null) === t, 'the running task is the current one');
  const stored = await answerTask(null, null, t, { chosen_weight_change_pct: 4.5, shown_at_s: 1, answered_at_s: 9, adjustments: 3 });
  check(stored.state === 'answered' && stored.answer.chosen_weight_change_pct === 4.5 && localTasks.answers.length === 1, 'an answer is stored with the task');
  check(await currentTask(null, null) === null, 'an answered task is no longer current');
  let status = null;
  try { await answerTask(null, null, t, { chosen_weight_change_pct: 0, shown_at_s: 1, answered_at_s: 2, adjustments: 0 }); } catch (e) { status = e.status; }
  check(status === 409, 'answering it again is refused (409, as the server does)', String(status));
}

console.log(failures ? `${failures} check(s) failed` : 'all checks passed');
process.exit(failures ? 1 : 0);
