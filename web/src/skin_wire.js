// SkinCharacterResponse read from its proto encoding (the gateway's answer to
// `Accept: application/x-protobuf`). A character's answer is large (RobotExpressive:
// 7,114 vertices, 524 KB as JSON, 174 KB as proto); as JSON the gateway also
// compresses it, with brotli for a browser, which takes seconds. The proto
// answer is not compressed and its floats are copied straight into Float32Arrays.
//   SkinCharacterResponse { string skeleton = 1; repeated SkinMeshResponse meshes = 2; }
//   SkinMeshResponse { string mesh = 1; int32 vertex_count = 2;
//                      repeated float positions = 3; repeated float normals = 4; }  (packed)

const text = new TextDecoder();

class Reader {
  constructor(bytes, start = 0, end = bytes.length) {
    this.bytes = bytes;
    this.pos = start;
    this.end = end;
  }

  get done() {
    return this.pos >= this.end;
  }

  varint() {
    let value = 0;
    for (let scale = 1; ; scale *= 128) {
      if (this.pos >= this.end) throw new Error('SkinCharacter answer: truncated varint');
      const byte = this.bytes[this.pos++];
      value += (byte & 0x7f) * scale;
      if (byte < 0x80) return value;
      if (scale > 2 ** 56) throw new Error('SkinCharacter answer: varint too long');
    }
  }

  // A length-delimited field's [start, end).
  span() {
    const length = this.varint();
    const start = this.pos;
    this.pos += length;
    if (this.pos > this.end) throw new Error('SkinCharacter answer: truncated field');
    return [start, this.pos];
  }

  skip(wire) {
    if (wire === 0) this.varint();
    else if (wire === 1) this.pos += 8;
    else if (wire === 2) this.span();
    else if (wire === 5) this.pos += 4;
    else throw new Error(`SkinCharacter answer: unsupported wire type ${wire}`);
  }
}

// Packed floats at bytes[start, end) (copied: a field need not be 4-byte aligned).
function floats(bytes, start, end) {
  return new Float32Array(bytes.buffer.slice(bytes.byteOffset + start, bytes.byteOffset + end));
}

function readMesh(bytes, start, end) {
  const r = new Reader(bytes, start, end);
  const mesh = { mesh: '', vertexCount: 0, positions: new Float32Array(0), normals: new Float32Array(0) };
  while (!r.done) {
    const key = r.varint();
    const [field, wire] = [Math.floor(key / 8), key & 7];
    if (field === 1 && wire === 2) mesh.mesh = text.decode(bytes.subarray(...r.span()));
    else if (field === 2 && wire === 0) mesh.vertexCount = r.varint();
    else if ((field === 3 || field === 4) && wire === 2) mesh[field === 3 ? 'positions' : 'normals'] = floats(bytes, ...r.span());
    else r.skip(wire);
  }
  return mesh;
}

// { skeleton, meshes: [{ mesh, vertexCount, positions, normals }] } from the encoded bytes.
export function decodeSkinCharacter(buffer) {
  const bytes = new Uint8Array(buffer);
  const r = new Reader(bytes);
  const answer = { skeleton: '', meshes: [] };
  while (!r.done) {
    const key = r.varint();
    const [field, wire] = [Math.floor(key / 8), key & 7];
    if (field === 1 && wire === 2) answer.skeleton = text.decode(bytes.subarray(...r.span()));
    else if (field === 2 && wire === 2) answer.meshes.push(readMesh(bytes, ...r.span()));
    else r.skip(wire);
  }
  return answer;
}
