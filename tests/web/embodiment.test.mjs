// Unit tests of the mirror's body driver (web/src/embodiment.js) under plain node, on a hand-built
// SMPL skeleton of a 1.7 m person: reach, reach limits, elbow and knee directions, full stretch,
// a lost controller, planted feet and steps, a crouch, leaning over (the spine bends) against
// walking (it does not), a tracked hand's wrist and fingers (WebXR Hand Input, on the same
// skeleton with SMPL-H's finger joints), and no NaN on random or broken input.
// Expected values come from the geometry of the set-up (targets placed by the test, bone lengths
// of the hand-built rig), never from the driver's own output.
import { webSource } from './web-source.mjs';
const { BodyDriver, XR_HAND_JOINTS, wristInGrip } = await webSource('embodiment.js');

// SMPL's 24 joints, T-pose, facing +Z, the body's left on +X, metres, feet on y = 0.
const JOINTS = {
  pelvis: [0, 0.95, 0], left_hip: [0.09, 0.87, 0], right_hip: [-0.09, 0.87, 0], spine1: [0, 1.06, -0.01],
  left_knee: [0.1, 0.49, 0.01], right_knee: [-0.1, 0.49, 0.01], spine2: [0, 1.19, 0],
  left_ankle: [0.11, 0.08, -0.03], right_ankle: [-0.11, 0.08, -0.03], spine3: [0, 1.25, 0.01],
  left_foot: [0.12, 0.02, 0.1], right_foot: [-0.12, 0.02, 0.1], neck: [0, 1.46, -0.02],
  left_collar: [0.07, 1.39, -0.01], right_collar: [-0.07, 1.39, -0.01], head: [0, 1.55, 0.01],
  left_shoulder: [0.18, 1.41, -0.02], right_shoulder: [-0.18, 1.41, -0.02],
  left_elbow: [0.44, 1.41, -0.03], right_elbow: [-0.44, 1.41, -0.03],
  left_wrist: [0.69, 1.41, -0.02], right_wrist: [-0.69, 1.41, -0.02],
  left_hand: [0.77, 1.4, -0.02], right_hand: [-0.77, 1.4, -0.02],
};
const NAMES = Object.keys(JOINTS);
const PARENTS = [-1, 0, 0, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 9, 9, 12, 13, 14, 16, 17, 18, 19, 20, 21];
const RIG = { jointNames: NAMES, parents: PARENTS, restJoints: NAMES.flatMap((n) => JOINTS[n]) };
const EYES = [0, 0.07, 0.08];           // eyes 7 cm above and 8 cm ahead of the head joint
const dist = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
const UPPER_ARM = dist(JOINTS.left_shoulder, JOINTS.left_elbow), FOREARM = dist(JOINTS.left_elbow, JOINTS.left_wrist);
const THIGH = dist(JOINTS.left_hip, JOINTS.left_knee), SHIN = dist(JOINTS.left_knee, JOINTS.left_ankle);

