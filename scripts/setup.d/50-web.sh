#!/usr/bin/env bash
# Web tooling for the viewer (esbuild, three.js) and its tests
# (playwright-core, swagger-parser): `npm ci` in web/ from the committed
# package-lock.json, from the npm registry only. Skipped when node_modules
# already matches the lock file. $1: "test" or "" (both need the bundler).
set -euo pipefail
cd "$(dirname "$0")/../../web"

if ! command -v npm >/dev/null 2>&1; then
  echo "setup: installing nodejs and npm"
  sudo=""
  [[ $(id -u) -ne 0 ]] && sudo="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends nodejs npm
fi

stamp=node_modules/.armature-lock.sha256
want=$(sha256sum package-lock.json | cut -d' ' -f1)
if [[ -f "$stamp" && "$(cat "$stamp")" == "$want" ]]; then
  exit 0
fi
echo "setup: npm ci in web/"
# swagger-ui-dist (the /docs page) depends on @scarf/scarf, whose install script would send
# telemetry: off here and in package.json's scarfSettings.
SCARF_ANALYTICS=false npm ci --no-audit --no-fund
echo "$want" > "$stamp"
