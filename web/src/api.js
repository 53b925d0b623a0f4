// The server, as the viewer uses it: every unary and streaming call and both
// sessions go through the TypeScript client (clients/typescript): the calls
// over gRPC-Web, the IK and deformation sessions over WebSockets (the client's
// sessions, its socket in a worker), and the crowd session over its WebSocket,
// all in binary protobuf, so big answers
// (skinned meshes, pose batches, deformed shapes) travel as protobuf, not JSON
// text. Only dropped files go another way: posted as a form by drop_import.js.
// Requests and answers keep the REST gateway's JSON shape (proto3 JSON names,
// enums by name, every field present), so the rest of the viewer reads the
// same objects it always has; only a deformation move's answer stays the
// decoded message (every vertex's floats, never printed as JSON). Every call
// rejects with an Error carrying the server's message and its gRPC `code`.
import { fromJson, toJson } from '@bufbuild/protobuf';

import {
  AssetService, AuthoringService, CrowdSession, DeformService, IkService, MeshService, PoseService, WorkerWebSocket,
  createArmatureClient, openDeformSession as openClientDeformSession, openIkSession as openClientIkSession,
} from '../../clients/typescript/src/index.ts';

const origin = globalThis.location?.origin ?? '';
const client = createArmatureClient(origin);

// As the gateway prints them: default values too.
const JSON_OUT = { alwaysEmitImplicit: true };

function viewerError(e) {
  const error = new Error(e.rawMessage ?? e.message);
  error.code = e.code;
  return error;
}

// `call()`'s answer; a failure rejects with the server's message and `code`.
async function viewerCall(call) {
  try {
    return await call();
  } catch (e) {
    throw viewerError(e);
  }
}

// One unary call: `request` as proto3 JSON in, the answer as proto3 JSON out.
function unary(service, calls, name, request) {
  const method = service.method[name];
  return viewerCall(async () => toJson(method.output, await calls[name](fromJson(method.input, request)), JSON_OUT));
}

const pose = (name, request) => unary(PoseService, client.pose, name, request);
const asset = (name, request) => unary(AssetService, client.asset, name, request);
const mesh = (name, request) => unary(MeshService, client.mesh, name, request);

export async function listClips() {
  return (await asset('listClips', {})).clips;
}

export function getClip(clip) {
  return asset('getClip', { clip });
}

export function getSkeleton(skeleton) {
  return asset('getSkeleton', { skeleton });
}

// A skeleton's joint names, fetched once (forgetSkeletons drops them, as after an import).
export function jointNames(skeleton) {
  return viewerCall(() => client.jointNames(skeleton));
}

export function forgetSkeletons() {
  client.forgetSkeletons();
}

// `clip` moved onto skeleton `skeleton` and stored (a RetargetClipRequest as
// JSON, less those two): { clip, asset, mapping, unmapped, warnings }.
export function retargetClip(clip, skeleton, request = {}) {
  return unary(AuthoringService, client.authoring, 'retargetClip', { ...request, clip, skeleton });
}

// Poses of every joint at `times`, in `space` ('WORLD' or 'LOCAL').
export function evaluate(clip, times, space = 'WORLD') {
  return pose('evaluateClip', { clip, times, space });
}

// Poses of a motion (motion.proto as JSON: layers, sync, ...) at `times`.
export function evaluateMotion(motion, times, space = 'WORLD') {
  return pose('evaluateMotion', { motion, times, space });
}

// One inverse kinematics solve (a SolveIkRequest as JSON, less the skeleton).
export function solveIk(skeleton, request) {
  return unary(IkService, client.ik, 'solveIk', { ...request, skeleton });
}

export async function listMeshes() {
  return (await mesh('listMeshes', {})).meshes ?? [];
}

// The rest mesh: { mesh, vertexCount, positions, normals, triangles, uvs, materials, materialGroups }.
export function getMeshGeometry(name) {
  return mesh('getMeshGeometry', { mesh: name });
}

// Material `index` of mesh `name` (GetMaterial: factors, textures, images' types and sizes).
export function getMaterial(name, index) {
  return mesh('getMaterial', { mesh: name, material: index });
}

// One image of a material as the server stores it: { mimeType, data: Uint8Array }
// (binary protobuf: the bytes are not base64'd into JSON).
export function getMaterialImage(name, material, image) {
  return viewerCall(async () => {
    const answer = await client.mesh.getMaterialImage({ mesh: name, material, image });
    return { mimeType: answer.mimeType, data: answer.data };
  });
}

