// The body driver of the virtual mirror (Pujades et al. 2019, Fig. 1; docs/mirror.md): poses an
// SMPL-style skeleton from a WebXR headset and two controller grips so that the user's own avatar
// moves with them. No DOM: the page feeds it poses and reads joint rotations back, and the unit
// tests (tests/web/embodiment.test.mjs) run it under plain node.
//
// Conventions. Everything is in the XR `local-floor` space: metres, +Y up, floor at y = 0. The
// rest skeleton is the model's T-pose, facing +Z, the body's left on +X (SMPL). Each joint's
// output is its world position and its *world rotation relative to the rest pose* (a "delta"):
// a bone whose rest orientation is the identity takes it as is; any other rig converts it with
// its rest orientation. Nothing is rescaled: the avatar has the user's dimensions, so the head is
// put where the headset is and the wrists where the controllers hold them.
//
// Choices (docs/mirror.md "The IK"):
// - head from the headset, minus the eye offset (rest frame, from the avatar's own head);
// - pelvis, spine and collars turn with the head's yaw, with a lag; the neck takes part of the
//   head's turn; the pelvis is placed so the head joint lands exactly on its target, which keeps
//   it under the head and lowers it (bending the knees) when the user crouches;
// - the spine bends (forward, back, sideways) when the head is both ahead of the feet and lower
//   than standing, by as much as both allow: leaning over bends the back, walking (ahead, not
//   lower) moves the body and steps, crouching (lower, not ahead) bends the knees;
// - arms and legs by analytic two-bone IK (law of cosines), elbows pulled down and out, knees
//   forward, clamped just short of full stretch so there is always a valid triangle;
// - a controller that stops tracking eases its arm back to hanging at the side;
// - with WebXR hand tracking, the wrist and the hand's turn come from the tracked wrist and
//   knuckles, and each finger joint of the rig (SMPL-H's 15 per hand) turns to the tracked
//   bone's direction (the avatar's own finger lengths are kept);
// - ankles stay planted on the floor and one foot at a time steps to its place under the pelvis
//   when the pelvis has moved more than 25 cm from it, turned more than 45°, or moved so that
//   the leg would have to stretch 1.5 cm (until then the ankle is lifted along the leg: tiptoe).
// All vectors and quaternions are allocated once here: update() allocates nothing.
import { Quaternion, Vector3 } from 'three';

export const DEFAULTS = Object.freeze({
  // The wrist joint sits this far from the grip's origin along the grip's +Y (WebXR grip space:
  // the origin in the middle of the fist, −Z along the held rod towards the thumb, +X out of the
  // back of the right hand or the palm of the left, so +Y points from the fingers to the wrist).
  wristBehindGrip: 0.07,
  torsoYawLag: 0.25,         // s: time constant of the pelvis following the head's yaw
  maxHeadTwist: Math.PI * 50 / 180,   // the torso is pulled along past this head–torso yaw
  neckShare: 0.4,            // share of the head's rotation (from the torso) taken by the neck
  armFadeTime: 0.5,          // s: an arm eases to rest, or back to its controller, in this time
  maxStretch: 0.015,         // m: or when its leg would have to be this much longer to reach it
  stepDistance: 0.25,        // m: a foot this far from its place under the pelvis steps
  stepTurn: Math.PI / 4,     // rad: or when the pelvis has turned this much since it was planted
  stepDuration: 0.35,        // s
  stepHeight: 0.07,          // m: the foot's lift at mid-step
  reachMargin: 1e-4,         // the two-bone chains stop this fraction short of full stretch
  maxBendForward: Math.PI * 80 / 180,   // rad: how far the spine bends forward,
  maxBendBack: Math.PI * 25 / 180,      // back
  maxBendSide: Math.PI * 35 / 180,      // and sideways
});

// WebXR Hand Input's 25 joints, in the order XRHand iterates them (and fillPoses fills them).
export const XR_HAND_JOINTS = Object.freeze(['wrist',
  'thumb-metacarpal', 'thumb-phalanx-proximal', 'thumb-phalanx-distal', 'thumb-tip',
  ...['index-finger', 'middle-finger', 'ring-finger', 'pinky-finger'].flatMap((f) =>
    ['metacarpal', 'phalanx-proximal', 'phalanx-intermediate', 'phalanx-distal', 'tip'].map((j) => `${f}-${j}`))]);

// The wrist joint in grip space, metres (for tests that place controllers for a wrist).
export const wristInGrip = (options = DEFAULTS) => [0, options.wristBehindGrip, 0];

