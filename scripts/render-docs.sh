#!/usr/bin/env bash
# Renders the pictures of the built-in body shown in the README and docs/mannequin.md, with the
# project's own renderer (caliper render). Usage: scripts/render-docs.sh
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh >/dev/null
c=build/bin/caliper
mkdir -p docs/images
size=(--image-width 420 --image-height 700 --pose a)  # A-pose through the rig: the body fills the frame
$c render --sex female --beta 0 -o docs/images/mannequin-mean-female.png "${size[@]}"
$c render --sex male --beta 0 -o docs/images/mannequin-mean-male.png "${size[@]}"
$c render --sex male --height 193 --weight 72 -o docs/images/mannequin-tall-thin.png "${size[@]}"
$c render --sex female --height 153 --weight 88 -o docs/images/mannequin-short-heavy.png "${size[@]}"
# Head close-ups (the relief's face): front, side, three-quarter.
head=(--pose a --focus head --views front,side,three-quarter --image-width 360 --image-height 400)
$c render --sex female --beta 0 -o docs/images/mannequin-head.png "${head[@]}"
$c render --sex male --beta 0 -o docs/images/mannequin-head-male.png "${head[@]}"
# The rig at work: mid-stride, knees and elbows bent by the skinning weights.
$c render --sex female --beta 0 -o docs/images/mannequin-posed.png --pose stride --views front,side,three-quarter \
  --image-width 420 --image-height 700
# The UV layout: the atlas, and the mean female painted with a checker through it.
$c model uv-atlas mannequin --sex female --size 1024 -o docs/images/uv-atlas-female.png
$c render --sex female --beta 0 --uv-checker -o docs/images/uv-checker-female.png "${size[@]}"
