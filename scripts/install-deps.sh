#!/usr/bin/env bash
# Installs every system and npm dependency Caliper needs on Debian bookworm.
# Idempotent and non-interactive; safe to run again. Needs root (or sudo).
set -euo pipefail
cd "$(dirname "$0")/.."

APT_PACKAGES=(
  build-essential cmake ninja-build pkg-config git
  libeigen3-dev nlohmann-json3-dev libtinygltf-dev libcpp-httplib-dev libcli11-dev
  libsqlite3-dev libzip-dev zlib1g-dev libssl-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libassimp-dev assimp-utils
  clang libclang-rt-14-dev
  nodejs npm chromium
  python3-numpy python3-dev pybind11-dev python3-pybind11 python3-pytest
  python3-pip python3-setuptools python3-wheel python3-venv python3-distributed
)

SUDO=""
if [ "$(id -u)" != "0" ]; then SUDO="sudo"; fi

missing=()
for p in "${APT_PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# node/npm may come from elsewhere (e.g. NodeSource): accept any working node >= 18.
if command -v node >/dev/null && command -v npm >/dev/null; then
  filtered=()
  for p in "${missing[@]}"; do [[ "$p" == nodejs || "$p" == npm ]] || filtered+=("$p"); done
  missing=("${filtered[@]+"${filtered[@]}"}")
fi
if [ "${#missing[@]}" -gt 0 ]; then
  echo "[caliper] installing Debian packages: ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -q
  $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
else
  echo "[caliper] Debian packages already installed"
fi

# npm packages (the glTF validator, the web front end's libraries): only from the npm registry.
for dir in tools web; do
  if [ -f "$dir/package.json" ]; then
    if [ -d "$dir/node_modules" ] && [ "$dir/node_modules/.package-lock.json" -nt "$dir/package-lock.json" ]; then
      echo "[caliper] npm packages in $dir/ already installed"
    else
      echo "[caliper] installing npm packages in $dir/"
      (cd "$dir" && npm ci --no-audit --no-fund --loglevel=error)
    fi
  fi
done
