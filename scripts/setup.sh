#!/usr/bin/env bash
# Installs rayscout's Debian packages (only those missing), then configures and builds.
# Usage: scripts/setup.sh [build-dir [extra cmake args...]]   (default build-dir: build)
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(build-essential cmake libtbb-dev libembree-dev libassimp-dev
          nlohmann-json3-dev libcli11-dev libfmt-dev libstb-dev libopenexr-dev
          libgtest-dev libgmock-dev libbenchmark-dev python3-matplotlib pkgconf)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  sudo_cmd=(); [ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

build_dir=${1:-build}
shift || true
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release "$@" > "$build_dir.configure.log" 2>&1 ||
  { cat "$build_dir.configure.log"; exit 1; }
cmake --build "$build_dir" -j"$(nproc)"
