#!/usr/bin/env bash
# The sign conventions of the contacts group (docs/hdf5-schema.md, "Sign conventions"), checked
# on the committed equilibrated files of docs/data and docs/data/2d (those written after a
# compress stage: fix_rattlers outputs carry external pushes, aggregates are not static).
# With n = unit(minimum-image r_second - r_first), f = (N^e + N^a) n + T acts on the second
# grain and -f on the first, at the contact points b_first = (R_first - h/2) n and
# b_second = -(R_second - h/2) n; the rolling moment is -K_r rolling on the second grain and
# +K_r rolling on the first (K_r after the stiffen stages, replayed here from the deck
# independently of the file's /parameters group). Then every
# grain's net static force is below 1.5 x the stage's tolerance_force F1 and its net moment
# below 1.5 x tolerance_moment F1 a (1e-3 F1 a in 3D, where the decks set no moment
# criterion), and (1/V) sum f.r / dim is the imposed pressure (with n reversed it would be
# -P). The opposite conventions must fail: T taken on the first grain (forces), the rolling
# moment taken on the first grain (moments, files with K_r > 0). Negative controls on copies: T
# negated, rolling negated -> fail; the pair swapped with T and rolling negated (the rule of
# jobs/tools/replicate.py) -> still balanced.
# ctest: PROCESSORS 1   (one process at a time: ctest -j2 runs another test beside it)
set -u
: "${GRANPACK_SOURCE_DIR:?}"
py=/usr/bin/python3
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
cli_scratch
data="$GRANPACK_SOURCE_DIR/docs/data"

cat > "$scratch/signs.py" <<'PY'
"""Contact sign conventions of docs/hdf5-schema.md, checked on equilibrated files."""
import os, sys, tomllib
import h5py, numpy as np

def material_after(deck, stage_index):
    """K_r, F0, D0 in force at the file's stage, replayed from the deck (an independent check of
    the /parameters group the engine writes)."""
    m = dict(deck["material"])
    kr, kn = m.get("rolling_stiffness", 0.0), m.get("normal_stiffness")
    for st in deck["stage"][: stage_index + 1]:
        if st["kind"] == "stiffen":
            if st.get("scale_rolling_stiffness", True):
                kr *= st["normal_stiffness"] / kn
            kn = st["normal_stiffness"]
    return kr, m.get("cohesion_force", 0.0), m.get("cohesion_range", 1.0)

def producing_stage(deck, stage_index):
    """The last stage up to the file's that is not a write: the one that left the state."""
    return [st for st in deck["stage"][: stage_index + 1] if st["kind"] != "write"][-1]

def net(path, t_sign=1.0, n_sign=1.0, r_sign=1.0):
    """Net static force and moment on every grain (normalised by F1 and F1 a) under
    f = N n + T on second, -f on first, n from first to second, contact point at
    b_first = (R_first - h/2) n, b_second = -(R_second - h/2) n, rolling moment
    G = -K_r rolling on second, +K_r rolling on first. t_sign, n_sign, r_sign = -1 flip T,
    the normal, or G (the wrong conventions)."""
    with h5py.File(path, "r") as f:
        dim = int(f.attrs["dimension"])
        si = int(f.attrs["stage_index"])
        deck = tomllib.loads(f["deck"][()].decode("utf-8"))
        L = f["cell/length"][:]
        ids = f["particles/id"][:]
        s = f["particles/scaled_position"][:]
        R = f["particles/radius"][:]
        c = {k: f["contacts/" + k][:] for k in
             ("first", "second", "normal_force", "tangential_force", "rolling", "flags")}
    kr, f0, d0 = material_after(deck, si)
    a = deck["sample"]["diameter"]
    row = {int(g): k for k, g in enumerate(ids)}
    i = np.array([row[int(g)] for g in c["first"]], dtype=np.int64)
    j = np.array([row[int(g)] for g in c["second"]], dtype=np.int64)
    ds = s[j] - s[i]
    ds -= np.rint(ds)                                  # minimum image
    r = ds * L
    d = np.linalg.norm(r, axis=1)
    n = n_sign * r / d[:, None]
    h = R[i] + R[j] - d
    # [GRC] eq. 4-5: N^a = -F0 in contact, -F0 (1 - g/D0) across a gap g (flag 4, distant)
    na = 0.0
    if f0 > 0:
        na = np.where((c["flags"] & 4) != 0, -f0 * (1 - np.maximum(0.0, -h) / d0), -f0)
    f2 = (c["normal_force"] + na)[:, None] * n + t_sign * c["tangential_force"]
    b1 = (R[i] - h / 2)[:, None] * n
    b2 = -(R[j] - h / 2)[:, None] * n
    cross = (lambda b, v: np.cross(b, v)[:, None]) if dim == 2 else np.cross
    g2 = -r_sign * kr * c["rolling"]                   # rolling moment on second
    F = np.zeros((len(ids), dim))
    M = np.zeros((len(ids), 1 if dim == 2 else 3))
    np.add.at(F, j, f2)
    np.add.at(F, i, -f2)
    np.add.at(M, j, cross(b2, f2) + g2)
    np.add.at(M, i, cross(b1, -f2) - g2)
    stage = producing_stage(deck, si)
    P = stage.get("pressure", 0.0)
    F1 = max(f0, P * a ** (dim - 1))
    # static stress (1/V) sum f (x) r, r = L ds from first to second: its pressure is P > 0 only
    # if f (N n + T, N > 0 repulsive) is the force on second
    p_meas = np.einsum("ka,ka->", f2, r) / (dim * np.prod(L))
    t_max = np.linalg.norm(c["tangential_force"], axis=1).max(initial=0.0) / F1
    return dict(force=np.linalg.norm(F, axis=1).max() / F1,
                moment=np.linalg.norm(M, axis=1).max() / (F1 * a), pressure=p_meas, P=P,
                stage=stage, kr=kr, t_max=t_max, F1=F1, a=a, dim=dim)

