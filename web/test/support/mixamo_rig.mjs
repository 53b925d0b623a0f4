// A Mixamo-style rig made from RobotExpressive: the armature node becomes
// `Armature` at scale 0.01 (RobotExpressive's is at 100) with every joint
// below it in centimetres (translations and their animation keys × 10⁴), as
// Mixamo characters exported to glTF are. The drawn character is unchanged:
// every joint's world placement keeps its position and gains a uniform scale
// of 10⁻⁴, which the inverse bind matrices (× 10⁴) and the rigid parts'
// mesh nodes (scale × 10⁴) take out again. Pure buffer edits of the .glb.
//   node mixamo_rig.mjs <RobotExpressive.glb> <out.glb>
import { readFileSync, writeFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';

const FACTOR = 1e4;  // 100 (the old scale) / 0.01 (the new one)

function readGlb(bytes) {
  const jsonLength = bytes.readUInt32LE(12);
  const json = JSON.parse(bytes.subarray(20, 20 + jsonLength).toString('utf8'));
  const binStart = 20 + jsonLength;
  const binLength = bytes.readUInt32LE(binStart);
  return { json, bin: Buffer.from(bytes.subarray(binStart + 8, binStart + 8 + binLength)) };
}

function writeGlb({ json, bin }) {
  const pad = (buffer, fill) => Buffer.concat([buffer, Buffer.alloc((4 - (buffer.length % 4)) % 4, fill)]);
  const text = pad(Buffer.from(JSON.stringify(json), 'utf8'), 0x20);
  const data = pad(bin, 0);
  const header = Buffer.alloc(12);
  header.write('glTF', 0);
  header.writeUInt32LE(2, 4);
  header.writeUInt32LE(12 + 8 + text.length + 8 + data.length, 8);
  const chunk = (buffer, type) => {
    const head = Buffer.alloc(8);
    head.writeUInt32LE(buffer.length, 0);
    head.write(type, 4);
    return Buffer.concat([head, buffer]);
  };
  return Buffer.concat([header, chunk(text, 'JSON'), chunk(data, 'BIN\0')]);
}

// Multiplies the float components `which(component index)` of accessor `index` by FACTOR.
function scaleAccessor(gltf, index, which = () => true) {
  const accessor = gltf.json.accessors[index];
  if (accessor.componentType !== 5126) throw new Error(`accessor ${index} is not float`);
  const view = gltf.json.bufferViews[accessor.bufferView];
  const components = { SCALAR: 1, VEC2: 2, VEC3: 3, VEC4: 4, MAT4: 16 }[accessor.type];
  const stride = view.byteStride ?? 4 * components;
  const start = (view.byteOffset ?? 0) + (accessor.byteOffset ?? 0);
  for (let i = 0; i < accessor.count; ++i)
    for (let c = 0; c < components; ++c) {
      if (!which(c)) continue;
      const at = start + i * stride + 4 * c;
      gltf.bin.writeFloatLE(gltf.bin.readFloatLE(at) * FACTOR, at);
    }
  for (const bound of ['min', 'max'])
    if (accessor[bound]) accessor[bound] = accessor[bound].map((v, c) => (which(c) ? v * FACTOR : v));
}

export function mixamoRigGlb(robotGlb) {
  const gltf = readGlb(robotGlb);
  const { nodes } = gltf.json;
  const armature = nodes.findIndex((n) => n.name === 'RobotArmature');
  if (armature < 0) throw new Error('no RobotArmature node: not RobotExpressive');
  nodes[armature].name = 'Armature';
  nodes[armature].scale = [0.01, 0.01, 0.01];
  const below = new Set();
  const visit = (i) => (nodes[i].children ?? []).forEach((c) => (below.add(c), visit(c)));
  visit(armature);
  for (const i of below) {
    const node = nodes[i];
    if (node.translation) node.translation = node.translation.map((v) => v * FACTOR);
    if (node.mesh !== undefined && node.skin === undefined)  // a rigid part: its vertices keep their size
      node.scale = (node.scale ?? [1, 1, 1]).map((v) => v * FACTOR);
  }
  const scaled = new Set();
  const once = (accessor, which) => scaled.has(accessor) || (scaled.add(accessor), scaleAccessor(gltf, accessor, which));
  for (const animation of gltf.json.animations ?? [])
    for (const channel of animation.channels)
      if (channel.target.path === 'translation' && below.has(channel.target.node))
        once(animation.samplers[channel.sampler].output);
  // Column-major 4×4: rows 0–2 (component index % 4 < 3) scale, the last row stays.
  for (const skin of gltf.json.skins ?? []) once(skin.inverseBindMatrices, (c) => c % 4 < 3);
  return writeGlb(gltf);
}

if (process.argv[1] === fileURLToPath(import.meta.url)) {
  const [input, output] = process.argv.slice(2);
  if (!input || !output) {
    console.error('usage: node mixamo_rig.mjs <RobotExpressive.glb> <out.glb>');
    process.exit(2);
  }
  writeFileSync(output, mixamoRigGlb(readFileSync(input)));
}
