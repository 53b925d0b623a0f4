#!/usr/bin/env bash
# Test mode only: the node packages of the gRPC-Web client test
# (tests/clients/grpc_web: connect-web, connect-node, protobuf-es and its protoc
# plugin) and of the TypeScript client (clients/typescript: the same, and
# typescript), and s3rver (tests/store: the --store tests' S3 server), `npm ci` in each
# from its committed package-lock.json. A folder
# is skipped when its node_modules already matches its lock file.
set -euo pipefail
[[ "${1:-}" == "test" ]] || exit 0
root="$(cd "$(dirname "$0")/../.." && pwd)"
if ! command -v npm > /dev/null; then
  echo "setup: npm not found; the gRPC-Web and TypeScript client tests will fail until node and npm are installed"
  exit 0
fi
for dir in tests/clients/grpc_web clients/typescript tests/store; do
  cd "$root/$dir"
  stamp=node_modules/.armature-lock.sha256
  want=$(sha256sum package-lock.json | cut -d' ' -f1)
  if [[ -f "$stamp" && "$(cat "$stamp")" == "$want" ]]; then
    continue
  fi
  echo "setup: npm ci in $dir"
  npm ci --no-audit --no-fund --loglevel=error
  echo "$want" > "$stamp"
done
