// Skinned mesh playback in the viewer, end to end: the test makes a skinned
// tube whose middle joint twists 150° about the tube's axis (fixtures.mjs),
// imports it over REST, chooses it in the page and plays it. Checks that
// skinned frames arrive over gRPC-Web and the mesh is drawn; that switching
// LBS → DQS while playing restarts the stream with DQS; and, paused at the
// full twist, that the middle ring (weighted half and half) keeps the
// radius under DQS and shrinks to radius·cos 75° under LBS (the "candy
// wrapper"), measured from the positions the MeshView draws. Then
// ?mesh=&clip=&method=, and back to the skeleton alone. Saves screenshots.
//   node mesh_e2e.mjs <armature-server> <web dir> <screenshot.png>
import { besides, check, colourStats, runViewerTest } from '../support/browser.mjs';
import { twistTubeGltf } from '../support/fixtures.mjs';

const tube = twistTubeGltf();
const MESH = 'tube.tube';
const CLIP = 'tube.twist';
const MIDDLE = tube.length / 2;  // the middle ring's height, weighted ½ base, ½ twist
const R = tube.radius;
const LBS_RADIUS = R * Math.cos((tube.twistDegrees * Math.PI) / 360);  // |½ + ½·e^{iθ}|·R

// In the page: the mean distance from the tube's axis (y) of the middle
// ring's vertices, as the MeshView draws them now.
function defineRingRadius(middle) {
  window.ringRadius = () => {
    const { meshView } = window.armatureViewer;
    const rest = meshView.geometry.positions;
    let sum = 0, n = 0;
    for (let v = 0; v < meshView.vertexCount; ++v) {
      if (Math.abs(rest[3 * v + 1] - middle) > 1e-4) continue;
      const p = meshView.vertexPosition(v);
      sum += Math.hypot(p.x, p.z);
      ++n;
    }
    return n ? sum / n : NaN;
  };
}

const near = (value, expected, tolerance) => Math.abs(value - expected) <= tolerance * expected;
const fmt = (x) => x.toFixed(4);

// Waits for a new SkinMesh answer after `action`.
async function skinnedAfter(page, action) {
  const before = await page.evaluate(() => window.armatureViewer.meshPlayer.stats.evaluations);
  await action();
  await page.waitForFunction((n) => {
    const { meshPlayer } = window.armatureViewer;
    return meshPlayer.stats.evaluations > n && !meshPlayer.sampler.busy;
  }, before);
}

const scrubTo = (page, time) => page.$eval('#scrub', (s, t) => {
  s.value = String(t);
  s.dispatchEvent(new Event('input'));
}, time);

// Play (LBS): each frame's positions are drawn; record the middle ring.
async function playLbs(page, screenshot) {
  await page.evaluate(() => {
    const { meshPlayer } = window.armatureViewer;
    window.frames = [];
    meshPlayer.addEventListener('frame', ({ detail }) => detail.frame &&
      window.frames.push({ method: meshPlayer.method, time: detail.time, radius: window.ringRadius() }));
  });
  const started = Date.now();
  await page.click('#play');
  await page.waitForFunction(() => window.frames.length >= 60, null, { timeout: 30000 });
  const seconds = (Date.now() - started) / 1000;
  const lbs = await page.evaluate(() => window.frames.filter((f) => f.method === 'LBS'));
  const lbsMin = Math.min(...lbs.map((f) => f.radius));
  check(lbs.length >= 60, `skinned frames arrive over gRPC-Web (${lbs.length} in ${seconds.toFixed(2)} s of wall time)`);
  check(/^\d+ frames\/s$/.test(await page.textContent('#rate')), `the frame rate is shown (${await page.textContent('#rate')})`);
  check(lbsMin < 0.5 * R && lbsMin >= LBS_RADIUS * 0.99,
        `playing LBS, the middle ring shrinks as the tube twists (smallest mean radius ${fmt(lbsMin)}, ` +
        `bound ${fmt(LBS_RADIUS)})`);
  // The tube twists as it plays, and a loaded machine can catch it at its
  // thinnest: the best of a few screenshots a quarter second apart.
  let drawn = { count: 0, height: 0 };
  for (let i = 0; i < 5 && !(drawn.count > 5000 && drawn.height > 200); ++i) {
    if (i > 0) await page.waitForTimeout(250);
    const playingShot = await page.screenshot({ path: screenshot });
    const stats = await colourStats(page, playingShot, 'mesh');
    if (stats.count > drawn.count) drawn = stats;
  }
  check(drawn.count > 5000 && drawn.height > 200,
        `the mesh is drawn (${drawn.count} mesh-coloured pixels, ${drawn.width}×${drawn.height} px)`);
}

