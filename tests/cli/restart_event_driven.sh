#!/usr/bin/env bash
# ctest: RANKS 1 2   (one ctest entry per rank count: GRANPACK_TEST_RANKS)
# Checkpoints inside the event-driven stages (ed_gas, ls_compress) continue exactly.
#  1. An FCC lattice melted by ed_gas (75 pieces of 2000 collisions) and grown by ls_compress
#     (about 125 pieces), uninterrupted and without any checkpoint, on 1 and on 2 ranks (rank 0
#     runs the engine; the others take part in the checkpoint polls and writes).
#  2. The same deck, stopped and killed where GRANPACK_FAULT says (docs/long-jobs.md, "Fault
#     injection"), so every stop lands in the stage it is meant for on any machine load:
#     held at piece 40 of ed_gas and stopped by SIGUSR1 (exit 75, a checkpoint inside ed_gas);
#     restarted and killed (SIGKILL) 20 pieces later; restarted, held at piece 90 (past the
#     35 left of ed_gas, inside ls_compress) and stopped by SIGUSR1; restarted and killed 10
#     pieces later; restarted to the end.
#  3. final.h5 equals the uninterrupted one bit for bit (tests/support/same_state.py), and
#     report.json has the same stage values: the engine's complete state is saved, so neither
#     the checkpoints nor their instants change the trajectory (docs/long-jobs.md).
set -u
: "${GRANPACK_EXE:?}" "${GRANPACK_SOURCE_DIR:?}"
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
. "$GRANPACK_SOURCE_DIR/tests/support/restart_chain.sh"
restart_scratch   # $scratch, $pid, stop_run, and the EXIT trap
deck=$scratch/ed.toml
cat > "$deck" <<'TOML'
[sample]
dimension = 3
n = 500
diameter = 1.0e-3
seed = 3
[material]
density = 2500.0
young_modulus = 70.0e9
poisson_ratio = 0.3
friction = 0.3
damping = 0.98
[[stage]]
kind = "lattice"
lattice = "fcc"
phi = 0.45
cells = [5, 5, 5]
[[stage]]
name = "melt"
kind = "ed_gas"
collisions_per_grain = 600
[[stage]]
name = "ls"
kind = "ls_compress"
phi = 0.60
report_phi = [0.52]
growth_rate = 3.0e-3
TOML
run_options=(--checkpoint-every-seconds 0)   # no checkpoint but those the stops write

# chain NP: the uninterrupted run and the interrupted chain on NP ranks, compared. A failed
# step ends the chain (the next ones need its files); the other rank count still runs.
chain() {
  np=$1 whole=$scratch/whole$1 out=$scratch/chain$1
  local restart=(--restart "$scratch/chain$1/checkpoint.h5")
  check_exit "$np rank(s): uninterrupted run" 0 "$whole.txt" run_deck "$whole" || return

  held_leg "stopped at piece 40 of ed_gas" piece_hold:40 || return
  check "$np rank(s): the checkpoint is inside ed_gas" '[ "$(checkpoint_stage | cut -d" " -f1)" = 1 ]' \
    || { echo "checkpoint at stage $(checkpoint_stage)"; return; }
  faulty_leg "killed 20 pieces after the restart inside ed_gas" piece:20 "${restart[@]}" || return
  held_leg "stopped at piece 90 of ls_compress" piece_hold:90 "${restart[@]}" || return
  check "$np rank(s): the checkpoint is inside ls_compress" '[ "$(checkpoint_stage | cut -d" " -f1)" = 2 ]' \
    || { echo "checkpoint at stage $(checkpoint_stage)"; return; }
  faulty_leg "killed 10 pieces after the restart inside ls_compress" piece:10 "${restart[@]}" || return
  check_exit "$np rank(s): last restart" 0 "$scratch/last.txt" run_deck "$out" "${restart[@]}" || return
  in_melt=$(grep -c "inside stage 1 'melt'" "$out/log.txt") in_ls=$(grep -c "inside stage 2 'ls'" "$out/log.txt")
  check "$np rank(s): two restarts resumed inside ed_gas ($in_melt)" '[ "$in_melt" -eq 2 ]' || grep "restart from" "$out/log.txt"
  check "$np rank(s): two restarts resumed inside ls_compress ($in_ls)" '[ "$in_ls" -eq 2 ]' || grep "restart from" "$out/log.txt"

  check "$np rank(s): the chain ends as the uninterrupted run (final.h5 bit for bit, report.json)" \
    'same_run "$whole" "$out" "$np"'
}
over_ranks
bad_fault() { GRANPACK_FAULT=pieces:3 granpack_on 1 run "$deck" -o "$scratch/bad_fault" -q; }
check_refused "an unknown fault point refused (exit 2), naming the points" 2 "unknown point 'pieces'.*piece_hold" \
  "$scratch/bad_fault.txt" bad_fault
checks_done "restart event driven"
