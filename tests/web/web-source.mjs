// What the pages' unit tests share: web/src's modules under plain node, once three.js is installed
// in web/ (without it a test skips with 77, the code ctest reads as skipped; under
// CALIPER_REQUIRE_TOOLS=1, as CI and the screenshots set it, it fails instead).
import { createRequire } from 'node:module';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';

const root = resolve(dirname(fileURLToPath(import.meta.url)), '..', '..');

// Where node finds three.js for web/ (its CommonJS build); exits the test when it is not there.
function threePath() {
  try {
    return createRequire(join(root, 'web', 'package.json')).resolve('three');
  } catch {
    console.log('SKIP: three is not installed in web/ (run scripts/install-deps.sh)');
    process.exit(process.env.CALIPER_REQUIRE_TOOLS === '1' ? 1 : 77);
  }
}

// The module web/src/NAME (e.g. 'embodiment.js').
export async function webSource(name) {
  threePath();
  return import(join(root, 'web', 'src', name));
}

// three.js itself, as the tests compare with it.
export async function three() {
  const module = await import(threePath());
  return module.BufferGeometry ? module : module.default;
}
