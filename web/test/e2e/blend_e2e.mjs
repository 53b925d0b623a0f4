// The blend panel end to end: RobotExpressive imported over REST, two and
// then other clips set with the panel's controls, and the joints the page
// draws compared with a direct EvaluateMotion of the motion written here by
// hand (same time, within 1e-6); a weight slider, phase sync, the upper-body
// mask (override and additive: the joints outside the mask's subtree do not
// move) and the crossfade button (the two weights ramp linearly 1 → 0 and
// 0 → 1 over its duration of playback). Saves a screenshot.
//   node blend_e2e.mjs <armature-server> <web dir> <screenshot.png>
// SKIP when ../shared/data (or $ARMATURE_SHARED_DATA) has no RobotExpressive.
import { existsSync, readFileSync } from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { besides, check, colourStats, runViewerTest } from '../support/browser.mjs';

const here = path.dirname(fileURLToPath(import.meta.url));
const DATA = process.env.ARMATURE_SHARED_DATA ?? path.resolve(here, '../../../../shared/data');
const GLB = path.join(DATA, 'gltf/RobotExpressive/RobotExpressive.glb');
if (!existsSync(GLB)) {
  console.log(`SKIP: ${GLB} is not present (../shared/data is only beside the project's own clone)`);
  process.exit(0);
}
const TOLERANCE = 1e-6;
const FADE = 0.5;
const T = 0.7;  // the time blends are compared at

// What the page draws: the blend's time and motion, and every joint's sphere position.
const drawn = (page) => page.evaluate(() => {
  const { blend, view } = window.armatureViewer;
  return { time: blend.last.time, motion: blend.last.motion, positions: view.joints.map((j) => j.position.toArray()) };
});

// Runs `action` and waits until the blend has drawn a new answer and has none in flight.
async function drawnAfter(page, action) {
  const before = await page.evaluate(() => window.armatureViewer.blend.stats.evaluations);
  await action();
  await page.waitForFunction((n) => {
    const { blend } = window.armatureViewer;
    return blend.stats.evaluations > n && !blend.sampler.busy;
  }, before, { timeout: 30000 });
  return drawn(page);
}

const setSlider = (page, selector, value) => page.$eval(selector, (s, v) => {
  s.value = String(v);
  s.dispatchEvent(new Event('input'));
}, value);

// Largest coordinate difference between joint positions `a` ([[x, y, z]…]) and
// the flat translations `b`, over the joints in `only` (default all).
function maxDiff(a, b, only) {
  let most = 0;
  a.forEach((p, i) => {
    if (only && !only.has(i)) return;
    for (let k = 0; k < 3; ++k) most = Math.max(most, Math.abs(p[k] - b[3 * i + k]));
  });
  return most;
}

// Two clips and their weights through the controls, at t = T; a slider moved.
// Returns Walking's joints at T.
async function weightsThroughControls({ page, evaluate, walk, run, height }) {
  await page.selectOption('#blend-clip-0', walk);
  await page.selectOption('#blend-clip-1', run);
  await setSlider(page, '#blend-weight-0', 0.6);
  let shown = await drawnAfter(page, async () => {
    await setSlider(page, '#blend-weight-1', 0.4);
    await page.evaluate((t) => window.armatureViewer.blend.seek(t), T);
  });
  let motion = { layers: [{ clip: walk, weight: 0.6 }, { clip: run, weight: 0.4 }], sync: 'NONE' };
  let reference = await evaluate(motion, T);
  let diff = maxDiff(shown.positions, reference);
  check(shown.time === T && diff < TOLERANCE,
        `Walking 0.6 + Running 0.4 at t = ${T}: the drawn joints equal EvaluateMotion (max diff ${diff.toExponential(2)})`);
  const walkAtT = await evaluate({ layers: [{ clip: walk }] }, T);
  const blendShift = maxDiff(shown.positions, walkAtT);
  check(blendShift > 0.01 * height, `the blend is not the walk alone (joints ${blendShift.toFixed(4)} apart, height ${height.toFixed(3)})`);
  check((await page.textContent('#blend-weight-value-1')) === '0.40', 'the weight is shown beside its slider');

  // Moving a slider changes the pose.
  const before = shown.positions;
  shown = await drawnAfter(page, () => setSlider(page, '#blend-weight-1', 0.9));
  motion.layers[1].weight = 0.9;
  reference = await evaluate(motion, T);
  const moved = maxDiff(before, reference);
  diff = maxDiff(shown.positions, reference);
  check(moved > 0.01 * height && diff < TOLERANCE,
        `moving Running's slider to 0.9 moves joints by up to ${moved.toFixed(4)}; drawn = EvaluateMotion (${diff.toExponential(2)})`);
  return walkAtT;
}

