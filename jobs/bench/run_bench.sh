#!/usr/bin/env bash
# granpack vs LAMMPS on this machine (issue 8, docs/performance.md).
#   bash jobs/bench/run_bench.sh [BUILD_DIR]
# For n = 4000 (the committed A packing) and n = 32000 (the same replicated 2x2x2):
#   1. static check (1 rank): both codes compute the forces of the grains at rest on the
#      same configuration; compare_static.py reports the relative differences of the
#      per-grain forces and of the pressure;
#   2. timing: granpack then LAMMPS, on 1 then 2 ranks, the same state (positions, small
#      random velocities), time step, skin and number of steps; summarize.py prints
#      particle-steps/s per rank, the ratio granpack/LAMMPS and the 1 -> 2 rank efficiency.
# Environment: STEPS (default 1000), SIZES (default "1x1x1 2x2x2"), BENCH_OUT (default
# /tmp/granpack-bench), RANKS (default "1 2"), REPEAT (default 2: each pair of runs is
# repeated and the best rate of each code is kept, which filters the worst of the noise of a
# shared machine), E2E (default empty: decks under jobs/decks/ run end to end on 2 ranks after
# the ratios, e.g. E2E="A experiments/A_dt0.05 B"; each prints its wall time and the state's
# Phi and z*: issue 32's time-to-state targets), ED (default 1: the event-driven melt's
# collisions per second, jobs/bench/ed_bench.cpp, if the build has granpack_ed_bench), HALO
# (default shared_memory, granpack's default: the halo's transport of the timed granpack runs,
# `granpack bench --halo`, and of the E2E decks, run from a copy with [numerics] halo set;
# HALO=messages, against a run of the default on the same machine, times docs/performance.md
# "The shared-memory halo").
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
build=${1:-${GRANPACK_BUILD_DIR:-$root/build}}
exe=$build/granpack
packing=$root/docs/data/A_n4000_seed1.h5
out=${BENCH_OUT:-/tmp/granpack-bench}
steps=${STEPS:-1000}
sizes=${SIZES:-"1x1x1 2x2x2"}
ranks=${RANKS:-"1 2"}
repeat=${REPEAT:-2}
halo=${HALO:-shared_memory}
py=/usr/bin/python3
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
# A rank waiting in MPI yields its core instead of spinning: on a machine shared with other
# jobs (more runnable processes than cores) a spinning rank steals the core its partner needs.
# Applies to both codes alike; on a dedicated machine it makes no difference.
export OMPI_MCA_mpi_yield_when_idle=1

[ -x "$exe" ] || { echo "run_bench: no granpack executable at $exe (build first)" >&2; exit 1; }
if ! command -v lmp >/dev/null; then
  echo "[bench] installing LAMMPS (Debian package lammps)"
  sudo=""; [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends lammps >/dev/null
fi

echo "[bench] $(date -u +%FT%TZ) load: $(cut -d' ' -f1-3 /proc/loadavg)  halo: $halo  granpack $("$exe" --version)  $(lmp -h | sed -n 's/^Large-scale.*- \(.*\)$/LAMMPS \1/p' | head -1)"
for size in $sizes; do
  read -r kx ky kz <<<"${size//x/ }"
  dir=$out/$size
  mkdir -p "$dir"
  # 1. static forces, and the LAMMPS data file of the initial state
  mpirun -np 1 "$exe" bench "$packing" --replicate "$kx" "$ky" "$kz" --steps 1 \
    --static-forces "$dir/granpack_static.txt" --lammps-data "$dir/bench.data" \
    --json "$dir/static.json" >"$dir/static.txt"
  dt=$($py "$root/jobs/tools/granpack_io.py" value "$dir/static.json" dt)
  skin=$($py "$root/jobs/tools/granpack_io.py" value "$dir/static.json" skin)
  (cd "$dir" && mpirun -np 1 lmp -in "$here/lammps/in.granular" -var data bench.data -var dt "$dt" \
     -var skin "$skin" -var steps 0 -var mode static -log lammps_static.log -screen none)
  $py "$here/compare_static.py" "$dir/granpack_static.txt" "$dir/forces.dump" "$dir/lammps_static.log" \
    | tee "$dir/static_check.txt"
  # 2. timing, same load for both codes
  for r in $(seq 1 "$repeat"); do
    for np in $ranks; do
      echo "[bench] $size np=$np try $r load $(cut -d' ' -f1 /proc/loadavg)"
      mpirun -np "$np" "$exe" bench "$packing" --replicate "$kx" "$ky" "$kz" --steps "$steps" \
        --halo "$halo" --json "$dir/granpack_np${np}_$r.json" >"$dir/granpack_np${np}_$r.txt"
      (cd "$dir" && mpirun -np "$np" lmp -in "$here/lammps/in.granular" -var data bench.data \
         -var dt "$dt" -var skin "$skin" -var steps "$steps" -var mode run \
         -log "lammps_np${np}_$r.log" -screen none)
    done
  done
done
$py "$here/summarize.py" "$out" $sizes
if [ "${ED:-1}" = 1 ] && [ -x "$build/granpack_ed_bench" ]; then
  echo "[bench] event-driven melt (n = 4000, Phi = 0.45, 100 collisions per grain, best of 3)"
  "$build/granpack_ed_bench" 100 3 | tee "$out/ed_bench.txt"
fi
for deck in ${E2E:-}; do
  d=$out/e2e/${deck//\//_}
  rm -rf "$d" && mkdir -p "$out/e2e"
  deck_file=$root/jobs/decks/$deck.toml
  if [ "$halo" != shared_memory ]; then
    # A copy of the deck with [numerics] halo set: under its [numerics] header, or in a new
    # table at the end (read stages' paths are relative to the working directory: unchanged).
    gen=$d.toml
    if grep -q '^\[numerics\]' "$deck_file"; then
      sed "/^\[numerics\]/a halo = \"$halo\"" "$deck_file" >"$gen"
    else
      { cat "$deck_file"; printf '\n[numerics]\nhalo = "%s"\n' "$halo"; } >"$gen"
    fi
    deck_file=$gen
  fi
  t0=$(date +%s.%N)
  mpirun -np 2 "$exe" run "$deck_file" -o "$d" -q >"$d.log" 2>&1 \
    || { echo "[bench] $deck failed (log $d.log)" >&2; continue; }
  t1=$(date +%s.%N)
  $py "$here/e2e_line.py" "$deck" "$t0" "$t1" "$d"
done
