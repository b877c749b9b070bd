# Sourced by tests/examples/*.sh (not *.sh itself, so ctest does not run it alone).
# Usage: source "$(dirname "$0")/common.bash"; PROGRAM=path; run EXPECTED_RC PATTERN ARGS...; finish "message"
set -euo pipefail
failures=0
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

fail() {
  echo "FAIL: $*" >&2
  failures=$((failures + 1))
}

# run EXPECTED_RC PATTERN ARGS...: $PROGRAM ARGS must exit EXPECTED_RC and print a line matching
# PATTERN (grep -E, stdout or stderr); its output stays in $tmp/log.
run() {
  local expected=$1 pattern=$2 rc=0
  shift 2
  "$PROGRAM" "$@" >"$tmp/log" 2>&1 || rc=$?
  local what
  what="$(basename "$PROGRAM") $*"
  if [[ $rc != "$expected" ]]; then
    fail "$what: exit $rc, expected $expected: $(cat "$tmp/log")"
    return
  fi
  grep -Eq -- "$pattern" "$tmp/log" || fail "$what: no line matching '$pattern' in: $(cat "$tmp/log")"
}

# finish MESSAGE: exit 1 after any failure, else print MESSAGE.
finish() {
  if ((failures)); then
    echo "$failures failure(s)" >&2
    exit 1
  fi
  echo "$1"
}
