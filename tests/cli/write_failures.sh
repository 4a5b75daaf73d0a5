#!/usr/bin/env bash
# ctest: RANKS 1 2   (one ctest entry per rank count: GRANPACK_TEST_RANKS)
# A write that fails (disk full, quota, file size limit) stops every rank together, never hangs
# and never crashes: exit code 74, one message naming the file and the cause, no temporary file
# left, the previous checkpoint untouched (docs/long-jobs.md, "Exit codes"). On 1 and 2 ranks,
# restarting from a checkpoint of a small compression:
#  - into a 2 MB tmpfs filled up to a few kB, with checkpoints off: the final write fails;
#  - the same with a checkpoint every 50 steps: the first checkpoint write fails (it waits for
#    the next neighbour-list rebuild, at most 1000 steps: the stage is cut at 1500 steps);
#  - under `ulimit -f` (a file size limit: SIGXFSZ is ignored, write() fails with EFBIG), the
#    checkpoint write and the final write fail. On 2 ranks this also checks that the halo's
#    shared-memory window (the default), whose backing file would pass the limit, is given up
#    for messages instead of aborting the job inside Open MPI (comm/shared_window.h).
# The tmpfs needs root (mount); without it those cases are skipped with a message, the
# ulimit ones still run. Each run has a hard timeout (300 s) that only a hang reaches.
set -u
: "${GRANPACK_EXE:?}" "${GRANPACK_SOURCE_DIR:?}"
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
mnt=
cli_scratch '[ -n "$mnt" ] && umount "$mnt"'
deck=$scratch/small.toml
sed -e 's/^log_every = .*/log_every = 100000/' \
    -e 's/^inertia_max = 1.0e-2$/inertia_max = 1.0e-2\nmax_steps = 1500/' \
    "$GRANPACK_SOURCE_DIR/jobs/decks/ci/gas_small.toml" > "$deck"
if mkdir -p "$scratch/tmpfs" && mount -t tmpfs -o size=2m granpack_test "$scratch/tmpfs" 2> "$scratch/mount.txt"
then mnt=$scratch/tmpfs
else echo "SKIPPED: the tmpfs cases (mount -t tmpfs not permitted: $(head -1 "$scratch/mount.txt"))"
fi

# fill KB: fills $mnt up to KB kB free (a filler file).
fill() {
  rm -f "$mnt/filler"
  local avail; avail=$(df --output=avail -k "$mnt" | tail -1)
  head -c $(( (avail - $1) * 1024 )) /dev/zero > "$mnt/filler" 2> /dev/null
}
# limit: empty, or "limited KB": each rank (not mpiexec, whose PMIx files are larger) under a
# file size limit of KB kB (ulimit -f).
limit=()
# failing_run NAME WHAT OUT [ARGS...]: a restart from $base/checkpoint.h5 copied to OUT, which
# must fail to write OUT/WHAT: exit 74 (not the timeout's 124), the message printed once,
# naming the file and a cause (ENOSPC or EFBIG), no temporary file in OUT, and OUT's
# checkpoint.h5 still the one copied there, readable.
failing_run() {
  local name="$np rank(s), $1" what=$2 out=$3 log=$scratch/run.txt; shift 3
  local exe=("$GRANPACK_EXE")
  # Under ulimit -f, Open MPI's defaults: the tests' shared-memory transport (vader, chosen in
  # tests/CMakeLists.txt for its quick start) backs its segment with a file larger than the limit.
  local mpi_env=()
  [ ${#limit[@]} -gt 0 ] && exe=(bash -c 'ulimit -f "$0" && exec "$@"' "${limit[1]}" "$GRANPACK_EXE") \
    && mpi_env=(-u OMPI_MCA_pml -u OMPI_MCA_btl)
  check_exit "$name" 74 "$log" env "${mpi_env[@]}" timeout 300 mpiexec -n "$np" "${exe[@]}" run "$deck" -o "$out" -q \
    --checkpoint-every-seconds 0 --restart "$out/checkpoint.h5" "$@"
  check "$name: one message naming $what and the cause" \
    '[ "$(grep -c "error: cannot write $out/$what: .*\(No space left on device\|File too large\)" "$log")" -eq 1 ]' \
    || cat "$log"
  check "$name: no temporary file left" '! ls "$out" | grep -q "\.tmp$"' || ls -l "$out"
  check "$name: the previous checkpoint is untouched and readable" \
    'cmp -s "$base/checkpoint.h5" "$out/checkpoint.h5" && "$GRANPACK_EXE" info "$out/checkpoint.h5" > /dev/null' \
    || ls -l "$out"
  [ "$what" = final.h5 ] && check "$name: no final.h5" '[ ! -e "$out/final.h5" ]'
}

for np in ${GRANPACK_TEST_RANKS:-1 2}; do
  # A checkpoint inside the compression, left by a run killed in its next checkpoint write.
  base=$scratch/base$np
  GRANPACK_FAULT=checkpoint_datasets:3 timeout 300 mpiexec -n $np "$GRANPACK_EXE" run "$deck" -o "$base" -q \
    --checkpoint-every-steps 100 --checkpoint-every-seconds 0 < /dev/null > "$scratch/base.txt" 2>&1
  check "$np rank(s): a checkpoint to restart from" '"$GRANPACK_EXE" info "$base/checkpoint.h5" > /dev/null 2>&1' \
    || { tail "$scratch/base.txt"; continue; }
  size_kb=$(( $(stat -c %s "$base/checkpoint.h5") / 1024 ))
  if [ -n "$mnt" ]; then
    out=$mnt/final$np; mkdir -p "$out"; cp "$base/checkpoint.h5" "$out/"
    fill $((size_kb / 3))
    failing_run "disk full during the final write" final.h5 "$out" --checkpoint-every-steps 0
    rm -rf "$out"
    out=$mnt/checkpoint$np; mkdir -p "$out"; cp "$base/checkpoint.h5" "$out/"
    fill $((size_kb / 3))
    failing_run "disk full during a checkpoint" checkpoint.h5 "$out" --checkpoint-every-steps 50
    rm -rf "$out" "$mnt/filler"
  fi
  out=$scratch/limit$np; mkdir -p "$out"; cp "$base/checkpoint.h5" "$out/"
  limit=(limited $((size_kb / 2)))
  failing_run "ulimit -f during a checkpoint" checkpoint.h5 "$out" --checkpoint-every-steps 50
  failing_run "ulimit -f during the final write" final.h5 "$out" --checkpoint-every-steps 0
  # On 2 ranks the halo's default shared-memory window would need a backing file beyond the
  # limit, which would abort the job inside Open MPI: the halo uses messages and says so.
  [ "$np" -gt 1 ] && check "$np rank(s), ulimit -f: the limit and the halo's fallback to messages are logged" \
    'grep -q "file size limit (ulimit -f) of $((size_kb / 2)) kB" "$out/log.txt"' && :
  limit=()
done
checks_done "write failures"
