#!/usr/bin/env bash
# [GRC] method 2 on 150 cohesive disks (jobs/decks/2d/method2_small.toml):
# aggregation of Maxwell-agitated grains in the fixed cell, relaxation at P* = 0, compression
# to P* = 0.01 with the strain rate capped at 0.05/T0; then a second deck reads the result and
# `stiffen`s it from kappa = 1e2 to 1e3 at P* = 0.01 and re-equilibrates. Checked from the
# files, independently of the engine:
# - every stage that seeks equilibrium reached it; the aggregate is one cluster (union-find
#   over the file's contacts and distant pairs);
# - P0.h5 and the stiffened final.h5: N^e = K_N h for every contact, with the NEW K_N after
#   stiffen (the stage changed the law; `analyze` reads it from the file's /parameters), net static
#   force and moment on every grain below the deck's tolerance (1e-3 F0, 1e-3 F0 a), static
#   stress within 1e-3 F0/a of P;
# - the aggregation keeps the fixed cell's Phi; the relaxation at P* = 0 changes it by less
#   than 5 %; the strain rate of the P* = 0.01 compression stayed below its cap (the inertia
#   number the stage reports, I = eps_dot sqrt(m/P), is at most 0.05/T0 sqrt(m/P));
# - the stiffen deck (40 increments over 100 000 steps, a checkpoint every 20 000) killed
#   (SIGKILL injected by GRANPACK_FAULT=step:N) 1000 steps after its first checkpoint inside
#   stiffen and restarted from it
#   ends bit for bit as the uninterrupted run (the frame holds the ramp's increment and start
#   stiffness, the checkpoint the stiffnesses in force);
# - `granpack analyze` of P0.h5 reports the [GRC] coordination the file gives;
# - the aggregation with velocity quenches (quench_interval) under [GRC]'s own criteria: it
#   quenched, ended in equilibrium with one cluster, and the file's velocities are not the
#   zeroed ones of a quench (kinetic energy > 0 and < 5e-8 F0 a per grain, net force < 1e-4 F0);
#   with quench_delay, the first quench comes that many steps after the aggregate became one
#   cluster.
set -u
: "${GRANPACK_EXE:?}" "${GRANPACK_SOURCE_DIR:?}"
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
. "$GRANPACK_SOURCE_DIR/tests/support/restart_chain.sh"
restart_scratch   # $scratch, $pid, stop_run, and the EXIT trap
# The method 2 deck and the aggregation with quenches run side by side on one rank
# each: at 150 disks one rank is faster than two (the halo exchange outweighs the forces). The
# stiffen chain, whose restart must be exact on every rank count, runs on 2 ranks.
m2=$scratch/m2 q=$scratch/quench
awk '/^\[\[stage\]\]/ { k++ } k < 3' "$GRANPACK_SOURCE_DIR/jobs/decks/2d/method2_small.toml" |   # random, aggregate
  sed -e 's/^tolerance_force = 1e-3/tolerance_force = 1e-4/' -e 's/^tolerance_moment = 1e-3/tolerance_moment = 1e-4/' \
      -e 's/^tolerance_kinetic = 1e-6/tolerance_kinetic = 5e-8/' \
      -e 's/^cluster_every = 5000/cluster_every = 5000\nquench_interval = 20000\nquench_delay = 40000/' > "$scratch/quench.toml"
printf '[[stage]]\nkind = "write"\nfile = "aggregate.h5"\n' >> "$scratch/quench.toml"
t0=$(now)
start_bg "$scratch/m2.txt" granpack_on 1 run "$GRANPACK_SOURCE_DIR/jobs/decks/2d/method2_small.toml" -o "$m2" -q
m2_pid=$bg_pid
start_bg "$scratch/q.txt" granpack_on 1 run "$scratch/quench.toml" -o "$q" -q
check_bg "quench run" 0 "$scratch/q.txt" $bg_pid
check_bg "method 2 run" 0 "$scratch/m2.txt" $m2_pid || checks_stop method2_2d
echo "method 2 deck and aggregation with quenches: $(elapsed $t0) s"
grep -E "aggregated|equilibrated|interactions" "$m2/log.txt"
np=2

