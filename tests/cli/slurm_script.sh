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
#     exit 0, "deck done"; srun got the default placement options.
#  4. DRY_RUN=1 (no allocation needed): the layout of a 4-node ensemble as the script
#     computes it, and the layouts it refuses with exit 2 (a sample straddling two nodes, a
#     sample size that does not divide the ranks, uneven nodes), without running anything.
# ctest: PROCESSORS 1
set -u
: "${GRANPACK_EXE:?}" "${GRANPACK_SOURCE_DIR:?}"
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
. "$GRANPACK_SOURCE_DIR/tests/support/restart_chain.sh"
cli_scratch 'pkill -9 -f -- "$scratch/" 2>/dev/null'
deck=$scratch/deck.toml
short_deck "$deck"
mkdir -p "$scratch/bin"
cat > "$scratch/bin/srun" <<SH
#!/usr/bin/env bash
# srun's own options (SRUN_OPTIONS) are recorded, then dropped.
while [[ \$1 == --* ]]; do echo "\$1" >> "$scratch/srun_options.txt"; shift; done
exec mpiexec -n 1 "\$@"
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
check "srun placed the ranks in blocks, one core each (SRUN_OPTIONS default)" \
  'grep -qx -- "--distribution=block:block" "$scratch/srun_options.txt" && grep -qx -- "--cpu-bind=cores" "$scratch/srun_options.txt"' \
  || cat "$scratch/srun_options.txt"

# 4. Dry runs: NODES TASKS SAMPLES RANKS_PER_SAMPLE; the script's output to $scratch/dry.txt.
dry() {
  SLURM_JOB_NUM_NODES=$1 SLURM_NTASKS=$2 SAMPLES=$3 RANKS_PER_SAMPLE=$4 DRY_RUN=1 OUT=$scratch/dry \
    bash "$sbatch_script" < /dev/null > "$scratch/dry.txt" 2>&1
}
dry 4 128 16 8; code=$?
check "dry run, 4 nodes x 32: 16 samples of 8 ranks, 4 per node, nothing run (exit $code)" \
  '[ $code -eq 0 ] && grep -q "4 node(s) x 32 rank(s) = 128 rank(s): 16 sample(s) of 8 rank(s), 16 at a time in 1 wave(s), 4 per node" "$scratch/dry.txt" &&
   grep -q "dry run: srun --distribution=block:block --cpu-bind=cores .* --samples 16 --first-seed 1 --restart --ranks-per-sample 8" "$scratch/dry.txt" &&
   [ ! -e "$scratch/dry" ]' || cat "$scratch/dry.txt"
dry 2 64 40 2; code=$?
check "dry run, 40 samples of 2 ranks on 64: 32 at a time in 2 waves (exit $code)" \
  '[ $code -eq 0 ] && grep -q "40 sample(s) of 2 rank(s), 32 at a time in 2 wave(s), 16 per node" "$scratch/dry.txt"' || cat "$scratch/dry.txt"
# dry_refused NAME NODES TASKS SAMPLES RANKS_PER_SAMPLE MESSAGE: a layout refused with exit 2.
dry_refused() {
  local name=$1 message=$6; shift
  dry "$@"; code=$?
  check "dry run refused: $name (exit $code)" '[ $code -eq 2 ] && grep -q "$message" "$scratch/dry.txt"' \
    || cat "$scratch/dry.txt"
}
dry_refused "a sample of 12 ranks straddles nodes of 32" 3 96 8 12 \
  "a sample of 12 ranks would straddle two nodes (32 ranks per node)"
dry_refused "24 ranks per sample do not divide 128" 4 128 16 24 "RANKS_PER_SAMPLE = 24 does not divide the 128 ranks"
dry_refused "100 ranks on 3 nodes" 3 100 4 1 "100 ranks on 3 nodes is not the same count on every node"
checks_done "slurm script"
