#!/bin/bash
# Geometric ballistic cluster-cluster aggregation (BCCA) gels at several solid fractions,
# analysed like [GRC]'s fig. 23 (issue 27; docs/reproduction-2d.md, "Geometric BCCA at
# [GRC]'s density"): K samples per solid fraction from jobs/tools/known_structures.py, each
# through `granpack analyze`, then `granpack ensemble` pools their I(k) and fits eq. (28) once.
# Prints, per solid fraction, the pooled fit and the per-sample C(r) fits (eq. 27). It is the
# yardstick for table VII: what blob size ξ the same analysis finds in the aggregation model
# [GRC] compare their RR structures with, at their density and cell size.
#
#   bash jobs/tools/bcca_density_sweep.sh [OUT] (default OUT: out/bcca_sweep)
#   N=5600 K=6 PHIS="0.36" bash jobs/tools/bcca_density_sweep.sh out/bcca_5600
# GRANPACK (default build/granpack) is the binary; seconds per sample at n = 1400.
set -euo pipefail
out=${1:-out/bcca_sweep}
n=${N:-1400}
k=${K:-6}
phis=${PHIS:-"0.36 0.26 0.13 0.05"}
exe=${GRANPACK:-build/granpack}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
[ -x "$exe" ] || { echo "bcca_density_sweep.sh: no binary $exe (set GRANPACK)" >&2; exit 2; }

for phi in $phis; do
  ens="$out/phi$phi"
  for s in $(seq 1 "$k"); do
    d="$ens/sample_$s"
    mkdir -p "$d"
    # `granpack ensemble` reads sample_S/report.json and every <stem>.analysis.json beside it.
    [ -f "$d/report.json" ] || echo '{"stages": []}' > "$d/report.json"
    if [ ! -f "$d/bcca.analysis.json" ]; then
      /usr/bin/python3 jobs/tools/known_structures.py bcca --n "$n" --phi "$phi" --seed "$s" \
        -o "$d/bcca.h5" > "$d/bcca.gen.json"
      mpirun -np 1 --bind-to none "$exe" analyze "$d/bcca.h5" --json "$d/bcca.analysis.json" \
        > "$d/analyze.log" 2>&1
    fi
  done
  mpirun -np 1 --bind-to none "$exe" ensemble "$ens" > "$ens/ensemble.log" 2>&1
done

/usr/bin/python3 jobs/tools/bcca_sweep_table.py "$out" --n "$n" --k "$k" --phis $phis
