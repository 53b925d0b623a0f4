// @armature/client against a real server: EvaluateClip, StreamClip and
// SkinMesh through the client (gRPC-Web, binary), and an IK session over a
// WebSocket (node's WebSocket: run with --experimental-websocket on node 20),
// equal the same calls over gRPC (@connectrpc/connect-node on the gRPC port) value for value; joint names
// equal REST's skeleton; errors are typed; the token and the deadline apply; a session keeps its log.
// Needs dist/ (npm run build).
//   node test/client.test.mjs <armature-server>
import path from 'node:path';
import { execFileSync } from 'node:child_process';
import { mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { after, before, test } from 'node:test';
import assert from 'node:assert/strict';
import { fileURLToPath } from 'node:url';

import { createClient } from '@connectrpc/connect';
import { createGrpcTransport } from '@connectrpc/connect-node';

import { toBinary } from '@bufbuild/protobuf';

import {
  ArmatureError, Code, DeadlineExceededError, IkService, InvalidArgumentError, MeshService, NotFoundError, PoseService, Space,
  UnauthenticatedError, createArmatureClient, openIkSession,
} from '../dist/index.js';
import { SolveIkResponseSchema } from '../dist/gen/armature/v1/ik_pb.js';
import { startServer } from '../../../web/test/support/server.mjs';
import { ARM_BVH } from '../../../web/test/support/fixtures.mjs';

const HERE = path.dirname(fileURLToPath(import.meta.url));
const [serverBin] = process.argv.slice(2);
const TOKEN = 'typescript-client-token';

let server, secured, dir, client, grpc;

before(async () => {
  server = await startServer(serverBin);
  dir = mkdtempSync(path.join(tmpdir(), 'armature-ts-client-'));
  writeFileSync(path.join(dir, 'tokens'), `${TOKEN}\n`);
  secured = await startServer(serverBin, ['--auth-token-file', path.join(dir, 'tokens')]);
  client = createArmatureClient(server.url, { timeoutMs: 30000 });
  const transport = createGrpcTransport({ baseUrl: `http://127.0.0.1:${server.grpcPort}` });
  grpc = {
    pose: createClient(PoseService, transport), mesh: createClient(MeshService, transport),
    ik: createClient(IkService, transport),
  };
});

after(async () => {
  await server?.stop();
  await secured?.stop();
  if (dir) rmSync(dir, { recursive: true, force: true });
});

const flat = (parts) => Float32Array.from(parts.flat());
const restClip = async (name) => (await (await fetch(`${server.url}/v1/clips/${encodeURIComponent(name)}`)).json());
const restSkeleton = async (name) => (await (await fetch(`${server.url}/v1/skeletons/${encodeURIComponent(name)}`)).json());

test('evaluateClip packs the gRPC answer into Float32Arrays, with REST\'s joint names', async (t) => {
  const times = [0, 0.4, 1.3];
  const got = await client.evaluateClip('demo_walk', times, { space: 'world' });
  const want = await grpc.pose.evaluateClip({ clip: 'demo_walk', times, space: Space.WORLD });
  const joints = want.joints.length;
  assert.ok(joints > 1, `${joints} joints`);
  t.diagnostic(`${joints} joints, ${times.length} times`);
  assert.equal(got.skeleton, want.skeleton);
  assert.deepEqual(got.jointIndices, want.joints);
  assert.ok(got.translations instanceof Float32Array && got.rotations instanceof Float32Array);
  assert.equal(got.translations.length, times.length * joints * 3);
  assert.equal(got.rotations.length, times.length * joints * 4);
  assert.deepEqual(got.translations, flat(want.poses.map((p) => p.translations)));
  assert.deepEqual(got.rotations, flat(want.poses.map((p) => p.rotations)));
  // Pose 2, joint 1 sits at offset (2·joints + 1)·3: the layout is times × joints × 3.
  assert.equal(got.translations[(2 * joints + 1) * 3 + 2], want.poses[2].translations[5]);
  const skeleton = await restSkeleton(want.skeleton);
  assert.deepEqual(got.jointNames, want.joints.map((i) => skeleton.joints[i].name));
  // World space differs from local: the option reached the server.
  const local = await client.evaluateClip('demo_walk', times, { space: 'local' });
  assert.notDeepEqual(local.translations, got.translations);
});

test('evaluateClip with a subset of joints names exactly those joints', async () => {
  const all = await client.evaluateClip('demo_walk', [0.5]);
  const pick = [all.jointNames[all.jointNames.length - 1], all.jointNames[0]];
  const got = await client.evaluateClip('demo_walk', [0.5], { joints: pick });
  assert.deepEqual([...got.jointNames].sort(), [...pick].sort());
  assert.equal(got.translations.length, 2 * 3);
  for (const [k, name] of got.jointNames.entries()) {
    const j = all.jointNames.indexOf(name);
    assert.deepEqual(got.rotations.subarray(4 * k, 4 * k + 4), all.rotations.subarray(4 * j, 4 * j + 4));
  }
});

test('streamClip yields every frame gRPC sends, as Float32Arrays', async (t) => {
  const options = { fps: 240, speed: 8, space: 'world' };
  const frames = [];
  for await (const f of client.streamClip('demo_walk', options)) frames.push(f);
  const want = [];
  for await (const f of grpc.pose.streamClip({ clip: 'demo_walk', fps: 240, speed: 8, space: Space.WORLD })) want.push(f);
  assert.ok(want.length > 5, `${want.length} frames`);
  t.diagnostic(`${frames.length} frames`);
  assert.equal(frames.length, want.length);
  const names = (await client.evaluateClip('demo_walk', [0])).jointNames;
  frames.forEach((f, i) => {
    assert.equal(f.index, Number(want[i].index));
    assert.equal(f.time, want[i].time);
    assert.deepEqual(f.translations, Float32Array.from(want[i].pose.translations), `frame ${i}`);
    assert.deepEqual(f.rotations, Float32Array.from(want[i].pose.rotations), `frame ${i}`);
    assert.deepEqual(f.jointNames, names);  // every frame, though only the first carries them
  });
});

test('skinMesh equals the gRPC answer, normals included', async (t) => {
  const { meshes } = await grpc.mesh.listMeshes({});
  assert.ok(meshes.length > 0, 'the demo character has a mesh');
  const m = meshes[0];
  const got = await client.skinMesh(m.name, 'demo_character.walk', 0.5);
  const want = await grpc.mesh.skinMesh({ mesh: m.name, clip: 'demo_character.walk', time: 0.5 });
  assert.equal(got.vertexCount, m.vertexCount);
  assert.equal(got.positions.length, 3 * m.vertexCount);
  t.diagnostic(`${m.name}: ${m.vertexCount} vertices, normals ${want.normals.length > 0}`);
  assert.deepEqual(got.positions, Float32Array.from(want.positions));
  if (want.normals.length > 0) assert.deepEqual(got.normals, Float32Array.from(want.normals));
  else assert.equal(got.normals, undefined);
  const dqs = await client.skinMesh(m.name, 'demo_character.walk', 0.5, { method: 'dqs' });
  const wantDqs = await grpc.mesh.skinMesh({ mesh: m.name, clip: 'demo_character.walk', time: 0.5, method: 2 });
  assert.deepEqual(dqs.positions, Float32Array.from(wantDqs.positions));
});

test('an unknown clip is a NotFoundError naming it, unary and streaming', async () => {
  const err = await client.evaluateClip('no such clip 100%', [0]).then(() => null, (e) => e);
  assert.ok(err instanceof NotFoundError && err instanceof ArmatureError, String(err));
  assert.equal(err.code, Code.NotFound);
  assert.equal(err.code, 5);
  assert.equal(err.status, 'NOT_FOUND');
  assert.match(err.rawMessage, /no such clip 100%/);
  const viaGrpc = await grpc.pose.evaluateClip({ clip: 'no such clip 100%', times: [0] }).then(() => null, (e) => e);
  assert.equal(err.rawMessage, viaGrpc.rawMessage);

  const streamed = await (async () => { for await (const _ of client.streamClip('no such clip 100%')) ; })().then(() => null, (e) => e);
  assert.ok(streamed instanceof NotFoundError, String(streamed));
  assert.match(streamed.rawMessage, /no such clip 100%/);
  const mesh = await client.skinMesh('no such mesh', 'demo_character.walk', 0).then(() => null, (e) => e);
  assert.ok(mesh instanceof NotFoundError, String(mesh));
  assert.match(mesh.rawMessage, /no such mesh/);
});

test('with a token file the client\'s token is sent; without it the call is Unauthenticated', async () => {
  const none = await createArmatureClient(secured.url).evaluateClip('demo_walk', [0]).then(() => null, (e) => e);
  assert.ok(none instanceof UnauthenticatedError, String(none));
  assert.equal(none.code, Code.Unauthenticated);
  const wrong = await createArmatureClient(secured.url, { token: 'wrong' }).asset.listClips({}).then(() => null, (e) => e);
  assert.ok(wrong instanceof UnauthenticatedError, String(wrong));
  const good = createArmatureClient(secured.url, { token: TOKEN });
  const pose = await good.evaluateClip('demo_walk', [0.25]);
  assert.deepEqual(pose.rotations, (await client.evaluateClip('demo_walk', [0.25])).rotations);
  assert.equal((await good.asset.listClips({})).clips.length, 2);
});

test('timeoutMs ends a stream that would never end with a DeadlineExceededError', async (t) => {
  const short = createArmatureClient(server.url, { timeoutMs: 400 });
  const started = Date.now();
  let frames = 0;
  const err = await (async () => { for await (const _ of short.streamClip('demo_walk', { loop: true, fps: 30 })) frames++; })()
    .then(() => null, (e) => e);
  const elapsed = Date.now() - started;
  assert.ok(err instanceof DeadlineExceededError, String(err));
  assert.ok(frames > 3, `${frames} frames before the deadline`);
  assert.ok(elapsed >= 350 && elapsed < 5000, `${elapsed} ms`);
  t.diagnostic(`${frames} frames, ended after ${elapsed} ms`);
});

test('bad option names are refused before any call', async () => {
  await assert.rejects(client.evaluateClip('demo_walk', [0], { space: 'sideways' }), /space "sideways"/);
});

test('the README\'s TypeScript example runs as written', async () => {
  const readme = readFileSync(path.join(HERE, '../../../README.md'), 'utf8');
  const block = readme.match(/```ts\n([\s\S]*?)```/);
  assert.ok(block, 'README.md has a ```ts block');
  assert.ok(block[1].split('\n').length <= 10, 'under ten lines');
  // Run beside the package so that '@armature/client' resolves to it (a package's own name).
  const script = path.join(HERE, `.readme-${process.pid}.mjs`);
  writeFileSync(script, block[1].replace(/^ {2}/gm, '').replaceAll('http://localhost:8080', server.url));
  try {
    const out = execFileSync(process.execPath, [script], { encoding: 'utf8', timeout: 60000 });
    const lines = out.trim().split('\n');
    const { jointNames, translations } = await client.evaluateClip('demo_walk', [0, 0.5]);
    assert.equal(lines[0], `${jointNames[0]} ${translations.length}`);
    assert.ok(lines.length > 2, `${lines.length} lines: a frame per line after the first`);
    for (const line of lines.slice(1)) assert.match(line, new RegExp(`^[0-9.e-]+ ${jointNames.length * 4}$`));
  } finally {
    rmSync(script, { force: true });
  }
});

test('an IK session over a WebSocket answers each drag step as the gRPC session does', async (t) => {
  assert.ok(globalThis.WebSocket, 'node has WebSocket (node 22, or node 20 with --experimental-websocket)');
  const pose = await client.evaluateClip('demo_walk', [0.8], { space: 'world' });
  const w = pose.jointNames.indexOf('LeftWrist');
  const at = Array.from(pose.translations.subarray(3 * w, 3 * w + 3));
  const start = {
    skeleton: 'demo_walk', start: { case: 'fromClip', value: { clip: 'demo_walk', time: 0.8 } },
    effectors: [{ joint: 'LeftWrist', targetPosition: at }],
  };
  const moves = Array.from({ length: 20 }, (_, i) => [at[0] + i * 0.2, at[1] + i * 0.3, at[2] + i * 0.2]);

  const { session, first } = await openIkSession(server.url, start);
  const viaWs = [first];
  for (const target of moves) viaWs.push(await session.send({ targets: [{ effector: 0, targetPosition: target }] }));
  await session.close();

  async function* requests() {
    yield { start };
    for (const target of moves) yield { targets: [{ effector: 0, targetPosition: target }] };
  }
  const viaGrpc = [];
  for await (const answer of grpc.ik.ikSession(requests())) viaGrpc.push(answer);

  assert.equal(viaWs.length, moves.length + 1);
  assert.equal(viaGrpc.length, viaWs.length);
  viaWs.forEach((answer, i) => assert.deepEqual(toBinary(SolveIkResponseSchema, answer),
                                                toBinary(SolveIkResponseSchema, viaGrpc[i]), `answer ${i}`));
  assert.ok(first.converged && first.iterations === 0, 'the start pose already reaches the first target');
  assert.ok(viaWs.every((a) => a.world.translations.length === first.world.translations.length && a.residuals.length === 1));
  assert.ok(viaWs.slice(1).some((a) => a.iterations > 0), 'the moves needed solving');
  t.diagnostic(`${viaWs.length} answers equal, byte for byte (${viaWs.filter((a) => a.converged).length} converged)`);

  // An unknown skeleton: the session's status arrives as a typed error.
  await assert.rejects(openIkSession(server.url, { ...start, skeleton: 'nobody' }),
                       (e) => e instanceof NotFoundError && /nobody/.test(e.rawMessage));
  // With a token file the token travels as the subprotocol "bearer.<token>".
  const secure = await openIkSession(secured.url, start, { token: TOKEN });
  assert.ok(secure.first.world);
  await secure.session.close();
  await assert.rejects(openIkSession(secured.url, start), /could not open a session/);
});

test('a session with keepLog keeps its latest requests and their round trips', async () => {
  const start = {
    skeleton: 'demo_walk', start: { case: 'fromClip', value: { clip: 'demo_walk', time: 0.8 } },
    effectors: [{ joint: 'LeftWrist', targetPosition: [0, 100, 0] }],
  };
  const { session } = await openIkSession(server.url, start, { keepLog: 2 });
  for (let i = 0; i < 3; ++i) await session.send({ targets: [{ effector: 0, targetPosition: [i, 100, 0] }] });
  assert.ok(session.isOpen && session.pending === 0);
  await session.close();
  assert.ok(!session.isOpen, 'closed');
  const { log } = session;
  assert.ok(log.url.startsWith('ws://') && log.url.endsWith('/v1/skeletons/demo_walk:ikSession'), log.url);
  assert.equal(log.sent.length, 2, 'the latest two frames');
  assert.ok(log.sent.every((frame) => frame instanceof Uint8Array && frame.length > 0));
  assert.deepEqual(log.requests.map((r) => r.targets[0].targetPosition), [[1, 100, 0], [2, 100, 0]]);
  assert.ok(log.roundTrips.length === 2 && log.pageRoundTrips.length === 2 &&
            log.roundTrips.every((ms, i) => ms > 0 && ms <= log.pageRoundTrips[i]));
});

test('importAsset sends its precision: "exact" keeps the keys, a number is the bound in centimetres', async () => {
  const bvh = new TextEncoder().encode(ARM_BVH);
  const exact = await client.importAsset(bvh, { filename: 'arm.bvh', name: 'arm_exact', precision: 'exact' });
  const [clip] = exact.asset.clips;
  assert.equal(exact.asset.name, 'arm_exact');
  assert.ok(clip.exact, 'exact was asked');
  assert.equal(clip.errorBoundCm, 0);
  const bounded = (await client.importAsset(bvh, { filename: 'arm.bvh', name: 'arm_2cm', precision: 2 })).asset.clips[0];
  assert.equal(bounded.exact, false);
  assert.equal(bounded.errorBoundCm, 2);
  assert.ok(bounded.worstErrorCm <= 2, `worst error ${bounded.worstErrorCm} cm`);
  // The same as REST reports it, and without a precision the server's default (--clip-error 0.01).
  assert.equal((await restClip(bounded.name)).errorBoundCm, 2);
  const plain = (await client.importAsset(bvh, { filename: 'arm.bvh', name: 'arm_default' })).asset.clips[0];
  assert.equal(plain.errorBoundCm, 0.01);
  await assert.rejects(client.importAsset(bvh, { filename: 'arm.bvh', name: 'arm_11', precision: 11 }), (e) => {
    assert.ok(e instanceof InvalidArgumentError, `${e.constructor.name}: ${e.message}`);
    assert.match(e.message, /precision/);
    return true;
  });
  await assert.rejects(client.importAsset(bvh, { filename: 'arm.bvh', precision: Number.NaN }), TypeError);
});
