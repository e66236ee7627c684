#!/usr/bin/env bash
# Checks exported .glb avatars with every independent reader available:
#   1. the Khronos glTF validator (required: zero errors),
#   2. Assimp's command-line importer (if assimp-utils is installed),
#   3. Blender's glTF importer (if blender is installed): armature, weights, rest shape.
#   tests/e2e/check-glb.sh out/avatar.glb [more.glb ...]
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
[ $# -ge 1 ] || { echo "usage: $0 FILE.glb [FILE.glb ...]" >&2; exit 2; }
status=0

echo "== Khronos glTF validator"
if [ ! -d "$root/tools/node_modules/gltf-validator" ]; then
  echo "missing tools/node_modules: run scripts/install-deps.sh (or cd tools && npm ci)" >&2
  exit 2
fi
node "$root/tools/validate-gltf.mjs" "$@" || status=1

if command -v assimp >/dev/null; then
  echo "== Assimp"
  for f in "$@"; do
    if out="$(assimp info "$f" 2>&1)"; then
      echo "$f: $(grep -E '^(Meshes|Vertices|Faces|Bones):\s+[0-9]' <<<"$out" | tr -s ' ' | paste -sd ' ')"
    else
      echo "$f: assimp could not import it" >&2
      status=1
    fi
  done
else
  echo "== Assimp: assimp-utils not installed, skipped"
fi

if command -v blender >/dev/null; then
  echo "== Blender"
  blender -b --factory-startup --python-exit-code 1 --python "$here/blender_import_glb.py" -- "$@" 2>/dev/null \
    | grep '^{' || status=1
else
  echo "== Blender: not installed, skipped (apt-get install blender python3-numpy)"
fi
exit $status
