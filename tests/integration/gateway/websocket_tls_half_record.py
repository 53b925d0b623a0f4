"""Half a TLS record must not stall a WebSocket session's frames, for
WebSocketSession.HalfATlsRecordDoesNotStallTheFrames:
python3 websocket_tls_half_record.py <port> <ca.pem>. Over wss (TLS through
memory BIOs, so the test decides which bytes go out), opens a playback
session on demo_walk at 30 fps, reads three frames, then sends only the
first half of the TLS record carrying a ping frame and counts the frames that
arrive in the next 2 s; then sends the other half. Prints the 101's status
line, "stalled <frames in those 2 s>", then "pong True" once the ping is
answered."""
import socket
import ssl
import struct
import sys
import time

port, ca = int(sys.argv[1]), sys.argv[2]
sock = socket.create_connection(("127.0.0.1", port), timeout=30)
incoming, outgoing = ssl.MemoryBIO(), ssl.MemoryBIO()
tls = ssl.create_default_context(cafile=ca).wrap_bio(incoming, outgoing, server_hostname="localhost")
plain = bytearray()


def flush():
    data = outgoing.read()
    if data:
        sock.sendall(data)


def pump(deadline):
    """Moves bytes from the socket into the TLS object; False at the deadline or the end."""
    left = deadline - time.monotonic()
    if left <= 0:
        return False
    sock.settimeout(left)
    try:
        data = sock.recv(65536)
    except socket.timeout:
        return False
    if not data:
        return False
    incoming.write(data)
    return True


def fill(n, deadline):
    """Decrypted bytes until `plain` holds n, or False at the deadline."""
    while len(plain) < n:
        try:
            plain.extend(tls.read(65536))
        except ssl.SSLWantReadError:
            flush()
            if not pump(deadline):
                return False
    return True


def take(n):
    out = bytes(plain[:n])
    del plain[:n]
    return out


def receive(deadline):
    """(opcode, payload) of the next server frame, or None at the deadline."""
    if not fill(2, deadline):
        return None
    n, extra = plain[1] & 0x7F, 0
    extra = 2 if n == 126 else 8 if n == 127 else 0
    if not fill(2 + extra, deadline):
        return None
    if extra:
        n = int.from_bytes(plain[2:2 + extra], "big")
    if not fill(2 + extra + n, deadline):
        return None
    head = take(2 + extra)
    return head[0] & 0x0F, take(n)


def frame(op, payload, mask=b"\x11\x22\x33\x44"):
    return bytes([0x80 | op, 0x80 | len(payload)]) + mask + bytes(c ^ mask[i % 4] for i, c in enumerate(payload))


while True:
    try:
        tls.do_handshake()
        break
    except ssl.SSLWantReadError:
        flush()
        if not pump(time.monotonic() + 30):
            sys.exit("no TLS handshake")
flush()
tls.write(b"GET /v1/skeletons/demo_walk:playbackSession HTTP/1.1\r\nHost: localhost\r\nUpgrade: websocket\r\n"
          b"Connection: Upgrade\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n")
flush()
deadline = time.monotonic() + 30
while b"\r\n\r\n" not in plain:
    if not fill(len(plain) + 1, deadline):
        sys.exit("no handshake answer")
head, _, rest = bytes(plain).partition(b"\r\n\r\n")
plain[:] = rest
print(head.split(b"\r\n")[0].decode())

tls.write(frame(1, b'{"start": {"fps": 30, "play": {"clip": "demo_walk"}}}'))
flush()
for _ in range(3):
    f = receive(time.monotonic() + 30)
    if f is None or f[0] != 1:
        sys.exit("no frame: %r" % (f,))

tls.write(frame(9, b"half"))
record = outgoing.read()
sock.sendall(record[: len(record) // 2])
stalled, deadline = 0, time.monotonic() + 2
while receive(deadline) is not None:
    stalled += 1
print("stalled", stalled)
sock.sendall(record[len(record) // 2:])
deadline = time.monotonic() + 15
while True:
    f = receive(deadline)
    if f is None:
        sys.exit("no pong")
    if f[0] == 10:
        print("pong", f[1] == b"half")
        break
