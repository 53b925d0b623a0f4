// Playback of a clip's skeleton: world-space poses, streamed with StreamClip
// while playing, one EvaluateClip per seek while paused. Emits 'load'
// ({ clip, skeleton }), 'pose' ({ time, pose, frame }), 'state' and 'error'.
import * as api from '../api.js';
import { Playback } from './playback.js';

export class Player extends Playback {
  constructor({ fps = 30 } = {}) {
    super({ fps, sampleEvent: 'pose' });
    this.skeleton = null;
  }

  // `clipOrPromise`: see Playback.fetchClip.
  async load(clipOrPromise) {
    this.pause();
    const load = ++this.loads;
    const clip = await Playback.fetchClip(clipOrPromise);
    const skeleton = await api.getSkeleton(clip.skeleton);
    if (load !== this.loads) return;
    this.clip = clip;
    this.skeleton = skeleton;
    this.time = 0;
    this.emit('load', { clip, skeleton });
    await this.seek(0);
  }

  async sample(time) {
    const result = await api.evaluate(this.clip.name, [time]);
    return { time, pose: result.poses[0] };
  }

  openStream(options, onFrame, onEnd) {
    return api.streamClip(this.clip.name, options, onFrame, onEnd);
  }

  frameDetail(frame) {
    return { time: frame.time, pose: frame.pose, frame };
  }
}
