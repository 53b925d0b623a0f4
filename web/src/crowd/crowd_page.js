// The crowd page (crowd.html): `count` characters of one skeleton (by
// default the skeleton with the most clips, e.g. RobotExpressive) on its
// clips in turn, at staggered offsets and speeds, laid out on a grid, in one
// CrowdSession over the server's WebSocket. Frames update the characters due
// each tick; the others are drawn interpolated (crowd_poses.js); every bone of
// every character is one instance (crowd_view.js). The HUD shows the drawing
// rate and the server's tick figures.
//   crowd.html?skeleton=<name>&count=1000&fps=30&budget=<ms>
import * as THREE from 'three';

import * as api from '../api.js';
import { CrowdPoses } from './crowd_poses.js';
import { CrowdView } from './crowd_view.js';

const params = new URLSearchParams(location.search);
const count = Math.max(1, Number(params.get('count') ?? 1000));
const fps = Number(params.get('fps') ?? 30);
const budgetMs = Number(params.get('budget') ?? 0);  // 0: the server's --crowd-budget-ms
const MAX_DRAW_COST_MS = 150;  // at least about three draws a second, whatever the page stalls on
const $ = (id) => document.getElementById(id);
const hud = {
  rate: $('crowd-fps'), tick: $('crowd-tick'), updated: $('crowd-updated'), deferred: $('crowd-deferred'),
  late: $('crowd-late'), budget: $('crowd-budget'), work: $('crowd-work'), characters: $('crowd-characters'),
  message: $('message'),
};
const state = {
  count, skeleton: '', clips: [], framesReceived: 0, lastTick: -1, lateTicks: 0, rendered: 0, drawRate: 0,
  stats: null, errors: [],
};
window.armatureCrowd = state;

// The skeleton asked for, or the one with the most clips.
function chooseSkeleton(clips) {
  if (params.get('skeleton')) return params.get('skeleton');
  const clipsOf = new Map();
  for (const c of clips) clipsOf.set(c.skeleton, (clipsOf.get(c.skeleton) ?? 0) + 1);
  return [...clipsOf].sort((a, b) => b[1] - a[1] || a[0].localeCompare(b[0]))[0]?.[0];
}

// The rest pose's extent (height along y, width across x and z), from its world joint positions.
function restExtent(skeleton) {
  const poses = new CrowdPoses(skeleton.joints.map((j) => j.parent), 1);
  const rest = (key, fallback) => Float32Array.from(skeleton.joints.flatMap((j) => (j[key]?.length ? j[key] : fallback)));
  poses.apply(0, {
    ids: [0], joints: skeleton.joints.length, rotations: rest('restRotation', [1, 0, 0, 0]),
    translations: rest('offset', [0, 0, 0]), scales: rest('restScale', [1, 1, 1]),
  });
  const at = new Float32Array(skeleton.joints.length * 3);
  poses.worldPositions(0, 0, at);
  const span = (k) => {
    const v = at.filter((_, i) => i % 3 === k);
    return Math.max(...v) - Math.min(...v);
  };
  return { height: Math.max(span(1), 1e-3), width: Math.max(span(0), span(2), 1e-3), positions: at };
}

function showStats(tick) {
  const s = tick.stats;
  state.stats = s;
  state.lateTicks += s?.late ? 1 : 0;
  hud.tick.textContent = String(tick.tick);
  hud.characters.textContent = String(s?.characters ?? 0);
  hud.updated.textContent = String(s?.updated ?? 0);
  hud.deferred.textContent = String(s?.deferred ?? 0);
  hud.late.textContent = String(state.lateTicks);
  hud.budget.textContent = (s?.budgetMs ?? 0).toFixed(2);
  hud.work.textContent = (s?.workMs ?? 0).toFixed(2);
}

