#!/usr/bin/env bash
# Runs the Python module's pytest suite. Usage: run.sh PYTHON MODULE_DIR CALIPER_CLI
# Without pytest or NumPy the test is skipped (exit 77), or fails when CALIPER_REQUIRE_TOOLS=1.
set -u
PYTHON="$1"
export PYTHONPATH="$2${PYTHONPATH:+:$PYTHONPATH}"
export CALIPER_CLI="$3"
if ! "$PYTHON" -c "import pytest, numpy" 2>/dev/null; then
  echo "python: pytest or NumPy missing for $PYTHON (Debian: python3-pytest python3-numpy, scripts/install-deps.sh)"
  if [ "${CALIPER_REQUIRE_TOOLS:-0}" = "1" ]; then exit 1; fi
  exit 77
fi
cd "$(dirname "$0")"
exec "$PYTHON" -m pytest -q -p no:cacheprovider test_caliper.py
