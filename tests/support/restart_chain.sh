# Shared by the bit-for-bit restart tests of tests/cli (sourced, not run, after
# tests/support/cli_checks.sh): a scratch directory and the killing of a run in progress, the
# runs of a deck and of the legs of an interrupted chain, the comparison of a restarted chain
# with its uninterrupted run, and the loop over 1 and 2 ranks.

# restart_scratch: makes $scratch (removed on exit), and stop_run, which kills the run whose
# mpiexec pid is $pid (with its ranks, kill -9) and waits for it; the EXIT trap calls both.
restart_scratch() {
  scratch=$(mktemp -d)
  pid=
  trap 'stop_run; rm -rf "$scratch"' EXIT
}
stop_run() { [ -n "$pid" ] && kill -9 $(pgrep -P "$pid") "$pid" 2>/dev/null; wait "$pid" 2>/dev/null; pid=; }

# short_deck FILE: the CI gas deck cut short (compress stopped after 3000 steps) followed by
# three pressure steps of at most 600 steps: about 6600 steps through three MD stages.
short_deck() {
  sed -e 's/^log_every = .*/log_every = 500/' \
      -e 's/^inertia_max = 1.0e-2$/inertia_max = 1.0e-2\nmax_steps = 3000/' \
      "$GRANPACK_SOURCE_DIR/jobs/decks/ci/gas_small.toml" > "$1"
  cat >> "$1" <<'TOML'

[[stage]]
name = "qs"
kind = "pressure_steps"
factor = 1.5
count = 3
inertia_max = 1.0e-2
max_steps = 600
TOML
}

# run_deck OUT [ARGS...]: `granpack run "$deck" -o OUT -q "${run_options[@]}" ARGS` on $np ranks
# (stdin from /dev/null). start_leg [ARGS...]: the same into $out in the background, its output
# appended to $scratch/chain.txt; $pid is mpiexec's own (not a subshell's: the ranks are its
# children, and SIGUSR1 sent to it reaches them).
run_options=()
run_deck() {
  local o=$1; shift
  granpack_on "$np" run "$deck" -o "$o" -q "${run_options[@]}" "$@"
}
start_leg() {
  mpiexec -n "$np" "$GRANPACK_EXE" run "$deck" -o "$out" -q "${run_options[@]}" "$@" \
    < /dev/null >> "$scratch/chain.txt" 2>&1 &
  pid=$!
}
# inside [STAGE]: the checkpoints written inside a stage (inside stage index STAGE, if given)
# that $out/log.txt records so far, over every leg. checkpoint_stage: the stage that
# $out/checkpoint.h5 holds, as `granpack info` says it.
inside() {
  [ -f "$out/log.txt" ] || { echo 0; return; }
  awk -v want="${1:-}" '/^stage /{ s = $2 } /inside the stage/ && (want == "" || s == want) { c++ }
    END { print c + 0 }' "$out/log.txt"
}
checkpoint_stage() { "$GRANPACK_EXE" info "$out/checkpoint.h5" | sed -n 's/^stage: *//p'; }

# faulty_leg NAME FAULT [ARGS...]: a leg into $out with GRANPACK_FAULT=FAULT, which must end
# killed by the fault: a non-zero exit that is not the hard timeout's (124), the fault's
# message, and afterwards a readable checkpoint.h5 holding the step of the newest checkpoint
# that log.txt reports written.
faulty_leg() {
  local name="$np rank(s), $1" fault=$2 log=$scratch/leg.txt; shift 2
  GRANPACK_FAULT=$fault timeout 300 mpiexec -n "$np" "$GRANPACK_EXE" run "$deck" -o "$out" -q \
    "${run_options[@]}" "$@" < /dev/null > "$log" 2>&1
  local rc=$?
  cat "$log" >> "$scratch/chain.txt"
  check "$name: killed by the fault (exit $rc; 124 would be the timeout)" '[ $rc -ne 0 ] && [ $rc -ne 124 ]' \
    || { tail -20 "$log"; return 1; }
  check "$name: the fault fired where it was meant to" 'grep -q "GRANPACK_FAULT=$fault: rank [0-9]* killed itself" "$log"' \
    || { tail -20 "$log"; return 1; }
  check "$name: checkpoint.h5 is readable" '"$GRANPACK_EXE" info "$out/checkpoint.h5" > "$scratch/info.txt" 2>&1' \
    || { cat "$scratch/info.txt"; return 1; }
  local stored logged
  stored=$(sed -n 's/^time: .*(step \([0-9]*\))$/\1/p' "$scratch/info.txt")
  logged=$(sed -n 's/^  checkpoint [0-9]* at step \([0-9]*\) .*/\1/p' "$out/log.txt" | tail -1)
  check "$name: checkpoint.h5 is the newest written (step $stored; log.txt: $logged)" \
    '[ -n "$stored" ] && [ "$stored" = "$logged" ]' || return 1
}
# held_leg NAME FAULT [ARGS...]: a leg into $out with GRANPACK_FAULT=FAULT, a hold point
# (hold:N, piece_hold:N): once every rank holds there, SIGUSR1 to mpiexec; the leg must end
# with exit 75 (stopped with a checkpoint). The stop lands where FAULT says on any machine load.
held_leg() {
  local name="$np rank(s), $1" fault=$2; shift 2
  : > "$scratch/chain.txt"
  GRANPACK_FAULT=$fault start_leg "$@"
  wait_until 3000 0.1 "[ \$(grep -c 'GRANPACK_FAULT=$fault: rank [0-9]* holds at' '$scratch/chain.txt') -ge $np ]"
  kill -USR1 $pid 2>/dev/null
  wait $pid; local code=$?; pid=
  check "$name: stopped by SIGUSR1 while held (exit $code, expected 75)" '[ $code -eq 75 ]' \
    || { tail -20 "$scratch/chain.txt"; return 1; }
}
# final_step FILE: the step a configuration or checkpoint file holds.
final_step() { "$GRANPACK_EXE" info "$1" | sed -n 's/^time: .*(step \([0-9]*\))$/\1/p'; }
# checkpoint_steps STAGE: the steps of the checkpoints written inside stage index STAGE, as
# $out/log.txt records them.
checkpoint_steps() {
  awk -v want="$1" '/^stage /{ s = $2 } /inside the stage/ && s == want { print $5 }' "$out/log.txt"
}

# same_run WHOLE OUT NP: OUT/final.h5 equals WHOLE/final.h5 bit for bit and the report.json
# files agree.
same_run() {
  same_state "$1/final.h5" "$2/final.h5" || return 1
  if ! same_report "$1/report.json" "$2/report.json"
  then echo "FAIL: report.json of the chain differs"; return 1; fi
  echo "$3 rank(s): identical"
}

# over_ranks: calls the script's `chain NP` for NP = 1 and 2 (or the rank count that
# GRANPACK_TEST_RANKS names: ctest runs each as its own entry, tests/CMakeLists.txt), then its
# `stop_run`; the checks inside `chain` are tallied by tests/support/cli_checks.sh (the script
# ends with checks_done).
over_ranks() {
  local n
  for n in ${GRANPACK_TEST_RANKS:-1 2}; do
    chain $n
    stop_run
  done
}
