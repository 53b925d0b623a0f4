// Bundles the viewer (three.js included) into one module: node build.mjs <outdir>.
// Nothing is fetched: esbuild and three come from node_modules (npm ci).
import { copyFile, mkdir } from 'node:fs/promises';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import * as esbuild from 'esbuild';

const here = path.dirname(fileURLToPath(import.meta.url));
const outdir = path.resolve(process.argv[2] ?? path.join(here, 'dist'));
await mkdir(outdir, { recursive: true });
await esbuild.build({
  entryPoints: [path.join(here, 'src/main.js')],
  bundle: true,
  format: 'esm',
  target: 'es2020',
  minify: true,
  sourcemap: true,
  outfile: path.join(outdir, 'app.js'),
  logLevel: 'warning',
});
for (const file of ['index.html', 'style.css']) await copyFile(path.join(here, file), path.join(outdir, file));
console.log(`viewer bundled into ${outdir}`);