let failures = 0;
function check(ok, what, detail = '') {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}${detail ? ` (${detail})` : ''}`);
  if (!ok) failures += 1;
}

const IDENTITY = { x: 0, y: 0, z: 0, w: 1 };
// The grip position that puts the wrist at w when the grip has the identity orientation: the
// wrist's offset in grip space taken off (the driver's documented constant).
const W = wristInGrip();
const gripFor = (w) => ({ x: w[0] - W[0], y: w[1] - W[1], z: w[2] - W[2] });
// A headset looking along −Z (the user faces −Z, so the avatar's left is the user's left: −X... 
// the body turns half around: its +Z faces −Z and its left (+X) goes to −X).
const STAND_EYES = { x: 0, y: JOINTS.head[1] + EYES[1], z: -(JOINTS.head[2] + EYES[2]) };
const pos = (d, name) => d.positions[d.jointIndex(name)].toArray();
const p3 = (x, y, z) => ({ x, y, z });

function driver(options) {
  const d = new BodyDriver(RIG, EYES, options);
  d.setHead(STAND_EYES, IDENTITY);
  return d;
}
// n frames at 90 Hz with the current inputs.
function run(d, n = 1) { for (let i = 0; i < n; ++i) d.update(1 / 90); }
const allFinite = (d) => d.positions.every((p) => Number.isFinite(p.x + p.y + p.z)) &&
  d.rotations.every((q) => Number.isFinite(q.x + q.y + q.z + q.w));
function boneLengthsKept(d) {
  let worst = 0;
  for (let i = 1; i < NAMES.length; ++i) {
    const rest = dist(JOINTS[NAMES[i]], JOINTS[NAMES[PARENTS[i]]]);
    worst = Math.max(worst, Math.abs(d.positions[i].distanceTo(d.positions[PARENTS[i]]) - rest));
  }
  return worst;
}

// 1. The head joint is where the headset is, minus the eye offset turned with the head.
{
  const d = driver();
  run(d);
  // Facing −Z, the rest-frame eye offset (0, 0.07, 0.08) points to (0, 0.07, −0.08) in the world.
  const expected = [STAND_EYES.x, STAND_EYES.y - 0.07, STAND_EYES.z + 0.08];
  check(dist(pos(d, 'head'), expected) < 1e-6, 'head joint at the headset minus the eye offset', `${(dist(pos(d, 'head'), expected) * 1000).toFixed(3)} mm`);
  // Standing straight at the rest eye height: the pelvis at its rest height, the feet on the floor.
  check(Math.abs(pos(d, 'pelvis')[1] - JOINTS.pelvis[1]) < 1e-6, 'standing: pelvis at its rest height');
  check(Math.abs(pos(d, 'left_ankle')[1] - JOINTS.left_ankle[1]) < 1e-6 && Math.abs(pos(d, 'right_ankle')[1] - JOINTS.right_ankle[1]) < 1e-6,
    'standing: ankles at their rest height above the floor');
  // The body faces the user's way: its left shoulder is on the user's left (−X when facing −Z).
  check(pos(d, 'left_shoulder')[0] < -0.1 && pos(d, 'right_shoulder')[0] > 0.1, 'the body turns to face where the headset looks');
  check(boneLengthsKept(d) < 1e-6, 'bone lengths kept (nothing rescaled)');
}

// 2. Reachable targets: the wrist lands on the controller's wrist point.
{
  const d = driver();
  d.setHand('left', p3(-0.3, 1.2, -0.4), IDENTITY);
  d.setHand('right', p3(0.3, 1.2, -0.4), IDENTITY);
  run(d, 180);     // controllers that appear are eased in
  let worst = 0, elbowsDown = 0, elbowsOut = 0, n = 0;
  const rng = seeded(7);
  for (let i = 0; i < 300; ++i) {
    const side = i % 2 ? 'left' : 'right';
    const s = pos(d, `${side}_shoulder`);
    // A direction in front of the body (−Z), within 0.35–0.95 of the arm's reach.
    const dir = [rng() * 2 - 1, rng() * 1.6 - 0.8, -0.3 - rng()];
    const len = Math.hypot(...dir), r = (0.35 + 0.6 * rng()) * (UPPER_ARM + FOREARM);
    const wrist = dir.map((c, k) => s[k] + (c / len) * r);
    d.setHand(side, gripFor(wrist), IDENTITY);
    run(d, 2);
    worst = Math.max(worst, dist(pos(d, `${side}_wrist`), wrist));
    // Elbow below the shoulder–wrist line and outside it (the user's left is −X).
    const e = pos(d, `${side}_elbow`);
    const mid = s.map((c, k) => c + (wrist[k] - c) * (UPPER_ARM / (UPPER_ARM + FOREARM)));
    // (for targets in front of the chest; reaching down, the elbow goes back and out)
    if (Math.abs(dir[1] / len) < 0.5) {
      if (e[1] < mid[1] + 1e-6) elbowsDown += 1;
      if ((side === 'left' ? -1 : 1) * (e[0] - mid[0]) > -1e-6) elbowsOut += 1;
      n += 1;
    }
  }
  check(worst < 1e-4, 'reachable targets: wrist on target', `worst ${(worst * 1000).toFixed(4)} mm over 300`);
  check(elbowsDown === n, 'elbows point down', `${elbowsDown}/${n}`);
  check(elbowsOut >= n * 0.9, 'elbows point out', `${elbowsOut}/${n}`);
  check(boneLengthsKept(d) < 1e-5, 'arm bone lengths kept while reaching');
}

// 3. Out of reach and at exactly full stretch: the arm points at the target, straight, no NaN.
{
  const d = driver();
  d.setHand('right', p3(0.3, 1.2, -0.4), IDENTITY);
  run(d, 180);
  const s = pos(d, 'right_shoulder');
  for (const factor of [1, 1.0001, 1.5, 10]) {
    const r = factor * (UPPER_ARM + FOREARM);
    const wrist = [s[0] + r * 0.6, s[1] + r * 0.0, s[2] - r * 0.8];
    d.setHand('right', gripFor(wrist), IDENTITY);
    run(d, 2);
    const w = pos(d, 'right_wrist'), reach = dist(w, s);
    const along = ((w[0] - s[0]) * 0.6 + (w[2] - s[2]) * -0.8) / reach;
    check(allFinite(d), `target at ${factor}× the arm's length: no NaN`);
    check(reach <= UPPER_ARM + FOREARM + 1e-9 && reach > (UPPER_ARM + FOREARM) * 0.999, `target at ${factor}× the arm's length: arm at full stretch`, `${reach.toFixed(5)} m of ${(UPPER_ARM + FOREARM).toFixed(5)}`);
    check(along > 0.9999, `target at ${factor}× the arm's length: arm points at it`);
  }
  // A target on the shoulder itself (zero distance) and one at the elbow's length.
  for (const r of [0, 0.001, Math.abs(UPPER_ARM - FOREARM)]) {
    d.setHand('right', gripFor([s[0] + r, s[1], s[2]]), IDENTITY);
    run(d, 2);
    check(allFinite(d) && boneLengthsKept(d) < 1e-5, `target ${r} m from the shoulder: no NaN, bones kept`);
  }
}

