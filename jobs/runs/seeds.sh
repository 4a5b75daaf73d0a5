#!/usr/bin/env bash
# Several samples of one deck, as [GRC] average several samples per case: the deck with
# `seed = S` for each S, one after the other, each into out/2d/<deck>_seed<S>/ (restartable: a
# directory with a checkpoint and no final.h5 is continued through jobs/slurm/mpirun_loop.sh),
# then one line per sample from report.json (jobs/tools/case_table.py) and the mean and
# standard deviation of the last compress stage's Phi and z_int over the samples that finished.
# The deck must hold the line `seed = 1` (every jobs/decks/2d deck does).
#   bash jobs/runs/seeds.sh DECK [RANKS] SEED...
# e.g. bash jobs/runs/seeds.sh jobs/decks/2d/method2_seriesB_rr_delayed.toml 1 2 3
# Two one-rank samples side by side: run the script twice with one seed each
# (OMPI_MCA_hwloc_base_binding_policy=none is set, so mpirun does not bind both to core 0).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
deck=${1:?usage: seeds.sh DECK [RANKS] SEED...}
ranks=${2:-1}; shift 2 || { echo "seeds.sh: give at least one seed" >&2; exit 2; }
(($#)) || { echo "seeds.sh: give at least one seed" >&2; exit 2; }
[ -f "$deck" ] || { echo "seeds.sh: no deck $deck" >&2; exit 2; }
grep -q '^seed = 1$' "$deck" || { echo "seeds.sh: $deck has no line 'seed = 1' to replace" >&2; exit 2; }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_hwloc_base_binding_policy=${OMPI_MCA_hwloc_base_binding_policy:-none}
name=$(basename "$deck" .toml)
cd "$root"
cases=()
for s in "$@"; do
  [[ "$s" =~ ^[0-9]+$ ]] || { echo "seeds.sh: seed '$s' is not a non-negative integer" >&2; exit 2; }
  dir=out/2d/${name}_seed$s
  mkdir -p "$dir"
  # the deck's own read paths stay relative to the source root, where this runs
  sed "s/^seed = 1\$/seed = $s/" "$deck" > "$dir/deck.toml"
  [ -e "$dir/final.h5" ] || bash jobs/slurm/mpirun_loop.sh "$dir/deck.toml" "$dir" "$ranks"
  cases+=("${name}_seed$s")
done
/usr/bin/python3 jobs/tools/case_table.py out/2d "${cases[@]}" --mean
