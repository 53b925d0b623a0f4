#!/usr/bin/env bash
# The container image end to end, with podman: builds deploy/Dockerfile (a
# real multi-stage build), runs it, and from the host checks gRPC health,
# an EvaluateClip call, a REST call, /metrics, the image's own HEALTHCHECK,
# the non-root user, that the data volume survives a new container, and that
# SIGTERM stops it within 10 s with exit code 0. Then it validates the
# Kubernetes manifests and compose.yaml offline.
#
#   deploy/image-test.sh [--cli PATH]     (PATH: a host-built `armature` CLI; default build/bin/armature)
# Environment: JOBS (image build parallelism, default 2), ARMATURE_PODMAN_FLAGS
# (extra `podman run` flags; the default suits a root podman inside a container).
# Prints "SKIP: …" and exits 0 when podman is not installed.
set -euo pipefail
cd "$(dirname "$0")/.."

cli=build/bin/armature
[[ "${1:-}" == "--cli" ]] && cli=$2
if ! command -v podman >/dev/null; then
  echo "SKIP: podman is not installed (apt-get install podman runc debootstrap); the container image was not tested"
  exit 0
fi
[[ -x "$cli" ]] || { echo "image-test: no armature CLI at $cli (cmake --build build --target armature)" >&2; exit 1; }
for tool in curl node npm python3; do
  command -v "$tool" >/dev/null || { echo "image-test: $tool is needed (the checks and the manifest validator use it)" >&2; exit 1; }
done

t0=$(date +%s)
phase_start=$t0
timings=()
phase() {  # records how long the previous phase took
  local now
  now=$(date +%s)
  timings+=("$1: $((now - phase_start)) s")
  phase_start=$now
}

# runc, and ulimits no higher than this process's (podman would otherwise
# raise them, which fails without CAP_SYS_RESOURCE, e.g. inside a container).
run_flags=()
command -v runc >/dev/null && run_flags+=(--runtime runc)
nofile=$(ulimit -Hn); [[ "$nofile" == unlimited || "$nofile" -gt 20000 ]] && nofile=20000
nproc=$(ulimit -Hu); [[ "$nproc" == unlimited || "$nproc" -gt 32768 ]] && nproc=32768
run_flags+=(--ulimit "nofile=$nofile:$nofile" --ulimit "nproc=$nproc:$nproc")
# shellcheck disable=SC2206
[[ -n "${ARMATURE_PODMAN_FLAGS:-}" ]] && run_flags+=(${ARMATURE_PODMAN_FLAGS})

tag=localhost/armature:image-test
name=armature-image-test-$$
volume=armature-image-test-$$
cleanup() {
  podman rm -f "$name" "$name-2" >/dev/null 2>&1 || true
  podman volume rm -f "$volume" >/dev/null 2>&1 || true
}
trap cleanup EXIT
fail() { echo "FAIL: $*" >&2; podman logs "$name" 2>&1 | tail -20 >&2 || true; exit 1; }

# 1. Base images: local Debian 12 images, made with debootstrap if none is there.
build_image=$(deploy/base-image.sh docker.io/library/debian:bookworm)
base_image=$(deploy/base-image.sh docker.io/library/debian:bookworm-slim)
echo "image-test: building on $build_image, running on $base_image"
phase "base images"

# 2. The multi-stage build (docker format, so HEALTHCHECK is kept).
previous=$(podman image inspect --format '{{.Id}}' "$tag" 2>/dev/null || true)
podman build --format docker "${run_flags[@]}" --build-arg BUILD_IMAGE="$build_image" \
  --build-arg BASE_IMAGE="$base_image" --build-arg JOBS="${JOBS:-2}" \
  --build-arg GIT_COMMIT="$(git rev-parse --short=12 HEAD 2>/dev/null || true)" -f deploy/Dockerfile -t "$tag" .
# The build stage (about 900 MB) is not needed once the image is made.
podman image prune -f --filter label=org.armature.stage=build >/dev/null || true
if [[ -n "$previous" && "$previous" != "$(podman image inspect --format '{{.Id}}' "$tag")" ]]; then
  podman rmi "$previous" >/dev/null 2>&1 || true  # the last run's image, now untagged
fi
phase "image build"

# 3. Run it with a named data volume, ports on free host ports.
podman run -d --name "$name" "${run_flags[@]}" -v "$volume:/var/lib/armature/data" \
  -p 127.0.0.1::50051 -p 127.0.0.1::8080 "$tag" >/dev/null
grpc=$(podman port "$name" 50051/tcp | head -n1)
http=$(podman port "$name" 8080/tcp | head -n1)
echo "image-test: gRPC on $grpc, HTTP on $http"
for _ in $(seq 1 120); do
  "$cli" --server "$grpc" --timeout 1 health >/dev/null 2>&1 && break
  sleep 0.5
