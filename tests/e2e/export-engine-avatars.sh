#!/usr/bin/env bash
# The avatars the engine checks import (docs/engines.md): female and male .glb and .fbx, and a
# .fbx and a .glb with shape keys. Used by scripts/test.sh (CALIPER_BLENDER=1) and by
# scripts/screenshots.sh (the Blender pictures).
#
#   tests/e2e/export-engine-avatars.sh CALIPER_BIN OUT_DIR
set -euo pipefail
c="$1" out="$2"
mkdir -p "$out"
"$c" avatar --sex female --height 165 --weight 62 -o "$out/female.glb" -q
"$c" avatar --sex male --height 180 --weight 85 --arm-span 186 --inseam 84 -o "$out/male.glb" -q
"$c" avatar --sex female --height 165 --weight 62 -o "$out/female.fbx" -q
"$c" avatar --sex male --height 180 --weight 85 --skeleton humanoid -o "$out/male.fbx" -q
"$c" avatar --sex female --height 165 --weight 62 --morphs -o "$out/female-morphs.fbx" -q
"$c" avatar --sex female --height 170 --weight 70 --skeleton humanoid --morphs -o "$out/female-morphs.glb" -q
