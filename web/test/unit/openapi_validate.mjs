// /openapi.json of a real armature-server is a valid OpenAPI 3 document:
// validated offline with @apidevtools/swagger-parser (schema and $refs).
//   node openapi_validate.mjs <armature-server>
import SwaggerParser from '@apidevtools/swagger-parser';
import { startServer } from '../support/server.mjs';

const [serverBin] = process.argv.slice(2);
if (!serverBin) {
  console.error('usage: node openapi_validate.mjs <armature-server>');
  process.exit(2);
}
const server = await startServer(serverBin);
let failed = false;
try {
  const res = await fetch(`${server.url}/openapi.json`);
  if (res.status !== 200) throw new Error(`GET /openapi.json: ${res.status}`);
  const doc = await res.json();
  // The document describes what the server serves: every GET without path
  // parameters answers 200. Fetched before the validation, which holds the
  // event loop for seconds on a busy machine: a kept-alive socket idle that
  // long is one the server has closed (its keep-alive timeout, 5 s).
  for (const [p, methods] of Object.entries(doc.paths)) {
    if (!methods.get || p.includes('{')) continue;
    const r = await fetch(server.url + p);
    if (r.status !== 200) throw new Error(`GET ${p}: ${r.status}`);
  }
  const api = await SwaggerParser.validate(structuredClone(doc));
  const operations = Object.values(api.paths).flatMap((p) => Object.keys(p));
  console.log(`valid OpenAPI ${api.openapi}: ${Object.keys(api.paths).length} paths, ${operations.length} operations, ` +
              `${Object.keys(doc.components.schemas).length} schemas`);
} catch (error) {
  failed = true;
  console.error(`FAIL: ${error.message}`);
} finally {
  await server.stop();
}
process.exit(failed ? 1 : 0);
