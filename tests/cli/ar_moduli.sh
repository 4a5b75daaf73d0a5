#!/usr/bin/env bash
# ctest: PROCESSORS 1   (one process at a time: ctest -j2 runs another test beside it)
# Physics checks of the moduli of `granpack stiffness` (docs/stiffness.md, "Moduli of the [AR]
# ensembles"), against an independent reference written from the contact list alone
# (tests/support/hertz_moduli.py: Hertz forces N0 (h/h0)^(3/2) of the strained packing, stress
# by central differences, the grains relaxed with a Hessian assembled in Python):
# - A at 1 MPa (frictionless, n = 1372, docs/data/fig3/A_n1372_seed1_level4.h5): every entry of
#   c_affine and of c equals the reference to 1e-7 of max |c|, the shear block to 1e-5 of G_V
#   (its pre-stress terms are P ~ 5e-2 G_V); B of the tensor equals the pressure response to
#   an isotropic strain with the grains relaxed, measured directly (1e-7); the non-affine part
#   is negative semi-definite (frictionless: the relaxation can only soften);
# - D (mu = 0.3, n = 4000, docs/data/D_n4000_seed1.h5): the affine B equals its closed form
#   (2/3) P + sum k_n r^2 / (9 V) over the backbone contacts (friction does not enter it);
# - on both: the affine G/B of isotropically oriented contacts, 3 (2 + 3 k_t/k_n) / 10 (1 %); Voigt and Reuss averages recomputed from c (Hill's textbook forms) equal the JSON's,
#   Voigt >= Reuss for B and G, relaxed <= affine for B and G, mean k_n = 3 N / (2 h);
# - jobs/tools/ensemble_moduli.py on synthetic stiffness JSONs: mean, sd (ddof = 1), K, G/B
#   per sample, z* = 2 N_c* / n*, non-affine fractions, an invalid sample excluded, K = 1 with
#   sd null, the JSON summary, bad input exit 2;
# - the committed docs/data/ensembles/moduli.json is what this build computes for D and A at 1 MPa
#   (rerun jobs/runs/ar_moduli.sh and jobs/tools/ensemble_moduli.py when the physics changes);
# - the committed K = 5 ensembles are isotropic within their scatter: per state and group (the
#   axial c11, c22, c33; the shear c44, c55, c66, (c11 - c12)/2), the largest paired |t| over
#   the samples stays below Student's t at 1 % two-sided, Bonferroni-corrected over the group's
#   pairs (4 degrees of freedom: 6.25 axial, 7.53 shear). Lenient for a state, not for a code
#   error: a c44/c55 index mix-up would shift one entry by G_V against pair sds of 0.2-2 % of it;
# - every A and A' rerun (jobs/runs/ar_moduli_json/ens/) is stable along the strains the cell
#   relaxed while it was prepared: the normal-strain block c11..c33 is positive definite, and
#   the tensor's symmetric part has the eigenvalues the JSON reports (docs/stiffness.md, "The
#   frictionless ensembles at n = 4000").
set -u
: "${GRANPACK_EXE:?}" "${GRANPACK_SOURCE_DIR:?}"
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
cli_scratch
data=$GRANPACK_SOURCE_DIR/docs/data

check_exit "stiffness of A at 1 MPa" 0 "$scratch/A.txt" \
  granpack_on 1 stiffness "$data/fig3/A_n1372_seed1_level4.h5" --json "$scratch/A.json" ||
  checks_stop ar_moduli
check_exit "stiffness of D" 0 "$scratch/D.txt" \
  granpack_on 1 stiffness "$data/D_n4000_seed1.h5" --json "$scratch/D.json" || checks_stop ar_moduli

/usr/bin/python3 - "$scratch" "$data" "$GRANPACK_SOURCE_DIR/jobs/tools" > "$scratch/py.txt" 2>&1 <<'PY'
import json, re, sys
import numpy as np
d, data, tools = sys.argv[1:4]
sys.path.insert(0, tools)
import granpack_io as gio
import hertz_moduli as hm
from checks import check

