#!/usr/bin/env bash
# ParaView opens what a 2-rank run writes (docs/visualisation.md): jobs/tools/pv_packing.py
# under pvbatch reads final.xdmf (a committed 2D cohesive packing, compressive and tensile
# contacts, read and rewritten on 2 ranks) and its
# contact network, and the numbers of points, cells and arrays it reports are those of
# final.h5 (grains n points and n cells with radius, id, velocity, angular_velocity, contacts,
# carrying_contacts, net_force, net_moment (2D: a scalar, = granpack_io's net_moment()), mean_stress, stress (2D: 4 components); contacts nc cells of 2 of 2 nc points with normal_force,
# tangential_force, kind, the force range that of the file); the rendered force network is a
# PNG of 300 x 300 pixels or more with more than one colour; jobs/tools/xdmf_series.py makes
# a time series of the run's two files, which ParaView reads as 2 steps at their times, and the
# run's trajectory ([output] trajectory_every) is read as one time step per snapshot. A
# missing file is refused
# (exit 2, naming it). Skipped (exit 77) where pvbatch or Xvfb is absent: `bash jobs/setup.sh
# test` installs paraview, python3-paraview and xvfb (Debian's ParaView renders through X only,
# so pvbatch runs on a virtual X server: jobs/tools/with_xvfb.sh).
set -u
: "${GRANPACK_EXE:?}" "${GRANPACK_SOURCE_DIR:?}"
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
require_pvbatch
cli_scratch
export MPLCONFIGDIR="$scratch/mpl"
pv="$GRANPACK_SOURCE_DIR/jobs/tools/pv_packing.py"

# A 2D cohesive packing (compressive and tensile contacts) rewritten by a 2-rank run: a deck
# with the committed file's own [sample] and [material] and one `read` stage.
coh="$GRANPACK_SOURCE_DIR/docs/data/2d/method1_cohesive_small.h5"
/usr/bin/python3 - "$coh" "$scratch/coh.toml" <<'PY'
import os, sys
sys.path.insert(0, os.environ["GRANPACK_SOURCE_DIR"] + "/jobs/tools")
import granpack_io as gio
deck = gio.read_packing(sys.argv[1]).deck.split("[[stage]]")[0]
# Snapshots every 100 steps of the compress stage (OUT/trajectory.h5 and its series).
deck = (deck.replace("[output]", "[output]\ntrajectory_every = 100") if "[output]" in deck
        else deck + "\n[output]\ntrajectory_every = 100\n")
open(sys.argv[2], "w").write(deck + f'\n[[stage]]\nkind = "read"\nfile = "{sys.argv[1]}"\n'
                             '[[stage]]\nkind = "write"\nfile = "before.h5"\n'
                             '[[stage]]\nkind = "compress"\npressure = 20.0\nmax_steps = 400\n')
PY
out="$scratch/run"
check_exit "2-rank run reading a 2D cohesive packing" 0 "$scratch/run.txt" \
  granpack_on 2 run "$scratch/coh.toml" -o "$out" || checks_stop paraview "$scratch/run.txt"
check "final.xdmf has the contacts grid" "grep -q 'Polyline' '$out/final.xdmf'"

t0=$(now)
check_exit "pvbatch reads final.xdmf and renders it" 0 "$scratch/pv.txt" \
  pvrun "$pv" "$out/final.xdmf" --summary "$scratch/summary.json" --png "$scratch/chains.png" --size 480 480
echo "pvbatch: $(elapsed "$t0") s"
check "chains.png: a PNG of 480 x 480" "big_png '$scratch/chains.png' 5000"

/usr/bin/python3 - "$out/final.h5" "$scratch/summary.json" "$scratch/chains.png" > "$scratch/py.txt" 2>&1 <<'PY'
import json, sys
sys.path.insert(0, __import__("os").environ["GRANPACK_SOURCE_DIR"] + "/jobs/tools")
import numpy as np
import granpack_io as gio
from checks import check

p = gio.read_packing(sys.argv[1])
s = json.load(open(sys.argv[2]))["grids"]
g, c = s.get("particles", {}), s.get("contacts", {})
check(f"particles: {g.get('points')} points, {g.get('cells')} cells = n = {p.n}",
      g.get("points") == p.n and g.get("cells") == p.n)
# ParaView pads 2-component vectors to 3.
want = {"radius": 1, "id": 1, "velocity": 3, "angular_velocity": 1, "contacts": 1,
        "carrying_contacts": 1, "net_force": 3, "net_moment": 1, "mean_stress": 1, "rattler": 1, "fixed_rattler": 1,
        "stress": 4,  # 2D: the 2 x 2 stress tensor as 4 components
        "cluster_id": 1, "bond_order": 1, "crystalline": 1}
got = {k: v["components"] for k, v in g.get("point_arrays", {}).items()}
check(f"particle arrays {got}", all(got.get(k) == v for k, v in want.items()))
cid = p.cluster_ids()
check(f"cluster_id range {g['point_arrays']['cluster_id']['range']} = the reader's cluster_ids() "
      f"({len(np.unique(cid))} clusters, distant pairs as links)",
      np.allclose(g["point_arrays"]["cluster_id"]["range"], [cid.min(), cid.max()])
      and np.array_equal(p.network["cluster_id"], cid))