// Phase sync (Walking and Running last as long: Idle, 3.3 s, in their place),
// and a rejected motion's message.
async function phaseSync({ page, evaluate, expectConsoleError, walk, run, idle, height }) {
  let shown, motion, diff;
  await page.selectOption('#blend-clip-1', idle);
  shown = await drawnAfter(page, () => page.check('#blend-sync'));
  motion = { layers: [{ clip: walk, weight: 0.6 }, { clip: idle, weight: 0.9 }], sync: 'PHASE' };
  const phased = await evaluate(motion, T);
  diff = maxDiff(shown.positions, phased);
  const syncShift = maxDiff(shown.positions, await evaluate({ ...motion, sync: 'NONE' }, T));
  check(shown.motion.sync === 'PHASE' && diff < TOLERANCE && syncShift > 1e-3 * height,
        `Walking + Idle with phase sync: drawn = EvaluateMotion with PHASE (${diff.toExponential(2)}), ` +
        `${syncShift.toFixed(4)} from NONE`);
  // An error is shown and cleared: PHASE with no override layer to drive it.
  await page.selectOption('#blend-clip-1', '');
  expectConsoleError(/status of 400/);  // Chromium logs the rejected request
  await page.selectOption('#blend-mode-0', 'ADDITIVE');
  await page.waitForFunction(() => /^Blend: .*PHASE/.test(document.getElementById('message').textContent));
  const message = await page.textContent('#message');
  await drawnAfter(page, () => page.selectOption('#blend-mode-0', 'OVERRIDE'));
  const cleared = await page.textContent('#message');
  check(cleared === '', `a rejected motion shows the server's message (${message}) until the next pose`);
  await page.uncheck('#blend-sync');
  await drawnAfter(page, () => page.selectOption('#blend-clip-1', run));
}

// The upper-body mask: the subtree of the first spine-like joint (Abdomen on this rig).
async function upperBodyMask({ page, screenshot, evaluate, skeleton, walk, wave, yes, height }, walkAtT) {
  let shown, reference, diff;
  const upperText = await page.textContent('#blend-upper-body');
  check(/\bAbdomen\b/.test(upperText), `the upper body is found by name (${upperText})`);
  const abdomen = skeleton.joints.findIndex((j) => j.name === 'Abdomen');
  const upper = new Set([abdomen]);
  let grew = true;
  while (grew) {
    grew = false;
    skeleton.joints.forEach((j, i) => {
      if (upper.has(j.parent) && !upper.has(i)) upper.add(i), (grew = true);
    });
  }
  const lower = new Set(skeleton.joints.map((_, i) => i).filter((i) => !upper.has(i)));
  const maskCases = [
    { name: 'Wave override', clip: wave, mode: 'OVERRIDE', weight: 1 },
    { name: 'Yes additive', clip: yes, mode: 'ADDITIVE', weight: 1 },
  ];
  for (const c of maskCases) {
    await setSlider(page, '#blend-weight-0', 1);
    await page.selectOption('#blend-clip-1', c.clip);
    await page.selectOption('#blend-mode-1', c.mode);
    await setSlider(page, '#blend-weight-1', c.weight);
    shown = await drawnAfter(page, () => page.selectOption('#blend-mask-1', 'upper'));
    const layer = { clip: c.clip, weight: c.weight, mode: c.mode, mask: ['Abdomen'],
      ...(c.mode === 'ADDITIVE' ? { referenceTime: 0 } : {}) };
    reference = await evaluate({ layers: [{ clip: walk, weight: 1 }, layer], sync: 'NONE' }, T);
    diff = maxDiff(shown.positions, reference);
    const lowerShift = maxDiff(shown.positions, walkAtT, lower);
    const upperShift = maxDiff(shown.positions, walkAtT, upper);
    check(diff < TOLERANCE, `Walking + ${c.name} on the upper body: drawn = EvaluateMotion (${diff.toExponential(2)})`);
    check(lowerShift < TOLERANCE && upperShift > 0.01 * height,
          `it moves only the ${upper.size} upper-body joints (by up to ${upperShift.toFixed(4)}; ` +
          `the ${lower.size} others by ${lowerShift.toExponential(2)})`);
    if (c.mode === 'OVERRIDE') await page.screenshot({ path: besides(screenshot, 'mask') });
    await drawnAfter(page, () => page.selectOption('#blend-mask-1', 'full'));
  }
}