def common(tag, j, net):
    e = j["elastic_tensor"]
    c, aff = np.array(e["c"]), np.array(e["c_affine"])
    check(f"{tag}: the reference keeps the backbone's {j['backbone_contacts']} contacts ({len(net.i)})",
          len(net.i) == j["backbone_contacts"])
    kn = net.kn().mean()
    check(f"{tag}: mean k_n = 3N/(2h) {kn:.8g} = mean_kn {j['mean_kn']:.8g}",
          abs(kn - j["mean_kn"]) <= 1e-9 * kn)
    bv, gv, br, gr = hm.hill_averages(c)
    for name, ours, key in (("B_V", bv, "bulk_voigt"), ("G_V", gv, "shear_voigt"),
                            ("B_R", br, "bulk_reuss"), ("G_R", gr, "shear_reuss")):
        check(f"{tag}: {name} from c {ours:.8g} = {key} {e[key]}",
              e[key] is not None and abs(ours - e[key]) <= 1e-9 * abs(ours))
    check(f"{tag}: positive definite", e["positive_definite"])
    check(f"{tag}: B_V {bv:.6g} >= B_R {br:.6g}", bv >= br * (1 - 1e-12) and br > 0)
    check(f"{tag}: G_V {gv:.6g} >= G_R {gr:.6g}", gv >= gr * (1 - 1e-12) and gr > 0)
    ba, ga = e["affine"]["bulk_voigt"], e["affine"]["shear_voigt"]
    check(f"{tag}: relaxed B {bv:.6g} <= affine {ba:.6g}", bv <= ba)
    check(f"{tag}: relaxed G_V {gv:.6g} <= affine {ga:.6g}", gv <= ga)
    b_trace = hm.bulk_affine_trace(net, gio_p[tag].pressure)
    check(f"{tag}: affine B {ba:.10g} = (2/3) P + sum k_n r^2 / (9V) {b_trace:.10g} (1e-9)",
          abs(ba - b_trace) <= 1e-9 * ba)
    # Affine moduli of isotropically oriented contacts (r ~ a, docs/stiffness.md): B = z Phi k_n /
    # (3 pi a), G = z Phi (2 k_n + 3 k_t) / (10 pi a), so G/B = 3 (2 + 3 k_t/k_n) / 10, with
    # Mindlin's k_t / k_n = (2 - 2 nu) / (2 - nu) (0 without friction); 1 %: the contact
    # orientations of 4000 grains are isotropic to a few 1e-3.
    nu = float(re.search(r"(?m)^poisson_ratio\s*=\s*([0-9.eE+-]+)", gio_p[tag].deck).group(1))
    kt = 0.0 if j["friction"] == 0 else (2 - 2 * nu) / (2 - nu)
    want = 3 * (2 + 3 * kt) / 10
    check(f"{tag}: affine G/B {ga / ba:.5f} = 3 (2 + 3 k_t/k_n) / 10 = {want:.5f} (1 %)",
          abs(ga / ba - want) < 0.01 * want)
    print(f"{tag}: B_V {bv:.6g} B_R {br:.6g} G_V {gv:.6g} G_R {gr:.6g} affine B {ba:.6g} G {ga:.6g}")
    return c, aff, gv

