// The two DeformSession messages a drag step sends and receives, in the proto
// encoding (deform.proto), so a 100k-vertex answer is 1.2 MB of floats read
// straight into a Float32Array instead of JSON printed and parsed.
//   DeformSessionRequest { DeformMove move = 2 { repeated double positions = 1 } }
//   DeformResponse { string mesh = 1; repeated float positions = 2; uint64 index = 3; int32 iterations = 4 }

function varint(value, out) {
  while (value >= 0x80) {
    out.push((value & 0x7f) | 0x80);
    value = Math.floor(value / 128);
  }
  out.push(value);
}

// DeformSessionRequest{move: {positions}}: x, y, z per handle.
export function encodeDeformMove(positions) {
  const doubles = new Uint8Array(new Float64Array(positions).buffer);  // little-endian, as the wire
  const inner = [0x0a];  // field 1, length-delimited (packed doubles)
  varint(doubles.length, inner);
  const head = [0x12];  // field 2 (move), length-delimited
  varint(inner.length + doubles.length, head);
  const out = new Uint8Array(head.length + inner.length + doubles.length);
  out.set(head, 0);
  out.set(inner, head.length);
  out.set(doubles, head.length + inner.length);
  return out;
}

// A DeformResponse's encoding → { mesh, positions: Float32Array, index, iterations }.
export function decodeDeformResponse(buffer) {
  const view = new DataView(buffer);
  const bytes = new Uint8Array(buffer);
  let at = 0;
  const readVarint = () => {
    let value = 0, scale = 1, byte;
    do {
      if (at >= bytes.length) throw new Error('DeformResponse: cut short');
      byte = bytes[at++];
      value += (byte & 0x7f) * scale;
      scale *= 128;
    } while (byte & 0x80);
    return value;
  };
  const response = { mesh: '', positions: new Float32Array(0), index: 0, iterations: 0 };
  const floats = [];
  while (at < bytes.length) {
    const tag = readVarint();
    const [field, wire] = [Math.floor(tag / 8), tag & 7];
    if (wire === 0) {
      const v = readVarint();
      if (field === 3) response.index = v;
      else if (field === 4) response.iterations = v | 0;
    } else if (wire === 2) {
      const length = readVarint();
      if (at + length > bytes.length) throw new Error('DeformResponse: cut short');
      if (field === 1) response.mesh = new TextDecoder().decode(bytes.subarray(at, at + length));
      else if (field === 2) floats.push([at, length / 4]);
      at += length;
    } else if (wire === 5) {
      if (field === 2) floats.push([at, 1]);
      at += 4;
    } else if (wire === 1) {
      at += 8;
    } else {
      throw new Error(`DeformResponse: wire type ${wire}`);
    }
  }
  const total = floats.reduce((n, [, count]) => n + count, 0);
  response.positions = new Float32Array(total);
  let k = 0;
  for (const [start, count] of floats)
    for (let i = 0; i < count; ++i) response.positions[k++] = view.getFloat32(start + 4 * i, true);
  return response;
}