// Switch to DQS while playing: a new stream, every frame keeps the radius.
async function switchToDqs(page) {
  const streams = await page.evaluate(() => window.armatureViewer.meshPlayer.streams);
  await page.selectOption('#method', 'DQS');
  await page.waitForFunction(() => window.frames.filter((f) => f.method === 'DQS').length >= 60, null, { timeout: 30000 });
  const live = await page.evaluate(() => ({
    streams: window.armatureViewer.meshPlayer.streams,
    playing: window.armatureViewer.meshPlayer.playing,
    dqs: window.frames.filter((f) => f.method === 'DQS'),
  }));
  const dqsRadii = live.dqs.map((f) => f.radius);
  const twisted = live.dqs.filter((f) => Math.abs(f.time - 1) < 0.25).length;
  check(live.streams === streams + 1 && live.playing, 'switching the method while playing restarts the stream');
  check(dqsRadii.every((r) => near(r, R, 0.01)) && twisted > 0,
        `playing DQS, the middle ring keeps its radius (${fmt(Math.min(...dqsRadii))}–${fmt(Math.max(...dqsRadii))} ` +
        `over ${live.dqs.length} frames, ${twisted} within 0.25 s of the full twist)`);
}

// Pause at the full twist and switch: SkinMesh at the slider's time.
async function pauseAtFullTwist(page, screenshot) {
  await page.click('#play');
  await page.waitForFunction(() => !window.armatureViewer.meshPlayer.playing);
  await skinnedAfter(page, () => scrubTo(page, 1.0));
  const shown = await page.textContent('#time');
  const dqsRadius = await page.evaluate(() => window.ringRadius());
  const dqsShot = await page.screenshot({ path: besides(screenshot, 'dqs') });
  await skinnedAfter(page, () => page.selectOption('#method', 'LBS'));
  const lbsRadius = await page.evaluate(() => window.ringRadius());
  const lbsShot = await page.screenshot({ path: besides(screenshot, 'lbs') });
  check(/t = 1\.000/.test(shown), `paused at the full twist (${shown})`);
  check(near(dqsRadius, R, 0.01), `DQS at t = 1: middle ring mean radius ${fmt(dqsRadius)} (radius ${R})`);
  check(near(lbsRadius, LBS_RADIUS, 0.02),
        `LBS at t = 1: middle ring mean radius ${fmt(lbsRadius)} (expected R·cos 75° = ${fmt(LBS_RADIUS)}, ` +
        `${((lbsRadius / dqsRadius) * 100).toFixed(1)}% of DQS's)`);
  check(!dqsShot.equals(lbsShot), 'the LBS and DQS pictures differ');
}

// The skeleton drawn over the mesh, posed at the same clip time.
async function skeletonOverMesh(page) {
  const overlay = await page.evaluate(() => {
    const { view, player } = window.armatureViewer;
    return { visible: view.figure.visible, overlay: view.overlay, clip: player.clip?.name, time: player.time };
  });
  check(overlay.visible && overlay.overlay && overlay.clip === CLIP && Math.abs(overlay.time - 1) < 1e-9,
        `the skeleton is drawn over the mesh at the same time (${overlay.clip} at ${overlay.time} s)`);
}

// The same from the URL.
async function fromTheUrl(page, server) {
  await page.goto(`${server.url}/?mesh=${MESH}&clip=${CLIP}&method=DQS`);
  await page.waitForFunction(() => window.armatureViewer?.meshPlayer.stats.evaluations > 0, null, { timeout: 30000 });
  await page.evaluate(defineRingRadius, MIDDLE);
  const fromUrl = await page.evaluate(() => ({
    mesh: document.getElementById('mesh').value, clip: document.getElementById('clip').value,
    method: document.getElementById('method').value, playerMethod: window.armatureViewer.meshPlayer.method,
  }));
  await skinnedAfter(page, () => scrubTo(page, 1.0));
  const urlRadius = await page.evaluate(() => window.ringRadius());
  check(fromUrl.mesh === MESH && fromUrl.clip === CLIP && fromUrl.method === 'DQS' && fromUrl.playerMethod === 'DQS' &&
        near(urlRadius, R, 0.01), `?mesh=…&clip=…&method=DQS shows the tube by DQS (radius ${fmt(urlRadius)} at t = 1)`);
}

// Edit mode pauses playback and shows the rest shape; leaving it skins again.
async function editMode(page) {
  const fromRest = () => page.evaluate(() => {
    const { meshView } = window.armatureViewer;
    const rest = Float32Array.from(meshView.geometry.positions);  // as drawn: float32
    const now = meshView.object.geometry.getAttribute('position').array;
    return Math.max(...Array.from(now, (x, i) => Math.abs(x - rest[i])));
  });
  await page.check('#edit');
  const restShift = await fromRest();
  await skinnedAfter(page, () => page.uncheck('#edit'));
  const skinnedShift = await fromRest();
  check(restShift === 0 && skinnedShift > 0.4,
        `edit mode shows the rest shape (${restShift} from rest); leaving it skins t = 1 again ` +
        `(${fmt(skinnedShift)} from rest)`);
  await page.click('#play');
  await page.waitForFunction(() => window.armatureViewer.meshPlayer.stats.framesReceived > 0);
  await page.check('#edit');
  const editing = await page.evaluate(() => ({
    playing: window.armatureViewer.meshPlayer.playing, play: document.getElementById('play').disabled,
  }));
  check(!editing.playing && editing.play && (await fromRest()) === 0, 'edit mode pauses playback');
  await page.uncheck('#edit');
}