// 4. A controller lost: the arm eases to hanging at the side, smoothly, and comes back.
{
  const d = driver();
  const s0 = (() => { run(d); return pos(d, 'left_shoulder'); })();
  const held = [s0[0] - 0.1, s0[1], s0[2] - 0.4];
  d.setHand('left', gripFor(held), IDENTITY);
  run(d, 180);     // a controller that appears is eased in
  check(dist(pos(d, 'left_wrist'), held) < 1e-4, 'tracked: the wrist holds the controller', `${(dist(pos(d, 'left_wrist'), held) * 1000).toFixed(3)} mm`);
  d.setHand('left', null, null);
  let prev = pos(d, 'left_wrist'), jump = 0;
  for (let i = 0; i < 180; ++i) {
    run(d);
    const w = pos(d, 'left_wrist');
    jump = Math.max(jump, dist(w, prev));
    prev = w;
  }
  const s = pos(d, 'left_shoulder'), w = pos(d, 'left_wrist');
  check(w[1] < s[1] - 0.85 * (UPPER_ARM + FOREARM), 'lost for 2 s: the arm hangs at the side', `wrist ${(s[1] - w[1]).toFixed(3)} m below the shoulder`);
  check(Math.abs(w[2] - s[2]) < 0.1, 'lost: the wrist hangs beside the body, not in front');
  check(jump < 0.03, 'lost: the arm eases down (no jump)', `largest step per frame ${(jump * 100).toFixed(2)} cm`);
  check(allFinite(d), 'lost: no NaN');
  d.setHand('left', gripFor(held), IDENTITY);
  run(d, 180);
  check(dist(pos(d, 'left_wrist'), held) < 0.005, 'found again: the arm returns to the controller');
}

