#!/usr/bin/env bash
# Regenerates the tables of docs/makehuman.md, "Evaluation next to the built-in body": caliper
# eval (the paper's R2, R4, R5 and R6, no added noise, seed 1) on the built-in body and on the
# MakeHuman body built here, for both sexes, then tools/makehuman-report.mjs. Raw JSON in
# build/makehuman-eval/.
# Usage: scripts/compare-makehuman.sh [ANSUR_DIR]   (default ../shared/data/ansur2; MakeHuman's
# assets as scripts/makehuman-model.sh finds them). About a minute once the models are built.
set -euo pipefail
cd "$(dirname "$0")/.."
ansur="${1:-../shared/data/ansur2}"
for sex in FEMALE MALE; do
  [ -f "$ansur/ANSUR_II_${sex}_dev.csv" ] || { echo "ANSUR II development data not found in $ansur" >&2; exit 4; }
done
bash scripts/build.sh >/dev/null
out=build/makehuman-eval
mkdir -p "$out"
for sex in female male; do
  makehuman=$(bash scripts/makehuman-model.sh "$sex")
  for body in builtin makehuman; do
    model=mannequin
    [ "$body" = makehuman ] && model="$makehuman"
    echo "[caliper] eval $sex, $body body"
    build/bin/caliper eval --subjects "$ansur/ANSUR_II_${sex^^}_dev.csv" --model "$model" --regressor R2,R4,R5,R6 \
      --noise none --seed 1 -q --json "$out/$sex-$body.json"
  done
done
node tools/makehuman-report.mjs "$out" docs/makehuman.md
