#!/usr/bin/env bash
# The `caliper` command line: `eval` (with --train on the development data when ../shared is
# there) and `batch` in every format. Usage: eval_batch_test.sh CALIPER_BINARY
# shellcheck source=tests/cli/common.sh
source "$(dirname "$0")/common.sh"

# Evaluation and batch on a small file that lacks most held-out columns.
expect 0 "eval on a partial file" "$CALIPER" eval --subjects "$SRC/examples/people.csv" --json "$TMP/eval.json" -q
expect 0 "eval JSON has inputs and only the held-out columns present" node -e '
  const e = JSON.parse(require("fs").readFileSync(process.argv[1]));
  const r5 = e.regressors.R5;
  process.exit(e.subjects === 3 && r5.inputs.stature.mae_cm < 0.01 && "armlength" in r5.held_out &&
               !("chestcircumference" in r5.held_out) && "uniform_scale" in e.baselines ? 0 : 1);' "$TMP/eval.json"
expect 3 "eval with unknown noise" "$CALIPER" eval --subjects "$SRC/examples/people.csv" --noise loud
expect 4 "eval on a missing file" "$CALIPER" eval --subjects /nonexistent.csv
expect 4 "eval with a missing training file" "$CALIPER" eval --subjects "$SRC/examples/people.csv" --train /nonexistent.csv
says "/nonexistent.csv" "the training file is named"
ANSUR_F="$SRC/../shared/data/ansur2/ANSUR_II_FEMALE_dev.csv"
if [ -f "$ANSUR_F" ]; then
  # The linear limit fitted on one part of the women (all but the first 200), tested on another
  # (the first 200; the sanitizer build's ctest sets CALIPER_EVAL_TEST_SUBJECTS=60).
  tested="${CALIPER_EVAL_TEST_SUBJECTS:-200}"
  case "$tested" in ''|*[!0-9]*) tested=200 ;; esac
  [ "$tested" -ge 1 ] && [ "$tested" -le 200 ] || tested=200  # never into the training rows
  head -$((tested + 1)) "$ANSUR_F" >"$TMP/test.csv"; { head -1 "$ANSUR_F"; tail -n +202 "$ANSUR_F"; } >"$TMP/train.csv"
  expect 0 "eval with --train" "$CALIPER" eval --subjects "$TMP/test.csv" --train "$TMP/train.csv" --regressor R2,auto --json "$TMP/lin.json"
  says "linear limit: 1290 training subjects" "the training file is used and counted"
  says "held out / linear limit: median" "ratios to the limit are printed"
  expect 0 "the JSON has the ratios" node -e '
    const j = JSON.parse(require("fs").readFileSync(process.argv[1]));
    const a = j.regressors.auto, r2 = j.regressors.R2;
    const ok = /1290 training/.test(j.linear_limit.fitted_on) && a.ratio_to_linear_median > 0.5 && a.ratio_to_linear_median < 2 &&
      Object.keys(a.ratio_to_linear).length === 12 && a.linear_limit.chestcircumference.mae_cm < r2.linear_limit.chestcircumference.mae_cm * 1.01;
    process.exit(ok ? 0 : 1);' "$TMP/lin.json"
else
  echo "skip: eval --train needs ../shared/data/ansur2 (not found)"
fi
expect 0 "batch" "$CALIPER" batch --subjects "$SRC/examples/people.csv" --out "$TMP/batch"
expect 0 "batch wrote an avatar and a report per row" bash -c "ls '$TMP/batch' | grep -c . | grep -qx 6"
# --format takes every file `avatar -o` writes, written by the same routine (provenance included).
for format in vrm fbx obj; do
  expect 0 "batch --format $format" "$CALIPER" batch --subjects "$SRC/examples/people.csv" --out "$TMP/batch-$format" --format $format
  expect 0 "batch --format $format wrote a .$format per row" bash -c "ls '$TMP/batch-$format'/*.$format | grep -c . | grep -qx 3"
done
head -c 18 "$TMP/batch-fbx/ex-2.fbx" >"$TMP/out"
says "Kaydara FBX Binary" "batch's .fbx is a binary FBX"
expect 0 "batch's .vrm has the VRMC_vrm extension" grep -aq "VRMC_vrm" "$TMP/batch-vrm/ex-1.vrm"
expect 0 "batch's .fbx carries its provenance" grep -aq "caliper_licence" "$TMP/batch-fbx/ex-1.fbx"
expect 2 "batch --format stl" "$CALIPER" batch --subjects "$SRC/examples/people.csv" --out "$TMP/batch-stl" --format stl
says "glb, vrm, fbx or obj" "the --format error lists the formats"

summary
