// Starts a real armature-server on free ports with a fresh data dir (for the
// browser and OpenAPI tests) and stops it again.
import { spawn } from 'node:child_process';
import { mkdtempSync, readFileSync, rmSync, existsSync, openSync } from 'node:fs';
import { tmpdir } from 'node:os';
import path from 'node:path';

export async function startServer(serverBin, extraArgs = []) {
  const dir = mkdtempSync(path.join(tmpdir(), 'armature-web-'));
  const portFile = path.join(dir, 'ports.json');
  const log = path.join(dir, 'server.log');
  const out = openSync(log, 'w');
  const child = spawn(
    serverBin,
    ['--grpc-port', '0', '--http-port', '0', '--host', '127.0.0.1', '--data-dir', path.join(dir, 'data'),
      '--port-file', portFile, ...extraArgs],
    { stdio: ['ignore', out, out] },
  );
  let exited = null;
  child.on('exit', (code) => (exited = code));
  const deadline = Date.now() + 60000;
  while (!existsSync(portFile)) {
    if (exited !== null) throw new Error(`armature-server exited (${exited}):\n${readFileSync(log, 'utf8')}`);
    if (Date.now() > deadline) {
      child.kill('SIGKILL');
      throw new Error(`armature-server did not start:\n${readFileSync(log, 'utf8')}`);
    }
    await new Promise((r) => setTimeout(r, 20));
  }
  const ports = JSON.parse(readFileSync(portFile, 'utf8'));
  return {
    url: `http://127.0.0.1:${ports.http}`,
    grpcPort: ports.grpc,
    log: () => readFileSync(log, 'utf8'),
    // Imports a file the way `armature import` does over REST: the raw file
    // is the body of POST /v1/assets:import. Returns the AssetInfo.
    async importAsset(filename, name, data) {
      const query = new URLSearchParams({ filename, name });
      const res = await fetch(`http://127.0.0.1:${ports.http}/v1/assets:import?${query}`, {
        method: 'POST', headers: { 'Content-Type': 'application/octet-stream' }, body: data,
      });
      const body = await res.json();
      if (!res.ok) throw new Error(`importing ${filename}: ${res.status} ${body.message}`);
      return body.asset;
    },
    // A REST call with a JSON body (GET without one); the answer as JSON, or an Error with its message.
    async call(route, body) {
      const res = await fetch(`http://127.0.0.1:${ports.http}${route}`, body && {
        method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(body),
      });
      const json = await res.json();
      if (!res.ok) throw new Error(`${route}: ${res.status} ${json.message}`);
      return json;
    },
    async stop() {
      if (exited === null) {
        const done = new Promise((r) => child.on('exit', r));
        child.kill('SIGTERM');
        await done;
      }
      rmSync(dir, { recursive: true, force: true });
    },
  };
}
