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
# Head close-ups (the relief's face, the nape): front, side, back, three-quarter.
head=(--pose a --focus head --views front,side,back,three-quarter --image-width 360 --image-height 400)
$c render --sex female --beta 0 -o docs/images/mannequin-head.png "${head[@]}"
$c render --sex male --beta 0 -o docs/images/mannequin-head-male.png "${head[@]}"
# The rig at work: mid-stride, knees and elbows bent by the skinning weights.
$c render --sex female --beta 0 -o docs/images/mannequin-posed.png --pose stride --views front,side,three-quarter \
  --image-width 420 --image-height 700
# The UV layout: the atlas, and the mean female painted with a checker through it.
$c model uv-atlas mannequin --sex female --size 1024 -o docs/images/uv-atlas-female.png
$c render --sex female --beta 0 --uv-checker -o docs/images/uv-checker-female.png "${size[@]}"
# Hands: the open hand and the fist, close up; the body posed with fists.
$c render --sex female --beta 0 --focus left_middle1 --focus-radius 12 --views top,front,three-quarter \
  -o docs/images/mannequin-hand.png --image-width 480 --image-height 400
$c render --sex male --beta 0 --pose fist --focus left_middle1 --focus-radius 11 --views side,three-quarter \
  -o docs/images/mannequin-fist.png --image-width 480 --image-height 400
# Feet: the mean male's, close up (front, the outer side, three-quarter).
$c render --sex male --beta 0 --focus left_foot --focus-radius 8 --views front,side,three-quarter \
  -o docs/images/mannequin-foot.png --image-width 480 --image-height 320
# A heavy man (BMI 35: 178 cm, 111 kg).
$c render --sex male --height 178 --weight 111 -o docs/images/mannequin-heavy-man.png "${size[@]}"
# Beside the MakeHuman body at the same measurements, when MakeHuman's assets are beside the
# project (scripts/makehuman-model.sh builds the model into build/, never committed; docs/makehuman.md).
for sex in female male; do
  status=0
  mh=$(bash scripts/makehuman-model.sh "$sex" 2>"build/makehuman-$sex.log") || status=$?
  if [ "$status" -eq 77 ]; then
    echo "render-docs: $(tail -1 "build/makehuman-$sex.log"); the MakeHuman comparison pictures are left as they are" >&2
    break
  elif [ "$status" -ne 0 ]; then
    tail -20 "build/makehuman-$sex.log" >&2; echo "render-docs: building the MakeHuman model failed" >&2; exit 1
  fi
  # name, height (cm), weight (kg): the mean body, then the issue's thin and heavy ones
  if [ "$sex" = female ]; then bodies=("female 165 62" "short-heavy 153 88")
  else bodies=("male 178 82" "tall-thin 193 72" "heavy-man 178 111"); fi
  for body in "${bodies[@]}"; do
    read -r name height weight <<<"$body"
    m=(--sex "$sex" --height "$height" --weight "$weight" --views front,side --pose a --image-width 420 --image-height 700)
    $c render --model "$mh" "${m[@]}" -o "docs/images/makehuman-$name.png"
    $c render "${m[@]}" -o "docs/images/makehuman-mannequin-$name.png"
  done
done
