// The Retarget panel's first choice of source clip (retarget_source.js) in
// node: a clip of another body, not the character's own clips nor clips
// already retargeted onto it, nor a skeleton that is no body.
//   node retarget_source_test.mjs
import { defaultRetargetSource, looksLikeABody } from '../../src/retarget/retarget_source.js';

let failed = false;
function check(condition, message) {
  console.log(`${condition ? 'ok' : 'FAIL'}: ${message}`);
  if (!condition) failed = true;
}

const demo = ['Hips', 'LeftHip', 'LeftKnee', 'LeftAnkle', 'LeftToe', 'RightHip', 'RightKnee', 'RightAnkle', 'RightToe',
  'Spine', 'Chest', 'Neck', 'Head', 'LeftShoulder', 'LeftElbow', 'LeftWrist', 'RightShoulder', 'RightElbow',
  'RightWrist'];
const mixamo = ['mixamorig:Hips', 'mixamorig:Head', 'mixamorig:LeftHand', 'mixamorig:LeftHandIndex1',
  'mixamorig:RightHand', 'mixamorig:LeftFoot', 'mixamorig:RightFoot'];
const robot = ['Root', 'Hips', 'Head', 'HandL', 'HandR', 'FootL', 'FootR'];
const cc = ['CC_Base_Hip', 'CC_Base_Pelvis', 'CC_Base_Head', 'CC_Base_L_Hand', 'CC_Base_R_Hand', 'CC_Base_L_Foot',
  'CC_Base_R_Foot'];
const arm = ['Base', 'Tip'];
const oneHand = ['Hips', 'Head', 'LeftHand', 'LeftHandIndex1', 'LeftFoot', 'RightFoot'];

for (const [names, body, what] of [[demo, true, 'the demo walk'], [mixamo, true, 'mixamo'],
  [robot, true, 'RobotExpressive'], [cc, true, 'Character Creator'], [arm, false, 'a two-joint arm'],
  [oneHand, false, 'one hand (a finger is no second hand)']]) {
  check(looksLikeABody(names) === body, `${what}: ${body ? '' : 'not '}a body`);
}

const skeletons = { demo_character: demo, demo_walk: demo, arm, cmu: mixamo, demo_character_copy: demo };
const jointsOf = (s) => skeletons[s] ?? [];
const clips = [
  { name: 'arm', skeleton: 'arm' },
  { name: 'demo_character.walk', skeleton: 'demo_character' },
  { name: 'demo_walk_on_demo_character', skeleton: 'demo_character_copy' },
  { name: 'demo_walk', skeleton: 'demo_walk' },
  { name: 'cmu', skeleton: 'cmu' },
];
check(defaultRetargetSource(clips, 'demo_character', jointsOf) === 'demo_walk',
  'on demo_character: demo_walk (not the arm, its own walk, nor a clip already retargeted onto it)');
check(defaultRetargetSource(clips.slice(0, 2), 'demo_character', jointsOf) === 'arm',
  'no other body: the first clip of another skeleton');
check(defaultRetargetSource(clips.slice(1, 2), 'demo_character', jointsOf) === 'demo_character.walk',
  'only its own clip: that one');
check(defaultRetargetSource([], 'demo_character', jointsOf) === '', 'no clips: none');
process.exit(failed ? 1 : 0);
