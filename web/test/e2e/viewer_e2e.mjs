// The viewer end to end: a real armature-server serves the page, headless
// Chromium (Debian's, driven by playwright-core) plays the demo clip. Checks
// that frames arrive over gRPC-Web, that the skeleton is drawn (pixels of the
// bone colour in a screenshot, and different ones as it walks), scrubbing
// while paused, and that the console shows no errors. Saves a screenshot.
//   node viewer_e2e.mjs <armature-server> <web dir> <screenshot.png>
import { besides, check, colourStats, runViewerTest } from '../support/browser.mjs';

// Every call the viewer makes is gRPC-Web (binary protobuf), none REST JSON:
// the paths it calls, and any REST or non-binary call.
function watchCalls(page) {
  const calls = { grpcWeb: new Set(), rest: [] };
  page.on('request', (r) => {
    const url = new URL(r.url());
    if (url.pathname.startsWith('/armature.v1.')) {
      calls.grpcWeb.add(url.pathname);
      if (r.headers()['content-type'] !== 'application/grpc-web+proto') calls.rest.push(`${url.pathname} as ${r.headers()['content-type']}`);
    } else if (url.pathname.startsWith('/v1/')) {
      calls.rest.push(url.pathname);
    }
  });
  return calls;
}

// Plays the clip: frames arrive over gRPC-Web and the skeleton is drawn, moving.
async function playAndDraw(page, screenshot, calls) {
  await page.click('#play');
  await page.waitForFunction(() => window.armatureViewer.player.stats.framesReceived >= 45, null, { timeout: 30000 });
  const playing = await page.evaluate(() => ({ ...window.armatureViewer.player.stats, time: window.armatureViewer.player.time }));
  check(playing.framesReceived >= 45, `poses arrive over gRPC-Web (${playing.framesReceived} frames, clip time ${playing.time.toFixed(3)} s)`);
  check(/poses\/s/.test(await page.textContent('#rate')), `the stream rate is shown (${await page.textContent('#rate')})`);
  const first = await page.screenshot();
  await page.waitForFunction((n) => window.armatureViewer.player.stats.framesReceived >= n + 10, playing.framesReceived);
  await page.click('#play');  // pause
  await page.waitForFunction(() => !window.armatureViewer.player.playing);
  const second = await page.screenshot({ path: screenshot });
  check(calls.grpcWeb.has('/armature.v1.PoseService/StreamClip') && calls.grpcWeb.has('/armature.v1.AssetService/ListClips'),
    `the viewer calls over gRPC-Web (${[...calls.grpcWeb].join(', ')})`);

  const a = await colourStats(page, first, 'bone');
  const b = await colourStats(page, second, 'bone');
  check(a.count > 800 && b.count > 800, `the skeleton is drawn (${a.count} and ${b.count} bone-coloured pixels of ${b.pixels})`);
  check(b.height > 150 && b.width > 30, `it has a body's extent (${b.width}×${b.height} px)`);
  check(!first.equals(second), 'the picture changes as the clip plays');
}

// Scrubs while paused, then plays at 2× from there.
async function scrubAndSpeed(page) {
  // One EvaluateClip at the slider's time.
  const before = await page.evaluate(() => window.armatureViewer.player.stats.evaluations);
  await page.$eval('#scrub', (s) => {
    s.value = '1.5';
    s.dispatchEvent(new Event('input'));
  });
  await page.waitForFunction((n) => window.armatureViewer.player.stats.evaluations > n, before);
  const shown = await page.textContent('#time');
  check(/t = 1\.500/.test(shown), `scrubbing shows the pose at the slider's time (${shown})`);

  // Speed 2×: the new stream's frames step 2/30 s of clip time each.
  await page.evaluate(() => {
    window.__frameTimes = [];
    window.armatureViewer.player.addEventListener('pose', (e) => e.detail.frame && window.__frameTimes.push(e.detail.time));
  });
  await page.selectOption('#speed', '2');
  await page.click('#play');
  await page.waitForFunction(() => window.__frameTimes.length >= 6, null, { timeout: 30000 });
  await page.click('#play');
  const times = await page.evaluate(() => window.__frameTimes.slice(0, 6));
  const steps = times.slice(1).map((t, i) => t - times[i]);
  check(Math.abs(times[0] - 1.5) < 1e-6 && steps.every((d) => Math.abs(d - 2 / 30) < 1e-6),
        `playing at 2× from the scrubbed time steps ${steps.map((d) => d.toFixed(4)).join(', ')} s per frame`);
}

