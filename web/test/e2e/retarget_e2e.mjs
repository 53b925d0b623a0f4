// Retargeting in the viewer: CMU 01_01 (BVH mocap) and RobotExpressive
// imported over REST, the robot chosen as the character, the CMU clip chosen
// in the Retarget panel and Retarget pressed. Checks that the answer shown
// (pairs mapped, joints unmapped on each side) is what RetargetClip answers
// for the same request over REST; that the new clip (the robot's own, named
// as the panel asked) is offered for the robot and plays on it; that what is drawn at
// two times is a direct SkinCharacter of the retargeted clip, mesh by mesh;
// that the two times give different pictures with the robot framed; that
// pressing again (with Feet) replaces the clip; and that a failure shows the
// server's message. Saves screenshots (the page; …_early.png, …_later.png).
//   node retarget_e2e.mjs <armature-server> <web dir> <screenshot.png>
// SKIP when ../shared/data (or $ARMATURE_SHARED_DATA) lacks either file.
import { readFileSync, writeFileSync } from 'node:fs';
import { answeredAfter, besides, changedPixels, check, colourStats, runViewerTest } from '../support/browser.mjs';
import { drawnPositions, rendered, scrubTo, sharedDataOrSkip } from '../support/character_page.mjs';

const [GLB, BVH] = sharedDataOrSkip('gltf/RobotExpressive/RobotExpressive.glb', 'bvh/cmu_01_01.bvh');

// Waits for the panel's answer after pressing Retarget: the text it shows.
async function pressRetarget(page) {
  const before = await page.evaluate(() => window.armatureViewer.retarget.calls);
  await page.click('#retarget-run');
  await page.waitForFunction((count) => {
    const { retarget } = window.armatureViewer;
    return !retarget.busy && retarget.calls > count;
  }, before, { timeout: 60000 });
  return page.textContent('#retarget-result');
}

