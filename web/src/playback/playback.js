// Playback of one clip, whatever it drives: play streams frames (gRPC-Web) from
// the current time at the chosen speed (looping); pause closes the stream;
// seeking while paused samples the clip once at that time (one call in
// flight, the latest time wins). Subclasses say what a sample and a stream
// are (a pose, a skinned mesh) and which event shows one; all emit 'load',
// 'state' and 'error'.
import * as api from '../api.js';
import { LatestWins } from '../latest_wins.js';

export class Playback extends EventTarget {
  // `sampleEvent`: the event each sample or frame is emitted as.
  constructor({ fps = 30, sampleEvent }) {
    super();
    this.fps = fps;
    this.sampleEvent = sampleEvent;
    this.clip = null;  // a GetClip response: name, duration, frameTime
    this.time = 0;
    this.speed = 1;
    this.playing = false;
    this.stopStream = null;
    this.streams = 0;  // streams started; frames of an older one are dropped
    this.loads = 0;    // loads started; answers for an older one are dropped
    this.stats = { framesReceived: 0, evaluations: 0 };
    this.sampler = new LatestWins((time) => this.sampleAndShow(time));
  }

  // Subclasses: sample(time) → Promise<detail>; openStream(options, onFrame,
  // onEnd) → stop function; frameDetail(frame) → detail.

  // `clip`: a clip name, or a promise of its GetClip response when the caller
  // already asked for it (one fetch serves the mesh and the skeleton).
  static fetchClip(clip) {
    return typeof clip === 'string' ? api.getClip(clip) : clip;
  }

  emit(type, detail) {
    this.dispatchEvent(new CustomEvent(type, { detail }));
  }

  play() {
    if (!this.clip || this.playing) return;
    this.playing = true;
    this.startStream();
    this.emit('state', { playing: true });
  }

  pause() {
    if (!this.playing) return;
    this.playing = false;
    this.stopStream?.();
    this.stopStream = null;
    this.emit('state', { playing: false });
  }

  setSpeed(speed) {
    this.speed = speed;
    if (this.playing) this.startStream();
  }

  // Shows the clip at `time`: a new stream from there while playing, one
  // sample while paused. Settles when the samples asked for are shown.
  async seek(time) {
    if (!this.clip) return;
    this.time = Math.min(Math.max(time, 0), this.clip.duration);
    if (this.playing) {
      this.startStream();
      return;
    }
    await this.sampler.request(this.time);
  }

  // Shows the current time again after a setting changed: a new stream, or one sample.
  refresh() {
    return this.seek(this.time);
  }

  async sampleAndShow(time) {
    const load = this.loads;
    try {
      const detail = await this.sample(time);
      if (load !== this.loads) return;
      this.stats.evaluations++;
      if (!this.playing) this.emit(this.sampleEvent, detail);
    } catch (error) {
      if (load === this.loads) this.emit('error', error.message);
    }
  }

  startStream() {
    this.stopStream?.();
    const stream = ++this.streams;
    const startTime = this.time >= this.clip.duration ? 0 : this.time;
    this.stopStream = this.openStream(
      { startTime, speed: this.speed, fps: this.fps, loop: true },
      (frame) => {
        if (!this.playing || stream !== this.streams) return;
        this.stats.framesReceived++;
        this.time = frame.time;
        this.emit(this.sampleEvent, this.frameDetail(frame));
      },
      (status) => {
        if (stream !== this.streams) return;
        if (status.code !== 0) this.emit('error', status.message);
        this.playing = false;
        this.stopStream = null;
        this.emit('state', { playing: false });
      },
    );
  }
}
