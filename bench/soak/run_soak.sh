#!/bin/sh
# run_soak.sh SERVER_BIN SOAK_BIN [CLIENTS [SECONDS]]
# Soaks a real armature-server (started by bench/load/with_server.sh, which
# also checks it exits 0 on SIGTERM) with CLIENTS clients (default 8) for
# SECONDS (default 10): the ctest runs the defaults, `make soak` 50 for 600.
# Fails on any soak error.
set -eu
here=$(dirname "$0")
exec sh "$here/../load/with_server.sh" "$1" --log-level warn -- \
  "$2" --server 127.0.0.1:@PORT@ --http-port @HTTP@ --clients "${3:-8}" --seconds "${4:-10}" --server-pid @PID@
