#!/usr/bin/env bash
# The CI variants of the [AR] packing states (jobs/decks/ci/{AC,B,D}_small.toml: n = 500,
# kappa = 1000) run end to end, and their report.json metrics fall in bands. They run on one
# rank each, AC_small beside B_small and then D_small (at n = 500 one rank is faster than two:
# the halo exchange outweighs the forces; the stages on 2 ranks: tests/cli/restart_*.sh).
# Bands: mean +- about 4 standard deviations over seeds 1-4 (jobs/tools/ci_bands.sh; table in
# docs/reproduction.md), plus relations that must hold whatever the seed:
#  - frictionless A: z* >= 6 (a frictionless backbone is at least isostatic), no 2-coordinated
#    backbone grain;
#  - C (A expanded, mixed, compressed with friction) keeps A's density within 0.006 but loses
#    coordination and gains rattlers ([AR] sec. IV B);
#  - D (direct compression with mu = 0.3) is looser than A by more than 0.03;
#  - a quasistatic pressure step raises Phi and z* and narrows the force distribution (Z(2)
#    decreases, [AR] table III "QS" rows);
#  - after fix_rattlers every rattler rests on at least 3 contacts;
#  - the LS stage reports its collisions per grain.
set -u
: "${GRANPACK_EXE:?}" "${GRANPACK_SOURCE_DIR:?}"
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
cli_scratch
ran=0
start_bg "$scratch/AC_small.txt" granpack_on 1 run "$GRANPACK_SOURCE_DIR/jobs/decks/ci/AC_small.toml" \
  -o "$scratch/AC_small" --quiet
ac_pid=$bg_pid
for deck in B_small D_small; do
  check_exit "$deck run" 0 "$scratch/$deck.txt" \
    granpack_on 1 run "$GRANPACK_SOURCE_DIR/jobs/decks/ci/$deck.toml" -o "$scratch/$deck" --quiet && ran=$((ran + 1))
done
check_bg "AC_small run" 0 "$scratch/AC_small.txt" $ac_pid && ran=$((ran + 1))
[ $ran -eq 3 ] || checks_stop states_small
# granpack analyze of the C packing on 1 and 2 ranks (compared below).
for np in 1 2; do
  check_exit "analyze on $np rank(s)" 0 "$scratch/analyze_np$np.txt" granpack_on $np analyze \
    "$scratch/AC_small/final.h5" --json "$scratch/analysis_np$np.json" --h5 "$scratch/analysis_np$np.h5"
done
# The metrics: one line per check (cli_checks.sh checks_from), named by what a failure means.
/usr/bin/python3 - "$scratch" > "$scratch/py.txt" 2>&1 <<'PY'
import json, sys
from checks import check
d = sys.argv[1]
def stages(deck):
    return {s["name"]: s for s in json.load(open(f"{d}/{deck}/report.json"))["stages"]}
ac, b, dd = stages("AC_small"), stages("B_small"), stages("D_small")
A, C, B, D, Q, F = ac["A"], ac["C"], b["B"], dd["D"], dd["qs"], dd["fixed"]
def band(name, s, key, lo, hi):
    v = s[key]
    check(f"{name} {key} = {v} outside [{lo}, {hi}]", v is not None and lo <= v <= hi)
for name, s in [("A", A), ("C", C), ("B", B), ("D", D), ("qs", Q)]:
    check(f"{name} not equilibrated", s["equilibrated"] is True)
band("A", A, "phi", 0.635, 0.648); band("A", A, "z_star", 6.38, 6.62); band("A", A, "x0", 0.0, 0.03)
check(f"A z* = {A['z_star']} < 6", A["z_star"] >= 6.0)
check(f"A x2 = {A['x2']} != 0 without friction", A["x2"] == 0)
band("C", C, "phi", 0.632, 0.647); band("C", C, "z_star", 4.95, 5.60); band("C", C, "x0", 0.005, 0.08)
check("C density not within 0.006 of A", abs(C["phi"] - A["phi"]) < 0.006)
check("C z* not below A z* - 0.8", C["z_star"] < A["z_star"] - 0.8)
check("C x0 not above A x0", C["x0"] > A["x0"])
band("B", B, "phi", 0.636, 0.646); band("B", B, "z_star", 6.0, 6.4)
ls = b["ls"]["values"]
# LS to 0.58 with the default report_phi [0.49, 0.58]: intervals [0.45, 0.49] and [0.49, 0.58].
check(f"LS collisions per grain missing: {ls}", sorted(ls) == ["collisions_per_grain_0.450_0.490",
      "collisions_per_grain_0.490_0.580"] and all(v > 0 for v in ls.values()))
