// The retarget control: a source clip (any clip; typically BVH mocap) moved
// onto the character shown with RetargetClip. The new asset takes the
// server's default name, `<clip>_on_<skeleton>`, and replaces an earlier one
// (so pressing twice works); "Feet" pins the feet the source plants. Shows the
// answer (pairs mapped, joints unmapped on each side) or the server's message.
// Emits 'retargeted' ({ response, skeleton }) and 'error' (message).
import * as api from './api.js';

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
    this.ui.run.addEventListener('click', () => this.retarget());
    this.ui.source.addEventListener('change', () => this.update());
  }

  emit(type, detail) {
    this.dispatchEvent(new CustomEvent(type, { detail }));
  }

  // Every clip (ClipInfos) can be a source; the choice is kept when it is still there.
  setClips(clips) {
    const current = this.ui.source.value;
    this.ui.source.replaceChildren(...clips.map((c) => new Option(`${c.name} (${c.skeleton})`, c.name)));
    if (clips.some((c) => c.name === current)) this.ui.source.value = current;
    this.update();
  }

  // The character shown ('' for none): the target.
  setCharacter(skeleton) {
    this.skeleton = skeleton;
    this.ui.target.textContent = skeleton ? `onto ${skeleton}` : 'onto: choose a character';
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
