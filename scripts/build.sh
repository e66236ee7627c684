#!/usr/bin/env bash
# Configures and builds Caliper (Release) into build/. Usage: scripts/build.sh [extra cmake args]
# A new build/ is a unity build (CMakeLists.txt, "Unity builds"): about half the time from scratch.
# For quick rebuilds while editing one file, configure your own tree without it.
set -euo pipefail
cd "$(dirname "$0")/.."
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
if [ ! -f build/CMakeCache.txt ]; then
  cmake -S . -B build "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DCMAKE_UNITY_BUILD=ON "$@"
fi
cmake --build build -j "$(nproc)"
# The desktop tool's page: web/src plus three.js from npm, copied into web/dist (served by caliper serve).
if [ -d web/node_modules ]; then node web/build.mjs; fi