// SMPL joint names the driver needs (the SMPL-H finger joints and any others follow their parents).
const NEEDED = ['pelvis', 'spine1', 'spine2', 'spine3', 'neck', 'head', 'left_collar', 'right_collar',
  'left_shoulder', 'right_shoulder', 'left_elbow', 'right_elbow', 'left_wrist', 'right_wrist',
  'left_hip', 'right_hip', 'left_knee', 'right_knee', 'left_ankle', 'right_ankle'];

const SIDES = ['left', 'right'];
const TORSO = ['pelvis', 'spine1', 'spine2', 'spine3', 'left_collar', 'right_collar'];
// Share of the spine's bend each torso joint takes, cumulative from the pelvis (the collars ride
// on spine3): a bend spread along the back rather than a hinge at the hips.
const BEND_SHARE = [0.25, 0.5, 0.75, 1, 1, 1];
// SMPL-H's finger joints (name suffixes 1–3, from the knuckle out) and the XR_HAND_JOINTS indices
// of the four points that bound their three bones: joint k's bone runs from xr[k] to xr[k + 1].
const FINGERS = [
  { name: 'thumb', xr: [1, 2, 3, 4] },       // SMPL-H's thumb1 sits at the thumb's metacarpal base
  { name: 'index', xr: [6, 7, 8, 9] },
  { name: 'middle', xr: [11, 12, 13, 14] },
  { name: 'ring', xr: [16, 17, 18, 19] },
  { name: 'pinky', xr: [21, 22, 23, 24] },
];
const XR_WRIST = 0, XR_INDEX_KNUCKLE = 6, XR_MIDDLE_KNUCKLE = 11, XR_PINKY_KNUCKLE = 21;
const HALF_TURN_Y = new Quaternion(0, 1, 0, 0);    // the body faces +Z, an XR viewer looks along −Z
// Rest hand → grip frame. In the T-pose a hand's fingers point out along ±X, its palm faces down
// (−Y) and its thumb forward (+Z); holding a controller, the fingers point along the grip's −Y
// (from the wrist round the rod), the palm faces the rod (−X for the right hand, +X for the
// left) and the thumb lies along −Z. Columns: where the rest hand's X, Y and Z go in grip space.
const GRIP_TO_HAND = {
  right: new Quaternion().setFromRotationMatrix(rotation3([0, 1, 0], [1, 0, 0], [0, 0, -1])),
  left: new Quaternion().setFromRotationMatrix(rotation3([0, -1, 0], [-1, 0, 0], [0, 0, -1])),
};

function rotation3(x, y, z) {
  // A Matrix4-like object for setFromRotationMatrix (elements column-major, 16 long).
  return { elements: [x[0], x[1], x[2], 0, y[0], y[1], y[2], 0, z[0], z[1], z[2], 0, 0, 0, 0, 1] };
}

// Where the eyes are in the rest pose relative to the head joint (rest frame, metres), from the
// avatar's own surface: eye level 7% of the stature below the top of the head (ANSUR: the
// vertex-to-pupil height of adults is 11–13 cm); in depth, the eyeball's centre of rotation,
// about 13 mm behind the front of the eye (the eye is about 24 mm long), the front of the eye
// being the most forward surface 2–4.5 cm to either side of the midline at that level. Not the
// face's midline: the nose stands in front of the eyes by an amount that differs from face to
// face (on the built-in body it moved the eyes 4 mm when the nose was redrawn).
// vertices: flat x,y,z of the rest mesh; headJoint: [x,y,z].
export function eyeOffsetFromBody(vertices, headJoint) {
  let top = -Infinity, bottom = Infinity;
  for (let i = 1; i < vertices.length; i += 3) { top = Math.max(top, vertices[i]); bottom = Math.min(bottom, vertices[i]); }
  const eyeY = top - 0.07 * (top - bottom);
  let front = -Infinity;
  for (let i = 0; i < vertices.length; i += 3) {
    const across = Math.abs(vertices[i] - headJoint[0]);
    if (across > 0.02 && across < 0.045 && Math.abs(vertices[i + 1] - eyeY) < 0.01) front = Math.max(front, vertices[i + 2]);
  }
  if (!Number.isFinite(front)) front = headJoint[2] + 0.1;
  return [0, eyeY - headJoint[1], front - 0.013 - headJoint[2]];
}

// A pose as the page hands it over: position and orientation, reused every frame.
class TrackedPose {
  constructor() {
    this.position = new Vector3();
    this.orientation = new Quaternion();
    this.tracked = false;
    // Hand tracking: the 25 joints' positions (XR_HAND_JOINTS order, flat x,y,z), and the rest
    // hand's turn onto the tracked one; `position` is then the wrist itself, not a grip.
    this.fromJoints = false;
    this.joints = new Float32Array(3 * XR_HAND_JOINTS.length);
    this.handQ = new Quaternion();
  }
}

