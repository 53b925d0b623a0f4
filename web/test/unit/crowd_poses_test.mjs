// CrowdPoses in node against three.js as the reference: a character's world
// joint positions are three.js's Object3D hierarchy (position, quaternion,
// scale) for its local pose, its root placement added; between two updates it
// is drawn interpolated over the interval between them (at the later update:
// the earlier pose, one interval on: the later one, halfway: three.js's slerp
// halfway within nlerp's error); a frame that leaves a character out leaves
// its poses as they were.   node crowd_poses_test.mjs
import * as THREE from 'three';

import { CrowdPoses } from '../../src/crowd/crowd_poses.js';

let failed = false;
function check(condition, message) {
  console.log(`${condition ? 'ok' : 'FAIL'}: ${message}`);
  if (!condition) failed = true;
}

// Three joints: root → spine → head; rotations w x y z.
const PARENTS = [-1, 0, 1];
const quat = (axis, degrees) => new THREE.Quaternion().setFromAxisAngle(new THREE.Vector3(...axis).normalize(),
                                                                           (degrees * Math.PI) / 180);
const wxyz = (q) => [q.w, q.x, q.y, q.z];
function pose(rotations, translations, scales) {
  return { rotations: rotations.flatMap(wxyz), translations: translations.flat(), scales: scales.flat() };
}
const A = pose([quat([0, 0, 1], 10), quat([1, 0, 0], 30), quat([0, 1, 0], 0)],
               [[0.5, 1, 0], [0, 1.2, 0], [0, 0.4, 0.1]], [[1, 1, 1], [2, 2, 2], [1, 1, 1]]);
const B = pose([quat([0, 0, 1], 70), quat([1, 1, 0], -40), quat([0, 1, 0], 25)],
               [[0.5, 1.3, 0], [0, 1.2, 0], [0, 0.4, 0.1]], [[1, 1, 1], [2, 2, 2], [1, 1, 1]]);

// Decoded frames as the TypeScript client gives them.
function frame(ids, poses) {
  return {
    ids: Uint32Array.from(ids), joints: 3,
    rotations: Float32Array.from(poses.flatMap((p) => p.rotations)),
    translations: Float32Array.from(poses.flatMap((p) => p.translations)),
    scales: Float32Array.from(poses.flatMap((p) => p.scales)),
  };
}

// three.js's world positions for a pose, its rotations slerped `s` of the way from `from` to `to` (translations lerped).
function reference(from, to, s, root) {
  const objects = PARENTS.map(() => new THREE.Object3D());
  PARENTS.forEach((p, k) => {
    const o = objects[k];
    const q0 = new THREE.Quaternion(from.rotations[4 * k + 1], from.rotations[4 * k + 2], from.rotations[4 * k + 3],
                                    from.rotations[4 * k]);
    const q1 = new THREE.Quaternion(to.rotations[4 * k + 1], to.rotations[4 * k + 2], to.rotations[4 * k + 3],
                                    to.rotations[4 * k]);
    o.quaternion.copy(q0).slerp(q1, s);
    const t0 = new THREE.Vector3().fromArray(from.translations, 3 * k), t1 = new THREE.Vector3().fromArray(to.translations, 3 * k);
    o.position.copy(t0).lerp(t1, s);
    o.scale.fromArray(from.scales, 3 * k);
    if (p >= 0) objects[p].add(o);
  });
  const holder = new THREE.Object3D();
  holder.position.set(...root);
  holder.add(objects[0]);
  holder.updateMatrixWorld(true);
  return objects.flatMap((o) => new THREE.Vector3().setFromMatrixPosition(o.matrixWorld).toArray());
}

function worst(got, want) {
  return Math.max(...want.map((v, i) => Math.abs(got[i] - v)));
}

const poses = new CrowdPoses(PARENTS, 2);
poses.roots.set([10, 0, -4], 3);  // character 1 stands at (10, 0, -4)
poses.apply(4, frame([0, 1], [A, A]));
poses.apply(6, frame([1], [B]));  // character 1 is updated at tick 6; character 0 is not
const at = new Float32Array(9);

poses.worldPositions(1, 6, at);
let e = worst(at, reference(A, A, 0, [10, 0, -4]));
check(e < 1e-5, `at its later update a character shows its earlier pose, as three.js places it (${e.toExponential(2)})`);
poses.worldPositions(1, 8, at);
e = worst(at, reference(B, B, 0, [10, 0, -4]));
check(e < 1e-5, `one interval (2 ticks) later it shows its later pose (${e.toExponential(2)})`);
poses.worldPositions(1, 9.5, at);
check(worst(at, reference(B, B, 0, [10, 0, -4])) < 1e-5, 'past that it holds the later pose');
poses.worldPositions(1, 7, at);
e = worst(at, reference(A, B, 0.5, [10, 0, -4]));
const moved = worst(reference(A, A, 0, [10, 0, -4]), reference(B, B, 0, [10, 0, -4]));
check(e < 0.02 * moved, `halfway it is three.js's slerp halfway within nlerp's error (${e.toExponential(2)} of a ` +
      `${moved.toFixed(3)} move)`);
poses.worldPositions(0, 7, at);
e = worst(at, reference(A, A, 0, [0, 0, 0]));
check(e < 1e-5, `a character a frame leaves out keeps its pose (${e.toExponential(2)})`);
check(poses.posed === 2 && poses.blendOf(0, 100) === 1, 'both characters are posed; one updated once shows that pose');

process.exit(failed ? 1 : 0);
