#!/usr/bin/env bash
# Elastic moduli of every committed [AR] configuration (issue 28; docs/stiffness.md, "Moduli of
# the [AR] ensembles"): `granpack stiffness FILE --json` on one rank, one file after the other,
# into OUT (default out/moduli):
#   OUT/ens/<state>/sample_<k>.json   the finished samples of the committed ensembles,
#                                     jobs/runs/ar_ensembles/<state>/sample_<k>/final.h5
#                                     (a sample with only a checkpoint, an unfinished run,
#                                     is listed and skipped: it is not an equilibrium state)
#   OUT/single/<stem>.json            docs/data/<stem>.h5, one sample per state (A, A', C, D:
#                                     the only committed configurations of those states)
#   OUT/fig3/<stem>.json              docs/data/fig3/<stem>.h5, A at n = 1372 from 100 Pa to 1 MPa
#   OUT/qs/D_QS_sample_<k>/<stem>.json  jobs/runs/ar_ensembles/D_QS/sample_<k>/{D,QS_1..QS_4}.h5
#                                     and ENS_OUT/D_QS/sample_<k>/ (finished samples: report.json),
#                                     D at 1 kPa and its quasi-static steps to 100 kPa
#   OUT/ens/<name>/sample_<k>.json    the regenerated ensembles whose configurations are not
#                                     committed (A, C, D, A' of table IV; their summaries are
#                                     in docs/data/ensembles/): out/ens/<state>/sample_<k>/<stem>.h5
#                                     for each RERUN entry state:stem:name (default
#                                     "C:A:A C:C:C D_QS:D:D A_prime:A_prime:A_prime"), after
#                                     `bash jobs/runs/ar_ensembles.sh C D_QS A_prime`; a sample
#                                     whose stem file is missing (unfinished) is skipped
# Restartable: a file whose JSON exists is skipped (the JSON is written under a temporary name
# and renamed when the run succeeded), so the same command continues an interrupted sweep.
# Then `jobs/tools/ensemble_moduli.py OUT` tabulates them.
#   bash jobs/runs/ar_moduli.sh [OUT]
# GRANPACK=path/to/granpack (default build/granpack); STATES="B Z" restricts the ensembles;
# PARTS="ens single fig3 qs rerun" restricts what is run; ENS_OUT (default out/ens) is where
# the rerun and qs groups find the regenerated samples.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
out=${1:-$root/out/moduli}
exe=${GRANPACK:-$root/build/granpack}
states=${STATES:-B Z D_10kPa D_10kPa_zeta0.098 D_100kPa}
parts=${PARTS:-ens single fig3 qs rerun}
reruns=${RERUN:-C:A:A C:C:C D_QS:D:D A_prime:A_prime:A_prime}
ens_out=${ENS_OUT:-$root/out/ens}
[ -x "$exe" ] || { echo "ar_moduli: no granpack executable at $exe (set GRANPACK)" >&2; exit 2; }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_hwloc_base_binding_policy=${OMPI_MCA_hwloc_base_binding_policy:-none}
# One BLAS thread: the machine is shared, and one solve at a time is the rule (docs/stiffness.md).
export OPENBLAS_NUM_THREADS=${OPENBLAS_NUM_THREADS:-1}

ran=0 skipped=0 failed=0
# stiffness IN.h5 OUT.json: one run, unless OUT.json exists.
stiffness() {
  local in=$1 json=$2
  if [ -s "$json" ]; then skipped=$((skipped + 1)); return 0; fi
  mkdir -p "$(dirname "$json")"
  local t0=$SECONDS
  if nice -n 10 mpirun -np 1 "$exe" stiffness "$in" --json "$json.tmp" \
      > "${json%.json}.txt" 2>&1 < /dev/null; then
    mv "$json.tmp" "$json"
    ran=$((ran + 1))
    echo "[ar_moduli] ${json#"$out"/}: $((SECONDS - t0)) s"
  else
    rm -f "$json.tmp"
    failed=$((failed + 1))
    echo "[ar_moduli] FAILED on $in (log ${json%.json}.txt):" >&2
    tail -5 "${json%.json}.txt" >&2
  fi
}

# ensemble DIR STEM NAME: the stiffness of DIR/sample_<k>/STEM.h5 into OUT/ens/NAME/sample_<k>.json
# for every finished sample (its report.json written); a sample with only a checkpoint is an
# unfinished run, not an equilibrium state, and is skipped.
ensemble() {
  local dir=$1 stem=$2 name=$3 d
  for d in "$dir"/sample_*; do
    [ -d "$d" ] || continue
    # Its JSON already there (e.g. restored from jobs/runs/ar_moduli_json on a machine without
    # the configuration): nothing to run.
    if [ -s "$out/ens/$name/$(basename "$d").json" ]; then
      skipped=$((skipped + 1))
    elif [ -e "$d/$stem.h5" ] && [ -e "$d/report.json" ]; then
      stiffness "$d/$stem.h5" "$out/ens/$name/$(basename "$d").json"
    else
      echo "[ar_moduli] $name/$(basename "$d"): no $stem.h5 of a finished run (only a checkpoint?): skipped"
    fi
  done
}

for g in $parts; do
  case $g in
    ens)
      for s in $states; do
        ensemble "$root/jobs/runs/ar_ensembles/$s" final "$s"
      done ;;
    single)
      for f in "$root"/docs/data/*_n4000_seed*.h5; do
        stiffness "$f" "$out/single/$(basename "$f" .h5).json"
      done ;;
    fig3)
      for f in "$root"/docs/data/fig3/*.h5; do
        stiffness "$f" "$out/fig3/$(basename "$f" .h5).json"
      done ;;
    qs)
      # The committed samples, then the regenerated ones in ENS_OUT (finished runs only: a
      # sample of the same name already done is skipped by its JSONs).
      for d in "$root"/jobs/runs/ar_ensembles/D_QS/sample_* "$ens_out"/D_QS/sample_*; do
        [ -e "$d/report.json" ] || continue
        for f in "$d"/D.h5 "$d"/QS_*.h5; do
          [ -e "$f" ] || continue
          stiffness "$f" "$out/qs/D_QS_$(basename "$d")/$(basename "$f" .h5).json"
        done
      done ;;
    rerun)
      for entry in $reruns; do
        IFS=: read -r state stem name <<< "$entry"
        [ -n "$name" ] || { echo "ar_moduli: RERUN entry '$entry' is not state:stem:name" >&2; exit 2; }
        ensemble "$ens_out/$state" "$stem" "$name"
      done ;;
    *) echo "ar_moduli: unknown group '$g' (ens, single, fig3, qs, rerun)" >&2; exit 2 ;;
  esac
done
echo "[ar_moduli] $ran run, $skipped already there, $failed failed; results in $out"
[ "$failed" -eq 0 ]
