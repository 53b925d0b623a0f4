// Playback of one clip: play streams poses over SSE from the current time at
// the chosen speed (looping); pause closes the stream; scrubbing while paused
// evaluates the clip at the slider's time. Emits 'load', 'pose', 'state' and
// 'error' events.
import * as api from './api.js';

export class Player extends EventTarget {
  constructor({ fps = 30 } = {}) {
    super();
    this.fps = fps;
    this.clip = null;
    this.skeleton = null;
    this.time = 0;
    this.speed = 1;
    this.playing = false;
    this.stopStream = null;
    this.stats = { framesReceived: 0, evaluations: 0 };
    this.seekWanted = null;  // the latest scrub time not yet evaluated
    this.seeking = false;
  }

  emit(type, detail) {
    this.dispatchEvent(new CustomEvent(type, { detail }));
  }

  async load(clipName) {
    this.pause();
    this.clip = await api.getClip(clipName);
    this.skeleton = await api.getSkeleton(this.clip.skeleton);
    this.time = 0;
    this.emit('load', { clip: this.clip, skeleton: this.skeleton });
    await this.seek(0);
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

  // Shows the pose at `time`: a new stream from there while playing, one
  // EvaluateClip call (the latest wins) while paused.
  async seek(time) {
    if (!this.clip) return;
    this.time = Math.min(Math.max(time, 0), this.clip.duration);
    if (this.playing) {
      this.startStream();
      return;
    }
    this.seekWanted = this.time;
    if (this.seeking) return;
    this.seeking = true;
    try {
      while (this.seekWanted !== null) {
        const t = this.seekWanted;
        this.seekWanted = null;
        const result = await api.evaluate(this.clip.name, [t]);
        this.stats.evaluations++;
        if (!this.playing) this.emit('pose', { time: t, pose: result.poses[0] });
      }
    } catch (error) {
      this.emit('error', error.message);
    } finally {
      this.seeking = false;
    }
  }

  startStream() {
    this.stopStream?.();
    const clipName = this.clip.name;
    const startTime = this.time >= this.clip.duration ? 0 : this.time;
    this.stopStream = api.streamClip(
      clipName,
      { startTime, speed: this.speed, fps: this.fps, loop: true },
      (frame) => {
        if (!this.playing || this.clip?.name !== clipName) return;
        this.stats.framesReceived++;
        this.time = frame.time;
        this.emit('pose', { time: frame.time, pose: frame.pose, frame });
      },
      (status) => {
        if (status.code !== 0) this.emit('error', status.message);
        this.playing = false;
        this.stopStream = null;
        this.emit('state', { playing: false });
      },
    );
  }
}
