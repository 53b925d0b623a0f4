// The viewer page: choose a clip, play / pause, scrub, set the speed.
import * as api from './api.js';
import { IkDrag } from './ik_drag.js';
import { Player } from './player.js';
import { SkeletonView } from './skeleton_view.js';

const $ = (id) => document.getElementById(id);
const ui = {
  clip: $('clip'), play: $('play'), scrub: $('scrub'), speed: $('speed'),
  time: $('time'), frameTime: $('frame-time'), joints: $('joints'), rate: $('rate'), message: $('message'),
};

const view = new SkeletonView($('viewport'));
const player = new Player({ fps: 30 });
const ik = new IkDrag(view, player);
let scrubbing = false;
const arrivals = [];  // stream frame arrival times, for the rate shown

function showMessage(text) {
  ui.message.textContent = text ?? '';
}

player.addEventListener('load', ({ detail: { clip, skeleton } }) => {
  view.setSkeleton(skeleton);
  ui.scrub.max = String(clip.duration);
  ui.scrub.step = String(clip.frameTime > 0 ? clip.frameTime / 4 : clip.duration / 1000);
  ui.scrub.disabled = false;
  ui.play.disabled = false;
  ui.joints.textContent = `${skeleton.joints.length} joints`;
  ui.frameTime.textContent =
    clip.frameTime > 0 ? `frame time ${(clip.frameTime * 1000).toFixed(1)} ms` : 'key-framed';
});

player.addEventListener('pose', ({ detail: { time, pose, frame } }) => {
  view.setPose(pose);
  const clip = player.clip;
  const frameIndex = clip.frameTime > 0 ? Math.round(time / clip.frameTime) : null;
  ui.time.textContent =
    `t = ${time.toFixed(3)} / ${clip.duration.toFixed(3)} s` + (frameIndex !== null ? ` · frame ${frameIndex}` : '');
  if (!scrubbing) ui.scrub.value = String(time);
  if (frame) {
    const now = performance.now();
    arrivals.push(now);
    while (arrivals.length && now - arrivals[0] > 1000) arrivals.shift();
    ui.rate.textContent = `${arrivals.length} poses/s`;
  }
});

player.addEventListener('state', ({ detail: { playing } }) => {
  ui.play.textContent = playing ? 'Pause' : 'Play';
  if (!playing) ui.rate.textContent = '';
});

player.addEventListener('error', ({ detail }) => showMessage(detail));

ik.addEventListener('solve', ({ detail: { joint, response } }) => {
  const [residual] = response.residuals;
  showMessage(
    response.converged
      ? `IK: ${joint} reached (${response.iterations} iterations)`
      : `IK: ${joint} out of reach by ${residual.positionError.toFixed(2)}`,
  );
});
ik.addEventListener('error', ({ detail }) => showMessage(`IK: ${detail}`));

ui.play.addEventListener('click', () => (player.playing ? player.pause() : player.play()));
ui.scrub.addEventListener('pointerdown', () => (scrubbing = true));
ui.scrub.addEventListener('pointerup', () => (scrubbing = false));
ui.scrub.addEventListener('input', () => player.seek(Number(ui.scrub.value)));
ui.speed.addEventListener('change', () => player.setSpeed(Number(ui.speed.value)));
ui.clip.addEventListener('change', () => {
  showMessage('');
  player.load(ui.clip.value).catch((e) => showMessage(e.message));
});

async function start() {
  const clips = await api.listClips();
  if (clips.length === 0) {
    showMessage('No clips loaded: import one (armature import file.bvh)');
    return;
  }
  for (const clip of clips) ui.clip.add(new Option(`${clip.name} (${clip.duration.toFixed(2)} s)`, clip.name));
  const wanted = new URLSearchParams(location.search).get('clip');
  if (wanted && clips.some((c) => c.name === wanted)) ui.clip.value = wanted;
  await player.load(ui.clip.value);
}

// For tests and the console.
window.armatureViewer = { player, view, ik };

start().catch((e) => showMessage(`Cannot reach the server: ${e.message}`));
