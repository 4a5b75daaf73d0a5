#!/usr/bin/env bash
# compress with quench_when = "always" (docs/deck.md), on 2 ranks: the n = 300 cohesive deck
# compressed to P* = 0.01, then to P* = 0.02 while every velocity and the cell rate are set to
# zero every 4000 steps. Checks:
# - the stage quenches (report.json values.quenches >= 1, the log announces the quenches);
# - it still ends in [GRC]'s equilibrium, judged on motion, never on zeroed velocities: the
#   file's kinetic energy is > 0 and below 5e-8 F0 a per grain, and the stage ended at least
#   half an interval after its last quench (quenches fall on multiples of 4000 steps);
# - quenches are counted as the interval says: one at the start and one per 4000 steps after.
set -u
: "${GRANPACK_EXE:?}" "${GRANPACK_SOURCE_DIR:?}"
source "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
np=${GRANPACK_TEST_RANKS:-2}
cli_scratch

# Its compression to P* = 0.01, then a second one to P* = 0.02 that quenches.
sed -e 's/^file = "method1.h5"$/file = "P0.01.h5"/' \
  "$GRANPACK_SOURCE_DIR/jobs/decks/2d/method1_cohesive_small.toml" > "$scratch/deck.toml"
printf '%s\n' '' '[[stage]]' 'name = "quenched"' 'kind = "compress"' 'pressure = 20.0' 'cell_mass = 0.3' \
  'quench_interval = 4000' 'quench_when = "always"' 'tolerance_force = 1e-4' 'tolerance_moment = 1e-4' \
  'tolerance_stress = 1e-4' 'tolerance_kinetic = 5e-8' '' '[[stage]]' 'kind = "write"' \
  'file = "method1.h5"' >> "$scratch/deck.toml"
check "deck edited" 'grep -q "^quench_when = \"always\"" "$scratch/deck.toml"'
mpiexec -n $np --oversubscribe "$GRANPACK_EXE" run "$scratch/deck.toml" -o "$scratch/out" -q \
  < /dev/null > "$scratch/run.txt" 2>&1
check "run exits 0" '[ $? -eq 0 ] || { tail -20 "$scratch/run.txt"; false; }'
check "log announces the quenches" \
  'grep -q "velocities and cell rate set to zero every 4000 steps from now on" "$scratch/out/log.txt"'

/usr/bin/python3 - "$scratch/out" <<'PY'
import json, sys
import h5py
import numpy as np
out = sys.argv[1]
st = [s for s in json.load(open(f"{out}/report.json"))["stages"] if s["name"] == "quenched"][0]
fails = []
q, steps = int(st["values"]["quenches"]), int(st["steps"])
print(f"compress: {steps} steps, {q} quenches, phi {st['phi']:.4f}, equilibrated {st.get('equilibrated')}")
if not st.get("equilibrated"):
    fails.append("not equilibrated")
if q < 2:
    fails.append(f"{q} quenches: the test needs the stage to outlast one interval")
if q != steps // 4000 + 1:
    fails.append(f"{q} quenches in {steps} steps (one per 4000 from step 0 expected)")
if steps % 4000 < 2000:
    fails.append(f"ended {steps % 4000} steps after a quench (criteria judged from 2000 on)")
with h5py.File(f"{out}/method1.h5", "r") as f:
    m = f["particles/mass"][:]
    v = f["particles/velocity"][:]
    w = f["particles/angular_velocity"][:, 0]
    inertia = f["particles/inertia"][:]
    a = 2 * f["particles/radius"][:].max()
ek = (0.5 * (m * (v ** 2).sum(1)).sum() + 0.5 * (inertia * w ** 2).sum()) / len(m) / (1.0 * a)
print(f"kinetic energy {ek:.3g} F0 a per grain")
if not 0 < ek < 5e-8:
    fails.append(f"kinetic energy per grain {ek:.3g} F0 a (expected in (0, 5e-8))")
for f_ in fails:
    print("FAIL:", f_)
sys.exit(1 if fails else 0)
PY
check "equilibrium after the quenches" '[ $? -eq 0 ]'
checks_done "quench_always"
