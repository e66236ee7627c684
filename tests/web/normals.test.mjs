// Unit test of the pages' vertex normals (web/src/shared.js vertexNormals) under plain node: on
// rings of a unit sphere 1° of latitude apart below the equator and 15° above it, every vertex
// with faces on both sides has its radius as normal. three.js's computeVertexNormals (area
// weighting) tilts the equator's normals about 7° toward the larger faces above; the test checks
// that too, so it shows the difference it is about.
import { three, webSource } from './web-source.mjs';
const { vertexNormals } = await webSource('shared.js');
const THREE = await three();

let failures = 0;
function check(ok, what, detail = '') {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}${detail ? ` (${detail})` : ''}`);
  if (!ok) failures += 1;
}

const latitudes = [];
for (let d = -30; d <= 0; ++d) latitudes.push(d);
latitudes.push(15, 30, 45);
const columns = 48, rings = latitudes.length;
const positions = new Float32Array(3 * rings * columns);
for (let r = 0; r < rings; ++r)
  for (let c = 0; c < columns; ++c) {
    const lat = latitudes[r] * Math.PI / 180, lon = 2 * Math.PI * c / columns, i = 3 * (r * columns + c);
    positions[i] = Math.cos(lat) * Math.cos(lon); positions[i + 1] = Math.sin(lat); positions[i + 2] = -Math.cos(lat) * Math.sin(lon);
  }
const index = [];
for (let r = 0; r + 1 < rings; ++r)
  for (let c = 0; c < columns; ++c) {
    const a = r * columns + c, b = r * columns + (c + 1) % columns;
    index.push(a, b, b + columns, a, b + columns, a + columns);
  }
// The largest angle, degrees, between a normal and its vertex's radius over the rings with faces
// on both sides, and the ring where it is.
function worst(normals) {
  let most = 0, where = 0;
  for (let r = 1; r + 1 < rings; ++r)
    for (let c = 0; c < columns; ++c) {
      const i = 3 * (r * columns + c);
      const dot = normals[i] * positions[i] + normals[i + 1] * positions[i + 1] + normals[i + 2] * positions[i + 2];
      const len = Math.hypot(positions[i], positions[i + 1], positions[i + 2]) * Math.hypot(normals[i], normals[i + 1], normals[i + 2]);
      const angle = Math.acos(Math.min(1, dot / len)) * 180 / Math.PI;
      if (angle > most) { most = angle; where = latitudes[r]; }
    }
  return [most, where];
}
const [ours, at] = worst(vertexNormals(positions, new Uint32Array(index)));
check(ours < 0.05, 'every normal is its radius', `largest ${ours.toFixed(4)}° at latitude ${at}°`);

const g = new THREE.BufferGeometry();
g.setAttribute('position', new THREE.BufferAttribute(positions, 3));
g.setIndex(index);
g.computeVertexNormals();
const [area, areaAt] = worst(g.attributes.normal.array);
check(area > 3, 'three.js area weighting leans toward the large faces', `largest ${area.toFixed(2)}° at latitude ${areaAt}°`);

// A degenerate face (two corners in one place) adds nothing and does not make NaN.
const degenerate = vertexNormals(new Float32Array([0, 0, 0, 1, 0, 0, 1, 0, 0]), new Uint32Array([0, 1, 2]));
check(Array.from(degenerate).every(Number.isFinite), 'a degenerate face leaves finite normals');

console.log(failures ? `${failures} failed` : 'all passed');
process.exit(failures ? 1 : 0);
