// A bounded load test of `caliper serve` on loopback (docs/reliability.md "Load").
//
// Starts its own server (or uses --url with --pid), then runs for --duration seconds:
//   - desktop clients: each a person at the desktop tool changing a value: one POST /api/avatar
//     (the page's request: regressor auto, mesh, random measurements) every --interval ms on
//     average (±30 % jitter), waiting for each answer as the page does; one in ten is a GET
//     /api/measurements (a page load's catalogue) instead;
//   - headset clients (--headsets of the --clients): each a capture session on a headset: the
//     session is created and paired, then a batch of controller samples (~7 frames of both
//     controllers) is POSTed every 100 ms, as the capture page does;
//   - optionally --slowloris N attack connections that send a request's header one byte every
//     5 s (and reconnect when closed; from 127.0.2.x, or all from --slowloris-from ADDRESS),
//     --flood N idle connections (10 per address, reopened when closed), and --memory, which first creates --sessions sessions and
//     asks for --regressors distinct custom regressors, printing the server's RSS as it goes.
// Each client keeps one connection alive and binds its own loopback address (127.0.1.x), so the
// server's per-address connection cap does not throttle the load itself; attackers use 127.0.2.x.
//
// Prints connections, duration, requests, throughput, p50/p95/p99/max latency per kind and in
// all, 5xx and errors, and the server's RSS before and after. Exit 1 if any request failed.
//
//   node scripts/load-test.mjs --caliper build/bin/caliper [--clients 64] [--headsets 8]
//        [--duration 30] [--interval 1000] [--slowloris 0] [--memory --sessions 600 --regressors 200]
import { spawn } from 'node:child_process';
import { readFileSync, mkdtempSync, rmSync } from 'node:fs';
import http from 'node:http';
import net from 'node:net';
import { tmpdir } from 'node:os';
import { join } from 'node:path';

const args = process.argv.slice(2);
function option(name, fallback) {
  const i = args.indexOf(`--${name}`);
  if (i < 0) return fallback;
  if (typeof fallback === 'boolean') return true;
  return typeof fallback === 'number' ? Number(args[i + 1]) : args[i + 1];
}
const config = {
  caliper: option('caliper', 'build/bin/caliper'),
  url: option('url', ''),
  pid: option('pid', 0),
  clients: option('clients', 64),
  headsets: option('headsets', 8),
  duration: option('duration', 30),
  interval: option('interval', 1000),
  slowloris: option('slowloris', 0),
  slowlorisFrom: option('slowloris-from', ''),
  flood: option('flood', 0),
  memory: option('memory', false),
  sessions: option('sessions', 600),
  regressors: option('regressors', 200),
};
for (const [k, v] of Object.entries(config))
  if (typeof v === 'number' && !(v >= 0)) throw new Error(`--${k} must be a number >= 0, got ${v}`);
if (config.headsets > config.clients) throw new Error('--headsets must not exceed --clients');

// ---- The server ----

function startServer() {
  const data = mkdtempSync(join(tmpdir(), 'caliper-load-'));
  return new Promise((resolve, reject) => {
    const child = spawn(config.caliper, ['serve', '--port', '0', '--quiet', '--data', data], { stdio: ['ignore', 'pipe', 'pipe'] });
    let out = '', err = '';
    const timer = setTimeout(() => reject(new Error(`server did not start: ${err}`)), 120000);
    child.stdout.on('data', (d) => {
      out += d;
      const m = /http:\/\/([\d.]+):(\d+)\//.exec(out);
      if (m) {
        clearTimeout(timer);
        resolve({ child, data, url: `http://${m[1]}:${m[2]}`, pid: child.pid });
      }
    });
    child.stderr.on('data', (d) => { err += d; });
    child.on('exit', (code) => { clearTimeout(timer); reject(new Error(`server exited (${code}): ${err}`)); });
  });
}

function rssMiB(pid) {
  const status = readFileSync(`/proc/${pid}/status`, 'utf8');
  const kb = (key) => Number(new RegExp(`${key}:\\s+(\\d+)`).exec(status)[1]);
  return { rss: kb('VmRSS') / 1024, peak: kb('VmHWM') / 1024 };
}

// ---- Requests ----

