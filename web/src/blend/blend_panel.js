// The blend panel: up to three clips of the loaded skeleton, each with a
// weight, a mode (override or additive) and a mask (full or upper body), a
// phase-sync toggle and a crossfade between the first two layers. Playing
// advances the motion time with the page's clock (times the speed) and
// evaluates the motion once per animation frame with EvaluateMotion, one call
// in flight and the latest time winning; paused, every change evaluates the
// current time once. Emits 'pose' ({ time, motion, pose, frame }), 'state'
// ({ playing }) and 'error' (message).
import * as api from '../api.js';
import { buildMotion, crossfadeWeights, upperBodyJoint } from './blend_motion.js';
import { LatestWins } from '../latest_wins.js';

const LAYERS = 3;

export class BlendPanel extends EventTarget {
  // `root`: the panel's element (its static controls are looked up by id);
  // `speed()`: the playback speed.
  constructor(root, { speed = () => 1 } = {}) {
    super();
    this.root = root;
    this.speed = speed;
    this.enabled = false;
    this.skeleton = null;
    this.clips = [];  // names of the clips of `skeleton`
    this.upperBody = '';  // the upper-body mask joint's name, '' when the skeleton has none
    this.layers = Array.from({ length: LAYERS }, () => ({ clip: '', weight: 0, mode: 'OVERRIDE', upperBody: false }));
    this.sync = 'NONE';
    this.time = 0;
    this.playing = false;
    this.fade = null;  // { from, to, start, duration } while a crossfade runs
    this.last = null;  // what is drawn: { time, motion, pose }
    this.stats = { evaluations: 0, frames: 0 };
    this.generation = 0;  // bumped when answers in flight no longer apply
    this.sampler = new LatestWins((time) => this.sampleAndShow(time));
    this.ui = this.buildControls();
  }

  emit(type, detail) {
    this.dispatchEvent(new CustomEvent(type, { detail }));
  }

  buildControls() {
    const byId = (id) => this.root.querySelector(`#${id}`);
    const ui = {
      layers: [], sync: byId('blend-sync'), play: byId('blend-play'), fade: byId('blend-fade'),
      fadeDuration: byId('blend-fade-duration'), time: byId('blend-time'), upperBody: byId('blend-upper-body'),
    };
    const container = byId('blend-layers');
    for (let k = 0; k < LAYERS; ++k) {
      const row = document.createElement('div');
      row.className = 'row blend-layer';
      const label = `layer ${k + 1}`;
      row.innerHTML =
        `<span class="layer-name">${k + 1}</span>` +
        `<select id="blend-clip-${k}" aria-label="${label} clip"></select>` +
        `<input id="blend-weight-${k}" type="range" min="0" max="1" step="0.01" aria-label="${label} weight">` +
        `<span class="weight" id="blend-weight-value-${k}"></span>` +
        `<select id="blend-mode-${k}" aria-label="${label} mode">` +
        '<option value="OVERRIDE">override</option><option value="ADDITIVE">additive</option></select>' +
        `<select id="blend-mask-${k}" aria-label="${label} mask">` +
        '<option value="full">full body</option><option value="upper">upper body</option></select>';
      container.append(row);
      const [clip, weight, weightValue, mode, mask] = ['clip', 'weight', 'weight-value', 'mode', 'mask']
        .map((part) => row.querySelector(`#blend-${part}-${k}`));
      ui.layers.push({ clip, weight, weightValue, mode, mask });
      const layer = this.layers[k];
      clip.addEventListener('change', () => this.changed(() => (layer.clip = clip.value)));
      weight.addEventListener('input', () => this.changed(() => (layer.weight = Number(weight.value))));
      mode.addEventListener('change', () => this.changed(() => (layer.mode = mode.value)));
      mask.addEventListener('change', () => this.changed(() => (layer.upperBody = mask.value === 'upper')));
    }
    ui.sync.addEventListener('change', () => this.changed(() => (this.sync = ui.sync.checked ? 'PHASE' : 'NONE')));
    ui.play.addEventListener('click', () => (this.playing ? this.pause() : this.play()));
    ui.fade.addEventListener('click', () => this.crossfade(Number(ui.fadeDuration.value)));
    return ui;
  }

  // A setting changed by hand: it ends any crossfade, and shows.
  changed(apply) {
    this.fade = null;
    apply();
    this.showControls();
    if (!this.playing) this.refresh();
  }

