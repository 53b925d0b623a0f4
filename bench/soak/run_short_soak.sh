#!/bin/sh
# Soaks a real armature-server (started by bench/load/with_server.sh, which
# also checks it exits 0 on SIGTERM) for 10 s with 8 clients. Fails on any
# soak error.
set -eu
here=$(dirname "$0")
exec sh "$here/../load/with_server.sh" "$1" --log-level warn -- \
  "$2" --server 127.0.0.1:@PORT@ --clients 8 --seconds 10 --server-pid @PID@
