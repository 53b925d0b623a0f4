// The REST gateway, as the viewer uses it. Every call rejects with an Error
// carrying the server's message (and its gRPC `code`).
import { decodeSkinCharacter } from './skin_wire.js';

async function call(path, options = {}) {
  const res = await fetch(path, options);
  const body = await res.json().catch(() => null);
  if (!res.ok) {
    const error = new Error(body?.message ?? `${res.status} ${res.statusText}`);
    error.code = body?.code;
    throw error;
  }
  return body;
}

const clipPath = (clip) => `/v1/clips/${encodeURIComponent(clip)}`;

export async function listClips() {
  return (await call('/v1/clips')).clips;
}

export function getClip(clip) {
  return call(clipPath(clip));
}

export function getSkeleton(skeleton) {
  return call(`/v1/skeletons/${encodeURIComponent(skeleton)}`);
}

const postJson = (body) => ({
  method: 'POST',
  headers: { 'Content-Type': 'application/json' },
  body: JSON.stringify(body),
});

// Poses of every joint at `times`, in `space` ('WORLD' or 'LOCAL').
export function evaluate(clip, times, space = 'WORLD') {
  return call(`${clipPath(clip)}:evaluate`, postJson({ times, space }));
}

// Poses of a motion (motion.proto as JSON: layers, sync, ...) at `times`.
export function evaluateMotion(motion, times, space = 'WORLD') {
  return call('/v1/motions:evaluate', postJson({ motion, times, space }));
}

// One inverse kinematics solve (a SolveIkRequest as JSON, less the skeleton).
export function solveIk(skeleton, request) {
  return call(`/v1/skeletons/${encodeURIComponent(skeleton)}:solveIk`, postJson(request));
}

const meshPath = (mesh) => `/v1/meshes/${encodeURIComponent(mesh)}`;

export async function listMeshes() {
  return (await call('/v1/meshes')).meshes ?? [];
}

// The rest mesh: { mesh, vertexCount, positions, normals, triangles }.
export function getMeshGeometry(mesh) {
  return call(`${meshPath(mesh)}:geometry`);
}

// World-space positions (and normals) of `mesh` (a SkinMeshRequest as JSON, less the mesh).
export function skinMesh(mesh, request) {
  return call(`${meshPath(mesh)}:skin`, postJson(request));
}

// Every mesh of skeleton `skeleton` (a character) posed alike (a
// SkinCharacterRequest as JSON, less the skeleton): { skeleton, meshes: [SkinMesh
// answers, with Float32Array positions and normals] }, asked for as proto (skin_wire.js says why).
export async function skinCharacter(skeleton, request) {
  const options = postJson(request);
  options.headers.Accept = 'application/x-protobuf';
  const res = await fetch(`/v1/skeletons/${encodeURIComponent(skeleton)}:skinCharacter`, options);
  if (!res.ok) {
    const body = await res.json().catch(() => null);
    const error = new Error(body?.message ?? `${res.status} ${res.statusText}`);
    error.code = body?.code;
    throw error;
  }
  return decodeSkinCharacter(await res.arrayBuffer());
}

// One Laplacian/ARAP edit (a DeformRequest as JSON, less the mesh).
export function deform(mesh, request) {
  return call(`${meshPath(mesh)}:deform`, postJson(request));
}

// A server stream as Server-Sent Events: `onFrame(message)` per message,
// `onEnd(status)` with the final {code, message} (code 0: the stream ended).
// Returns a function that stops the stream.
function stream(path, query, onFrame, onEnd) {
  const source = new EventSource(`${path}?${new URLSearchParams(query)}`);
  let open = true;
  const close = () => {
    open = false;
    source.close();
  };
  source.onmessage = (event) => onFrame(JSON.parse(event.data));
  source.addEventListener('status', (event) => {
    close();  // the stream is over: no automatic reconnect
    onEnd(JSON.parse(event.data));
  });
  source.onerror = () => {
    if (!open) return;
    close();
    onEnd({ code: 14, message: 'the stream was interrupted' });
  };
  return close;
}

// Plays `clip` over SSE: `onFrame(frame)` gets each PoseFrame (world space).
export function streamClip(clip, { startTime = 0, speed = 1, fps = 30, loop = true }, onFrame, onEnd) {
  const query = { startTime, speed, fps, loop, space: 'WORLD' };
  return stream(`${clipPath(clip)}:stream`, query, onFrame, onEnd);
}

// Plays `clip` on `mesh` over SSE: `onFrame(frame)` gets each
// SkinnedMeshFrame; `method` is 'LBS' or 'DQS'.
export function streamSkinnedMesh(mesh, clip, { startTime = 0, speed = 1, fps = 30, loop = true, method = 'LBS' },
  onFrame, onEnd) {
  const query = { clip, startTime, speed, fps, loop, method };
  return stream(`${meshPath(mesh)}:stream`, query, onFrame, onEnd);
}
