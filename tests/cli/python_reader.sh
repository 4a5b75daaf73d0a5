#!/usr/bin/env bash
# jobs/tools/granpack_io.py (docs/visualisation.md, "The Python reader") on the files of a small
# 2-rank run: final.h5 (grains, contacts, cell, parameters: counts, units, contacts between
# existing grains, forces balanced on the non-rattlers within the stage's tolerance, the
# stress and rattler fraction equal to report.json's), report.json (stage table), the analysis
# as --json and --h5 (the same curves), a committed cohesive 2D file (attraction N^a, balance
# in F1), a committed stiffness JSON (modes, rattler ids), write_packing (round trip); and bad
# input (missing file, foreign HDF5, missing dataset, unknown contact id) raises
# GranpackFileError naming the file and the object. Then the scripts of jobs/tools and
# jobs/bench: argparse, no h5py or json.load of their own (granpack_io reads), no sys.argv in
# the Python their shell scripts run, and the scripts those call, on small inputs.
set -u
: "${GRANPACK_EXE:?}" "${GRANPACK_SOURCE_DIR:?}"
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
cli_scratch
export PYTHONPATH="$GRANPACK_SOURCE_DIR/jobs/tools:$PYTHONPATH"

{ small_deck 3 120 3; cat <<'TOML'
[[stage]]
kind = "random"
phi = 0.45
[[stage]]
kind = "compress"
pressure = 1.0e4
inertia_max = 1.0e-2
quench_interval = 20000
tolerance_moment = 1.0e-4
TOML
} > "$scratch/small.toml"
out="$scratch/run"
check_exit "2-rank run" 0 "$scratch/run.txt" granpack_on 2 run "$scratch/small.toml" -o "$out" \
  || checks_stop python_reader "$scratch/run.txt"
check_exit "analyze --json --h5" 0 "$scratch/an.txt" granpack_on 2 analyze "$out/final.h5" \
  --json "$out/analysis.json" --h5 "$out/analysis.h5"
check_exit "stiffness --modes 2" 0 "$scratch/st.txt" granpack_on 2 stiffness "$out/final.h5" \
  --json "$out/stiffness.json" --modes 2 --modes-file "$out/modes.h5"

/usr/bin/python3 - "$out" "$GRANPACK_SOURCE_DIR" > "$scratch/py.txt" 2>&1 <<'PY'
import os
import sys
import numpy as np
import granpack_io as gio
from checks import check

out, src = sys.argv[1], sys.argv[2]
exe = os.environ["GRANPACK_EXE"]
p = gio.read_packing(f"{out}/final.h5")
rep = gio.read_report(f"{out}/report.json")
last = rep.stages[-1]
check(f"dimension 3, n = 120, nc = {p.nc} > 120", p.dimension == 3 and p.n == 120 and p.nc > 120)
check("kind configuration, stage 1 compress",
      p.kind == "configuration" and p.stage_index == 1 and p.law()["friction"] == 0.3)
check("grain arrays have n rows and the schema's columns",
      all(len(v) == 120 for v in p.grains.values()) and p.grains["position"].shape == (120, 3)
      and p.grains["orientation"].shape == (120, 4) and p.grains["angular_velocity"].shape == (120, 3))
check("contact arrays have nc rows", all(len(v) == p.nc for v in p.contacts.values())
      and p.contacts["tangential_force"].shape == (p.nc, 3))
check("units named", p.units["particles/radius"] == "m" and p.units["contacts/normal_force"] == "N"
      and p.units["cell/length"] == "m" and gio.DERIVED_UNITS["stress"] == "Pa")
check("ids unique", len(np.unique(p.grains["id"])) == p.n)
check("contacts reference existing grains, first < second",
      np.all(p.grains["id"][p.i] == p.contacts["first"]) and
      np.all(p.grains["id"][p.j] == p.contacts["second"]) and
      np.all(p.contacts["first"] < p.contacts["second"]))
check("position = L * scaled_position",
      np.allclose(p.grains["position"], p.grains["scaled_position"] * p.cell_length, rtol=1e-14))
