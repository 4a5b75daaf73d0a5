#!/usr/bin/env bash
# compress with quench_when = "always" (docs/deck.md), on 2 ranks: an equilibrated packing of
# the n = 300 cohesive deck (jobs/decks/2d/method1_cohesive_small.toml) at P* = 0.01, read from
# docs/data/2d/method1_cohesive_small.h5 (cli.cohesive_2d makes and checks that compression anew
# on 1 and 2 ranks), compressed to P* = 0.02 while every velocity and the cell rate are set to
# zero every 4000 steps. Checks:
# - the stage quenches (report.json values.quenches >= 1, the log announces the quenches);
# - it still ends in [GRC]'s equilibrium, judged on motion, never on zeroed velocities: the
#   file's kinetic energy is > 0 and below 5e-8 F0 a per grain, and the stage ended at least
#   half an interval after its last quench (quenches fall on multiples of 4000 steps);
# - quenches are counted as the interval says: one at the start and one per 4000 steps after.
set -u
: "${GRANPACK_EXE:?}" "${GRANPACK_SOURCE_DIR:?}"
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
cli_scratch

# The deck's sample, material and output, its packing at P* = 0.01 read, then a second
# compression to P* = 0.02 that quenches.
awk '/^\[\[stage\]\]/ { exit } { print }' "$GRANPACK_SOURCE_DIR/jobs/decks/2d/method1_cohesive_small.toml" \
  > "$scratch/deck.toml"
printf '%s\n' '[[stage]]' 'kind = "read"' "file = \"$GRANPACK_SOURCE_DIR/docs/data/2d/method1_cohesive_small.h5\"" \
  '' '[[stage]]' 'name = "quenched"' 'kind = "compress"' 'pressure = 20.0' 'cell_mass = 0.3' \
  'quench_interval = 4000' 'quench_when = "always"' 'tolerance_force = 1e-4' 'tolerance_moment = 1e-4' \
  'tolerance_stress = 1e-4' 'tolerance_kinetic = 5e-8' '' '[[stage]]' 'kind = "write"' \
  'file = "method1.h5"' >> "$scratch/deck.toml"
check "deck edited" 'grep -q "^quench_when = \"always\"" "$scratch/deck.toml"'
check_exit "run" 0 "$scratch/run.txt" granpack_on 2 run "$scratch/deck.toml" -o "$scratch/out" -q
check "log announces the quenches" \
  'grep -q "velocities and cell rate set to zero every 4000 steps from now on" "$scratch/out/log.txt"'

# The stage's numbers and the file: one line per check (cli_checks.sh checks_from).
/usr/bin/python3 - "$scratch/out" > "$scratch/py.txt" 2>&1 <<'PY'
import json, sys
import h5py
import numpy as np
from checks import check
out = sys.argv[1]
st = [s for s in json.load(open(f"{out}/report.json"))["stages"] if s["name"] == "quenched"][0]
q, steps = int(st["values"]["quenches"]), int(st["steps"])
print(f"compress: {steps} steps, {q} quenches, phi {st['phi']:.4f}, equilibrated {st.get('equilibrated')}")
check("equilibrated", st.get("equilibrated"))
check(f"{q} quenches: the test needs the stage to outlast one interval", q >= 2)
check(f"{q} quenches in {steps} steps (one per 4000 from step 0 expected)", q == steps // 4000 + 1)
check(f"ended {steps % 4000} steps after a quench (criteria judged from 2000 on)", steps % 4000 >= 2000)
with h5py.File(f"{out}/method1.h5", "r") as f:
    m = f["particles/mass"][:]
    v = f["particles/velocity"][:]
    w = f["particles/angular_velocity"][:, 0]
    inertia = f["particles/inertia"][:]
    a = 2 * f["particles/radius"][:].max()
ek = (0.5 * (m * (v ** 2).sum(1)).sum() + 0.5 * (inertia * w ** 2).sum()) / len(m) / (1.0 * a)
print(f"kinetic energy {ek:.3g} F0 a per grain")
check(f"kinetic energy per grain {ek:.3g} F0 a (expected in (0, 5e-8))", 0 < ek < 5e-8)
PY
checks_from "equilibrium after the quenches" "$scratch/py.txt" $?
checks_done "quench_always"
