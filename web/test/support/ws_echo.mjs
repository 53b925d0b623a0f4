// A minimal WebSocket peer for measuring the browser's own round trip: it
// answers every client frame with one binary frame of `?answer=` bytes and
// does nothing else, so a round trip to it is Chromium's worker, renderer and
// network-service hops plus loopback, with no server work at all.
import { createHash } from 'node:crypto';
import http from 'node:http';

const GUID = '258EAFA5-E914-47DA-95CA-C5AB0DC85B11';  // RFC 6455 §1.3

function frameHeader(length) {
  if (length < 126) return Buffer.from([0x82, length]);
  if (length < 65536) return Buffer.from([0x82, 126, length >> 8, length & 255]);
  const header = Buffer.alloc(10);
  header[0] = 0x82;
  header[1] = 127;
  header.writeBigUInt64BE(BigInt(length), 2);
  return header;
}

// Resolves with { url, close() } once listening on a free loopback port.
export function startEcho() {
  const server = http.createServer((req, res) => res.writeHead(426).end());
  server.on('upgrade', (req, socket) => {
    socket.setNoDelay(true);
    const size = Number(new URL(req.url, 'ws://echo').searchParams.get('answer') ?? 16);
    const answer = Buffer.concat([frameHeader(size), Buffer.alloc(size, 1)]);
    const accept = createHash('sha1').update(req.headers['sec-websocket-key'] + GUID).digest('base64');
    socket.write('HTTP/1.1 101 Switching Protocols\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n' +
                 `Sec-WebSocket-Accept: ${accept}\r\n\r\n`);
    let pending = Buffer.alloc(0);
    socket.on('data', (data) => {
      pending = Buffer.concat([pending, data]);
      for (;;) {  // each whole client frame (masked: 4 key bytes) gets the answer
        if (pending.length < 2) return;
        let length = pending[1] & 0x7f, at = 2;
        if (length === 126) [length, at] = [pending.length >= 4 ? pending.readUInt16BE(2) : Infinity, 4];
        else if (length === 127) [length, at] = [pending.length >= 10 ? Number(pending.readBigUInt64BE(2)) : Infinity, 10];
        if (pending.length < at + 4 + length) return;
        const opcode = pending[0] & 0x0f;
        pending = pending.subarray(at + 4 + length);
        if (opcode === 0x8) return socket.end();
        socket.write(answer);
      }
    });
    socket.on('error', () => {});
  });
  return new Promise((resolve) => server.listen(0, '127.0.0.1', () => resolve({
    url: `ws://127.0.0.1:${server.address().port}/`,
    close: () => new Promise((done) => { server.closeAllConnections?.(); server.close(done); }),
  })));
}
