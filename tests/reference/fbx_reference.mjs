// Independent reference for FBX import: three.js's FBXLoader (from the npm
// `three` package) reads the file in node, its AnimationMixer plays one
// animation stack, and every node's world position and every mesh's skinned
// world-space vertices are reported at each time. Textures are never loaded:
// TextureLoader.load returns an empty Texture (node has no DOM to decode one).
//
//   node fbx_reference.mjs <file.fbx> <animation index|-1> <t1,t2,...>
//
// Prints JSON: {"animations": [names], "nodes": {"Name": [[x, y, z] per time]},
// "meshes": [{"name", "rest": [x, y, z, ...] (geometry space), "frames": [[x, y, z, ...] per time]}]}.
// Node names are three's (PropertyBinding.sanitizeNodeName: `[ ] . : /` dropped).
import { readFileSync } from 'node:fs';
import { AnimationMixer, LoopOnce, Texture, TextureLoader, Vector3 } from 'three';
import { FBXLoader } from 'three/examples/jsm/loaders/FBXLoader.js';

TextureLoader.prototype.load = () => new Texture();
// FBXLoader sizes cameras by the browser window.
globalThis.window ??= { innerWidth: 1, innerHeight: 1 };

const [file, animationArg, timesArg] = process.argv.slice(2);
const bytes = readFileSync(file);
const buffer = bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength);
const loader = new FBXLoader();
// Binary files as an ArrayBuffer, ASCII ones as text (FBXLoader.parse takes either).
const scene = loader.parse(buffer, '');
const animationIndex = Number(animationArg ?? -1);
const times = (timesArg ?? '0').split(',').map(Number);

const mixer = new AnimationMixer(scene);
let action = null;
if (animationIndex >= 0 && animationIndex < scene.animations.length) {
  action = mixer.clipAction(scene.animations[animationIndex]);
  action.setLoop(LoopOnce, 1);
  action.clampWhenFinished = true;
  action.play();
}

const nodes = {};
const meshes = [];
scene.traverse((o) => {
  if (o !== scene && !(o.name in nodes)) nodes[o.name] = [];
  if (o.isMesh) meshes.push({ object: o, name: o.name, rest: Array.from(o.geometry.attributes.position.array), frames: [] });
});

const v = new Vector3();
for (const time of times) {
  if (action) {
    action.time = time;
    mixer.update(0);
  }
  scene.updateMatrixWorld(true);
  // FBXLoader turns a Z-up file's scene to Y-up; the engine keeps the file's
  // axes (and reports the up axis), so positions are taken in the scene's frame.
  const toFile = scene.matrixWorld.clone().invert();
  const seen = new Set();
  scene.traverse((o) => {
    if (o === scene || seen.has(o.name)) return;
    seen.add(o.name);
    nodes[o.name].push(o.getWorldPosition(new Vector3()).applyMatrix4(toFile).toArray());
  });
  for (const mesh of meshes) {
    const o = mesh.object;
    const count = o.geometry.attributes.position.count;
    const out = new Array(3 * count);
    for (let i = 0; i < count; i++) {
      o.getVertexPosition(i, v);
      v.applyMatrix4(o.matrixWorld).applyMatrix4(toFile);
      out[3 * i] = v.x;
      out[3 * i + 1] = v.y;
      out[3 * i + 2] = v.z;
    }
    mesh.frames.push(out);
  }
}

process.stdout.write(JSON.stringify({
  animations: scene.animations.map((a) => a.name),
  durations: scene.animations.map((a) => a.duration),
  nodes,
  meshes: meshes.map(({ name, rest, frames }) => ({ name, rest, frames })),
}));