// rig: {jointNames: [...], parents: [...] (−1 for a root), restJoints: flat x,y,z (T-pose)};
// eyeOffset: [x,y,z] (eyeOffsetFromBody); options: DEFAULTS to override.
export class BodyDriver {
  constructor(rig, eyeOffset, options = {}) {
    this.options = { ...DEFAULTS, ...options };
    const n = rig.jointNames.length;
    if (rig.parents.length !== n || rig.restJoints.length !== 3 * n) throw new Error('rig: joint_names, parents and joints disagree in length');
    this.names = rig.jointNames;
    this.parents = Int32Array.from(rig.parents);
    this.index = Object.fromEntries(rig.jointNames.map((name, i) => [name, i]));
    for (const name of NEEDED) if (!(name in this.index)) throw new Error(`rig: no joint named ${name}`);
    this.order = topologicalOrder(this.parents);
    this.rest = Array.from({ length: n }, () => new Vector3());
    this.eyeOffset = new Vector3();
    this.positions = Array.from({ length: n }, () => new Vector3());   // world
    this.rotations = Array.from({ length: n }, () => new Quaternion()); // world delta
    this.explicit = new Uint8Array(n);        // joints the solver set this frame; others inherit
    const j = this.index;
    this.torso = TORSO.map((name) => j[name]);
    this.limbs = {};
    for (const side of SIDES) {
      const at = (part) => j[`${side}_${part}`];
      this.limbs[side] = {
        shoulder: at('shoulder'), elbow: at('elbow'), wrist: at('wrist'), hip: at('hip'), knee: at('knee'), ankle: at('ankle'),
        arm: [0, 0], leg: [0, 0],                         // bone lengths, set by setRest
        sign: side === 'left' ? 1 : -1,                  // +1 on the body's left (+X)
        other: side === 'left' ? 'right' : 'left',
      };
    }
    // The finger chains this rig has (all three joints of a finger, SMPL-H names), per side.
    this.fingers = {};
    for (const side of SIDES) {
      this.fingers[side] = FINGERS.map((f) => ({ xr: f.xr, joints: [1, 2, 3].map((k) => j[`${side}_${f.name}${k}`] ?? -1) }))
        .filter((f) => f.joints.every((i) => i >= 0));
      const knuckle = (f) => j[`${side}_${f}1`] ?? -1;
      this.limbs[side].knuckles = [knuckle('index'), knuckle('middle'), knuckle('pinky')];
    }
    this.setRest(rig.restJoints, eyeOffset);
    this.head = new TrackedPose();
    this.hands = { left: new TrackedPose(), right: new TrackedPose() };
    this.armWeight = { left: 0, right: 0 };            // 1: following the controller, 0: at rest
    this.lastWrist = { left: new Vector3(), right: new Vector3() };
    this.lastHand = { left: new Quaternion(), right: new Quaternion() };
    this.bodyYaw = 0;
    this.started = false;
    this.feet = {
      left: { planted: new Vector3(), from: new Vector3(), yaw: 0, fromYaw: 0, t: -1 },
      right: { planted: new Vector3(), from: new Vector3(), yaw: 0, fromYaw: 0, t: -1 },
    };
    this.steps = 0;

    // Scratch, allocated once.
    this.q = [new Quaternion(), new Quaternion(), new Quaternion(), new Quaternion()];
    this.v = Array.from({ length: 10 }, () => new Vector3());
    this.limbScratch = Array.from({ length: 5 }, () => new Vector3());
    this.yawQ = new Quaternion();
    this.wristOffset = new Vector3().fromArray(wristInGrip(this.options));
    this.headQ = new Quaternion();
    this.bendAxis = new Vector3();
    this.bendAngle = 0;
    this.m3 = [new Vector3(), new Vector3(), new Vector3(), new Vector3(), new Vector3(), new Vector3()];
    this.basis = { elements: new Float64Array(16) };
  }