function request(agent, base, method, path, body, headers = {}) {
  const url = new URL(path, base);
  const payload = body === undefined ? undefined : JSON.stringify(body);
  return new Promise((resolve) => {
    const started = process.hrtime.bigint();
    const req = http.request({ host: url.hostname, port: url.port, path: url.pathname + url.search, method, agent,
      headers: { ...headers, ...(payload ? { 'Content-Type': 'application/json', 'Content-Length': Buffer.byteLength(payload) } : {}) } },
    (res) => {
      const chunks = [];
      res.on('data', (c) => chunks.push(c));
      res.on('end', () => resolve({ status: res.statusCode, body: Buffer.concat(chunks).toString(),
        ms: Number(process.hrtime.bigint() - started) / 1e6 }));
      res.on('error', (e) => resolve({ error: e.message, ms: Number(process.hrtime.bigint() - started) / 1e6 }));
    });
    req.setTimeout(30000, () => req.destroy(new Error('timeout after 30 s')));
    req.on('error', (e) => resolve({ error: e.message, ms: Number(process.hrtime.bigint() - started) / 1e6 }));
    req.end(payload);
  });
}

const random = (lo, hi) => lo + Math.random() * (hi - lo);
const sleep = (ms) => new Promise((r) => setTimeout(r, Math.max(0, ms)));

function avatarBody() {
  const sex = Math.random() < 0.5 ? 'female' : 'male';
  const stature = random(150, 195);
  const measurements = { stature: +stature.toFixed(1), weight: +random(50, 100).toFixed(1) };
  if (Math.random() < 0.6) measurements.span = +(stature * random(0.98, 1.05)).toFixed(1);
  if (Math.random() < 0.4) measurements.crotch_height = +(stature * random(0.44, 0.48)).toFixed(1);
  return { sex, regressor: 'auto', noise: 'exact', measurements };  // the desktop page's defaults
}

// One frame of both controllers, held still at the given tips (grip poses, metres).
function frames(t0, count, trigger) {
  const samples = [];
  for (let i = 0; i < count; i++) {
    const t = t0 + i / 72;
    samples.push({ t, hand: 'right', position: [0.3, 1.0 + 0.001 * Math.sin(t), 0.2], orientation: [0, 0, 0, 1], trigger });
    samples.push({ t, hand: 'left', position: [-0.3, 1.0, 0.2], orientation: [0, 0, 0, 1], trigger: 0 });
  }
  return samples;
}

// ---- Clients ----

let refusals = 0;  // 503s the slow-loris connections got
const results = new Map();  // kind → {ms: [], status5xx, errors, other}
function record(kind, r) {
  if (!results.has(kind)) results.set(kind, { ms: [], s5xx: 0, errors: 0, other: 0, examples: [] });
  const k = results.get(kind);
  if (r.error) { k.errors++; if (k.examples.length < 3) k.examples.push(r.error); return; }
  k.ms.push(r.ms);
  if (r.status >= 500) { k.s5xx++; if (k.examples.length < 3) k.examples.push(`${r.status} ${r.body.slice(0, 200)}`); }
  else if (r.status >= 400) { k.other++; if (k.examples.length < 3) k.examples.push(`${r.status} ${r.body.slice(0, 200)}`); }
}

function agentFor(i) {
  return new http.Agent({ keepAlive: true, maxSockets: 1, localAddress: `127.0.1.${1 + i}` });
}

async function desktopClient(i, base, until) {
  const agent = agentFor(i);
  await sleep(random(0, config.interval));  // people do not start in step
  while (Date.now() < until) {
    const next = Date.now() + config.interval * random(0.7, 1.3);
    if (Math.random() < 0.1) record('GET /api/measurements', await request(agent, base, 'GET', '/api/measurements'));
    else record('POST /api/avatar', await request(agent, base, 'POST', '/api/avatar', avatarBody()));
    await sleep(next - Date.now());
  }
  agent.destroy();
}

async function headsetClient(i, base, until) {
  const agent = agentFor(i);
  const created = await request(agent, base, 'POST', '/api/sessions', { mode: 'self', steps: 'core' });
  record('POST /api/sessions', created);
  if (created.error || created.status !== 201) return agent.destroy();
  const { session, pairing_code: code } = JSON.parse(created.body);
  const path = `/api/sessions/${session.id}/samples`;
  let t = 0;
  while (Date.now() < until) {
    const next = Date.now() + 100;
    // Holds of 1.2 s (a floor tap or a measurement), then a release, over and over.
    const holding = (t % 2) < 1.2;
    const body = { profile: 'meta-quest-touch-plus', samples: frames(t, 7, holding ? 1 : 0) };
    t += 7 / 72;
    record('POST samples', await request(agent, base, 'POST', path, body, { 'X-Caliper-Pairing': code }));
    await sleep(next - Date.now());
  }
  agent.destroy();
}

