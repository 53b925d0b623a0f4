// Generates the TypeScript stubs from proto/ into src/gen/ with protoc (PROTOC, or
// `protoc` on PATH) and @bufbuild/protoc-gen-es. Nothing generated is committed.
// The viewer's bundler (web/build.mjs) calls it with its own output folder and plugin.
//   node scripts/generate.mjs [proto dir] [out dir] [protoc-gen-es]
import { execFileSync } from 'node:child_process';
import { mkdirSync, readdirSync, rmSync } from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
const protoDir = path.resolve(process.argv[2] ?? path.join(root, '../../proto'));
const out = path.resolve(process.argv[3] ?? path.join(root, 'src/gen'));
const plugin = path.resolve(process.argv[4] ?? path.join(root, 'node_modules/.bin/protoc-gen-es'));
rmSync(out, { recursive: true, force: true });
mkdirSync(out, { recursive: true });
const files = readdirSync(path.join(protoDir, 'armature/v1'))
  .filter((f) => f.endsWith('.proto')).map((f) => `armature/v1/${f}`);
execFileSync(process.env.PROTOC || 'protoc', [
  `-I${protoDir}`,
  `--plugin=protoc-gen-es=${plugin}`,
  `--es_out=${out}`, '--es_opt=target=ts,import_extension=js',
  ...files, 'google/api/annotations.proto', 'google/api/http.proto',
], { stdio: 'inherit' });