check("contacts overlap (h > 0) and are shorter than half the cell",
      np.all(p.overlap > 0) and np.all(p.distance < 0.5 * p.cell_length.min()))
P = p.law()["pressure_target"]
check(f"pressure {p.pressure:.6g} = target {P} within 1e-3", abs(p.pressure - P) < 1e-3 * P)
check(f"pressure = report's {last['pressure']:.8g}", abs(p.pressure - last["pressure"]) < 1e-6 * P)
r = p.rattlers()
check(f"rattler fraction {r.mean():.4f} = report's x0 {last['x0']:.4f}", abs(r.mean() - last["x0"]) < 1e-12)
z = p.coordination(carrying_only=True)
check(f"z* {z[~r].mean():.4f} ~ report's {last['z_star']:.4f}", abs(z[~r].mean() - last["z_star"]) < 0.05)
net = np.linalg.norm(p.net_force(), axis=1) / (p.diameter ** 2 * P)
print(f"max net force on non-rattlers: {net[~r].max():.3g} a^2 P")
check("forces balance on non-rattlers (< 1.5e-4 a^2 P)", net[~r].max() < 1.5e-4)


def net_of(pk, f):
    """Net force per grain of per-contact forces f on `second` (-f on `first`)."""
    out = np.zeros((pk.n, pk.dimension))
    np.add.at(out, pk.j, f)
    np.add.at(out, pk.i, -f)
    return np.linalg.norm(out, axis=1)


flipped = net_of(p, p.contact_force - 2 * p.contacts["tangential_force"]) / (p.diameter ** 2 * P)
check(f"with T on `first` instead, no balance ({flipped[~r].max():.3g} a^2 P): the check can fail",
      flipped[~r].max() > 1e-2)
# /network (written by the engine from its own ghost layer) against the reader's recomputation.
nw = p.network
check("final.h5 has /network with nc lines, 2 nc points, n grains",
      nw.get("line", np.zeros((0, 2))).shape == (p.nc, 2) and nw["point"].shape == (2 * p.nc, 3)
      and nw["contacts"].shape == (p.n,) and nw["net_force"].shape == (p.n, 3))