// Slow-loris: a request header, one byte every 5 s; reconnects when the server closes it.
function slowLoris(i, base, until) {
  const url = new URL(base);
  const text = 'POST /api/avatar HTTP/1.1\r\nHost: localhost\r\nContent-Type: application/json\r\nX-Padding: ' + 'a'.repeat(10000);
  let closes = 0;
  return new Promise((resolve) => {
    const open = () => {
      if (Date.now() >= until) return resolve(closes);
      // From one address, refused connections would reconnect at once: pace them like the rest.
      const localAddress = config.slowlorisFrom || `127.0.2.${1 + (i % 250)}`;
      const socket = net.connect({ host: url.hostname, port: Number(url.port), localAddress });
      let at = 0, timer = null, ours = false;
      const drip = () => {
        if (Date.now() >= until) { ours = true; socket.destroy(); return; }
        socket.write(text[at++ % text.length]);
        timer = setTimeout(drip, 5000);
      };
      socket.on('connect', drip);
      socket.on('data', (d) => { if (/^HTTP\/1\.1 503/.test(d.toString())) refusals++; });
      socket.on('error', () => {});
      socket.on('close', () => {
        clearTimeout(timer);
        if (!ours) closes++;
        setTimeout(open, config.slowlorisFrom ? 1000 : 100);
      });
    };
    open();
  });
}

// A connection flood: connections that send nothing, 10 from each address (127.0.4.x), each
// reopened as soon as the server closes it.
function flood(i, base, until) {
  const url = new URL(base);
  return new Promise((resolve) => {
    const open = () => {
      if (Date.now() >= until) return resolve();
      const socket = net.connect({ host: url.hostname, port: Number(url.port), localAddress: `127.0.4.${1 + Math.floor(i / 10) % 250}` });
      const end = setTimeout(() => socket.destroy(), Math.max(0, until - Date.now()));
      socket.on('error', () => {});
      socket.on('close', () => { clearTimeout(end); setTimeout(open, 10); });
    };
    open();
  });
}

// ---- Memory: many sessions and custom regressors ----

async function memoryPhase(base, pid) {
  const agent = agentFor(200);
  const catalogue = ['span', 'crotch_height', 'hip_breadth', 'arm_length', 'chest_circumference', 'waist_circumference',
    'biacromial_breadth', 'buttock_circumference', 'thigh_circumference', 'neck_circumference'];
  const started = Date.now();
  console.log(`memory: RSS ${rssMiB(pid).rss.toFixed(1)} MiB before`);
  for (let k = 1; k <= config.sessions; k++) {
    const r = await request(agent, base, 'POST', '/api/sessions', { mode: 'other', steps: 'core', sex: 'female', weight_kg: 60 });
    record('POST /api/sessions', r);
    if (r.status === 201) record('GET /api/sessions/{id}', await request(agent, base, 'GET', `/api/sessions/${JSON.parse(r.body).session.id}`));
    if (k % 100 === 0) console.log(`memory: ${k} sessions, RSS ${rssMiB(pid).rss.toFixed(1)} MiB`);
  }
  record('GET /api/sessions', await request(agent, base, 'GET', '/api/sessions'));
  console.log(`memory: after listing ${config.sessions} sessions, RSS ${rssMiB(pid).rss.toFixed(1)} MiB`);
  for (let k = 1; k <= config.regressors; k++) {
    // A distinct input list each time: stature, weight and a subset of the catalogue (bit mask k).
    const inputs = ['stature', 'weight', ...catalogue.filter((_, b) => (k >> b) & 1)];
    const measurements = { stature: 170, weight: 65, span: 172, crotch_height: 78, hip_breadth: 36, arm_length: 60,
      chest_circumference: 95, waist_circumference: 80, biacromial_breadth: 40, buttock_circumference: 100,
      thigh_circumference: 58, neck_circumference: 36 };
    record('POST /api/avatar (custom regressor)',
      await request(agent, base, 'POST', '/api/avatar', { sex: 'female', regressor: inputs.join(','), measurements, mesh: false }));
    if (k % 50 === 0) console.log(`memory: ${k} custom regressors, RSS ${rssMiB(pid).rss.toFixed(1)} MiB`);
  }
  agent.destroy();
  console.log('memory phase requests:');
  report((Date.now() - started) / 1000);
}

