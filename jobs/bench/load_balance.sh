#!/usr/bin/env bash
# The load-balance measurement of docs/performance.md ("Load balance of clustered packings"):
# jobs/bench/load_balance_aggregate.toml (the [GRC] series-A aggregate, 1400 disks) continued for
# STEPS steps on each rank count given, once on the static grid and once with
# `[numerics] load_balance = true`, printing the force work of the slowest rank over the mean
# (thread CPU time, valid with more ranks than cores) and the balancer's log line.
#   bash jobs/bench/load_balance.sh [NP...]        (default: 4 8 16; STEPS=20000; GRANPACK=build/granpack)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
cd "$root"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_rmaps_base_oversubscribe=1 OMPI_MCA_mpi_yield_when_idle=1
exe=${GRANPACK:-build/granpack}
steps=${STEPS:-20000}
ranks=("$@")
((${#ranks[@]})) || ranks=(4 8 16)
[ -x "$exe" ] || { echo "load_balance.sh: no granpack at $exe (bash jobs/setup.sh build)" >&2; exit 2; }
[ -f jobs/runs/v0A_0.095/checkpoint.h5 ] || { echo "load_balance.sh: jobs/runs/v0A_0.095/checkpoint.h5 is missing" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
sed -e "s/^max_steps = .*/max_steps = $steps/" jobs/bench/load_balance_aggregate.toml > "$work/static.toml"
cp "$work/static.toml" "$work/balanced.toml"
printf '\n[numerics]\nload_balance = true\n' >> "$work/balanced.toml"
printf '%-6s %-9s %-12s %s\n' ranks grid "force work" "balancer"
for np in "${ranks[@]}"; do
  for v in static balanced; do
    mpiexec -n "$np" "$exe" run "$work/$v.toml" -o "$work/out_${v}_$np" -q > "$work/log.txt" 2>&1 \
      || { cat "$work/log.txt" >&2; exit 1; }
    f=$(sed -n 's/.*force work of the slowest rank \/ mean \([0-9.]*\).*/\1/p' "$work/out_${v}_$np/log.txt" | tail -1)
    b=$(sed -n 's/^  load balance: //p' "$work/out_${v}_$np/log.txt" | tail -1)
    printf '%-6s %-9s %-12s %s\n' "$np" "$v" "$f" "${b:--}"
  done
done