if nw:
    start, end = nw["point"][0::2], nw["point"][1::2]
    check("segments start at the first grain's centre (folded into the cell)",
          np.allclose(start, np.mod(p.grains["scaled_position"][p.i], 1.0) * p.cell_length, atol=1e-12))
    check("segments are the branch vectors (drawn to the image, never across the cell)",
          np.allclose(end - start, p.branch, atol=1e-12))
    out_of_cell = ((end < 0) | (end >= p.cell_length)).any(axis=1)
    print(f"{out_of_cell.sum()} of {p.nc} segments end at an image outside the cell")
    check("some contacts cross the boundary (the image case is exercised)", out_of_cell.sum() > 0)
    check("lines join rows 2k, 2k+1", np.array_equal(nw["line"], np.arange(2 * p.nc).reshape(-1, 2)))
    fscale = np.abs(p.total_normal_force).max()
    check("normal_force = N^e + N^a", np.allclose(nw["normal_force"], p.total_normal_force, rtol=0, atol=1e-12 * fscale))
    check("tangential_force = |T|", np.allclose(nw["tangential_force"], p.tangential_magnitude, rtol=0, atol=1e-12 * fscale))
    check("kind: compressive where N > 0", np.array_equal(nw["kind"] == 0, p.total_normal_force > 0))
    check("per-grain contacts across ranks", np.array_equal(nw["contacts"], p.coordination()))
    check("per-grain carrying contacts", np.array_equal(nw["carrying_contacts"], p.coordination(carrying_only=True)))
    check("per-grain net force", np.allclose(nw["net_force"], p.net_force(), rtol=0, atol=1e-9 * fscale))
    # The net moment: the engine's sums against the reader's (forces at the middle of the
    # overlap), their sum against the virial's antisymmetric part, and the balance that the
    # compress stage's tolerance_moment = 1e-4 enforced (|M| < 1e-4 F1 a, F1 a = a^3 P).
    M, mscale = nw.get("net_moment", np.zeros((0, 3))), fscale * p.diameter
    check("per-grain net moment = the reader's net_moment() (force at the contact point)",
          M.shape == (p.n, 3) and np.allclose(M, p.net_moment(), rtol=0, atol=1e-9 * mscale))
    if M.shape == (p.n, 3):
        total_m = -np.cross(p.branch, p.contact_force).sum(axis=0)
        check(f"sum of net moments = -sum r_12 x f ({M.sum(axis=0)} N m)",
              np.allclose(M.sum(axis=0), total_m, rtol=0, atol=1e-9 * mscale * p.nc))
        mm = np.linalg.norm(M, axis=1) / (p.diameter ** 3 * P)
        check(f"moments balance on every grain (max {mm.max():.3g} a^3 P < 1.5e-4)", mm.max() < 1.5e-4)
        # In equilibrium the moments of T cancel on each grain: with T acting on `first` as on
        # `second` (not opposite), they would not.
        t = p.contacts["tangential_force"].astype(float)
        mt = np.zeros((p.n, 3))
        np.add.at(mt, p.i, np.cross((p.radius[p.i] - 0.5 * p.overlap)[:, None] * p.normal, t))
        wm = np.linalg.norm(M + 2 * mt, axis=1).max() / (p.diameter ** 3 * P)
        check(f"T on both grains alike would leave moments of {wm:.3g} a^3 P: the check can fail", wm > 1e-2)
    vg = 4.0 / 3.0 * np.pi * p.radius ** 3
    check(f"sum of V_g mean_stress_g / V = P ({(vg * nw['mean_stress']).sum() / p.volume:.8g} Pa)",
          abs((vg * nw["mean_stress"]).sum() / p.volume - p.pressure) < 1e-9 * P)
    share = np.zeros(p.n)
    w = 0.5 * (p.contact_force * p.branch).sum(axis=1)
    np.add.at(share, p.i, w)
    np.add.at(share, p.j, w)
    check("per-grain mean stress", np.allclose(nw["mean_stress"], share / (3 * vg), rtol=1e-12, atol=1e-9 * P))
    sg = nw["stress"].reshape(p.n, 3, 3)
    half = 0.5 * np.einsum("ka,kb->kab", p.contact_force, p.branch)
    mine = np.zeros((p.n, 3, 3))
    np.add.at(mine, p.i, half)
    np.add.at(mine, p.j, half)
    check("per-grain stress tensor = (1/V_g) sum f (x) r_12 / 2 (recomputed)",
          nw["stress"].shape == (p.n, 9) and np.allclose(sg, mine / vg[:, None, None], rtol=1e-12, atol=1e-9 * P))
    check("tr(stress)/3 = mean_stress", np.allclose(np.trace(sg, axis1=1, axis2=2) / 3, nw["mean_stress"], rtol=0, atol=1e-9 * P))
    total = np.einsum("g,gab->ab", vg, sg) / p.volume
    check(f"sum of V_g stress_g / V = the cell's stress (max difference {np.abs(total - p.stress()).max():.3g} Pa)",
          np.allclose(total, p.stress(), rtol=0, atol=1e-9 * P))
    rat = p.rattlers()
    check(f"rattler flags of the iterated rule ({int(nw['rattler'].sum())} of {p.n}) = the reader's rattlers()",
          np.array_equal(nw["rattler"] == 1, rat) and rat.sum() > 0)
    check("rattler flags give report.json's x0", abs(nw["rattler"].mean() - rep.stages[-1]["x0"]) < 1e-12)
    mu = p._param("friction")
    mob = np.where(p.contacts["normal_force"] > 0,
                   p.tangential_magnitude / np.maximum(mu * p.contacts["normal_force"], 1e-300), 0.0)
    check(f"mobilisation = |T|/(mu N^e) (max {nw['mobilisation'].max():.6f} <= 1: Coulomb)",
          np.allclose(nw["mobilisation"], mob, rtol=1e-12, atol=1e-12) and nw["mobilisation"].max() <= 1 + 1e-9
          and nw["mobilisation"].max() > 0.5)
    Nt = p.total_normal_force
    strong = (Nt > 0) & (Nt > Nt[Nt > 0].mean())
    check(f"strong flags: N > <N> over the compressive contacts ({int(nw['strong'].sum())} of {p.nc})",
          np.array_equal(nw["strong"] == 1, strong) and 0 < strong.sum() < p.nc)
    check("units of /network", p.units.get("network/point") == "m" and p.units.get("network/net_force") == "N"
          and p.units.get("network/net_moment") == "N m" and gio.DERIVED_UNITS["net_moment"] == "N m")
