#!/bin/sh
# Runs one fuzz target: replays tests/fuzz/regressions/<target>/ and the
# seeds once, then fuzzes for <seconds> (0: replay only).
#   run_fuzz.sh <target binary> <seconds> <work dir>
# Crashes, leaks, timeouts (-timeout) and allocations over -malloc_limit_mb
# fail the run; the input is left in <work dir>/<target>/ as crash-*, oom-*, …
# FUZZ_RUNS=N also stops after N inputs (the 10 M campaigns:
# `make fuzz FUZZ_SECONDS=86400 FUZZ_RUNS=10000000`). FUZZ_MAX_LEN (default
# 4096) caps the inputs libFuzzer makes and cuts longer seeds: the bug
# shapes are small files, and whole mocap files run 10x slower.
set -eu
bin=$1
seconds=$2
work=$3
here=$(cd "$(dirname "$0")" && pwd)
target=$(basename "$bin")
case $target in
  engine_bvh_fuzz|engine_bvh_writer_fuzz) format=bvh ;;
  engine_gltf_fuzz|engine_gltf_writer_fuzz) format=gltf ;;
  engine_obj_fuzz) format=obj ;;
  engine_fbx_fuzz) format=fbx ;;
  engine_detect_fuzz|engine_compress_fuzz) format=detect ;;
  server_transcode_fuzz) format=transcode ;;
  server_path_template_fuzz) format=path_template ;;
  server_import_upload_fuzz) format=import_upload ;;
  server_grpc_web_framing_fuzz) format=grpc_web ;;
  server_websocket_framing_fuzz) format=websocket ;;
  *) format=$target ;;
esac
dir=$work/$target
mkdir -p "$dir/corpus" "$dir/seeds"
python3 "$here/make_seeds.py" "$format" "$dir/seeds" "$here/../../../shared/data"
inputs="$dir/seeds"
[ -d "$here/seeds/$target" ] && inputs="$inputs $here/seeds/$target"
[ -d "$here/regressions/$target" ] && inputs="$inputs $here/regressions/$target"
dict=
[ -f "$here/dict/$format.dict" ] && dict="-dict=$here/dict/$format.dict"
limits="-malloc_limit_mb=512 -rss_limit_mb=1024 -timeout=5 -artifact_prefix=$dir/"
echo "== $target: replaying $inputs"
# shellcheck disable=SC2086
"$bin" $limits -runs=0 $inputs
[ "$seconds" -gt 0 ] || exit 0
echo "== $target: fuzzing for $seconds s${FUZZ_RUNS:+ or $FUZZ_RUNS runs}"
runs=
[ -n "${FUZZ_RUNS:-}" ] && runs="-runs=$FUZZ_RUNS"
# The long run stores no allocation stacks and keeps a 64 MB quarantine:
# ASan's stack depot otherwise grew without end on Debian's libraries built
# without frame pointers (README.md, "Limits"). The replay above keeps them;
# an ASAN_OPTIONS of the caller's own still wins.
fuzz_asan="quarantine_size_mb=64:malloc_context_size=0${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
# assimp 5.2's FBX parser leaks its parse tree (a few hundred bytes) when it
# throws part-way through a malformed file (seen with an ASCII header before
# binary records, 2026-11-29); the leak is inside libassimp, where no
# suppression can match without allocation stacks, so the FBX target's long
# run does not count leaks. Its replay still does.
if [ "$target" = engine_fbx_fuzz ]; then fuzz_asan="detect_leaks=0:$fuzz_asan"; fi
# shellcheck disable=SC2086
ASAN_OPTIONS=$fuzz_asan "$bin" $limits $dict $runs -max_len="${FUZZ_MAX_LEN:-4096}" -max_total_time="$seconds" -print_final_stats=1 \
  "$dir/corpus" $inputs
