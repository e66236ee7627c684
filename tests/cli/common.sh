#!/usr/bin/env bash
# What the CLI tests share (sourced by cli_test.sh, eval_batch_test.sh and sessions_test.sh): the
# binary, a temporary folder removed on exit, and the checks. ctest runs the three files side by
# side: as one file, under the sanitizers, they took 6 minutes one command after another.
set -u
# shellcheck disable=SC2034  # CALIPER, SRC: used by the scripts that source this file
CALIPER="$1"
SRC="$(cd "$(dirname "$0")/../.." && pwd)"
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT
passed=0; failed=0

# expect CODE "description" command...  — runs the command, checks its exit code; keeps output in $TMP/out
expect() {
  local code="$1" what="$2"; shift 2
  "$@" >"$TMP/out" 2>&1
  local got=$?
  if [ "$got" = "$code" ]; then passed=$((passed + 1)); else
    failed=$((failed + 1)); echo "FAIL: $what: exit $got, expected $code"; sed 's/^/    /' "$TMP/out" | head -20; fi
}
# says "text" "description" — the last command's output contains text
says() {
  if grep -qF -- "$1" "$TMP/out"; then passed=$((passed + 1)); else
    failed=$((failed + 1)); echo "FAIL: $2: output lacks '$1'"; sed 's/^/    /' "$TMP/out" | head -20; fi
}

# with_metadata SRC DST KEY VALUE — copies the model SRC to DST with its metadata's KEY set to the
# string VALUE (metadata.npy holds one JSON text as a 0-d numpy unicode array). Needs python3.
with_metadata() {
  python3 - "$@" <<'PY'
import json, struct, sys, zipfile
source, target, key, value = sys.argv[1:5]
def npy_unicode(text):
    header = ("{'descr': '<U%d', 'fortran_order': False, 'shape': (), }" % max(1, len(text))).encode()
    header += b" " * ((64 - (10 + len(header) + 1) % 64) % 64) + b"\n"
    return b"\x93NUMPY\x01\x00" + struct.pack("<H", len(header)) + header + text.encode("utf-32-le")
with zipfile.ZipFile(source) as src, zipfile.ZipFile(target, "w", zipfile.ZIP_DEFLATED) as out:
    for name in src.namelist():
        data = src.read(name)
        if name == "metadata.npy":
            header_len = struct.unpack("<H", data[8:10])[0]
            meta = json.loads(data[10 + header_len:].decode("utf-32-le").rstrip("\0"))
            meta[key] = value
            data = npy_unicode(json.dumps(meta))
        out.writestr(name, data)
PY
}

# summary — prints the counts; the exit status says whether every check passed
summary() {
  echo "$passed passed, $failed failed"
  [ "$failed" = 0 ]
}
