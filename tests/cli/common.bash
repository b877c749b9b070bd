# Sourced by the tests/cli/*.sh scripts (deliberately not *.sh, so ctest does not run it alone).
# Usage in a script:  source "$(dirname "$0")/common.bash" "$@"
set -euo pipefail

if (($# < 2)); then
  echo "usage: $0 <path to janus> <repo root>" >&2
  exit 2
fi
JANUS=$1
REPO_ROOT=$2
# This folder: the scripts' Python helpers (pngio.py) live here.
CLI_DIR=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
export PYTHONDONTWRITEBYTECODE=1   # importing pngio must not write __pycache__ into the source tree
if [[ ! -x $JANUS ]]; then
  echo "FAIL: janus binary '$JANUS' is not executable" >&2
  exit 1
fi

TMP=$(mktemp -d "${TMPDIR:-/tmp}/janus-cli-test.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
failures=0

fail() {
  echo "FAIL: $*" >&2
  failures=$((failures + 1))
}

# run_janus ARGS...: runs janus, leaving the exit status in $rc and the output in $TMP/stdout, $TMP/stderr.
run_janus() {
  rc=0
  "$JANUS" "$@" >"$TMP/stdout" 2>"$TMP/stderr" || rc=$?
}

# expect_error CODE REGEX ARGS...: janus must exit with CODE and print exactly one stderr line,
# "janus: error: ...", matching REGEX (grep -E); never a crash or a stack trace.
expect_error() {
  local code=$1 pattern=$2
  shift 2
  run_janus "$@"
  local what="janus $*"
  if [[ $rc != "$code" ]]; then
    fail "$what: exit $rc, expected $code; stderr: $(cat "$TMP/stderr")"
    return 0
  fi
  local lines
  lines=$(wc -l <"$TMP/stderr")
  if [[ $lines != 1 ]]; then
    fail "$what: expected one line on stderr, got $lines: $(cat "$TMP/stderr")"
  fi
  if ! head -n 1 "$TMP/stderr" | grep -q '^janus: error: '; then
    fail "$what: stderr does not start with 'janus: error: ': $(cat "$TMP/stderr")"
  fi
  if ! grep -Eq -- "$pattern" "$TMP/stderr"; then
    fail "$what: stderr does not match /$pattern/: $(cat "$TMP/stderr")"
  fi
}

# expect_success ARGS...: janus must exit 0.
expect_success() {
  run_janus "$@"
  if [[ $rc != 0 ]]; then
    fail "janus $*: exit $rc, expected 0; stderr: $(cat "$TMP/stderr")"
  fi
}

# check_png FILE WIDTH HEIGHT: FILE is a PNG (signature, IHDR) of the given size.
check_png() {
  local file=$1 width=$2 height=$3
  if [[ ! -f $file ]]; then
    fail "$file was not written"
    return 0
  fi
  local problem
  problem=$(python3 - "$file" "$width" "$height" <<'PY'
import struct, sys
path, width, height = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
data = open(path, "rb").read()
if data[:8] != b"\x89PNG\r\n\x1a\n":
    print("no PNG signature")
elif data[12:16] != b"IHDR":
    print("first chunk is not IHDR")
else:
    w, h = struct.unpack(">II", data[16:24])
    if (w, h) != (width, height):
        print(f"size {w}x{h}, expected {width}x{height}")
PY
  )
  if [[ -n $problem ]]; then
    fail "$file: $problem"
  fi
}

# json_check FILE PYTHON_EXPRESSION DESCRIPTION: the expression, with the parsed JSON as `j`, is true.
json_check() {
  local file=$1 expression=$2 description=$3
  if ! python3 -c 'import json, sys; j = json.load(open(sys.argv[1])); sys.exit(0 if ('"$expression"') else 1)' "$file" 2>"$TMP/json-error"; then
    fail "$file: $description ($(cat "$TMP/json-error"))"
  fi
}

finish() {
  if ((failures > 0)); then
    echo "$(basename "$0"): $failures check(s) failed" >&2
    exit 1
  fi
  echo "$(basename "$0"): all checks passed"
}
