#!/usr/bin/env bash
# Libraries the benchmarks (make bench) compare against: assimp's BVH import
# (bench/engine/bvh_assimp_bench.cc). libassimp-dev is also the FBX importer's
# (scripts/setup.sh installs it for every mode); the list stays for older setups.
# Without them the comparison benchmarks are left out (bench/CMakeLists.txt).
set -euo pipefail
# Only for `make bench` (scripts/setup.sh bench).
[[ "${1:-}" == "bench" ]] || exit 0
peers=(libassimp-dev)
missing=()
for p in "${peers[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
((${#missing[@]})) || exit 0
echo "setup: installing benchmark peers ${missing[*]}"
sudo=""
[[ $(id -u) -ne 0 ]] && sudo="sudo"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