// 5. Feet stay planted for small moves and step after larger ones; a crouch bends the knees.
{
  const d = driver();
  run(d, 5);
  const ankle0 = pos(d, 'left_ankle');
  // 6 cm sideways: the hand-built legs (1.3 mm short of straight at rest) reach the planted
  // ankles only 4 mm too short, under the 1.5 cm that makes a foot step.
  d.setHead(p3(STAND_EYES.x + 0.06, STAND_EYES.y, STAND_EYES.z), IDENTITY);
  run(d, 90);
  const a1 = pos(d, 'left_ankle');
  check(d.steps === 0 && Math.hypot(a1[0] - ankle0[0], a1[2] - ankle0[2]) < 0.005 && a1[1] - ankle0[1] < 0.01,
    '6 cm sideways: the feet stay where they stand (lifted < 1 cm)', `${d.steps} steps, ankle moved ${(dist(a1, ankle0) * 100).toFixed(2)} cm`);
  // 15 cm sideways: the leg would have to stretch more than 1.5 cm: a step.
  d.setHead(p3(STAND_EYES.x + 0.15, STAND_EYES.y, STAND_EYES.z), IDENTITY);
  run(d, 90);
  check(d.steps >= 1 && Math.abs(pos(d, 'left_ankle')[1] - JOINTS.left_ankle[1]) < 1e-6, '15 cm sideways: a step, and both feet back on the floor', `${d.steps} steps`);
  check(dist(pos(d, 'head'), [STAND_EYES.x + 0.15, STAND_EYES.y - 0.07, STAND_EYES.z + 0.08]) < 1e-6, 'moving: the head stays on its target');
  d.setHead(p3(STAND_EYES.x + 0.45, STAND_EYES.y, STAND_EYES.z), IDENTITY);
  run(d, 180);
  const pelvis = pos(d, 'pelvis');
  check(d.steps >= 2, '45 cm sideways: the feet step', `${d.steps} steps`);
  check(Math.abs((pos(d, 'left_ankle')[0] + pos(d, 'right_ankle')[0]) / 2 - pelvis[0]) < 0.02, 'after the steps the feet stand under the pelvis');
  check(Math.abs(pos(d, 'left_ankle')[1] - JOINTS.left_ankle[1]) < 1e-6, 'after the steps the feet are back on the floor');
  // Turning 90°: the feet turn too.
  const steps = d.steps;
  const turn = { x: 0, y: Math.sin(Math.PI / 4), z: 0, w: Math.cos(Math.PI / 4) };
  d.setHead(p3(STAND_EYES.x + 0.45, STAND_EYES.y, STAND_EYES.z), turn);
  run(d, 270);
  check(d.steps > steps, 'turning 90°: the feet step round');
  // Crouch: the eyes 30 cm lower; the ankles stay on the floor, the knees bend forward.
  const c = driver();
  run(c, 5);
  c.setHead(p3(STAND_EYES.x, STAND_EYES.y - 0.3, STAND_EYES.z), IDENTITY);
  run(c, 30);
  const hip = pos(c, 'left_hip'), knee = pos(c, 'left_knee'), ankle = pos(c, 'left_ankle');
  check(Math.abs(ankle[1] - JOINTS.left_ankle[1]) < 1e-6, 'crouch: the ankles stay on the floor');
  check(Math.abs(pos(c, 'pelvis')[1] - (JOINTS.pelvis[1] - 0.3)) < 1e-6, 'crouch: the pelvis is 30 cm lower');
  const kneeForward = -(knee[2] - (hip[2] + ankle[2]) / 2);    // the body faces −Z
  check(kneeForward > 0.1, 'crouch: the knees bend forward', `${(kneeForward * 100).toFixed(1)} cm`);
  check(Math.abs(dist(hip, knee) - THIGH) < 1e-6 && Math.abs(dist(knee, ankle) - SHIN) < 1e-6, 'crouch: leg lengths kept');
}

// 6. Random poses and broken input: never a NaN, bones always kept.
{
  const d = driver();
  const rng = seeded(1234);
  let ok = true, worstBone = 0;
  const q = () => {
    const v = [rng() - 0.5, rng() - 0.5, rng() - 0.5, rng() - 0.5];
    const n = Math.hypot(...v);
    return { x: v[0] / n, y: v[1] / n, z: v[2] / n, w: v[3] / n };
  };
  const bad = [NaN, Infinity, -Infinity];
  for (let i = 0; i < 20000; ++i) {
    const kind = i % 10;
    const head = p3(rng() * 4 - 2, rng() * 2.2, rng() * 4 - 2);
    d.setHead(head, kind === 3 ? { x: Math.SQRT1_2, y: 0, z: 0, w: -Math.SQRT1_2 } : q());  // 3: looking straight down
    for (const side of ['left', 'right']) {
      if (kind === 5) d.setHand(side, null, null);
      else if (kind === 7) d.setHand(side, p3(bad[i % 3], 1, 0), q());
      else if (kind === 8) d.setHand(side, p3(head.x, head.y, head.z), { x: 0, y: 0, z: 0, w: 0 });
      else d.setHand(side, p3(head.x + rng() * 3 - 1.5, rng() * 2.5, head.z + rng() * 3 - 1.5), q());
    }
    if (kind === 9) d.setHead(p3(NaN, 1, 1), q());
    d.update(kind === 6 ? NaN : rng() * 0.05);
    if (!allFinite(d)) { ok = false; break; }
    worstBone = Math.max(worstBone, boneLengthsKept(d));
  }
  check(ok, '20000 random and broken poses: no NaN');
  check(worstBone < 1e-4, '20000 random poses: bone lengths kept', `worst ${(worstBone * 1000).toFixed(4)} mm`);
  let threw = false;
  try { new BodyDriver({ jointNames: ['pelvis'], parents: [-1], restJoints: [0, 1, 0] }, EYES); } catch (e) { threw = /no joint named/.test(e.message); }
  check(threw, 'a rig without the SMPL joints is refused with the missing joint named');
}

