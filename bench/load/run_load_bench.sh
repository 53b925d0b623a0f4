#!/bin/sh
# `make bench`'s load part: armature-load against a real armature-server
# (default flags but for --max-streams-per-client) on loopback.
#   1. EvaluateClip, one pose of the CMU clip (the demo walk without
#      ../shared/data), closed loop at concurrency 1, 8, 32, 128, against the
#      health check in the same run (SECONDS_PER_POINT per side, in 5 alternating rounds);
#   2. N StreamClip streams at 60 fps, N = 100, 500, 1000 (SECONDS_PER_POINT measured).
# SECONDS_PER_POINT defaults to 5; CONCURRENCY and STREAMS override the points.
set -eu
server_bin=$1
load_bin=$2
here=$(dirname "$0")
seconds=${SECONDS_PER_POINT:-5}
cmu="$here/../../../shared/data/bvh/cmu_01_01.bvh"
if [ -f "$cmu" ]; then
  clip_flags="--import-bvh $cmu --clip load_cmu"
else
  echo "armature-load: $cmu not present, loading the demo walk instead"
  clip_flags="--clip demo_walk"
fi
echo "== armature-load: closed loop, EvaluateClip (one pose) vs grpc.health.v1.Health/Check"
# shellcheck disable=SC2086
sh "$here/with_server.sh" "$server_bin" -- "$load_bin" --target 127.0.0.1:@PORT@ $clip_flags --rpc evaluate \
  --concurrency "${CONCURRENCY:-1,8,32,128}" --seconds "$seconds" --rounds 5 --server-pid @PID@
echo "== armature-load: StreamClip streams at 60 fps"
# shellcheck disable=SC2086
sh "$here/with_server.sh" "$server_bin" --max-streams-per-client 5000 -- "$load_bin" --target 127.0.0.1:@PORT@ \
  $clip_flags --streams "${STREAMS:-100,500,1000}" --fps 60 --seconds "$seconds" --server-pid @PID@
