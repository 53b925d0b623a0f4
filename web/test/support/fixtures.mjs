// Meshes the browser tests make themselves (no shared data needed).

// A skinned tube as a .gltf (JSON, one embedded base64 buffer): `rings` rings
// of `segments` vertices, radius `radius`, along +y from 0 to `length`. Three
// joints on the axis: base (y = 0), twist (y = length/2), tip (y = length).
// Weights blend base → twist linearly over y ∈ [length/4, 3·length/4], so the
// middle ring is weighted half and half. One animation, "twist", turns the
// twist joint about the axis (y) from 0 to `twistDegrees` at t = 1 s and back
// at t = 2 s (LINEAR).
// A ring weighted w on a joint turned by θ stays at the radius under DQS;
// under LBS it shrinks to radius·|1 − w + w·e^{iθ}| (radius·cos(θ/2) at w = ½).
export function twistTubeGltf({ rings = 25, segments = 16, radius = 0.25, length = 2, twistDegrees = 150 } = {}) {
  const vertexCount = rings * segments;
  const positions = new Float32Array(3 * vertexCount);
  const normals = new Float32Array(3 * vertexCount);
  const joints = new Uint16Array(4 * vertexCount);
  const weights = new Float32Array(4 * vertexCount);
  for (let k = 0; k < rings; ++k) {
    const y = (length * k) / (rings - 1);
    const w = Math.min(Math.max((y - length / 4) / (length / 2), 0), 1);
    for (let j = 0; j < segments; ++j) {
      const v = k * segments + j;
      const a = (2 * Math.PI * j) / segments;
      positions.set([radius * Math.cos(a), y, radius * Math.sin(a)], 3 * v);
      normals.set([Math.cos(a), 0, Math.sin(a)], 3 * v);
      joints.set([0, 1, 0, 0], 4 * v);
      weights.set([1 - w, w, 0, 0], 4 * v);
    }
  }
  const indices = new Uint16Array(6 * (rings - 1) * segments);
  let t = 0;
  for (let k = 0; k + 1 < rings; ++k) {
    for (let j = 0; j < segments; ++j) {
      const a = k * segments + j, b = k * segments + ((j + 1) % segments);
      indices.set([a, a + segments, b, b, a + segments, b + segments], t);
      t += 6;
    }
  }
  const half = length / 2;
  // Inverse bind matrices (column-major): the inverse of each joint's rest placement.
  const translation = (y) => [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -y, 0, 1];
  const inverseBind = new Float32Array([...translation(0), ...translation(half), ...translation(length)]);
  const times = new Float32Array([0, 1, 2]);
  const s = Math.sin((twistDegrees * Math.PI) / 360), c = Math.cos((twistDegrees * Math.PI) / 360);
  const rotations = new Float32Array([0, 0, 0, 1, 0, s, 0, c, 0, 0, 0, 1]);  // x, y, z, w

  const buffer = new GltfBuffer();
  const min = [-radius, 0, -radius], max = [radius, length, radius];
  const accessors = [
    buffer.accessor(positions, 5126, 'VEC3', { target: 34962, min, max }),
    buffer.accessor(normals, 5126, 'VEC3', { target: 34962 }),
    buffer.accessor(joints, 5123, 'VEC4', { target: 34962 }),
    buffer.accessor(weights, 5126, 'VEC4', { target: 34962 }),
    buffer.accessor(indices, 5123, 'SCALAR', { target: 34963 }),
    buffer.accessor(inverseBind, 5126, 'MAT4'),
    buffer.accessor(times, 5126, 'SCALAR', { min: [0], max: [2] }),
    buffer.accessor(rotations, 5126, 'VEC4'),
  ];
  const gltf = {
    asset: { version: '2.0', generator: 'armature web tests' },
    scene: 0,
    scenes: [{ nodes: [0, 3] }],
    nodes: [
      { name: 'base', children: [1] },
      { name: 'twist', translation: [0, half, 0], children: [2] },
      { name: 'tip', translation: [0, half, 0] },
      { name: 'tube', mesh: 0, skin: 0 },
    ],
    meshes: [{
      name: 'tube',
      primitives: [{ attributes: { POSITION: 0, NORMAL: 1, JOINTS_0: 2, WEIGHTS_0: 3 }, indices: 4 }],
    }],
    skins: [{ joints: [0, 1, 2], inverseBindMatrices: 5, skeleton: 0 }],
    animations: [{
      name: 'twist',
      samplers: [{ input: 6, output: 7, interpolation: 'LINEAR' }],
      channels: [{ sampler: 0, target: { node: 1, path: 'rotation' } }],
    }],
    ...buffer.finish(),
    accessors,
  };
  return { text: JSON.stringify(gltf), vertexCount, rings, segments, radius, length, twistDegrees };
}

