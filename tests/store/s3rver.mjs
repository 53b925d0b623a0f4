// A real S3-compatible server for the --store tests: s3rver on a loopback
// port. Usage: node --openssl-legacy-provider s3rver.mjs DIR PORT_FILE [--port N] [--tls KEY CERT] [BUCKET...]
// Writes {"port": N} to PORT_FILE once listening (port 0: any free one), keeps
// its objects in DIR (a restart on the same DIR finds them), and creates
// each BUCKET. It accepts only the access key S3RVER (secret S3RVER); it
// checks the key's existence, not SigV4 signatures. Its listings' continuation
// tokens are DES-encrypted: without the legacy provider a paged listing fails (HTTP 500).
import { writeFileSync, readFileSync, renameSync } from 'node:fs';
import S3rver from 's3rver';

const [dir, portFile, ...rest] = process.argv.slice(2);
let port = 0;
let key, cert;
const buckets = [];
for (let i = 0; i < rest.length; ++i) {
  if (rest[i] === '--port') port = Number(rest[++i]);
  else if (rest[i] === '--tls') {
    key = readFileSync(rest[++i]);
    cert = readFileSync(rest[++i]);
  } else buckets.push({ name: rest[i], configs: [] });
}
const server = new S3rver({
  address: '127.0.0.1',
  port,
  directory: dir,
  silent: true,
  key,
  cert,
  vhostBuckets: false,
  configureBuckets: buckets,
});
const address = await server.run();
writeFileSync(portFile + '.tmp', JSON.stringify({ port: address.port }));
renameSync(portFile + '.tmp', portFile);
process.on('SIGTERM', async () => {
  await server.close();
  process.exit(0);
});
