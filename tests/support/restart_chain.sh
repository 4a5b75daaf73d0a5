# Shared by the bit-for-bit restart tests of tests/cli (sourced, not run): the comparison of
# a restarted chain with its uninterrupted run, and the loop over 1 and 2 ranks.

# same_run WHOLE OUT NP: OUT/final.h5 equals WHOLE/final.h5 bit for bit and the report.json
# files agree.
same_run() {
  /usr/bin/python3 "$GRANPACK_SOURCE_DIR/tests/support/same_state.py" "$1/final.h5" "$2/final.h5" || return 1
  if ! /usr/bin/python3 "$GRANPACK_SOURCE_DIR/tests/support/same_report.py" "$1/report.json" "$2/report.json"
  then echo "FAIL: report.json of the chain differs"; return 1; fi
  echo "$3 rank(s): identical"
}

# over_ranks LABEL: calls the script's `chain NP` for NP = 1 and 2 (then its `stop_run`),
# prints the tally and fails if any failed.
over_ranks() {
  local passed=0 failed=0 n
  for n in 1 2; do
    if chain $n; then passed=$((passed + 1)); else failed=$((failed + 1)); fi
    stop_run
  done
  echo "$1: $passed passed, $failed failed"
  [ $failed -eq 0 ]
}
