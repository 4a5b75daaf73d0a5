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

# same_run WHOLE OUT NP: OUT/final.h5 equals WHOLE/final.h5 bit for bit and the report.json
# files agree.
same_run() {
  same_state "$1/final.h5" "$2/final.h5" || return 1
  if ! same_report "$1/report.json" "$2/report.json"
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
