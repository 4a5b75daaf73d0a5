#!/usr/bin/env bash
# [AR] App. E reproduction: 10 launch tests (the 10 divalent grains with the largest contact
# forces, picks 0-9) on D at 1 kPa and on the D series at 10 kPa, each with the contact network
# frozen and with contact creation (docs/stiffness.md, "Is a divalent grain's free rolling
# stable?"). Then jobs/tools/appendix_e.py counts the outcomes and draws the fig. 16 picture.
#
#   jobs/runs/appendix_e.sh [RATIO] [TURNS] [PICKS] [MODES] [LEVELS]
#     RATIO  centrifugal force / contact force (default 1e-4, [AR]'s)
#     TURNS  turns of the grain about its neighbours' axis before the run stops (default 1)
#     PICKS  e.g. "0 1 2" (default 0-9);  MODES "frozen free" (default both);
#     LEVELS "1kPa 10kPa" (default both)
#   RANKS=N (default 1), OUT=dir (default out/appendix_e), GRANPACK=build/granpack.
# Runs from the source tree's root. A finished test (its report.json present) is skipped, so the
# script can be rerun after an interruption.
set -eu
ratio=${1:-1e-4}
turns=${2:-1}
picks=${3:-"0 1 2 3 4 5 6 7 8 9"}
modes=${4:-"frozen free"}
levels=${5:-"1kPa 10kPa"}
ranks=${RANKS:-1}
out=${OUT:-out/appendix_e}
exe=${GRANPACK:-build/granpack}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_hwloc_base_binding_policy=none
mkdir -p "$out/decks"

# The 10 kPa input: the D series' second sqrt(10) step from the committed 1 kPa sample.
if [[ " $levels " == *" 10kPa "* && ! -f "$out/D_10kPa/D_10kPa_series.h5" ]]; then
  nice -n 10 mpirun -np "$ranks" "$exe" run jobs/decks/appendix_e/D_10kPa_series.toml -o "$out/D_10kPa" -q
fi

for level in $levels; do
  case $level in
    1kPa) file=docs/data/D_n4000_seed1.h5 pressure=1.0e3 ;;
    10kPa) file=$out/D_10kPa/D_10kPa_series.h5 pressure=1.0e4 ;;
    *) echo "unknown level $level (allowed: 1kPa 10kPa)" >&2; exit 2 ;;
  esac
  for mode in $modes; do
    case $mode in frozen) frozen=true stop=rearrangement ;; free) frozen=false stop=collapse ;;
      *) echo "unknown mode $mode (allowed: frozen free)" >&2; exit 2 ;;
    esac
    for pick in $picks; do
      name=${level}_${mode}_pick${pick}_ratio${ratio}
      [ -f "$out/$name/report.json" ] && continue
      sed -e "s|@FILE@|$file|" -e "s|@PRESSURE@|$pressure|" -e "s|@PICK@|$pick|" \
        -e "s|@FROZEN@|$frozen|" -e "s|@RATIO@|$ratio|" -e "s|@TURNS@|$turns|" -e "s|@STOP@|$stop|" \
        jobs/decks/appendix_e/launch.toml.in > "$out/decks/$name.toml"
      nice -n 10 mpirun -np "$ranks" "$exe" run "$out/decks/$name.toml" -o "$out/$name" -q
    done
  done
done
/usr/bin/python3 jobs/tools/appendix_e.py "$out" --ratio "$ratio"
