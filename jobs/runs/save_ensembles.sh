#!/usr/bin/env bash
# Saves the ensembles in progress (out/ens/<state>/sample_<seed>/) into the repository
# (jobs/runs/ar_ensembles/<state>/sample_<seed>/) so that a session's end loses nothing: a
# finished sample keeps its configurations (final.h5 and the write stages' files, usually
# byte-identical, so git stores them once), log.txt and report.json; an unfinished one its
# checkpoint.h5 and log.txt. Continue next session with
#   cp -r jobs/runs/ar_ensembles/* out/ens/ && bash jobs/runs/ar_ensembles.sh STATE...
#   bash jobs/runs/save_ensembles.sh STATE...     e.g. Z D_10kPa_zeta0.098 B
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
cd "$root"
(($#)) || { echo "usage: save_ensembles.sh STATE... (directories under out/ens/)" >&2; exit 2; }
for state in "$@"; do
  [ -d "out/ens/$state" ] || { echo "save_ensembles.sh: no out/ens/$state" >&2; exit 2; }
  for src in out/ens/"$state"/sample_*/; do
    src=${src%/} dst=jobs/runs/ar_ensembles/$state/$(basename "$src")
    [ -f "$src/log.txt" ] || continue
    rm -rf "$dst" && mkdir -p "$dst"
    if [ -f "$src/report.json" ]; then
      for f in "$src"/*.h5 "$src"/*.xdmf; do
        case $(basename "$f") in checkpoint.*) ;; *) cp "$f" "$dst/" ;; esac
      done
      cp "$src/report.json" "$src/log.txt" "$dst/"
      echo "$dst: finished"
    elif [ -f "$src/checkpoint.h5" ]; then
      cp "$src/checkpoint.h5" "$src/log.txt" "$dst/"
      echo "$dst: checkpoint"
    fi
  done
done
