#!/usr/bin/env node
// End-to-end test of the desktop tool in headless Chromium driven by Playwright (playwright-core,
// from web/node_modules; the browser is Debian's /usr/bin/chromium). It starts `caliper serve`
// on a free port, loads the page, changes values, checks the measurements table and the rendered
// canvas change, shows an error for an out-of-range value, exports a .glb and validates it with
// tools/validate-gltf.mjs, imports a CSV measurement set, and checks that the page asks for
// nothing outside the server (works offline).
//
//   node tests/e2e/desktop.spec.mjs --caliper build/bin/caliper [--screenshots DIR] [--keep]
//
// Exit: 0 pass, 1 fail, 77 skipped (no browser, no playwright-core or no body model).
import { spawnSync } from 'node:child_process';
import { mkdtempSync, readFileSync, rmSync, mkdirSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import {
  root, caliper, screenshots, hasFlag, loadChromium, prepare, check, fail, finish, startServer, launchBrowser,
} from './harness.mjs';

const chromium = loadChromium();
const modelsDir = prepare();

const tmp = mkdtempSync(join(tmpdir(), 'caliper-e2e-'));
const dataDir = mkdtempSync(join(tmpdir(), 'caliper-desktop-e2e-data-'));
const { child: server, base } = await startServer(modelsDir, dataDir);
const browser = await launchBrowser(chromium);

try {
  const context = await browser.newContext({ viewport: { width: 1440, height: 900 }, acceptDownloads: true });
  const page = await context.newPage();
  const pageErrors = [];
  page.on('pageerror', (e) => pageErrors.push(String(e)));
  // The browser logs every 4xx response as a console error; the deliberate ones are not bugs.
  page.on('console', (m) => {
    if (m.type() === 'error' && !/Failed to load resource: the server responded with a status of 4\d\d/.test(m.text()))
      pageErrors.push(m.text());
  });
  // Offline: everything must come from the Caliper server.
  const outside = [];
  await page.route('**/*', (route) => {
    const url = route.request().url();
    if (url.startsWith(base) || url.startsWith('data:') || url.startsWith('blob:')) return route.continue();
    outside.push(url);
    return route.abort();
  });

  const updates = () => page.evaluate(() => window.caliper?.updates ?? 0);
  // Waits until the page has finished at least `n` updates and nothing is pending.
  async function settle(n) {
    await page.waitForFunction((k) => (window.caliper?.updates ?? 0) >= k, n, { timeout: 60000 });
    let last = -1;
    for (let i = 0; i < 50; ++i) {
      const u = await updates();
      if (u === last) break;
      last = u;
      await page.waitForTimeout(300);
    }
  }
  // The canvas as pixels, kept in the page; the second call returns how many pixels changed.
  const snapshot = () => page.evaluate(() => {
    const src = window.caliper.viewer.canvas;
    const c = document.createElement('canvas');
    c.width = src.width; c.height = src.height;
    const ctx = c.getContext('2d');
    ctx.drawImage(src, 0, 0);
    const data = ctx.getImageData(0, 0, c.width, c.height).data;
    let changed = 0, painted = 0;
    const prev = window.__snap;
    for (let i = 0; i < data.length; i += 4) {
      if (data[i + 3] > 0) painted += 1;
      if (prev && (Math.abs(prev[i] - data[i]) + Math.abs(prev[i + 1] - data[i + 1]) + Math.abs(prev[i + 2] - data[i + 2]) > 24)) changed += 1;
    }
    window.__snap = data;
    return { changed, painted, total: data.length / 4 };
  });
  const tableText = () => page.locator('#measurements tbody').innerText();
  const cell = (name, col) => page.locator(`#measurements tr[data-name="${name}"] td`).nth(col).innerText();

  await page.goto(`${base}/`);
  await settle(1);
  check(await page.title() === 'Caliper — desktop tool', 'the page loads');
  const first = await snapshot();
  check(first.painted > first.total * 0.02, 'the canvas shows a body', `${first.painted} of ${first.total} pixels painted`);
  const tableA = await tableText();
  check(/Height/.test(tableA) && /Chest/i.test(tableA), 'the table lists inputs and predicted circumferences', tableA.slice(0, 200));
  check((await page.locator('#beta-bars .beta').count()) >= 2, 'shape values are drawn as bars');
  check(/plausible|unusual|implausible/.test(await page.locator('#verdict').innerText()), 'a verdict in words');
  if (screenshots) { mkdirSync(screenshots, { recursive: true }); await page.screenshot({ path: join(screenshots, 'desktop-tool.png') }); }

  // Change values: type a height, nudge the weight slider with the keyboard. (175 cm keeps this
  // woman's default arm span and inseam inside the population: auto reproduces every value.)
  let n = await updates();
  await page.fill('#in-stature', '175');
  await settle(n + 1);
  const weightSlider = page.locator('.row[data-name="weight"] input[type=range]');
  await weightSlider.focus();
  n = await updates();
  for (let i = 0; i < 40; ++i) await page.keyboard.press('ArrowRight');
  await settle(n + 1);
  const tableB = await tableText();
  check(tableB !== tableA, 'the table changes with the values');
  check((await cell('stature', 1)).startsWith('175.0'), 'the table shows the requested height', await cell('stature', 1));
  const achieved = parseFloat(await cell('stature', 2));
  check(Math.abs(achieved - 175) < 0.1, 'the avatar reaches the requested height', String(achieved));
  const weight = parseFloat(await page.inputValue('#in-weight'));
  check(Math.abs(weight - (67.8 + 4.0)) < 0.05, 'the slider drives the number field', String(weight));
  const second = await snapshot();
  check(second.changed > second.total * 0.005, 'the rendered canvas changes', `${second.changed} pixels changed`);

  // Round trips while a value changes (the page measures fetch → JSON).
  const trips = [];
  for (let i = 0; i < 10; ++i) {
    n = await updates();
    await page.fill('#in-span', String(180 + i));
    await settle(n + 1);
    trips.push(await page.evaluate(() => window.caliper.lastRoundTripMs));
  }
  trips.sort((a, b) => a - b);
  console.log(`info round trip in the page (headless, software GL): median ${trips[5].toFixed(1)} ms, max ${trips[9].toFixed(1)} ms`);

  // An out-of-range value: the page says which field and the accepted range, and keeps the body.
  await page.fill('#in-stature', '400');
  const err = page.locator('#error');
  await err.waitFor({ state: 'visible', timeout: 10000 });
  const errText = await err.innerText();
  check(/stature/.test(errText) && /50–250 cm/.test(errText), 'an out-of-range value is explained', errText);
  check(await page.locator('.row[data-name="stature"].invalid').count() === 1, 'the offending field is marked');
  n = await updates();
  await page.fill('#in-stature', '186');
  await settle(n + 1);
  check(await err.isHidden(), 'the error clears when the value is fixed');

  // A value typed in the wrong unit (issue 14): asked about in place, "Use …" applies the
  // suggestion, "Keep mine" builds with the value as typed.
  await page.fill('#in-stature', '68');  // inches
  await err.waitFor({ state: 'visible', timeout: 10000 });
  check(/inches/.test(await err.innerText()) && await page.locator('#use-suggested').isVisible(), 'a height in inches is questioned in place', await err.innerText());
  if (screenshots) await page.screenshot({ path: join(screenshots, 'desktop-tool-mistake.png') });
  n = await updates();
  await page.click('#use-suggested');
  await settle(n + 1);
  check(parseFloat(await page.inputValue('#in-stature')) === 172.7 && await err.isHidden(), 'the suggestion is applied',
    await page.inputValue('#in-stature'));
  await page.fill('#in-weight', '180');  // pounds at 172.7 cm
  await err.waitFor({ state: 'visible', timeout: 10000 });
  check(/pounds/.test(await err.innerText()), 'a weight in pounds is questioned', await err.innerText());
  n = await updates();
  await page.click('#keep-mine');
  await settle(n + 1);
  check(await err.isHidden() && parseFloat(await cell('weight', 1)) === 180, 'keep mine builds with the value as typed', await cell('weight', 1));
  n = await updates();
  await page.fill('#in-weight', '72');
  await settle(n + 1);
  n = await updates();
  await page.fill('#in-stature', '186');
  await settle(n + 1);

  // Camera presets.
  await snapshot();
  await page.click('.view-presets button[data-view="side"]');
  await page.waitForTimeout(300);
  const side = await snapshot();
  check(side.changed > side.total * 0.005, 'the side preset turns the view', `${side.changed} pixels changed`);
  if (screenshots) await page.screenshot({ path: join(screenshots, 'desktop-tool-side.png') });
  await page.click('.view-presets button[data-view="front"]');

  // Export a .glb and validate it with the Khronos validator.
  const [download] = await Promise.all([page.waitForEvent('download'), page.click('#export-glb')]);
  const glb = join(tmp, download.suggestedFilename());
  await download.saveAs(glb);
  check(/\.glb$/.test(glb), 'the export is named .glb', glb);
  const v = spawnSync(process.execPath, [join(root, 'tools', 'validate-gltf.mjs'), glb], { encoding: 'utf8' });
  let summary = {};
  try { summary = JSON.parse(v.stdout.trim().split('\n').pop()); } catch { /* reported below */ }
  check(v.status === 0 && summary.numErrors === 0, 'the exported .glb passes the glTF validator', v.stdout + v.stderr);
  check(summary.info?.hasSkins === true, 'the exported .glb is rigged (has a skin)');
  // And the .fbx button downloads a binary FBX.
  const [fbxDownload] = await Promise.all([page.waitForEvent('download'), page.click('#export-fbx')]);
  const fbx = join(tmp, fbxDownload.suggestedFilename());
  await fbxDownload.saveAs(fbx);
  check(/\.fbx$/.test(fbx) && readFileSync(fbx).subarray(0, 18).toString('latin1') === 'Kaydara FBX Binary',
    'the .fbx export is a binary FBX', fbx);

  // Measurement sets: import a CSV from a tape measure, export it again.
  n = await updates();
  const csv = 'measurement,value,unit\nsex,male,\nheight,1781,mm\nweight,79,kg\narm span,183,cm\ninseam,83.5,cm\nhip width,35,cm\nchest_circumference,99,cm\n';
  await page.setInputFiles('#import-file', { name: 'tape.csv', mimeType: 'text/csv', buffer: Buffer.from(csv) });
  await settle(n + 1);
  check(await page.inputValue('#sex') === 'male', 'the imported set sets the sex');
  check(parseFloat(await page.inputValue('#in-stature')) === 178.1, 'the imported set sets the height (mm → cm)', await page.inputValue('#in-stature'));
  check((await cell('chest_circumference', 1)).startsWith('99.0'), 'an imported non-input shows as requested vs avatar');
  check(/map · 6 inputs/.test(await page.locator('#regressor-used').innerText()), 'auto uses every imported value, chest included',
    await page.locator('#regressor-used').innerText());
  const [setDownload] = await Promise.all([page.waitForEvent('download'), page.click('#export-set-csv')]);
  const setFile = join(tmp, setDownload.suggestedFilename());
  await setDownload.saveAs(setFile);
  const setText = readFileSync(setFile, 'utf8');
  check(/^measurement,value,unit\n/.test(setText) && /\nstature,178\.1,cm\n/.test(setText) && /\nsex,male,\n/.test(setText),
    'the measurement set exports as CSV', setText);
  if (screenshots) await page.screenshot({ path: join(screenshots, 'desktop-tool-imported.png') });

  // The paper's presets stay selectable by name; who measured is auto's setting only.
  n = await updates();
  await page.selectOption('#regressor', 'R5');
  await settle(n + 1);
  check(/R5 · 5 inputs/.test(await page.locator('#regressor-used').innerText()), 'the paper\'s R5 can be chosen');
  check(await page.locator('#noise-row').isHidden(), 'a preset takes its values as exact');
  // The default estimator (issues 7, 14), self-measured values: error bars per measurement, a
  // heat map of the per-vertex SD, a warning naming an inconsistent value, and an export that
  // still validates.
  n = await updates();
  await page.selectOption('#regressor', 'auto');
  await settle(n + 1);
  n = await updates();
  await page.selectOption('#noise', 'self');
  await settle(n + 1);
  check(/map/.test(await page.locator('#regressor-used').innerText()), 'auto is the noise-aware estimator');
  check(await page.locator('#noise-row').isVisible(), 'auto shows who measured');
  check(/self-measured/.test(await page.locator('#regressor-hint').innerText()), 'the hint says how values are weighed');
  check(/of that population/.test(await page.locator('#explanation').innerText()), 'plausibility in words',
    await page.locator('#explanation').innerText());
  check(/ANSUR II/.test(await page.locator('#population').innerText()), 'the population is named');
  check(await page.locator('#measurements th.sd-col').isVisible(), 'auto adds the ± SD column');
  const chestSd = await cell('chest_circumference', 4);
  check(/^±\d+\.\d\d$/.test(chestSd.trim()) && parseFloat(chestSd.slice(1)) > 0, 'each measurement has an error bar (± SD)', chestSd);
  check(await page.locator('#measurements tr[data-name="chest_circumference"] .errbar .whisker').count() === 1, 'the error bar is drawn');
  check(await page.locator('#heatmap-bar').isVisible(), 'the heat-map toggle appears with map');
  await snapshot();
  await page.check('#heatmap');
  await page.waitForTimeout(300);
  const heat = await snapshot();
  check(heat.changed > heat.total * 0.005, 'the heat map colours the body', `${heat.changed} pixels changed`);
  if (screenshots) await page.screenshot({ path: join(screenshots, 'desktop-tool-map.png') });
  n = await updates();
  await page.fill('#in-span', '215');  // ~32 cm longer than this 178 cm body's arms
  await settle(n + 1);
  const warnings = await page.locator('#warnings').innerText();
  check(await page.locator('#warnings').isVisible() && /^span is/m.test(warnings), 'an inconsistent value is named in a warning', warnings);
  check(await page.locator('#verdict').innerText() !== 'implausible', 'map keeps the body plausible');
  const [mapDownload] = await Promise.all([page.waitForEvent('download'), page.click('#export-glb')]);
  const mapGlb = join(tmp, 'map-' + mapDownload.suggestedFilename());
  await mapDownload.saveAs(mapGlb);
  const mv = spawnSync(process.execPath, [join(root, 'tools', 'validate-gltf.mjs'), mapGlb], { encoding: 'utf8' });
  let mapSummary = {};
  try { mapSummary = JSON.parse(mv.stdout.trim().split('\n').pop()); } catch { /* reported below */ }
  check(mv.status === 0 && mapSummary.numErrors === 0, 'the map .glb (with _UNCERTAINTY) passes the glTF validator', mv.stdout + mv.stderr);
  check(readFileSync(mapGlb).includes('_UNCERTAINTY'), 'the map .glb carries the _UNCERTAINTY attribute');

  check(outside.length === 0, 'nothing is fetched from outside the server (offline)', outside.join(', '));
  check(pageErrors.length === 0, 'no errors in the page', pageErrors.join('\n'));
} catch (e) {
  fail(e.stack ?? e);
} finally {
  await browser.close();
  server.kill('SIGTERM');
  rmSync(dataDir, { recursive: true, force: true });
  if (!hasFlag('--keep')) rmSync(tmp, { recursive: true, force: true });
}

finish();
