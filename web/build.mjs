#!/usr/bin/env node
// Builds the desktop tool's static files into web/dist: the page's own files from web/src and the
// three.js modules it imports from node_modules (no CDN: the page works offline). There is no
// bundler; an import map in index.html points the bare 'three' specifier at vendor/three/.
// The WebXR capture page (capture.html, capture.js, capture.css) and the mirror page (mirror.*,
// mirror-body.js, embodiment.js) are copied the same way and use the same vendored three.js, plus
// qrcode-generator's ES module for the capture page's QR code; iwer (the WebXR emulator) and jsqr
// (the QR reader) are test-only devDependencies, never copied.
//
//   node web/build.mjs          (after `npm ci` in web/, which scripts/install-deps.sh runs)
import { cp, mkdir, rm, readFile, writeFile, access } from 'node:fs/promises';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const here = dirname(fileURLToPath(import.meta.url));
const src = join(here, 'src');
const dist = join(here, 'dist');
const three = join(here, 'node_modules', 'three');

try {
  await access(join(three, 'build', 'three.module.js'));
} catch {
  console.error('web/build.mjs: three is not installed; run `npm ci` in web/ (or scripts/install-deps.sh)');
  process.exit(2);
}

await rm(dist, { recursive: true, force: true });
await mkdir(join(dist, 'vendor', 'three', 'addons'), { recursive: true });
await cp(src, dist, { recursive: true });

// three.module.js imports ./three.core.js (r17x+); copy whichever of the two exist.
const vendored = ['three.module.js', 'three.core.js'];
for (const file of vendored) {
  try {
    await cp(join(three, 'build', file), join(dist, 'vendor', 'three', file));
  } catch (e) {
    if (file === 'three.module.js') throw e;
  }
}
await cp(join(three, 'examples', 'jsm', 'controls', 'OrbitControls.js'),
         join(dist, 'vendor', 'three', 'addons', 'OrbitControls.js'));
// The mirror page: the reflector, and the glTF loader (for an uploaded .glb) with the two
// utilities it imports, at the paths three's own `three/addons/` layout gives them.
for (const addon of ['objects/Reflector.js', 'loaders/GLTFLoader.js', 'utils/BufferGeometryUtils.js', 'utils/SkeletonUtils.js']) {
  await mkdir(dirname(join(dist, 'vendor', 'three', 'addons', addon)), { recursive: true });
  await cp(join(three, 'examples', 'jsm', addon), join(dist, 'vendor', 'three', 'addons', addon));
}
await cp(join(three, 'LICENSE'), join(dist, 'vendor', 'three', 'LICENSE'));
// The capture page draws the headset address as a QR code (qrcode-generator, MIT, one ES module).
const qr = join(here, 'node_modules', 'qrcode-generator');
try {
  await access(join(qr, 'dist', 'qrcode.mjs'));
} catch {
  console.error('web/build.mjs: qrcode-generator is not installed; run `npm ci` in web/ (or scripts/install-deps.sh)');
  process.exit(2);
}
await mkdir(join(dist, 'vendor', 'qrcode-generator'), { recursive: true });
await cp(join(qr, 'dist', 'qrcode.mjs'), join(dist, 'vendor', 'qrcode-generator', 'qrcode.mjs'));

// Both pages must be there (a missing file would only show as a 404 in a headset).
for (const page of ['index.html', 'app.js', 'style.css', 'shared.js', 'capture.html', 'capture.js', 'capture.css',
                    'mirror.html', 'mirror.js', 'mirror.css', 'mirror-body.js', 'embodiment.js']) {
  try {
    await access(join(dist, page));
  } catch {
    console.error(`web/build.mjs: web/src/${page} is missing`);
    process.exit(2);
  }
}

const pkg = JSON.parse(await readFile(join(three, 'package.json'), 'utf8'));
await writeFile(join(dist, 'vendor', 'three', 'VERSION'), `three ${pkg.version} (MIT), copied from node_modules\n`);
console.log(`web/build.mjs: wrote ${dist} (three ${pkg.version})`);
