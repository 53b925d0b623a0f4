// Independent reference for motion blending: three.js's own AnimationMixer
// plays a motion (the JSON of armature.v1.Motion, clips named by their glTF
// animation names) and reports every node's world position.
//
//   node motion_reference.mjs <file.glb> <cases.json>
//
// cases.json: [{"motion": {...}, "times": [t, ...]}, ...]
// Prints JSON: [[{"NodeName": [x, y, z], ...} per time] per case].
//
// Layers become actions played in layer order (the mixer accumulates in that
// order), weights are effective weights, ADDITIVE layers are clips made
// additive by AnimationUtils.makeClipAdditive at referenceTime (30 fps
// frames), a mask keeps only the tracks of the mask joints and their
// descendants. Time sync is done here, as the issue says: each action's time
// is set to its layer's time, then mixer.update(0) blends.
import { readFileSync } from 'node:fs';
import { AnimationMixer, AnimationUtils, Vector3 } from 'three';
import { loadGltf } from './gltf_node_loader.mjs';

const [file, casesFile] = process.argv.slice(2);
const gltf = await loadGltf(file);
const cases = JSON.parse(readFileSync(casesFile, 'utf8'));
const FPS = 30;

// Layer time, as the issue defines it: NONE → time·speed + timeOffset,
// wrapped (LOOP) or clamped; PHASE → the first override layer's phase times
// each layer's duration.
function frac(x) {
  return x - Math.floor(x);
}
function layerTimes(motion, time) {
  const layers = motion.layers;
  const speed = (l) => l.speed ?? 1;
  const offset = (l) => l.timeOffset ?? 0;
  const duration = (l) => gltf.animations.find((a) => a.name === l.clip).duration;
  if ((motion.sync ?? 'NONE') === 'PHASE') {
    const driver = layers.find((l) => (l.mode ?? 'OVERRIDE') === 'OVERRIDE');
    const phase = frac((time * speed(driver) + offset(driver)) / duration(driver));
    return layers.map((l) => phase * duration(l));
  }
  return layers.map((l) => {
    const t = time * speed(l) + offset(l);
    const d = duration(l);
    return (l.wrap ?? 'LOOP') === 'LOOP' ? frac(t / d) * d : Math.min(Math.max(t, 0), d);
  });
}

function maskedNames(mask) {
  const names = new Set();
  for (const joint of mask) gltf.scene.getObjectByName(joint).traverse((o) => names.add(o.name));
  return names;
}

// The rest pose, restored before each case: a mixer takes the values it
// finds as the "original" state that fills weights below 1.
const rest = [];
gltf.scene.traverse((o) => rest.push([o, o.position.clone(), o.quaternion.clone(), o.scale.clone()]));

const results = [];
for (const { motion, times } of cases) {
  for (const [o, p, q, s] of rest) {
    o.position.copy(p);
    o.quaternion.copy(q);
    o.scale.copy(s);
  }
  const mixer = new AnimationMixer(gltf.scene);
  const actions = motion.layers.map((l) => {
    let clip = gltf.animations.find((a) => a.name === l.clip).clone();
    if (l.mask && l.mask.length) {
      const keep = maskedNames(l.mask);
      clip.tracks = clip.tracks.filter((t) => keep.has(t.name.slice(0, t.name.lastIndexOf('.'))));
    }
    if (l.mode === 'ADDITIVE') clip = AnimationUtils.makeClipAdditive(clip, (l.referenceTime ?? 0) * FPS, clip, FPS);
    const action = mixer.clipAction(clip);
    action.setEffectiveWeight(l.weight ?? 1);
    action.play();
    return action;
  });
  const frames = [];
  for (const time of times) {
    const t = layerTimes(motion, time);
    actions.forEach((a, i) => (a.time = t[i]));
    mixer.update(0);
    gltf.scene.updateMatrixWorld(true);
    const positions = {};
    gltf.scene.traverse((o) => {
      if (o.isBone || o.type === 'Object3D') positions[o.name] = o.getWorldPosition(new Vector3()).toArray();
    });
    frames.push(positions);
  }
  mixer.stopAllAction();
  mixer.uncacheRoot(gltf.scene);
  results.push(frames);
}
process.stdout.write(JSON.stringify(results));