# 2D: the net moment about z, a scalar; the engine's sums against the reader's recomputation.
M = p.net_moment()
mscale = np.abs(p.total_normal_force).max() * p.diameter
check(f"net_moment range {g['point_arrays'].get('net_moment', {}).get('range')} = the reader's "
      f"net_moment() [{M.min():.6g}, {M.max():.6g}] (K_r = {p._param('rolling_stiffness'):.3g})",
      np.allclose(g["point_arrays"]["net_moment"]["range"], [M.min(), M.max()], rtol=0,
                  atol=1e-9 * mscale)
      and np.allclose(p.network["net_moment"].reshape(-1), M, rtol=0, atol=1e-9 * mscale))
check("radius range as in the file", np.allclose(g["point_arrays"]["radius"]["range"],
                                                  [p.radius.min(), p.radius.max()]))
check(f"contacts: {c.get('cells')} cells = nc = {p.nc}, {c.get('points')} points = 2 nc",
      c.get("cells") == p.nc and c.get("points") == 2 * p.nc)
got = {k: v["components"] for k, v in c.get("cell_arrays", {}).items()}
check(f"contact arrays {got}", got == {"normal_force": 1, "tangential_force": 1, "kind": 1,
                                      "mobilisation": 1, "strong": 1})
N = p.total_normal_force
check(f"normal force range {c['cell_arrays']['normal_force']['range']} = file's",
      np.allclose(c["cell_arrays"]["normal_force"]["range"], [N.min(), N.max()]))
check("tensile and compressive contacts both present", N.min() < 0 < N.max())
L = p.cell_length
b = c["bounds"]
reach = 2 * p.radius.max()
check(f"contact segments within one diameter of the cell (bounds {np.round(b, 6).tolist()})",
      b[0] >= -reach and b[1] <= L[0] + reach and b[2] >= -reach and b[3] <= L[1] + reach)


import matplotlib.image
img = matplotlib.image.imread(sys.argv[3])[:, :, :3]
colours = len(np.unique(img.reshape(-1, 3), axis=0))
check(f"the picture is not blank ({colours} colours)", colours > 20)
PY
checks_from "ParaView's view of the file" "$scratch/py.txt" $?

# A time series of the two files the run wrote (before.h5 at the read, final.h5 400 steps on).
check_exit "xdmf_series.py" 0 "$scratch/series.txt" /usr/bin/python3 \
  "$GRANPACK_SOURCE_DIR/jobs/tools/xdmf_series.py" "$out/series.xdmf" "$out/final.h5" "$out/before.h5"
check_exit "pvbatch reads the series" 0 "$scratch/pvs.txt" \
  pvrun "$pv" "$out/series.xdmf" --summary "$scratch/series.json"
check_python "the series: 2 steps at the files' times, grains and contacts in each" "$scratch/ser.txt" \
  "$out" "$scratch/series.json" <<'PY'
import json, os, sys
sys.path.insert(0, os.environ["GRANPACK_SOURCE_DIR"] + "/jobs/tools")
import granpack_io as gio
out, s = sys.argv[1], json.load(open(sys.argv[2]))
a, b = gio.read_packing(f"{out}/before.h5"), gio.read_packing(f"{out}/final.h5")
assert b.time > a.time, (a.time, b.time)
assert s["times"] == [a.time, b.time], (s["times"], a.time, b.time)
g = s["grids"]
assert g["particles"]["points"] == a.n and g["contacts"]["cells"] == a.nc, g
PY
check_refused "a series of one file twice" 2 "same time" "$scratch/twice.txt" /usr/bin/python3 \
  "$GRANPACK_SOURCE_DIR/jobs/tools/xdmf_series.py" "$out/twice.xdmf" "$out/final.h5" "$out/final.h5"

# The run's trajectory (trajectory_every = 100 during the 400 steps of compress) as ParaView
# plays it: one time step per snapshot, at its step, the grains and contacts of the first.
check_exit "pvbatch reads the trajectory's series" 0 "$scratch/pvt.txt" \
  pvrun "$pv" "$out/trajectory.xdmf" --summary "$scratch/trajectory.json"
check_python "the trajectory: one time step per snapshot (at its step), grains and contacts" \
  "$scratch/traj.txt" "$out" "$scratch/trajectory.json" <<'PY'
import json, os, sys
sys.path.insert(0, os.environ["GRANPACK_SOURCE_DIR"] + "/jobs/tools")
import granpack_io as gio
out, s = sys.argv[1], json.load(open(sys.argv[2]))
t = gio.read_trajectory(f"{out}/trajectory.h5")
assert len(t) >= 3, t.steps
assert s["times"] == [float(x) for x in t.steps], (s["times"], t.steps)
first = t[0]
g = s["grids"]
assert g["particles"]["points"] == first.n and g["contacts"]["cells"] == first.nc, (g, first.n, first.nc)
print(f"{len(t)} time steps at steps {t.steps.tolist()}")
PY

check_refused "a missing file" 2 "nope.xdmf: no such file" "$scratch/bad.txt" pvrun "$pv" "$scratch/nope.xdmf"

checks_done paraview