  // A new rest skeleton (the body changed shape, e.g. its weight): flat x,y,z and the eye offset.
  setRest(restJoints, eyeOffset) {
    if (restJoints.length !== 3 * this.rest.length) throw new Error('rig: the rest joints changed in number');
    for (let i = 0; i < this.rest.length; ++i) this.rest[i].fromArray(restJoints, 3 * i);
    this.eyeOffset.fromArray(eyeOffset);
    const r = this.rest;
    for (let k = 0; k < SIDES.length; ++k) {
      const l = this.limbs[SIDES[k]];
      l.arm[0] = r[l.shoulder].distanceTo(r[l.elbow]);
      l.arm[1] = r[l.elbow].distanceTo(r[l.wrist]);
      l.leg[0] = r[l.hip].distanceTo(r[l.knee]);
      l.leg[1] = r[l.knee].distanceTo(r[l.ankle]);
    }
    // The segments from the pelvis up to the head, each with its height and the share of the
    // bend its joint takes (the neck's: what the neck keeps of the spine's when the head is upright).
    const j = this.index, up = ['pelvis', 'spine1', 'spine2', 'spine3', 'neck', 'head'];
    this.spineChain = up.slice(0, -1).map((name, k) => ({
      height: r[j[up[k + 1]]].y - r[j[name]].y,
      share: name === 'neck' ? 1 - this.options.neckShare : BEND_SHARE[k],
    }));
    if (!this.started) for (let i = 0; i < r.length; ++i) this.positions[i].copy(r[i]);
  }

  setHead(position, orientation) {
    if (!finitePose(position, orientation)) return;     // keep the last good head
    this.head.position.set(position.x, position.y, position.z);
    this.head.orientation.set(orientation.x, orientation.y, orientation.z, orientation.w).normalize();
    this.head.tracked = true;
  }

  // A grip pose, or null when the controller is not tracked this frame.
  setHand(side, position, orientation) {
    const hand = this.hands[side];
    hand.fromJoints = false;
    if (!position || !finitePose(position, orientation)) { hand.tracked = false; return; }
    hand.position.set(position.x, position.y, position.z);
    hand.orientation.set(orientation.x, orientation.y, orientation.z, orientation.w).normalize();
    hand.tracked = true;
  }

  // A tracked hand (WebXR Hand Input): the 25 joint poses as XRFrame.fillPoses writes them
  // (column-major 4×4 matrices, XR_HAND_JOINTS order; only the positions are used), or null when
  // the hand is not tracked this frame. The wrist goes where the tracked wrist is; the hand turns
  // so that its knuckles line up with the tracked ones; the fingers follow in update().
  setHandJoints(side, matrices) {
    const hand = this.hands[side], J = hand.joints;
    hand.fromJoints = false;
    hand.tracked = false;
    if (!matrices || matrices.length < 16 * XR_HAND_JOINTS.length) return;
    for (let k = 0; k < XR_HAND_JOINTS.length; ++k) {
      const x = matrices[16 * k + 12], y = matrices[16 * k + 13], z = matrices[16 * k + 14];
      if (!Number.isFinite(x + y + z)) return;
      J[3 * k] = x; J[3 * k + 1] = y; J[3 * k + 2] = z;
    }
    const knuckles = this.limbs[side].knuckles, r = this.rest, w = this.limbs[side].wrist;
    if (knuckles[0] < 0 || knuckles[1] < 0 || knuckles[2] < 0) return;   // a rig without fingers cannot be turned by them
    const m = this.m3, a = m[0], b = m[1], c = m[2], d = m[3], e = m[4], f = m[5];
    // Rest frame: wrist → middle knuckle (along the hand), pinky → index knuckle (across it).
    a.subVectors(r[knuckles[1]], r[w]);
    b.subVectors(r[knuckles[0]], r[knuckles[2]]);
    c.fromArray(J, 3 * XR_MIDDLE_KNUCKLE).sub(d.fromArray(J, 3 * XR_WRIST));
    e.fromArray(J, 3 * XR_INDEX_KNUCKLE).sub(f.fromArray(J, 3 * XR_PINKY_KNUCKLE));
    if (!frameTurn(a, b, c, e, this.basis, hand.handQ)) return;
    hand.position.fromArray(J, 3 * XR_WRIST);
    hand.fromJoints = true;
    hand.tracked = true;
  }

  // Where the wrist joint goes for a grip pose (the test checks the avatar against this).
  wristTarget(side, out) {
    const hand = this.hands[side];
    return out.copy(this.wristOffset).applyQuaternion(hand.orientation).add(hand.position);
  }

  jointIndex(name) { return this.index[name] ?? -1; }

  // One frame: dt in seconds since the last (clamped, so a stall does not teleport the lags).
  update(dt) {
    if (!this.head.tracked) return;
    dt = Number.isFinite(dt) ? Math.min(Math.max(dt, 0), 0.1) : 0;
    this.explicit.fill(0);
    this.solveTorso(dt);
    this.forward();
    this.solveFeet(dt);
    this.solveArm('left', dt);
    this.solveArm('right', dt);
    this.solveFingers('left');
    this.solveFingers('right');
    this.solveLeg('left');
    this.solveLeg('right');
    this.forward();
    this.started = true;
  }

