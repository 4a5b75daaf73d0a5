#!/usr/bin/env bash
# jobs/tools/plot_2d.py (docs/plots.md, "2D pictures"): on a small cohesive packing made here
# (120 disks, soft contacts, D0 = 0.05 a so that distant pairs exist; a few seconds on 1 rank)
# and on the committed cohesionless 2D packings (docs/data/2d) it writes LABEL_forces.png,
# LABEL_NT.png, LABEL_theta.png per file and theta.png for several files (PNGs of sensible
# size); the --summary colour classes (compressive / tensile / distant / unstressed) equal a
# count made here from the file alone (flags, N^e, the distant attraction -F0 (1 - g/D0) from
# the positions, T); a missing file, a non-HDF5 file, a 3D file (docs/data/D_n4000_seed1.h5)
# or a wrong --labels count give a non-zero exit, a message naming the problem, no traceback
# and no PNG.
# ctest: PROCESSORS 1   (one process at a time: ctest -j2 runs another test beside it)
set -u
: "${GRANPACK_EXE:?}" "${GRANPACK_SOURCE_DIR:?}"
tool="$GRANPACK_SOURCE_DIR/jobs/tools/plot_2d.py"
data="$GRANPACK_SOURCE_DIR/docs/data"
py=/usr/bin/python3
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
cli_scratch
export MPLCONFIGDIR="$scratch/mpl"

cat > "$scratch/coh.toml" <<'EOF'
# 120 cohesive disks, kappa = a K_N / F0 = 1e3, D0 = 0.05 a, P* = 0.01, loose tolerances.
[sample]
dimension = 2
n = 120
diameter = 1.0e-3
distribution = "uniform"
min_diameter_ratio = 0.5
seed = 2

[material]
density = 2500.0
normal_law = "linear"
normal_stiffness = 1.0e6
tangential_stiffness_ratio = 1.0
friction = 0.5
damping = 0.8
cohesion_force = 1.0
cohesion_range = 5.0e-5
rolling_stiffness = 1.0e-4
rolling_friction = 5.0e-6
rolling_damping = 0.8

[[stage]]
kind = "random"
phi = 0.36

[[stage]]
kind = "compress"
pressure = 10.0
cell_mass = 0.3
tolerance_force = 1e-3
tolerance_moment = 1e-3
tolerance_stress = 1e-3
tolerance_kinetic = 1e-6
EOF
check_exit "the cohesive packing run" 0 "$scratch/run.txt" "$GRANPACK_EXE" run "$scratch/coh.toml" -o "$scratch/coh" --quiet \
  || checks_stop plot_2d
coh="$scratch/coh/final.h5"
mu05="$data/2d/method1_noncohesive_mu0.5.h5"
mu015="$data/2d/method1_noncohesive_mu0.15.h5"

# Independent colour classes from the file: N = N^e + N^a (N^a = -F0 in contact,
# -F0 (1 - g/D0) across a gap g), T = the tangential vector's component along n turned by
# +90 deg; unit F0 (cohesive) or the mean N of the contacts; unstressed: |F| < thr x unit.
count() {  # count FILE THRESHOLD F0 D0 -> "compressive=.. tensile=.. distant=.. unstressed=.."
  "$py" - "$@" <<'PY'
import sys
import h5py, numpy as np
path, thr, F0, D0 = sys.argv[1], float(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4])
with h5py.File(path, "r") as f:
    ids = list(f["particles/id"][:])
    at = {g: k for k, g in enumerate(ids)}
    L = f["cell/length"][:]
    x = f["particles/scaled_position"][:] * L
    R = f["particles/radius"][:]
    a = np.array([at[g] for g in f["contacts/first"][:]])
    b = np.array([at[g] for g in f["contacts/second"][:]])
    Ne = f["contacts/normal_force"][:]
    Tv = f["contacts/tangential_force"][:]
    flags = f["contacts/flags"][:]
c = {"compressive": 0, "tensile": 0, "distant": 0, "unstressed": 0}
distant = (flags & 4) != 0
unit = F0 if F0 > 0 else Ne[~distant].mean()
for k in range(len(a)):
    r = x[b[k]] - x[a[k]]
    r -= L * np.round(r / L)
    dist = np.hypot(*r)
    n = r / dist
    if distant[k]:
        c["distant"] += 1
        continue
    N = Ne[k] - F0
    T = -Tv[k][0] * n[1] + Tv[k][1] * n[0]
    if np.hypot(N, T) < thr * unit:
        c["unstressed"] += 1
    elif N > 0:
        c["compressive"] += 1
    else:
        c["tensile"] += 1
print(" ".join(f"{k}={v}" for k, v in c.items()))
PY
}
summary_of() { grep "^summary $1:" "$2" | sed 's/^summary [^:]*: //; s/ idle_grains.*//'; }

