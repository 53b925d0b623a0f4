// A whole character in the viewer: RobotExpressive (19 meshes on one
// skeleton) imported over REST, chosen in the character picker, its Running
// clip played. Checks that the picker lists exactly the skeletons that have
// meshes; that while Running plays every one of the 19 meshes is drawn with
// the positions of a direct SkinCharacter answer for the shown time; that the
// camera frames the whole character (its pixels' bounding box inside the
// viewport, and a good part of it); that each mesh alone puts pixels on
// screen; and that two times of the clip give different pictures. Saves
// screenshots (the page; …_early.png and …_later.png: the viewport at both times).
//   node character_e2e.mjs <armature-server> <web dir> <screenshot.png>
// SKIP when ../shared/data (or $ARMATURE_SHARED_DATA) has no RobotExpressive.
import { readFileSync, writeFileSync } from 'node:fs';
import { answeredAfter, besides, changedPixels, check, colourStats, runViewerTest } from '../support/browser.mjs';
import { drawnPositions, rendered, scrubTo, sharedDataOrSkip } from '../support/character_page.mjs';

const [GLB] = sharedDataOrSkip('gltf/RobotExpressive/RobotExpressive.glb');

await runViewerTest('character_e2e.mjs', async ({ page, server, screenshot }) => {
  const asset = await server.importAsset('RobotExpressive.glb', 'robot', readFileSync(GLB));
  const running = asset.clips.find((c) => c.name.endsWith('Running'));
  const skeleton = running?.skeleton;
  const meshNames = asset.meshes.filter((m) => m.skeleton === skeleton).map((m) => m.name).sort();
  check(running && meshNames.length === 19, `RobotExpressive imports with Running and 19 meshes on ${skeleton}`);
  const rest = server.call;

  await page.goto(`${server.url}/?character=${encodeURIComponent(skeleton)}&clip=${encodeURIComponent(running.name)}`);
  await page.waitForFunction((clip) => {
    const { characterPlayer } = window.armatureViewer ?? {};
    return characterPlayer?.clip?.name === clip && characterPlayer.stats.evaluations > 0;
  }, running.name, { timeout: 60000 });

  // The picker: none, then one entry per skeleton that has meshes.
  const withMeshes = [...new Set((await rest('/v1/meshes')).meshes.filter((m) => m.skeleton).map((m) => m.skeleton))].sort();
  const options = await page.$$eval('#character option', (os) => os.map((o) => ({ value: o.value, text: o.textContent })));
  check(options[0].value === '' && JSON.stringify(options.slice(1).map((o) => o.value)) === JSON.stringify(withMeshes),
        `the character picker lists the skeletons with meshes (${options.map((o) => o.text).join(', ')})`);
  check(options.find((o) => o.value === skeleton)?.text === `${skeleton} (19 meshes)`, 'RobotExpressive shows as 19 meshes');
  const clips = await page.$$eval('#clip option', (os) => os.map((o) => o.value));
  check(clips.includes(running.name) && clips.every((c) => asset.clips.some((a) => a.name === c)),
        `the clip picker holds the robot's ${clips.length} clips`);

  // Play Running: frames arrive, every mesh is drawn.
  await page.click('#play');
  await page.waitForFunction(() => window.armatureViewer.characterPlayer.stats.framesReceived >= 5, null, { timeout: 60000 });
  const playing = await page.evaluate(() => {
    const { characterPlayer, characterView } = window.armatureViewer;
    return { playing: characterPlayer.playing, time: characterPlayer.time, drawn: characterView.drawn() };
  });
  const rate = await page.textContent('#rate');
  check(playing.playing && JSON.stringify(playing.drawn.map((d) => d.mesh).sort()) === JSON.stringify(meshNames),
        `while Running plays all 19 meshes are drawn (t = ${playing.time.toFixed(3)} s, ${rate})`);
  const hud = await page.textContent('#vertices');
  check(hud.startsWith('19 meshes · '), `the HUD counts the character (${hud})`);
  await page.click('#play');  // pause

  // At a chosen time: what is drawn is SkinCharacter's answer, mesh by mesh.
  const shots = [];
  for (const time of [0.2, 0.5]) {
    await answeredAfter(page, 'characterPlayer', () => scrubTo(page, time));
    // The slider snaps to its step: the time shown is the player's.
    const shown = await page.evaluate(() => window.armatureViewer.characterPlayer.time);
    if (Math.abs(shown - time) > 0.01) throw new Error(`scrubbed to ${time} s, shown ${shown} s`);
    const answer = await rest(`/v1/skeletons/${encodeURIComponent(skeleton)}:skinCharacter`, { clip: running.name, time: shown });
    const drawn = await drawnPositions(page);
    let worst = 0, compared = 0;
    for (const part of drawn) {
      const expected = answer.meshes.find((m) => m.mesh === part.mesh);
      if (!expected || expected.positions.length !== part.positions.length) throw new Error(`${part.mesh}: no matching answer`);
      part.positions.forEach((p, i) => (worst = Math.max(worst, Math.abs(p - expected.positions[i]))));
      compared += part.positions.length / 3;
    }
    check(drawn.length === 19 && worst <= 1e-6,
          `at t = ${shown.toFixed(4)} s the 19 meshes drawn are SkinCharacter's (${compared} vertices, max diff ${worst})`);
    await rendered(page);
    const png = await page.locator('#viewport').screenshot();
    const stats = await colourStats(page, png, 'character');
    shots.push({ png, stats, time });
  }
  const viewport = await page.locator('#viewport').boundingBox();
  const [a, b] = shots;
  const box = { width: a.stats.imageWidth, height: a.stats.imageHeight };
  check(a.stats.count > 0.02 * a.stats.pixels,
        `the character covers ${(100 * a.stats.count / a.stats.pixels).toFixed(1)}% of the ${box.width}×${box.height} viewport`);
  check(a.stats.height > 0.35 * box.height && a.stats.height < box.height - 4 && a.stats.width < box.width - 4,
        `the camera frames the whole character: ${a.stats.width}×${a.stats.height} px inside ` +
        `${Math.round(viewport.width)}×${Math.round(viewport.height)}`);
  // Two times of Running, two pictures: count the pixels that changed.
  const changed = await changedPixels(page, a.png, b.png);
  check(changed > 0.1 * a.stats.count,
        `t = 0.2 s and t = 0.5 s differ in ${changed} pixels (the character has ${a.stats.count} at 0.2 s, ${b.stats.count} at 0.5 s)`);

  // Each mesh alone puts pixels in the frame: the pixels it changes from the
  // frame without any (its file's material may be grey or black, no shade).
  const showOnly = (k) =>
    page.evaluate((k) => window.armatureViewer.characterView.parts.forEach((p, j) => (p.object.visible = j === k)), k);
  await showOnly(-1);
  await rendered(page);
  const none = await page.locator('#viewport').screenshot();
  const alone = [];
  for (let i = 0; i < 19; ++i) {
    await showOnly(i);
    await rendered(page);
    alone.push(await changedPixels(page, none, await page.locator('#viewport').screenshot()));
  }
  await page.evaluate(() => window.armatureViewer.characterView.parts.forEach((p) => (p.object.visible = true)));
  await rendered(page);
  check(alone.every((n) => n > 0), `each of the 19 meshes alone is drawn (pixels: ${alone.join(', ')})`);

  writeFileSync(screenshot, await page.screenshot());
  writeFileSync(besides(screenshot, 'early'), a.png);
  writeFileSync(besides(screenshot, 'later'), b.png);
});