  // Head rotation, torso yaw with its lag, the neck's share, and the pelvis under the head.
  solveTorso(dt) {
    const o = this.options, j = this.index, hf = this.v[0], hu = this.v[1], t1 = this.v[2];
    this.headQ.copy(this.head.orientation).multiply(HALF_TURN_Y);
    // The facing direction: the view's forward on the floor, helped by the head's up vector
    // when looking down (the forward vector alone vanishes there).
    hf.set(0, 0, -1).applyQuaternion(this.head.orientation);
    hu.set(0, 1, 0).applyQuaternion(this.head.orientation);
    const down = Math.max(0, -hf.y);
    const fx = hf.x + hu.x * down, fz = hf.z + hu.z * down;
    if (fx * fx + fz * fz > 1e-8) {
      const target = Math.atan2(fx, fz);         // yaw turning the body's +Z onto (fx, fz)
      if (!this.started) this.bodyYaw = target;
      let diff = wrapAngle(target - this.bodyYaw);
      diff *= 1 - Math.exp(-dt / o.torsoYawLag);
      this.bodyYaw = wrapAngle(this.bodyYaw + diff);
      const lagging = wrapAngle(target - this.bodyYaw);
      if (Math.abs(lagging) > o.maxHeadTwist) this.bodyYaw = wrapAngle(target - Math.sign(lagging) * o.maxHeadTwist);
    }
    this.yawQ.setFromAxisAngle(t1.set(0, 1, 0), this.bodyYaw);
    const R = this.rotations;
    const target = this.v[3].copy(this.eyeOffset).applyQuaternion(this.headQ).negate().add(this.head.position);
    this.spineBend(target);
    const bent = this.q[3];
    for (let k = 0; k < this.torso.length; ++k) {
      bent.setFromAxisAngle(this.bendAxis, this.bendAngle * BEND_SHARE[k]).multiply(this.yawQ);
      this.setRotation(this.torso[k], bent);
    }
    this.setRotation(j.neck, this.q[0].copy(bent).slerp(this.headQ, o.neckShare));   // bent: spine3's
    this.setRotation(j.head, this.headQ);
    // Rotations of the joints between the pelvis and the head are known: place the pelvis so
    // the chain ends at the head target (headset minus the eye offset).
    let cursor = j.head;
    while (cursor !== j.pelvis && cursor >= 0) {
      const parent = this.parents[cursor];
      t1.subVectors(this.rest[cursor], this.rest[parent]).applyQuaternion(R[parent]);
      target.sub(t1);
      cursor = parent;
    }
    this.positions[j.pelvis].copy(target);
  }

  // How far the spine bends, and about which horizontal axis, for the head joint at `head`: the
  // head's lean beyond its standing place above the planted feet, and its drop below standing
  // height, each asks for an angle (with the pelvis staying over the feet and at its height);
  // the spine takes the smaller, within the limits for that direction. Whatever lean is left
  // moves the pelvis (and the feet step); whatever drop is left bends the knees. Before the feet
  // stand (the first frame) the spine is straight.
  spineBend(head) {
    this.bendAngle = 0;
    if (!this.started) return;
    const o = this.options, j = this.index, r = this.rest;
    const lf = this.limbs.left, rt = this.limbs.right, stand = this.v[6], lean = this.v[7];
    // Where the head joint stands above the planted feet: the rest pose's offset from the ankles'
    // midpoint, turned with the body.
    stand.copy(r[j.head]).sub(this.v[8].addVectors(r[lf.ankle], r[rt.ankle]).multiplyScalar(0.5)).applyQuaternion(this.yawQ);
    stand.add(this.v[8].addVectors(this.feet.left.planted, this.feet.right.planted).multiplyScalar(0.5));
    lean.subVectors(head, stand);
    const drop = r[j.head].y - head.y;
    lean.y = 0;
    const reach = lean.length();
    if (!(reach > 1e-4) || !(drop > 0)) return;
    const forward = this.v[9].set(0, 0, 1).applyQuaternion(this.yawQ);
    const cos = lean.dot(forward) / reach, sin = Math.sqrt(Math.max(0, 1 - cos * cos));
    const along = cos >= 0 ? o.maxBendForward : o.maxBendBack;
    const limit = 1 / Math.hypot(cos / along, sin / o.maxBendSide);   // an ellipse through the limits
    const chain = this.spineChain;
    this.bendAngle = Math.min(bendFor(chain, reach, false, limit), bendFor(chain, drop, true, limit));
    this.bendAxis.set(0, 1, 0).cross(lean).normalize();    // turning +Y towards the lean
  }