gio_p = {}
# A at 1 MPa, frictionless: the whole tensor against the reference
ja = json.load(open(f"{d}/A.json"))
gio_p["A"] = p = gio.read_packing(f"{data}/fig3/A_n1372_seed1_level4.h5")
check("A: frictionless", ja["friction"] == 0)
net = hm.HertzNetwork(p, ja["force_threshold"], ja["rattler_grains"])
c, aff, gv = common("A", ja, net)
top = np.abs(c).max()
ref_aff = hm.affine_tensor(net)
ref_c, residual, lu = hm.relaxed_tensor(net)
check(f"A: the reference's linear solves hold (residual {residual:.2g})", residual < 1e-10)
for name, ours, ref in (("c_affine", aff, ref_aff), ("c", c, ref_c)):
    dev = np.abs(ours - ref).max() / top
    sdev = np.abs(ours[3:, 3:] - ref[3:, 3:]).max() / gv
    print(f"A: {name} against the reference: {dev:.3g} of max|c|, shear block {sdev:.3g} of G_V")
    check(f"A: {name} = reference to {dev:.3g} of max|c| (< 1e-7)", dev < 1e-7)
    check(f"A: {name} shear block = reference to {sdev:.3g} of G_V (< 1e-5)", sdev < 1e-5)
b_iso = hm.isotropic_pressure_response(net, lu)
e = ja["elastic_tensor"]
check(f"A: pressure response to an isotropic strain {b_iso:.10g} = bulk_voigt {e['bulk_voigt']:.10g} (1e-7)",
      abs(b_iso - e["bulk_voigt"]) <= 1e-7 * b_iso)
check("A: bulk_voigt = bulk_modulus", abs(e["bulk_voigt"] - ja["bulk_modulus"]) <= 1e-12 * ja["bulk_modulus"])
non = np.array(e["c_nonaffine"])
lam = np.linalg.eigvalsh(0.5 * (non + non.T)).max()
check(f"A: c_nonaffine negative semi-definite (largest eigenvalue {lam / top:.3g} max|c|)", lam <= 1e-9 * top)

# D, frictional: the affine bulk modulus in closed form, bounds
jd = json.load(open(f"{d}/D.json"))
gio_p["D"] = p = gio.read_packing(f"{data}/D_n4000_seed1.h5")
check("D: frictional", jd["friction"] > 0)
common("D", jd, hm.HertzNetwork(p, jd["force_threshold"], jd["rattler_grains"]))

# The committed table (docs/data/ensembles/moduli.json) is what this build computes: the D row
# and the 1 MPa level of the pressure series, recomputed here (1e-8; 1 and 2 ranks agree to 1e-13).
sys.path.insert(0, tools)
import ensemble_moduli as em
committed = json.load(open(f"{data}/ensembles/moduli.json"))
row = committed["states"]["D (docs/data)"]["quantities"]
level = [r for r in committed["pressure_series"] if r["file"] == "A_n1372_seed1_level4.json"]
check("moduli.json has the D row and the 1 MPa A level", row["B_V"]["values"] and len(level) == 1)
for tag, j, ref in (("D", jd, {q: row[q]["values"][0] for q in row}), ("A 1 MPa", ja, level[0] if level else {})):
    now, _ = em.sample_values(f"{d}/{'D' if tag == 'D' else 'A'}.json")
    for q in ("B_V", "B_R", "G_V", "G_R", "nonaffine_G", "z_star", "k"):
        check(f"{tag}: committed {q} {ref.get(q)} = this build's {now[q]}",
              ref.get(q) is not None and abs(ref[q] - now[q]) <= 1e-8 * abs(now[q]))
PY
checks_from "the moduli checks" "$scratch/py.txt" $?