// The crossfade: Walking → Running over 0.5 s of playback (at 0.25× speed: 2 s of the clock).
async function crossfade({ page, screenshot, evaluate, walk, run }) {
  let shown, reference, diff;
  await page.selectOption('#blend-clip-1', run);
  await page.selectOption('#blend-mode-1', 'OVERRIDE');
  await setSlider(page, '#blend-weight-0', 1);
  await drawnAfter(page, () => setSlider(page, '#blend-weight-1', 0));
  await page.selectOption('#speed', '0.25');
  const label = await page.textContent('#blend-fade');
  check(label === `Crossfade ${walk} → ${run}`, `the button says which way it fades (${label})`);
  await page.fill('#blend-fade-duration', String(FADE));
  await page.evaluate(() => {
    window.__fade = [];
    window.armatureViewer.blend.addEventListener('pose', ({ detail: { time, motion, pose } }) =>
      window.__fade.push({
        time, weights: motion.layers.map((l) => l.weight), translations: pose.translations,
        sliders: [0, 1].map((k) => Number(document.getElementById(`blend-weight-${k}`).value)),
      }));
  });
  await page.click('#blend-fade');
  const fade = await page.evaluate(() => ({ ...window.armatureViewer.blend.fade }));
  check(fade.from === 0 && fade.to === 1 && fade.duration === FADE, `the crossfade runs from layer 1 to 2 over ${fade.duration} s`);
  await page.waitForFunction(({ start, duration }) => {
    const samples = window.__fade;
    return samples.length > 0 && samples[samples.length - 1].time > start + duration + 0.1;
  }, fade, { timeout: 30000 });
  await page.click('#blend-play');  // pause
  const samples = await page.evaluate(() => window.__fade);
  let worst = 0, worstSlider = 0;
  for (const s of samples) {
    const p = Math.min(Math.max((s.time - fade.start) / FADE, 0), 1);
    worst = Math.max(worst, Math.abs(s.weights[0] - (1 - p)), Math.abs(s.weights[1] - p));
    worstSlider = Math.max(worstSlider, ...s.sliders.map((v, k) => Math.abs(v - s.weights[k])));
  }
  const inside = samples.filter((s) => s.time > fade.start + 0.05 * FADE && s.time < fade.start + 0.95 * FADE);
  check(inside.length >= 3 && worst < 1e-12,
        `${samples.length} frames, ${inside.length} inside the fade: weights = (1 − p, p), p = (t − ${fade.start.toFixed(3)}) / ${FADE} ` +
        `(worst ${worst.toExponential(2)}; at t = ${inside.map((s) => s.time.toFixed(3)).join(', ')})`);
  check(worstSlider <= 0.005 + 1e-12, `the sliders follow the ramp (within their 0.01 step: ${worstSlider.toFixed(4)})`);
  for (const s of [inside[0], inside[Math.floor(inside.length / 2)], inside[inside.length - 1]]) {
    const p = (s.time - fade.start) / FADE;
    const ramped = await evaluate({ layers: [{ clip: walk, weight: 1 - p }, { clip: run, weight: p }] }, s.time);
    diff = Math.max(...ramped.map((v, i) => Math.abs(v - s.translations[i])));
    check(diff < TOLERANCE, `at t = ${s.time.toFixed(3)} (p = ${p.toFixed(3)}) the frame is the two-layer blend (${diff.toExponential(2)})`);
  }
  const end = await page.evaluate(() => ({
    fade: window.armatureViewer.blend.fade,
    sliders: [0, 1].map((k) => document.getElementById(`blend-weight-${k}`).value),
    label: document.getElementById('blend-fade').textContent,
  }));
  check(end.fade === null && end.sliders[0] === '0' && end.sliders[1] === '1',
        `after the fade the sliders read ${end.sliders.join(' and ')}; the button now offers ${end.label}`);
  shown = await drawn(page);
  reference = await evaluate({ layers: [{ clip: walk, weight: 0 }, { clip: run, weight: 1 }] }, shown.time);
  diff = maxDiff(shown.positions, reference);
  check(diff < TOLERANCE, `paused after the fade, the drawn joints are Running's (${diff.toExponential(2)})`);

  const png = await page.screenshot({ path: screenshot });
  const bones = await colourStats(page, png, 'bone');
  check(bones.count > 500 && bones.height > 100, `the blended skeleton is drawn (${bones.count} bone-coloured pixels, ${bones.width}×${bones.height} px)`);
}

