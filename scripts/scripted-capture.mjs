// A capture session measured over the HTTP API as a headset would, with no headset: the
// controllers' grips held still where each ISAK step wants them (identity orientation, so heights
// and distances are the grips' own), one trigger hold per request. Used by the kill -9 test
// (scripts/kill-test.mjs) and by the mirror's end-to-end test, which needs a finished session.

// The person the holds describe (metres): what a finished session measures, up to ISAK's rounding.
export const SCRIPTED_PERSON = Object.freeze({
  heights: { stature: 1.70, crotch_height: 0.80 },
  distances: { span: 1.72, hip_breadth: 0.36, arm_length: 0.60 },
});

// Where the two grips are held for a step; repetitions differ by 2 mm (within ISAK's 1.5 %).
export function stepPose(step, repetition) {
  const wobble = 0.002 * repetition;
  const { heights, distances } = SCRIPTED_PERSON;
  if (step.kind === 'floor') return { right: [0.3 * Math.cos(repetition), 0, 0.3 * Math.sin(repetition)], left: [-0.3, 0.9, 0] };
  if (step.kind === 'height') return { right: [0.2, (heights[step.name] ?? 1.2) + wobble, 0.1], left: [-0.3, 0.9, 0] };
  const d = (distances[step.name] ?? 0.4) + wobble;
  return { right: [d / 2, 1.3, 0.2], left: [-d / 2, 1.3, 0.2] };
}

// One trigger hold of 1.2 s then a release, both controllers at 72 frames a second, from t0 (s).
export function holdSamples(t0, where) {
  const samples = [];
  for (let i = 0; i < 100; i++) {
    const t = t0 + i / 72;
    const trigger = i < 87 ? 1 : 0;
    samples.push({ t, hand: 'right', position: where.right, orientation: [0, 0, 0, 1], trigger });
    samples.push({ t, hand: 'left', position: where.left, orientation: [0, 0, 0, 1], trigger: 0 });
  }
  return samples;
}
export const HOLD_SECONDS = 100 / 72 + 0.1;   // one hold and the pause before the next

// A JSON call with the pairing code when given: {status, json}.
export async function call(base, method, path, body, code) {
  const headers = { 'Content-Type': 'application/json' };
  if (code) headers['X-Caliper-Pairing'] = code;
  const r = await fetch(base + path, { method, headers, body: body === undefined ? undefined : JSON.stringify(body) });
  const text = await r.text();
  return { status: r.status, json: text ? JSON.parse(text) : null };
}

// Creates a session (`create`: the POST /api/sessions body; sex and weight_kg make it finish
// without the entries step) and holds every step until it is done. Returns {id, code, session}.
export async function measureSession(base, create = { mode: 'self', steps: 'core', sex: 'female', weight_kg: 60 }) {
  const made = await call(base, 'POST', '/api/sessions', create);
  if (made.status !== 201) throw new Error(`creating a session: ${made.status} ${JSON.stringify(made.json)}`);
  const id = made.json.session.id, code = made.json.pairing_code;
  let session = made.json.session, t = 0, points = 0;
  for (let requests = 0; session.step && requests < 200; requests++) {
    const body = { profile: 'meta-quest-touch-plus', samples: holdSamples(t, stepPose(session.step, points)) };
    t += HOLD_SECONDS;
    const r = await call(base, 'POST', `/api/sessions/${id}/samples`, body, code);
    if (r.status !== 200) throw new Error(`samples: ${r.status} ${JSON.stringify(r.json)}`);
    points += r.json.events.filter((e) => e.type === 'point_accepted').length;
    session = r.json.session;
  }
  if (session.state !== 'done') throw new Error(`the scripted session did not finish: ${JSON.stringify(session).slice(0, 300)}`);
  return { id, code, session };
}
