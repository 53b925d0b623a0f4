// The blend view shows the body: blending the demo character's skeleton draws
// its mesh too, posed by SkinCharacter with the blend's own motion at the
// blend's time (what is drawn matches a direct call within 1e-4), under the
// skeleton drawn thin; leaving the blend takes the mesh away.
//   node blend_body_e2e.mjs <armature-server> <web dir> <screenshot.png>
import { check, runViewerTest } from '../support/browser.mjs';
import { drawnPositions } from '../support/character_page.mjs';

await runViewerTest('blend_body_e2e.mjs', async ({ page, server, screenshot }) => {
  await page.goto(`${server.url}/?clip=demo_character.walk`);
  await page.waitForFunction(() => window.armatureViewer?.player.skeleton, null, { timeout: 30000 });
  await page.check('#blend');
  await page.waitForFunction(() => {
    const { blendCharacter } = window.armatureViewer;
    return blendCharacter.skinned > 0 && !blendCharacter.skinner.busy;
  }, null, { timeout: 60000 });
  const drawn = await page.evaluate(() => window.armatureViewer.characterView.drawn());
  check(drawn.length === 1 && drawn[0].mesh === 'demo_character.body' && drawn[0].vertices === 7506,
        `blending shows the character's mesh (${JSON.stringify(drawn)})`);
  check(await page.evaluate(() => window.armatureViewer.view.overlay), 'the skeleton is drawn thin over it');

  const { time, motion } = await page.evaluate(() => window.armatureViewer.blendCharacter.last);
  const [shown] = await drawnPositions(page);
  const res = await fetch(`${server.url}/v1/skeletons/demo_character:skinCharacter`, {
    method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify({ motion, time }) });
  const answer = await res.json();
  const expected = answer.meshes.find((m) => m.mesh === 'demo_character.body').positions;
  let worst = 0;
  for (let i = 0; i < expected.length; ++i) worst = Math.max(worst, Math.abs(expected[i] - shown.positions[i]));
  check(expected.length === shown.positions.length && worst < 1e-4,
        `what is drawn is SkinCharacter of the blend's motion at t = ${time.toFixed(3)} s (max difference ${worst.toExponential(2)})`);
  await page.screenshot({ path: screenshot });

  await page.uncheck('#blend');
  await page.waitForFunction(() => window.armatureViewer.characterView.drawn().length === 0, null, { timeout: 30000 });
  check(true, 'leaving the blend takes the mesh away');
});
