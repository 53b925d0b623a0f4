// createArmatureClient: the generated services on connect-web's gRPC-Web
// transport (binary protobuf, the server's HTTP port), with the token and a
// deadline on every call, errors as ArmatureError, and the calls a viewer uses
// most with their packed floats as Float32Array.
import type { Client, Interceptor, Transport } from '@connectrpc/connect';
import { createClient } from '@connectrpc/connect';
import type { DescService } from '@bufbuild/protobuf';
import { createGrpcWebTransport } from '@connectrpc/connect-web';

import { packFloats } from './arrays.js';
import { toArmatureError } from './errors.js';
import { importAsset } from './import_asset.js';
import type { ImportAssetOptions } from './import_asset.js';
import { AssetService } from './gen/armature/v1/assets_pb.js';
import type { ImportAssetResponse } from './gen/armature/v1/assets_pb.js';
import { AuthoringService } from './gen/armature/v1/authoring_pb.js';
import { DeformService } from './gen/armature/v1/deform_pb.js';
import { IkService } from './gen/armature/v1/ik_pb.js';
import { MeshService, SkinningMethod } from './gen/armature/v1/meshes_pb.js';
import { PoseService } from './gen/armature/v1/poses_pb.js';
import { Interpolation, Space, WrapMode } from './gen/armature/v1/types_pb.js';

export interface ClientOptions {
  /** Sent as `Authorization: Bearer <token>` on every call. */
  token?: string;
  /** Deadline of every call (a stream's whole life); none when absent. */
  timeoutMs?: number;
  /** A fetch to use instead of the global one. */
  fetch?: typeof globalThis.fetch;
  /** More interceptors, run after the token's. */
  interceptors?: Interceptor[];
}

export type SpaceName = 'local' | 'world';
export type InterpolationName = 'step' | 'linear' | 'cubic';

export interface EvaluateClipOptions {
  space?: SpaceName | Space;
  interpolation?: InterpolationName | Interpolation;
  wrap?: 'clamp' | 'loop' | WrapMode;
  /** A subset of joints by name; all when absent. */
  joints?: string[];
  signal?: AbortSignal;
}

export interface PoseSequence {
  clip: string;
  skeleton: string;
  times: number[];
  /** The skeleton's index of each joint in the answer, and its name. */
  jointIndices: number[];
  jointNames: string[];
  /** times × joints × 3: x, y, z. */
  translations: Float32Array;
  /** times × joints × 4: w, x, y, z. */
  rotations: Float32Array;
}

export interface StreamClipOptions extends EvaluateClipOptions {
  fps?: number;
  speed?: number;
  loop?: boolean;
  startTime?: number;
  /** Wall-clock seconds; 0 = until the clip's end (never when looping). */
  duration?: number;
}

export interface PoseStreamFrame {
  index: number;
  time: number;
  wallTime: number;
  skeleton: string;
  jointIndices: number[];
  jointNames: string[];
  /** joints × 3 */
  translations: Float32Array;
  /** joints × 4: w, x, y, z */
  rotations: Float32Array;
}

export interface SkinMeshOptions {
  method?: 'lbs' | 'dqs' | SkinningMethod;
  interpolation?: InterpolationName | Interpolation;
  wrap?: 'clamp' | 'loop' | WrapMode;
  morphWeights?: number[];
  signal?: AbortSignal;
}

export interface SkinnedMesh {
  mesh: string;
  vertexCount: number;
  /** vertices × 3, world space */
  positions: Float32Array;
  /** vertices × 3, unit; absent when the mesh has no normals */
  normals?: Float32Array;
}