deck=$scratch/stiffen.toml
cat > "$deck" <<TOML
[sample]
dimension = 2
n = 150
diameter = 1.0e-3
distribution = "uniform"
min_diameter_ratio = 0.5
seed = 2
[material]
density = 2500.0
normal_law = "linear"
normal_stiffness = 1.0e5
tangential_stiffness_ratio = 1.0
friction = 0.5
damping = 0.8
cohesion_force = 1.0
cohesion_range = 1.0e-6
[output]
log_every = 1000000
[[stage]]
kind = "read"
file = "$m2/final.h5"
[[stage]]
kind = "stiffen"
normal_stiffness = 1.0e6
steps = 100000   # 2500 per increment: the stiff stage then equilibrates in ~12 000 steps
increments = 40
pressure = 10.0
cell_mass = 0.3
cell_mass_per_length = true
[[stage]]
name = "stiff"
kind = "compress"
pressure = 10.0
cell_mass = 0.3
cell_mass_per_length = true
tolerance_force = 1e-3
tolerance_moment = 1e-3
tolerance_stress = 1e-3
tolerance_kinetic = 1e-6
TOML
run_options=(--checkpoint-every-steps 20000 --checkpoint-every-seconds 0)
whole=$scratch/whole
t0=$(now)
check_exit "stiffen run" 0 "$scratch/whole.txt" run_deck "$whole"
echo "stiffen deck: $(elapsed $t0) s"
grep -E "increment 40|equilibrated" "$whole/log.txt"
out=$whole; first=$(checkpoint_steps 1 | head -n 1); out=$scratch/chain
check "the uninterrupted run wrote a checkpoint inside stiffen (step ${first:-none})" '[ -n "$first" ]'
# The kill-and-restart chain, each step needing the one before. The kill is injected 1000
# steps after that checkpoint (GRANPACK_FAULT=step:N), so it lands there on any machine load.
if [ -n "$first" ] && faulty_leg "killed at step $((first + 1000)), inside stiffen" "step:$((first + 1000))"; then
  echo "killed inside stiffen; checkpoint at stage $(checkpoint_stage)"
  check_exit "restart from the checkpoint inside stiffen" 0 "$scratch/restart.txt" run_deck "$out" --restart "$out/checkpoint.h5"
  resumed=$(grep -c "inside stage 1 'stiffen'" "$out/log.txt")
  check "the restart resumed inside stiffen" '[ "$resumed" -gt 0 ]' || grep "restart from" "$out/log.txt"
  check "the chain ends as the uninterrupted run (final.h5 bit for bit, report.json)" 'same_run "$whole" "$out" "$np"'
fi
stop_run

check_exit "analyze P0.h5" 0 "$scratch/an.txt" granpack_on $np analyze "$m2/P0.h5" --json "$scratch/an.json"

# The files, checked independently of the engine: one line per check (cli_checks.sh checks_from).
/usr/bin/python3 - "$m2" "$whole" "$scratch/an.json" "$q" > "$scratch/py.txt" 2>&1 <<'PY'
import json, sys
import numpy as np
from checks import check
from packing_file import Packing
m2, stiff, an_file, quench = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4]
a, F0, D0, mu, phi_I, tol = 1e-3, 1.0, 1e-6, 0.5, 0.36, 1e-3
m = 2500 * np.pi * a * a / 4

def check_file(path, K_N, P, label, tol=tol):
    p = Packing(path)
    touch = ~p.distant
    err = np.abs(p.Ne[touch] - K_N * p.h[touch]).max() / F0
    check(f"{label}: N^e = K_N h (K_N = {K_N:g}) within 1e-9 F0 ({err:.3g} F0)", not err > 1e-9)
    Ns, net, mom, sigma = p.static_balance(F0, D0)
    fmax = np.sqrt((net ** 2).sum(1)).max() / F0
    gmax = np.abs(mom).max() / (F0 * a)
    dp = np.abs(np.diag(sigma) - P).max() * a / F0 if P is not None else 0.0  # None: fixed cell
    check(f"{label}: net force {fmax:.3g} F0 < {tol:g}", not fmax >= tol)
    check(f"{label}: net moment {gmax:.3g} F0 a < {tol:g}", not gmax >= tol)
    check(f"{label}: |sigma - P| {dp:.3g} F0/a < {tol:g}", not dp >= tol)
    clusters = p.clusters()
    check(f"{label}: {clusters} clusters (one expected)", clusters == 1)
    print(f"{label}: F/F0 {fmax:.2e}, G/(F0 a) {gmax:.2e}, |sigma - P| a/F0 {dp:.2e}, "
          f"N^e - K_N h {err:.1e} F0, {clusters} cluster")
    return Ns, len(p.x)

rep = json.load(open(f"{m2}/report.json"))
st = {s["name"]: s for s in rep["stages"]}
for name in ("aggregate", "P0", "P0.01"):
    check(f"stage {name} equilibrated", st[name].get("equilibrated"))
check(f"aggregate: {st['aggregate']['values']['clusters']} clusters (one expected)",
      st["aggregate"]["values"]["clusters"] == 1)