// ---- Report ----

function percentile(sorted, p) {
  if (!sorted.length) return NaN;
  return sorted[Math.min(sorted.length - 1, Math.ceil((p / 100) * sorted.length) - 1)];
}

function report(seconds) {
  const all = { ms: [], s5xx: 0, errors: 0, other: 0 };
  const line = (name, k) => {
    const s = [...k.ms].sort((a, b) => a - b);
    const n = s.length + k.errors;
    console.log(`${name.padEnd(38)} ${String(n).padStart(7)} ${(n / seconds).toFixed(1).padStart(8)}/s` +
      `  p50 ${percentile(s, 50).toFixed(1).padStart(6)}  p95 ${percentile(s, 95).toFixed(1).padStart(6)}` +
      `  p99 ${percentile(s, 99).toFixed(1).padStart(6)}  max ${(s.length ? s[s.length - 1] : NaN).toFixed(1).padStart(7)} ms` +
      `  5xx ${k.s5xx}  4xx ${k.other}  errors ${k.errors}`);
  };
  for (const [name, k] of results) {
    line(name, k);
    for (const e of k.examples) console.log(`    e.g. ${e}`);
    all.ms.push(...k.ms); all.s5xx += k.s5xx; all.errors += k.errors; all.other += k.other;
  }
  line('all', all);
  return all;
}

// ---- Main ----

const server = config.url ? { url: config.url, pid: config.pid } : await startServer();
const base = server.url;
const warm = await request(undefined, base, 'POST', '/api/avatar', avatarBody());  // trains nothing new: warm-up ran
if (warm.status !== 200) throw new Error(`the server does not build avatars: ${warm.status} ${warm.body || warm.error}`);
if (config.memory) await memoryPhase(base, server.pid);
results.clear();
const before = server.pid ? rssMiB(server.pid) : null;
const start = Date.now();
const until = start + config.duration * 1000;
const cpuBefore = server.pid ? readFileSync(`/proc/${server.pid}/stat`, 'utf8').split(') ')[1].split(' ') : null;
const attackers = Array.from({ length: config.slowloris }, (_, i) => slowLoris(i, base, until));
const flooders = Array.from({ length: config.flood }, (_, i) => flood(i, base, until));
const clients = Array.from({ length: config.clients }, (_, i) =>
  (i < config.headsets ? headsetClient : desktopClient)(i, base, until));
await Promise.all(clients);
const seconds = (Date.now() - start) / 1000;
const after = server.pid ? rssMiB(server.pid) : null;
const closes = (await Promise.all(attackers)).reduce((a, b) => a + b, 0);
await Promise.all(flooders);

console.log(`server ${base} (pid ${server.pid || '?'}), ${config.clients} clients (${config.headsets} headsets posting samples ` +
  `every 100 ms, ${config.clients - config.headsets} desktop users, one request every ${config.interval} ms ±30 %), ` +
  `${config.slowloris} slow-loris connections, ${config.flood} idle flood connections, ${seconds.toFixed(1)} s`);
if (cpuBefore) {
  const cpuAfter = readFileSync(`/proc/${server.pid}/stat`, 'utf8').split(') ')[1].split(' ');
  const ticks = (f) => Number(f[11]) + Number(f[12]);  // utime + stime (fields 14, 15)
  console.log(`server CPU time ${((ticks(cpuAfter) - ticks(cpuBefore)) / 100).toFixed(1)} s over ${seconds.toFixed(1)} s`);
}
const all = report(seconds);
if (config.slowloris) {
  console.log(`slow-loris connections (from ${config.slowlorisFrom || 'one address each'}) closed by the server: ${closes}, ` +
    `of which answered 503: ${refusals}`);
}
if (before) console.log(`server RSS before ${before.rss.toFixed(1)} MiB, after ${after.rss.toFixed(1)} MiB (peak ${after.peak.toFixed(1)} MiB)`);
if (server.child) {
  server.child.kill('SIGTERM');
  await new Promise((r) => server.child.on('exit', r));
  rmSync(server.data, { recursive: true, force: true });
}
process.exit(all.s5xx || all.errors ? 1 : 0);
