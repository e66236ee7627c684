// Small helpers both pages use (the desktop tool and the WebXR capture page).

// A typed array (Type: Float32Array, Uint32Array, …) over the bytes of base64 text, as the API
// sends vertices and faces.
export function decodeBase64(text, Type) {
  const bin = atob(text);
  const bytes = new Uint8Array(bin.length);
  for (let i = 0; i < bin.length; ++i) bytes[i] = bin.charCodeAt(i);
  return new Type(bytes.buffer);
}
