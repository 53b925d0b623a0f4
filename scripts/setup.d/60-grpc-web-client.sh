#!/usr/bin/env bash
# Test mode only: the gRPC-Web client test's packages (connect-web,
# connect-node, protobuf-es and its protoc plugin), `npm ci` in
# tests/clients/grpc_web from the committed package-lock.json. Skipped when
# node_modules already matches the lock file.
set -euo pipefail
[[ "${1:-}" == "test" ]] || exit 0
cd "$(dirname "$0")/../../tests/clients/grpc_web"
if ! command -v npm > /dev/null; then
  echo "setup: npm not found; the gRPC-Web client test will fail until node and npm are installed"
  exit 0
fi
stamp=node_modules/.armature-lock.sha256
want=$(sha256sum package-lock.json | cut -d' ' -f1)
if [[ -f "$stamp" && "$(cat "$stamp")" == "$want" ]]; then
  exit 0
fi
echo "setup: npm ci in tests/clients/grpc_web (gRPC-Web client test)"
npm ci --no-audit --no-fund --loglevel=error
echo "$want" > "$stamp"
