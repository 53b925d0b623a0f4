// The retarget control: a source clip (any clip; typically BVH mocap) moved
// onto the character shown with RetargetClip. The new asset takes the
// server's default name, `<clip>_on_<skeleton>`, and replaces an earlier one
// (so pressing twice works); "Feet" pins the feet the source plants. Shows the
// answer (pairs mapped, joints unmapped on each side) or the server's message,
// until the character changes. The source offered first is a clip of another
// body (retarget_source.js) until the user picks one.
// Emits 'retargeted' ({ response, skeleton }) and 'error' (message).
import * as api from '../api.js';
import { defaultRetargetSource } from './retarget_source.js';

// One line for a RetargetClipResponse (as JSON).
export function describeRetarget(response) {
  const { mapping = [], unmapped = {}, warnings = [] } = response;
  const source = unmapped.source?.length ?? 0;
  const target = unmapped.target?.length ?? 0;
  return `${response.clip.name}: ${mapping.length} pairs mapped · unmapped ${source} source, ${target} target joints` +
         (warnings.length ? ` · ${warnings.join('; ')}` : '');
}

export class RetargetPanel extends EventTarget {
  // `root`: the panel's element (its controls are looked up by id).
  constructor(root) {
    super();
    const byId = (id) => root.querySelector(`#${id}`);
    this.root = root;
    this.ui = {
      source: byId('retarget-source'), target: byId('retarget-target'), feet: byId('retarget-feet'),
      run: byId('retarget-run'), result: byId('retarget-result'),
    };
    this.skeleton = '';  // the character's skeleton, '' when none is shown
    this.busy = false;
    this.last = null;    // the last answer, or null after a failure
    this.calls = 0;      // calls answered (for tests)
    this.clips = [];
    this.picked = false;  // the user chose the source: it is kept
    this.defaulted = 0;   // defaults chosen (for tests)
    this.ui.run.addEventListener('click', () => this.retarget());
    this.ui.source.addEventListener('change', () => {
      this.picked = true;
      this.update();
    });
  }

  emit(type, detail) {
    this.dispatchEvent(new CustomEvent(type, { detail }));
  }

  // Every clip (ClipInfos) can be a source; the choice is kept when it is still there.
  setClips(clips) {
    const current = this.ui.source.value;
    this.ui.source.replaceChildren(...clips.map((c) => new Option(`${c.name} (${c.skeleton})`, c.name)));
    if (clips.some((c) => c.name === current)) this.ui.source.value = current;
    else this.picked = false;
    this.clips = clips;
    this.update();
    return this.chooseDefault();
  }

  // The character shown ('' for none): the target. Another character clears the last answer.
  setCharacter(skeleton) {
    if (skeleton !== this.skeleton) {
      this.last = null;
      this.ui.result.textContent = '';
      this.ui.result.title = '';
      this.picked = false;
    }
    this.skeleton = skeleton;
    this.ui.target.textContent = skeleton ? `onto ${skeleton}` : 'onto: choose a character';
    this.update();
    return this.chooseDefault();
  }

  // Preselects a clip of another body, unless the user picked one.
  async chooseDefault() {
    const { skeleton, clips } = this;
    if (!skeleton || this.picked || clips.length === 0) return;
    const joints = new Map();
    await Promise.all([...new Set(clips.map((c) => c.skeleton))].map(async (s) => {
      joints.set(s, await api.jointNames(s).catch(() => []));  // deleted meanwhile: no body
    }));
    if (skeleton !== this.skeleton || clips !== this.clips || this.picked) return;  // changed meanwhile
    const name = defaultRetargetSource(clips, skeleton, (s) => joints.get(s) ?? []);
    if (name) this.ui.source.value = name;
    this.defaulted += 1;
    this.update();
  }

  update() {
    this.ui.run.disabled = this.busy || !this.skeleton || !this.ui.source.value;
  }

  async retarget() {
    const clip = this.ui.source.value;
    const skeleton = this.skeleton;
    if (!clip || !skeleton || this.busy) return;
    this.busy = true;
    this.update();
    this.ui.result.textContent = `retargeting ${clip} onto ${skeleton}…`;
    this.ui.result.title = '';
    try {
      const response = await api.retargetClip(clip, skeleton, { feet: this.ui.feet.checked, replace: true });
      this.last = response;
      this.ui.result.textContent = describeRetarget(response);
      this.ui.result.title = `unmapped source: ${response.unmapped?.source?.join(', ') || 'none'}\n` +
                             `unmapped target: ${response.unmapped?.target?.join(', ') || 'none'}`;
      this.emit('retargeted', { response, skeleton });
    } catch (error) {
      this.last = null;
      this.ui.result.textContent = `Retarget failed: ${error.message}`;
      this.emit('error', error.message);
    } finally {
      this.calls += 1;
      this.busy = false;
      this.update();
    }
  }
}
