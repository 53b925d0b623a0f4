// Bundles the viewer (three.js and the TypeScript client included) into one
// module: node build.mjs <outdir>. Nothing is fetched: esbuild, three,
// protobuf-es and connect-web come from node_modules (npm ci).
//
// The viewer talks to the server through clients/typescript (its source,
// bundled as is): gRPC-Web for the calls, its WebSocket sessions for IK and
// deformation. That client imports its protoc-gen-es stubs from ./gen/, which are
// not committed: the client's own generate.mjs makes them here from proto/
// (protoc, web's protoc-gen-es) into node_modules/.armature-gen; the bundler resolves
// the client's ./gen/ imports there.
import { execFileSync } from 'node:child_process';
import { copyFile, mkdir } from 'node:fs/promises';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import * as esbuild from 'esbuild';

const here = path.dirname(fileURLToPath(import.meta.url));
const outdir = path.resolve(process.argv[2] ?? path.join(here, 'dist'));
const protoDir = path.join(here, '../proto');
const clientSrc = path.join(here, '../clients/typescript/src');
const genDir = path.join(here, 'node_modules/.armature-gen');

execFileSync(process.execPath, [
  path.join(here, '../clients/typescript/scripts/generate.mjs'), protoDir, genDir,
  path.join(here, 'node_modules/.bin/protoc-gen-es'),
], { stdio: 'inherit' });

// The client's `./gen/...` imports → the stubs generated above.
const generatedStubs = {
  name: 'armature-generated-stubs',
  setup(build) {
    build.onResolve({ filter: /^\.\/gen\// }, (args) => {
      if (path.resolve(args.resolveDir) !== clientSrc) return undefined;
      return { path: path.join(genDir, args.path.slice('./gen/'.length).replace(/\.js$/, '.ts')) };
    });
  },
};

await mkdir(outdir, { recursive: true });
await esbuild.build({
  // The viewer (index.html) and the crowd page (crowd.html).
  entryPoints: { app: path.join(here, 'src/main.js'), crowd: path.join(here, 'src/crowd/crowd_page.js') },
  bundle: true,
  format: 'esm',
  target: 'es2020',
  minify: true,
  sourcemap: true,
  outdir,
  logLevel: 'warning',
  // The client and the stubs live outside web/: their packages come from web's node_modules.
  nodePaths: [path.join(here, 'node_modules')],
  plugins: [generatedStubs],
});
for (const file of ['index.html', 'crowd.html', 'style.css']) await copyFile(path.join(here, file), path.join(outdir, file));
// The API reference at /docs: swagger-ui-dist's prebuilt files, with our page that points it at /openapi.json.
await mkdir(path.join(outdir, 'docs'), { recursive: true });
for (const file of ['index.html', 'docs.js']) await copyFile(path.join(here, 'docs', file), path.join(outdir, 'docs', file));
for (const file of ['swagger-ui.css', 'swagger-ui-bundle.js']) {
  await copyFile(path.join(here, 'node_modules/swagger-ui-dist', file), path.join(outdir, 'docs', file));
}
console.log(`viewer bundled into ${outdir}`);