  solveArm(side, dt) {
    const o = this.options, hand = this.hands[side], limb = this.limbs[side];
    // The arm's weight ramps linearly over armFadeTime and is eased (smoothstep); on the very
    // first frame an arm with a controller snaps to it rather than swinging up from rest.
    const goal = hand.tracked ? 1 : 0, step = dt / o.armFadeTime;
    const w0 = this.armWeight[side];
    this.armWeight[side] = !this.started ? goal : goal > w0 ? Math.min(goal, w0 + step) : Math.max(goal, w0 - step);
    const weight = this.armWeight[side] * this.armWeight[side] * (3 - 2 * this.armWeight[side]);
    if (hand.tracked && hand.fromJoints) {
      this.lastWrist[side].copy(hand.position);
      this.lastHand[side].copy(hand.handQ);
    } else if (hand.tracked) {
      this.wristTarget(side, this.lastWrist[side]);
      this.lastHand[side].copy(hand.orientation).multiply(GRIP_TO_HAND[side]);
    }
    const shoulder = this.positions[limb.shoulder];
    const a = limb.arm[0], b = limb.arm[1];
    // Hanging at rest: the wrist a little out from below the shoulder.
    const rest = this.v[4].set(0.12 * limb.sign, -(a + b) * 0.97, 0.03).applyQuaternion(this.yawQ).add(shoulder);
    const wrist = rest.lerp(this.lastWrist[side], weight);
    const pole = this.v[5].set(0.5 * limb.sign, -1, -0.35).applyQuaternion(this.yawQ);
    this.solveLimb(limb.shoulder, limb.elbow, limb.wrist, wrist, a, b, pole);
    // The hand: the controller's orientation, eased like the arm.
    const handQ = this.q[1].copy(this.rotations[limb.elbow]).slerp(this.lastHand[side], weight);
    this.setRotation(limb.wrist, handQ);
  }

  // A tracked hand's fingers: each finger joint turns its bone (rest direction, as its parent
  // turned it) onto the tracked bone's direction, keeping the parent's twist. A finger's last
  // joint has no child in the rig: its rest direction is the previous bone's.
  solveFingers(side) {
    const hand = this.hands[side];
    if (!hand.tracked || !hand.fromJoints) return;
    const J = hand.joints, rest = this.rest, R = this.rotations, from = this.m3[0], to = this.m3[1], tip = this.m3[2];
    const fingers = this.fingers[side];
    for (let f = 0; f < fingers.length; ++f) {
      const finger = fingers[f], js = finger.joints;
      for (let k = 0; k < 3; ++k) {
        const i = js[k];
        if (k < 2) from.subVectors(rest[js[k + 1]], rest[i]);
        else from.subVectors(rest[i], rest[js[1]]);
        from.applyQuaternion(R[this.parents[i]]).normalize();
        to.fromArray(J, 3 * finger.xr[k + 1]).sub(tip.fromArray(J, 3 * finger.xr[k]));
        if (to.lengthSq() < 1e-12 || from.lengthSq() < 0.5) { this.setRotation(i, R[this.parents[i]]); continue; }
        to.normalize();
        this.setRotation(i, this.q[2].setFromUnitVectors(from, to).multiply(R[this.parents[i]]));
      }
    }
  }

  // Two-bone IK: root → mid → end reaching `target`, the mid joint bent towards `pole`. Sets the
  // world rotations of root and mid (the swing from their rest direction, parent's twist kept)
  // and the positions of mid and end.
  solveLimb(root, mid, end, target, a, b, pole) {
    const s = this.limbScratch, u = s[0], w = s[1], e = s[2], t1 = s[3], t2 = s[4];
    const P = this.positions, R = this.rotations, rest = this.rest;
    const S = P[root];
    u.subVectors(target, S);
    let d = u.length();
    if (d < 1e-6) u.copy(pole); else u.divideScalar(d);
    u.normalize();
    const m = this.options.reachMargin;
    d = Math.min(Math.max(d, Math.abs(a - b) * (1 + m) + 1e-6), (a + b) * (1 - m));
    const cosA = Math.min(1, Math.max(-1, (a * a + d * d - b * b) / (2 * a * d)));
    const sinA = Math.sqrt(1 - cosA * cosA);
    // The bend direction: the pole's part perpendicular to the limb (any perpendicular if none).
    w.copy(pole).addScaledVector(u, -pole.dot(u));
    if (w.lengthSq() < 1e-10) w.set(u.y, -u.x, 0);
    if (w.lengthSq() < 1e-10) w.set(0, u.z, -u.y);
    w.normalize();
    e.copy(S).addScaledVector(u, a * cosA).addScaledVector(w, a * sinA);      // the mid joint
    // Root: swing its rest direction (as its parent turned it) onto root→mid.
    const parentQ = R[this.parents[root]];
    t1.subVectors(rest[mid], rest[root]).applyQuaternion(parentQ).normalize();
    t2.subVectors(e, S).normalize();
    this.setRotation(root, this.q[2].setFromUnitVectors(t1, t2).multiply(parentQ));
    P[mid].copy(e);
    t1.subVectors(rest[end], rest[mid]).applyQuaternion(R[root]).normalize();
    t2.copy(S).addScaledVector(u, d).sub(e).normalize();
    this.setRotation(mid, this.q[2].setFromUnitVectors(t1, t2).multiply(R[root]));
    P[end].copy(e).addScaledVector(t2, b);
  }

