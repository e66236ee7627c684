#!/usr/bin/env bash
# The installed program is relocatable: install to a temporary prefix, MOVE the tree, and run it
# there (it must find its models and web page from its own path, not from the source or build
# tree), then build a small C++ program against the moved prefix with find_package(caliper).
# Usage: install_test.sh BUILD_DIR
set -u
BUILD="$1"
SRC="$(cd "$(dirname "$0")/../.." && pwd)"
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT
passed=0; failed=0
check() {  # check "description" command...
  local what="$1"; shift
  if "$@" >"$TMP/out" 2>&1; then passed=$((passed + 1)); else
    failed=$((failed + 1)); echo "FAIL: $what"; sed 's/^/    /' "$TMP/out" | head -20; fi
}

check "cmake --install" cmake --install "$BUILD" --prefix "$TMP/first"
mv "$TMP/first" "$TMP/moved"
P="$TMP/moved"
unset CALIPER_MODELS_DIR
check "the moved tree has the program and the models" test -x "$P/bin/caliper" -a -f "$P/share/caliper/models/mannequin-female.npz"
check "it finds its models in the moved tree" bash -c "'$P/bin/caliper' model list | grep -qF 'models in $P/share/caliper/models'"
check "caliper avatar runs from the moved tree" "$P/bin/caliper" avatar --height 165 --weight 62 -o "$TMP/a.glb" -q
check "and wrote the avatar" test -s "$TMP/a.glb"
check "--models overrides the folder" bash -c "'$P/bin/caliper' --models '$SRC/models' model list | grep -qF 'models in $SRC/models'"
check "--models refuses a missing folder" bash -c "! '$P/bin/caliper' --models '$TMP/none' model list"
if [ -d "$SRC/web/dist" ]; then
  check "the web page is installed" test -f "$P/share/caliper/web/index.html"
  check "serve's default web root is the moved tree's" bash -c "'$P/bin/caliper' serve --help | grep -qF '$P/share/caliper/web'"
fi
check "no installed file names the build or the first prefix" bash -c "! grep -rlF '$TMP/first' '$P'"

# A C++ program built against the moved prefix.
if cmake -S "$SRC/tests/install/consumer" -B "$TMP/consumer" -DCMAKE_PREFIX_PATH="$P" -DCMAKE_BUILD_TYPE=Release >"$TMP/out" 2>&1 &&
   cmake --build "$TMP/consumer" >>"$TMP/out" 2>&1; then
  passed=$((passed + 1))
  check "the consumer runs" bash -c "'$TMP/consumer/consumer' > '$TMP/stature.txt'"
  check "and builds a 165 cm woman" awk '{ exit !($1 > 164.9 && $1 < 165.1) }' "$TMP/stature.txt"
else
  failed=$((failed + 1)); echo "FAIL: find_package(caliper) consumer did not build"; tail -30 "$TMP/out"
fi
echo "$passed passed, $failed failed"
[ "$failed" = 0 ]
