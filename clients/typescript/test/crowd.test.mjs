// @armature/client's crowd against a real server: a CrowdSession over the
// WebSocket route (/v1/crowds:session, binary frames) with CMU 01_01 and
// RobotExpressive characters mixed in one crowd; every decoded pose equals
// EvaluateClip's LOCAL pose (through the client, gRPC-Web) at the frame's
// clip time within the encoding's stated error plus the clip's compression
// bound; refused commands come back in a frame, naming the character, and the
// session runs on. Needs dist/ (npm run build) and ../shared/data (or
// $ARMATURE_SHARED_DATA): the test skips without CMU 01_01 and RobotExpressive.
//   node --experimental-websocket test/crowd.test.mjs <armature-server>
import path from 'node:path';
import { existsSync, readFileSync } from 'node:fs';
import { after, before, test } from 'node:test';
import assert from 'node:assert/strict';
import { fileURLToPath } from 'node:url';

import { CrowdSession, createArmatureClient } from '../dist/index.js';
import { startServer } from '../../../web/test/support/server.mjs';

const HERE = path.dirname(fileURLToPath(import.meta.url));
const SHARED = process.env.ARMATURE_SHARED_DATA ?? path.resolve(HERE, '../../../../shared/data');
const CMU = path.join(SHARED, 'bvh/cmu_01_01.bvh');
const ROBOT = path.join(SHARED, 'gltf/RobotExpressive/RobotExpressive.glb');
const skip = existsSync(CMU) && existsSync(ROBOT) ? false : `${SHARED} has no cmu_01_01.bvh or RobotExpressive.glb`;
const [serverBin] = process.argv.slice(2);

// The clips' compression bound (0.01 cm at ACL's 3 cm shell: 0.01 units at 3 for
// CMU in centimetres, 0.0001 at 0.03 for the robot in metres) as a local rotation:
// a joint's error moves a shell point by at least its angle × the shell distance,
// so its angle is under 0.01 / 3; twice that for margin, as the C++ test Crowd.* has it.
const COMPRESSION_ANGLE = (2 * 0.01) / 3;
// Translations: twice the bound in each skeleton's units, plus float32 rounding of CMU's hips (~20 units).
const TRANSLATION_TOLERANCE = { cmu: 0.02, robot: 0.0002 + 1e-6 };

let server, client, robot;

before(async () => {
  if (skip) return;
  server = await startServer(serverBin);
  client = createArmatureClient(server.url, { timeoutMs: 60000 });
  await server.importAsset('cmu_01_01.bvh', 'cmu', readFileSync(CMU));
  const asset = await server.importAsset('RobotExpressive.glb', 'robot', readFileSync(ROBOT));
  robot = ['Running', 'Walking', 'Dance'].map((n) => asset.clips.find((c) => c.name.endsWith(n)));
  assert.ok(robot.every(Boolean), `RobotExpressive has Running, Walking and Dance (${asset.clips.map((c) => c.name)})`);
});

after(async () => server?.stop());

// The angle between two rotations (w, x, y, z) at a[i..i+4) and b[j..j+4).
function angle(a, i, b, j) {
  let dot = 0, na = 0, nb = 0;
  for (let k = 0; k < 4; ++k) dot += a[i + k] * b[j + k], na += a[i + k] ** 2, nb += b[j + k] ** 2;
  return 2 * Math.acos(Math.min(1, Math.abs(dot) / Math.sqrt(na * nb)));
}

test('decoded crowd poses are EvaluateClip\'s local poses within the stated error', { skip }, async (t) => {
  const session = await CrowdSession.open(server.url, { fps: 30, duration: 0.6 });
  const clips = new Map();  // id → [clip, which skeleton's tolerance]
  for (let id = 0; id < 30; ++id) {
    const onRobot = id % 3 !== 0;
    const clip = onRobot ? robot[Math.floor(id / 3) % robot.length].name : 'cmu';
    clips.set(id, [clip, onRobot ? 'robot' : 'cmu']);
    session.add({ id, clip, timeOffset: 0.29 * id, speed: 0.6 + 0.05 * id, significance: -id });
  }
  let frames = 0, compared = 0, stated = 0;
  const worst = { angle: 0, cmu: 0, robot: 0 };
  const layouts = new Set();
  for await (const tick of session.frames()) {
    ++frames;
    assert.deepEqual(tick.errors, []);
    const { poses } = tick;
    assert.equal(poses.rotations.length, poses.ids.length * poses.joints * 4);
    for (let i = 0; i < poses.ids.length; ++i) {
      const [clip, units] = clips.get(poses.ids[i]);
      const layout = session.decoder.layout(poses.layouts[i]);
      layouts.add(layout.layout);
      stated = layout.maxRotationError;
      const want = await client.evaluateClip(clip, [poses.clipTimes[i]], { space: 'local' });
      assert.equal(want.jointIndices.length, layout.joints, `${clip}: every joint`);
      for (let j = 0; j < layout.joints; ++j) {
        worst.angle = Math.max(worst.angle, angle(poses.rotations, (i * poses.joints + j) * 4, want.rotations, j * 4));
        for (let k = 0; k < 3; ++k) {
          const d = Math.abs(poses.translations[(i * poses.joints + j) * 3 + k] - want.translations[j * 3 + k]);
          worst[units] = Math.max(worst[units], d);
        }
      }
      ++compared;
    }
  }
  t.diagnostic(`${frames} frames, ${compared} poses compared over ${layouts.size} layouts; worst rotation ` +
               `${worst.angle.toExponential(3)} rad (stated ${stated.toExponential(4)}), translation ` +
               `${worst.cmu.toExponential(3)} (CMU units), ${worst.robot.toExponential(3)} (robot, metres)`);
  assert.equal(frames, 18);  // 0.6 s at 30 ticks a second
  assert.ok(compared >= 30 * 10, `${compared} poses`);
  assert.equal(layouts.size, 4, 'one layout per clip');
  assert.ok(Math.abs(stated - 1.495e-4) < 1e-6, `stated error ${stated}`);
  assert.ok(worst.angle <= stated + COMPRESSION_ANGLE, `worst rotation ${worst.angle}`);
  assert.ok(worst.cmu <= TRANSLATION_TOLERANCE.cmu, `worst CMU translation ${worst.cmu}`);
  assert.ok(worst.robot <= TRANSLATION_TOLERANCE.robot, `worst robot translation ${worst.robot}`);
  assert.ok(worst.angle > 0, 'the encoding is lossy: a zero difference means the comparison compared nothing');
});

test('a refused command names the character in a frame and the crowd runs on', { skip }, async () => {
  const session = await CrowdSession.open(server.url, { fps: 30, duration: 0.3 });
  session.add({ id: 5, clip: 'cmu' });
  session.add({ id: 5, clip: 'cmu' });
  session.add({ id: 6, clip: 'cmu', speed: Number.POSITIVE_INFINITY });
  session.remove(99);
  const errors = [];
  let frames = 0, last;
  for await (const tick of session.frames()) {
    ++frames;
    errors.push(...tick.errors);
    last = tick;
  }
  assert.equal(frames, 9);
  assert.deepEqual(errors.map((e) => [e.id, e.code]), [[5, 6], [6, 3], [99, 5]]);
  for (const e of errors) assert.ok(e.error.startsWith(`character ${e.id}: `), e.error);
  assert.equal(last.stats.characters, 1);
  assert.ok(last.poses.ids.length >= 0 && session.isOpen === false);
});
