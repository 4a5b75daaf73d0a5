#!/usr/bin/env bash
# [GRC] method 1 in 3D (jobs/decks/3d/method1_cohesive_small.toml: 150 cohesive spheres with
# rolling resistance, P* = 0.01), run on 1 rank, then `granpack stiffness` on the packing on 1
# and 2 ranks (docs/stiffness.md, "Cohesive and rolling-resistant 3D packings"):
# - the compress stage meets the II D criteria;
# - the network is the interaction network, G has 5 rows per contact in touch (δu and the two
#   rolling rows) and 1 per distant pair, H = rows + k - N_f (eq. 21);
# - mechanisms: the 3 translations plus one free pivoting per grain with a single contact in
#   touch (the law leaves pivoting free), each an exact null vector (residual < 1e-12), and
#   nothing else: the network is rigid and K(1) positive definite;
# - the elastic tensor is reported (6 x 6, Voigt order, positive definite, B from it = the
#   bulk modulus) and agrees between 1 and 2 ranks to 1e-9 of max |c|; the counts exactly.
set -u
: "${GRANPACK_EXE:?}" "${GRANPACK_SOURCE_DIR:?}"
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
cli_scratch
deck="$GRANPACK_SOURCE_DIR/jobs/decks/3d/method1_cohesive_small.toml"
check_exit "run on 1 rank" 0 "$scratch/run.txt" granpack_on 1 run "$deck" -o "$scratch/run" --quiet \
  || checks_stop cohesive_3d
for np in 1 2; do
  check_exit "stiffness on $np rank(s)" 0 "$scratch/st$np.txt" \
    granpack_on $np stiffness "$scratch/run/final.h5" --json "$scratch/st$np.json" \
    || checks_stop cohesive_3d
done
check "the table prints the tensor" "grep -q 'elastic tensor c_IJ' '$scratch/st2.txt'"
/usr/bin/python3 - "$scratch" > "$scratch/py.txt" 2>&1 <<'PY'
import json, sys
import numpy as np
from checks import check
d = sys.argv[1]
rep = json.load(open(f"{d}/run/report.json"))
comp = [s for s in rep["stages"] if s["kind"] == "compress"][0]
check("compress equilibrated", comp.get("equilibrated"))
a, b = (json.load(open(f"{d}/st{n}.json")) for n in (1, 2))
for j in (a, b):
    tag = f"{j['ranks']} rank(s)"
    check(f"{tag}: network {j['network']}, {j['H_relation']}",
          j["network"] == "interactions" and j["H_relation"] == "GRC eq. 21" and j["rolling_rows"])
    rows = 5 * (j["backbone_contacts"] - j["distant_pairs"]) + j["distant_pairs"]
    check(f"{tag}: G rows {j['G_rows']} = 5 per contact + 1 per distant pair = {rows}", j["G_rows"] == rows)
    check(f"{tag}: H {j['H']} = rows + k - N_f", j["H"] == j["G_rows"] + j["mechanisms"] - j["N_f"])
    k = 3 + j["pivoting_mechanisms"]
    check(f"{tag}: k {j['mechanisms']} = 3 trivial + {j['pivoting_mechanisms']} pivoting, "
          f"other {j['other_mechanisms']}, strain {j['strain_mechanisms']}, divalent {j['divalent_mechanisms']}",
          j["mechanisms"] == k and j["divalent_mechanisms"] == 0 and j["other_mechanisms"] == 0)
    check(f"{tag}: pivoting modes null ({j['pivoting_mode_residual']:.2g})", j["pivoting_mode_residual"] < 1e-12)
    check(f"{tag}: rigid, K(1) positive definite", j["rigid"] and j["positive_definite"] and j["moduli_valid"])
    e = j["elastic_tensor"]
    c = np.array(e["c"])
    check(f"{tag}: tensor 6 x 6 in Voigt order", c.shape == (6, 6) and e["voigt_order"] == ["xx", "yy", "zz", "yz", "xz", "xy"])
    check(f"{tag}: tensor positive definite (eigenvalues {e['eigenvalues'][0]:.4g} ...)",
          e["positive_definite"] and min(e["eigenvalues"]) > 0)
    check(f"{tag}: B from the tensor {e['bulk_voigt']} = bulk_modulus {j['bulk_modulus']}",
          abs(e["bulk_voigt"] - j["bulk_modulus"]) <= 1e-12 * abs(j["bulk_modulus"]))
for key in ("mechanisms", "pivoting_mechanisms", "H", "N_f", "G_rows", "backbone_contacts", "distant_pairs"):
    check(f"{key}: {a[key]} on 1 rank, {b[key]} on 2", a[key] == b[key])
for name in ("elastic_tensor", "constitutive"):
    ea = a[name] if name == "elastic_tensor" else a[name]["elastic_tensor"]
    eb = b[name] if name == "elastic_tensor" else b[name]["elastic_tensor"]
    ca, cb = np.array(ea["c"]), np.array(eb["c"])
    dev = np.abs(ca - cb).max() / np.abs(ca).max()
    check(f"{name}: 1 and 2 ranks agree to {dev:.2g} of max |c| (< 1e-9)", dev < 1e-9)
e = a["elastic_tensor"]
c = np.array(e["c"])
print(f"n* {a['backbone_grains']}, contacts {a['backbone_contacts']} (distant {a['distant_pairs']}), "
      f"k {a['mechanisms']} = 3 + {a['pivoting_mechanisms']} pivoting, H {a['H']}, H/N_f* {a['H_over_Nf']:.4f}, "
      f"B {e['bulk_voigt']:.5g} Pa, G_V {e['shear_voigt']:.5g} Pa, G_R {e['shear_reuss']}, "
      f"c_aa {np.diag(c)[:3].mean():.5g}, c_shear {np.diag(c)[3:].mean():.5g}, "
      f"nonaffine B {e['nonaffine']['bulk_voigt']:.4g}, symmetry {e['symmetry_deviation']:.2g}, "
      f"P {a['pressure']:.6g} Pa, virtual work {a['virtual_work_residual']:.2g}")
PY
checks_from "the stiffness checks" "$scratch/py.txt" $?
checks_done cohesive_3d
