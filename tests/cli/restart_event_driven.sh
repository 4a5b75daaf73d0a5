#!/usr/bin/env bash
# Checkpoints inside the event-driven stages (ed_gas, ls_compress) continue exactly.
#  1. An FCC lattice melted by ed_gas and grown by ls_compress, uninterrupted and without any
#     checkpoint, on 1 and on 2 ranks (rank 0 runs the engine; the others take part in the
#     checkpoint polls and writes).
#  2. The same deck with a checkpoint every 0.1 s of wall time: killed with kill -9 (mpiexec
#     and the ranks) after a checkpoint inside ed_gas, restarted; stopped with SIGUSR1 (exit
#     75) after a checkpoint inside ls_compress, restarted to the end.
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
collisions_per_grain = 1500
[[stage]]
name = "ls"
kind = "ls_compress"
phi = 0.60
report_phi = [0.52]
growth_rate = 3.0e-3
TOML
# leg STAGE [ARGS...]: a leg with a checkpoint every 0.1 s of wall time, in the background,
# until it has written a checkpoint inside stage STAGE.
leg() {
  local stage=$1; shift
  local before; before=$(inside)
  start_leg --checkpoint-every-seconds 0.1 "$@"
  wait_until 600 0.05 '[ "$(inside)" -gt "$before" ] &&
    [ "$(grep "^stage " "$out/log.txt" | tail -1 | cut -d" " -f2)" = "$stage" ]'
}

# chain NP: the uninterrupted run and the interrupted chain on NP ranks, compared. A failed
# step ends the chain (the next ones need its files); the other rank count still runs.
chain() {
  np=$1 whole=$scratch/whole$1 out=$scratch/chain$1
  t0=$(now)
  check_exit "$np rank(s): uninterrupted run" 0 "$whole.txt" run_deck "$whole" --checkpoint-every-seconds 0 || return
  wall=$(elapsed $t0)

  leg 1; rc=$?
  check "$np rank(s): a checkpoint inside ed_gas (uninterrupted run: $wall s)" '[ $rc -eq 0 ]' \
    || { tail "$scratch/chain.txt"; return; }
  stop_run   # kill -9
  echo "killed inside ed_gas; checkpoint at stage $(checkpoint_stage)"
  leg 2 --restart "$out/checkpoint.h5"; rc=$?
  check "$np rank(s): a checkpoint inside ls_compress" '[ $rc -eq 0 ]' || { tail "$scratch/chain.txt"; return; }
  kill -USR1 $pid
  wait $pid; code=$?; pid=
  check "$np rank(s): SIGUSR1 inside ls_compress: exit $code (expected 75)" '[ $code -eq 75 ]' \
    || { tail "$scratch/chain.txt"; return; }
  echo "stopped inside ls_compress (exit 75); checkpoint at stage $(checkpoint_stage)"
  check_exit "$np rank(s): last restart" 0 "$scratch/last.txt" \
    run_deck "$out" --checkpoint-every-seconds 0.1 --restart "$out/checkpoint.h5" || return
  echo "uninterrupted run $wall s; the chain wrote $(inside) checkpoints inside a stage"
  in_melt=$(grep -c "inside stage 1 'melt'" "$out/log.txt") in_ls=$(grep -c "inside stage 2 'ls'" "$out/log.txt")
  check "$np rank(s): a restart resumed inside ed_gas" '[ "$in_melt" -gt 0 ]' || grep "restart from" "$out/log.txt"
  check "$np rank(s): a restart resumed inside ls_compress" '[ "$in_ls" -gt 0 ]' || grep "restart from" "$out/log.txt"

  check "$np rank(s): the chain ends as the uninterrupted run (final.h5 bit for bit, report.json)" \
    'same_run "$whole" "$out" "$np"'
}
over_ranks
checks_done "restart event driven"
