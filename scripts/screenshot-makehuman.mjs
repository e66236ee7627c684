#!/usr/bin/env node
// docs/images/makehuman-desktop-tool.png: the desktop tool with a built MakeHuman model picked,
// paper R5 from five values typed in. Run by scripts/screenshots.sh, which makes the models folder:
//
//   CALIPER_MODELS_DIR=DIR node scripts/screenshot-makehuman.mjs --caliper build/bin/caliper --screenshots OUT
//
// DIR holds the mannequin models and a built makehuman-female.npz (docs/makehuman.md).
import { mkdirSync, mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { screenshots, loadChromium, prepare, startServer, launchBrowser, settle } from '../tests/e2e/harness.mjs';

if (!screenshots) {
  console.error('usage: node scripts/screenshot-makehuman.mjs [--caliper BIN] --screenshots OUT_DIR');
  process.exit(2);
}
const chromium = loadChromium();
const modelsDir = prepare();
const dataDir = mkdtempSync(join(tmpdir(), 'caliper-makehuman-shot-'));
let server = null, browser = null, status = 1;
try {
  const started = await startServer(modelsDir, dataDir);
  server = started.child;
  browser = await launchBrowser(chromium);
  const page = await browser.newPage({ viewport: { width: 1440, height: 900 } });
  await page.goto(`${started.base}/`);
  await settle(page, 1);
  await page.selectOption('#model', 'makehuman');
  await page.selectOption('#regressor', 'R5');
  // The mean woman's height, weight, arm span, inseam and hip width, as the picture always had.
  for (const [name, value] of [['stature', '162.9'], ['weight', '67.8'], ['span', '166.0'],
    ['crotch_height', '78.2'], ['hip_breadth', '35.4']]) await page.fill(`#in-${name}`, value);
  await page.waitForFunction(() => /R5 · 5 inputs/.test(document.getElementById('regressor-used')?.textContent ?? ''),
    null, { timeout: 60000 });
  await settle(page, 1, 500);
  mkdirSync(screenshots, { recursive: true });
  await page.screenshot({ path: join(screenshots, 'makehuman-desktop-tool.png') });
  status = 0;
} catch (e) {
  console.log(`FAIL ${e.stack ?? e}`);
} finally {
  if (browser) await browser.close();
  if (server) server.kill();
  rmSync(dataDir, { recursive: true, force: true });
}
process.exit(status);
