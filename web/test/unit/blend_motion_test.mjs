// The blend panel's pure parts in node (no browser, no server): the
// upper-body joint on hand-made skeletons (by name, past a small node named
// like a torso, by the hips' shape, none), the crossfade ramp and the motion
// JSON.   node blend_motion_test.mjs
import { buildMotion, crossfadeWeights, subtree, upperBodyJoint } from '../../src/blend/blend_motion.js';

let failed = false;
function check(condition, message) {
  console.log(`${condition ? 'ok' : 'FAIL'}: ${message}`);
  if (!condition) failed = true;
}

// A skeleton from [name, parent name] pairs, parents first.
function skeleton(pairs) {
  const names = pairs.map(([name]) => name);
  return { joints: pairs.map(([name, parent]) => ({ name, parent: parent ? names.indexOf(parent) : -1 })) };
}
const nameOf = (s, i) => (i >= 0 ? s.joints[i].name : 'none');

// Legs, then arms and a head under a chest, under a spine (mixamo-like).
const leg = (side, hips) => [[`${side}UpLeg`, hips], [`${side}Leg`, `${side}UpLeg`], [`${side}Foot`, `${side}Leg`]];
const arm = (side, chest) => [[`${side}Shoulder`, chest], [`${side}Arm`, `${side}Shoulder`], [`${side}Hand`, `${side}Arm`]];
// `extra` joints come right after the hips (breadth first, before the spine).
const humanoid = (extra = []) => skeleton([
  ['Hips', null], ...extra, ...leg('Left', 'Hips'), ...leg('Right', 'Hips'),
  ['Spine', 'Hips'], ['Chest', 'Spine'], ...arm('Left', 'Chest'), ...arm('Right', 'Chest'), ['Neck', 'Chest'], ['Head', 'Neck'],
]);

const named = humanoid();
check(nameOf(named, upperBodyJoint(named)) === 'Spine', `a spine by name: ${nameOf(named, upperBodyJoint(named))}`);
const upper = [...subtree(named, upperBodyJoint(named))].map((i) => named.joints[i].name).sort();
check(upper.length === 10 && !upper.some((n) => /Leg|Foot|Hips/.test(n)),
      `its subtree: the spine, chest, arms and head (${upper.length} joints)`);

// A torso mesh node (two joints) hangs off the body before the spine: it is
// too small to be the upper body. (Legs on the body, as RobotExpressive's.)
const withMesh = skeleton([['Body', null], ['TorsoMesh', 'Body'], ['TorsoMesh_1', 'TorsoMesh'],
  ...humanoid().joints.map((j, i, all) => [j.name, j.parent >= 0 ? all[j.parent].name : 'Body'])]);
check(withMesh.joints[1].name === 'TorsoMesh' && nameOf(withMesh, upperBodyJoint(withMesh)) === 'Spine',
      `past a small node named like a torso: ${nameOf(withMesh, upperBodyJoint(withMesh))}`);

// No telling names: the hips' shape (three children, two subtrees of one size)
// finds the spine.
const anonymous = {
  joints: humanoid().joints.map((j, i) => ({ name: j.name === 'Spine' ? 'up' : `j${i}`, parent: j.parent })),
};
check(nameOf(anonymous, upperBodyJoint(anonymous)) === 'up', `by the hips' shape: ${nameOf(anonymous, upperBodyJoint(anonymous))}`);

// A chain has no upper body.
const chain = skeleton([['a', null], ['b', 'a'], ['c', 'b']]);
check(upperBodyJoint(chain) === -1 && subtree(chain, -1).size === 0, 'a chain has none');

// The crossfade ramp: linear in playback time, clamped; zero duration jumps.
const fade = { start: 2, duration: 0.5 };
const at = (t) => crossfadeWeights(fade, t);
check(at(1.9).from === 1 && at(1.9).to === 0 && at(2).progress === 0, 'before and at the start: 1 and 0');
check(Math.abs(at(2.125).to - 0.25) < 1e-15 && Math.abs(at(2.125).from - 0.75) < 1e-15, 'a quarter in: 0.75 and 0.25');
check(at(2.5).from === 0 && at(2.5).to === 1 && at(9).progress === 1, 'at the end and after: 0 and 1');
check(crossfadeWeights({ start: 2, duration: 0 }, 2).to === 1, 'a zero-length fade is done at once');

// The motion JSON: layers without a clip left out, the mask and the additive reference only when set.
const motion = buildMotion([
  { clip: 'walk', weight: 0.25, mode: 'OVERRIDE', upperBody: false },
  { clip: '', weight: 1, mode: 'OVERRIDE', upperBody: true },
  { clip: 'nod', weight: 1, mode: 'ADDITIVE', upperBody: true },
], 'PHASE', 'Spine');
check(JSON.stringify(motion) === JSON.stringify({
  layers: [{ clip: 'walk', weight: 0.25, mode: 'OVERRIDE' },
    { clip: 'nod', weight: 1, mode: 'ADDITIVE', referenceTime: 0, mask: ['Spine'] }],
  sync: 'PHASE',
}), `the motion JSON: ${JSON.stringify(motion)}`);

process.exit(failed ? 1 : 0);