if nw:
    cid = p.cluster_ids()
    print(f"{len(np.unique(nw['cluster_id']))} clusters, the largest of {np.bincount(np.unique(cid, return_inverse=True)[1]).max()} grains")
    check("cluster ids across ranks = the reader's cluster_ids() (smallest id of each cluster)",
          nw["cluster_id"].dtype == np.int64 and np.array_equal(nw["cluster_id"], cid))
    order = gio.read_analysis(f"{out}/analysis.json")["order"]["1.40"]
    q6 = nw["bond_order"]
    check(f"mean bond_order (Q6) over grains with bonds {q6[q6 > 0].mean():.12f} = analyze's Q6_local_mean "
          f"{order['Q6_local_mean']:.12f}", abs(q6[q6 > 0].mean() - order["Q6_local_mean"]) < 1e-12)
    check(f"crystalline fraction {nw['crystalline'].mean()} = analyze's {order['crystalline_fraction']}",
          abs(nw["crystalline"].mean() - order["crystalline_fraction"]) < 1e-12)
t = rep.stage_table()
check("stage table: names, phi and pressure arrays", list(t["kind"]) == ["random", "compress"]
      and abs(t["phi"][-1] - p.phi) < 1e-9 and t["pressure"].shape == (2,) and rep.units["pressure"] == "Pa")

aj = gio.read_analysis(f"{out}/analysis.json")
ah = gio.read_analysis(f"{out}/analysis.h5")
check("analysis JSON: curves as arrays", isinstance(aj["g_r"]["g_I"], np.ndarray) and aj["n"] == 120)
check("analysis --h5 and --json agree (g(r), P(f), phi)",
      np.allclose(aj["g_r"]["g_I"], ah["g_r"]["g_I"]) and np.allclose(aj["P_f"]["pdf"], ah["P_f"]["pdf"])
      and abs(aj["phi"] - ah["phi"]) < 1e-15 and abs(aj["phi"] - p.phi) < 1e-9)
# analyze --threshold T recounts the backbone without contacts under T a^2 P: against
# granpack_io's own rattler rule at that threshold, through contact_threshold_scan.py.
import contact_threshold_scan as cts
x0, z_star, x2 = cts.backbone_counts(f"{out}/final.h5", 1e-4, exe)
check(f"contact_threshold_scan at 1e-4 a^2 P = analyze's default (x0 {x0}, z* {z_star}, x2 {x2})",
      x0 == aj["x0"] and z_star == aj["z_star"] and x2 == aj["x2"])
x0_hi, z_hi, x2_hi = cts.backbone_counts(f"{out}/final.h5", 0.3, exe)
r_hi = p.rattlers(threshold=0.3)
live = p.carrying(threshold=0.3) & ~r_hi[p.i] & ~r_hi[p.j]
deg = np.bincount(p.i[live], minlength=p.n) + np.bincount(p.j[live], minlength=p.n)
check(f"analyze --threshold 0.3 = granpack_io's rattler rule at 0.3 (x0 {x0_hi}, z* {z_hi}, "
      f"x2 {x2_hi}) and drops contacts (z* {z_star} -> {z_hi})",
      abs(x0_hi - r_hi.mean()) < 1e-12 and abs(z_hi - 2 * live.sum() / (~r_hi).sum()) < 1e-9
      and abs(x2_hi - np.mean(~r_hi & (deg == 2))) < 1e-12 and z_hi < z_star and x0_hi > x0)
check("read() dispatches on content", isinstance(gio.read(f"{out}/final.h5"), gio.Packing)
      and isinstance(gio.read(f"{out}/report.json"), gio.Report)
      and isinstance(gio.read(f"{out}/analysis.h5"), dict))

