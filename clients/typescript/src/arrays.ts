// Packs repeated floats of several messages into one Float32Array, so that a
// pose sequence is times × joints × 3 (or 4) contiguous values, as WebGL and
// three.js want them.

/** Copies each part, in order, into one Float32Array of their total length. */
export function packFloats(parts: readonly (readonly number[])[]): Float32Array {
  let total = 0;
  for (const p of parts) total += p.length;
  const out = new Float32Array(total);
  let at = 0;
  for (const p of parts) {
    out.set(p, at);
    at += p.length;
  }
  return out;
}