// 7. Leaning over against walking. Leaning: the head 30 cm ahead of where it stands and 12 cm
// lower; the spine bends forward, the pelvis stays over the feet, no step. Walking: the head
// 30 cm ahead at standing height; the spine stays upright and the feet step.
{
  const horizontal = (a, b) => Math.hypot(a[0] - b[0], a[2] - b[2]);
  // The trunk's tilt from vertical: pelvis → spine3, degrees.
  const tilt = (d) => {
    const p = pos(d, 'pelvis'), s3 = pos(d, 'spine3');
    return Math.atan2(horizontal(s3, p), s3[1] - p[1]) * 180 / Math.PI;
  };
  const restTilt = Math.atan2(Math.hypot(JOINTS.spine3[0] - JOINTS.pelvis[0], JOINTS.spine3[2] - JOINTS.pelvis[2]),
    JOINTS.spine3[1] - JOINTS.pelvis[1]) * 180 / Math.PI;
  const lean = driver();
  run(lean, 5);
  const pelvis0 = pos(lean, 'pelvis'), ankle0 = pos(lean, 'left_ankle');
  lean.setHead(p3(STAND_EYES.x, STAND_EYES.y - 0.12, STAND_EYES.z - 0.3), IDENTITY);   // ahead = −Z
  run(lean, 90);
  const bentBy = tilt(lean);
  const ahead = pelvis0[2] - pos(lean, 'spine3')[2];
  check(bentBy > 15 && ahead > 0, 'leaning over: the spine bends forward', `trunk ${bentBy.toFixed(1)}° from vertical`);
  check(horizontal(pos(lean, 'pelvis'), pelvis0) < 0.02, 'leaning over: the pelvis stays over the feet',
    `moved ${(horizontal(pos(lean, 'pelvis'), pelvis0) * 100).toFixed(1)} cm`);
  check(lean.steps === 0 && dist(pos(lean, 'left_ankle'), ankle0) < 1e-6, 'leaning over: the feet stay planted', `${lean.steps} steps`);
  check(dist(pos(lean, 'head'), [STAND_EYES.x, STAND_EYES.y - 0.12 - 0.07, STAND_EYES.z - 0.3 + 0.08]) < 1e-6, 'leaning over: the head stays on its target');
  check(boneLengthsKept(lean) < 1e-6, 'leaning over: bone lengths kept');
  // Leaning back is limited: the head far behind and low bends the spine at most 25°.
  const back = driver();
  run(back, 5);
  back.setHead(p3(STAND_EYES.x, STAND_EYES.y - 0.3, STAND_EYES.z + 0.5), IDENTITY);
  run(back, 90);
  check(back.bendAngle <= Math.PI * 25 / 180 + 1e-9 && back.bendAngle > Math.PI * 20 / 180, 'leaning back: the bend stops at its limit', `${(back.bendAngle * 180 / Math.PI).toFixed(1)}°`);
  const walk = driver();
  run(walk, 5);
  walk.setHead(p3(STAND_EYES.x, STAND_EYES.y, STAND_EYES.z - 0.3), IDENTITY);
  run(walk, 90);
  check(Math.abs(tilt(walk) - restTilt) < 0.01, 'walking: the spine stays upright', `trunk ${tilt(walk).toFixed(2)}°, ${restTilt.toFixed(2)}° at rest`);
  check(walk.steps >= 1, 'walking: the feet step', `${walk.steps} steps`);
}

