#!/usr/bin/env bash
# Checkpoints inside fix_rattlers continue exactly.
#  1. A small packing (random gas -> short compress) whose rattlers are pushed onto the frozen
#     backbone by fix_rattlers, uninterrupted, with a checkpoint every 400 steps, on 1 and on 2
#     ranks.
#  2. The same deck and schedule, killed with kill -9 (mpiexec and the ranks) after a
#     checkpoint inside fix_rattlers, restarted from it, killed again after a later one,
#     restarted to the end. Both restarts must resume inside fix_rattlers (the log says
#     "inside stage 2 'fixed'").
#  3. final.h5 equals the uninterrupted one bit for bit (tests/support/same_state.py), and
#     report.json has the same stage values: the frame holds the rattlers found at the stage
#     start and the loop counters, the checkpoint the backbone contacts' stage-start state
#     (docs/long-jobs.md). (Stop signals: tests/cli/restart_signal_exact.sh.)
set -u
: "${GRANPACK_EXE:?}" "${GRANPACK_SOURCE_DIR:?}"
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
. "$GRANPACK_SOURCE_DIR/tests/support/restart_chain.sh"
restart_scratch   # $scratch, $pid, stop_run, and the EXIT trap
deck=$scratch/fix.toml
cat > "$deck" <<'TOML'
[sample]
dimension = 3
n = 250
diameter = 1.0e-3
seed = 11
[material]
density = 2500.0
normal_law = "hertz"
young_modulus = 2.88e8
poisson_ratio = 0.3
friction = 0.3
damping = 0.98
[output]
log_every = 100000
[[stage]]
kind = "random"
phi = 0.45
[[stage]]
name = "D"
kind = "compress"
pressure = 1.0e4
inertia_max = 1.0e-2
max_steps = 6000
[[stage]]
name = "fixed"
kind = "fix_rattlers"
max_steps = 6025
TOML
run_options=(--checkpoint-every-steps 400 --checkpoint-every-seconds 0)
# leg [ARGS...]: a leg in the background, until it has written a new checkpoint inside
# fix_rattlers (stage 2).
leg() {
  local before; before=$(inside 2)
  start_leg "$@"
  wait_until 1200 0.05 '[ "$(inside 2)" -gt "$before" ]'
}

# chain NP: the uninterrupted run and the interrupted chain on NP ranks, compared. A failed
# step ends the chain (the next ones need its files); the other rank count still runs.
chain() {
  np=$1 whole=$scratch/whole$1 out=$scratch/chain$1
  t0=$(now)
  check_exit "$np rank(s): uninterrupted run" 0 "$whole.txt" run_deck "$whole" || return
  wall=$(elapsed $t0)
  out=$whole; whole_inside=$(inside 2); out=$scratch/chain$1

  leg; rc=$?
  check "$np rank(s): a checkpoint inside fix_rattlers (uninterrupted run: $wall s)" '[ $rc -eq 0 ]' \
    || { tail "$scratch/chain.txt"; return; }
  stop_run   # kill -9
  echo "killed inside fix_rattlers; checkpoint at stage $(checkpoint_stage)"
  leg --restart "$out/checkpoint.h5"; rc=$?
  check "$np rank(s): a second checkpoint inside fix_rattlers" '[ $rc -eq 0 ]' || { tail "$scratch/chain.txt"; return; }
  stop_run
  echo "killed inside fix_rattlers again; checkpoint at stage $(checkpoint_stage)"
  check_exit "$np rank(s): last restart" 0 "$scratch/last.txt" run_deck "$out" --restart "$out/checkpoint.h5" || return
  echo "uninterrupted run $wall s with $whole_inside checkpoints inside fix_rattlers; the chain wrote $(inside 2)"
  resumed=$(grep -c "inside stage 2 'fixed'" "$out/log.txt")
  check "$np rank(s): both restarts resumed inside fix_rattlers ($resumed)" '[ "$resumed" -eq 2 ]' \
    || grep "restart from" "$out/log.txt"
  grep "resumed after" "$out/log.txt"

  check "$np rank(s): the chain ends as the uninterrupted run (final.h5 bit for bit, report.json)" \
    'same_run "$whole" "$out" "$np"'
}
over_ranks
checks_done "restart fix_rattlers"
