// What the blend panel sends: the motion JSON of motion.proto built from the
// panel's layers, the upper-body mask joint of a skeleton, and the weights of
// a crossfade at a playback time.

// Names of the joint the upper body hangs from, first match wins by depth.
const UPPER_BODY_NAME = /spine|chest|torso|abdomen|thorax|waist/i;

// The joint whose subtree is the upper body of `skeleton` (a GetSkeleton
// response): the shallowest joint (from the root, breadth first) named like a
// spine or chest that holds at least a quarter of the joints (a rigid torso
// mesh node or a spine's end site does not); failing that, the hips by shape: the first joint with
// three children of which two (the legs) have subtrees of one size, and
// the upper body is the third; failing that, below the first joint that
// branches, the child with the most descendants (the spine carries the arms
// and the head). Returns its index, or -1 for a skeleton with no branch.
export function upperBodyJoint(skeleton) {
  const joints = skeleton.joints;
  const children = joints.map(() => []);
  const roots = [];
  joints.forEach((joint, i) => (joint.parent >= 0 ? children[joint.parent].push(i) : roots.push(i)));
  const order = [...roots];  // breadth first
  for (let k = 0; k < order.length; ++k) order.push(...children[order[k]]);
  const size = new Array(joints.length).fill(1);  // joints in each subtree
  for (let k = order.length - 1; k >= 0; --k) {
    const i = order[k];
    if (joints[i].parent >= 0) size[joints[i].parent] += size[i];
  }
  const named = order.find((i) => UPPER_BODY_NAME.test(joints[i].name) && 4 * size[i] >= joints.length);
  if (named !== undefined) return named;
  for (const i of order) {
    if (children[i].length !== 3) continue;
    const [a, b, c] = children[i].map((child) => size[child]);
    if (a === b && c !== a) return children[i][2];
    if (a === c && b !== a) return children[i][1];
    if (b === c && a !== b) return children[i][0];
  }
  const branch = order.find((i) => children[i].length >= 2);
  if (branch === undefined) return -1;
  return children[branch].reduce((best, i) => (size[i] > size[best] ? i : best));
}

// Indices of `joint` and its descendants in `skeleton`.
export function subtree(skeleton, joint) {
  const inside = new Set(joint >= 0 ? [joint] : []);
  // Parents come before their children in a skeleton's joint list.
  skeleton.joints.forEach((j, i) => inside.has(j.parent) && inside.add(i));
  return inside;
}

// The motion of `layers` ({ clip, weight, mode, upperBody }, those without a
// clip left out), with `sync` 'NONE' or 'PHASE'; `upperBodyName` is the mask
// joint of an upper-body layer.
export function buildMotion(layers, sync, upperBodyName) {
  return {
    layers: layers.filter((layer) => layer.clip).map((layer) => ({
      clip: layer.clip,
      weight: layer.weight,
      mode: layer.mode,
      ...(layer.mode === 'ADDITIVE' ? { referenceTime: 0 } : {}),
      ...(layer.upperBody && upperBodyName ? { mask: [upperBodyName] } : {}),
    })),
    sync,
  };
}

// A crossfade from layer `from` to layer `to` started at playback time
// `start` for `duration` s: at `time` the weights ramp linearly, `from`
// 1 → 0 and `to` 0 → 1 (three.js's crossFadeTo without warping). Returns
// { progress, from, to } (progress 0..1, the two weights).
export function crossfadeWeights(fade, time) {
  const progress = fade.duration > 0 ? Math.min(Math.max((time - fade.start) / fade.duration, 0), 1) : 1;
  return { progress, from: 1 - progress, to: progress };
}