# The ensemble tool on synthetic stiffness JSONs (numbers chosen here, statistics recomputed)
/usr/bin/python3 - "$scratch/syn" > "$scratch/mk.txt" 2>&1 <<'PY'
import json, os, sys
root = sys.argv[1]
def sample(path, b, g, ba, ga, nc, nstar, p, k, valid=True, br=None, gr=None, diag=None):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    e = {"bulk_voigt": b, "shear_voigt": g, "bulk_reuss": br or 0.99 * b, "shear_reuss": gr or 0.98 * g,
         "affine": {"bulk_voigt": ba, "shear_voigt": ga}}
    if diag:  # a Voigt tensor in the order yz, xz, xy, xx, yy, zz (the tool must follow voigt_order)
        order = ["yz", "xz", "xy", "xx", "yy", "zz"]
        c = [[4e7 if r >= 3 and q >= 3 else 0.0 for q in range(6)] for r in range(6)]
        for r in range(6):
            c[r][r] = diag[r]
        e.update(c=c, voigt_order=order, shear_c44=sum(diag[:3]) / 3,
                 shear_c11_c12=(sum(diag[3:]) / 3 - 4e7) / 2)
    j = {"backbone_contacts": nc, "backbone_grains": nstar, "pressure": p, "phi": 0.6, "mechanisms": k,
         "H_over_Nf": 0.1, "bulk_modulus": b, "bulk_modulus_reduced": b / 1e8, "moduli_valid": valid,
         "elastic_tensor": e if valid else None}
    json.dump(j, open(path, "w"))
# Diagonals (yz, xz, xy, xx, yy, zz): c44 = yz, c55 = xz, c66 = xy, c11 = xx, ...
sample(f"{root}/ens/X/sample_1.json", 3e7, 1.5e7, 4e7, 4e7, 9000, 3600, 1000, 100,
       diag=[3.0e7, 3.1e7, 2.9e7, 10e7, 11e7, 12e7])
sample(f"{root}/ens/X/sample_2.json", 3.2e7, 1.4e7, 4e7, 5e7, 9100, 3500, 1001, 110,
       diag=[3.2e7, 3.0e7, 3.1e7, 10.5e7, 10e7, 11e7])
sample(f"{root}/ens/X/sample_3.json", 2.9e7, 1.6e7, 5e7, 4e7, 8900, 3700, 999, 90,
       diag=[2.8e7, 2.9e7, 3.3e7, 9e7, 10.5e7, 12.5e7])
sample(f"{root}/ens/X/sample_4.json", 1, 1, 1, 1, 1, 1, 1, 1, valid=False)
sample(f"{root}/single/Y_n4000_seed1.json", 8e7, 1e6, 1e8, 6e7, 12000, 3950, 1e4, 3)
# A frictional pressure series, files named out of pressure order: B = 1e7 (P/1e3)^0.35,
# G = 5e6 (P/1e3)^0.4
for stem, p in (("QS_2", 1e5), ("D", 1e3), ("QS_1", 1e4)):
    sample(f"{root}/qs/S/{stem}.json", 1e7 * (p / 1e3) ** 0.35, 5e6 * (p / 1e3) ** 0.4, 2e7, 2e7,
           9000, 4000, p, 90)
    # a second seed of the same series: B = 1.2e7 (P/1e3)^0.33, G = 6e6 (P/1e3)^0.42
    sample(f"{root}/qs/T/{stem}.json", 1.2e7 * (p / 1e3) ** 0.33, 6e6 * (p / 1e3) ** 0.42, 2e7, 2e7,
           9000, 4000, p, 90)
PY
check "synthetic inputs written" '[ -s "$scratch/syn/single/Y_n4000_seed1.json" ]' || cat "$scratch/mk.txt"
check_exit "ensemble_moduli.py on the synthetic set" 0 "$scratch/tool.txt" \
  /usr/bin/python3 "$GRANPACK_SOURCE_DIR/jobs/tools/ensemble_moduli.py" "$scratch/syn" --json "$scratch/syn.json"
/usr/bin/python3 - "$scratch/syn.json" > "$scratch/py2.txt" 2>&1 <<'PY'
import json, statistics, sys
from checks import check
s = json.load(open(sys.argv[1]))["states"]
x, y = s["X"]["quantities"], s["Y (docs/data)"]["quantities"]
check(f"X: K = 3 ({s['X']['K']}), sample_4 excluded", s["X"]["K"] == 3 and
      [e["file"] for e in s["X"]["excluded"]] == ["sample_4.json"])
def same(name, got, want):
    check(f"{name}: {got} = {want}", got is not None and abs(got - want) <= 1e-12 * abs(want))
