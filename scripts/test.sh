#!/usr/bin/env bash
# The README's second command (and CI's): makes sure dependencies are there, builds, and runs
# the whole test suite — unit tests, CLI tests, export validation (Khronos glTF validator,
# Assimp), API and browser tests.
# Heavy optional check: CALIPER_BLENDER=1 also installs Blender (~750 MB) and imports exported
# avatars into it (tests/e2e/check-glb.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
(cd build && ctest --output-on-failure -j "$(nproc)" --timeout 600)
if [ "${CALIPER_BLENDER:-0}" = "1" ]; then
  if ! command -v blender >/dev/null; then
    SUDO=""; [ "$(id -u)" = "0" ] || SUDO="sudo"
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends blender python3-numpy
  fi
  tmp="$(mktemp -d)"
  build/bin/caliper avatar --sex female --height 165 --weight 62 -o "$tmp/female.glb" -q
  build/bin/caliper avatar --sex male --height 180 --weight 85 --arm-span 186 --inseam 84 -o "$tmp/male.glb" -q
  bash tests/e2e/check-glb.sh "$tmp/female.glb" "$tmp/male.glb"
  rm -rf "$tmp"
fi
