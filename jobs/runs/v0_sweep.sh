#!/usr/bin/env bash
# [GRC] fig. 8 / table VI: jobs/decks/2d/method2_v0_sweep.toml for V0/V* = 0.095, 0.95, 9.5, 95,
# one after the other, each into out/2d/v0_<ratio>/ (restartable: a directory with a
# checkpoint and no final.h5 is continued through jobs/slurm/mpirun_loop.sh), then
# `granpack analyze` of each P0.h5 into out/2d/v0_<ratio>/analysis.json.
#   bash jobs/runs/v0_sweep.sh [RANKS] [RATIOS...]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
ranks=${1:-2}; shift || true
ratios=${*:-"0.095 0.95 9.5 95"}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
for r in $ratios; do
  dir=$root/out/2d/v0_$r
  mkdir -p "$dir"
  sed "s/^velocity_ratio = .*/velocity_ratio = $r/" "$root/jobs/decks/2d/method2_v0_sweep.toml" > "$dir/deck.toml"
  [ -e "$dir/final.h5" ] || bash "$root/jobs/slurm/mpirun_loop.sh" "$dir/deck.toml" "$dir" "$ranks"
  mpirun -np "$ranks" "$root/build/granpack" analyze "$dir/P0.h5" --json "$dir/analysis.json" > "$dir/analysis.txt"
  echo "[v0_sweep] V0/V* = $r: $(grep -m1 'z ' "$dir/analysis.txt" || true)"
done
