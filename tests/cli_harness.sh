# Shared by the command-line tests (sourced, not run): counters, pass/fail lines, `expect`,
# `expect_error` and `contains`.
# The sourcing script sets `set -euo pipefail`, works in its own temporary folder and ends with
#   echo "$passed passed, $failed failed"; [[ $failed == 0 ]]
passed=0
failed=0
pass() { passed=$((passed + 1)); echo "ok      $1"; }
fail() { failed=$((failed + 1)); echo "FAILED  $1"; }

# expect CODE NAME -- COMMAND...: runs COMMAND (stdout+stderr to NAME.out/.err), checks the code.
expect() {
  local want=$1 name=$2
  shift 3
  local got=0
  "$@" >"$name.out" 2>"$name.err" || got=$?
  if [[ $got == "$want" ]]; then
    pass "$name (exit $got)"
  else
    fail "$name: exit $got, expected $want"
    sed 's/^/        /' "$name.out" "$name.err" | tail -n 20
  fi
}

# expect_error NAME PATTERN -- COMMAND...: exit 2 and exactly one stderr line,
# 'topotet: error: ...' matching PATTERN.
expect_error() {
  local name=$1 pattern=$2
  shift 2
  expect 2 "$name" "$@"
  if [[ $(wc -l <"$name.err") == 1 ]] && grep -q "^topotet: error: .*$pattern" "$name.err"; then
    pass "$name: one error line with '$pattern'"
  else
    fail "$name: stderr is not one 'topotet: error:' line with '$pattern':"
    sed 's/^/        /' "$name.err" | head -n 10
  fi
}

# contains NAME FILE PATTERN: FILE has a line matching PATTERN.
contains() {
  if grep -q -- "$3" "$2"; then pass "$1"; else fail "$1: no '$3' in $2"; sed 's/^/        /' "$2" | head -n 10; fi
}