await runViewerTest('retarget_e2e.mjs', async ({ page, server, screenshot }) => {
  const mocap = await server.importAsset('cmu_01_01.bvh', 'cmu', readFileSync(BVH));
  const robot = await server.importAsset('RobotExpressive.glb', 'robot', readFileSync(GLB));
  const source = mocap.clips[0];
  const skeleton = robot.meshes[0]?.skeleton;
  const meshNames = robot.meshes.filter((m) => m.skeleton === skeleton).map((m) => m.name).sort();
  check(source && skeleton && meshNames.length === 19, `CMU (${source?.name}) and the robot (${skeleton}, 19 meshes) imported`);
  const rest = server.call;

  await page.goto(`${server.url}/?character=${encodeURIComponent(skeleton)}`);
  await page.waitForFunction(() => window.armatureViewer?.characterPlayer?.character, null, { timeout: 60000 });
  check(await page.isVisible('#retarget-panel'), 'the Retarget panel shows (there is a character)');
  const target = await page.textContent('#retarget-target');
  check(target === `onto ${skeleton}`, `its target is the character shown (${target})`);
  await page.selectOption('#retarget-source', source.name);

  // Press Retarget: the answer is shown, and it is RetargetClip's.
  const shown = await pressRetarget(page);
  const answer = await page.evaluate(() => window.armatureViewer.retarget.last);
  check(answer !== null, `Retarget answered: "${shown}"`);
  const name = answer.clip.name;
  const reference = await rest(`/v1/clips/${encodeURIComponent(source.name)}:retarget`,
                               { skeleton, name: 'reference_copy' });
  const line = (r, clip) => `${clip}: ${r.mapping.length} pairs mapped · unmapped ${r.unmapped.source.length} source, ` +
                            `${r.unmapped.target.length} target joints`;
  check(shown === line(reference, name) && reference.mapping.length >= 12,
        `the panel shows REST's answer for the same request (${reference.mapping.length} pairs, unmapped ` +
        `${reference.unmapped.source.length} source / ${reference.unmapped.target.length} target)`);
  const info = await rest(`/v1/clips/${encodeURIComponent(name)}`);
  check(info.skeleton === skeleton && info.name === answer.asset.name && Math.abs(info.duration - source.duration) < 1e-3,
        `${name} is a clip of the robot's skeleton (${info.skeleton}), named as its asset, and lasts ${info.duration.toFixed(3)} s`);

  // It plays on the robot: offered in the clip picker beside the robot's own clips, not CMU's.
  await page.waitForFunction((clip) => {
    const { characterPlayer } = window.armatureViewer;
    return characterPlayer.clip?.name === clip && characterPlayer.playing && characterPlayer.stats.framesReceived >= 3;
  }, name, { timeout: 60000 });
  const offered = await page.$$eval('#clip option', (os) => os.map((o) => o.value));
  check(await page.inputValue('#clip') === name && offered.includes(name) && !offered.includes(source.name) &&
        robot.clips.every((c) => offered.includes(c.name)),
        `the robot plays ${name}, offered beside its ${robot.clips.length} own clips`);
  const playing = await page.evaluate(() => window.armatureViewer.characterView.drawn().length);
  check(playing === 19, `while it plays all 19 meshes are drawn (${await page.textContent('#rate')})`);
  await page.click('#play');  // pause

  // At two times: what is drawn is SkinCharacter's answer for the retargeted clip.
  const shots = [];
  for (const time of [1, 3]) {
    await answeredAfter(page, 'characterPlayer', () => scrubTo(page, time));
    const at = await page.evaluate(() => window.armatureViewer.characterPlayer.time);
    if (Math.abs(at - time) > 0.01) throw new Error(`scrubbed to ${time} s, shown ${at} s`);
    const skinned = await rest(`/v1/skeletons/${encodeURIComponent(skeleton)}:skinCharacter`, { clip: name, time: at });
    const drawn = await drawnPositions(page);
    let worst = 0, compared = 0;
    for (const part of drawn) {
      const expected = skinned.meshes.find((m) => m.mesh === part.mesh);
      if (!expected || expected.positions.length !== part.positions.length) throw new Error(`${part.mesh}: no matching answer`);
      part.positions.forEach((p, i) => (worst = Math.max(worst, Math.abs(p - expected.positions[i]))));
      compared += part.positions.length / 3;
    }
    check(drawn.length === 19 && worst <= 1e-6,
          `at t = ${at.toFixed(4)} s the 19 meshes drawn are SkinCharacter's of ${name} (${compared} vertices, max diff ${worst})`);
    await rendered(page);
    const png = await page.locator('#viewport').screenshot();
    shots.push({ png, stats: await colourStats(page, png, 'character') });
  }
  const [a, b] = shots;
  const box = { width: a.stats.imageWidth, height: a.stats.imageHeight };
  check(a.stats.count > 0.02 * a.stats.pixels && b.stats.count > 0.02 * b.stats.pixels,
        `the robot covers ${(100 * a.stats.count / a.stats.pixels).toFixed(1)}% and ` +
        `${(100 * b.stats.count / b.stats.pixels).toFixed(1)}% of the ${box.width}×${box.height} viewport`);
  check(a.stats.width < box.width - 4 && a.stats.height < box.height - 4,
        `the robot is framed: ${a.stats.width}×${a.stats.height} px inside ${box.width}×${box.height}`);
  const changed = await changedPixels(page, a.png, b.png);
  check(changed > 0.1 * a.stats.count, `t = 1 s and t = 3 s differ in ${changed} pixels (the robot has ${a.stats.count})`);
  writeFileSync(screenshot, await page.screenshot());
  writeFileSync(besides(screenshot, 'early'), a.png);
  writeFileSync(besides(screenshot, 'later'), b.png);

  // Pressing again, with Feet, replaces the clip and plays it again.
  await page.check('#retarget-feet');
  const again = await pressRetarget(page);
  const second = await page.evaluate(() => window.armatureViewer.retarget.last);
  check(second?.clip.name === name && again.startsWith(`${name}: `), `pressed again with Feet: "${again}"`);
  await page.waitForFunction((clip) => {
    const { characterPlayer } = window.armatureViewer;
    return characterPlayer.clip?.name === clip && characterPlayer.playing && characterPlayer.stats.framesReceived >= 3;
  }, name, { timeout: 60000 });
  const listed = (await rest('/v1/clips')).clips.filter((c) => c.name === name).length;
  check(listed === 1, 'the second press replaced the clip (listed once)');

  // A failure shows the server's message: the source deleted behind the page's back.
  const deleted = await fetch(`${server.url}/v1/assets/cmu`, { method: 'DELETE' });
  check(deleted.ok, 'the source asset deleted over REST');
  const failed = await pressRetarget(page);
  check(/^Retarget failed: .*cmu/.test(failed) && (await page.evaluate(() => window.armatureViewer.retarget.last)) === null,
        `a missing source shows the server's message ("${failed}")`);
});