# A cohesive 2D file (no /parameters: the deck is replayed): attraction and balance in F1.
c = gio.read_packing(f"{src}/docs/data/2d/method1_cohesive_small.h5")
f0 = c.law()["cohesion_force"]
check("2D: orientation and angular velocity have one column",
      c.grains["orientation"].shape == (c.n, 1) and c.contacts["rolling"].shape == (c.nc, 1))
check("2D: N^a = -F0 in contact", f0 > 0 and np.all(c.attraction[~c.distant] == -f0))
F1 = max(f0, c.diameter * c.law().get("pressure_target", c.pressure))
cr = c.rattlers()
cnet = np.linalg.norm(c.net_force(), axis=1) / F1
check(f"2D cohesive: balanced within 1.5e-4 F1 ({cnet[~cr].max():.3g})", cnet[~cr].max() < 1.5e-4)
bad = net_of(c, c.contact_force - c.attraction[:, None] * c.normal).max() / F1
check(f"2D cohesive: unbalanced without the attraction ({bad:.3g} F1)", bad > 1e-2)

import glob
sj = sorted(glob.glob(f"{src}/docs/data/analysis/fig3/*.json"))[0]
s = gio.read_stiffness(sj)
check("stiffness JSON: mechanisms, modes and rattler ids as arrays",
      isinstance(s["mechanisms"], int) and isinstance(s["modes"], list)
      and s["rattler_ids"].dtype == np.int64 and len(s["rattler_ids"]) == len(s["rattler_grains"]))

# read_modes: every array named with its unit, as Packing.units.
m = gio.read_modes(f"{out}/modes.h5")
keys = [k for k, v in m.items() if k != "units" and v is not None and not isinstance(v, dict)]
keys += [f"divalent_grains/{k}" for k in (m["divalent_grains"] or {})]
missing = [k for k in keys if k not in m["units"]]
check(f"read_modes: a unit for each of its {len(keys)} arrays (missing: {missing})",
      not missing and m["units"]["position"] == "m" and m["units"]["mean_kn"] == "N/m"
      and m["units"]["rotation_length"] == "m" and m["units"]["rotation"].startswith("rad/m")
      and m["displacement"].shape == (2, 120, 3) and m["units"] is not gio.MODES_UNITS)

gio.write_packing(f"{out}/copy.h5", 3, p.cell_length, p.grains, p.contacts,
                  attrs={"time": p.time, "step": p.step, "stage_index": 1}, deck=p.deck)
q = gio.read_packing(f"{out}/copy.h5")
check("write_packing round trip", q.n == p.n and q.nc == p.nc and q.deck == p.deck and
      all(np.array_equal(q.grains[k], p.grains[k]) for k in gio.PARTICLE_SETS) and
      all(np.array_equal(q.contacts[k], p.contacts[k]) for k in gio.CONTACT_SETS))
field = gio.mode_field(p, [p.grains["id"][:3], p.grains["id"][2:5]])
check("mode_field", list(field[:6]) == [0, 0, 0, 1, 1, -1])


def refused(name, fn, *words):
    try:
        fn()
    except gio.GranpackFileError as e:
        check(f"{name}: {e}", all(w in str(e) for w in words))
        return
    check(f"{name}: GranpackFileError raised", False)


import h5py
refused("missing file", lambda: gio.read_packing(f"{out}/nope.h5"), "nope.h5", "no such file")
with h5py.File(f"{out}/foreign.h5", "w") as f:
    f["x"] = [1]
refused("foreign HDF5", lambda: gio.read_packing(f"{out}/foreign.h5"), "foreign.h5", "not a granpack")
with open(f"{out}/text.h5", "w") as f:
    f.write("hello")
refused("not HDF5", lambda: gio.read_packing(f"{out}/text.h5"), "text.h5", "HDF5")
with h5py.File(f"{out}/copy.h5", "a") as f:
    del f["contacts/flags"]
