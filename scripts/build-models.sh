#!/usr/bin/env bash
# Rebuilds the committed built-in body models (models/mannequin-{female,male,neutral}.npz) from
# the ANSUR II development data beside the project. Same data + same code → the same bytes.
# Usage: scripts/build-models.sh [ANSUR_DIR]   (default ../shared/data/ansur2)
set -euo pipefail
cd "$(dirname "$0")/.."
ansur="${1:-../shared/data/ansur2}"
[ -d "$ansur" ] || { echo "ANSUR II data not found at $ansur" >&2; exit 4; }
bash scripts/build.sh >/dev/null
for sex in female male neutral; do
  build/bin/caliper model build mannequin --ansur "$ansur" --sex "$sex" -o "models/mannequin-$sex.npz"
done
sha256sum models/mannequin-*.npz
