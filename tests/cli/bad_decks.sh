#!/usr/bin/env bash
# Every deck in tests/decks/bad/ must be refused with exit code 2, a message matching its
# first line "# expect: REGEX" (the file, the key with its table path, the value, what is
# allowed), and nothing written: the output directory must not exist afterwards.
# Run on 2 ranks, because validation must stop every rank together.
set -u
: "${GRANPACK_EXE:?}" "${GRANPACK_SOURCE_DIR:?}"
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
fail=0; pass=0
for deck in "$GRANPACK_SOURCE_DIR"/tests/decks/bad/*.toml; do
  name=$(basename "$deck" .toml)
  expect=$(head -1 "$deck" | sed -n 's/^# expect: //p')
  out="$scratch/out_$name"
  msg=$(mpiexec -n 2 "$GRANPACK_EXE" run "$deck" -o "$out" 2>&1)
  code=$?
  if [ "$code" -ne 2 ]; then
    echo "FAIL $name: exit code $code, expected 2"; echo "$msg" | head -5; fail=$((fail+1)); continue
  fi
  if ! grep -Eq -- "$expect" <<<"$msg"; then
    echo "FAIL $name: message does not match /$expect/:"; echo "$msg" | head -5; fail=$((fail+1)); continue
  fi
  if [ -e "$out" ]; then
    echo "FAIL $name: output directory was created for a rejected deck"; fail=$((fail+1)); continue
  fi
  if [ "$(grep -c 'granpack: error' <<<"$msg")" -ne 1 ]; then
    echo "FAIL $name: the error must be printed once (by rank 0), got:"; echo "$msg"; fail=$((fail+1)); continue
  fi
  pass=$((pass+1))
done
# A deck that does not exist is bad input too.
msg=$(mpiexec -n 2 "$GRANPACK_EXE" run "$scratch/nope.toml" -o "$scratch/o" 2>&1); code=$?
if [ $code -eq 2 ] && grep -q "nope.toml: cannot open the deck file" <<<"$msg"; then pass=$((pass+1));
else echo "FAIL missing deck: exit $code: $msg"; fail=$((fail+1)); fi
# An unknown option is bad input (exit 2).
"$GRANPACK_EXE" run --frobnicate x >/dev/null 2>&1; code=$?
if [ $code -eq 2 ]; then pass=$((pass+1)); else echo "FAIL unknown option: exit $code"; fail=$((fail+1)); fi
echo "bad decks: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