# --- cohesive packing -------------------------------------------------------------------------
check_exit "cohesive" 0 "$scratch/o1.txt" "$py" "$tool" "$scratch/o1" "$coh" --labels coh --summary
check "cohesive: forces PNG" "big_png '$scratch/o1/coh_forces.png' 20000"
check "cohesive: N-T PNG" "big_png '$scratch/o1/coh_NT.png' 5000"
check "cohesive: theta PNG" "big_png '$scratch/o1/coh_theta.png' 5000"
check "cohesive: PNGs listed" "[ \$(grep -c '\.png$' '$scratch/o1.txt') -eq 3 ]"
want=$(count "$coh" 1e-3 1.0 5e-5); got=$(summary_of coh "$scratch/o1.txt")
check "cohesive: summary '$got' = file's '$want'" "[ -n '$got' ] && [ '$got' = '$want' ]"
check "cohesive: all four classes present ($want)" \
  "! echo '$want' | grep -q '=0\b'"
"$py" "$tool" "$scratch/o2" "$coh" --labels coh --summary --threshold 1e-2 --width total > "$scratch/o2.txt" 2>&1
want2=$(count "$coh" 1e-2 1.0 5e-5); got2=$(summary_of coh "$scratch/o2.txt")
check "cohesive, --threshold 1e-2: summary '$got2' = file's '$want2'" "[ -n '$got2' ] && [ '$got2' = '$want2' ]"
check "cohesive: a larger threshold finds more unstressed contacts" \
  "[ \${want2##*unstressed=} -gt \${want##*unstressed=} ]"

# --- committed cohesionless packings, together -----------------------------------------------
check_exit "cohesionless pair" 0 "$scratch/o3.txt" "$py" "$tool" "$scratch/o3" "$mu05" "$mu015" --summary
for s in method1_noncohesive_mu0.5 method1_noncohesive_mu0.15; do
  check "$s: forces PNG" "big_png '$scratch/o3/${s}_forces.png' 50000"
  check "$s: N-T PNG" "big_png '$scratch/o3/${s}_NT.png' 5000"
  check "$s: theta PNG" "big_png '$scratch/o3/${s}_theta.png' 5000"
done
check "cohesionless pair: overlaid theta.png" "big_png '$scratch/o3/theta.png' 5000"
for s in mu0.5 mu0.15; do
  f="$data/2d/method1_noncohesive_$s.h5"
  want=$(count "$f" 1e-3 0 0); got=$(summary_of "method1_noncohesive_$s" "$scratch/o3.txt")
  check "$s: summary '$got' = file's '$want'" "[ -n '$got' ] && [ '$got' = '$want' ]"
  check "$s: no tensile or distant interactions" "echo '$got' | grep -q 'tensile=0 distant=0'"
done
check "no traceback" "! grep -q Traceback '$scratch/o1.txt' '$scratch/o2.txt' '$scratch/o3.txt'"

# The tool's own forces (N along n, signed T along t) balance on every grain (both packings
# were equilibrated to 1e-3 F0 and 1e-4 a P): a wrong sign of T or of the distant attraction
# would not.
check_python "the tool's forces balance" "$scratch/balance.txt" "$GRANPACK_SOURCE_DIR/jobs/tools" "$coh" "$mu05" <<'PY'
import sys
sys.path.insert(0, sys.argv[1])
import numpy as np
import plot_2d
bad = 0
for path in sys.argv[2:]:
    r = plot_2d.load(path, "x")
    plot_2d.classify(r, 1e-3)
    F = r["N"][:, None] * r["n_hat"] + r["T"][:, None] * r["t_hat"]  # on the second grain
    net = np.zeros_like(r["x"])
    np.add.at(net, r["j"], F)
    np.add.at(net, r["i"], -F)
    worst = np.hypot(net[:, 0], net[:, 1]).max() / r["unit"]
    na = r["N"][r["distant"]] / r["unit"]
    ok = worst < 2e-3 and np.all((na < 0) & (na > -1))
    print(f"{path}: max net force {worst:.3g} unit, distant N {np.round(na, 4)}")
    bad += not ok
sys.exit(bad)
PY
cat "$scratch/balance.txt"

# --- bad input: non-zero exit, a clear message, nothing written ------------------------------
bad() {  # bad NAME PATTERN ARGS...: the tool must fail with PATTERN in its message
  local name=$1 pattern=$2; shift 2
  check_refused "$name" '!0' "$pattern" "$scratch/bad_$name.txt" "$py" "$tool" "$scratch/bad_$name" "$@"
  check "$name: no PNG written" "! ls '$scratch/bad_$name'/*.png > /dev/null 2>&1"
}
bad missing "does_not_exist.h5.*no such file" "$mu05" "$scratch/does_not_exist.h5"
echo "not hdf5" > "$scratch/text.h5"
bad not_hdf5 "text.h5.*not a readable HDF5 file" "$scratch/text.h5"
bad three_d "D_n4000_seed1.h5.*3D packing" "$mu05" "$data/D_n4000_seed1.h5"
bad labels "labels has 1 labels for 2 files" "$mu05" "$mu015" --labels one

checks_done plot_2d
