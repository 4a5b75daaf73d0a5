#!/usr/bin/env bash
# A run that goes bad stops every rank with a diagnosis (step, what, likely fix), exit code 1,
# and no hang: here contacts far too soft for the pressure (overlaps beyond 0.1 radius).
set -u
: "${GRANPACK_EXE:?}" "${GRANPACK_SOURCE_DIR:?}"
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
sed 's/^young_modulus = 2.88e8.*/young_modulus = 2.0e4/' \
  "$GRANPACK_SOURCE_DIR/jobs/decks/ci/gas_small.toml" > "$scratch/soft.toml"
msg=$(timeout 300 mpiexec -n 2 "$GRANPACK_EXE" run "$scratch/soft.toml" -o "$scratch/o" -q 2>&1)
code=$?
echo "$msg" | grep "error" | head -3
if [ $code -eq 1 ] && grep -q "overlap reached" <<<"$msg" && grep -q "likely" <<<"$msg"; then
  echo "bad states: 1 passed, 0 failed"
else
  echo "FAIL: exit code $code (expected 1 with an overlap diagnosis)"; echo "$msg" | tail -5
  echo "bad states: 0 passed, 1 failed"; exit 1
fi
