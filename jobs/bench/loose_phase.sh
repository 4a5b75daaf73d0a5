#!/usr/bin/env bash
# Loose-phase benchmark (issue 32, docs/performance.md "The loose phase"): runs the decks given
# (default: jobs/bench/loose_A.toml, jobs/bench/loose_grc.toml) with two granpack binaries in
# turn, TRIES times each, interleaved (binary 1, binary 2, binary 1, ...) so that both see the
# same load, on each rank count of RANKS, and prints one line per run: the stage's steps in the
# loose and dense classes with their particle-steps per second, the MD wall time and the force
# phase in wall and CPU seconds (report.json), the CPU seconds of the whole run (user + system
# of every rank, melt and start-up included; on 2 ranks it includes MPI's polling while a rank
# waits) and the load average at the start. On a shared machine the wall times follow the
# load; the CPU seconds much less.
#   bash jobs/bench/loose_phase.sh BEFORE_BINARY AFTER_BINARY [DECK...]
# Environment: TRIES (3), RANKS ("1 2"), NICE (10), OUT (/tmp/granpack-loose).
set -euo pipefail
before=$1 after=$2
shift 2
decks=("$@")
[[ ${#decks[@]} -gt 0 ]] || decks=(jobs/bench/loose_A.toml jobs/bench/loose_grc.toml)
TRIES=${TRIES:-3} RANKS=${RANKS:-"1 2"} NICE=${NICE:-10} OUT=${OUT:-/tmp/granpack-loose}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_hwloc_base_binding_policy=none OMPI_MCA_mpi_yield_when_idle=1
mkdir -p "$OUT"
for deck in "${decks[@]}"; do
  name=$(basename "$deck" .toml)
  for np in $RANKS; do
    for try in $(seq 1 "$TRIES"); do
      for which in before after; do
        bin=$before
        [[ $which == after ]] && bin=$after
        dir=$OUT/$name.np$np.$which.$try
        load=$(cut -d' ' -f1 /proc/loadavg)
        /usr/bin/time -f "%U %S" -o "$dir.cpu" nice -n "$NICE" mpirun -np "$np" "$bin" run "$deck" \
          -o "$dir" -q > "$dir.log" 2>&1
        /usr/bin/python3 "$(dirname "${BASH_SOURCE[0]}")/loose_line.py" "$dir/report.json" "$name" \
          "$np" "$which" "$try" "$load" "$dir.cpu"
      done
    done
  done
done
