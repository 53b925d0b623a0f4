// Independent reference for glTF export: three.js's GLTFLoader reads a file
// `armature export` wrote, its AnimationMixer plays the file's animation, and
// every node's world position is reported at each time.
//
//   node export_reference.mjs <file.glb|file.gltf> <times.json>
//
// times.json: [t, ...]. Prints JSON: {"animation": name, "duration": seconds,
// "meshes": [names of skinned meshes], "frames": [{"NodeName": [x, y, z], ...} per time]}.
import { readFileSync } from 'node:fs';
import { AnimationMixer, Vector3 } from 'three';
import { loadGltf } from './gltf_node_loader.mjs';

const [file, timesFile] = process.argv.slice(2);
const gltf = await loadGltf(file);
const times = JSON.parse(readFileSync(timesFile, 'utf8'));
if (gltf.animations.length !== 1) throw new Error(`expected one animation, found ${gltf.animations.length}`);
const clip = gltf.animations[0];
const mixer = new AnimationMixer(gltf.scene);
const action = mixer.clipAction(clip);
action.play();

const meshes = [];
gltf.scene.traverse((o) => {
  if (o.isSkinnedMesh) meshes.push({ name: o.name, vertices: o.geometry.attributes.position.count,
                                     morphTargets: (o.geometry.morphAttributes.position || []).length });
});

const frames = [];
for (const time of times) {
  action.time = time;
  mixer.update(0);
  gltf.scene.updateMatrixWorld(true);
  const positions = {};
  gltf.scene.traverse((o) => {
    // A node holding a mesh is a Bone (or Object3D) with the mesh as a child
    // of another name; the first object of a name is the node.
    if (o === gltf.scene || o.name in positions) return;
    positions[o.name] = o.getWorldPosition(new Vector3()).toArray();
  });
  frames.push(positions);
}
process.stdout.write(JSON.stringify({ animation: clip.name, duration: clip.duration, meshes, frames }));