let handBench = null;   // the rig with fingers and a tracked hand, for --bench
// 8. A tracked hand (WebXR Hand Input). The rig gains SMPL-H's finger joints; the user's hand is
// the rig's own hand scaled by 1.15 (a longer hand than the avatar's), its middle finger curled
// 50° at each joint and the thumb 20°, turned and moved in front of the body. The avatar's wrist
// goes to the tracked wrist, each finger bone points along the tracked bone, its lengths stay.
{
  const FINGER_JOINTS = {};
  const lanes = { thumb: [[0.715, 1.39, 0.03], [0.745, 1.385, 0.055], [0.77, 1.385, 0.07]],
    index: [[0.785, 1.405, 0.02], [0.825, 1.405, 0.02], [0.85, 1.405, 0.02]],
    middle: [[0.79, 1.405, 0], [0.835, 1.405, 0], [0.862, 1.405, 0]],
    ring: [[0.785, 1.405, -0.02], [0.825, 1.405, -0.02], [0.85, 1.405, -0.02]],
    pinky: [[0.775, 1.405, -0.038], [0.805, 1.405, -0.038], [0.825, 1.405, -0.038]] };
  const names = [...NAMES], parents = [...PARENTS];
  for (const side of ['left', 'right']) {
    for (const [finger, points] of Object.entries(lanes)) {
      points.forEach((p, k) => {
        const name = `${side}_${finger}${k + 1}`;
        FINGER_JOINTS[name] = side === 'left' ? p : [-p[0], p[1], p[2]];
        parents.push(k === 0 ? names.indexOf(`${side}_wrist`) : names.length - 1);
        names.push(name);
      });
    }
  }
  const ALL = { ...JOINTS, ...FINGER_JOINTS };
  const rigH = { jointNames: names, parents, restJoints: names.flatMap((n) => ALL[n]) };
  // The user's hand in its own rest: XR points from the rig's joints (metacarpal halfway from
  // the wrist to the knuckle, the tip one last bone further), scaled about the wrist.
  const side = 'right', sign = -1, wrist = ALL[`${side}_wrist`];
  const sub = (a, b) => a.map((x, k) => x - b[k]), addv = (a, b) => a.map((x, k) => x + b[k]);
  const scaleAbout = (p) => addv(wrist, sub(p, wrist).map((x) => 1.15 * x));
  const fingerPoints = (finger) => {
    const j = [1, 2, 3].map((k) => ALL[`${side}_${finger}${k}`]);
    const tip = addv(j[2], sub(j[2], j[1]));
    if (finger === 'thumb') return [...j, tip];
    return [j[0].map((x, k) => (x + wrist[k]) / 2), ...j, tip];
  };
  // Curl: turn the finger's points beyond joint k about the hand's across axis (Z: the thumb's
  // side is +Z) by `angle`, towards the palm (−Y).
  const curl = (pts, from, angle) => pts.map((p, i) => {
    if (i <= from) return p;
    const o = pts[from], v = sub(p, o);
    const c = Math.cos(angle), s = Math.sin(angle);
    // Rotating about Z: +X (the left hand's fingers) goes to −Y; the right hand's fingers point −X.
    const x = v[0] * c + sign * v[1] * s * -1, y = -sign * v[0] * s * -1 + v[1] * c;
    return addv(o, [x, y, v[2]]);
  });
  let xr = [wrist];
  for (const finger of ['thumb', 'index', 'middle', 'ring', 'pinky']) {
    let pts = fingerPoints(finger);
    const base = finger === 'thumb' ? 0 : 1;   // the knuckle
    const angle = finger === 'middle' ? 50 : finger === 'thumb' ? 20 : 0;
    for (let k = base; k < base + 3; ++k) pts = curl(pts, k, angle * Math.PI / 180);
    xr.push(...pts);
  }
  xr = xr.map(scaleAbout);
  check(xr.length === XR_HAND_JOINTS.length, 'the test builds all 25 WebXR hand joints');
  // Then the whole hand turned 40° about a tilted axis and put in front of the body.
  const axis = [0.3, 0.8, -0.52], n = Math.hypot(...axis), half = 20 * Math.PI / 180;
  const Q = [...axis.map((c) => (c / n) * Math.sin(half)), Math.cos(half)];
  const turn = (v) => {
    const [x, y, z, w] = Q, t = [2 * (y * v[2] - z * v[1]), 2 * (z * v[0] - x * v[2]), 2 * (x * v[1] - y * v[0])];
    return [v[0] + w * t[0] + (y * t[2] - z * t[1]), v[1] + w * t[1] + (z * t[0] - x * t[2]), v[2] + w * t[2] + (x * t[1] - y * t[0])];
  };
  // In front of the user (who faces −Z, the avatar turned half round: its right on +X).
  const place = [0.25, 1.2, -0.35];
  const tracked = xr.map((p) => addv(place, turn(sub(p, wrist)).map((x, k) => [-1, 1, -1][k] * x)));
  const matrices = new Float32Array(16 * 25);
  tracked.forEach((p, k) => { matrices[16 * k] = matrices[16 * k + 5] = matrices[16 * k + 10] = matrices[16 * k + 15] = 1; matrices.set(p, 16 * k + 12); });

  handBench = { rig: rigH, matrices };
  const d = new BodyDriver(rigH, EYES);
  d.setHead(STAND_EYES, IDENTITY);
  d.setHandJoints('right', matrices);
  run(d, 120);
  check(dist(pos(d, 'right_wrist'), tracked[0]) < 1e-4, 'hand tracking: the wrist is on the tracked wrist', `${(dist(pos(d, 'right_wrist'), tracked[0]) * 1000).toFixed(3)} mm`);
  const angle = (a, b) => {
    const dot = a.reduce((s, x, k) => s + x * b[k], 0) / (Math.hypot(...a) * Math.hypot(...b));
    return Math.acos(Math.min(1, Math.max(-1, dot))) * 180 / Math.PI;
  };
  const XR_OF = { thumb: [1, 2, 3], index: [6, 7, 8], middle: [11, 12, 13], ring: [16, 17, 18], pinky: [21, 22, 23] };
  let worst = 0, worstLength = 0;
  for (const [finger, xi] of Object.entries(XR_OF)) {
    for (let k = 0; k < 2; ++k) {
      const a = pos(d, `${side}_${finger}${k + 1}`), b = pos(d, `${side}_${finger}${k + 2}`);
      worst = Math.max(worst, angle(sub(b, a), sub(tracked[xi[k + 1]], tracked[xi[k]])));
      worstLength = Math.max(worstLength, Math.abs(dist(a, b) - dist(ALL[`${side}_${finger}${k + 1}`], ALL[`${side}_${finger}${k + 2}`])));
    }
  }
  check(worst < 0.5, 'hand tracking: every finger bone points along the tracked bone', `worst ${worst.toFixed(3)}°`);
  check(worstLength < 1e-6, 'hand tracking: the avatar keeps its own finger lengths');
  const middleBend = angle(sub(pos(d, 'right_middle2'), pos(d, 'right_middle1')), sub(pos(d, 'right_middle3'), pos(d, 'right_middle2')));
  check(Math.abs(middleBend - 50) < 1, 'hand tracking: a curled finger is curled by as much', `${middleBend.toFixed(2)}° between its bones`);
  // The palm: wrist → middle knuckle along the tracked one.
  const palm = angle(sub(pos(d, 'right_middle1'), pos(d, 'right_wrist')), sub(tracked[11], tracked[0]));
  check(palm < 1, 'hand tracking: the hand turns with the tracked hand', `${palm.toFixed(3)}°`);
  // A hand with a lost joint (NaN) is not tracked: the arm eases back to hanging at the side.
  const broken = Float32Array.from(matrices);
  broken[16 * 7 + 13] = NaN;
  d.setHandJoints('right', broken);
  run(d, 90);
  check(!d.hands.right.tracked && pos(d, 'right_wrist')[1] < pos(d, 'right_shoulder')[1] - 0.4 && allFinite(d),
    'hand tracking: a hand with a joint lost is let go (the arm hangs, no NaN)');
  // Random joints (degenerate hands too: all joints at one point, collinear knuckles): no NaN.
  const rng = seeded(99), noise = new Float32Array(16 * 25);
  let finite = true;
  for (let i = 0; i < 3000 && finite; ++i) {
    for (let k = 0; k < 25; ++k) {
      const p = i % 7 === 0 ? [0.3, 1.2, -0.3] : i % 11 === 0 ? [0.3 + 0.01 * k, 1.2, -0.3] : [rng() - 0.5, 1 + rng(), rng() - 0.5];
      noise.set(p, 16 * k + 12);
    }
    d.setHandJoints(i % 2 ? 'left' : 'right', noise);
    d.update(rng() * 0.03);
    finite = allFinite(d);
  }
  check(finite, 'hand tracking: 3000 random and degenerate hands, no NaN');
  // The same hand on a rig without finger joints: not followed (nothing to turn), no error.
  const plain = driver();
  plain.setHandJoints('right', matrices);
  run(plain, 5);
  check(!plain.hands.right.tracked && allFinite(plain), 'hand tracking on a rig without fingers: ignored, no NaN');
}

