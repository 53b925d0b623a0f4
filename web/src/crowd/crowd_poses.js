// A crowd's poses between frames: each character keeps the two latest LOCAL
// poses the server sent (a frame updates only the characters due that tick;
// the budget updates the less significant ones every 2–N ticks) and is drawn
// interpolated from the earlier to the later over the interval between them,
// so a character updated every k ticks moves smoothly, one interval late, as
// Unreal's budget allocator interpolates. Then forward kinematics with the
// skeleton's parents (poses are local: translation, rotation w x y z, scale)
// and the character's root placement. Pure: no three.js, testable in node.

export class CrowdPoses {
  // `parents`: each joint's parent index (-1 for a root), parents first; `count` characters, ids 0..count-1.
  constructor(parents, count) {
    this.parents = Int32Array.from(parents);
    this.joints = parents.length;
    this.count = count;
    const j = this.joints;
    this.rotations = [new Float32Array(count * j * 4), new Float32Array(count * j * 4)];  // [earlier, later]
    this.translations = [new Float32Array(count * j * 3), new Float32Array(count * j * 3)];
    this.scales = [new Float32Array(count * j * 3), new Float32Array(count * j * 3)];
    this.ticks = [new Float64Array(count).fill(-1), new Float64Array(count).fill(-1)];
    this.roots = new Float32Array(count * 3);  // each character's placement (a translation)
    this.world = new Float64Array(j * 12);      // one character's joints as 3×4 matrices, row-major
  }

  get posed() {
    let n = 0;
    for (let c = 0; c < this.count; ++c) n += this.ticks[1][c] >= 0 ? 1 : 0;
    return n;
  }

  // A decoded frame (the TypeScript client's CrowdPoses) at `tick`: its characters' later pose becomes their earlier one.
  apply(tick, poses) {
    const j = this.joints;
    if (poses.ids.length > 0 && poses.joints < j) throw new Error(`poses of ${poses.joints} joints for ${j}`);
    for (let i = 0; i < poses.ids.length; ++i) {
      const c = poses.ids[i];
      if (c >= this.count) continue;
      const first = this.ticks[1][c] < 0;
      for (const [arrays, from, width] of [[this.rotations, poses.rotations, 4], [this.translations, poses.translations, 3],
        [this.scales, poses.scales, 3]]) {
        const at = c * j * width, source = from.subarray(i * poses.joints * width, (i * poses.joints + j) * width);
        if (first) arrays[0].set(source, at);
        else arrays[0].set(arrays[1].subarray(at, at + j * width), at);
        arrays[1].set(source, at);
      }
      this.ticks[0][c] = first ? tick : this.ticks[1][c];
      this.ticks[1][c] = tick;
    }
  }

  // How far character `c` is from its earlier pose (0) to its later one (1) at `renderTick`.
  blendOf(c, renderTick) {
    const [earlier, later] = [this.ticks[0][c], this.ticks[1][c]];
    if (later <= earlier) return 1;
    return Math.min(1, Math.max(0, (renderTick - later) / (later - earlier)));
  }

  // Character c's world joint positions at `renderTick` into out[o..o + joints·3), its root placement added.
  worldPositions(c, renderTick, out, o = 0) {
    const s = this.blendOf(c, renderTick), j = this.joints, w = this.world;
    const [r0, r1] = this.rotations, [t0, t1] = this.translations, [s0, s1] = this.scales;
    for (let k = 0; k < j; ++k) {
      const q = (c * j + k) * 4, v = (c * j + k) * 3;
      // nlerp on the shorter arc: close enough to slerp over the small steps between updates.
      const sign = r0[q] * r1[q] + r0[q + 1] * r1[q + 1] + r0[q + 2] * r1[q + 2] + r0[q + 3] * r1[q + 3] < 0 ? -1 : 1;
      let qw = r0[q] * (1 - s) + sign * r1[q] * s, qx = r0[q + 1] * (1 - s) + sign * r1[q + 1] * s;
      let qy = r0[q + 2] * (1 - s) + sign * r1[q + 2] * s, qz = r0[q + 3] * (1 - s) + sign * r1[q + 3] * s;
      const n = Math.hypot(qw, qx, qy, qz) || 1;
      qw /= n; qx /= n; qy /= n; qz /= n;
      const sx = s0[v] + (s1[v] - s0[v]) * s, sy = s0[v + 1] + (s1[v + 1] - s0[v + 1]) * s;
      const sz = s0[v + 2] + (s1[v + 2] - s0[v + 2]) * s;
      // The local matrix T·R·S, row-major 3×4.
      const local = [
        (1 - 2 * (qy * qy + qz * qz)) * sx, 2 * (qx * qy - qz * qw) * sy, 2 * (qx * qz + qy * qw) * sz,
        t0[v] + (t1[v] - t0[v]) * s,
        2 * (qx * qy + qz * qw) * sx, (1 - 2 * (qx * qx + qz * qz)) * sy, 2 * (qy * qz - qx * qw) * sz,
        t0[v + 1] + (t1[v + 1] - t0[v + 1]) * s,
        2 * (qx * qz - qy * qw) * sx, 2 * (qy * qz + qx * qw) * sy, (1 - 2 * (qx * qx + qy * qy)) * sz,
        t0[v + 2] + (t1[v + 2] - t0[v + 2]) * s,
      ];
      const p = this.parents[k];
      if (p < 0) {
        w.set(local, k * 12);
      } else {
        for (let row = 0; row < 3; ++row) {
          const a = p * 12 + row * 4;
          for (let col = 0; col < 4; ++col) {
            w[k * 12 + row * 4 + col] = w[a] * local[col] + w[a + 1] * local[4 + col] + w[a + 2] * local[8 + col] +
              (col === 3 ? w[a + 3] : 0);
          }
        }
      }
      out[o + k * 3] = w[k * 12 + 3] + this.roots[c * 3];
      out[o + k * 3 + 1] = w[k * 12 + 7] + this.roots[c * 3 + 1];
      out[o + k * 3 + 2] = w[k * 12 + 11] + this.roots[c * 3 + 2];
    }
  }
}