B, G = [3e7, 3.2e7, 2.9e7], [1.5e7, 1.4e7, 1.6e7]
same("mean B_V", x["B_V"]["mean"], statistics.mean(B))
same("sd B_V (ddof 1)", x["B_V"]["sd"], statistics.stdev(B))
same("sd G_V (ddof 1)", x["G_V"]["sd"], statistics.stdev(G))
same("mean B_R", x["B_R"]["mean"], 0.99 * statistics.mean(B))
gb = [g / b for g, b in zip(G, B)]
same("mean G/B over the samples", x["G_over_B"]["mean"], statistics.mean(gb))
same("sd G/B", x["G_over_B"]["sd"], statistics.stdev(gb))
same("mean z*", x["z_star"]["mean"], statistics.mean([2 * 9000 / 3600, 2 * 9100 / 3500, 2 * 8900 / 3700]))
same("mean 1 - G/G_aff", x["nonaffine_G"]["mean"], statistics.mean([1 - 1.5 / 4, 1 - 1.4 / 5, 1 - 1.6 / 4]))
same("sd 1 - B/B_aff", x["nonaffine_B"]["sd"], statistics.stdev([1 - 3 / 4, 1 - 3.2 / 4, 1 - 2.9 / 5]))
same("mean k", x["k"]["mean"], 100)
same("sd P", x["P"]["sd"], 1.0)
same("G reduced", x["G_reduced"]["values"][0], 1.5e7 / 1e8)
check("Y: K = 1, sd null", s["Y (docs/data)"]["K"] == 1 and y["B_V"]["sd"] is None and y["B_V"]["mean"] == 8e7)
# The Voigt diagonal by voigt_order, and the isotropy t of the paired differences
diags = [[3.0e7, 3.1e7, 2.9e7, 10e7, 11e7, 12e7], [3.2e7, 3.0e7, 3.1e7, 10.5e7, 10e7, 11e7],
         [2.8e7, 2.9e7, 3.3e7, 9e7, 10.5e7, 12.5e7]]
same("c11 mean (xx)", x["c11"]["mean"], statistics.mean(d[3] for d in diags))
same("c33 sd (zz)", x["c33"]["sd"], statistics.stdev(d[5] for d in diags))
same("c66 mean (xy)", x["c66"]["mean"], statistics.mean(d[2] for d in diags))
def t_of(a, b):
    diff = [u - v for u, v in zip(a, b)]
    return abs(statistics.mean(diff)) / (statistics.stdev(diff) / len(diff) ** 0.5)
axial = {(i, j): t_of([d[3 + i] for d in diags], [d[3 + j] for d in diags])
         for i in range(3) for j in range(i + 1, 3)}
iso = s["X"]["isotropy"]
same("isotropy: axial max |t|", iso["axial"]["t"], max(axial.values()))
check(f"isotropy: axial pair {iso['axial']['pair']} is c22, c33", iso["axial"]["pair"] == ["c22", "c33"])
shear = [[d[0], d[1], d[2], (statistics.mean(d[3:]) - 4e7) / 2] for d in diags]
tmax = max(t_of([r[i] for r in shear], [r[j] for r in shear]) for i in range(4) for j in range(i + 1, 4))
same("isotropy: shear max |t| (c44, c55, c66, (c11 - c12)/2)", iso["shear"]["t"], tmax)
check("isotropy of a one-sample state is null", s["Y (docs/data)"]["isotropy"]["axial"] is None)
doc = json.load(open(sys.argv[1]))
rows = doc["qs_series"]["S"]
check(f"qs series S ordered by pressure: {[r['file'] for r in rows]}",
      [r["file"] for r in rows] == ["D.json", "QS_1.json", "QS_2.json"])
