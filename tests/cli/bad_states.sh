#!/usr/bin/env bash
# A run that goes bad stops every rank with a diagnosis (step, grain or pair, likely fix),
# exit code 1, a post-mortem snapshot DIR/postmortem.h5, and no hang:
#  1. contacts far too soft for the pressure: overlaps beyond 0.1 radius;
#  2. a skin so thin (1e-5 a) that the compression moves grains further than it in one step.
set -u
: "${GRANPACK_EXE:?}" "${GRANPACK_SOURCE_DIR:?}"
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
pass=0 fail=0
gas=$GRANPACK_SOURCE_DIR/jobs/decks/ci/gas_small.toml
sed 's/^young_modulus = 2.88e8.*/young_modulus = 2.0e4/' "$gas" > "$scratch/soft.toml"
sed 's/^log_every = 5000/log_every = 5000\n[numerics]\nskin = 1.0e-5/' "$gas" > "$scratch/thin.toml"
check() {  # name, expected phrase (regex)
  local msg code
  msg=$(timeout 300 mpiexec -n 2 "$GRANPACK_EXE" run "$scratch/$1.toml" -o "$scratch/$1" -q 2>&1)
  code=$?
  echo "$msg" | grep "error" | head -2
  if [ $code -eq 1 ] && grep -Eq "$2" <<<"$msg" && grep -q "likely" <<<"$msg" \
     && "$GRANPACK_EXE" info "$scratch/$1/postmortem.h5" > /dev/null 2>&1; then
    pass=$((pass + 1))
  else
    echo "FAIL: $1: exit code $code (expected 1 with '$2', a likely fix and postmortem.h5)"
    echo "$msg" | tail -5; fail=$((fail + 1))
  fi
}
check soft "the overlap of grains [0-9]+ and [0-9]+ reached"
check thin "grain [0-9]+ moved .* in one step"
echo "bad states: $pass passed, $fail failed"
[ $fail -eq 0 ]
