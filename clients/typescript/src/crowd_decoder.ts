// A crowd session's frames (CrowdService.CrowdSession) decoded to typed
// arrays, as clients/cpp's crowd_decoder.h does: the decoder keeps each
// clip's CrowdLayout from the frame that brought it and turns a frame's
// encoded poses into LOCAL poses, as EvaluateClip's local space gives them.
// The encoding is crowd.proto's CrowdLayout: per joint 48 bits of
// smallest-three, then float32 translations and scales for the joints whose
// clip varies them; the rest is the layout's base pose.
import { ArmatureError, Code } from './errors.js';
import type { CrowdFrame, CrowdLayout } from './gen/armature/v1/crowd_pb.js';

/** One frame's updated characters, each with `joints` transforms. */
export interface CrowdPoses {
  /** The most joints of the characters' layouts (a character with fewer: the rest identity). */
  joints: number;
  ids: Uint32Array;
  /** Per id: the clip time sampled (rounded when shared). */
  clipTimes: Float64Array;
  /** Per id: its CrowdLayout's number. */
  layouts: Uint32Array;
  /** ids × joints × 4: w, x, y, z. */
  rotations: Float32Array;
  /** ids × joints × 3. */
  translations: Float32Array;
  /** ids × joints × 3. */
  scales: Float32Array;
}

const HALF = Math.SQRT1_2;
const TWO_32 = 2 ** 32;

function malformed(what: string): never {
  throw new ArmatureError(Code.Internal, `crowd frame: ${what}`);
}

// 6 bytes of smallest-three at `at` → w, x, y, z into out[o..o+4).
function decodeRotation(bytes: Uint8Array, at: number, out: Float32Array, o: number): void {
  const low = (bytes[at] | (bytes[at + 1] << 8) | (bytes[at + 2] << 16)) + bytes[at + 3] * 2 ** 24;
  let bits = low + (bytes[at + 4] | (bytes[at + 5] << 8)) * TWO_32;  // 48 bits: exact in a double
  const largest = bits % 4;
  bits = Math.floor(bits / 4);
  const c = [0, 0, 0, 0];  // x, y, z, w
  let sum = 0;
  for (let i = 0; i < 4; ++i) {
    if (i === largest) continue;
    c[i] = ((bits % 32768) / 32767) * (2 * HALF) - HALF;
    bits = Math.floor(bits / 32768);
    sum += c[i] * c[i];
  }
  c[largest] = Math.sqrt(Math.max(0, 1 - sum));
  const norm = Math.sqrt(sum + c[largest] * c[largest]);
  out[o] = c[3] / norm;
  out[o + 1] = c[0] / norm;
  out[o + 2] = c[1] / norm;
  out[o + 3] = c[2] / norm;
}

// 3 little-endian float32 per joint in `joints`, into out (joints × 3) from `at`; the offset after them.
function readVectors(view: DataView, at: number, joints: readonly number[], count: number, out: Float32Array,
                     o: number): number {
  for (const j of joints) {
    if (j >= count) malformed(`a layout names joint ${j} of ${count}`);
    for (let k = 0; k < 3; ++k) out[o + 3 * j + k] = view.getFloat32(at + 4 * k, true);
    at += 12;
  }
  return at;
}

export class CrowdDecoder {
  private readonly known = new Map<number, CrowdLayout>();

  /** A layout sent so far, by its number. */
  layout(layout: number): CrowdLayout | undefined {
    return this.known.get(layout);
  }

  /** Decodes `frame` (reading its new layouts first); ArmatureError (Internal) when poses and layouts disagree. */
  decode(frame: CrowdFrame): CrowdPoses {
    for (const l of frame.newLayouts) this.known.set(l.layout, l);
    const n = frame.ids.length;
    if (frame.layouts.length !== n || frame.clipTimes.length !== n) malformed('ids, layouts and clip times differ in count');
    const layouts = frame.layouts.map((number) => this.known.get(number) ?? malformed(`layout ${number} never sent`));
    const joints = layouts.reduce((most, l) => Math.max(most, l.joints), 0);
    const poses: CrowdPoses = {
      joints, ids: Uint32Array.from(frame.ids), clipTimes: Float64Array.from(frame.clipTimes),
      layouts: Uint32Array.from(frame.layouts),
      rotations: new Float32Array(n * joints * 4), translations: new Float32Array(n * joints * 3),
      scales: new Float32Array(n * joints * 3).fill(1),
    };
    const bytes = frame.poses;
    const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
    let at = 0;
    layouts.forEach((l, i) => {
      if (bytes.length - at < l.poseBytes) malformed('poses end early');
      if (l.baseTranslations.length !== 3 * l.joints || l.baseScales.length !== 3 * l.joints)
        malformed(`layout ${l.layout} has no base pose for its joints`);
      poses.translations.set(l.baseTranslations, i * joints * 3);
      poses.scales.set(l.baseScales, i * joints * 3);
      let pose = at;
      for (let j = 0; j < l.joints; ++j, pose += 6) decodeRotation(bytes, pose, poses.rotations, (i * joints + j) * 4);
      for (let j = l.joints; j < joints; ++j) poses.rotations[(i * joints + j) * 4] = 1;  // padding: identity
      pose = readVectors(view, pose, l.translatedJoints, l.joints, poses.translations, i * joints * 3);
      pose = readVectors(view, pose, l.scaledJoints, l.joints, poses.scales, i * joints * 3);
      if (pose !== at + l.poseBytes) malformed(`layout ${l.layout}'s poseBytes disagree`);
      at += l.poseBytes;
    });
    if (at !== bytes.length) malformed('more pose bytes than the ids need');
    return poses;
  }
}
