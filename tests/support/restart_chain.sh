# Shared by the bit-for-bit restart tests of tests/cli (sourced, not run): a scratch directory
# and the killing of a run in progress, the comparison of a restarted chain with its
# uninterrupted run, and the loop over 1 and 2 ranks.

# restart_scratch: makes $scratch (removed on exit), and stop_run, which kills the run whose
# mpiexec pid is $pid (with its ranks, kill -9) and waits for it; the EXIT trap calls both.
restart_scratch() {
  scratch=$(mktemp -d)
  pid=
  trap 'stop_run; rm -rf "$scratch"' EXIT
}
stop_run() { [ -n "$pid" ] && kill -9 $(pgrep -P "$pid") "$pid" 2>/dev/null; wait "$pid" 2>/dev/null; pid=; }

# same_run WHOLE OUT NP: OUT/final.h5 equals WHOLE/final.h5 bit for bit and the report.json
# files agree.
same_run() {
  /usr/bin/python3 "$GRANPACK_SOURCE_DIR/tests/support/same_state.py" "$1/final.h5" "$2/final.h5" || return 1
  if ! /usr/bin/python3 "$GRANPACK_SOURCE_DIR/tests/support/same_report.py" "$1/report.json" "$2/report.json"
  then echo "FAIL: report.json of the chain differs"; return 1; fi
  echo "$3 rank(s): identical"
}

# over_ranks: calls the script's `chain NP` for NP = 1 and 2, then its `stop_run`; the
# checks inside `chain` are tallied by tests/support/cli_checks.sh (the script ends with
# checks_done).
over_ranks() {
  local n
  for n in 1 2; do
    chain $n
    stop_run
  done
}