def main(paths):
    bad = 0
    for path in paths:
        with h5py.File(path, "r") as f:
            deck = tomllib.loads(f["deck"][()].decode("utf-8"))
            stage = producing_stage(deck, int(f.attrs["stage_index"]))
        name = os.path.relpath(path, os.path.dirname(os.path.dirname(path)))
        if stage["kind"] != "compress":
            print(f"skip {name}: written after a {stage['kind']} stage, not an equilibrium")
            continue
        tol_f = stage.get("tolerance_force", 1e-4)
        tol_m = stage.get("tolerance_moment")
        # 3D decks set no moment criterion ([AR] has none): a loose bound there
        lim_f, lim_m = 1.5 * tol_f, 1.5 * tol_m if tol_m else 1e-3
        r = net(path)
        line = f"{name}: max|F|/F1 {r['force']:.2e}, max|M|/(F1 a) {r['moment']:.2e}"
        ok = r["force"] < lim_f and r["moment"] < lim_m
        # the normal: with n from first to second, (N n + T) on second gives the imposed
        # pressure P (the stress criterion: within tolerance_stress F1/a^(dim-1)); with n
        # reversed it would give -P
        lim_p = 1.5 * stage.get("tolerance_stress", 1e-4) * r["F1"] / r["a"] ** (r["dim"] - 1)
        if r["P"] > 10 * lim_p:
            line += f", P {r['pressure']:.6g} Pa (target {r['P']:g})"
            ok = ok and abs(r["pressure"] - r["P"]) < lim_p
        if r["t_max"] > 10 * lim_f:
            w = net(path, t_sign=-1)["force"]
            line += f"; T on first: max|F|/F1 {w:.2e}"
            ok = ok and w > 10 * lim_f
        if r["kr"] > 0:
            w = net(path, r_sign=-1)["moment"]
            line += f"; rolling moment -K_r rolling on first: max|M|/(F1 a) {w:.2e}"
            ok = ok and w > 10 * lim_m
        print(("ok   " if ok else "FAIL ") + line)
        bad += not ok
    return bad

if __name__ == "__main__":
    sys.exit(1 if main(sys.argv[1:]) else 0)
PY

check_exit "committed files: every equilibrated file balances" 0 "$scratch/all.txt" \
  "$py" "$scratch/signs.py" "$data"/*.h5 "$data"/2d/*.h5
cat "$scratch/all.txt"  # the numbers, for the test log
check "no traceback" "! grep -q Traceback '$scratch/all.txt'"
n_ok=$(grep -c '^ok ' "$scratch/all.txt")
check "at least 30 files checked (got $n_ok)" "[ $n_ok -ge 30 ]"
check "D (3D, mu = 0.3): T on the second grain, T on the first fails" \
  "grep -q '^ok   data/D_n4000_seed1.h5: .*P .*T on first' '$scratch/all.txt'"
check "2D with rolling resistance: rolling moment -K_r rolling on the second grain" \
  "grep -q '^ok   2d/seriesA_rr_P0.01.h5: .*rolling moment' '$scratch/all.txt'"

# Negative controls on copies: the check must see a wrong sign.
check_python "negative controls written" "$scratch/controls.txt" "$data" "$scratch" <<'PY'
import shutil, sys
import h5py
data, out = sys.argv[1:]
def edit(src, dst, fn):
    shutil.copy(f"{data}/{src}", f"{out}/{dst}")
    with h5py.File(f"{out}/{dst}", "r+") as f:
        fn(f["contacts"])
def neg(*names):
    def fn(c):
        for k in names:
            c[k][...] = -c[k][...]
    return fn
def swap(c):
    a, b = c["first"][:], c["second"][:]
    c["first"][...], c["second"][...] = b, a
    neg("tangential_force", "rolling")(c)
edit("D_n4000_seed1.h5", "D_T_negated.h5", neg("tangential_force"))
edit("D_n4000_seed1.h5", "D_swapped.h5", swap)
edit("2d/seriesA_rr_P0.01.h5", "rr_rolling_negated.h5", neg("rolling"))
edit("2d/seriesA_rr_P0.01.h5", "rr_swapped.h5", swap)
PY
for bad in D_T_negated rr_rolling_negated; do
  check_refused "$bad: refused" '!0' '^FAIL ' "$scratch/$bad.txt" "$py" "$scratch/signs.py" "$scratch/$bad.h5"
done
for good in D_swapped rr_swapped; do
  check_refused "$good (first/second swapped, T and rolling negated): balanced" 0 '^ok ' "$scratch/$good.txt" \
    "$py" "$scratch/signs.py" "$scratch/$good.h5"
done

checks_done contact_signs
