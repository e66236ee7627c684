#!/usr/bin/env bash
# Prints the path of the MakeHuman model build/makehuman-SEX.npz, building it first from
# MakeHuman's CC0 assets when it is missing or older than the CLI (a model built by an older
# MakeHuman importer would show that importer's body, not today's). The model is never committed.
# Usage: scripts/makehuman-model.sh female|male|neutral
#   assets: $CALIPER_MAKEHUMAN_ASSETS, else ../shared/data/makehuman (docs/makehuman.md);
#   exit 77 (skipped, a code caliper never uses) when a build is needed and they are not there;
#   any other failure exits with the builder's code. The builder's progress goes to stderr.
set -euo pipefail
cd "$(dirname "$0")/.."
sex="${1:-}"
case "$sex" in female|male|neutral) ;; *) echo "usage: scripts/makehuman-model.sh female|male|neutral" >&2; exit 2 ;; esac
assets="${CALIPER_MAKEHUMAN_ASSETS:-../shared/data/makehuman}"
caliper=build/bin/caliper
model="build/makehuman-$sex.npz"
if [ ! "$model" -nt "$caliper" ]; then
  [ -d "$assets" ] || { echo "makehuman-model: MakeHuman's assets not found in $assets (docs/makehuman.md)" >&2; exit 77; }
  "$caliper" model build makehuman --assets "$assets" --sex "$sex" -o "$model" >&2
fi
echo "$model"
