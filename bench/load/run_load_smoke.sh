#!/bin/sh
# The ctest smoke of armature-load: it refuses targets off this machine, and
# against a real server (demo assets) it reports sane numbers for a short
# closed loop at concurrency 2, for a few 60 fps streams and for two 30 fps crowds.
set -eu
server_bin=$1
load_bin=$2
here=$(dirname "$0")
fail() { echo "FAIL: $*"; exit 1; }

for t in 10.0.0.1:50051 example.com:50051 127.0.0.1.example.com:50051 128.0.0.1:50051 "[::2]:50051" 127.0.0.1; do
  status=0
  out=$("$load_bin" --target "$t" --concurrency 2 --seconds 1 2>&1) || status=$?
  [ $status -eq 2 ] || fail "target $t: exit $status, expected 2 (refused)"
  echo "$out" | grep -q "refused" || fail "target $t: no refusal message: $out"
done
echo "non-loopback targets refused"

# field NAME of a RESULT line
field() { echo "$1" | grep '^RESULT' | tr ' ' '\n' | sed -n "s/^$2=//p"; }
# true when a <= x <= b (decimals)
within() { awk -v x="$1" -v a="$2" -v b="$3" 'BEGIN { exit !(x != "" && x + 0 >= a && x + 0 <= b) }'; }

out=$(sh "$here/with_server.sh" "$server_bin" --log-level warn -- \
  "$load_bin" --target 127.0.0.1:@PORT@ --clip demo_walk --rpc evaluate=3,skin=1,stream=1 --concurrency 2 \
  --seconds 2 --rounds 1) || fail "unary run: $out"
echo "$out"
within "$(field "$out" calls_per_s)" 20 10000000 || fail "mix calls/s not sane"
within "$(field "$out" health_calls_per_s)" 50 10000000 || fail "health calls/s not sane"
within "$(field "$out" ratio)" 0.001 2 || fail "ratio not sane"
[ "$(field "$out" errors)" = 0 ] || fail "calls failed"
for rpc in Health/Check PoseService/EvaluateClip MeshService/SkinMesh PoseService/StreamClip; do
  echo "$out" | grep -q "$rpc" || fail "no row for $rpc"
done

out=$(sh "$here/with_server.sh" "$server_bin" --log-level warn -- \
  "$load_bin" --target 127.0.0.1:@PORT@ --clip demo_walk --streams 4 --fps 60 --seconds 2 --warmup 0.5 \
  --server-pid @PID@) || fail "stream run: $out"
echo "$out"
# 4 streams × 2 s × 60 fps = 480 frames due; the mean interval is 1/60 s.
within "$(field "$out" interval_mean_ms)" 15 18.5 || fail "mean interval not near 16.67 ms"
within "$(field "$out" frames)" 400 520 || fail "frames received not near the 480 due"
[ "$(field "$out" lost)" = 0 ] || fail "frames lost"
within "$(field "$out" server_cpu_pct)" 0 400 || fail "server CPU not read (-1: /proc/<pid>/stat unreadable)"

out=$(sh "$here/with_server.sh" "$server_bin" --log-level warn -- \
  "$load_bin" --target 127.0.0.1:@PORT@ --clip demo_walk --crowds 2x50 --fps 30 --seconds 2 --warmup 0.5 \
  --server-pid @PID@) || fail "crowd run: $out"
echo "$out"
# 2 crowds × 2 s × 30 fps = 120 frames due, each tick near 1/30 s; 50 characters fit any budget.
within "$(field "$out" interval_ratio)" 0.9 1.1 || fail "mean tick interval not near 33.3 ms"
within "$(field "$out" frames)" 100 130 || fail "crowd frames not near the 120 due"
within "$(field "$out" updated_per_tick)" 90 100 || fail "not every character updated each tick"
within "$(field "$out" wire_bytes_per_joint)" 1 8 || fail "over 8 bytes a joint"
[ "$(field "$out" failed)" = 0 ] || fail "a crowd failed"
echo PASS
