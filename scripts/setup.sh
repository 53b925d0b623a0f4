#!/usr/bin/env bash
# Installs the Debian packages Armature needs that are missing. Idempotent.
#   scripts/setup.sh        build and run
#   scripts/setup.sh test   also what the tests use (browser, Python, KDL)
#   scripts/setup.sh bench  also the benchmarks' peers
# SETUP_LIST=1 only prints the packages of that mode (tests/docs/readme_python_install.py).
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(
  build-essential cmake pkg-config ccache
  libgrpc++-dev protobuf-compiler-grpc libprotobuf-dev protobuf-compiler
  libeigen3-dev libspdlog-dev nlohmann-json3-dev libcpp-httplib-dev libtinygltf-dev
  libcli11-dev libgtest-dev libbenchmark-dev liborocos-kdl-dev libssl-dev
  # FBX import (engine/src/io/fbx): libassimp-dev builds it, libassimp5 runs it.
  libassimp-dev libassimp5
  # The --store s3:// client: libcurl's CURLOPT_AWS_SIGV4 (curl >= 7.75) signs every request
  libcurl4-openssl-dev
  # The Python client (clients/python) as the README installs it: Debian's Python sees these,
  # and pip installs it offline into a venv with --system-site-packages.
  python3 python3-grpcio python3-protobuf python3-numpy python3-venv python3-pip python3-setuptools
  python3-wheel
)
if [[ "${1:-}" == "test" ]]; then
  packages+=(python3-scipy)
  # Further test-only packages are listed in scripts/test-packages.txt (one per line).
  if [[ -f scripts/test-packages.txt ]]; then
    while read -r p; do [[ -n "$p" && "$p" != \#* ]] && packages+=("$p"); done < scripts/test-packages.txt
  fi
fi

if [[ "${SETUP_LIST:-}" == 1 ]]; then
  printf '%s\n' "${packages[@]}"
  exit 0
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  sudo=""
  [[ $(id -u) -ne 0 ]] && sudo="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# Extra setup steps contributed by parts of the project (web tooling, …).
for step in scripts/setup.d/*.sh; do
  [[ -e "$step" ]] || continue
  bash "$step" "${1:-}"
done