refused("missing dataset", lambda: gio.read_packing(f"{out}/copy.h5"), "copy.h5", "/contacts/flags")
cont = dict(p.contacts)
cont["second"] = cont["second"].copy()
cont["second"][0] = 10 ** 9
gio.write_packing(f"{out}/badid.h5", 3, p.cell_length, p.grains, cont)
refused("unknown contact id", lambda: gio.read_packing(f"{out}/badid.h5"), "badid.h5", "/contacts/second")
refused("report without stages", lambda: gio.read_report(f"{out}/analysis.json"), "analysis.json", "stages")
PY
checks_from "reader checks" "$scratch/py.txt" $?

# The tools read granpack files through the reader and parse their command lines with argparse.
tools="$GRANPACK_SOURCE_DIR/jobs/tools"
check "no jobs/tools script but granpack_io.py imports h5py: $(grep -l 'import h5py' "$tools"/*.py | grep -v granpack_io.py)" \
  "[ -z \"\$(grep -l 'import h5py' '$tools'/*.py | grep -v granpack_io.py)\" ]"
check "no hand-parsed argv in jobs/tools: $(grep -n 'sys\.argv' "$tools"/*.py | grep -v 'main(sys\.argv\[1:\])')" \
  "[ -z \"\$(grep -n 'sys\.argv' '$tools'/*.py | grep -v 'main(sys\.argv\[1:\])')\" ]"
