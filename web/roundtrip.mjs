#!/usr/bin/env node
// Measures the desktop tool's round trip the way the page makes it: POST /api/avatar with new
// values, read the JSON, decode the base64 vertex positions. Run against a running server:
//
//   build/bin/caliper serve --port 8080 &   node web/roundtrip.mjs [http://127.0.0.1:8080] [requests]
//
// Prints median, 95th percentile and max of the client-side round trip and of the server's own
// time (timing_ms.total), in milliseconds, for the default model (R5, values varying per request).
const base = process.argv[2] ?? 'http://127.0.0.1:8080';
const count = Number(process.argv[3] ?? 200);

async function once(i) {
  const body = {
    sex: i % 2 ? 'male' : 'female',
    regressor: 'auto',
    measurements: { stature: 160 + (i % 30), weight: 55 + (i % 25), span: 162 + (i % 30), crotch_height: 74 + (i % 10), hip_breadth: 33 + (i % 6) },
  };
  const t0 = performance.now();
  const res = await fetch(`${base}/api/avatar`, { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(body) });
  if (!res.ok) throw new Error(`HTTP ${res.status}: ${await res.text()}`);
  const j = await res.json();
  const positions = Buffer.from(j.mesh.positions, 'base64');
  const ms = performance.now() - t0;
  if (positions.length !== j.mesh.vertex_count * 12) throw new Error('bad positions');
  return { ms, server: j.timing_ms.total };
}

const stats = (xs) => {
  const s = [...xs].sort((a, b) => a - b);
  const q = (p) => s[Math.min(s.length - 1, Math.floor(p * s.length))];
  return `median ${q(0.5).toFixed(1)}  p95 ${q(0.95).toFixed(1)}  max ${s[s.length - 1].toFixed(1)}`;
};

for (let i = 0; i < 10; ++i) await once(i);  // warm-up (both sexes' regressors, connections)
const client = [], server = [];
for (let i = 0; i < count; ++i) {
  const r = await once(i);
  client.push(r.ms);
  server.push(r.server);
}
console.log(`${count} sequential POST /api/avatar round trips (ms)`);
console.log(`  client (request → decoded mesh): ${stats(client)}`);
console.log(`  server (parse → build → JSON):   ${stats(server)}`);
