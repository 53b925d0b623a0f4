"""A WebSocket session over TLS (wss://), for WebSocketSession.RunsOverTls:
python3 websocket_tls_client.py <port> <ca.pem>. Opens an IK session on
demo_walk, sends the start and three target moves (masked text frames,
RFC 6455), closes, and prints one line per frame received: the opcode, then
whether the JSON answer carries a world pose, or the close code."""
import json
import socket
import ssl
import struct
import sys

port, ca = int(sys.argv[1]), sys.argv[2]
ctx = ssl.create_default_context(cafile=ca)
s = ctx.wrap_socket(socket.create_connection(("127.0.0.1", port), timeout=30), server_hostname="localhost")
s.sendall(b"GET /v1/skeletons/demo_walk:ikSession HTTP/1.1\r\nHost: localhost\r\nUpgrade: websocket\r\n"
          b"Connection: Upgrade\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n")
head = b""
while b"\r\n\r\n" not in head:
    head += s.recv(1)
print(head.split(b"\r\n")[0].decode())


def send(op, payload, mask=b"\x11\x22\x33\x44"):
    n = len(payload)
    size = bytes([0x80 | n]) if n < 126 else bytes([0x80 | 126]) + struct.pack(">H", n)
    s.sendall(bytes([0x80 | op]) + size + mask + bytes(c ^ mask[i % 4] for i, c in enumerate(payload)))


def exactly(n):
    out = b""
    while len(out) < n:
        chunk = s.recv(n - len(out))
        if not chunk:
            raise EOFError
        out += chunk
    return out


def receive():
    h = exactly(2)
    n = h[1] & 0x7F
    if n == 126:
        n = struct.unpack(">H", exactly(2))[0]
    elif n == 127:
        n = struct.unpack(">Q", exactly(8))[0]
    op, payload = h[0] & 0x0F, exactly(n)
    if op == 1:
        print(op, "world" in json.loads(payload))
    else:
        print(op, struct.unpack(">H", payload[:2])[0] if len(payload) >= 2 else "")


send(1, b'{"start": {"effectors": [{"joint": "LeftWrist", "targetPosition": [10, 100, 10]}]}}')
receive()
for i in range(3):
    send(1, json.dumps({"targets": [{"effector": 0, "targetPosition": [10 + i, 100, 10]}]}).encode())
    receive()
send(8, b"\x03\xe8")
receive()
