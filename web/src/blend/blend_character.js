// The blend on the body: while the blend panel blends a skeleton that has
// meshes (a character), each pose it draws is also skinned — SkinCharacter
// with the same motion at the same time, the latest time winning, one call in
// flight — and drawn by the character view under the (thin, see-through)
// skeleton. Emits 'error' (message).
import * as api from '../api.js';
import { LatestWins } from '../latest_wins.js';

export class BlendCharacter extends EventTarget {
  constructor(characterView) {
    super();
    this.view = characterView;
    this.character = null;  // { skeleton, meshes } from charactersOf, or null: the skeleton alone
    this.last = null;       // what is drawn: { time, motion }
    this.skinned = 0;       // answers drawn (for tests)
    this.loads = 0;
    this.skinner = new LatestWins((wanted) => this.skin(wanted));
  }

  // Shows `character`'s meshes at rest (null: none) until the next pose.
  async show(character) {
    const load = ++this.loads;
    this.skinner.cancel();
    this.character = null;
    this.last = null;
    this.view.clear();
    if (!character) return;
    const geometries = await Promise.all(character.meshes.map((m) => api.getMeshGeometry(m.name)));
    if (load !== this.loads) return;
    this.character = character;
    this.view.show(geometries);
  }

  // The blend drew `motion` at `time`: the body follows.
  pose(motion, time) {
    if (this.character) this.skinner.request({ character: this.character, motion, time });
  }

  async skin({ character, motion, time }) {
    try {
      const answer = await api.skinCharacter(character.skeleton, { motion, time });
      if (character !== this.character) return;
      this.view.setMeshes(answer.meshes);
      this.last = { time, motion };
      this.skinned += 1;
    } catch (error) {
      if (character === this.character) this.dispatchEvent(new CustomEvent('error', { detail: error.message }));
    }
  }
}
