#!/usr/bin/env bash
# ctest: RANKS 1 2   (one ctest entry per rank count: GRANPACK_TEST_RANKS)
# Checkpoints inside fix_rattlers continue exactly.
#  1. A small packing (random gas -> short compress) whose rattlers are pushed onto the frozen
#     backbone by fix_rattlers, uninterrupted, with a checkpoint every 400 steps, on 1 and on 2
#     ranks.
#  2. The same deck and schedule, killed (SIGKILL, injected: GRANPACK_FAULT=step:N, docs/
#     long-jobs.md) 200 steps after the first checkpoint inside fix_rattlers, restarted from
#     it, killed again 200 steps after the third, restarted to the end. The steps come from
#     the uninterrupted run's log, so every kill lands where it is meant to on any machine
#     load. Both restarts must resume inside fix_rattlers (the log says "inside stage 2
#     'fixed'").
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
{ small_deck 3 250 11; cat <<'TOML'
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
} > "$deck"
run_options=(--checkpoint-every-steps 400 --checkpoint-every-seconds 0)
# chain NP: the uninterrupted run and the interrupted chain on NP ranks, compared. A failed
# step ends the chain (the next ones need its files); the other rank count still runs.
chain() {
  np=$1 whole=$scratch/whole$1 out=$scratch/chain$1
  local restart=(--restart "$scratch/chain$1/checkpoint.h5") steps
  check_exit "$np rank(s): uninterrupted run" 0 "$whole.txt" run_deck "$whole" || return
  out=$whole; steps=($(checkpoint_steps 2)); out=$scratch/chain$1
  check "$np rank(s): the uninterrupted run wrote ${#steps[@]} checkpoints inside fix_rattlers (at least 4)" \
    '[ ${#steps[@]} -ge 4 ]' || return

  faulty_leg "killed at step $((steps[0] + 200)), inside fix_rattlers" "step:$((steps[0] + 200))" || return
  faulty_leg "killed at step $((steps[2] + 200)), inside fix_rattlers" "step:$((steps[2] + 200))" \
    "${restart[@]}" || return
  check_exit "$np rank(s): last restart" 0 "$scratch/last.txt" run_deck "$out" "${restart[@]}" || return
  resumed=$(grep -c "inside stage 2 'fixed'" "$out/log.txt")
  check "$np rank(s): both restarts resumed inside fix_rattlers ($resumed)" '[ "$resumed" -eq 2 ]' \
    || grep "restart from" "$out/log.txt"
  grep "resumed after" "$out/log.txt"

  check "$np rank(s): the chain ends as the uninterrupted run (final.h5 bit for bit, report.json)" \
    'same_run "$whole" "$out" "$np"'
}
over_ranks
checks_done "restart fix_rattlers"