  // Feet: planted until their place under the pelvis is 25 cm away or 45° turned, then one at a
  // time steps there along a low arc.
  solveFeet(dt) {
    const o = this.options;
    for (let k = 0; k < SIDES.length; ++k) {
      const side = SIDES[k], foot = this.feet[side], otherSide = this.limbs[side].other;
      const home = this.footHome(side, this.v[6]);
      if (!this.started) { foot.planted.copy(home); foot.yaw = this.bodyYaw; continue; }
      const other = this.feet[otherSide];
      if (foot.t < 0 && other.t < 0) {
        const dx = home.x - foot.planted.x, dz = home.z - foot.planted.z;
        if (Math.hypot(dx, dz) > o.stepDistance || Math.abs(wrapAngle(this.bodyYaw - foot.yaw)) > o.stepTurn ||
            this.overstretch(side) > o.maxStretch) {
          // Only the foot farther from home steps now; the other follows next frame if needed.
          const otherHome = this.footHome(otherSide, this.v[7]);
          const otherFar = Math.hypot(otherHome.x - other.planted.x, otherHome.z - other.planted.z);
          if (Math.hypot(dx, dz) >= otherFar || Math.abs(wrapAngle(this.bodyYaw - foot.yaw)) > o.stepTurn ||
              this.overstretch(side) >= this.overstretch(otherSide)) {
            foot.from.copy(foot.planted);
            foot.fromYaw = foot.yaw;
            foot.t = 0;
            this.steps += 1;
          }
        }
      }
      if (foot.t >= 0) {
        foot.t = Math.min(1, foot.t + dt / o.stepDuration);
        const s = foot.t * foot.t * (3 - 2 * foot.t);
        foot.planted.lerpVectors(foot.from, home, s);
        foot.planted.y = home.y + o.stepHeight * Math.sin(Math.PI * foot.t);
        foot.yaw = wrapAngle(foot.fromYaw + wrapAngle(this.bodyYaw - foot.fromYaw) * s);
        if (foot.t >= 1) { foot.t = -1; foot.planted.y = home.y; }
      }
    }
  }

  // How much longer than it is the leg would have to be to reach its planted ankle (the pelvis
  // follows the head: moving sideways or up on tiptoe stretches the standing legs).
  overstretch(side) {
    const limb = this.limbs[side], p = this.index.pelvis;
    const hip = this.v[8].subVectors(this.rest[limb.hip], this.rest[p]).applyQuaternion(this.yawQ).add(this.positions[p]);
    return hip.distanceTo(this.feet[side].planted) - limb.leg[0] - limb.leg[1];
  }

  // Where a foot's ankle stands when the person stands straight under the pelvis.
  footHome(side, out) {
    const pelvis = this.index.pelvis, ankle = this.rest[this.limbs[side].ankle];
    out.subVectors(ankle, this.rest[pelvis]).applyQuaternion(this.yawQ).add(this.positions[pelvis]);
    out.y = ankle.y;
    return out;
  }

  solveLeg(side) {
    const limb = this.limbs[side], a = limb.leg[0], b = limb.leg[1], foot = this.feet[side];
    const knees = this.v[8].set(0, 0, 1).applyQuaternion(this.yawQ);
    this.solveLimb(limb.hip, limb.knee, limb.ankle, foot.planted, a, b, knees);
    this.setRotation(limb.ankle, this.q[3].setFromAxisAngle(this.v[9].set(0, 1, 0), foot.yaw));
  }

  setRotation(i, q) {
    this.rotations[i].copy(q);
    this.explicit[i] = 1;
  }

