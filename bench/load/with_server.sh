#!/bin/sh
# with_server.sh SERVER_BIN [server flags...] -- COMMAND [args...]
# Starts a real armature-server on free loopback ports in a temporary data
# dir, runs COMMAND with every @PORT@ replaced by its gRPC port, @HTTP@ by its
# HTTP port and @PID@ by its pid, then stops it with SIGTERM and fails unless it exits 0 within 30 s.
# Exits with COMMAND's status. The load runs and the soak (bench/soak) use it.
set -eu
server_bin=$1
shift
dir=$(mktemp -d)
pid=
cleanup() {
  [ -n "$pid" ] && kill -9 "$pid" 2>/dev/null || true
  rm -rf "$dir"
}
trap cleanup EXIT
server_flags=
while [ $# -gt 0 ] && [ "$1" != "--" ]; do server_flags="$server_flags $1"; shift; done
[ $# -gt 0 ] && shift
# shellcheck disable=SC2086
"$server_bin" --host 127.0.0.1 --grpc-port 0 --http-port 0 --data-dir "$dir/data" \
  --port-file "$dir/ports.json" $server_flags >"$dir/server.log" 2>&1 &
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
http=$(sed -n 's/.*"http": *\([0-9]*\).*/\1/p' "$dir/ports.json")
cmd=
for a in "$@"; do
  a=$(printf '%s' "$a" | sed "s/@PORT@/$port/g; s/@HTTP@/$http/g; s/@PID@/$pid/g")
  cmd="$cmd '$a'"
done
status=0
eval "$cmd" || status=$?
kill -TERM "$pid"
i=0
while kill -0 "$pid" 2>/dev/null; do
  i=$((i + 1))
  if [ $i -gt 300 ]; then echo "armature-server did not exit within 30 s of SIGTERM"; exit 1; fi
  sleep 0.1
done
wait "$pid" || { echo "armature-server exited non-zero after SIGTERM"; cat "$dir/server.log"; exit 1; }
pid=
[ $status -eq 0 ] || { echo "command failed ($status); server log tail:"; tail -20 "$dir/server.log"; }
exit $status
