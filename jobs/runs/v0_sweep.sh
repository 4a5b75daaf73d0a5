#!/usr/bin/env bash
# [GRC] fig. 8 / table VI: jobs/decks/2d/method2_v0_sweep.toml for V0/V* = 9.5, 95, 0.95,
# 0.095 (the slow aggregations last), one after the other, each into out/2d/v0_<ratio>/
# (restartable: a directory with a checkpoint and no final.h5 is continued through
# jobs/slurm/mpirun_loop.sh), then `granpack analyze` of each P0.h5 into
# out/2d/v0_<ratio>/analysis.json.
# Above V0/V* = 20 the kappa = 1e2 aggregation would overlap grains by more than their radius
# (collisions at 9.48 V* already reach 0.1 of the smallest radius): those runs aggregate at
# kappa = 1e4 directly (K_N = 1e7 N/m, K_r = 1e-3 N m, the default overlap limit) and skip the
# stiffening.
# SERIES=A runs [GRC]'s own protocol instead (their table VI samples are series A):
# jobs/decks/2d/method2_seriesA_rr_quench.toml, kappa = 1e5 throughout, no stiffening, into
# out/2d/v0A_<ratio>/. About 30x the time steps of the kappa = 1e2 aggregation: V0/V* = 0.95
# aggregates in half an hour on one core (16 M steps), 0.095 needs about 150 M steps.
#   [SERIES=A] bash jobs/runs/v0_sweep.sh [RANKS] [RATIOS...]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
ranks=${1:-2}; shift || true
ratios=${*:-"9.5 95 0.95 0.095"}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
series=${SERIES:-B}
case "$series" in
  A) deck=method2_seriesA_rr_quench.toml ;;
  B) deck=method2_v0_sweep.toml ;;
  *) echo "v0_sweep: SERIES must be A or B, got '$series'" >&2; exit 2 ;;
esac
for r in $ratios; do
  dir=$root/out/2d/v0$([ "$series" = A ] && echo A)_$r
  mkdir -p "$dir"
  /usr/bin/python3 - "$root/jobs/decks/2d/$deck" "$dir/deck.toml" "$r" "$series" <<'PY'
import re, sys
src, dst, ratio, series = sys.argv[1], sys.argv[2], float(sys.argv[3]), sys.argv[4]
text = open(src).read()
text, n = re.subn(r"(?m)^velocity_ratio = .*$", f"velocity_ratio = {ratio}", text)
assert n == 1, f"{src}: one velocity_ratio line expected, found {n}"
if series == "B" and ratio > 20:
    text = re.sub(r"(?m)^normal_stiffness = .*$", "normal_stiffness = 1.0e7", text)
    text = re.sub(r"(?m)^rolling_stiffness = .*$", "rolling_stiffness = 1.0e-3", text)
    text = re.sub(r"(?m)^max_overlap = .*$", "max_overlap = 0.1", text)
    text = re.sub(r'\[\[stage\]\]\nkind = "stiffen"\n(?:[^\[\n][^\n]*\n)*\n', "", text)
    assert 'kind = "stiffen"' not in text
open(dst, "w").write(text)
PY
  [ -e "$dir/final.h5" ] || bash "$root/jobs/slurm/mpirun_loop.sh" "$dir/deck.toml" "$dir" "$ranks"
  mpirun -np "$ranks" "$root/build/granpack" analyze "$dir/P0.h5" --json "$dir/analysis.json" > "$dir/analysis.txt"
  echo "[v0_sweep] V0/V* = $r done"
done
