#!/usr/bin/env bash
# [GRC] method 1 on 300 cohesive disks with rolling resistance (jobs/decks/2d/
# method1_cohesive_small.toml), on 1 and 2 ranks: the compress stage must meet the II D
# criteria (force, moment, pressure, kinetic energy on F1 = F0), and the written packing is
# then checked independently of the engine, from the file alone:
# - every contact obeys the law: N^e = K_N h, and Coulomb |T| < mu N^e and the rolling
#   condition K_r |dtheta| < mu_r N^e hold as STRICT inequalities ([GRC] II D observes this
#   of every equilibrated sample), with neither yield flag set; distant pairs (flag 4) have a
#   gap below D0 and no N^e, T or rolling rotation;
# - the net static force (N^e - F0 or the distant attraction, along n, plus T) on every grain
#   is below 1e-4 F0 and the net moment (branch vectors to the middle of the overlap, plus the
#   rolling moments -/+ K_r dtheta) below 1e-4 F0 a;
# - the static pressure from these forces is P within 1e-4 F0/a;
# - report.json's [GRC] coordination (z over all interactions, z+ / z- / z0 by the sign of the
#   static normal force beyond 1e-4 F0, distant fraction) equals the count from the file;
# - `granpack stiffness` (1 and 2 ranks): the network is rigid, K(1) positive definite, G has
#   3 rows per contact (rolling resistance) and 1 per distant pair, H by eq. (21);
# - `granpack analyze` (1 and 2 ranks, same results) gives the interaction statistics of
#   [GRC] sec. IV that the file gives independently: z+/z-/z0, the vanishing and > F0/10
#   fractions, the N/F0 and force-angle histograms, table VI's force means by sign class, the
#   x_k of figs. 3 and 6, Rumpf's eq. (17) and the percolation
#   threshold F_perc (here by bisection over |F| with a breadth-first unwrapping, not the
#   union-find of the code).
set -u
: "${GRANPACK_EXE:?}" "${GRANPACK_SOURCE_DIR:?}"
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
cli_scratch
deck="$GRANPACK_SOURCE_DIR/jobs/decks/2d/method1_cohesive_small.toml"
for np in 1 2; do
  check_exit "run on $np rank(s)" 0 "$scratch/np$np.txt" granpack_on $np run "$deck" -o "$scratch/np$np" --quiet \
    || checks_stop cohesive_2d
done
# --quiet: no progress lines on the terminal, but log.txt keeps them (a batch job's progress).
check "--quiet keeps progress lines out of the terminal" "! grep -q '^  step ' '$scratch/np2.txt'"
check "--quiet keeps progress lines in log.txt" "grep -q '^  step ' '$scratch/np2/log.txt'"
# [GRC]'s I-state has no contacts (random sequential addition): the compression must start
# with almost no interactions. The overlap-removal gas left ~0.6 n contacts here, which
# cohesion bonded before the compression and made method 1 6-18 % too loose.
n_grains=$(sed -n 's/^n = //p' "$deck")
for np in 1 2; do
  first=$(grep -m1 '^  step ' "$scratch/np$np/log.txt" | sed -n 's/.*contacts *\([0-9]*\).*/\1/p')
  check "np$np: the compression starts with '${first}' interactions among $n_grains disks (at most n/20: the I-state is contact-free)" \
    '! { [ -z "$first" ] || [ "$first" -gt $((n_grains / 20)) ]; }'
done
# Rigidity ([GRC] App. A) on 1 and 2 ranks: the interaction network of an equilibrated packing
# with rolling resistance at P* = 0.01 is rigid (only the 2 translations), K(1) is positive
# definite; G has 3 rows per contact and 1 per distant pair; both runs agree.
for np in 1 2; do
  check_exit "stiffness on $np rank(s)" 0 "$scratch/st$np.txt" \
    granpack_on $np stiffness "$scratch/np2/final.h5" --json "$scratch/st$np.json"
