#!/usr/bin/env bash
# Copies a finished ensemble's summary into the repository: out/ens/<NAME>/ensemble.json and
# each sample's report.json become docs/data/ensembles/<NAME>/ensemble.json and
# sample_<seed>.report.json (small JSON files; the samples' configurations and analyses stay in
# out/, `granpack ensemble --analyze` regenerates the latter). The "directory" key is rewritten
# to the repository path. The CI test cli.ar_table4_committed checks that the copied summary
# agrees with the copied reports, and checks table IV for the states docs/data/ensembles/states.txt
# lists.
#   bash jobs/runs/publish_ensemble.sh NAME...      e.g. C D_QS experiments/C_exp_base
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
cd "$root"
(($#)) || { echo "usage: publish_ensemble.sh NAME... (directories under out/ens/)" >&2; exit 2; }
for name in "$@"; do
  src=out/ens/$name dst=docs/data/ensembles/$name
  [ -s "$src/ensemble.json" ] || { echo "publish_ensemble.sh: no $src/ensemble.json (run granpack ensemble $src --analyze)" >&2; exit 2; }
  mkdir -p "$dst"
  seeds=$(/usr/bin/python3 -c 'import json,sys; print(" ".join(map(str, json.load(open(sys.argv[1]))["seeds"])))' "$src/ensemble.json")
  rm -f "$dst"/sample_*.report.json
  for s in $seeds; do cp "$src/sample_$s/report.json" "$dst/sample_$s.report.json"; done
  /usr/bin/python3 - "$src/ensemble.json" "$dst/ensemble.json" "$dst" <<'PY'
import json, sys
e = json.load(open(sys.argv[1]))
e["directory"] = sys.argv[3]
open(sys.argv[2], "w").write(json.dumps(e, separators=(",", ":")) + "\n")  # compact: curves are long
PY
  echo "published $name: K = $(echo $seeds | wc -w) (seeds $seeds) -> $dst"
done
