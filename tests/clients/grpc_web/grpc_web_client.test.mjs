// gRPC-Web on the HTTP port through a real client: @connectrpc/connect-web's
// createGrpcWebTransport (node's fetch) with stubs that @bufbuild/protoc-gen-es
// generates from proto/ when the test starts; every answer is compared with
// the same call over gRPC on the gRPC port (@connectrpc/connect-node's gRPC
// transport, HTTP/2). The text mode (application/grpc-web-text), which
// connect-web does not speak, goes through fetch with the generated codecs.
//   node grpc_web_client.test.mjs <armature-server> <protoc> <proto dir>
import { execFileSync } from 'node:child_process';
import { mkdtempSync, readdirSync, rmSync, writeFileSync } from 'node:fs';
import path from 'node:path';
import { after, before, test } from 'node:test';
import assert from 'node:assert/strict';
import { fileURLToPath } from 'node:url';

import { create, equals, fromBinary, toBinary } from '@bufbuild/protobuf';
import { Code, ConnectError, createClient } from '@connectrpc/connect';
import { createGrpcTransport } from '@connectrpc/connect-node';
import { createGrpcWebTransport } from '@connectrpc/connect-web';

import { startServer } from '../../../web/test/support/server.mjs';

const HERE = path.dirname(fileURLToPath(import.meta.url));
const [serverBin, protoc, protoDir] = process.argv.slice(2);
const TOKEN = 'grpc-web-client-token';

// Generated code lives under this folder so that it resolves node_modules.
const gen = mkdtempSync(path.join(HERE, '.gen-'));
execFileSync(protoc, [
  `-I${protoDir}`, `--plugin=protoc-gen-es=${path.join(HERE, 'node_modules/.bin/protoc-gen-es')}`,
  `--es_out=${gen}`, '--es_opt=target=js,import_extension=js',
  // Every API file: a new one imported by poses.proto (playback.proto) must not be missed.
  ...readdirSync(path.join(protoDir, 'armature/v1')).filter((f) => f.endsWith('.proto')).map((f) => `armature/v1/${f}`),
  'google/api/annotations.proto', 'google/api/http.proto',
], { stdio: 'inherit' });
const poses = await import(path.join(gen, 'armature/v1/poses_pb.js'));
const meshes = await import(path.join(gen, 'armature/v1/meshes_pb.js'));
const assets = await import(path.join(gen, 'armature/v1/assets_pb.js'));
const types = await import(path.join(gen, 'armature/v1/types_pb.js'));

let server, secured;
let web, grpc;  // the same services over gRPC-Web (HTTP port) and gRPC

function clients(transport) {
  return {
    pose: createClient(poses.PoseService, transport),
    mesh: createClient(meshes.MeshService, transport),
    asset: createClient(assets.AssetService, transport),
  };
}

before(async () => {
  server = await startServer(serverBin);
  web = clients(createGrpcWebTransport({ baseUrl: server.url, useBinaryFormat: true }));
  grpc = clients(createGrpcTransport({ baseUrl: `http://127.0.0.1:${server.grpcPort}` }));
  const tokens = path.join(gen, 'tokens');
  writeFileSync(tokens, `${TOKEN}\n`);
  secured = await startServer(serverBin, ['--auth-token-file', tokens]);
});

after(async () => {
  await server?.stop();
  await secured?.stop();
  rmSync(gen, { recursive: true, force: true });
});

const evaluate = () => create(poses.EvaluateClipRequestSchema, {
  clip: 'demo_walk', times: [0, 0.4, 1.3], space: types.Space.WORLD,
});

test('EvaluateClip over gRPC-Web equals the gRPC answer', async () => {
  const [viaWeb, viaGrpc] = await Promise.all([web.pose.evaluateClip(evaluate()), grpc.pose.evaluateClip(evaluate())]);
  assert.ok(viaGrpc.poses.length === 3 && viaGrpc.poses[0].translations.length > 0);
  assert.ok(equals(poses.EvaluateClipResponseSchema, viaWeb, viaGrpc));
});

