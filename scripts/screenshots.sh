#!/usr/bin/env bash
# Retakes the pictures in docs/images that show the web pages or the engine imports, on today's
# body, so they can be refreshed in one go after the body changes (the body's own renders are
# scripts/render-docs.sh's).
#
#   scripts/screenshots.sh [OUT_DIR]      (default: docs/images; a scratch folder to look first)
#
# - desktop tool, capture page, mirror, .vrm in three-vrm: the browser tests' own screenshots
#   (tests/e2e/*.spec.mjs --screenshots, headless Chromium), renamed by the table below;
# - makehuman-desktop-tool.png: scripts/screenshot-makehuman.mjs with build/makehuman-female.npz
#   (scripts/makehuman-model.sh: built from ../shared/data/makehuman when missing or older than
#   the CLI; skipped when that folder is missing);
# - engines-blender-*.png: tests/e2e/blender_render.py in Blender (EEVEE) on exported .fbx files
#   (skipped when `blender` is missing), the shape keys' three composed by
#   tests/e2e/blender_side_by_side.py.
# Needs build/bin/caliper (scripts/build.sh) and web/node_modules; builds web/dist itself.
# About 5–8 minutes on 2 cores, depending on the load (the mirror test takes the longest).
# A test that fails leaves its pictures untouched and the script exits 1 at the end.
set -euo pipefail
if [ "${1:-}" = "-h" ] || [ "${1:-}" = "--help" ]; then sed -n '2,/^set -e/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0; fi
root="$(cd "$(dirname "$0")/.." && pwd)"
out="$(realpath -m "${1:-$root/docs/images}")"
cd "$root"
caliper=build/bin/caliper
[ -x "$caliper" ] || { echo "screenshots: no $caliper (run scripts/build.sh)" >&2; exit 1; }
chromium="${CALIPER_CHROMIUM:-/usr/bin/chromium}"  # as tests/e2e/harness.mjs finds it
[ -x "$chromium" ] || { echo "screenshots: no Chromium at $chromium (scripts/install-deps.sh installs it)" >&2; exit 1; }
export CALIPER_REQUIRE_TOOLS=1   # a missing browser or npm package fails instead of skipping
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$out"
failed=0
say() { echo "[screenshots] $*"; }

# test  the file it writes  →  the name in docs/images
shots=(
  "desktop desktop-tool-1920x1080.png        desktop-tool.png"
  "desktop desktop-tool-1024x768.png         desktop-tool-1024.png"
  "desktop desktop-tool-375x812.png          desktop-tool-phone.png"
  "desktop desktop-tool-mistake.png          desktop-tool-mistake.png"
  "desktop desktop-tool-compare.png          desktop-tool-compare.png"
  "desktop desktop-tool-arm-length.png       desktop-tool-arm-length.png"
  "desktop desktop-tool-implausible.png      desktop-tool-implausible.png"
  "desktop desktop-tool-map.png              desktop-tool-map.png"
  "desktop desktop-tool-mirror-body.png      desktop-tool-mirror-body.png"
  "desktop desktop-tool-body-image-task.png  desktop-tool-body-image-task.png"
  "capture capture-vr.png                    capture-vr.png"
  "capture capture-vr-rejected.png           capture-vr-rejected.png"
  "capture capture-mirror.png                capture-mirror.png"
  "capture capture-page.png                  capture-page.png"
  "mirror  mirror-view.png                   mirror-view.png"
  "mirror  mirror-first-person.png           mirror-first-person.png"
  "mirror  mirror-hands.png                  mirror-hands.png"
  "vrm     vrm-three.png                     engines-three-vrm.png"
)
for spec in desktop capture mirror vrm; do
  say "tests/e2e/$spec.spec.mjs ..."
  start=$SECONDS
  if node "tests/e2e/$spec.spec.mjs" --caliper "$caliper" --screenshots "$tmp/$spec" >"$tmp/$spec.log" 2>&1; then
    for row in "${shots[@]}"; do
      read -r s from to <<<"$row"
      [ "$s" = "$spec" ] || continue
      if cp "$tmp/$spec/$from" "$out/$to"; then say "  $to  ($from)"; else failed=1; fi
    done
    say "  $spec took $((SECONDS - start)) s"
  else
    grep -E '^(FAIL|SKIP)' "$tmp/$spec.log" >&2 || tail -20 "$tmp/$spec.log" >&2
    say "  FAILED: $spec.spec.mjs; its pictures were left as they are" >&2
    failed=1
  fi
done

# The desktop tool with a MakeHuman model picked: the built model beside the mannequin ones
# (scripts/makehuman-model.sh rebuilds it when older than the CLI, so a changed MakeHuman builder shows).
status=0
mh=$(bash scripts/makehuman-model.sh female 2>"$tmp/makehuman.log") || status=$?
if [ "$status" -eq 77 ]; then
  say "$(tail -1 "$tmp/makehuman.log"): makehuman-desktop-tool.png is left as it is"
elif [ "$status" -ne 0 ]; then
  tail -20 "$tmp/makehuman.log" >&2; say "  FAILED: makehuman-desktop-tool.png" >&2; failed=1
else
  say "makehuman-desktop-tool.png ..."
  mkdir -p "$tmp/models"
  ln -s "$root"/models/mannequin-*.npz "$root/$mh" "$tmp/models/"
  if CALIPER_MODELS_DIR="$tmp/models" node scripts/screenshot-makehuman.mjs --caliper "$caliper" --screenshots "$out" \
      >>"$tmp/makehuman.log" 2>&1; then say "  makehuman-desktop-tool.png"
  else tail -20 "$tmp/makehuman.log" >&2; say "  FAILED: makehuman-desktop-tool.png" >&2; failed=1; fi
fi

# Blender: the engine checks' avatars (tests/e2e/export-engine-avatars.sh) posed by
# tests/e2e/blender_render.py; the shape keys' three pictures put side by side.
render() {  # FILE OUT.png [shape_k=VALUE]
  blender -b --python-exit-code 1 --python tests/e2e/blender_render.py -- "$1" "$2" BLENDER_EEVEE "${@:3}" >"$tmp/blender.log" 2>&1 ||
    { tail -20 "$tmp/blender.log" >&2; return 1; }
}
blender_shots() {
  bash tests/e2e/export-engine-avatars.sh "$caliper" "$tmp/avatars" >/dev/null &&
    render "$tmp/avatars/male.fbx" "$out/engines-blender-fbx.png" && say "  engines-blender-fbx.png" &&
    render "$tmp/avatars/female-morphs.fbx" "$tmp/keys-2.png" shape_0=-2 &&
    render "$tmp/avatars/female-morphs.fbx" "$tmp/keys0.png" shape_0=0 &&
    render "$tmp/avatars/female-morphs.fbx" "$tmp/keys2.png" shape_0=2 &&
    blender -b --python-exit-code 1 --python tests/e2e/blender_side_by_side.py -- \
      "$out/engines-blender-shape-keys.png" "$tmp"/keys{-2,0,2}.png >"$tmp/blender.log" 2>&1 &&
    say "  engines-blender-shape-keys.png"
}
if command -v blender >/dev/null; then
  say "engines-blender-fbx.png, engines-blender-shape-keys.png ..."
  blender_shots || { tail -20 "$tmp/blender.log" >&2 2>/dev/null; say "  FAILED: the Blender pictures" >&2; failed=1; }
else
  say "no blender on PATH: engines-blender-fbx.png and engines-blender-shape-keys.png are left as they are"
fi
[ "$failed" = 0 ] && say "done: pictures in $out" || say "some pictures failed (above)" >&2
exit "$failed"
