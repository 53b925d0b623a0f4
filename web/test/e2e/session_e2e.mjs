// The viewer's drags run real sessions over WebSockets, timed against gRPC on
// the same server: drags the left wrist (an IkSession on
// ws://…/v1/skeletons/demo_walk:ikSession) and a vertex of a 40×40 grid (a
// DeformSession on ws://…/v1/meshes:deformSession), step by step; then
// replays each session's very requests over gRPC with session_replay
// (tests/tools/), and over WebSockets from the page: to the server, and to a
// peer that only answers (ws_echo.mjs) with frames of the server's answers'
// size, which is the browser's own round trip. Logs every step beside the
// gRPC one, and the medians; asserts the whole step against
// ARMATURE_SESSION_RTT_RATIO only when that is set.
//   node session_e2e.mjs <armature-server> <web dir> <screenshot.png> <session_replay>
import { execFileSync } from 'node:child_process';
import { existsSync, mkdtempSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import path from 'node:path';
import { besides, check, runViewerTest } from '../support/browser.mjs';
import { bumpGridObj } from '../support/fixtures.mjs';
import { startEcho } from '../support/ws_echo.mjs';

const replayBin = process.argv[5];
const STEPS = 30;
const REPLAYS = 5;
const grid = bumpGridObj();
const MESH = 'plane';

const median = (values) => {
  const sorted = [...values].sort((a, b) => a - b);
  return sorted[Math.floor(sorted.length / 2)];
};

// Drags from `from` by (dx, dy) px in STEPS moves, each waited for until
// `drag` answered it (its `event`), so every move is one session step.
//
// The button goes down and up through Chromium's input (CDP); the moves are
// PointerEvents dispatched on the canvas in the page. Each CDP mouse move
// costs this 2-core machine about 1.3 ms of browser-process, renderer and
// test-process work while the step is in flight, which a user's mouse does
// not (viewer_e2e and deform_e2e drag with CDP moves). Headless Chromium
// also draws WebGL on the CPU (SwiftShader): its 60 Hz draw loop alone keeps
// the cores busy, which a GPU spares a real browser, so the timed drag runs
// with the draw loop stopped; it starts again (and draws the result) after.
async function dragInSteps(page, from, dx, dy, drag, event) {
  await page.evaluate(() => window.armatureViewer.view.renderer.setAnimationLoop(null));
  await page.mouse.move(from.x, from.y);
  await page.mouse.down();
  await page.evaluate(async ({ from, dx, dy, drag, event, steps }) => {
    const target = window.armatureViewer[drag];
    const canvas = window.armatureViewer.view.renderer.domElement;
    for (let i = 1; i <= steps; ++i) {
      const answered = new Promise((resolve, reject) => {
        target.addEventListener(event, resolve, { once: true });
        target.addEventListener('error', (e) => reject(new Error(`step ${i}: ${e.detail}`)), { once: true });
      });
      canvas.dispatchEvent(new PointerEvent('pointermove', {
        clientX: from.x + (dx * i) / steps, clientY: from.y + (dy * i) / steps,
        pointerId: 1, pointerType: 'mouse', buttons: 1, bubbles: true,
      }));
      await Promise.race([answered, new Promise((_, reject) => setTimeout(() => reject(new Error(`step ${i}: no ${event} ${JSON.stringify(target.stats, (k, v) => (k === 'sessions' ? v.map((x) => [x.log.sent.length, x.log.roundTrips.length, x.pending, x.isOpen]) : k === 'lastResponse' ? undefined : v))} busy ${target.busy}`)), 30000))]);
    }
  }, { from, dx, dy, drag, event, steps: STEPS });
  await page.mouse.up();
  await page.evaluate(() => {
    const { view } = window.armatureViewer;
    view.renderer.setAnimationLoop(() => view.render());
  });
}

// The latest session of `drag` ('ik' or 'vertexDrag'): its URL, how each
// request travelled, the requests as JSON, and the round trips.
function lastSession(drag) {
  const s = window.armatureViewer[drag].stats.sessions.at(-1).log;
  const frames = s.sent.map((m) => (typeof m === 'string' ? 'text' : 'binary'));
  return { url: s.url, frames, requests: s.requests, roundTrips: s.roundTrips, pageRoundTrips: s.pageRoundTrips };
}

// Sends the latest session of `drag`'s very frames again, back to back, over
// a new WebSocket from a worker of the page (as the viewer's WorkerWebSocket does) to `url`,
// or with `echo` to that peer asking for answers of the size the server
// gave; resolves with each step's round trip (the first frame left out) and
// that size.
function replayInPage({ drag, url, echo, answerBytes }) {
  const frames = window.armatureViewer[drag].stats.sessions.at(-1).log.sent;
  const target = echo ? `${echo}?answer=${answerBytes}` : url;
  const worker = new Worker(URL.createObjectURL(new Blob([`onmessage = async ({ data }) => {
    const socket = new WebSocket(data.target);
    socket.binaryType = 'arraybuffer';
    await new Promise((resolve) => (socket.onopen = resolve));
    const steps = [];
    let i = 0, sentAt = 0, answerBytes = 0;
    await new Promise((done) => {
      socket.onmessage = (e) => {
        answerBytes = e.data.byteLength ?? e.data.length;
        if (i > 0) steps.push(performance.now() - sentAt);
        if (++i === data.frames.length) return done();
        sentAt = performance.now();
        socket.send(data.frames[i]);
      };
      socket.send(data.frames[0]);
    });
    socket.close(1000);
    postMessage({ steps, answerBytes });
  }`], { type: 'text/javascript' })));
  return new Promise((resolve) => {
    worker.onmessage = ({ data }) => {
      worker.terminate();
      resolve(data);
    };
    worker.postMessage({ target, frames });
  });
}

// Replays the drag's requests over gRPC (3 times), and its frames from the
// page to the server and to the echo peer (REPLAYS times each), and logs the
// step round trips; the first request (the session's opening) is left out of
// all.
async function compare(page, server, echo, kind, drag, session) {
  const dir = mkdtempSync(path.join(tmpdir(), 'armature-replay-'));
  let grpc;
  try {
    const file = path.join(dir, 'requests.jsonl');
    writeFileSync(file, session.requests.map((r) => JSON.stringify(r)).join('\n') + '\n');
    const out = execFileSync(replayBin, [`127.0.0.1:${server.grpcPort}`, kind, file, '3'], { encoding: 'utf8' });
    grpc = JSON.parse(out).roundTripsMs;
  } finally {
    rmSync(dir, { recursive: true, force: true });
  }
  const replays = [], echoes = [];  // REPLAYS runs each, taken in turn so that load changes touch both alike
  for (let r = 0; r < REPLAYS; ++r) {
    const replay = await page.evaluate(replayInPage, { drag, url: session.url });
    replays.push(...replay.steps);
    echoes.push(...(await page.evaluate(replayInPage, { drag, echo: echo.url, answerBytes: replay.answerBytes })).steps);
  }
  const ws = session.roundTrips.slice(1);
  const handled = session.pageRoundTrips.slice(1);
  const steps = session.requests.length - 1;
  console.log(`${kind} drag, ${steps} steps: round trip per step over the WebSocket (answer received in the ` +
              `page's socket worker; handled by the page's thread) | over gRPC (3 replays of the same requests)`);
  ws.forEach((ms, i) => console.log(`  step ${String(i + 1).padStart(2)}: WebSocket ${ms.toFixed(3)} ms ` +
    `(page ${handled[i].toFixed(1)} ms) | gRPC ` + [0, 1, 2].map((r) => grpc[r * steps + i].toFixed(3)).join(', ') + ' ms'));
  const figures = { kind, ws: median(ws), grpc: median(grpc), replay: median(replays), echo: median(echoes) };
  console.log(`${kind}: median step: drag over the WebSocket ${figures.ws.toFixed(3)} ms (handled by the page's ` +
              `thread after ${median(handled).toFixed(1)} ms), gRPC ${figures.grpc.toFixed(3)} ms, ratio ` +
              `${(figures.ws / figures.grpc).toFixed(2)}; the same frames replayed from the page ${REPLAYS} times: ` +
              `to the server ${figures.replay.toFixed(3)} ms, to the echo peer (the browser's own round trip) ` +
              `${figures.echo.toFixed(3)} ms`);
  return figures;
}

await runViewerTest('session_e2e.mjs', async ({ page, server, screenshot }) => {
  check(replayBin && existsSync(replayBin), `session_replay is built (${replayBin})`);
  const echo = await startEcho();
  try {
    await dragAndCompare(page, server, echo, screenshot);
  } finally {
    await echo.close();
  }
});

async function dragAndCompare(page, server, echo, screenshot) {

  // IK: the left wrist dragged in STEPS steps over one IkSession.
  await page.goto(server.url + '/?clip=demo_walk');
  await page.waitForFunction(() => window.armatureViewer?.player.skeleton, null, { timeout: 30000 });
  check(await page.evaluate(() => globalThis.crossOriginIsolated), 'the viewer is cross-origin isolated (5 µs timers)');
  // Paused (as the viewer opens) at 1 s, the pose drawn from that evaluation.
  await page.waitForFunction(() => window.armatureViewer.player.stats.evaluations > 0, null, { timeout: 30000 });
  const evaluations = await page.evaluate(() => window.armatureViewer.player.stats.evaluations);
  await page.$eval('#scrub', (s) => {
    s.value = '1.0';
    s.dispatchEvent(new Event('input'));
  });
  await page.waitForFunction((n) => window.armatureViewer.player.stats.evaluations > n, evaluations);
  const at = await page.evaluate(() => {
    const { view, ik } = window.armatureViewer;
    return ik.screenPosition(view.skeleton.joints.findIndex((j) => j.name === 'LeftWrist'));
  });
  await dragInSteps(page, at, 40, -60, 'ik', 'solve');
  await page.waitForFunction(() => !window.armatureViewer.ik.busy, null, { timeout: 30000 });
  const ik = await page.evaluate(lastSession, 'ik');
  const skeleton = decodeURIComponent(ik.url.match(/\/v1\/skeletons\/(.*):ikSession$/)?.[1] ?? '');
  check(ik.url.startsWith('ws://') && skeleton === 'demo_walk', `the IK drag runs over a WebSocket (${ik.url})`);
  check(ik.frames.length === STEPS && ik.roundTrips.length === STEPS && ik.frames.every((f) => f === 'binary'),
        `one session in binary frames: the start and ${ik.frames.length - 1} target moves, each answered`);
  check(ik.requests.slice(1).every((r) => r.targets?.length === 1 && !r.start), 'later messages carry only the new target');
  ik.requests[0].start.skeleton = skeleton;  // the path gave it to the WebSocket session
  const results = [await compare(page, server, echo, 'ik', 'ik', ik)];
  await page.screenshot({ path: besides(screenshot, 'ik') });

  // Deform: a grid vertex dragged in STEPS steps over one DeformSession.
  await server.importAsset('plane.obj', MESH, grid.text);
  await page.goto(server.url + '/?clip=demo_walk');
  await page.waitForFunction(() => window.armatureViewer?.player.skeleton, null, { timeout: 30000 });
  await page.selectOption('#mesh', MESH);
  await page.waitForFunction((mesh) => window.armatureViewer.meshView.geometry?.mesh === mesh, MESH, { timeout: 30000 });
  await page.check('#edit');
  await page.waitForFunction(() => window.armatureViewer.vertexDrag.editing);
  const vertex = (grid.n / 2) * grid.n + grid.n / 2;  // the middle
  const from = await page.evaluate((v) => window.armatureViewer.vertexDrag.screenPosition(v), vertex);
  await dragInSteps(page, from, 40, -90, 'vertexDrag', 'deform');
  await page.waitForFunction(() => !window.armatureViewer.vertexDrag.busy, null, { timeout: 30000 });
  const deform = await page.evaluate(lastSession, 'vertexDrag');
  check(deform.url.startsWith('ws://') && deform.url.endsWith('/v1/meshes:deformSession'),
        `the vertex drag runs over a WebSocket (${deform.url})`);
  check(deform.frames.slice(1).every((f) => f === 'binary'), 'its moves travel as binary frames');
  check(deform.requests[0].start?.handleIndices?.[0] === vertex && deform.requests.length === STEPS + 1 &&
        deform.requests.slice(1).every((r) => r.move?.positions?.length === 3),
        `one session: the setup with handle ${vertex} and ${deform.requests.length - 1} moves, each answered ` +
        `(${deform.roundTrips.length} round trips)`);
  results.push(await compare(page, server, echo, 'deform', 'vertexDrag', deform));
  await page.screenshot({ path: screenshot });
  // The goal is each step within 2× the gRPC step. Headless Chromium
  // on this machine cannot reach it whatever the server does: its own round
  // trip to a peer that only answers is already 0.45-0.75 ms, two to ten
  // times a 0.06-0.25 ms gRPC step, and it grows with the answer's size far
  // faster than gRPC's. So the figures are logged: the whole step, and what
  // the server's WebSocket path adds to the browser's own round trip (the
  // same frames replayed from the page to the server and to the echo peer).
  // Timings are not asserted (a loaded machine stretches any of them; the
  // server's side is held to 2× gRPC in WebSocketSession from C++), except
  // the whole step against ARMATURE_SESSION_RTT_RATIO when that is set.
  const bound = Number(process.env.ARMATURE_SESSION_RTT_RATIO ?? 0);
  for (const { kind, ws, grpc, replay, echo: own } of results) {
    const added = replay - own;
    const part = `${kind}: the WebSocket path adds ${added.toFixed(3)} ms to the browser's own round trip ` +
                 `(${own.toFixed(3)} ms): ${(added / grpc).toFixed(2)}× the gRPC step ${grpc.toFixed(3)} ms`;
    console.log(`measured: ${part}`);
    const line = `${kind}: drag step median ${ws.toFixed(3)} ms = ${(ws / grpc).toFixed(2)}× the gRPC step median ` +
                 `${grpc.toFixed(3)} ms (goal: 2×)`;
    if (bound > 0) check(ws / grpc <= bound, `${line}, within ${bound}×`);
    else console.log(`measured: ${line}`);
  }
}
