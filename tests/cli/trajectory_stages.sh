#!/usr/bin/env bash
# Trajectories every Δt of simulated time and at each stage end ([output] trajectory_every_time,
# trajectory_stage_ends; docs/visualisation.md, "Trajectories"): a tiny 2D deck on 2 ranks
# (random: its overlap removal runs at dt ≈ 0.0197 s up to t ≈ 30 s, then the time starts again
# at 0; compress, 300 steps; write, no step) with trajectory_every_time = 3 s. Checked with
# jobs/tools/granpack_io.py: in the overlap removal one snapshot at the first step at or past
# each multiple of 3 s (k = 1, 2, ... without a gap or a repeat, each less than one step past
# kΔt), none in compress (0.02 s long); a snapshot at each stage end (the random stage's last
# step, the compress stage's), the write stage's end (no step) replacing the compress stage's
# (one snapshot per step, the last one the write stage's and equal to final.h5); the sidecar's
# time steps. Then the same run killed inside compress after a checkpoint and restarted: the
# same snapshots, bit for bit. And bad values are refused naming the key, the value and what is
# allowed.
set -u
: "${GRANPACK_EXE:?}" "${GRANPACK_SOURCE_DIR:?}"
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
cli_scratch
export PYTHONPATH="$GRANPACK_SOURCE_DIR/jobs/tools:$PYTHONPATH"

deck=$scratch/traj.toml
{ small_deck 2 64 5; cat <<'TOML'
trajectory_every_time = 3.0
trajectory_stage_ends = true
checkpoint_every_steps = 100
checkpoint_every_seconds = 0
[[stage]]
kind = "random"
phi = 0.6
[[stage]]
kind = "compress"
pressure = 1.0
inertia_max = 1.0e-3
max_steps = 300
[[stage]]
kind = "write"
file = "copy.h5"
TOML
} > "$deck"

whole=$scratch/whole chain=$scratch/chain
check_exit "2-rank run with trajectory_every_time = 3 s, trajectory_stage_ends" 0 "$scratch/whole.txt" \
  granpack_on 2 run "$deck" -o "$whole" -q || checks_stop trajectory_stages "$scratch/whole.txt"

# The same run killed at step 1700, inside compress (which starts after the random stage's
# ~1500 steps of overlap removal), then restarted from its checkpoint.
run_killed 2 "$deck" "$chain" 1700
check_exit "restart" 0 "$scratch/restart.txt" \
  granpack_on 2 run "$deck" -o "$chain" -q --restart "$chain/checkpoint.h5"

/usr/bin/python3 - "$whole" "$chain" > "$scratch/py.txt" 2>&1 <<'PY'
import json, math, re, sys
import numpy as np
import granpack_io as gio
from checks import check
whole, chain = sys.argv[1], sys.argv[2]
DT = 3.0
t = gio.read_trajectory(f"{whole}/trajectory.h5")
final = gio.read_packing(f"{whole}/final.h5")
stages = json.load(open(f"{whole}/report.json"))["stages"]
end0 = stages[0]["steps"]                      # the random stage starts at step 0
end1 = end0 + stages[1]["steps"]
stage = np.array([p.stage_index for p in t])
print("steps", t.steps.tolist())
print("times", t.times.tolist())
print("stages", stage.tolist())
check(f"one snapshot per step ({len(t)} snapshots)", len(np.unique(t.steps)) == len(t) and len(t) >= 10)
# Overlap removal: the time rule. dt from the snapshots themselves (constant in that stage).
timed = (stage == 0) & (t.steps != end0)
steps0, times0 = t.steps[timed], t.times[timed]
dt = times0[0] / steps0[0]
k = np.floor(times0 / DT + 1e-12).astype(int)
check(f"overlap removal: a snapshot past each multiple of {DT} s, k = {k.tolist()} (no gap, no repeat)",
      len(k) >= 8 and k.tolist() == list(range(1, len(k) + 1)))
check(f"each the first step at or past k Δt (less than one step dt = {dt:.4g} s past it)",
      np.all(times0 - k * DT >= 0) and np.all(times0 - k * DT < dt * (1 + 1e-9)))
check(f"stage ends: the random stage's last step {end0} and the compress stage's {end1}",
      end0 in t.steps.tolist() and end1 in t.steps.tolist()
      and t.at_step(end0).stage_index == 0)
check("no snapshot inside compress (0.02 s of simulated time, less than Δt)",
      not np.any((t.steps > end0) & (t.steps < end1)))
last = t[len(t) - 1]
check(f"the write stage's end (no step) replaced the compress stage's: step {last.step}, stage "
      f"{last.stage_index} '{last.stage_name}'",
      last.step == end1 == final.step and last.stage_index == 2 and t.steps.tolist().count(end1) == 1)
order = lambda p: np.argsort(p.grains["id"])
same = lambda a, b: a.shape == b.shape and np.array_equal(a, b)
check("the last snapshot is final.h5 (positions and velocities bit for bit)",
      same(last.grains["position"][order(last)], final.grains["position"][order(final)])
      and same(last.grains["velocity"][order(last)], final.grains["velocity"][order(final)])
      and len(last.network.get("net_moment", [])) == last.n)
x = open(f"{whole}/trajectory.xdmf").read()
members = re.findall(r'<Grid Name="packing" GridType="Collection" CollectionType="Spatial">\s*<Time Value="([^"]+)"', x)
check(f"trajectory.xdmf: {len(members)} time steps, the snapshots' steps",
      [float(v) for v in members] == t.steps.astype(float).tolist())
c = gio.read_trajectory(f"{chain}/trajectory.h5")
check(f"restarted chain: the same steps ({c.steps.tolist()})", same(c.steps, t.steps))
ok = len(c) == len(t)
for j in range(min(len(c), len(t))):
    p, q = c[j], t[j]
    ok &= p.time == q.time and p.stage_index == q.stage_index and same(p.grains["id"], q.grains["id"])
    for name in ("position", "velocity", "radius"):
        ok &= same(p.grains[name][order(p)], q.grains[name][order(q)])
check("restarted chain: every snapshot equals the uninterrupted run's, bit for bit", ok)
PY
checks_from "trajectory_stages checks" "$scratch/py.txt" $?

# Bad values: refused naming the key and the value (and, for a number, what is allowed).
refuse() {  # refuse LINE PATTERN: the deck with LINE in place of its own line for that key
  local key=${1%% =*}
  sed "s/^$key = .*/$1/" "$deck" > "$scratch/bad.toml"
  check_refused "$1" 2 "$2" "$scratch/bad.txt" granpack_on 1 run "$scratch/bad.toml" -o "$scratch/bad" -q
}
refuse "trajectory_every_time = -1.0" "trajectory_every_time.*-1.*out of range.*finite.*must be >= 0"
refuse "trajectory_every_time = inf" "trajectory_every_time.*inf.*out of range.*finite"
refuse 'trajectory_stage_ends = "yes"' 'trajectory_stage_ends.*yes'
sed "s/^trajectory_every_time = .*/trajectory_every_time = 2/" "$deck" > "$scratch/int.toml"
check_exit "trajectory_every_time = 2 (an integer number of seconds) accepted by granpack check" 0 \
  "$scratch/int.txt" "$GRANPACK_EXE" check "$scratch/int.toml"

checks_done trajectory_stages
