# Shared by the command-line tests (sourced, not run): counters, pass/fail lines and `expect`.
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