  // The skeleton (a GetSkeleton response) and the names of its clips;
  // `current` plays first. Layers keep their clips when the skeleton is the
  // same; otherwise layer 1 plays `current` at weight 1 and layer 2 the next
  // clip (a run after a walk, when there is one) at weight 0.
  setCharacter(skeleton, clips, current) {
    const same = this.skeleton?.name === skeleton.name;
    this.skeleton = skeleton;
    this.clips = clips;
    const upper = upperBodyJoint(skeleton);
    this.upperBody = upper >= 0 ? skeleton.joints[upper].name : '';
    const keep = same && this.layers.every((layer) => !layer.clip || clips.includes(layer.clip));
    if (!keep) {
      const second = (/walk/i.test(current) && clips.find((c) => /run/i.test(c))) ||
        clips[(clips.indexOf(current) + 1) % clips.length];
      const wanted = [current, second === current ? '' : second, ''];
      this.layers.forEach((layer, k) => Object.assign(layer, {
        clip: wanted[k], weight: k === 0 ? 1 : 0, mode: 'OVERRIDE', upperBody: false,
      }));
      this.fade = null;
    }
    for (const [k, { clip, mask }] of this.ui.layers.entries()) {
      clip.replaceChildren(...(k === 0 ? [] : [new Option('none', '')]),
        ...clips.map((name) => new Option(name, name)));
      mask.options[1].disabled = !this.upperBody;
    }
    this.ui.upperBody.textContent = this.upperBody ? `upper body: ${this.upperBody} and below` : 'no upper body found';
    this.showControls();
    if (this.enabled && !this.playing) this.refresh();
  }

  // The controls from the state (weights also move during a crossfade).
  showControls() {
    this.layers.forEach((layer, k) => {
      const ui = this.ui.layers[k];
      ui.clip.value = layer.clip;
      ui.weight.value = String(layer.weight);
      ui.weightValue.textContent = layer.weight.toFixed(2);
      ui.mode.value = layer.mode;
      ui.mask.value = layer.upperBody ? 'upper' : 'full';
      for (const control of [ui.weight, ui.mode, ui.mask]) control.disabled = !layer.clip;
    });
    this.ui.sync.checked = this.sync === 'PHASE';
    this.ui.play.textContent = this.playing ? 'Pause' : 'Play';
    const [a, b] = this.fadeLayers();
    this.ui.fade.disabled = !(this.layers[0].clip && this.layers[1].clip);
    this.ui.fade.textContent = `Crossfade ${this.layers[a].clip || a + 1} → ${this.layers[b].clip || b + 1}`;
  }

  // Which way the crossfade button goes: from the heavier of layers 1 and 2
  // to the other.
  fadeLayers() {
    return this.layers[0].weight >= this.layers[1].weight ? [0, 1] : [1, 0];
  }

  setEnabled(on) {
    if (on === this.enabled) return;
    this.enabled = on;
    this.root.hidden = !on;
    if (on) {
      this.refresh();
    } else {
      this.pause();
      this.fade = null;
      ++this.generation;
      this.sampler.cancel();
    }
  }

  // The motion at playback time `time`: a running crossfade sets the weights
  // of its two layers first (and ends when it is complete).
  motionAt(time) {
    if (this.fade) {
      const { progress, from, to } = crossfadeWeights(this.fade, time);
      this.layers[this.fade.from].weight = from;
      this.layers[this.fade.to].weight = to;
      if (progress >= 1) this.fade = null;
      this.showControls();
    }
    return buildMotion(this.layers, this.sync, this.upperBody);
  }

  // Crossfades from the heavier of layers 1 and 2 to the other over
  // `duration` s of playback, starting now; plays when paused.
  crossfade(duration) {
    if (!(this.layers[0].clip && this.layers[1].clip)) return;
    const [from, to] = this.fadeLayers();
    this.fade = { from, to, start: this.time, duration: Math.max(Number(duration) || 0, 0) };
    if (!this.playing) this.play();
  }

  play() {
    if (this.playing || !this.enabled) return;
    this.playing = true;
    let last = performance.now();
    const tick = (now) => {
      if (!this.playing) return;
      this.time += (Math.max(now - last, 0) / 1000) * this.speed();
      last = now;
      this.sampler.request(this.time);
      requestAnimationFrame(tick);
    };
    requestAnimationFrame(tick);
    this.showControls();
    this.emit('state', { playing: true });
  }

  pause() {
    if (!this.playing) return;
    this.playing = false;
    this.showControls();
    this.emit('state', { playing: false });
  }

  // Shows the motion at `time` (seconds, >= 0); settles once it is drawn when paused.
  seek(time) {
    this.fade = null;
    this.time = Math.max(Number(time) || 0, 0);
    return this.playing ? Promise.resolve() : this.refresh();
  }

  refresh() {
    return this.enabled ? this.sampler.request(this.time) : Promise.resolve();
  }

  async sampleAndShow(time) {
    const generation = this.generation;
    const motion = this.motionAt(time);
    try {
      const answer = await api.evaluateMotion(motion, [time]);
      if (generation !== this.generation || !this.enabled) return;
      this.stats.evaluations++;
      if (this.playing) this.stats.frames++;
      this.last = { time, motion, pose: answer.poses[0] };
      this.ui.time.textContent = `t = ${time.toFixed(3)} s`;
      this.emit('pose', { time, motion, pose: answer.poses[0], frame: this.playing });
    } catch (error) {
      if (generation === this.generation) this.emit('error', error.message);
    }
  }
}
