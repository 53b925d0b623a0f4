// The server, as the viewer uses it: every unary and streaming call goes
// through the TypeScript client (clients/typescript) over gRPC-Web with binary
// protobuf on the HTTP port (the sessions go over WebSockets in
// session_socket.js, and dropped files are posted as a form by drop_import.js), so big answers (skinned meshes, pose batches) travel as protobuf, not
// JSON text. Requests and answers keep the REST gateway's JSON shape (proto3
// JSON names, enums by name, every field present), so the rest of the viewer
// reads the same objects it always has. Every call rejects with an Error
// carrying the server's message and its gRPC `code`.
import { fromBinary, fromJson, toBinary, toJson } from '@bufbuild/protobuf';

import {
  AssetService, AuthoringService, DeformService, IkService, MeshService, PoseService, createArmatureClient,
} from '../../clients/typescript/src/index.ts';

const client = createArmatureClient(globalThis.location?.origin ?? '');

// As the gateway prints them: default values too.
const JSON_OUT = { alwaysEmitImplicit: true };

function viewerError(e) {
  const error = new Error(e.rawMessage ?? e.message);
  error.code = e.code;
  return error;
}

// One unary call: `request` as proto3 JSON in, the answer as proto3 JSON out.
async function unary(service, calls, name, request) {
  const method = service.method[name];
  try {
    const answer = await calls[name](fromJson(method.input, request));
    return toJson(method.output, answer, JSON_OUT);
  } catch (e) {
    throw viewerError(e);
  }
}

// An IkSession's messages in the proto encoding, for the joint drag's binary
// WebSocket frames: the server then neither parses nor prints JSON (about
// 0.3 ms of a 0.6 ms step), and the answer is a third of the JSON's size.
const ikSession = IkService.method.ikSession;
export const encodeIkSessionRequest = (request) => toBinary(ikSession.input, fromJson(ikSession.input, request));
export const decodeIkSessionAnswer = (buffer) =>
  toJson(ikSession.output, fromBinary(ikSession.output, new Uint8Array(buffer)), JSON_OUT);

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
  return client.jointNames(skeleton).catch((e) => {
    throw viewerError(e);
  });
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
export async function getMaterialImage(name, material, image) {
  try {
    const answer = await client.mesh.getMaterialImage({ mesh: name, material, image });
    return { mimeType: answer.mimeType, data: answer.data };
  } catch (e) {
    throw viewerError(e);
  }
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