Ns, n = check_file(f"{m2}/P0.h5", 1e5, 0.0, "P0.h5")
check_file(f"{m2}/final.h5", 1e5, 10.0, "P0.01")
srep = json.load(open(f"{stiff}/report.json"))
ss = {s["name"]: s for s in srep["stages"]}
sv = ss["stiffen"]["values"]
check(f"stiffen: K_N {sv['normal_stiffness_start']} -> {sv['normal_stiffness']} (1e5 -> 1e6)",
      not (sv["normal_stiffness"] != 1e6 or sv["normal_stiffness_start"] != 1e5))
check(f"stiffen: kappa {sv['kappa_start']} -> {sv['kappa']} (1e2 -> 1e3)",
      not (abs(sv["kappa"] - 1e3) > 1e-9 or abs(sv["kappa_start"] - 1e2) > 1e-9))
check("the stiffened packing equilibrated", ss["stiff"].get("equilibrated"))
check_file(f"{stiff}/final.h5", 1e6, 10.0, "stiffened")
phi = {k: st[k]["phi"] for k in ("aggregate", "P0", "P0.01")}
check(f"aggregate kept the fixed cell's phi: {phi['aggregate']}", not abs(phi["aggregate"] / phi_I - 1) > 1e-12)
check(f"relaxation at P* = 0: phi {phi_I} -> {phi['P0']}, within 5 %", abs(phi["P0"] / phi_I - 1) < 0.05)
I_cap = 35.68 * np.sqrt(m / 10.0)
check(f"P0.01: inertia number {st['P0.01']['inertia_max']} within the strain-rate cap's {I_cap}",
      st["P0.01"]["inertia_max"] <= I_cap * (1 + 1e-9))
zi = 2 * len(Ns) / n
an = json.load(open(an_file))["interactions"]
check(f"P0 report z {st['P0']['values']['z_interactions']}, the file gives {zi}",
      not abs(st["P0"]["values"]["z_interactions"] - zi) > 1e-12)
for k, v in (("z_plus", 2 * (Ns > 1e-4 * F0).sum() / n), ("z_minus", 2 * (Ns < -1e-4 * F0).sum() / n)):  # analyze: 1e-4 F1
    check(f"analyze {k} {an[k]}, the file gives {v}", not abs(an[k] - v) > 1e-12)
print(f"phi: I {phi_I}, aggregate {phi['aggregate']:.5f}, P*=0 {phi['P0']:.5f}, P*=0.01 "
      f"{phi['P0.01']:.5f}, stiffened {ss['stiff']['phi']:.5f}; z(P0) {zi:.4f}; "
      f"I {st['P0.01']['inertia_max']:.4g} <= {I_cap:.4g}")
qr = {s["name"]: s for s in json.load(open(f"{quench}/report.json"))["stages"]}["aggregate"]
check(f"quenched aggregation: equilibrated {qr.get('equilibrated')}, quenched, one cluster: values {qr['values']}",
      not (not qr.get("equilibrated") or qr["values"]["quenches"] < 1 or qr["values"]["clusters"] != 1))
check_file(f"{quench}/aggregate.h5", 1e5, None, "quenched aggregate", 1e-4)
# quench_delay: the first quench comes 40 000 steps (to the next 50-step check) after the first
# cluster count that found one cluster, not at that count.
import re
started = re.findall(r"step (\d+): velocity quenches from now on \(one cluster since step (\d+)\)",
                     open(f"{quench}/log.txt").read())
check(f"quench_delay = 40000: first quench / one cluster at steps {started}",
      not (len(started) != 1 or not 40000 <= int(started[0][0]) - int(started[0][1]) < 40050))
import h5py
with h5py.File(f"{quench}/aggregate.h5", "r") as f:
    v = f["particles/velocity"][:]
    w = f["particles/angular_velocity"][:]
    R = f["particles/radius"][:]
mass = 2500 * np.pi * R ** 2
inertia = 0.5 * mass * R ** 2
ek = 0.5 * (mass * (v ** 2).sum(1) + inertia * (w ** 2).sum(1)).mean() / (F0 * a)
check(f"quenched aggregate: kinetic energy per grain {ek:.3g} F0 a in (0, 5e-8)", 0 < ek < 5e-8)
print(f"quenched aggregate: {int(qr['values']['quenches'])} quenches, {qr['steps']} steps, "
      f"z {qr['values']['z_interactions']:.4f}, Ek {ek:.2e} F0 a per grain")
PY
checks_from "the file checks" "$scratch/py.txt" $?
checks_done method2_2d