for t in "$tools"/*.py; do
  grep -q '__main__' "$t" || continue
  check "$(basename "$t") uses argparse" "grep -q '^import argparse' '$t'"
done
# jobs/bench's scripts too, called by run_bench.sh with the same command lines as before.
bench="$GRANPACK_SOURCE_DIR/jobs/bench"
# (and jobs/bench/lammps's)
check "no hand-parsed argv in jobs/bench: $(grep -n 'sys\.argv' "$bench"/*.py "$bench"/*/*.py | grep -v 'main(sys\.argv\[1:\])')" \
  "[ -z \"\$(grep -n 'sys\.argv' '$bench'/*.py '$bench'/*/*.py | grep -v 'main(sys\.argv\[1:\])')\" ]"
for t in "$bench"/*.py "$bench"/*/*.py; do
  check "$(basename "$t") uses argparse" "grep -q '^import argparse' '$t'"
done
# Nor does a Python snippet inside their shell scripts read sys.argv (the snippets are tools of
# their own, with argparse); and no script, nor snippet, opens granpack's JSON outputs itself
# (report.json, analysis, ensemble, stiffness and bench JSON): granpack_io's read_* do.
check "no sys.argv in the shell scripts of jobs/tools, jobs/bench: $(grep -n 'sys\.argv' "$tools"/*.sh "$bench"/*.sh)" \
  "[ -z \"\$(grep -n 'sys\.argv' '$tools'/*.sh '$bench'/*.sh)\" ]"
json_open="$(grep -n 'json\.load' "$tools"/*.py "$tools"/*.sh "$bench"/*.py "$bench"/*/*.py "$bench"/*.sh | grep -v '/granpack_io\.py:')"
check "no json.load outside granpack_io.py in jobs/tools, jobs/bench: $json_open" "[ -z \"\$json_open\" ]"
b=$scratch/bench
mkdir -p "$b"
check_exit "tsuji_coefficient.py (zeta = 0.98 by default)" 0 "$b/tsuji.txt" /usr/bin/python3 \
  "$bench/lammps/tsuji_coefficient.py"
check "tsuji_coefficient.py: e = -0.164698... (docs/performance.md)" \
  "grep -q 'zeta = 0.98: alpha = 2.4004999479, e = -0.164698' '$b/tsuji.txt'"
mkdir -p "$b/1000"
printf '# pressure 100.0\n0 1.0 0.0 0.0\n1 0.0 2.0 0.0\n' > "$b/granpack_static.txt"
printf 'ITEM: TIMESTEP\n0\nITEM: ATOMS id fx fy fz\n1 1.0 0.0 0.0\n2 0.0 2.0 0.001\n' > "$b/forces.dump"
printf 'STATIC_PRESSURE 100.5\n' > "$b/lammps_static.log"
check_exit "compare_static.py, run_bench.sh's command line" 0 "$b/static_check.txt" /usr/bin/python3 \
  "$bench/compare_static.py" "$b/granpack_static.txt" "$b/forces.dump" "$b/lammps_static.log"
check "compare_static.py: n = 2, relative pressure difference 4.975e-03" \
  "grep -q 'n = 2: P granpack 100 Pa, LAMMPS 100.5 Pa, relative difference 4.975e-03' '$b/static_check.txt'"
check_refused "compare_static.py with two files" 2 "usage: compare_static.py" "$b/static_bad.txt" \
  /usr/bin/python3 "$bench/compare_static.py" "$b/granpack_static.txt" "$b/forces.dump"
for np in 1 2; do
  printf '{"n": 1000, "particle_steps_per_s_per_rank": %s, "wall": 10.0, "forces": 5.0, "neighbor": 1.0, "comm": 1.0, "integrate": 1.0, "rebuilds": 3, "bytes_per_grain": 500, "dt": 1.25e-07, "skin": 0.0001}\n' \
    $((2000000 / np)) > "$b/1000/granpack_np${np}_1.json"
  printf 'Loop time of 2.0 on %s procs for 100 steps with 1000 atoms\n' "$np" > "$b/1000/lammps_np${np}_1.log"
done
check_exit "summarize.py OUT_DIR SIZE, run_bench.sh's command line" 0 "$b/summary.txt" /usr/bin/python3 \
  "$bench/summarize.py" "$b" 1000
check "summarize.py: both rank counts and the efficiency (granpack 50.0%, LAMMPS 50.0%)" \
  "grep -q 'parallel efficiency 1->2 ranks: granpack 50.0%, LAMMPS 50.0%' '$b/summary.txt'"
check_refused "summarize.py without a size" 2 "usage: summarize.py" "$b/summary_bad.txt" \
  /usr/bin/python3 "$bench/summarize.py" "$b"

# The snippets that were inside the shell scripts, as those call them now.
check_exit "granpack_io.py value FILE dt, run_bench.sh's command line" 0 "$b/dt.txt" /usr/bin/python3 \
  "$tools/granpack_io.py" value "$b/1000/granpack_np1_1.json" dt
check "granpack_io.py value: repr of the stored dt ($(cat "$b/dt.txt"))" "[ \"\$(cat '$b/dt.txt')\" = 1.25e-07 ]"
check_refused "granpack_io.py value with an unknown key" 2 "granpack_np1_1.json: no key 'nope'" \
  "$b/dt_bad.txt" /usr/bin/python3 "$tools/granpack_io.py" value "$b/1000/granpack_np1_1.json" nope
check_exit "e2e_line.py on the 2-rank run, run_bench.sh's command line" 0 "$b/e2e.txt" /usr/bin/python3 \
  "$bench/e2e_line.py" small 100 220 "$out"
check "e2e_line.py: 2.00 min, the compress stage's phi ($(cat "$b/e2e.txt"))" \
  "grep -q '^\[bench\] end to end small: 2.00 min on 2 ranks, [0-9]* steps, phi 0\.[0-9]\{5\}, z\* [0-9.]*$' '$b/e2e.txt'"
mkdir -p "$b/ci"
for deck in AC_small B_small D_small; do ln -s "$out" "$b/ci/out_${deck}_1"; done
check_exit "ci_bands.py WORK SEED, ci_bands.sh's command line" 0 "$b/ci.txt" /usr/bin/python3 \
  "$tools/ci_bands.py" "$b/ci" 1
check "ci_bands.py: the compress stage of the three runs, sd 0 ($(sed -n 2p "$b/ci.txt"))" \
  "grep -q '^compress  *0\.[0-9]\{4\} ± 0\.0000 ' '$b/ci.txt'"
check_exit "read_deck.py FILE OUT, render_pictures.sh's command line" 0 "$b/deck.txt" /usr/bin/python3 \
  "$tools/read_deck.py" "$out/final.h5" "$b/read.toml"
check "read_deck.py: the deck's [sample] then one read stage of the file" \
  "grep -q '^\[sample\]' '$b/read.toml' && [ \$(grep -c '^\[\[stage\]\]' '$b/read.toml') -eq 1 ] && tail -1 '$b/read.toml' | grep -qF 'file = \"$(cd "$out" && pwd)/final.h5\"'"

checks_done python_reader
