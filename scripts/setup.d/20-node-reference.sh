#!/usr/bin/env bash
# Test mode only: installs three.js (pinned in tests/reference/package-lock.json)
# for the glTF skinning reference the engine tests run with node. Without
# node/npm the tests that need it skip with a message.
set -euo pipefail
[[ "${1:-}" == "test" ]] || exit 0
cd "$(dirname "$0")/../../tests/reference"
if ! command -v node > /dev/null || ! command -v npm > /dev/null; then
  echo "setup: node/npm not found; the three.js glTF reference tests will be skipped"
  exit 0
fi
# Already installed at the pinned version?
if node -e 'const w = require("./package.json").dependencies.three,
                 h = require("./node_modules/three/package.json").version;
           process.exit(w === h ? 0 : 1)' 2> /dev/null; then
  exit 0
fi
echo "setup: npm ci in tests/reference (three.js for the glTF reference)"
npm ci --no-audit --no-fund --loglevel=error
