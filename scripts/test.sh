#!/usr/bin/env bash
# The README's second command (and CI's): makes sure dependencies are there, builds, and runs
# the whole test suite — unit tests, CLI tests, export validation (Khronos glTF validator,
# Assimp), API and browser tests — in the Release build, then the C++ tests again in a sanitizer
# build (ASan + LSan + UBSan, clang, build-asan/, scripts/sanitize.sh; docs/reliability.md
# "Sanitizers"), then every fuzzer for a short time (scripts/fuzz.sh, CALIPER_FUZZ_SECONDS each,
# default 15). CALIPER_SKIP_SANITIZE=1 leaves the sanitizer and fuzzing parts out (local runs only:
# CI runs them).
# Heavy optional check: CALIPER_BLENDER=1 also installs Blender (~750 MB) and imports exported
# avatars into it (tests/e2e/check-glb.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
# Each phase says how long it took (CI has a time budget: docs/reliability.md "CI time").
timed() {
  local start=$SECONDS
  "$@"
  echo "[caliper] $* took $((SECONDS - start)) s"
}
timed bash scripts/install-deps.sh
timed bash scripts/build.sh
# install-deps.sh has installed every external checker: one that is missing now is a failure,
# not a skipped test.
export CALIPER_REQUIRE_TOOLS=1
(cd build && timed ctest --output-on-failure -j "$(nproc)" --timeout 600)
if [ "${CALIPER_SKIP_SANITIZE:-0}" != "1" ]; then
  timed bash scripts/sanitize.sh --build-only
  timed bash scripts/sanitize.sh
  timed bash scripts/fuzz.sh --seconds "${CALIPER_FUZZ_SECONDS:-15}"
else
  echo "[caliper] CALIPER_SKIP_SANITIZE=1: the sanitizer build and the fuzzers were not run"
fi
if [ "${CALIPER_BLENDER:-0}" = "1" ]; then
  if ! command -v blender >/dev/null; then
    SUDO=""; [ "$(id -u)" = "0" ] || SUDO="sudo"
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends blender python3-numpy
  fi
  tmp="$(mktemp -d)"
  bash tests/e2e/export-engine-avatars.sh build/bin/caliper "$tmp" >/dev/null
  shapes="$(build/bin/caliper model info mannequin --sex female --json 2>/dev/null | node -e 'let s="";process.stdin.on("data",d=>s+=d).on("end",()=>console.log(JSON.parse(s).shape_directions))')"
  bash tests/e2e/check-glb.sh "$tmp/female.glb" "$tmp/male.glb" "$tmp/female.fbx" "$tmp/male.fbx" \
    --shape-keys="$shapes" "$tmp/female-morphs.fbx" "$tmp/female-morphs.glb"
  rm -rf "$tmp"
fi
