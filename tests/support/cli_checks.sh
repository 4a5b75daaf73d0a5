# Shared by the tests/cli scripts that tally named checks (sourced, not run).
#
# cli_scratch: makes $scratch, removed when the script exits.
# check NAME CONDITION: evaluates CONDITION (a shell expression, in single quotes when it
#   should see the values at check time); counts a pass, or prints "FAIL: NAME" and counts a
#   failure. Every check runs, so one failure does not hide the others.
# checks_done LABEL [NOTE]: prints "LABEL: P passed, F failed [NOTE]" and returns non-zero if
#   any check failed; the script ends with it, so it is the test's exit status.
cli_scratch() {
  scratch=$(mktemp -d)
  trap 'rm -rf "$scratch"' EXIT
}
fail=0; pass=0
check() { if eval "$2"; then pass=$((pass+1)); else echo "FAIL: $1"; fail=$((fail+1)); fi; }
checks_done() {
  echo "$1: $pass passed, $fail failed${2:+ $2}"
  [ "$fail" -eq 0 ]
}
