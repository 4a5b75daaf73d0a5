#!/usr/bin/env bash
# The [AR] ensembles of issue 26: five samples (seeds 1-5) of each state deck at n = 4000, as
# sample_<seed>/ directories of one ensemble per state under out/ens/<state>/ -- the same files
# `mpirun -np 2 build/granpack run DECK --samples 5 -o out/ens/<state>` writes, but scheduled
# as a queue of (deck, seed) items over WORKERS one-rank workers, so that no core idles while
# the last sample of a state runs alone. Restartable: a finished sample (report.json) is
# skipped, one with a checkpoint is continued (`run --restart`), so after an interruption
# (session end, SIGTERM) simply run the script again. When a state's five samples are done,
# `granpack ensemble --analyze` writes out/ens/<state>/ensemble.json.
#   bash jobs/runs/ar_ensembles.sh [STATE...]      (default: C D_QS A_prime, the n = 1372 A and A', Z, B and the table III decks;
#   C also gives A, D_QS also D; the controlled experiments: experiments/C_exp_base ...)
# Environment: WORKERS (default 2), SEEDS (default "1 2 3 4 5"), GRANPACK (default build/granpack).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
cd "$root"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
# Two one-rank jobs side by side must not both be bound to core 0.
export OMPI_MCA_hwloc_base_binding_policy=none
exe=${GRANPACK:-build/granpack}
workers=${WORKERS:-2}
seeds=${SEEDS:-1 2 3 4 5}
states=("$@")
((${#states[@]})) || states=(C D_QS A_prime A_fig3_small A_prime_n1372 Z B D_10kPa D_100kPa D_10kPa_zeta0.098 D_10kPa_I0.1)
for s in "${states[@]}"; do
  [ -f "jobs/decks/$s.toml" ] || { echo "ar_ensembles.sh: no deck jobs/decks/$s.toml" >&2; exit 2; }
done
[ -x "$exe" ] || { echo "ar_ensembles.sh: no granpack at $exe (bash jobs/setup.sh build)" >&2; exit 2; }
mkdir -p out/ens
# One queue per call (several calls may run side by side, each with its own workers).
queue=out/ens/queue.$$.txt lock=out/ens/queue.$$.lock
trap 'rm -f "$queue" "$lock"' EXIT
: > "$queue"
for s in "${states[@]}"; do for k in $seeds; do echo "$s $k" >> "$queue"; done; done

# Pops the next item of the queue (under a lock: the workers share it).
pop() {
  flock "$lock" bash -c 'head -n1 "$0"; sed -i 1d "$0"' "$queue"
}

worker() {
  while true; do
    item=$(pop)
    [ -n "$item" ] || return 0
    read -r state seed <<< "$item"
    out=out/ens/$state
    [ -f "$out/sample_$seed/report.json" ] && continue
    echo "[worker $1] $state seed $seed ($(date +%H:%M))"
    code=0
    mpirun -np 1 "$exe" run "jobs/decks/$state.toml" --samples 1 --first-seed "$seed" -o "$out" \
      --restart --checkpoint-every-seconds 600 -q > "out/ens/worker$$.$1.log" 2>&1 || code=$?
    echo "[worker $1] $state seed $seed exit $code ($(date +%H:%M))"
    [ "$code" -eq 75 ] && return 75   # stop signal: leave the queue for the next call
  done
}

pids=()
for w in $(seq 1 "$workers"); do worker "$w" & pids+=($!); done
# On a stop signal, this call's runs (the workers' mpirun children) get it, not another call's.
trap 'for p in "${pids[@]}"; do pkill -TERM -P "$p"; done; kill -TERM "${pids[@]}" 2>/dev/null || true' TERM INT
for p in "${pids[@]}"; do wait "$p" || true; done

for s in "${states[@]}"; do
  n=0
  for k in $seeds; do [ -f "out/ens/$s/sample_$k/report.json" ] && n=$((n + 1)); done
  if [ "$n" -gt 0 ]; then
    mpirun -np 2 "$exe" ensemble "out/ens/$s" --analyze | tail -n 3
  fi
done
