#!/usr/bin/env bash
# ctest: RANKS 1 2   (one ctest entry per rank count: GRANPACK_TEST_RANKS)
# Checkpoint/restart on the same rank count is exact, and checkpoints survive a rank's death
# wherever it lands. The deaths are injected (GRANPACK_FAULT, docs/long-jobs.md "Fault
# injection"): a rank kills itself with SIGKILL at a named point, so every kill lands exactly
# where this test means it to, on any machine load (no sleeps, no counting of lucky kills).
#  1. A short deck (random gas -> compress -> three pressure steps), uninterrupted, with a
#     checkpoint every 150 steps, on 1 and on 2 ranks.
#  2. The same deck and schedule, killed four times, restarted after each kill from the newest
#     checkpoint: inside a checkpoint write (after the particle datasets), between a complete
#     write and its rename, in the step's all-reduce (on 2 ranks: rank 1 dies while rank 0
#     waits in it), and at a step of the last stage. After each kill: the run ended (no hang:
#     a hard timeout that only a hang reaches), the fault's message says it fired, and
#     checkpoint.h5 is readable and is the newest one log.txt reports written.
#  3. final.h5 of the chain equals the uninterrupted one bit for bit (tests/support/
#     same_state.py) and report.json has the same stage values.
set -u
: "${GRANPACK_EXE:?}" "${GRANPACK_SOURCE_DIR:?}"
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
. "$GRANPACK_SOURCE_DIR/tests/support/restart_chain.sh"
restart_scratch   # $scratch, $pid, stop_run, and the EXIT trap
deck=$scratch/restart.toml
short_deck "$deck"
run_options=(--checkpoint-every-steps 150 --checkpoint-every-seconds 0)
# faulty_leg (tests/support/restart_chain.sh): a leg killed by GRANPACK_FAULT, then checked.

# chain NP: the uninterrupted run and the interrupted chain on NP ranks, compared. A failed
# step ends the chain (the next ones need its files); the other rank count still runs.
chain() {
  np=$1 whole=$scratch/whole$1 out=$scratch/chain$1
  local last_rank=$(($1 - 1)) restart=(--restart "$scratch/chain$1/checkpoint.h5")
  check_exit "$np rank(s): uninterrupted run" 0 "$whole.txt" run_deck "$whole" || return
  local steps; steps=$(final_step "$whole/final.h5")
  # 1. Inside the third checkpoint write (the first is between the random and compress
  # stages): the temporary file stays behind, half written; the second checkpoint is intact.
  faulty_leg "killed inside a checkpoint write" checkpoint_datasets:3 || return
  check "$np rank(s): the half-written temporary file is there" '[ -f "$out/checkpoint.h5.tmp" ]'
  # 2. The leg's second checkpoint complete on every rank, not yet renamed: the complete
  # temporary file is there, checkpoint.h5 is still the first one.
  faulty_leg "killed between a checkpoint write and its rename" checkpoint_rename:2 "${restart[@]}" || return
  check "$np rank(s): the complete temporary file is there and readable" \
    '"$GRANPACK_EXE" info "$out/checkpoint.h5.tmp" > /dev/null 2>&1'
  # 3. In the all-reduce of the leg's 400th step: on 2 ranks, rank 1 dies while rank 0 waits.
  faulty_leg "killed in a collective" "collective:400@$last_rank" "${restart[@]}" || return
  # 4. At a step of the last stage (pressure_steps): 250 steps before the end.
  faulty_leg "killed at step $((steps - 250))" "step:$((steps - 250))" "${restart[@]}" || return
  check_exit "$np rank(s): last restart" 0 "$scratch/last.txt" run_deck "$out" "${restart[@]}" || return
  check "$np rank(s): every leg restarted where the previous one left (4 restarts)" \
    '[ "$(grep -c "^restart from" "$out/log.txt")" -eq 4 ]'
  check "$np rank(s): the killed-and-restarted chain ends as the uninterrupted run" \
    'same_run "$whole" "$out" "$np"' || tail -30 "$scratch/chain.txt"
}
over_ranks
checks_done "restart kill"