export interface ArmatureClient {
  /** The generated services, for every other call (errors are ArmatureError too). */
  readonly pose: Client<typeof PoseService>;
  readonly mesh: Client<typeof MeshService>;
  readonly asset: Client<typeof AssetService>;
  readonly ik: Client<typeof IkService>;
  readonly deform: Client<typeof DeformService>;
  readonly authoring: Client<typeof AuthoringService>;
  readonly transport: Transport;
  evaluateClip(clip: string, times: number[], options?: EvaluateClipOptions): Promise<PoseSequence>;
  streamClip(clip: string, options?: StreamClipOptions): AsyncIterable<PoseStreamFrame>;
  skinMesh(mesh: string, clip: string, time: number, options?: SkinMeshOptions): Promise<SkinnedMesh>;
  /** Imports a file over REST's raw upload (ImportAsset), e.g. `{filename: 'walk.bvh', precision: 0.5}`. */
  importAsset(data: Uint8Array | ArrayBuffer | Blob, options: ImportAssetOptions): Promise<ImportAssetResponse>;
  /** A skeleton's joint names, fetched once per client (see forgetSkeletons). */
  jointNames(skeleton: string): Promise<string[]>;
  /** Drops the cached joint names, e.g. after a skeleton was imported again. */
  forgetSkeletons(): void;
}

const SPACES: Record<SpaceName, Space> = { local: Space.LOCAL, world: Space.WORLD };
const INTERPOLATIONS: Record<InterpolationName, Interpolation> = {
  step: Interpolation.STEP, linear: Interpolation.LINEAR, cubic: Interpolation.CUBIC,
};
const WRAPS = { clamp: WrapMode.CLAMP, loop: WrapMode.LOOP };
const METHODS = { lbs: SkinningMethod.LBS, dqs: SkinningMethod.DQS };

// A name from the table, an enum value as is, absent as 0 (the server's default).
function enumOf<E extends number>(table: Record<string, E>, value: string | E | undefined, what: string): E {
  if (value === undefined) return 0 as E;
  if (typeof value === 'number') return value;
  const found = table[value.toLowerCase()];
  if (found === undefined) throw new TypeError(`${what} "${value}" is not one of ${Object.keys(table).join(', ')}`);
  return found;
}

// The token on every call.
function tokenInterceptor(token: string | undefined): Interceptor {
  return (next) => (req) => {
    if (token !== undefined) req.header.set('authorization', `Bearer ${token}`);
    return next(req);
  };
}

// A stream whose failure, at any message, is an ArmatureError.
async function* typedErrors<T>(messages: AsyncIterable<T>): AsyncGenerator<T> {
  try {
    yield* messages;
  } catch (e) {
    throw toArmatureError(e);
  }
}

// The generated client with every failure as an ArmatureError. Not done in an
// interceptor: connect turns whatever an interceptor throws into a ConnectError.
function typedClient<S extends DescService>(service: S, transport: Transport): Client<S> {
  const client = createClient(service, transport) as Record<string, (...args: unknown[]) => unknown>;
  const typed: Record<string, unknown> = {};
  for (const method of service.methods) {
    const call = client[method.localName];
    typed[method.localName] = method.methodKind === 'unary' || method.methodKind === 'client_streaming'
      ? (...args: unknown[]) => (call(...args) as Promise<unknown>).catch((e) => { throw toArmatureError(e); })
      : (...args: unknown[]) => typedErrors(call(...args) as AsyncIterable<unknown>);
  }
  return typed as Client<S>;
}

// Each skeleton's joint names, fetched once; `namesOf` fetches anew when an
// index is past the names known (the skeleton was imported again since).
function jointNameCache(asset: Client<typeof AssetService>) {
  const skeletons = new Map<string, Promise<string[]>>();

  function jointNames(skeleton: string): Promise<string[]> {
    let names = skeletons.get(skeleton);
    if (!names) {
      names = asset.getSkeleton({ skeleton }).then((s) => s.joints.map((j) => j.name));
      names.catch(() => skeletons.delete(skeleton));  // a failure is not cached
      skeletons.set(skeleton, names);
    }
    return names;
  }

  async function namesOf(skeleton: string, indices: number[]): Promise<string[]> {
    let all = await jointNames(skeleton);
    if (indices.some((i) => i >= all.length)) {
      skeletons.delete(skeleton);
      all = await jointNames(skeleton);
    }
    return indices.map((i) => all[i] ?? `#${i}`);
  }

  return { jointNames, namesOf, forget: () => skeletons.clear() };
}

