#!/usr/bin/env bash
# Checks exported .glb / .vrm / .fbx avatars with every independent reader available:
#   1. the Khronos glTF validator (required: zero errors; glb and vrm),
#   2. Assimp's command-line importer (if assimp-utils is installed),
#   3. Blender's glTF and FBX importers (if blender is installed): armature, weights, rest shape,
#      bone directions, a bent elbow.
#   tests/e2e/check-glb.sh out/avatar.glb [more.glb|.fbx ...] [--shape-keys=N more files...]
# --shape-keys=N: the files after it were written with --morphs (N shape directions); Blender
# must import them with N shape keys.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
[ $# -ge 1 ] || { echo "usage: $0 FILE.glb|FILE.fbx [...] [--shape-keys=N FILE...]" >&2; exit 2; }
status=0
gltf=()
files=()  # the files, without the --shape-keys=N markers (only Blender reads those)
for f in "$@"; do case "$f" in --shape-keys=*) ;; *) files+=("$f") ;; esac; done
for f in "${files[@]}"; do case "$f" in *.fbx|*.FBX) ;; *) gltf+=("$f") ;; esac; done

echo "== Khronos glTF validator"
if [ ! -d "$root/tools/node_modules/gltf-validator" ]; then
  echo "missing tools/node_modules: run scripts/install-deps.sh (or cd tools && npm ci)" >&2
  exit 2
fi
if [ ${#gltf[@]} -gt 0 ]; then node "$root/tools/validate-gltf.mjs" "${gltf[@]}" || status=1; fi

if command -v assimp >/dev/null; then
  echo "== Assimp"
  for f in "${files[@]}"; do
    # Assimp picks its importer by extension and has none for .vrm (the unit tests read it as glTF).
    case "$f" in *.vrm|*.VRM) echo "$f: skipped (Assimp has no .vrm importer)"; continue ;; esac
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
  # Only the .glb and .fbx files: Blender's glTF importer does not take the .vrm extension.
  blender_args=()
  for f in "$@"; do case "$f" in *.vrm|*.VRM) ;; *) blender_args+=("$f") ;; esac; done
  if [ ${#blender_args[@]} -gt 0 ]; then
    out="$(blender -b --factory-startup --python-exit-code 1 --python "$here/blender_import_glb.py" -- "${blender_args[@]}" 2>/dev/null)" \
      || status=1
    grep '^{' <<<"$out" || status=1
  fi
else
  echo "== Blender: not installed, skipped (apt-get install blender python3-numpy)"
fi
exit $status
