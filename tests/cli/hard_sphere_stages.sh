#!/usr/bin/env bash
# The serial event-driven stages hand the same grains back whatever the rank count: an FCC
# lattice melted by ed_gas, then grown by ls_compress, written by 1 and by 2 ranks, gives
# bit-identical positions (velocities are drawn in id order on rank 0). Also: the LS stage
# keeps the grain diameter and reaches the target solid fraction by shrinking the cell; the
# grains leave at rest without overlaps (smallest centre distance >= diameter); the order left
# of the lattice that ed_gas reports is the one of the gas it wrote.
set -u
: "${GRANPACK_EXE:?}" "${GRANPACK_SOURCE_DIR:?}"
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
cli_scratch
# Sample and material shared by both decks of this test.
header="[sample]
dimension = 3
n = 256
diameter = 1.0e-3
seed = 5
[material]
density = 2500.0
young_modulus = 70.0e9
poisson_ratio = 0.3
friction = 0.3
damping = 0.98
"
{ printf '%s' "$header"; cat <<'TOML'
[[stage]]
kind = "lattice"
phi = 0.45
[[stage]]
kind = "ed_gas"
collisions_per_grain = 20
[[stage]]
kind = "write"
file = "gas.h5"
[[stage]]
kind = "ls_compress"
phi = 0.55
report_phi = [0.5]
TOML
} > "$scratch/ed.toml"
for np in 1 2; do
  check_exit "run on $np rank(s)" 0 "$scratch/np$np.txt" granpack_on $np run "$scratch/ed.toml" -o "$scratch/np$np" --quiet \
    || checks_stop hard_sphere_stages
done
# The read stage starts a run from a stored file (here the gas written on 2 ranks, read on 1).
{ printf '%s' "$header"; cat <<TOML
[[stage]]
kind = "read"
file = "$scratch/np2/gas.h5"
TOML
} > "$scratch/read.toml"
check_exit "read stage run" 0 "$scratch/read.txt" granpack_on 1 run "$scratch/read.toml" -o "$scratch/read" --quiet \
  || checks_stop hard_sphere_stages
# The files, checked independently of the engine: one line per check (cli_checks.sh checks_from).
/usr/bin/python3 - "$scratch" > "$scratch/py.txt" 2>&1 <<'PY'
import json, sys
import h5py, numpy as np
from checks import check
d = sys.argv[1]
def load(path):
    with h5py.File(path, "r") as f:
        order = np.argsort(f["particles/id"][:])
        return (f["particles/scaled_position"][:][order], f["particles/velocity"][:][order],
                f["particles/radius"][:][order], f["cell/length"][:], int(f.attrs["n_contacts"]))
for name in ["gas.h5", "final.h5"]:
    s1, v1, r1, L1, c1 = load(f"{d}/np1/{name}")
    s2, v2, r2, L2, c2 = load(f"{d}/np2/{name}")
    check(f"{name}: the same positions on 1 and 2 ranks (max difference {np.abs(s1 - s2).max()})",
          np.array_equal(s1, s2) and np.array_equal(L1, L2))
    check(f"{name}: grains at rest and no contacts left after a hard-sphere stage",
          not (np.any(v1 != 0) or c1 != 0))
    # No overlap: smallest minimum-image distance between centres >= sum of radii (1e-9).
    x = s1 * L1
    dx = x[:, None, :] - x[None, :, :]
    dx -= L1 * np.round(dx / L1)
    dist = np.sqrt((dx ** 2).sum(-1)) + np.eye(len(x)) * 1e9
    gap = (dist - (r1[:, None] + r1[None, :])).min() / (2 * r1.max())
    check(f"{name}: no overlap (smallest gap {gap} diameters)", not gap < -1e-9)
s_gas = load(f"{d}/np2/gas.h5")[0]
s_read = load(f"{d}/read/final.h5")[0]
check("read stage: the file read back equals the file written", np.array_equal(s_gas, s_read))
r = json.load(open(f"{d}/np2/report.json"))
ls = r["stages"][3]
check(f"ls_compress ended at phi {ls['phi']} = 0.55", not abs(ls["phi"] - 0.55) > 1e-9)
with h5py.File(f"{d}/np2/final.h5", "r") as f:
    check("ls_compress kept the grain radii", np.allclose(f["particles/radius"][:], 0.5e-3, rtol=0, atol=1e-18))
check(f"ls values: {ls['values']}",
      set(ls["values"]) == {"collisions_per_grain_0.450_0.500", "collisions_per_grain_0.500_0.550"})
melt = r["stages"][1]["values"]
check(f"ed_gas collisions per grain {melt['collisions_per_grain']} = 20",
      not abs(melt["collisions_per_grain"] - 20) > 1e-9)
# The order left of the FCC lattice (4x4x4 cells: its (111) Bragg peaks at wave-vector index 4),
# recomputed from the written gas: mean over the 4 peaks of |sum_j exp(i k.x_j)| / N.
s_gas2, _, _, L_gas, _ = load(f"{d}/np2/gas.h5")
x = s_gas2 * L_gas
rho = np.mean([abs(np.exp(1j * (x @ (2 * np.pi * 4 * np.array(v) / L_gas))).mean())
               for v in [(1, 1, 1), (1, 1, -1), (1, -1, 1), (1, -1, -1)]])
check(f"ed_gas lattice_order {melt.get('lattice_order')} = {rho} from gas.h5",
      not ("lattice_order" not in melt or abs(melt["lattice_order"] - rho) > 1e-9))
PY
checks_from "the file checks" "$scratch/py.txt" $?
checks_done "hard-sphere stages"
