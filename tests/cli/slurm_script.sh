#!/usr/bin/env bash
# jobs/slurm/granpack.sbatch outside Slurm: srun and scontrol replaced by stand-ins (srun runs
# the command on one MPI rank; scontrol records its arguments), on a short deck
# (tests/support/restart_chain.sh short_deck). The run is held at step 3000
# (GRANPACK_FAULT=hold, docs/long-jobs.md) until the signal comes, so each signal lands inside
# the compression on any machine load.
#  1. SIGUSR1 to the script (Slurm's --signal=B:USR1 before the wall-time limit): granpack
#     checkpoints, exit 75, the script requeues its job (scontrol requeue <job id>).
#  2. SIGTERM to the script and to the ranks (scancel or preemption): granpack checkpoints,
#     exit 75, the script waits for it instead of dying and does not requeue.
#  3. The script run again on the first directory continues from its checkpoint to the end:
#     exit 0, "deck done".
# ctest: PROCESSORS 1
set -u
: "${GRANPACK_EXE:?}" "${GRANPACK_SOURCE_DIR:?}"
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
. "$GRANPACK_SOURCE_DIR/tests/support/restart_chain.sh"
cli_scratch 'pkill -9 -f -- "$scratch/" 2>/dev/null'
deck=$scratch/deck.toml
short_deck "$deck"
mkdir -p "$scratch/bin"
cat > "$scratch/bin/srun" <<'SH'
#!/usr/bin/env bash
exec mpiexec -n 1 "$@"
SH
cat > "$scratch/bin/scontrol" <<SH
#!/usr/bin/env bash
echo "\$*" >> "$scratch/scontrol.txt"
SH
chmod +x "$scratch/bin/srun" "$scratch/bin/scontrol"
sbatch_script=$GRANPACK_SOURCE_DIR/jobs/slurm/granpack.sbatch
export PATH=$scratch/bin:$PATH SLURM_JOB_ID=4242 GRANPACK=$GRANPACK_EXE DECK=$deck

# leg OUT LOG [FAULT]: the script in the background ($pid), GRANPACK_FAULT=FAULT if given.
leg() {
  OUT=$1 GRANPACK_FAULT=${3:-} bash "$sbatch_script" < /dev/null > "$2" 2>&1 &
  pid=$!
}
holding() { wait_until 3000 0.1 "grep -q 'holds at step 3000 until a stop signal' '$1'"; }

# 1. SIGUSR1 to the script.
leg "$scratch/a" "$scratch/a.txt" hold:3000
holding "$scratch/a.txt"
kill -USR1 $pid
wait $pid; code=$?
check "SIGUSR1: exit $code (expected 75), a checkpoint, the job requeued" \
  '[ $code -eq 75 ] && [ -f "$scratch/a/checkpoint.h5" ] && grep -q "checkpointed; requeueing" "$scratch/a.txt" &&
   [ "$(cat "$scratch/scontrol.txt" 2>/dev/null)" = "requeue 4242" ]' || { cat "$scratch/a.txt"; cat "$scratch/scontrol.txt"; }

# 2. SIGTERM to the script and to the rank, as scancel does.
leg "$scratch/b" "$scratch/b.txt" hold:3000
holding "$scratch/b.txt"
kill -TERM $pid
for p in $(pgrep -f -- "-o $scratch/b "); do
  [ "$(cat /proc/$p/comm 2>/dev/null)" = granpack ] && kill -TERM $p
done
wait $pid; code=$?
while kill -0 $pid 2>/dev/null; do wait $pid; code=$?; done
check "SIGTERM: exit $code (expected 75), a checkpoint, no requeue" \
  '[ $code -eq 75 ] && [ -f "$scratch/b/checkpoint.h5" ] && grep -q "checkpointed after SIGTERM" "$scratch/b.txt" &&
   [ "$(wc -l < "$scratch/scontrol.txt")" -eq 1 ]' || { cat "$scratch/b.txt"; cat "$scratch/scontrol.txt"; }

# 3. The requeued leg: continues from the checkpoint to the end.
leg "$scratch/a" "$scratch/a2.txt"
wait $pid; code=$?
check "requeued leg: exit $code (expected 0), continued from the checkpoint, deck done" \
  '[ $code -eq 0 ] && grep -q "continuing from $scratch/a/checkpoint.h5" "$scratch/a2.txt" &&
   grep -q "deck done" "$scratch/a2.txt" && [ -f "$scratch/a/final.h5" ]' || cat "$scratch/a2.txt"
checks_done "slurm script"
