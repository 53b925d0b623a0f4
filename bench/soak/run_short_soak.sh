#!/bin/sh
# Starts a real armature-server on free loopback ports in a temporary data
# dir, soaks it for 10 s with 8 clients, stops it with SIGTERM and checks
# it exits 0. Fails on any soak error.
set -eu
server_bin=$1
soak_bin=$2
dir=$(mktemp -d)
pid=
cleanup() {
  [ -n "$pid" ] && kill -9 "$pid" 2>/dev/null || true
  rm -rf "$dir"
}
trap cleanup EXIT
"$server_bin" --host 127.0.0.1 --grpc-port 0 --http-port 0 --data-dir "$dir/data" \
  --port-file "$dir/ports.json" --log-level warn >"$dir/server.log" 2>&1 &
pid=$!
i=0
port=
while [ -z "$port" ]; do  # up to 60 s for the port file
  i=$((i + 1))
  if [ $i -gt 600 ] || ! kill -0 "$pid" 2>/dev/null; then
    echo "armature-server did not start:"; cat "$dir/server.log"; exit 1
  fi
  sleep 0.1
  port=$(sed -n 's/.*"grpc": *\([0-9]*\).*/\1/p' "$dir/ports.json" 2>/dev/null || true)
done
status=0
"$soak_bin" --server "127.0.0.1:$port" --clients 8 --seconds 10 --server-pid "$pid" || status=$?
kill -TERM "$pid"
i=0
while kill -0 "$pid" 2>/dev/null; do
  i=$((i + 1))
  if [ $i -gt 300 ]; then echo "armature-server did not exit within 30 s of SIGTERM"; exit 1; fi
  sleep 0.1
done
wait "$pid" || { echo "armature-server exited non-zero after SIGTERM"; cat "$dir/server.log"; exit 1; }
pid=
[ $status -eq 0 ] || { echo "soak failed"; tail -50 "$dir/server.log"; }
exit $status
