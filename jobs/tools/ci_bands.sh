#!/usr/bin/env bash
# Runs the CI variants of the [AR] states (jobs/decks/ci/{AC,B,D}_small.toml) for several
# seeds and prints Phi, z*, x0, x2 and Z(2) of each state with the mean and standard
# deviation over the seeds: the data behind the tolerance bands of tests/cli/states_small.sh
# (recorded in docs/reproduction.md).
# Usage: bash jobs/tools/ci_bands.sh [SEEDS...]   (default 1 2 3 4; run from the repository)
set -eu
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
exe=${GRANPACK_EXE:-build/granpack}
np=${NP:-2}
seeds=${*:-1 2 3 4}
work=$(mktemp -d)
for seed in $seeds; do
  for deck in AC_small B_small D_small; do
    sed "s/^seed = .*/seed = $seed/" "jobs/decks/ci/$deck.toml" > "$work/${deck}_$seed.toml"
    mpiexec -n "$np" "$exe" run "$work/${deck}_$seed.toml" -o "$work/out_${deck}_$seed" --quiet > /dev/null
  done
done
/usr/bin/python3 "$(dirname "${BASH_SOURCE[0]}")/ci_bands.py" "$work" $seeds
rm -rf "$work"
