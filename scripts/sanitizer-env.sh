# Sourced by scripts/sanitize.sh and scripts/fuzz.sh: the sanitizers' run-time options.
# Every finding is fatal: ASan and UBSan abort the process (so the test or fuzz run fails),
# LeakSanitizer runs at exit. tests/sanitizer/lsan.supp would name the only third-party leaks
# tolerated, with reasons (none so far).
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"
if [ -s tests/sanitizer/lsan.supp ]; then
  export LSAN_OPTIONS="suppressions=$PWD/tests/sanitizer/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
fi
