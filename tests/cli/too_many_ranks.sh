#!/usr/bin/env bash
# A sub-domain narrower than the grains' interaction range is refused with a clear message and
# exit code 2, not run with pairs lost (issue 31). The FCC CI crystal (256 grains, a cell of
# 5.7 a) on 7 ranks is cut into 7 x 1 x 1 sub-domains of 0.81 a; its ghost layer needs 1.1 a,
# so at most 5 ranks fit along that axis.
set -u
: "${GRANPACK_EXE:?}" "${GRANPACK_SOURCE_DIR:?}"
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
cli_scratch
check_refused "7 ranks on a 5.7 a cell" 2 "7 ranks along axis 0 cut the cell into sub-domains .* run on fewer ranks \(at most 5 along this axis\)" \
  "$scratch/run.txt" granpack_on 7 run "$GRANPACK_SOURCE_DIR/jobs/decks/ci/fcc_hertz.toml" -o "$scratch/out" -q
checks_done "too many ranks"
