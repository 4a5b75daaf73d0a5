#!/usr/bin/env bash
# `granpack run` refuses bad input end to end, on 2 ranks (validation must stop every rank
# together): exit code 2, the error printed once (by rank 0), a message naming the file, the
# key with its table path, the value and what is allowed (tests/decks/bad/unknown_key.toml: its
# first line "# expect: REGEX"), and nothing written (the output directory must not exist
# afterwards). An unknown command-line option is bad input too (exit 2).
# Every deck of tests/decks/bad/ (unknown_key and the TOML syntax error included), and a deck
# file that does not exist, are refused in-process by load_deck_collectively, as `run` loads
# its deck, with the same messages on every rank (tests/mpi/deck_parse.cpp: BadDeck.*,
# BadDeckFile.*, on 1 and 2 ranks), so this script starts mpiexec once. No deck is refused
# with exit code 3 (not implemented): cli.stiffness checks that code end to end.
set -u
: "${GRANPACK_EXE:?}" "${GRANPACK_SOURCE_DIR:?}"
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
cli_scratch

name=unknown_key
deck="$GRANPACK_SOURCE_DIR/tests/decks/bad/$name.toml"
expect=$(head -1 "$deck" | sed -n 's/^# expect: //p')
check "$name.toml has a first line '# expect: REGEX'" '[ -n "$expect" ]'
out="$scratch/out_$name"
check_refused "$name" 2 "$expect" "$scratch/$name.txt" granpack_on 2 run "$deck" -o "$out"
check "$name: no output directory for a rejected deck" '[ ! -e "$out" ]'
check "$name: the error is printed once (by rank 0)" \
  '[ "$(grep -c "granpack: error" "$scratch/$name.txt")" -eq 1 ]' || cat "$scratch/$name.txt"
# An unknown option is bad input (exit 2).
check_exit "unknown option" 2 "$scratch/option.txt" "$GRANPACK_EXE" run --frobnicate x
checks_done "bad decks"
