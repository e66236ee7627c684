#!/usr/bin/env bash
# Runs one fuzzer once over each of its inputs, without mutating (a ctest test per gate, in the
# sanitizer build): the committed corpus fuzz/corpus/<gate>/, past findings fuzz/regressions/<gate>/
# and the derived seeds SEEDS/<gate>/. Any crash, sanitizer report or failed oracle fails it.
# Usage: fuzz/replay.sh FUZZER GATE SEEDS
set -euo pipefail
fuzzer="$1" gate="$2" seeds="$3"
here="$(cd "$(dirname "$0")" && pwd)"
inputs=()
for dir in "$here/corpus/$gate" "$here/regressions/$gate" "$seeds/$gate"; do
  [ -d "$dir" ] && while IFS= read -r -d '' f; do inputs+=("$f"); done < <(find "$dir" -type f -print0 | sort -z)
done
if [ "${#inputs[@]}" -eq 0 ]; then
  echo "no inputs for $gate" >&2
  exit 1
fi
echo "replaying ${#inputs[@]} inputs through $(basename "$fuzzer")"
"$fuzzer" -timeout=60 "${inputs[@]}"
