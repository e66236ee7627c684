#!/usr/bin/env bash
# Fuzzes Caliper's untrusted inputs with libFuzzer (docs/reliability.md "Fuzzing"): one target per
# gate (fuzz/*_fuzzer.cpp), each for a bounded time, on the sanitizer build (build-asan/, built by
# scripts/sanitize.sh --build-only if needed). Seeds: fuzz/corpus/<gate>/ and the derived seeds
# fuzz_make_seeds writes into build-asan/fuzz/seeds/. New interesting inputs stay in
# build-asan/fuzz/work/<gate>/ (not committed); a crash, sanitizer report, failed oracle, a run
# over 10 s or over 2.5 GB leaves its input in build-asan/fuzz/findings/<gate>/ and fails the script.
# Reproduce a finding: build-asan/fuzz/fuzz_<gate> FILE. Keep it: copy it to fuzz/regressions/<gate>/.
# Usage: scripts/fuzz.sh [--seconds N] [GATE...]   (default: 20 s for each gate; GATE as in fuzz_GATE)
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=20
gates=()
while [ $# -gt 0 ]; do
  case "$1" in
    --seconds) seconds="$2"; shift 2 ;;
    -h|--help) sed -n '2,9p' "$0"; exit 0 ;;
    *) gates+=("$1"); shift ;;
  esac
done
if [ "${#gates[@]}" -eq 0 ]; then
  for f in fuzz/*_fuzzer.cpp; do f="${f#fuzz/}"; gates+=("${f%_fuzzer.cpp}"); done
fi

bash scripts/sanitize.sh --build-only
source scripts/sanitizer-env.sh
out=build-asan/fuzz
"$out/fuzz_make_seeds" "$out/seeds"

status=0
printf '%-18s %8s %12s %8s  %s\n' gate seconds executions new result
for gate in "${gates[@]}"; do
  mkdir -p "$out/work/$gate" "$out/findings/$gate" "$out/logs"
  log="$out/logs/$gate.log"
  seeds=()
  for dir in "fuzz/corpus/$gate" "fuzz/regressions/$gate" "$out/seeds/$gate"; do [ -d "$dir" ] && seeds+=("$dir"); done
  result=ok
  if ! "$out/fuzz_$gate" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2560 -print_final_stats=1 \
      -artifact_prefix="$out/findings/$gate/" "$out/work/$gate" "${seeds[@]}" >"$log" 2>&1; then
    result="FINDING: $log"
    status=1
  fi
  executions="$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)"
  corpus="$(find "$out/work/$gate" -type f | wc -l)"
  printf '%-18s %8s %12s %8s  %s\n' "$gate" "$seconds" "${executions:-?}" "$corpus" "$result"
done
exit "$status"
