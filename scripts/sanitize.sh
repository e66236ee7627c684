#!/usr/bin/env bash
# The sanitizer part of the test suite (scripts/test.sh runs it after the Release part; see
# docs/reliability.md, "Sanitizers"). Builds Caliper with -DCALIPER_SANITIZE=ON (AddressSanitizer
# with LeakSanitizer, UndefinedBehaviorSanitizer, no recovery) into build-asan/ and runs the C++
# tests under it: unit tests, API tests and the CLI test (the CLI binary is the sanitized one).
# The two browser tests (desktop_e2e, capture_e2e) are left out: they drive the same server code
# through Chromium, which would only multiply their long software-rendered run time by the
# sanitizer's slowdown; the API tests exercise those routes in-process.
# The same build holds the fuzzers (fuzz/, clang's libFuzzer), and the suite replays their corpora
# (fuzz_*_replay tests); scripts/fuzz.sh runs them.
# Usage: scripts/sanitize.sh [--build-only | extra ctest args]
set -euo pipefail
cd "$(dirname "$0")/.."
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
# clang-14 (install-deps.sh): its libFuzzer lets one instrumented library serve both this suite and
# the fuzzers (CALIPER_FUZZ). -O1: the level clang's AddressSanitizer manual suggests for usable
# speed, and it compiles faster than -O2 (docs/reliability.md "Sanitizers" has the times); debug
# information is line tables only, and it is a unity build (both: CMakeLists.txt). A build-asan/
# from before (g++, no fuzzers) is replaced.
if [ -f build-asan/CMakeCache.txt ] && ! grep -q '^CALIPER_FUZZ:BOOL=ON' build-asan/CMakeCache.txt; then
  rm -rf build-asan
fi
if [ ! -f build-asan/CMakeCache.txt ]; then
  CC=clang-14 CXX=clang++-14 cmake -S . -B build-asan "${generator[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -DNDEBUG" -DCALIPER_FUZZ=ON -DCALIPER_BUILD_BENCHMARKS=OFF -DCMAKE_UNITY_BUILD=ON
fi
cmake --build build-asan -j "$(nproc)"
[ "${1:-}" = "--build-only" ] && exit 0

source scripts/sanitizer-env.sh
# The default run thins the slowest test's sample (MannequinGenerator.ReproducesAnsurSubjects,
# ~20 bodies instead of ~750: a body costs ~1.7 s under the sanitizers). CALIPER_SANITIZE_FULL=1
# restores the Release sample; that test then needs about two hours at -O1 (estimated), so
# it runs on its own, outside ctest's per-test timeout. The three browser tests of the pages
# run in the Release suite only: what they drive is JavaScript, and the server's side of each is
# covered here by the API tests.
exclude='^(desktop_e2e|capture_e2e|mirror_e2e)$'
if [ "${CALIPER_SANITIZE_FULL:-0}" = "1" ]; then
  export CALIPER_SANITIZE_FULL
  exclude='^(desktop_e2e|capture_e2e|mirror_e2e|MannequinGenerator\.ReproducesAnsurSubjects)$'
fi
(cd build-asan && ctest --output-on-failure -j "$(nproc)" --timeout 600 -E "$exclude" "$@")
if [ "${CALIPER_SANITIZE_FULL:-0}" = "1" ]; then
  build-asan/tests/caliper_tests --gtest_filter=MannequinGenerator.ReproducesAnsurSubjects
fi