// No mesh: the skeleton alone again, with the clip it had and every clip offered.
async function noMesh(page) {
  await page.selectOption('#mesh', '');
  await page.waitForFunction((clip) => {
    const { view, player, meshView, ik } = window.armatureViewer;
    return player.clip?.name === clip && !meshView.object && view.figure.visible && !view.overlay && ik.enabled;
  }, CLIP, { timeout: 30000 });
  const all = await page.$$eval('#clip option', (options) => options.map((o) => o.value));
  check(all.includes('demo_walk') && all.includes(CLIP) && await page.$eval('#mesh-controls', (e) => e.hidden),
        `choosing no mesh shows the skeleton alone again (clips: ${all.join(', ')})`);
}

// The plain page opens on the seeded demo character, walking when played.
async function demoCharacter(page, server, screenshot) {
  await page.goto(server.url + '/');
  await page.waitForFunction(() => window.armatureViewer?.meshPlayer.stats.evaluations > 0, null, { timeout: 30000 });
  const opened = await page.evaluate(() => ({
    mesh: document.getElementById('mesh').value, clip: document.getElementById('clip').value,
  }));
  check(opened.mesh === 'demo_character.body' && opened.clip === 'demo_character.walk',
        `/ opens on the demo character (${opened.mesh} playing ${opened.clip})`);
  const hips = () => page.evaluate(() => {
    const { meshView } = window.armatureViewer;
    const p = meshView.object.geometry.getAttribute('position').array;
    let z = 0;
    for (let i = 2; i < p.length; i += 3) z += p[i];
    return z / (p.length / 3);
  });
  const startZ = await hips();
  await page.click('#play');
  await page.waitForFunction(() => window.armatureViewer.meshPlayer.stats.framesReceived >= 30, null, { timeout: 30000 });
  await page.click('#play');  // pause
  const walkedZ = await hips();
  const demoShot = await page.screenshot({ path: besides(screenshot, 'demo_character') });
  const demoDrawn = await colourStats(page, demoShot, 'mesh');
  check(demoDrawn.count > 5000 && walkedZ - startZ > 20,
        `the demo character walks (${demoDrawn.count} mesh-coloured pixels; its mean z moved ${fmt(walkedZ - startZ)} cm)`);
}

await runViewerTest('mesh_e2e.mjs', async ({ page, server, screenshot }) => {
  const asset = await server.importAsset('tube.gltf', 'tube', tube.text);
  check(asset.meshes?.[0]?.name === MESH && asset.clips?.[0]?.name === CLIP && asset.meshes[0].skeleton === 'tube',
        `the tube imports over REST (mesh ${asset.meshes?.[0]?.name}, clip ${asset.clips?.[0]?.name}, ` +
        `${asset.meshes?.[0]?.vertexCount} vertices)`);

  await page.goto(server.url + '/?clip=demo_walk');  // skeleton mode first: the picker takes it from there
  await page.waitForFunction(() => window.armatureViewer?.player.skeleton, null, { timeout: 30000 });
  await page.evaluate(defineRingRadius, MIDDLE);
  const meshes = await page.$$eval('#mesh option', (options) => options.map((o) => o.value));
  check(meshes[0] === '' && meshes.includes(MESH),
        `the mesh picker offers none and the tube (${meshes.map((m) => m || 'none').join(', ')})`);

  await page.selectOption('#mesh', MESH);
  await page.waitForFunction((clip) => {
    const { meshPlayer } = window.armatureViewer;
    return meshPlayer.clip?.name === clip && meshPlayer.stats.evaluations > 0;
  }, CLIP, { timeout: 30000 });
  const clips = await page.$$eval('#clip option', (options) => options.map((o) => o.value));
  check(clips.length === 1 && clips[0] === CLIP, `the clip picker holds the tube's clips only (${clips.join(', ')})`);
  const vertices = await page.textContent('#vertices');
  check(vertices === `${tube.vertexCount} vertices · ${6 * (tube.rings - 1) * tube.segments / 3} triangles`,
        `the vertex count is on screen (${vertices})`);
  const atRest = await page.evaluate(() => window.ringRadius());
  check(near(atRest, R, 1e-4), `at t = 0 the middle ring has the tube's radius (${fmt(atRest)}, radius ${R})`);

  await playLbs(page, screenshot);
  await switchToDqs(page);
  await pauseAtFullTwist(page, screenshot);
  await skeletonOverMesh(page);
  await fromTheUrl(page, server);
  await editMode(page);
  await noMesh(page);
  await demoCharacter(page, server, screenshot);
});
