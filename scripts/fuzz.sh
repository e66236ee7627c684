#!/usr/bin/env bash
# Fuzzes Caliper's untrusted inputs with libFuzzer (docs/reliability.md "Fuzzing"): one target per
# gate (fuzz/*_fuzzer.cpp), each for a bounded time, on the sanitizer build (build-asan/, built by
# scripts/sanitize.sh --build-only if needed). Seeds: fuzz/corpus/<gate>/ and the derived seeds
# fuzz_make_seeds writes into build-asan/fuzz/seeds/. New interesting inputs stay in
# build-asan/fuzz/work/<gate>/ (not committed); a crash, sanitizer report, failed oracle, a run
# over 10 s or over 2.5 GB leaves its input in build-asan/fuzz/findings/<gate>/ and fails the script.
# Reproduce a finding: build-asan/fuzz/fuzz_<gate> FILE. Keep it: copy it to fuzz/regressions/<gate>/.
# Usage: scripts/fuzz.sh [--seconds N] [--jobs N] [GATE...]   (default: 20 s for each gate; GATE as
# in fuzz_GATE). Gates run side by side, one per CPU (--jobs, default nproc): each still has its
# seconds on a core of its own, and the suite's wall time is divided by the cores.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=20
parallel="$(nproc)"
gates=()
while [ $# -gt 0 ]; do
  case "$1" in
    --seconds) seconds="$2"; shift 2 ;;
    --jobs) parallel="$2"; shift 2 ;;
    -h|--help) sed -n '2,11p' "$0"; exit 0 ;;
    *) gates+=("$1"); shift ;;
  esac
done
[[ "$parallel" =~ ^[1-9][0-9]*$ ]] || { echo "fuzz.sh: --jobs takes a whole number of 1 or more, not '$parallel'" >&2; exit 2; }
if [ "${#gates[@]}" -eq 0 ]; then
  for f in fuzz/*_fuzzer.cpp; do f="${f#fuzz/}"; gates+=("${f%_fuzzer.cpp}"); done
fi

bash scripts/sanitize.sh --build-only
source scripts/sanitizer-env.sh
out=build-asan/fuzz
"$out/fuzz_make_seeds" "$out/seeds"

# One gate: its row of the table in $out/logs/<gate>.row, and "finding" there if it found one.
fuzz_gate() {
  local gate="$1" log="$out/logs/$1.log" result=ok seeds=() dir executions corpus
  mkdir -p "$out/work/$gate" "$out/findings/$gate"
  for dir in "fuzz/corpus/$gate" "fuzz/regressions/$gate" "$out/seeds/$gate"; do [ -d "$dir" ] && seeds+=("$dir"); done
  if ! "$out/fuzz_$gate" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2560 -print_final_stats=1 \
      -artifact_prefix="$out/findings/$gate/" "$out/work/$gate" "${seeds[@]}" >"$log" 2>&1; then
    result="FINDING: $log"
  fi
  executions="$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)"
  corpus="$(find "$out/work/$gate" -type f | wc -l)"
  printf '%-18s %8s %12s %8s  %s\n' "$gate" "$seconds" "${executions:-?}" "$corpus" "$result" >"$out/logs/$gate.row"
}

mkdir -p "$out/logs"
for gate in "${gates[@]}"; do
  while [ "$(jobs -rp | wc -l)" -ge "$parallel" ]; do wait -n || true; done
  rm -f "$out/logs/$gate.row"
  fuzz_gate "$gate" &
done
wait

status=0
printf '%-18s %8s %12s %8s  %s\n' gate seconds executions new result
for gate in "${gates[@]}"; do
  if [ ! -f "$out/logs/$gate.row" ]; then
    echo "$gate: the fuzzer did not report (see $out/logs/$gate.log)"; status=1; continue
  fi
  cat "$out/logs/$gate.row"
  grep -q "FINDING" "$out/logs/$gate.row" && status=1
done
exit "$status"
