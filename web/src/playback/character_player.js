// Playback of a clip on a character (a skeleton with all of its meshes): every
// mesh skinned together by one SkinCharacter call per shown time. There is no
// character stream, so play is paced here: the next call starts when the last
// answer is shown (one in flight), at the clip time the wall clock says, no
// more often than `fps`. Emits 'load' ({ character, geometries, clip }),
// 'frame' ({ time, meshes, frame }), 'state' and 'error', as MeshPlayer does.
import * as api from '../api.js';
import { Playback } from './playback.js';

// The characters among `meshes` (MeshInfos): one per skeleton that has
// meshes, { skeleton, meshes } by skeleton name, each's meshes by name.
export function charactersOf(meshes) {
  const bySkeleton = new Map();
  for (const mesh of meshes) {
    if (!mesh.skeleton) continue;
    if (!bySkeleton.has(mesh.skeleton)) bySkeleton.set(mesh.skeleton, []);
    bySkeleton.get(mesh.skeleton).push(mesh);
  }
  return [...bySkeleton.entries()]
    .sort(([a], [b]) => (a < b ? -1 : a > b ? 1 : 0))
    .map(([skeleton, list]) => ({ skeleton, meshes: list.sort((a, b) => (a.name < b.name ? -1 : 1)) }));
}

// The clips a character plays (from `clips`, ClipInfos): its skeleton's, and
// those of skeletons with the same joint names — SkinCharacter poses the
// meshes by joint name (a retargeted clip is the character's own; one stored
// by an older server lives on a copy of its skeleton).
export async function clipsForCharacter(skeleton, clips) {
  const key = (names) => [...names].sort().join('\n');
  const own = key(await api.jointNames(skeleton));
  const others = [...new Set(clips.map((c) => c.skeleton))].filter((s) => s && s !== skeleton);
  const alike = new Set([skeleton]);
  await Promise.all(others.map(async (other) => {
    const names = await api.jointNames(other).catch(() => null);  // deleted meanwhile: not alike
    if (names && key(names) === own) alike.add(other);
  }));
  return clips.filter((c) => alike.has(c.skeleton));
}

export class CharacterPlayer extends Playback {
  constructor({ fps = 30 } = {}) {
    super({ fps, sampleEvent: 'frame' });
    this.character = null;   // { skeleton, meshes } from charactersOf
    this.geometries = null;  // a GetMeshGeometry response per mesh, in the same order
    this.method = 'LBS';
  }

  // `character`: from charactersOf; `clip`: one of clipsForCharacter (see
  // Playback.fetchClip), or '' for the rest shape.
  async load(character, clip) {
    this.pause();
    const load = ++this.loads;
    const same = character.skeleton === this.character?.skeleton;
    const [geometries, clipAnswer] = await Promise.all([
      same ? this.geometries : Promise.all(character.meshes.map((m) => api.getMeshGeometry(m.name))),
      clip ? Playback.fetchClip(clip) : null,
    ]);
    if (load !== this.loads) return;
    this.character = character;
    this.geometries = geometries;
    this.clip = clipAnswer;
    this.time = 0;
    this.emit('load', { character, geometries, clip: clipAnswer });
    await this.seek(0);
  }

  unload() {
    this.pause();
    ++this.loads;
    this.character = this.geometries = this.clip = null;
  }

  setMethod(method) {
    this.method = method;
    return this.refresh();
  }

  async sample(time) {
    const answer = await api.skinCharacter(this.character.skeleton, { clip: this.clip.name, time, method: this.method });
    return { time, meshes: answer.meshes };
  }

  // Plays by repeated SkinCharacter calls from `startTime` at `speed`,
  // looping over the clip; `onEnd` gets a failed call's status.
  openStream({ startTime, speed, fps, loop }, onFrame, onEnd) {
    let open = true;
    const duration = this.clip.duration;
    const started = performance.now();
    const clipTime = () => {
      const t = startTime + (speed * (performance.now() - started)) / 1000;
      if (duration <= 0) return 0;
      if (loop) return ((t % duration) + duration) % duration;
      return Math.min(Math.max(t, 0), duration);
    };
    const run = async () => {
      for (let index = 0; open; ++index) {
        const asked = performance.now();
        const time = clipTime();
        let answer;
        try {
          answer = await api.skinCharacter(this.character.skeleton, { clip: this.clip.name, time, method: this.method });
        } catch (error) {
          if (open) onEnd({ code: error.code ?? 2, message: error.message });
          return;
        }
        if (!open) return;
        onFrame({ index, time, meshes: answer.meshes });
        const wait = 1000 / fps - (performance.now() - asked);
        if (wait > 0) await new Promise((resolve) => setTimeout(resolve, wait));
      }
    };
    run();
    return () => {
      open = false;
    };
  }

  frameDetail(frame) {
    return { time: frame.time, meshes: frame.meshes, frame };
  }
}
