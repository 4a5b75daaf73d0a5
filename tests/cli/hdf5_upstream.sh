#!/usr/bin/env bash
# The three files of tests/fuzz/hdf5_upstream/ crash (SIGSEGV), hang or take 21 GB inside
# HDF5 1.10.8 itself when it converts a variable-length string attribute (docs/fuzzing.md).
# granpack checks the stored string reference and its global heap collection first
# (src/io/hdf5_string_guard.cpp), so `granpack info` refuses each with exit code 2 and a
# message naming the file and the attribute, within seconds and a 4 GiB address space.
# End to end here, the one that needs the address-space cap (vlen_string_21GB.h5) on 2 ranks:
# exit code 2 and the message printed by rank 0, not a hang (a hard timeout of 300 s, which
# only a hang reaches: the refusal takes about half a second; the time is printed, not
# asserted, so that a loaded machine cannot fail the test). All three files, on 1 and 2
# ranks, are refused in-process with the same messages by every reader, `info`'s
# describe_file on all ranks together included, within 5 s each and a 4 GiB cap
# (tests/mpi/fuzz_inputs.cpp, FuzzRegressions.CorruptGlobalHeapsAreRefusedBeforeHdf5FollowsThem);
# every committed granpack file (docs/data/*.h5, jobs/runs/*/checkpoint.h5) still reads as
# `info` reads it (tests/mpi/hdf5_store.cpp, CommittedFiles.ReadAsInfoReadsThem), and
# cli.run_and_info runs `info` on a valid file end to end.
set -u
: "${GRANPACK_EXE:?}" "${GRANPACK_SOURCE_DIR:?}"
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
cli_scratch

name=vlen_string_21GB.h5
expect="variable-length string of 4294967041-byte characters"   # after "FILE: attribute /NAME: "
f=$GRANPACK_SOURCE_DIR/tests/fuzz/hdf5_upstream/$name
np=2
t0=$(now)
# timeout: a hang fails the test (exit 124, not 2) instead of stalling it; ulimit -v: so does
# a 21 GB allocation, without taking the machine's memory. Under ASan, whose shadow memory needs terabytes of
# address space, its allocator is capped at the same 4 GiB instead.
capped() {
  (if [[ ${GRANPACK_SANITIZE:-} == *address* ]]; then
     export ASAN_OPTIONS="${ASAN_OPTIONS:-}${ASAN_OPTIONS:+:}max_allocation_size_mb=4096:allocator_may_return_null=1"
   else ulimit -v 4194304; fi
   exec "$@")
}
check_exit "$name, $np rank(s)" 2 "$scratch/msg.txt" capped timeout 300 mpiexec -n $np "$GRANPACK_EXE" info "$f"
secs=$(elapsed $t0)
echo "$name on $np rank(s): exit $rc in $secs s"
# The first line of the message, as rank 0 prints it.
line=$(grep -m1 "$f: " "$scratch/msg.txt")
check "$name, $np rank(s): the message names the file, the attribute and '$expect'" \
  '[[ "$line" == *"$f: attribute /"*": "*"$expect"* ]]' || cat "$scratch/msg.txt"
check "$name, $np rank(s): printed once (by rank 0)" '[ "$(grep -c "$f: " "$scratch/msg.txt")" -eq 1 ]' \
  || cat "$scratch/msg.txt"

checks_done "hdf5 upstream"
