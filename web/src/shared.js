// Small helpers every page uses (the desktop tool, the WebXR capture page, the mirror).

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