async function run() {
  const allClips = await api.listClips();
  state.skeleton = chooseSkeleton(allClips);
  const clips = allClips.filter((c) => c.skeleton === state.skeleton).sort((a, b) => a.name.localeCompare(b.name));
  if (clips.length === 0) throw new Error('no clips: import a character with clips (e.g. RobotExpressive.glb)');
  state.clips = clips.map((c) => c.name);
  const skeleton = await api.getSkeleton(state.skeleton);
  const parents = skeleton.joints.map((j) => j.parent);
  const extent = restExtent(skeleton);
  const spacing = Math.max(extent.width * 1.6, extent.height * 0.6);
  const columns = Math.ceil(Math.sqrt(count)), rows = Math.ceil(count / columns);
  const colours = clips.map((_, i) => new THREE.Color().setHSL(i / clips.length, 0.65, 0.58));
  // Bones of no length at rest (nodes that only hold a mesh) are not drawn.
  const at = extent.positions, shown = (p, k) => Math.hypot(...[0, 1, 2].map((i) => at[3 * k + i] - at[3 * p + i])) >
    1e-3 * extent.height;
  const view = new CrowdView($('viewport'), parents, count, (c) => colours[c % clips.length], shown);
  view.frame(columns * spacing, rows * spacing, extent.height);
  const poses = new CrowdPoses(parents, count);
  Object.assign(state, { view, poses });

  const session = await api.openCrowdSession({ fps, budgetMs, maxInterval: 8 });
  state.session = session;
  addEventListener('pagehide', () => session.close());
  const eye = view.camera.position;
  for (let c = 0; c < count; ++c) {
    const x = (c % columns - (columns - 1) / 2) * spacing, z = (Math.floor(c / columns) - (rows - 1) / 2) * spacing;
    poses.roots.set([x, 0, z], c * 3);
    const clip = clips[c % clips.length];
    session.add({
      id: c, clip: clip.name, timeOffset: ((c * 0.618034) % 1) * clip.duration, speed: 0.8 + ((c * 0.381966) % 1) * 0.4,
      root: { translation: [x, 0, z], rotation: [1, 0, 0, 0] },
      significance: 1 / (1 + Math.hypot(x - eye.x, z - eye.z)),  // nearer the camera: updated more often
    });
  }

  let arrival = performance.now();
  const positions = new Float32Array(count * parents.length * 3);
  const drawTimes = [];
  let drawnAt = -Infinity, drawCost = 0;  // the latest draw's start and its whole cost, until the next animation frame
  view.renderer.setAnimationLoop(() => {
    const now = performance.now();
    // A draw costs more than its call (the GPU's work, software GL in a test): after one, skip
    // animation frames for as long again, so the session's frames are read between draws. The
    // cost is capped: a stall of the page (a loaded machine, a collection) is not the draw's,
    // and skipping twice a stall froze the view (CI saw 3 draws in 3 s).
    if (drawnAt > 0 && drawCost === 0) state.drawCost = drawCost = Math.min(now - drawnAt, MAX_DRAW_COST_MS);
    if (now - drawnAt < 2 * drawCost) return;
    drawnAt = now;
    drawCost = 0;
    drawTimes.push(now);
    while (drawTimes.length > 1 && now - drawTimes[0] > 1000) drawTimes.shift();
    if (drawTimes.length > 1) state.drawRate = (1000 * (drawTimes.length - 1)) / (now - drawTimes[0]);
    hud.rate.textContent = state.drawRate.toFixed(1);
    // Between frames the crowd moves on by the time since the latest one, up to a tick.
    const renderTick = state.lastTick + Math.min(1, ((now - arrival) / 1000) * fps);
    for (let c = 0; c < count; ++c) poses.worldPositions(c, renderTick, positions, c * parents.length * 3);
    const posed = performance.now();
    view.draw(positions);
    state.rendered += 1;
    state.poseMs = posed - now;
    state.drawMs = performance.now() - posed;
  });
  for await (const tick of session.frames()) {
    poses.apply(tick.tick, tick.poses);
    arrival = performance.now();
    state.lastTick = tick.tick;
    state.framesReceived += 1;
    state.errors.push(...tick.errors.map((e) => e.error));
    if (tick.errors.length) hud.message.textContent = tick.errors[0].error;
    showStats(tick);
  }
}

run().catch((e) => {
  hud.message.textContent = e.message;
  state.failure = e.message;
  console.error(e);
});
