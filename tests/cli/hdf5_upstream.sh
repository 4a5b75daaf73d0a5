#!/usr/bin/env bash
# The three files of tests/fuzz/hdf5_upstream/ crash (SIGSEGV), hang or take 21 GB inside
# HDF5 1.10.8 itself when it converts a variable-length string attribute (docs/fuzzing.md).
# granpack checks the stored string reference and its global heap collection first
# (src/io/hdf5_string_guard.cpp), so `granpack info` refuses each with exit code 2 and a
# message naming the file and the attribute, within seconds and a 4 GiB address space, on 1
# and 2 ranks. Every committed granpack file (docs/data/*.h5, jobs/runs/*/checkpoint.h5)
# still reads.
set -u
: "${GRANPACK_EXE:?}" "${GRANPACK_SOURCE_DIR:?}"
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
cli_scratch

# file|what the message must say after "FILE: attribute /format: "
cases="global_heap_hang.h5|object 0 at byte 456 of the collection claims 0 bytes, which is less than its own header
global_heap_segv.h5|object 8 at byte 192 of the collection claims 18446742974197923841 bytes, more than the collection's 4096
vlen_string_21GB.h5|variable-length string of 4294967041-byte characters"
while IFS='|' read -r name expect; do
  f=$GRANPACK_SOURCE_DIR/tests/fuzz/hdf5_upstream/$name
  for np in 1 2; do
    t0=$(date +%s.%N)
    # timeout: a hang fails the test instead of stalling it; ulimit -v: so does a 21 GB
    # allocation, without taking the machine's memory. Under ASan, whose shadow memory needs
    # terabytes of address space, its allocator is capped at the same 4 GiB instead.
    msg=$( (if [[ ${GRANPACK_SANITIZE:-} == *address* ]]; then
              export ASAN_OPTIONS="${ASAN_OPTIONS:-}${ASAN_OPTIONS:+:}max_allocation_size_mb=4096:allocator_may_return_null=1"
            else ulimit -v 4194304; fi
            timeout 20 mpiexec -n $np "$GRANPACK_EXE" info "$f" < /dev/null) 2>&1)
    code=$?
    secs=$(awk -v a=$t0 -v b=$(date +%s.%N) 'BEGIN { printf "%.2f", b - a }')
    echo "$name on $np rank(s): exit $code in $secs s"
    check "$name, $np rank(s): exit $code (want 2)" '[ $code -eq 2 ]' || echo "$msg"
    # The first line of the message, as rank 0 prints it.
    line=$(grep -m1 "$f: " <<<"$msg")
    check "$name, $np rank(s): the message names the file, the attribute and '$expect'" \
      '[[ "$line" == *"$f: attribute /"*": "*"$expect"* ]]' || echo "$msg"
    check "$name, $np rank(s): refused within 10 s ($secs s)" \
      '! awk -v s=$secs "BEGIN { exit !(s > 10) }"'
  done
done <<<"$cases"

# Valid files, written by this and earlier versions, still read.
n=0
for f in "$GRANPACK_SOURCE_DIR"/docs/data/*.h5 "$GRANPACK_SOURCE_DIR"/jobs/runs/*/checkpoint.h5; do
  [ -f "$f" ] || continue
  n=$((n + 1))
  "$GRANPACK_EXE" info "$f" > "$scratch/info.txt" 2>&1
  code=$?
  check "granpack info $f: exit $code, a particles line" \
    '[ $code -eq 0 ] && grep -q "^particles:" "$scratch/info.txt"' || cat "$scratch/info.txt"
done
check "committed .h5 files found to read: $n" '[ $n -ge 1 ]'
echo "valid committed files read: $n"

checks_done "hdf5 upstream"
