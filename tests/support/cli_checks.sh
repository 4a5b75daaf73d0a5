# Shared by the tests/cli scripts that tally named checks (sourced, not run).
#
# cli_scratch [CLEANUP]: makes $scratch, removed when the script exits (after running the shell
#   command CLEANUP, if given: e.g. killing runs of the test still in progress).
# check NAME CONDITION: evaluates CONDITION (a shell expression, in single quotes when it
#   should see the values at check time); counts a pass, or prints "FAIL: NAME" and counts a
#   failure. Every check runs, so one failure does not hide the others. Returns non-zero on a
#   failure, so that `check ... || cat LOG` shows the evidence.
# checks_from LABEL FILE RC: the checks of a Python block that wrote one line per check to
#   FILE, "ok: NAME" (a pass) or "FAIL: NAME" (printed, a failure), counted as check does;
#   other lines (numbers for the log, a traceback) are printed. RC is the block's exit status:
#   one more check, "LABEL ran to the end", fails when it is not 0 (the block stopped early).
# checks_stop LABEL [LOG]: after a failed check that the following ones cannot do without (a
#   run whose files they read): prints the end of LOG, the tally marked "(stopped early)", and
#   ends the script with exit code 1.
# checks_done LABEL [NOTE]: prints "LABEL: P passed, F failed [NOTE]" and returns non-zero if
#   any check failed; the script ends with it, so it is the test's exit status.
cli_scratch() {
  scratch=$(mktemp -d)
  trap "${1:+$1; }"'rm -rf "$scratch"' EXIT
}
fail=0; pass=0
check() {
  if eval "$2"; then pass=$((pass+1)); else echo "FAIL: $1"; fail=$((fail+1)); return 1; fi
}
checks_from() {
  local line
  while IFS= read -r line || [ -n "$line" ]; do
    case $line in
      "ok: "*) pass=$((pass+1)) ;;
      "FAIL: "*) echo "$line"; fail=$((fail+1)) ;;
      *) printf '%s\n' "$line" ;;
    esac
  done < "$2"
  check "$1 ran to the end (exit $3)" "[ $3 -eq 0 ]"
}
checks_stop() {
  [ -n "${2:-}" ] && tail -20 "$2"
  checks_done "$1" "(stopped early)"
  exit 1
}
checks_done() {
  echo "$1: $pass passed, $fail failed${2:+ $2}"
  [ "$fail" -eq 0 ]
}