  // Forward kinematics from the pelvis: joints the solver did not set take their parent's rotation.
  forward() {
    const P = this.positions, R = this.rotations, t = this.v[9];
    for (let k = 0; k < this.order.length; ++k) {
      const i = this.order[k], p = this.parents[i];
      if (i === this.index.pelvis) continue;   // placed by solveTorso, whatever is above it
      if (p < 0) {
        if (i !== this.index.pelvis) { P[i].copy(this.rest[i]); R[i].identity(); }
        continue;
      }
      if (!this.explicit[i]) R[i].copy(R[p]);
      P[i].copy(t.subVectors(this.rest[i], this.rest[p]).applyQuaternion(R[p]).add(P[p]));
    }
  }
}

function finitePose(p, q) {
  return p && q && Number.isFinite(p.x) && Number.isFinite(p.y) && Number.isFinite(p.z) &&
    Number.isFinite(q.x) && Number.isFinite(q.y) && Number.isFinite(q.z) && Number.isFinite(q.w) &&
    q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w > 1e-6;
}

// How far the spine chain (segments of `height`, each turned by its `share` of `angle`) moves
// the head: ahead (sines) or down (1 − cosines).
function chainMove(chain, angle, down) {
  let sum = 0;
  for (let k = 0; k < chain.length; ++k) {
    const a = chain[k].share * angle;
    sum += chain[k].height * (down ? 1 - Math.cos(a) : Math.sin(a));
  }
  return sum;
}

// The bend angle in [0, max] at which the chain moves the head by `amount` (ahead, or down);
// both grow with the angle up to a right angle, so bisection finds it.
function bendFor(chain, amount, down, max) {
  if (chainMove(chain, max, down) <= amount) return max;
  let lo = 0, hi = max;
  for (let i = 0; i < 20; ++i) {      // to 80°/2^20: well under a thousandth of a degree
    const mid = 0.5 * (lo + hi);
    if (chainMove(chain, mid, down) < amount) lo = mid; else hi = mid;
  }
  return 0.5 * (lo + hi);
}

// The rotation taking the frame built from (a, b) onto the one built from (c, d): each frame is
// x = a, z = a × b, y = z × x, normalised. Writes it into `out`; false when either is degenerate.
function frameTurn(a, b, c, d, scratch, out) {
  const restQ = basisQuaternion(a, b, scratch, out);
  if (!restQ) return false;
  const rx = restQ.x, ry = restQ.y, rz = restQ.z, rw = restQ.w;
  if (!basisQuaternion(c, d, scratch, out)) return false;
  // out = tracked · rest⁻¹
  const ix = -rx, iy = -ry, iz = -rz, iw = rw;
  const ox = out.x, oy = out.y, oz = out.z, ow = out.w;
  out.set(ow * ix + ox * iw + oy * iz - oz * iy, ow * iy - ox * iz + oy * iw + oz * ix,
    ow * iz + ox * iy - oy * ix + oz * iw, ow * iw - ox * ix - oy * iy - oz * iz);
  return true;
}

function basisQuaternion(a, b, scratch, out) {
  const ax = a.x, ay = a.y, az = a.z, la = Math.hypot(ax, ay, az);
  let zx = ay * b.z - az * b.y, zy = az * b.x - ax * b.z, zz = ax * b.y - ay * b.x;
  const lz = Math.hypot(zx, zy, zz);
  if (!(la > 1e-9) || !(lz > 1e-9 * la)) return null;
  const xx = ax / la, xy = ay / la, xz = az / la;
  zx /= lz; zy /= lz; zz /= lz;
  const yx = zy * xz - zz * xy, yy = zz * xx - zx * xz, yz = zx * xy - zy * xx;
  const m = scratch.elements;
  m[0] = xx; m[1] = xy; m[2] = xz; m[4] = yx; m[5] = yy; m[6] = yz; m[8] = zx; m[9] = zy; m[10] = zz;
  return out.setFromRotationMatrix(scratch);
}

function wrapAngle(a) {
  return a - 2 * Math.PI * Math.floor((a + Math.PI) / (2 * Math.PI));
}

// Parents before children, whatever the order of the rig's joints.
function topologicalOrder(parents) {
  const order = [], seen = new Uint8Array(parents.length);
  const visit = (i, depth) => {
    if (seen[i]) return;
    if (depth > parents.length) throw new Error('rig: the parents form a cycle');
    if (parents[i] >= 0) visit(parents[i], depth + 1);
    seen[i] = 1;
    order.push(i);
  };
  for (let i = 0; i < parents.length; ++i) {
    if (parents[i] >= parents.length) throw new Error(`rig: joint ${i} has no parent ${parents[i]}`);
    visit(i, 0);
  }
  return order;
}