// Packs typed arrays into one buffer (4-byte aligned views) with an accessor each.
class GltfBuffer {
  constructor() {
    this.parts = [];
    this.bufferViews = [];
    this.byteLength = 0;
  }

  accessor(array, componentType, type, { target, min, max } = {}) {
    const bytes = new Uint8Array(array.buffer, array.byteOffset, array.byteLength);
    const view = { buffer: 0, byteOffset: this.byteLength, byteLength: bytes.length, ...(target ? { target } : {}) };
    this.bufferViews.push(view);
    this.parts.push(bytes);
    this.byteLength += bytes.length;
    const pad = (4 - (this.byteLength % 4)) % 4;
    if (pad) {
      this.parts.push(new Uint8Array(pad));
      this.byteLength += pad;
    }
    const width = { SCALAR: 1, VEC3: 3, VEC4: 4, MAT4: 16 }[type];
    return {
      bufferView: this.bufferViews.length - 1, componentType, type, count: array.length / width,
      ...(min ? { min, max } : {}),
    };
  }

  finish() {
    const data = Buffer.concat(this.parts.map((p) => Buffer.from(p)));
    return {
      buffers: [{ byteLength: data.length, uri: `data:application/octet-stream;base64,${data.toString('base64')}` }],
      bufferViews: this.bufferViews,
    };
  }
}

// A square grid in the x-z plane as an .obj: `n` × `n` vertices over
// [-half, half]², with a smooth bump of height `bump` in the middle;
// vertex (i, j) (row i along z, column j along x) is index i·n + j.
export function bumpGridObj({ n = 40, half = 1, bump = 0.3, width = 0.35 } = {}) {
  const lines = ['# a grid with a bump, made by the armature web tests'];
  for (let i = 0; i < n; ++i) {
    for (let j = 0; j < n; ++j) {
      const x = -half + (2 * half * j) / (n - 1), z = -half + (2 * half * i) / (n - 1);
      const y = bump * Math.exp(-(x * x + z * z) / (width * width));
      lines.push(`v ${x.toFixed(6)} ${y.toFixed(6)} ${z.toFixed(6)}`);
    }
  }
  for (let i = 0; i + 1 < n; ++i) {
    for (let j = 0; j + 1 < n; ++j) {
      const a = i * n + j + 1;  // OBJ counts from 1
      lines.push(`f ${a} ${a + n} ${a + n + 1} ${a + 1}`);
    }
  }
  return { text: lines.join('\n') + '\n', n, vertexCount: n * n, half };
}

// The arm of the integration tests: two joints, three frames.
export const ARM_BVH = `HIERARCHY
ROOT Base
{
  OFFSET 0 0 0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
  JOINT Tip
  {
    OFFSET 2 0 0
    CHANNELS 3 Zrotation Xrotation Yrotation
    End Site
    {
      OFFSET 1 0 0
    }
  }
}
MOTION
Frames: 3
Frame Time: 0.5
0 0 0 0 0 0 0 0 0
0 0 0 90 0 0 0 0 0
0 0 0 180 0 0 0 0 0
`;