f = doc["qs_fits"]["S"]
same("qs: B_V exponent", f["B_V_vs_P"]["exponent"], 0.35)
same("qs: G_V exponent", f["G_V_vs_P"]["exponent"], 0.4)
same("qs: G_V prefactor", f["G_V_vs_P"]["prefactor"] * 1e3 ** 0.4, 5e6)
# The two series S, T as an ensemble: per level mean ± sd over the series, and of the exponents
e = doc["qs_ensemble"]
check(f"qs ensemble: K = 2, levels {list(e['levels'])} by pressure",
      e["K"] == 2 and list(e["levels"]) == ["D.json", "QS_1.json", "QS_2.json"])
b1 = [1e7 * 10 ** 0.35, 1.2e7 * 10 ** 0.33]
same("qs ensemble: mean B_V at QS_1", e["levels"]["QS_1.json"]["B_V"]["mean"], statistics.mean(b1))
same("qs ensemble: sd B_V at QS_1", e["levels"]["QS_1.json"]["B_V"]["sd"], statistics.stdev(b1))
same("qs ensemble: mean G_V exponent", e["exponents"]["G_V_vs_P"]["mean"], 0.41)
same("qs ensemble: sd B_V exponent", e["exponents"]["B_V_vs_P"]["sd"], statistics.stdev([0.35, 0.33]))
PY
checks_from "the ensemble tool checks" "$scratch/py2.txt" $?

/usr/bin/python3 - "$data/ensembles/moduli.json" "$GRANPACK_SOURCE_DIR/jobs/runs/ar_moduli_json/ens" \
  > "$scratch/py3.txt" 2>&1 <<'PY'
import glob, json, sys
import numpy as np
from scipy import stats
from checks import check
states = json.load(open(sys.argv[1]))["states"]
crit = {g: stats.t.ppf(1 - 0.01 / 2 / pairs, 4) for g, pairs in (("axial", 3), ("shear", 6))}
five = [n for n, s in states.items() if s["K"] == 5 and s.get("isotropy")]
check(f"K = 5 ensembles with an isotropy entry: {five}",
      {"A", "A_prime", "B", "C", "D", "Z"} <= set(five))
for name in five:
    for g, c in crit.items():
        t = states[name]["isotropy"][g]["t"]
        check(f"{name}: {g} max paired |t| {t:.2f} < {c:.2f}", t < c)
for st in ("A", "A_prime"):
    files = sorted(glob.glob(f"{sys.argv[2]}/{st}/sample_*.json"))
    check(f"{st}: five rerun tensors", len(files) == 5)
    for f in files:
        e = json.load(open(f))["elastic_tensor"]
        c = np.array(e["c"]); c = (c + c.T) / 2
        assert e["voigt_order"][:3] == ["xx", "yy", "zz"], e["voigt_order"]
        lam = np.linalg.eigvalsh(c[:3, :3]).min() / np.abs(c).max()
        check(f"{st} {f[-13:]}: normal-strain block positive definite ({lam:.2e} max|c|)", lam > 0)
        ev = np.sort(np.linalg.eigvalsh(c)); rep = np.sort(np.array(e["eigenvalues"]))
        check(f"{st} {f[-13:]}: eigenvalues as reported", np.allclose(ev, rep, rtol=0, atol=1e-9 * np.abs(c).max()))
        check(f"{st} {f[-13:]}: positive_definite flag = smallest eigenvalue > 0",
              e["positive_definite"] == bool(ev[0] > 0))
PY
checks_from "the committed ensembles' isotropy and stability" "$scratch/py3.txt" $?
check "the table prints X with mean ± sd" "grep -q '^X | 3 | ' '$scratch/tool.txt'" || cat "$scratch/tool.txt"
mkdir -p "$scratch/empty"
check_refused "ensemble_moduli.py on an empty directory" 2 "no stiffness JSON" "$scratch/empty.txt" \
  /usr/bin/python3 "$GRANPACK_SOURCE_DIR/jobs/tools/ensemble_moduli.py" "$scratch/empty"
checks_done ar_moduli
