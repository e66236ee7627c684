#!/usr/bin/env bash
# The README's first command: installs every dependency (Debian + npm), builds Caliper, installs
# it for you (the `caliper` command, its models and the desktop tool's page) under
# $CALIPER_PREFIX (default ~/.local) and the Python package `caliper` for your user, and runs the
# main job with the installed command — an avatar from measurements on the built-in body model.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
PREFIX="${CALIPER_PREFIX:-$HOME/.local}"
echo
echo "[caliper] installing into $PREFIX (bin/caliper, share/caliper/, include/, lib/; CALIPER_PREFIX=… picks another folder)"
cmake --install build --prefix "$PREFIX" >/dev/null
# The Python package (docs/python.md), for Debian's python3 and your user, from the module just
# built (no second compile, no network).
if ls build/python/caliper/_caliper*.so >/dev/null 2>&1; then
  echo "[caliper] installing the Python package caliper for your user (import caliper; docs/python.md)"
  CALIPER_CMAKE_BUILD_DIR=build /usr/bin/python3 -m pip install --quiet --user --no-build-isolation --no-index \
    --break-system-packages --root-user-action=ignore --disable-pip-version-check .
fi
CALIPER="$PREFIX/bin/caliper"
mkdir -p out
echo
echo "[caliper] building an avatar on the built-in body (female, 165 cm, 62 kg, arm span 167 cm, inseam 78 cm, hip width 36 cm)"
"$CALIPER" avatar --sex female --height 165 --weight 62 --arm-span 167 --inseam 78 --hip-width 36 \
  -o out/avatar.glb --report out/avatar-report.json
"$CALIPER" render --sex female --height 165 --weight 62 --arm-span 167 --inseam 78 --hip-width 36 \
  -o out/avatar.png
echo
echo "[caliper] done: out/avatar.glb (rigged glTF 2.0: Blender, Unity, three.js), out/avatar-report.json, out/avatar.png"
case ":$PATH:" in
  *":$PREFIX/bin:"*) echo "[caliper] the command is $CALIPER (on your PATH: type caliper --help)" ;;
  *) echo "[caliper] the command is $CALIPER; add $PREFIX/bin to your PATH to type just caliper" ;;
esac
if [ -n "${CI:-}" ] || [ "${CALIPER_NO_SERVE:-0}" = "1" ]; then exit 0; fi
echo
echo "[caliper] starting the desktop tool: open http://127.0.0.1:8080/ in a browser (Ctrl+C stops it)"
exec "$CALIPER" serve
