#!/usr/bin/env bash
# Every deck under jobs/decks and jobs/bench passes `granpack check` (the validation `run`
# does before any work), so a renamed or retired key cannot leave a deck that only fails
# when a long job starts. A deck whose `read` stage names a missing file, and a deck with an unknown key, are
# refused with exit 2, a message naming the file, and nothing written.
set -u
: "${GRANPACK_EXE:?}" "${GRANPACK_SOURCE_DIR:?}"
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
cli_scratch
# The decks written here and the runs' working directory; their logs go to $scratch.
mkdir "$scratch/work" && cd "$scratch/work"

# Relative `read` paths are taken from the working directory: the decks run from the source
# tree's root. One call for all (the first invalid deck stops it, named in the message).
# Decks that read the output of another run (out/..., e.g. the controlled experiments that start
# from an ensemble's packings, `file = "out/ens/C/sample_{seed}/A.h5"`) are checked from the
# directory $scratch/stand_in, where that output is stood in for by an empty file of the same
# path (one call for them all too).
mapfile -t decks < <(cd "$GRANPACK_SOURCE_DIR" && find jobs/decks jobs/bench -name '*.toml' | sort)
mapfile -t reads_out < <(cd "$GRANPACK_SOURCE_DIR" && grep -l '^file = "out/' "${decks[@]}")
own=()
for d in "${decks[@]}"; do [[ " ${reads_out[*]} " == *" $d "* ]] || own+=("$d"); done
n=${#decks[@]}
out=$(cd "$GRANPACK_SOURCE_DIR" && "$GRANPACK_EXE" check "${own[@]}" 2>&1); rc=$?
stand_in=$scratch/stand_in
for d in "${reads_out[@]}"; do
  f=$(sed -n 's/^file = "\(out\/[^"]*\)".*/\1/p' "$GRANPACK_SOURCE_DIR/$d" | sed 's/{seed}/1/g')
  mkdir -p "$stand_in/$(dirname "$f")" && : > "$stand_in/$f"
done
if [ ${#reads_out[@]} -gt 0 ]; then
  out+=$'\n'$(cd "$stand_in" && "$GRANPACK_EXE" check "${reads_out[@]/#/$GRANPACK_SOURCE_DIR/}" 2>&1) || rc=$?
fi
check "check of the $n decks: exit 0 (got $rc: $out)" '[ $rc -eq 0 ]'
check "found the decks (got $n)" '[ $n -ge 20 ]'
check "one summary line per deck" \
  '[ $(grep -c ": ok, dimension [23], n = [0-9]*, [0-9]* stages:" <<<"$out") -eq $n ]'

# Several decks at once: one line each.
check_exit "two decks" 0 "$scratch/two.log" "$GRANPACK_EXE" check "$GRANPACK_SOURCE_DIR/jobs/decks/main.toml" \
  "$GRANPACK_SOURCE_DIR/jobs/decks/2d/method2_small.toml"
check "two decks: two lines" '[ $(grep -c ": ok," "$scratch/two.log") -eq 2 ]'

# A read stage whose file is missing.
cat > read_missing.toml <<'TOML'
[sample]
dimension = 2
n = 10
diameter = 1.0e-3
[material]
density = 2500.0
normal_law = "linear"
normal_stiffness = 1.0e5
friction = 0.5
damping = 0.8
[[stage]]
kind = "read"
file = "no_such_packing.h5"
TOML
check_refused "missing read file, naming deck, stage and file" 2 \
  "read_missing.toml: stage 0 .read. \(read\): file .no_such_packing.h5. does not exist" "$scratch/missing.log" \
  "$GRANPACK_EXE" check read_missing.toml

# On 2 ranks (rank 0 reads and broadcasts): the same lines, and the same refusal without a hang.
cd "$GRANPACK_SOURCE_DIR"
check_exit "2 ranks" 0 "$scratch/np2.log" granpack_on 2 check jobs/decks/main.toml jobs/decks/2d/collapse/seriesA_P0.01.toml
cd "$scratch/work"
check "2 ranks: one line per deck, printed once" '[ $(grep -c ": ok," "$scratch/np2.log") -eq 2 ]'
check_exit "2 ranks, missing read file" 2 "$scratch/np2_missing.log" \
  timeout 120 mpiexec -n 2 "$GRANPACK_EXE" check read_missing.toml
check "2 ranks, missing read file: said once" '[ $(grep -c "does not exist" "$scratch/np2_missing.log") -eq 1 ]'

# An unknown key: the parser's message (file:line, key), as `run` gives it.
sed 's/^friction = 0.5/frictoin = 0.5/' read_missing.toml > typo.toml
check_refused "unknown key, named" 2 "frictoin" "$scratch/typo.log" "$GRANPACK_EXE" check typo.toml
check "nothing written" '[ "$(ls | sort | tr "\n" " ")" = "read_missing.toml typo.toml " ]'

checks_done decks_check "($n decks)"
