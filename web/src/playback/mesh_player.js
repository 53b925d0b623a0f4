// Playback of a clip on a mesh: skinned positions and normals, streamed with
// StreamSkinnedMesh while playing, one SkinMesh per seek while paused, by
// LBS or DQS (switchable live: the stream restarts, or the current time is
// skinned again). A mesh without a clip is only shown at rest. Emits 'load'
// ({ mesh, geometry, clip }), 'frame' ({ time, positions, normals, frame }),
// 'state' and 'error'.
import * as api from '../api.js';
import { Playback } from './playback.js';

export const SKINNING_METHODS = ['LBS', 'DQS'];

// The clips that can play on `mesh` (a MeshInfo): those of its skeleton; any
// clip for an unbound mesh with morph targets (only its weights track moves
// it); none for a mesh with neither.
export function clipsFor(mesh, clips) {
  if (mesh.skeleton) return clips.filter((clip) => clip.skeleton === mesh.skeleton);
  return mesh.targetNames?.length ? clips : [];
}

export class MeshPlayer extends Playback {
  constructor({ fps = 30 } = {}) {
    super({ fps, sampleEvent: 'frame' });
    this.mesh = null;      // the MeshInfo
    this.geometry = null;  // its GetMeshGeometry response
    this.method = 'LBS';
  }

  // `mesh`: a MeshInfo; `clip`: a clip from clipsFor (see Playback.fetchClip),
  // or '' for the rest shape.
  async load(mesh, clip) {
    this.pause();
    const load = ++this.loads;
    const [geometry, clipAnswer] = await Promise.all([
      mesh.name === this.mesh?.name ? this.geometry : api.getMeshGeometry(mesh.name),
      clip ? Playback.fetchClip(clip) : null,
    ]);
    if (load !== this.loads) return;
    this.mesh = mesh;
    this.geometry = geometry;
    this.clip = clipAnswer;
    this.time = 0;
    this.emit('load', { mesh, geometry, clip: clipAnswer });
    await this.seek(0);
  }

  unload() {
    this.pause();
    ++this.loads;
    this.mesh = this.geometry = this.clip = null;
  }

  setMethod(method) {
    if (!SKINNING_METHODS.includes(method)) throw new Error(`unknown skinning method ${method}`);
    this.method = method;
    return this.refresh();
  }

  async sample(time) {
    const skinned = await api.skinMesh(this.mesh.name, { clip: this.clip.name, time, method: this.method });
    return { time, positions: skinned.positions, normals: skinned.normals };
  }

  openStream(options, onFrame, onEnd) {
    return api.streamSkinnedMesh(this.mesh.name, this.clip.name, { ...options, method: this.method }, onFrame, onEnd);
  }

  frameDetail(frame) {
    return { time: frame.time, positions: frame.positions, normals: frame.normals, frame };
  }
}
