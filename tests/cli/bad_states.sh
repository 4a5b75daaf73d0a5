#!/usr/bin/env bash
# A run that goes bad stops every rank with a diagnosis (step, grain or pair, likely fix),
# exit code 1, a post-mortem snapshot DIR/postmortem.h5, and no hang:
#  1. contacts far too soft for the pressure: overlaps beyond 0.1 radius;
#  2. a skin so thin (1e-5 a) that the compression moves grains further than it in one step.
set -u
: "${GRANPACK_EXE:?}" "${GRANPACK_SOURCE_DIR:?}"
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
cli_scratch
gas=$GRANPACK_SOURCE_DIR/jobs/decks/ci/gas_small.toml
sed 's/^young_modulus = 2.88e8.*/young_modulus = 2.0e4/' "$gas" > "$scratch/soft.toml"
sed 's/^log_every = 5000/log_every = 5000\n[numerics]\nskin = 1.0e-5/' "$gas" > "$scratch/thin.toml"
goes_bad() {  # NAME PHRASE: the run of NAME.toml ends as above, its diagnosis matching PHRASE (regex)
  local name=$1 phrase=$2
  check_exit "$name (124 is a hang)" 1 "$scratch/$name.txt" \
    timeout 300 mpiexec -n 2 "$GRANPACK_EXE" run "$scratch/$name.toml" -o "$scratch/$name" -q
  grep "error" "$scratch/$name.txt" | head -2
  check "$name: the diagnosis says '$phrase'" 'grep -Eq "$phrase" "$scratch/$name.txt"'
  check "$name: a likely fix" 'grep -q "likely" "$scratch/$name.txt"'
  check "$name: postmortem.h5 written and readable" \
    '"$GRANPACK_EXE" info "$scratch/$name/postmortem.h5" > /dev/null 2>&1'
}
goes_bad soft "the overlap of grains [0-9]+ and [0-9]+ reached"
goes_bad thin "grain [0-9]+ moved .* in one step"
checks_done "bad states"