done
"$cli" --server "$grpc" --timeout 5 health || fail "gRPC health is not SERVING"
echo "ok   gRPC health: SERVING"
phase "start"

pose=$("$cli" --server "$grpc" pose demo_walk --time 0.5 --json) || fail "EvaluateClip failed"
python3 - "$pose" <<'PY' || fail "EvaluateClip answered $pose"
import json, sys
j = json.loads(sys.argv[1])
assert j["clip"] == "demo_walk" and j["space"] == "world", j
assert len(j["joints"]) > 10 and all(len(x["translation"]) == 3 for x in j["joints"]), j
PY
echo "ok   EvaluateClip: a world pose of demo_walk"

# REST: the gateway's GET /v1/clips.
code=$(curl -s -o /tmp/$name.rest -w '%{http_code}' "http://$http/v1/clips")
[[ "$code" == 200 ]] || fail "GET /v1/clips answered HTTP $code: $(cat /tmp/$name.rest)"
grep -q demo_walk /tmp/$name.rest || fail "GET /v1/clips does not list demo_walk: $(cat /tmp/$name.rest)"
echo "ok   REST: GET /v1/clips lists demo_walk"
rm -f /tmp/$name.rest
# Captured first: with pipefail, `curl | grep -q` fails when grep exits early and curl gets SIGPIPE.
metrics=$(curl -s "http://$http/metrics")
grep -q 'armature_rpc_requests_total{method="armature.v1.PoseService/EvaluateClip",code="OK"} 1' <<<"$metrics" \
  || fail "/metrics does not count the EvaluateClip call"
echo "ok   /metrics counts the call"

podman healthcheck run "$name" >/dev/null || fail "the image's HEALTHCHECK failed"
echo "ok   HEALTHCHECK passes"
[[ $(podman exec "$name" id -u) == 10001 ]] || fail "the server does not run as uid 10001"
[[ $(podman exec "$name" cat /proc/1/cmdline | tr '\0' ' ') == /usr/local/bin/armature-server* ]] \
  || fail "armature-server is not PID 1"
echo "ok   runs as uid 10001, armature-server is PID 1"
phase "checks"

# 4. SIGTERM: a clean exit, code 0, within 10 s.
stop_start=$(date +%s.%N)
podman kill --signal TERM "$name" >/dev/null
exit_code=$(timeout 10 podman wait "$name") || fail "no exit within 10 s of SIGTERM"
stop_seconds=$(python3 -c "import time; print(f'{time.time() - $stop_start:.2f}')")
[[ "$exit_code" == 0 ]] || fail "exit code $exit_code after SIGTERM"
log=$(podman logs "$name" 2>&1)
grep -q '"msg":"stopped"' <<<"$log" || fail "no clean shutdown in the log"
echo "ok   SIGTERM: exit 0 after ${stop_seconds} s"

# 5. The data volume outlives the container: a new one serves the same assets, no second seeding.
podman run -d --name "$name-2" "${run_flags[@]}" -v "$volume:/var/lib/armature/data" -p 127.0.0.1::50051 "$tag" >/dev/null
grpc2=$(podman port "$name-2" 50051/tcp | head -n1)
for _ in $(seq 1 120); do "$cli" --server "$grpc2" --timeout 1 health >/dev/null 2>&1 && break; sleep 0.5; done
listing=$("$cli" --server "$grpc2" list)
grep -q "clip     demo_walk" <<<"$listing" || fail "the new container does not serve demo_walk"
log2=$(podman logs "$name-2" 2>&1)
grep -q "seeded demo" <<<"$log2" && fail "the new container seeded the demo again"
echo "ok   the data volume persists across containers"
podman stop -t 10 "$name-2" >/dev/null
phase "shutdown, volume"

# 6. Kubernetes manifests and compose.yaml, offline.
podman run --rm "${run_flags[@]}" -v "$volume:/var/lib/armature/data" "$tag" --help | grep -oE 'ARMATURE_[A-Z_]+' | sort -u > /tmp/$name.env
if [[ ! -d deploy/k8s-validate/node_modules ]]; then
  (cd deploy/k8s-validate && npm ci --no-audit --no-fund --loglevel=error)
fi
node deploy/k8s-validate/validate.mjs --env-names /tmp/$name.env || fail "deploy/k8s or compose.yaml is not valid"
rm -f /tmp/$name.env
phase "manifests"

echo "image-test: $(podman image inspect "$tag" --format '{{.Size}}' | awk '{printf "%.0f MB", $1/1e6}') image"
for t in "${timings[@]}"; do echo "image-test: $t"; done
echo "image-test: passed in $(( $(date +%s) - t0 )) s"
