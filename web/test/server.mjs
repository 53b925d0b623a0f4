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
    log: () => readFileSync(log, 'utf8'),
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
