#!/usr/bin/env bash
# In-run trajectories ([output] trajectory_every; docs/visualisation.md, "Trajectories"): a tiny
# 2D deck on 2 ranks writes a snapshot every 50 steps into OUT/trajectory.h5 with the temporal
# sidecar OUT/trajectory.xdmf. Checked with jobs/tools/granpack_io.py: the number of snapshots
# and their steps, their contents (grains with ids, radii, positions, velocities; contacts; the
# /network group), the last snapshot equal to final.h5, the sidecar's time steps. Then the same
# run killed after a checkpoint (GRANPACK_FAULT=step:N) with snapshots past the checkpoint, and
# restarted: its trajectory equals the uninterrupted one (the same steps, the same bits). And
# trajectory_every = -1 is refused naming the key.
set -u
: "${GRANPACK_EXE:?}" "${GRANPACK_SOURCE_DIR:?}"
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
cli_scratch
export PYTHONPATH="$GRANPACK_SOURCE_DIR/jobs/tools:$PYTHONPATH"

deck=$scratch/traj.toml
{ small_deck 2 64 5; cat <<'TOML'
trajectory_every = 50
checkpoint_every_steps = 100
checkpoint_every_seconds = 0
[[stage]]
kind = "random"
phi = 0.6
[[stage]]
kind = "compress"
pressure = 1.0
inertia_max = 1.0e-3
max_steps = 600
TOML
} > "$deck"

whole=$scratch/whole chain=$scratch/chain
check_exit "2-rank run with trajectory_every = 50" 0 "$scratch/whole.txt" \
  granpack_on 2 run "$deck" -o "$whole" -q || checks_stop trajectory "$scratch/whole.txt"

# The same run killed at step 1970, inside compress (which starts near step 1500, after the
# random stage's overlap removal; its checkpoints wait for a rebuild after each 100 steps),
# then restarted from its checkpoint.
run_killed 2 "$deck" "$chain" 1970
ck_step=$("$GRANPACK_EXE" info "$chain/checkpoint.h5" | sed -n 's/^time:.*(step \([0-9]*\)).*/\1/p')
check "a checkpoint before the kill (step ${ck_step:-none})" "[ -n '$ck_step' ] && [ '$ck_step' -lt 1970 ]"
cp "$chain/trajectory.h5" "$scratch/before_restart.h5"
check_exit "restart" 0 "$scratch/restart.txt" \
  granpack_on 2 run "$deck" -o "$chain" -q --restart "$chain/checkpoint.h5"

/usr/bin/python3 - "$whole" "$chain" "$scratch/before_restart.h5" "${ck_step:-0}" > "$scratch/py.txt" 2>&1 <<'PY'
import re, sys
import numpy as np
import granpack_io as gio
from checks import check
whole, chain, before, ck_step = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])
t = gio.read_trajectory(f"{whole}/trajectory.h5")
final = gio.read_packing(f"{whole}/final.h5")
check(f"uninterrupted: snapshots at steps 50, 100, ... up to final.h5's {final.step} "
      f"({t.steps.tolist()})", t.steps.tolist() == list(range(50, final.step + 1, 50)) and len(t) >= 8)
check("gio.read() recognises a trajectory", isinstance(gio.read(f"{whole}/trajectory.h5"), gio.Trajectory))
check("the trajectory stores the deck", "trajectory_every = 50" in t.deck)
ok = True
for k, p in enumerate(t):
    ok &= p.n == 64 and p.dimension == 2 and p.step == t.steps[k] and p.time == t.times[k]
    ok &= sorted(p.grains["id"].tolist()) == list(range(64))
    ok &= all(k_ in p.grains for k_ in ("radius", "position", "velocity", "angular_velocity"))
    ok &= len(p.network.get("normal_force", [])) == p.nc and len(p.network["contacts"]) == p.n
stage = np.array([p.stage_index for p in t])
check(f"snapshots of both stages (random's overlap removal, compress: {np.bincount(stage).tolist()}), "
      "the time increasing within each", set(stage) == {0, 1} and np.all(np.diff(stage) >= 0)
      and all(np.all(np.diff(t.times[stage == s]) > 0) for s in (0, 1)))
check("every snapshot: 64 grains (ids 0..63, radii, positions, velocities), contacts, /network", ok)
last = t[len(t) - 1]
same = lambda a, b: a.shape == b.shape and np.array_equal(a, b)
order = lambda p: np.argsort(p.grains["id"])
d = np.abs(last.grains["position"][order(last)] - final.grains["position"][order(final)]).max()
check(f"the last snapshot (step {last.step}) is final.h5's run {final.step - last.step} steps "
      f"earlier (grains {d:.1e} m apart)", 0 <= final.step - last.step < 50 and d < 1e-4
      and same(last.grains["radius"][order(last)], final.grains["radius"][order(final)]))
moving = np.abs(t[0].grains["position"][order(t[0])] - last.grains["position"][order(last)]).max()
check(f"the grains moved between the first and the last snapshot ({moving:.2e} m)", moving > 0)

# Sidecar: one temporal collection, one member per snapshot at its time.
x = open(f"{whole}/trajectory.xdmf").read()
check("trajectory.xdmf is a temporal collection",
      re.search(r'GridType="Collection" CollectionType="Temporal"', x) is not None)
members = re.findall(r'<Grid Name="packing" GridType="Collection" CollectionType="Spatial">\s*<Time Value="([^"]+)"', x)
check(f"trajectory.xdmf: {len(members)} time steps, the snapshots' steps",
      [float(v) for v in members] == t.steps.astype(float).tolist())
check("trajectory.xdmf points into the snapshots' groups",
      all(f"trajectory.h5:{g}/particles/position" in x for g in t.groups))

# The killed run left snapshots after its checkpoint; the restart dropped and rewrote them.
b = gio.read_trajectory(before)
check(f"the killed run wrote snapshots after its checkpoint at step {ck_step} "
      f"(up to {b.steps.max()})", b.steps.max() > ck_step)
c = gio.read_trajectory(f"{chain}/trajectory.h5")
check(f"restarted chain: the same steps ({c.steps.tolist()})", same(c.steps, t.steps))
ok = len(c) == len(t)
for k in range(min(len(c), len(t))):
    p, q = c[k], t[k]
    ok &= p.time == q.time and same(p.grains["id"], q.grains["id"])
    for name in ("position", "velocity", "radius"):
        ok &= same(p.grains[name][order(p)], q.grains[name][order(q)])
check("restarted chain: every snapshot equals the uninterrupted run's, bit for bit", ok)
check("restarted chain's sidecar lists the same time steps",
      open(f"{chain}/trajectory.xdmf").read().count('CollectionType="Spatial"') == len(t))
try:
    gio.read_trajectory(f"{whole}/final.h5")
    check("read_trajectory refuses a configuration", False)
except gio.GranpackFileError as e:
    check(f"read_trajectory refuses a configuration naming the file ({e})", "final.h5" in str(e))
PY
checks_from "trajectory checks" "$scratch/py.txt" $?

sed 's/^trajectory_every = 50/trajectory_every = -1/' "$deck" > "$scratch/bad.toml"
check_refused "trajectory_every = -1" 2 "trajectory_every.*-1|-1.*trajectory_every" "$scratch/bad.txt" \
  granpack_on 1 run "$scratch/bad.toml" -o "$scratch/bad" -q

checks_done trajectory