done
# The Python blocks print one line per check (cli_checks.sh checks_from).
/usr/bin/python3 - "$scratch" > "$scratch/st_py.txt" 2>&1 <<'PY'
import json, sys
from checks import check
d = sys.argv[1]
a, b = (json.load(open(f"{d}/st{n}.json")) for n in (1, 2))
for j in (a, b):
    check(f"stiffness, ranks {j['ranks']}: rigid {j['rigid']}, positive definite {j['positive_definite']}, k {j['mechanisms']} = 2",
          j["rigid"] and j["positive_definite"] and j["mechanisms"] == 2)
    rows = 3 * (j["backbone_contacts"] - j["distant_pairs"]) + j["distant_pairs"]
    check(f"stiffness, ranks {j['ranks']}: rows {j['G_rows']} (expected {rows}), H {j['H']}, {j['H_relation']}",
          not (j["G_rows"] != rows or j["H"] != rows + j["mechanisms"] - j["N_f"] or j["H_relation"] != "GRC eq. 21"))
for key in ("H", "mechanisms", "backbone_contacts", "distant_pairs"):
    check(f"stiffness {key}: {a[key]} on 1 rank, {b[key]} on 2", a[key] == b[key])
check(f"stiffness B {a['bulk_modulus']} on 1 rank, {b['bulk_modulus']} on 2",
      not abs(a["bulk_modulus"] - b["bulk_modulus"]) > 1e-8 * abs(a["bulk_modulus"]))
print(f"stiffness: H {a['H']} (eq. 21), B {a['bulk_modulus']:.6g} N/m on 1 and 2 ranks")
PY
checks_from "the stiffness checks" "$scratch/st_py.txt" $?
for np in 1 2; do
  check_exit "analyze on $np rank(s)" 0 "$scratch/an$np.txt" \
    granpack_on $np analyze "$scratch/np2/final.h5" --json "$scratch/an$np.json"
