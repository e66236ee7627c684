#!/usr/bin/env bash
# Regenerates docs/evaluation.md, its plots and raw JSON from the ANSUR II development data:
# caliper eval per sex and noise setting (none, self, other), plus the synthetic surface study;
# every run also evaluates the default estimator `auto` against the linear limit;
# tools/eval-map-section.mjs adds its self-noise section (uncertainty calibration) to the page.
# Usage: scripts/evaluate.sh [ANSUR_DIR]   (default ../shared/data/ansur2)
set -euo pipefail
cd "$(dirname "$0")/.."
ansur="${1:-../shared/data/ansur2}"
[ -f "$ansur/ANSUR_II_FEMALE_dev.csv" ] || { echo "ANSUR II development data not found in $ansur" >&2; exit 4; }
bash scripts/build.sh >/dev/null
out=docs/evaluation
mkdir -p "$out"
for sex in female male; do
  file="$ansur/ANSUR_II_${sex^^}_dev.csv"
  for noise in none self other; do
    synthetic=()
    if [ "$noise" != none ] && [ "$sex" = female ]; then synthetic=(--synthetic 100); fi  # both sexes
    regressors=R2,R4,R5,R6,auto
    echo "[caliper] eval $sex, noise $noise, $regressors"
    build/bin/caliper eval --subjects "$file" --noise "$noise" --seed 1 -q --json "$out/$sex-$noise.json" \
      --regressor "$regressors" "${synthetic[@]}"
  done
done
node tools/eval-report.mjs "$out" docs/evaluation.md
node tools/eval-map-section.mjs "$out" docs/evaluation.md
echo "[caliper] wrote docs/evaluation.md"