// A small seeded generator (mulberry32): the random cases are the same on every run.
function seeded(seed) {
  let a = seed >>> 0;
  return () => {
    a = (a + 0x6D2B79F5) >>> 0;
    let t = a;
    t = Math.imul(t ^ (t >>> 15), t | 1);
    t ^= t + Math.imul(t ^ (t >>> 7), t | 61);
    return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
  };
}

// --bench: the driver's cost per frame (docs/performance.md "Mirror"), the head swaying and
// dipping (the spine bends), either both controllers tracked on SMPL's 24 joints, or both hands
// tracked (25 joints each) on the rig with SMPL-H's fingers; the garbage collections meanwhile
// show whether frames allocate.
async function bench(label, d, feedHands) {
  const frames = 200000;
  const head = p3(0, STAND_EYES.y, STAND_EYES.z);
  const turn = { x: 0, y: 0, z: 0, w: 1 };
  const step = (i) => {
    head.x = 0.1 * Math.sin(i * 0.01);
    head.y = STAND_EYES.y - 0.08 * (1 - Math.cos(i * 0.007));
    head.z = STAND_EYES.z - 0.1 * (1 - Math.cos(i * 0.007));
    turn.y = 0.3 * Math.sin(i * 0.003); turn.w = Math.sqrt(1 - turn.y * turn.y);
    d.setHead(head, turn);
    feedHands(i);
    d.update(1 / 90);
  };
  for (let i = 0; i < 20000; ++i) step(i);    // warm up (JIT)
  const { PerformanceObserver } = await import('node:perf_hooks');
  let collections = 0;
  const observer = new PerformanceObserver((list) => { collections += list.getEntries().length; });
  observer.observe({ entryTypes: ['gc'] });
  const t0 = process.hrtime.bigint();
  for (let i = 0; i < frames; ++i) step(i);
  const ns = Number(process.hrtime.bigint() - t0) / frames;
  await new Promise((r) => setTimeout(r, 50));
  observer.disconnect();
  console.log(`bench: ${(ns / 1000).toFixed(2)} µs per update over ${frames} frames (${label}); ${collections} garbage collections meanwhile`);
}
if (process.argv.includes('--bench')) {
  const d = driver(), l = p3(-0.3, 1.2, -0.4), r = p3(0.3, 1.2, -0.4);
  await bench('24 joints, controllers', d, (i) => {
    l.y = 1.2 + 0.1 * Math.sin(i * 0.02); r.z = -0.4 + 0.1 * Math.cos(i * 0.02);
    d.setHand('left', l, IDENTITY); d.setHand('right', r, IDENTITY);
  });
  const h = new BodyDriver(handBench.rig, EYES), moving = Float32Array.from(handBench.matrices);
  await bench('54 joints, both hands tracked', h, (i) => {
    for (let k = 0; k < 25; ++k) moving[16 * k + 13] = handBench.matrices[16 * k + 13] + 0.1 * Math.sin(i * 0.02);
    h.setHandJoints('right', moving);
    h.setHandJoints('left', moving);     // the right hand's joints for the left too: the cost, not the pose
  });
}

console.log(failures ? `${failures} check(s) failed` : 'all checks passed');
process.exit(failures ? 1 : 0);