export function createArmatureClient(baseUrl: string, options: ClientOptions = {}): ArmatureClient {
  const transport = createGrpcWebTransport({
    baseUrl: baseUrl.replace(/\/+$/, ''),
    useBinaryFormat: true,
    defaultTimeoutMs: options.timeoutMs,
    fetch: options.fetch,
    interceptors: [tokenInterceptor(options.token), ...(options.interceptors ?? [])],
  });
  const pose = typedClient(PoseService, transport);
  const mesh = typedClient(MeshService, transport);
  const asset = typedClient(AssetService, transport);
  const { jointNames, namesOf, forget } = jointNameCache(asset);

  return {
    pose, mesh, asset, transport,
    ik: typedClient(IkService, transport),
    deform: typedClient(DeformService, transport),
    authoring: typedClient(AuthoringService, transport),
    jointNames,
    forgetSkeletons: forget,
    importAsset: (data, o) => importAsset(baseUrl, data, o, { token: options.token, fetch: options.fetch }),

    async evaluateClip(clip, times, o = {}) {
      const res = await pose.evaluateClip({
        clip, times,
        space: enumOf(SPACES, o.space, 'space'),
        interpolation: enumOf(INTERPOLATIONS, o.interpolation, 'interpolation'),
        wrap: enumOf(WRAPS, o.wrap, 'wrap'),
        joints: o.joints ?? [],
      }, { signal: o.signal });
      return {
        clip: res.clip,
        skeleton: res.skeleton,
        times: res.times,
        jointIndices: res.joints,
        jointNames: await namesOf(res.skeleton, res.joints),
        translations: packFloats(res.poses.map((p) => p.translations)),
        rotations: packFloats(res.poses.map((p) => p.rotations)),
      };
    },

    async *streamClip(clip, o = {}) {
      const stream = pose.streamClip({
        clip,
        fps: o.fps ?? 0, speed: o.speed ?? 0, loop: o.loop ?? false,
        startTime: o.startTime ?? 0, duration: o.duration ?? 0,
        space: enumOf(SPACES, o.space, 'space'),
        interpolation: enumOf(INTERPOLATIONS, o.interpolation, 'interpolation'),
        joints: o.joints ?? [],
      }, { signal: o.signal });
      // The first frame names the skeleton and the joints; the rest reuse them.
      let skeleton = '';
      let jointIndices: number[] = [];
      let names: string[] = [];
      for await (const f of stream) {
        if (f.skeleton) {
          skeleton = f.skeleton;
          jointIndices = f.joints;
          names = await namesOf(skeleton, jointIndices);
        }
        yield {
          index: Number(f.index), time: f.time, wallTime: f.wallTime,
          skeleton, jointIndices, jointNames: names,
          translations: Float32Array.from(f.pose?.translations ?? []),
          rotations: Float32Array.from(f.pose?.rotations ?? []),
        };
      }
    },

    async skinMesh(meshName, clip, time, o = {}) {
      const res = await mesh.skinMesh({
        mesh: meshName, clip, time,
        method: enumOf(METHODS, o.method, 'method'),
        interpolation: enumOf(INTERPOLATIONS, o.interpolation, 'interpolation'),
        wrap: enumOf(WRAPS, o.wrap, 'wrap'),
        morphWeights: o.morphWeights ?? [],
      }, { signal: o.signal });
      const skinned: SkinnedMesh = {
        mesh: res.mesh, vertexCount: res.vertexCount, positions: Float32Array.from(res.positions),
      };
      if (res.normals.length > 0) skinned.normals = Float32Array.from(res.normals);
      return skinned;
    },
  };
}