done
/usr/bin/python3 - "$scratch" > "$scratch/py.txt" 2>&1 <<'PY'
import json, sys
import h5py, numpy as np
from checks import check
d = sys.argv[1]
# The deck's parameters (jobs/decks/2d/method1_cohesive_small.toml).
a, F0, D0, KN, mu, Kr, mur, P = 1e-3, 1.0, 1e-6, 1e7, 0.5, 1e-3, 5e-6, 10.0
for np_ in (1, 2):
    rep = json.load(open(f"{d}/np{np_}/report.json"))
    comp = [s for s in rep["stages"] if s["kind"] == "compress"][0]
    check(f"np{np_}: compress equilibrated", comp.get("equilibrated"))
    with h5py.File(f"{d}/np{np_}/final.h5", "r") as f:
        ids = f["particles/id"][:]
        idx = {g: k for k, g in enumerate(ids)}
        L = f["cell/length"][:]
        x = f["particles/scaled_position"][:] * L
        R = f["particles/radius"][:]
        first = np.array([idx[g] for g in f["contacts/first"][:]])
        second = np.array([idx[g] for g in f["contacts/second"][:]])
        Ne = f["contacts/normal_force"][:]
        T = f["contacts/tangential_force"][:]
        rot = f["contacts/rolling"][:][:, 0]
        flags = f["contacts/flags"][:]
    r = x[second] - x[first]
    r -= L * np.round(r / L)
    dist = np.sqrt((r ** 2).sum(1))
    n = r / dist[:, None]
    h = R[first] + R[second] - dist
    distant = (flags & 4) != 0
    touch = ~distant
    check(f"np{np_}: {int(((flags & 3) != 0).sum())} contacts on a yield surface (none allowed)",
          not (flags & 3).any())
    if touch.any():
        check(f"np{np_}: every contact overlaps", not (h[touch] <= 0).any())
        err = np.abs(Ne[touch] - KN * h[touch]).max() / F0
        check(f"np{np_}: N^e = K_N h within 1e-9 F0 ({err:.3g} F0)", not err > 1e-9)
        Tn = np.sqrt((T[touch] ** 2).sum(1))
        check(f"np{np_}: Coulomb strict: max |T|/(mu N^e) {np.max(Tn / (mu * Ne[touch])):.6f} < 1",
              (Tn < mu * Ne[touch]).all())
        check(f"np{np_}: rolling condition strict", (Kr * np.abs(rot[touch]) < mur * Ne[touch]).all())
        coulomb = np.max(Tn / (mu * Ne[touch]))
        rolling = np.max(Kr * np.abs(rot[touch]) / (mur * Ne[touch]))
    if distant.any():
        g = -h[distant]
        check(f"np{np_}: distant pairs within range, without contact forces",
              not ((g < 0).any() or (g >= D0).any() or Ne[distant].any() or T[distant].any() or rot[distant].any()))
    # Static forces: along n the elastic part and the attraction, plus T (on the second grain).
    Na = np.where(distant, -F0 * (1 + h / D0), -F0)
    F = (Ne + Na)[:, None] * n + T
    net = np.zeros_like(x)
    np.add.at(net, second, F)
    np.add.at(net, first, -F)
    cross = lambda b, f: b[:, 0] * f[:, 1] - b[:, 1] * f[:, 0]
    gam = -Kr * rot  # rolling moment on the second grain
    mom = np.zeros(len(x))
    np.add.at(mom, second, cross(-(R[second] - 0.5 * h)[:, None] * n, F) + gam)
    np.add.at(mom, first, cross((R[first] - 0.5 * h)[:, None] * n, -F) - gam)
    fmax = np.sqrt((net ** 2).sum(1)).max() / F0
    gmax = np.abs(mom).max() / (F0 * a)
    sigma = (F[:, :, None] * r[:, None, :]).sum(0) / (L[0] * L[1])
    dp = np.abs(np.diag(sigma) - P).max() * a / F0
    phi = np.pi * (R ** 2).sum() / (L[0] * L[1])
    print(f"np{np_}: phi {phi:.4f}, {int(touch.sum())} contacts + {int(distant.sum())} distant, "
          f"max |T|/(mu N^e) {coulomb:.4f}, max K_r|dtheta|/(mu_r N^e) {rolling:.4f}, "
          f"F/F0 {fmax:.2e}, Gamma/(F0 a) {gmax:.2e}, |dP| a/F0 {dp:.2e}")
    check(f"np{np_}: net force {fmax:.3g} F0 from the file < 1e-4", not fmax >= 1e-4)
    check(f"np{np_}: net moment {gmax:.3g} F0 a from the file < 1e-4", not gmax >= 1e-4)
    check(f"np{np_}: pressure error {dp:.3g} F0/a from the file < 1e-4", not dp >= 1e-4)
    check(f"np{np_}: phi {phi} in (0.5, 0.8)", 0.5 < phi < 0.8)
    Ns = Ne + Na
    counts = {"z_interactions": 2 * len(Ns) / len(x), "z_plus": 2 * (Ns > 1e-4 * F0).sum() / len(x),
              "z_minus": 2 * (Ns < -1e-4 * F0).sum() / len(x),
              "z_zero": 2 * (np.abs(Ns) <= 1e-4 * F0).sum() / len(x),
              "distant_fraction": distant.sum() / len(Ns)}
    vals = comp.get("values", {})
    for k, v in counts.items():
        check(f"np{np_}: report {k} = {vals.get(k)}, the file gives {v}",
              not (k not in vals or abs(vals[k] - v) > 1e-12))
    print(f"np{np_}: " + ", ".join(f"{k} {v:.4f}" for k, v in counts.items()))
    if np_ != 2:
        continue
    # granpack analyze's interaction section against the file (this is the file it analysed).
    an = [json.load(open(f"{d}/an{k}.json"))["interactions"] for k in (1, 2)]
    def close(key, v1, v2, tol=1e-12):
        check(f"analyze {key}: {v1}, expected {v2}", not abs(v1 - v2) > tol * max(1.0, abs(v2)))
    t = np.where(distant[:, None], 0.0, T - (T * n).sum(1)[:, None] * n)
    Tm = np.sqrt((t ** 2).sum(1))
    F = np.hypot(Ns, Tm)
    tol = 1e-4 * F0
    d_grain = 2 * R
    z_all = 2 * len(Ns) / len(x)
    pred = np.pi * (np.diag(sigma).mean()) * (d_grain ** 2).mean() / (d_grain.mean() * z_all * phi)
    expect = {"z_plus": counts["z_plus"], "z_minus": counts["z_minus"], "z_zero": counts["z_zero"],
              "fraction_vanishing": (F < tol).mean(), "fraction_above_tenth": (np.abs(Ns) > 0.1 * F0).mean()}
    for k, v in expect.items():
        close(k, an[1][k], v)
    close("rumpf mean N", an[1]["rumpf"]["mean_normal_force"], Ns.mean())
    close("rumpf eq. (17)", an[1]["rumpf"]["predicted_eq17"], pred, 1e-9)
    hN, _ = np.histogram(Ns / F0, bins=np.linspace(-1.5, 3.5, 101))
    th = np.degrees(np.arctan2(Tm, Ns))[F >= tol]
    hA, _ = np.histogram(th, bins=np.linspace(0, 180, 37))
    for key, h in (("normal_force_pdf", hN), ("force_angle_pdf", hA)):
        got = np.array(an[1][key]["pdf"]) * an[1][key]["count"] * (np.diff(an[1][key]["edges"])[0])
        check(f"analyze {key}: counts {got[:8]}..., the file gives {h[:8]}...", np.allclose(got, h, atol=1e-9))
    # Table VI's force means by sign class and the x_k of figs. 3 and 6, on 1 and 2 ranks.
    for a_ in an:
        for cls, sel in (("repulsive", Ns > tol), ("attractive", Ns < -tol), ("vanishing", np.abs(Ns) <= tol)):
            m = a_["force_means"][cls]
            close(f"{cls} count", m["count"], sel.sum())
            close(f"{cls} <|N|>/F0", m["mean_abs_N_over_Fs"], np.abs(Ns[sel]).mean() / F0)
            close(f"{cls} <N^2>^1/2/F0", m["rms_N_over_Fs"], np.sqrt((Ns[sel] ** 2).mean()) / F0)
            close(f"{cls} <|T|>/F0", m["mean_abs_T_over_Fs"], Tm[sel].mean() / F0)
            close(f"{cls} <T^2>^1/2/F0", m["rms_T_over_Fs"], np.sqrt((Tm[sel] ** 2).mean()) / F0)
        for key, sel in (("x_k", np.ones(len(Ns), bool)), ("x_k_stressed", np.abs(Ns) > tol)):
            k_i = np.bincount(np.concatenate([first[sel], second[sel]]), minlength=len(x))
            expect_x = {str(k): c / len(x) for k, c in enumerate(np.bincount(k_i)) if c}
            check(f"analyze {key}: {a_[key]}, the file gives {expect_x}",
                  a_[key].keys() == expect_x.keys() and all(abs(a_[key][k] - v) < 1e-12 for k, v in expect_x.items()))
    # F_perc: the largest |F| whose network {|F| >= F} wraps around the cell.
    img = np.round(((x[first] + r) - x[second]) / L).astype(int)  # image of the second grain
    def wraps(thr):
        sel = np.nonzero(F >= thr)[0]
        adj = {}
        for e in sel:
            i, j, s_ = first[e], second[e], img[e]
            adj.setdefault(i, []).append((j, s_))
            adj.setdefault(j, []).append((i, -s_))
        seen = {}
        for start in adj:
            if start in seen: continue
            seen[start] = np.zeros(2, int); stack = [start]
            while stack:
                u = stack.pop()
                for w, s_ in adj[u]:
                    o = seen[u] + s_
                    if w not in seen:
                        seen[w] = o; stack.append(w)
                    elif (seen[w] != o).any():
                        return True
        return False
    cand = np.unique(F)[::-1]
    lo, hi = 0, len(cand) - 1  # find the first (largest) candidate that wraps
    if wraps(cand[hi]):
        while lo < hi:
            mid = (lo + hi) // 2
            if wraps(cand[mid]): hi = mid
            else: lo = mid + 1
        fperc = cand[lo]
    else:
        fperc = 0.0
    close("F_perc", an[1]["F_perc_over_Fs"], fperc / F0)
    check(f"F_perc {fperc} in (0, max |F|)", 0 < fperc < F.max())
    for k in an[0]:
        if isinstance(an[0][k], (int, float)) and not isinstance(an[0][k], bool):
            close(f"{k} (1 against 2 ranks)", an[0][k], an[1][k])
    print(f"analyze: F_perc/F0 {fperc / F0:.4g}, Rumpf <N>/pred {Ns.mean() / pred:.4f}, "
          f"vanishing {expect['fraction_vanishing']:.4f}")
PY
checks_from "the file checks" "$scratch/py.txt" $?
checks_done cohesive_2d
