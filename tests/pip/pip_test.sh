#!/usr/bin/env bash
# `pip install .` works from the source tree with Debian's pip and no network (docs/python.md
# "Installing"): into a fresh venv made with --system-site-packages (Debian's NumPy, setuptools
# and wheel), --no-build-isolation --no-index, reusing BUILD_DIR's module
# (CALIPER_CMAKE_BUILD_DIR), then imported from outside the source tree: the package must hold
# the module and the built-in models and find them there.
# Usage: pip_test.sh PYTHON BUILD_DIR. Skipped (77) without pip/venv unless CALIPER_REQUIRE_TOOLS=1.
set -u
PYTHON="$1"
BUILD="$2"
SRC="$(cd "$(dirname "$0")/../.." && pwd)"
# (pip and setuptools are checked apart: importing both in one process trips setuptools' distutils hack)
if ! { "$PYTHON" -m pip --version && "$PYTHON" -c "import venv, setuptools, wheel"; } >/dev/null 2>&1; then
  echo "pip: pip, venv, setuptools or wheel missing for $PYTHON (Debian: python3-pip python3-venv python3-setuptools python3-wheel)"
  if [ "${CALIPER_REQUIRE_TOOLS:-0}" = "1" ]; then exit 1; fi
  exit 77
fi
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT
passed=0; failed=0
check() {  # check "description" command...
  local what="$1"; shift
  if "$@" >"$TMP/out" 2>&1; then passed=$((passed + 1)); else
    failed=$((failed + 1)); echo "FAIL: $what"; sed 's/^/    /' "$TMP/out" | tail -30; fi
}
check "a venv with the system's packages" "$PYTHON" -m venv --system-site-packages "$TMP/venv"
VPY="$TMP/venv/bin/python"
check "pip install . without network" env CALIPER_CMAKE_BUILD_DIR="$BUILD" PIP_NO_INDEX=1 PIP_DISABLE_PIP_VERSION_CHECK=1 \
  "$VPY" -m pip install --no-build-isolation --no-index "$SRC"
# Run from an empty folder with nothing on PYTHONPATH and no models folder in the environment: only
# the installed package can answer.
mkdir -p "$TMP/elsewhere"
check "the installed package imports, builds an avatar from its own models and saves it" \
  env -u PYTHONPATH -u CALIPER_MODELS_DIR -C "$TMP/elsewhere" "$VPY" -c '
import pathlib, sys, caliper
package = pathlib.Path(caliper.__file__).resolve().parent
assert str(package).startswith(sys.prefix), f"imported {package}, not the venv copy"
assert sorted(p.name for p in (package / "models").glob("*.npz")) == ["mannequin-female.npz", "mannequin-male.npz", "mannequin-neutral.npz"]
a = caliper.build_avatar(sex="male", stature_cm=180, weight_kg=80)
assert abs(a.achieved["stature"] - 1.80) < 0.005, a.achieved["stature"]
a.save("me.glb")
assert pathlib.Path("me.glb").stat().st_size > 100000
print(caliper.__version__, package)
'
check "pip knows the package's version" bash -c "'$VPY' -m pip show caliper | grep -qx 'Version: $(sed -n 's/^project(caliper VERSION \([0-9.]*\).*/\1/p' "$SRC/CMakeLists.txt")'"
check "and uninstalls it" "$VPY" -m pip uninstall -y caliper
check "leaving nothing behind" bash -c "! ls '$TMP'/venv/lib/python3*/site-packages/caliper 2>/dev/null"
echo "pip: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
