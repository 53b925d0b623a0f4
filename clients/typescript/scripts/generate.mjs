// Generates the TypeScript stubs from proto/ into src/gen/ with protoc (PROTOC, or
// `protoc` on PATH) and @bufbuild/protoc-gen-es. Nothing generated is committed.
//   node scripts/generate.mjs [proto dir]
import { execFileSync } from 'node:child_process';
import { mkdirSync, readdirSync, rmSync } from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
const protoDir = path.resolve(process.argv[2] ?? path.join(root, '../../proto'));
const out = path.join(root, 'src/gen');
rmSync(out, { recursive: true, force: true });
mkdirSync(out, { recursive: true });
const files = readdirSync(path.join(protoDir, 'armature/v1'))
  .filter((f) => f.endsWith('.proto')).map((f) => `armature/v1/${f}`);
execFileSync(process.env.PROTOC || 'protoc', [
  `-I${protoDir}`,
  `--plugin=protoc-gen-es=${path.join(root, 'node_modules/.bin/protoc-gen-es')}`,
  `--es_out=${out}`, '--es_opt=target=ts,import_extension=js',
  ...files, 'google/api/annotations.proto', 'google/api/http.proto',
], { stdio: 'inherit' });