band("D", D, "phi", 0.590, 0.606); band("D", D, "z_star", 4.75, 5.25); band("D", D, "x0", 0.01, 0.11)
check("D not looser than A by 0.03", D["phi"] < A["phi"] - 0.03)
check("QS step: phi did not increase", Q["phi"] > D["phi"])
check("QS step: z* did not increase", Q["z_star"] > D["z_star"])
check("QS step: Z(2) did not decrease", Q["z2"] < D["z2"])
check("QS level not recorded", len(Q.get("levels", [])) == 1 and abs(Q["levels"][0]["pressure"] / 31622.8 - 1) < 1e-3)
v = F["values"]
check(f"fix_rattlers did not settle: {F}", F["equilibrated"] is True)
check(f"fix_rattlers: {v['rattlers_resting_on_dim_contacts']} of {v['rattlers']} rattlers rest on >= 3 contacts",
      v["rattlers"] > 0 and v["rattlers_resting_on_dim_contacts"] == v["rattlers"])
check("fix_rattlers: grains with 0 or 1 contact remain", v["x0_II"] == 0 and v["x1_II"] == 0)
# analyze: counts equal and reals within 1e-12 between 1 and 2 ranks (absolute for values that
# are differences near zero), except the strong/weak split, undefined at N = <N> exactly.
def leaves(j, pre=""):
    if isinstance(j, dict):
        for k, x in j.items(): yield from leaves(x, pre + "/" + k)
    elif isinstance(j, list):
        for k, x in enumerate(j): yield from leaves(x, f"{pre}[{k}]")
    else:
        yield pre, j
one = dict(leaves(json.load(open(f"{d}/analysis_np1.json"))))
two = dict(leaves(json.load(open(f"{d}/analysis_np2.json"))))
check("analyze: different keys on 1 and 2 ranks", set(one) == set(two))
for k, x in one.items():
    y = two.get(k)
    if k == "/file" or isinstance(x, bool) or x is None:
        check(f"analyze {k}: {x} vs {y}", x == y)
    elif isinstance(x, int) and isinstance(y, int):
        check(f"analyze {k}: {x} vs {y}", x == y)
    elif isinstance(x, (int, float)) and isinstance(y, (int, float)):
        # A relative error is a ratio minus 1: its scale is 1, whatever its size.
        scale = 1.0 if k.endswith("relative_error") else max(abs(x), 1e-3)
        check(f"analyze {k}: {x} vs {y}", abs(x - y) <= 1e-12 * scale)
    else:
        check(f"analyze {k}: {x} vs {y}", x == y)
an = json.load(open(f"{d}/analysis_np2.json"))
check(f"analyze z* {an['z_star']} != report {C['z_star']}", abs(an["z_star"] - C["z_star"]) < 1e-12)
# eq. (22) neglects the deflections (h/a ~ 1e-2 at kappa = 1000): a percent-level check.
check(f"eq. (22) relative error {an['eq22_relative_error']}", abs(an["eq22_relative_error"]) < 0.02)
# --h5: the curves as datasets, the same numbers as the JSON.
import h5py
with h5py.File(f"{d}/analysis_np2.h5", "r") as h:
    for path in ("g_r/g_I", "g_r/r_over_a", "z_h/z_III", "P_f/pdf"):
        group, key = path.split("/")
        check(f"analyze --h5 {path} differs from the JSON", list(h[path][:]) == an[group][key])
    check("analyze --h5 z_star attribute", h.attrs["z_star"] == an["z_star"])
PY
checks_from "the metric checks" "$scratch/py.txt" $?
checks_done states_small