// IK: drags the left wrist with the mouse; the skeleton follows through
// an IkSession over a WebSocket, the other end joints stay pinned.
async function dragTheWrist(page, screenshot) {
  const beforeIk = await page.evaluate(() => window.armatureViewer.player.stats.evaluations);
  await page.$eval('#scrub', (s) => {
    s.value = '1.0';
    s.dispatchEvent(new Event('input'));
  });
  await page.waitForFunction((n) => window.armatureViewer.player.stats.evaluations > n, beforeIk);
  const grab = await page.evaluate(() => {
    const { view, ik } = window.armatureViewer;
    const names = view.skeleton.joints.map((j) => j.name);
    const wrist = names.indexOf('LeftWrist');
    const at = ik.screenPosition(wrist);
    const nearest = Math.min(...names.map((_, i) => i === wrist ? Infinity : Math.hypot(
      ik.screenPosition(i).x - at.x, ik.screenPosition(i).y - at.y)));
    const world = (i) => view.joints[i].position.toArray();
    return { wrist, at, nearest, world: world(wrist), pinned: world(names.indexOf('RightWrist')) };
  });
  check(grab.nearest > 16, `the left wrist can be grabbed (the nearest other joint is ${grab.nearest.toFixed(1)} px away)`);
  const drop = { x: grab.at.x + 40, y: grab.at.y - 60 };
  await page.mouse.move(grab.at.x, grab.at.y);
  await page.mouse.down();
  await page.mouse.move(drop.x, drop.y, { steps: 15 });
  await page.mouse.up();
  await page.waitForFunction(() => {
    const { ik } = window.armatureViewer;
    return !ik.busy && ik.stats.solves > 0;
  }, null, { timeout: 30000 });
  const dragged = await page.evaluate(({ wrist }) => {
    const { view, ik } = window.armatureViewer;
    const names = view.skeleton.joints.map((j) => j.name);
    return {
      stats: { solves: ik.stats.solves, converged: ik.stats.converged },
      joint: ik.stats.lastResponse.residuals[0].joint,
      converged: ik.stats.lastResponse.converged,
      at: ik.screenPosition(wrist),
      world: view.joints[wrist].position.toArray(),
      pinned: view.joints[names.indexOf('RightWrist')].position.toArray(),
      message: document.getElementById('message').textContent,
    };
  }, grab);
  const moved = Math.hypot(...dragged.world.map((v, k) => v - grab.world[k]));
  const pinShift = Math.hypot(...dragged.pinned.map((v, k) => v - grab.pinned[k]));
  const miss = Math.hypot(dragged.at.x - drop.x, dragged.at.y - drop.y);
  check(dragged.joint === 'LeftWrist' && dragged.stats.solves >= 2,
        `dragging solves IK for the wrist (${dragged.stats.solves} IkSession steps over a WebSocket, ${dragged.stats.converged} converged)`);
  check(dragged.converged && /LeftWrist reached/.test(dragged.message), `the last solve converged (${dragged.message})`);
  check(moved > 10, `the wrist moved ${moved.toFixed(1)} units in the world`);
  check(miss < 2, `the wrist is drawn under the pointer (${miss.toFixed(2)} px away)`);
  check(pinShift < 0.05, `the other wrist stayed pinned (moved ${pinShift.toFixed(4)})`);
  await page.screenshot({ path: besides(screenshot, 'ik') });
}

await runViewerTest('viewer_e2e.mjs', async ({ page, server, screenshot }) => {
  const calls = watchCalls(page);
  // The seeded clips sort demo_character.walk first; this test plays the BVH demo.
  await page.goto(server.url + '/?clip=demo_walk');
  await page.waitForFunction(() => window.armatureViewer?.player.skeleton, null, { timeout: 30000 });
  const clip = await page.$eval('#clip', (s) => s.value);
  check(clip === 'demo_walk', `the clip list offers the demo (selected: ${clip})`);
  check((await page.textContent('#joints')) === '19 joints', 'the joint count is on screen');
  check(/frame time 33\.3 ms/.test(await page.textContent('#frame-time')), 'the frame time is on screen');

  await playAndDraw(page, screenshot, calls);
  await scrubAndSpeed(page);
  await dragTheWrist(page, screenshot);
  check(calls.rest.length === 0, `no REST JSON call${calls.rest.length ? ': ' + calls.rest.join(', ') : ''} (the IK drag included)`);
});
