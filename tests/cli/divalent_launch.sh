#!/usr/bin/env bash
# The divalent_launch stage ([AR] App. E; docs/stiffness.md, "Is a divalent grain's free rolling
# stable?") on the small D-like packing tests/data/D_n500_divalent.h5 (one divalent grain;
# jobs/decks/ci/D_divalent_small.toml), centrifugal ratio 1e-2 for short runs:
# - a frozen launch on 1 and on 2 ranks: the same grain, omega0 with m omega0^2 D = 1e-2 |F|, the
#   grain rolls on its circle (x^2 + y^2 = 1 in units of D, y growing: along +t) at constant
#   kinetic energy with its contact forces unchanged, no contact created, verdict "rolling";
#   both rank counts give the same trajectory (to 1e-6 of D);
# - under twice the packing's pressure the cell shrinks: with contact creation new contacts
#   form, with the network frozen none does (the frozen mode can fail this test);
# - bad input is refused with exit 2 and a message naming the value and what is allowed: a pick
#   beyond the divalent grains, a frictionless law, a 2D deck.
set -u
: "${GRANPACK_EXE:?}" "${GRANPACK_SOURCE_DIR:?}"
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
cli_scratch

deck() { # deck NAME FRICTION STAGE-LINES...
  local name=$1 friction=$2; shift 2
  {
    printf '%s\n' '[sample]' 'dimension = 3' 'n = 500' 'diameter = 1.0e-3' 'seed = 1' '' \
      '[material]' 'density = 2500.0' 'normal_law = "hertz"' 'young_modulus = 2.88e8' \
      'poisson_ratio = 0.3' "friction = $friction" 'damping = 0.98' '' '[output]' \
      'log_every = 100000' '' '[[stage]]' 'kind = "read"' \
      "file = \"$GRANPACK_SOURCE_DIR/tests/data/D_n500_divalent.h5\"" '' '[[stage]]' \
      'kind = "divalent_launch"'
    printf '%s\n' "$@"
  } > "$scratch/$name.toml"
}
deck frozen 0.3 'pressure = 1.0e4' 'frozen_network = true' 'centrifugal_ratio = 1e-2' \
  'max_steps = 3000' 'record_every = 250'
deck squeeze_frozen 0.3 'pressure = 2.0e4' 'frozen_network = true' 'centrifugal_ratio = 1e-2' \
  'max_steps = 1500' 'record_every = 500'
deck squeeze_free 0.3 'pressure = 2.0e4' 'frozen_network = false' 'centrifugal_ratio = 1e-2' \
  'max_steps = 1500' 'record_every = 500'
deck bad_pick 0.3 'pressure = 1.0e4' 'pick = 1'
deck frictionless 0.0 'pressure = 1.0e4'

start_bg "$scratch/f1.txt" granpack_on 1 run "$scratch/frozen.toml" -o "$scratch/f1" -q
pid1=$bg_pid
check_exit "frozen launch, 2 ranks" 0 "$scratch/f2.txt" granpack_on 2 run "$scratch/frozen.toml" -o "$scratch/f2" -q
check_bg "frozen launch, 1 rank" 0 "$scratch/f1.txt" "$pid1"
start_bg "$scratch/sq1.txt" granpack_on 1 run "$scratch/squeeze_frozen.toml" -o "$scratch/sqf" -q
pid1=$bg_pid
check_exit "squeezed, contact creation" 0 "$scratch/sq2.txt" granpack_on 1 run "$scratch/squeeze_free.toml" -o "$scratch/sqc" -q
check_bg "squeezed, frozen" 0 "$scratch/sq1.txt" "$pid1"

check_python "launch, trajectory, 1 vs 2 ranks, frozen creates no contact" "$scratch/py.txt" "$scratch" <<'PY'
import csv, json, sys
s = sys.argv[1]
def stage(d):
    return [x for x in json.load(open(f"{s}/{d}/report.json"))["stages"] if x["kind"] == "divalent_launch"][0]
def rows(d):
    return [{k: float(v) for k, v in r.items()} for r in csv.DictReader(open(f"{s}/{d}/divalent_trajectory.csv"))]
v1, v2 = stage("f1")["values"], stage("f2")["values"]
assert v1["divalent_grains"] == 1 and v1["grain"] == v2["grain"], (v1["grain"], v2["grain"])
assert abs(v1["centrifugal_over_force"] - 1e-2) < 1e-9, v1["centrifugal_over_force"]
assert v1["frozen_network"] == 1 and v1["max_new_contacts"] == 0, v1["max_new_contacts"]
assert v1["network_holds"] == 1 and v1["collapsed"] == v1["rearranged"] == v1["arrested"] == 0, v1
r1, r2 = rows("f1"), rows("f2")
assert len(r1) == len(r2) == 3000 // 250 + 1, (len(r1), len(r2))
assert r1[0]["x_over_D"] == 1.0 and abs(r1[0]["y_over_D"]) < 1e-12, r1[0]  # starts at (D, 0)
assert r1[0]["kinetic_over_launch"] == 1.0, r1[0]  # the packing at rest but for the grain
for r in r1:
    assert abs(r["x_over_D"] ** 2 + r["y_over_D"] ** 2 - 1) < 2e-3, r  # on its circle
    assert abs(r["grain_kinetic_over_launch"] - 1) < 1e-3, r          # free rolling: no work
    assert abs(r["N_ij_over_F"] - r1[0]["N_ij_over_F"]) < 1e-2, r     # forces kept
    assert r["grain_contacts"] == 2 and r["new_contacts"] == 0, r
assert r1[-1]["y_over_D"] > 0.05 and r1[-1]["angle"] > 0.05, r1[-1]  # it moved, along +t
for a, b in zip(r1, r2):
    for k in ("x_over_D", "y_over_D", "kinetic_over_launch"):
        assert abs(a[k] - b[k]) < 1e-6, (k, a[k], b[k])
qf, qc = stage("sqf")["values"], stage("sqc")["values"]
assert qf["max_new_contacts"] == 0, qf["max_new_contacts"]
assert qc["max_new_contacts"] > 0, qc["max_new_contacts"]  # the squeeze does create contacts
assert all(r["new_contacts"] == 0 for r in rows("sqf"))
print("grain", int(v1["grain"]), "turns", v1["turns_done"], "new contacts when free", qc["max_new_contacts"])
PY

check_refused "pick beyond the divalent grains" 2 \
  'pick = 1 but the packing has 1 divalent grains \(allowed: 0 to 0\)' "$scratch/pick.txt" \
  granpack_on 1 run "$scratch/bad_pick.toml" -o "$scratch/pick" -q
check_refused "frictionless law" 2 'bad_frictionless|frictionless.toml.*needs friction' \
  "$scratch/mu0.txt" granpack_on 1 run "$scratch/frictionless.toml" -o "$scratch/mu0" -q
sed -e 's/^dimension = 3/dimension = 2/' "$scratch/frozen.toml" > "$scratch/flat.toml"
check_refused "2D deck" 2 'flat.toml.*divalent_launch.* is 3D' "$scratch/2d.txt" \
  granpack_on 1 run "$scratch/flat.toml" -o "$scratch/2d" -q
checks_done divalent_launch