// Leaving blend mode shows the clip again; from a skinned mesh, Blend shows
// the mesh's skeleton alone, with the layers set before (same skeleton).
async function blendFromAMesh({ page, evaluate, asset, skeleton, walk, run }) {
  let shown, reference, diff;
  await page.uncheck('#blend');
  check(await page.isHidden('#blend-panel'), 'unticking Blend closes the panel');

  // From a skinned mesh, Blend shows the mesh's skeleton alone, with the layers set before (same skeleton).
  const mesh = asset.meshes.find((m) => m.skeleton === skeleton.name);
  await page.selectOption('#mesh', mesh.name);
  await page.waitForFunction(() => window.armatureViewer.meshPlayer.clip, null, { timeout: 30000 });
  shown = await drawnAfter(page, () => page.check('#blend'));
  const state = await page.evaluate(() => ({
    mesh: document.getElementById('mesh').value,
    layers: [0, 1].map((k) => document.getElementById(`blend-clip-${k}`).value),
  }));
  reference = await evaluate({ layers: [{ clip: walk, weight: 0 }, { clip: run, weight: 1 }] }, shown.time);
  diff = maxDiff(shown.positions, reference);
  check(state.mesh === '' && state.layers[0] === walk && state.layers[1] === run && diff < TOLERANCE,
        `from the mesh ${mesh.name}, Blend shows its skeleton with the layers kept (${diff.toExponential(2)})`);
}

await runViewerTest('blend_e2e.mjs', async ({ page, server, screenshot, expectConsoleError }) => {
  const rest = server.call;
  // World joint positions of `motion` at `time`, straight from the REST gateway.
  const evaluate = async (motion, time) =>
    (await rest('/v1/motions:evaluate', { motion, times: [time], space: 'WORLD' })).poses[0].translations;

  const asset = await server.importAsset('RobotExpressive.glb', 'robot', readFileSync(GLB));
  const clipNamed = (suffix) => asset.clips.find((c) => c.name.endsWith(`.${suffix}`))?.name;
  const [walk, run, wave, yes, idle] = ['Walking', 'Running', 'Wave', 'Yes', 'Idle'].map(clipNamed);
  check(walk && run && wave && yes && idle,
        `RobotExpressive imports with ${asset.clips.length} clips (${walk}, ${run}, ${wave}, ${yes}, ${idle})`);
  const skeleton = await rest(`/v1/skeletons/${encodeURIComponent(asset.clips[0].skeleton)}`);

  await page.goto(`${server.url}/?clip=${encodeURIComponent(walk)}`);
  await page.waitForFunction(() => window.armatureViewer?.player.skeleton, null, { timeout: 30000 });
  check(await page.isHidden('#blend-panel'), 'the blend panel is closed at first');
  let shown = await drawnAfter(page, () => page.check('#blend'));
  check(await page.isVisible('#blend-panel'), 'ticking Blend opens the panel');
  const options = await page.$$eval('#blend-clip-1 option', (os) => os.map((o) => o.value));
  check(options.length === asset.clips.length + 1 && options[0] === '',
        `a layer offers none and the ${options.length - 1} clips of the skeleton`);
  const firstTwo = [await page.$eval('#blend-clip-0', (s) => s.value), await page.$eval('#blend-clip-1', (s) => s.value)];
  check(firstTwo[0] === walk && firstTwo[1] === run, `the layers start as the clip and a run (${firstTwo.join(', ')})`);
  const walkOnly = await evaluate({ layers: [{ clip: walk }] }, 0);
  check(maxDiff(shown.positions, walkOnly) < TOLERANCE, 'at first the panel draws the clip alone (weights 1 and 0)');

  // Extent of the character, for "moved" thresholds.
  const ys = walkOnly.filter((_, i) => i % 3 === 1);
  const height = Math.max(...ys) - Math.min(...ys);

  const t = { page, screenshot, expectConsoleError, evaluate, asset, skeleton, walk, run, wave, yes, idle, height };
  const walkAtT = await weightsThroughControls(t);
  await phaseSync(t);
  await upperBodyMask(t, walkAtT);
  await crossfade(t);
  await blendFromAMesh(t);
});