// World-space positions (and normals) of `mesh` (a SkinMeshRequest as JSON, less the mesh).
export function skinMesh(name, request) {
  return mesh('skinMesh', { ...request, mesh: name });
}

// Every mesh of skeleton `skeleton` (a character) posed alike (a
// SkinCharacterRequest as JSON, less the skeleton): { skeleton, meshes: [SkinMesh answers] }.
export function skinCharacter(skeleton, request) {
  return mesh('skinCharacter', { ...request, skeleton });
}

// One Laplacian/ARAP edit (a DeformRequest as JSON, less the mesh).
export function deform(name, request) {
  return unary(DeformService, client.deform, 'deform', { ...request, mesh: name });
}

// A server stream: `onFrame(message)` per message as JSON, `onEnd(status)`
// with the final {code, message} (code 0: the stream ended). Returns a
// function that stops the stream (then onEnd is not called).
function stream(service, calls, name, request, onFrame, onEnd) {
  const method = service.method[name];
  const abort = new AbortController();
  (async () => {
    try {
      for await (const frame of calls[name](fromJson(method.input, request), { signal: abort.signal })) {
        onFrame(toJson(method.output, frame, JSON_OUT));
      }
      if (!abort.signal.aborted) onEnd({ code: 0, message: '' });
    } catch (e) {
      if (!abort.signal.aborted) onEnd({ code: e.code ?? 2, message: e.rawMessage ?? String(e.message ?? e) });
    }
  })();
  return () => abort.abort();
}

// Plays `clip`: `onFrame(frame)` gets each PoseFrame (world space).
export function streamClip(clip, { startTime = 0, speed = 1, fps = 30, loop = true }, onFrame, onEnd) {
  const request = { clip, startTime, speed, fps, loop, space: 'WORLD' };
  return stream(PoseService, client.pose, 'streamClip', request, onFrame, onEnd);
}

// Plays `clip` on `mesh`: `onFrame(frame)` gets each SkinnedMeshFrame;
// `method` is 'LBS' or 'DQS'.
export function streamSkinnedMesh(name, clip, { startTime = 0, speed = 1, fps = 30, loop = true, method = 'LBS' },
  onFrame, onEnd) {
  const request = { mesh: name, clip, startTime, speed, fps, loop, method };
  return stream(MeshService, client.mesh, 'streamSkinnedMesh', request, onFrame, onEnd);
}

// Sessions: the socket in a worker (answers timed as they arrive, while the
// page draws), and each session's latest requests and round trips kept in its
// `log` (the drags' stats; web.session_e2e replays and times them).
const SESSIONS = { WebSocket: WorkerWebSocket, keepLog: 512 };
const ikSession = IkService.method.ikSession;
const deformSession = DeformService.method.deformSession;

// An IkSession on skeleton `skeleton`, opened with `start` (a SolveIkRequest as
// JSON, less the skeleton): { session, first: the start's answer as JSON }.
export function openIkSession(skeleton, start) {
  return viewerCall(async () => {
    const request = fromJson(IkService.method.solveIk.input, { ...start, skeleton });
    const { session, first } = await openClientIkSession(origin, request, SESSIONS);
    return { session, first: toJson(ikSession.output, first, JSON_OUT) };
  });
}

// One IkSession step (an IkSessionRequest as JSON): its answer as JSON.
export function ikStep(session, request) {
  return viewerCall(async () => {
    const answer = await session.send(fromJson(ikSession.input, request));
    return toJson(ikSession.output, answer, JSON_OUT);
  });
}

// A DeformSession for `setup` (a DeformSetup as JSON) and the handles
// `handleIndices`, factored when it opens: the session.
export function openDeformSession(setup, handleIndices) {
  return viewerCall(async () => {
    const start = fromJson(deformSession.input, { start: { setup, handleIndices } }).message.value;
    return (await openClientDeformSession(origin, start, SESSIONS)).session;
  });
}

// One DeformSession move, the handles' targets (x, y, z each): the
// DeformResponse as decoded (every vertex's `positions`, `iterations`).
export function deformMove(session, positions) {
  return viewerCall(() => session.send({ message: { case: 'move', value: { positions } } }));
}

// A crowd (CrowdService.CrowdSession over its WebSocket): the client's
// CrowdSession, its frames' poses decoded to typed arrays. `start` as the
// CrowdStart message's fields (fps, budgetMs, maxInterval, shareQuantum).
export function openCrowdSession(start) {
  return viewerCall(() => CrowdSession.open(origin, start));
}