test('StreamClip over gRPC-Web sends every frame gRPC sends', async () => {
  const req = create(poses.StreamClipRequestSchema, { clip: 'demo_walk', fps: 240, speed: 8, space: types.Space.WORLD });
  const collect = async (stream) => {
    const frames = [];
    for await (const f of stream) frames.push({ ...f, wallTime: 0 });  // wall-clock time differs between runs
    return frames;
  };
  const [viaWeb, viaGrpc] = await Promise.all([collect(web.pose.streamClip(req)), collect(grpc.pose.streamClip(req))]);
  assert.ok(viaGrpc.length > 5, `${viaGrpc.length} frames`);
  assert.equal(viaWeb.length, viaGrpc.length);
  viaWeb.forEach((f, i) => assert.ok(equals(poses.PoseFrameSchema, f, viaGrpc[i]), `frame ${i}`));
});

test('SkinMesh over gRPC-Web equals the gRPC answer', async () => {
  const { meshes: list } = await grpc.mesh.listMeshes({});
  assert.ok(list.length > 0, 'the demo character has a mesh');
  const req = create(meshes.SkinMeshRequestSchema, { mesh: list[0].name, clip: 'demo_character.walk', time: 0.5 });
  const [viaWeb, viaGrpc] = await Promise.all([web.mesh.skinMesh(req), grpc.mesh.skinMesh(req)]);
  assert.equal(viaGrpc.positions.length, 3 * list[0].vertexCount);
  assert.ok(equals(meshes.SkinMeshResponseSchema, viaWeb, viaGrpc));
});

test('an unknown clip is NOT_FOUND with its message', async () => {
  const req = create(poses.EvaluateClipRequestSchema, { clip: 'no such clip 100%', times: [0] });
  const err = await web.pose.evaluateClip(req).then(() => null, (e) => ConnectError.from(e));
  assert.equal(err?.code, Code.NotFound);
  assert.match(err.rawMessage, /no such clip 100%/);
  const viaGrpc = await grpc.pose.evaluateClip(req).then(() => null, (e) => ConnectError.from(e));
  assert.equal(err.rawMessage, viaGrpc.rawMessage);
});

test('with a token file the token is required', async () => {
  const transport = (headers) => createGrpcWebTransport({
    baseUrl: secured.url, useBinaryFormat: true,
    interceptors: [(next) => (req) => { for (const [k, v] of Object.entries(headers)) req.header.set(k, v); return next(req); }],
  });
  const none = createClient(assets.AssetService, transport({}));
  const err = await none.listClips({}).then(() => null, (e) => ConnectError.from(e));
  assert.equal(err?.code, Code.Unauthenticated);
  const good = createClient(assets.AssetService, transport({ authorization: `Bearer ${TOKEN}` }));
  assert.equal((await good.listClips({})).clips.length, 2);
});

test('the text mode (application/grpc-web-text) gives the same answer', async () => {
  const message = toBinary(poses.EvaluateClipRequestSchema, evaluate());
  const frame = Buffer.alloc(5 + message.length);
  frame.writeUInt32BE(message.length, 1);
  frame.set(message, 5);
  const res = await fetch(`${server.url}/armature.v1.PoseService/EvaluateClip`, {
    method: 'POST',
    headers: { 'content-type': 'application/grpc-web-text', 'x-grpc-web': '1' },
    body: frame.toString('base64'),
  });
  assert.equal(res.status, 200);
  assert.equal(res.headers.get('content-type'), 'application/grpc-web-text+proto');
  const body = Buffer.from(await res.text(), 'base64');
  assert.equal(body[0], 0);
  const length = body.readUInt32BE(1);
  const answer = fromBinary(poses.EvaluateClipResponseSchema, body.subarray(5, 5 + length));
  assert.ok(equals(poses.EvaluateClipResponseSchema, answer, await grpc.pose.evaluateClip(evaluate())));
  const trailer = body.subarray(5 + length);
  assert.equal(trailer[0], 0x80);
  assert.match(trailer.subarray(5).toString(), /^grpc-status: ?0\r\n/);
});
