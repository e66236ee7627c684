// Small helpers every page uses (the desktop tool, the WebXR capture page, the mirror).
import * as THREE from 'three';

// A typed array (Type: Float32Array, Uint32Array, …) over the bytes of base64 text, as the API
// sends vertices and faces.
export function decodeBase64(text, Type) {
  const bin = atob(text);
  const bytes = new Uint8Array(bin.length);
  for (let i = 0; i < bin.length; ++i) bytes[i] = bin.charCodeAt(i);
  return new Type(bytes.buffer);
}

// An error answer of the API (docs/api.md "Errors"): the HTTP status (0: no answer) and the
// body's error object — message, field, kind, accepted range, and for kind "suspect_values" the
// values that look mistyped.
export class ApiError extends Error {
  constructor(status, error) {
    super(error?.message ?? `HTTP ${status}`);
    this.status = status;
    this.field = error?.field ?? null;
    this.range = error?.accepted_range ?? null;
    this.kind = error?.kind ?? null;
    this.suspects = error?.suspects ?? [];
  }
}

// One request to the Caliper server. body: an object (sent as JSON) or text (sent as it is, as
// contentType, else text/plain); code: a session's pairing code for X-Caliper-Pairing (null or
// undefined: no header); raw: the Response itself instead of its JSON. Throws ApiError.
export async function api(path, { method = 'GET', body, contentType, raw = false, headers = {}, code } = {}) {
  const init = { method, headers: { ...headers } };
  if (body !== undefined) {
    const text = typeof body === 'string';
    init.body = text ? body : JSON.stringify(body);
    init.headers['Content-Type'] = contentType ?? (text ? 'text/plain' : 'application/json');
  }
  if (code !== undefined && code !== null) init.headers['X-Caliper-Pairing'] = code;
  let res;
  try {
    res = await fetch(path, init);
  } catch {
    throw new ApiError(0, { message: 'the Caliper server is not reachable (is `caliper serve` still running?)' });
  }
  if (!res.ok) {
    let payload = null;
    try { payload = await res.json(); } catch { /* not JSON */ }
    throw new ApiError(res.status, payload?.error ?? { message: `HTTP ${res.status}` });
  }
  if (raw) return res;
  return res.status === 204 ? null : res.json();
}

// Per-vertex unit normals of an indexed triangle mesh (positions: x, y, z per vertex; index: three
// vertex numbers per face), into `out`. Each face counts at a corner by the sine of its angle there
// over its two edges' lengths (N. Max, 1999), as the server's renderer and exports weight them
// (vertex_normals, docs/mannequin.md "Shading across uneven rings"): three.js's
// computeVertexNormals weights by area, and where the body's rings change spacing (1.6 mm under
// the head's widest ring, 13 mm over it) the shading showed a band.
export function vertexNormals(positions, index, out = new Float32Array(positions.length)) {
  out.fill(0);
  for (let f = 0; f < index.length; f += 3) {
    const a = 3 * index[f], b = 3 * index[f + 1], c = 3 * index[f + 2];
    const abx = positions[b] - positions[a], aby = positions[b + 1] - positions[a + 1], abz = positions[b + 2] - positions[a + 2];
    const acx = positions[c] - positions[a], acy = positions[c + 1] - positions[a + 1], acz = positions[c + 2] - positions[a + 2];
    const bcx = acx - abx, bcy = acy - aby, bcz = acz - abz;
    // Every corner's two edges span the same cross product; each corner divides it by the
    // product of its two edges' squared lengths.
    const nx = aby * acz - abz * acy, ny = abz * acx - abx * acz, nz = abx * acy - aby * acx;
    const ab = abx * abx + aby * aby + abz * abz, ac = acx * acx + acy * acy + acz * acz;
    const bc = bcx * bcx + bcy * bcy + bcz * bcz;
    const corners = [[a, ab * ac], [b, ab * bc], [c, bc * ac]];
    for (const [v, edges] of corners) {
      if (!(edges > 0)) continue;
      out[v] += nx / edges; out[v + 1] += ny / edges; out[v + 2] += nz / edges;
    }
  }
  for (let v = 0; v < out.length; v += 3) {
    const len = Math.hypot(out[v], out[v + 1], out[v + 2]);
    if (len > 0) { out[v] /= len; out[v + 1] /= len; out[v + 2] /= len; } else { out[v] = 0; out[v + 1] = 1; out[v + 2] = 0; }
  }
  return out;
}

// Sets `geometry`'s normal attribute from its positions and index (vertexNormals), updating the
// one it has in place when the size matches (the mirror does so while the body changes weight).
export function setVertexNormals(geometry) {
  const positions = geometry.attributes.position.array, index = geometry.index.array;
  const normal = geometry.attributes.normal;
  if (normal && normal.array.length === positions.length) {
    vertexNormals(positions, index, normal.array);
    normal.needsUpdate = true;
  } else {
    geometry.setAttribute('normal', new THREE.BufferAttribute(vertexNormals(positions, index), 3));
  }
}
