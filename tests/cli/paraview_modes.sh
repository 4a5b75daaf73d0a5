#!/usr/bin/env bash
# ParaView opens what `granpack stiffness --modes` writes and the 3D grain stress tensor
# (docs/visualisation.md, docs/stiffness.md "Modes as fields"). A Hertz FCC crystal (3D, 108
# grains, friction) is run on 1 rank (a 2-rank file: tests/cli/paraview.sh): pvbatch reads its
# final.xdmf with `stress` a 9-component tensor whose range is the file's, and
# jobs/tools/pv_modes.py reads the modes file of a 2-rank `stiffness --modes 3`: one point per
# grain, radius/id/backbone, each mode_k and mode_k_rotation a 3-vector, |u| of each mode as
# ParaView computes it equal to the file's (granpack_io.read_modes). The 2D triangular crystal
# (jobs/decks/ci/triangular_linear.toml, friction; stiffness on 1 rank): the same with mode_k a
# 2-vector (ParaView pads it to 3) and mode_k_rotation a scalar. Each picture of a mode is a PNG
# of 420 x 420 with more than 20 colours. One divalent grain's free rolling, zoomed (--mode
# divalent --grain, on tests/data/D_n500_divalent.h5): the grain, its partners, contacts and
# arrows ParaView holds. A file without modes, a mode the file does not hold, --mode divalent
# without divalent grains, a grain the file does not hold or that is not divalent, --grain
# without --png and a --packing of other grains are refused (exit 2, naming them). Skipped
# (exit 77) where pvbatch or Xvfb is absent.
set -u
: "${GRANPACK_EXE:?}" "${GRANPACK_SOURCE_DIR:?}"
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
require_pvbatch
cli_scratch
export MPLCONFIGDIR="$scratch/mpl"
tools="$GRANPACK_SOURCE_DIR/jobs/tools"

# The FCC deck at 3 x 3 x 3 cells (108 grains) started nearer close packing: 5 000 steps.
sed -e 's/^n = 256/n = 108/' -e 's/^phi = 0.73 .*/phi = 0.738/' -e 's/^cells = \[4, 4, 4\]/cells = [3, 3, 3]/' \
  "$GRANPACK_SOURCE_DIR/jobs/decks/ci/fcc_hertz.toml" > "$scratch/fcc_hertz.toml"
cp "$GRANPACK_SOURCE_DIR/jobs/decks/ci/triangular_linear.toml" "$scratch/"
for d in 3 2; do
  deck=$([ $d -eq 3 ] && echo fcc_hertz || echo triangular_linear)
  out="$scratch/d$d" np=$((d - 1))
  check_exit "${d}D: $deck run" 0 "$scratch/run$d.txt" granpack_on 1 run "$scratch/$deck.toml" -o "$out" -q ||
    checks_stop paraview_modes "$scratch/run$d.txt"
  check_exit "${d}D: stiffness --modes 3 on $np rank(s)" 0 "$scratch/st$d.txt" \
    granpack_on $np stiffness "$out/final.h5" --json "$scratch/st$d.json" --modes 3 \
    --modes-file "$scratch/modes$d.h5" || checks_stop paraview_modes "$scratch/st$d.txt"
  check_exit "${d}D: pvbatch reads the modes file and draws mode 0" 0 "$scratch/pvm$d.txt" \
    pvrun "$tools/pv_modes.py" "$scratch/modes$d.xdmf" --summary "$scratch/modes$d.json" \
    --png "$scratch/mode$d.png" --size 420 420
  check "${d}D: mode 0 is a PNG of 420 x 420" "big_png '$scratch/mode$d.png' 3000"
  check_python "${d}D: ParaView's view of the modes file is the file's" "$scratch/py$d.txt" \
    "$scratch/modes$d.h5" "$scratch/modes$d.json" "$scratch/mode$d.png" <<'PY'
import json, os, sys
sys.path.insert(0, os.environ["GRANPACK_SOURCE_DIR"] + "/jobs/tools")
import numpy as np
import matplotlib.image
import granpack_io as gio
m, s = gio.read_modes(sys.argv[1]), json.load(open(sys.argv[2]))
dim, n, K = m["dimension"], len(m["id"]), len(m["eigenvalues"])
g = s["grids"] if "grids" in s else s["grains"]
assert s["dimension"] == dim and K == 3, (s["dimension"], dim, K)
assert g["points"] == n and g["cells"] == n, (g["points"], g["cells"], n)
got = {k: v["components"] for k, v in g["point_arrays"].items()}
want = {"radius": 1, "id": 1, "backbone": 1, "divalent": 1}
for k in range(K):
    want[f"mode_{k}"] = 3  # ParaView pads a 2D vector to 3 components
    want[f"mode_{k}_rotation"] = 3 if dim == 3 else 1
assert got == want, (got, want)
assert s["modes"] == [f"mode_{k}" for k in range(K)], s["modes"]
for k in range(K):
    a = np.linalg.norm(m["displacement"][k], axis=1)
    r = s["magnitude_range"][f"mode_{k}"]
    assert np.allclose(r, [a.min(), a.max()], rtol=1e-12, atol=1e-15), (k, r, a.min(), a.max())
    first = m["rotation"][k][:, 0] if dim == 3 else m["rotation"][k]
    rr = g["point_arrays"][f"mode_{k}_rotation"]["range"]
    assert np.allclose(rr, [first.min(), first.max()], rtol=1e-12, atol=1e-15), (k, rr)
assert np.allclose(g["point_arrays"]["id"]["range"], [m["id"].min(), m["id"].max()])
img = matplotlib.image.imread(sys.argv[3])[:, :, :3]
colours = len(np.unique(img.reshape(-1, 3), axis=0))
assert colours > 20, colours
print(f"{dim}D: {n} grains, {K} modes, |u| ranges as in the file, picture of {colours} colours")
PY
done

# One divalent grain's free rolling, zoomed (pv_modes.py --mode divalent --grain): the small
# D-like packing tests/data/D_n500_divalent.h5 (3D, friction, one divalent grain), modes of a
# 2-rank stiffness. ParaView reads divalent, divalent_rolling and divalent_rolling_rotation
# with the file's |u| range; the zoom draws the grain, its two partners (the JSON's), only
# grains within 2.1 diameters that touch one of the three, the grain's two contacts, its two
# contact points (the file's), and 14 arrows (12 surface velocities, u, theta) that Glyph turns
# into arrows of equal point counts; a PNG of 480 x 360.
dfile="$GRANPACK_SOURCE_DIR/tests/data/D_n500_divalent.h5"
check_exit "D_n500: stiffness --modes 1 on 2 ranks" 0 "$scratch/std.txt" \
  granpack_on 2 stiffness "$dfile" --json "$scratch/std.json" --modes 1 --modes-file "$scratch/modesd.h5" ||
  checks_stop paraview_modes "$scratch/std.txt"
grain=$(/usr/bin/python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["divalent_grains"][0]["grain"])' "$scratch/std.json")
check_exit "pvbatch draws divalent grain $grain's rolling, zoomed" 0 "$scratch/pvd.txt" \
  pvrun "$tools/pv_modes.py" "$scratch/modesd.xdmf" --mode divalent --grain "$grain" --packing "$dfile" \
  --summary "$scratch/modesd.json" --png "$scratch/rolling.png" --size 480 360
check "the rolling is a PNG of 480 x 360" "big_png '$scratch/rolling.png' 3000"
check_python "the zoom holds grain $grain, its partners, contacts and arrows" "$scratch/pyd.txt" \
  "$scratch/modesd.h5" "$scratch/modesd.json" "$scratch/std.json" "$dfile" "$scratch/rolling.png" <<'PY'
import json, os, sys
sys.path.insert(0, os.environ["GRANPACK_SOURCE_DIR"] + "/jobs/tools")
import numpy as np
import matplotlib.image
import granpack_io as gio
m, s, j = gio.read_modes(sys.argv[1]), json.load(open(sys.argv[2])), json.load(open(sys.argv[3]))
p = gio.read_packing(sys.argv[4])
d, z = m["divalent_grains"], s["zoom"]
g, partners = j["divalent_grains"][0]["grain"], j["divalent_grains"][0]["neighbours"]
pa = s["grains"]["point_arrays"]
assert {k: pa[k]["components"] for k in ("divalent", "divalent_rolling", "divalent_rolling_rotation")} == \
    {"divalent": 1, "divalent_rolling": 3, "divalent_rolling_rotation": 3}, pa
assert "divalent_rolling" in s["modes"], s["modes"]
a = np.linalg.norm(d["displacement"], axis=1)
assert np.allclose(s["magnitude_range"]["divalent_rolling"], [a.min(), a.max()], rtol=1e-12, atol=1e-15)
assert z["grain"] == g and g in z["grains"] and z["partners"] == partners, (z["grain"], z["partners"], partners)
assert set(partners) <= set(z["grains"]) and z["faint"] == len(z["grains"]) - 3, z
assert sorted(map(sorted, z["own_contacts"])) == sorted(sorted([g, q]) for q in partners), z["own_contacts"]
# Every grain drawn is near and touches the grain or a partner (contacts with N^e > 0).
ids = p.grains["id"].astype(int)
a_, b_ = ids[p.i], ids[p.j]
on = (p.contacts["normal_force"] > 0) & ~p.distant
hub = set(partners) | {g}
touch = {int(x) for x, y in zip(a_[on], b_[on]) if y in hub} | {int(y) for x, y in zip(a_[on], b_[on]) if x in hub}
assert set(z["grains"]) <= touch | {g}, set(z["grains"]) - touch
r = m["position"][list(m["id"]).index(g)]
for i in z["grains"]:
    x = m["position"][list(m["id"]).index(i)] - r
    x -= m["cell_length"] * np.round(x / m["cell_length"])
    assert np.linalg.norm(x) <= 2.1 * 2 * m["radius"].mean(), (i, x)
k = list(d["grain"]).index(g)
assert np.allclose(z["contact_points"], r + d["contact_points"][k], rtol=0, atol=1e-12), z["contact_points"]
assert z["arrows"] == {"u": 1, "surface": 12, "theta": 1}, z["arrows"]
n1 = z["arrow_points"]["u"]
assert n1 > 0 and z["arrow_points"] == {"u": n1, "surface": 12 * n1, "theta": n1}, z["arrow_points"]
img = matplotlib.image.imread(sys.argv[5])[:, :, :3]
assert img.shape[:2] == (360, 480), img.shape
colours = len(np.unique(img.reshape(-1, 3), axis=0))
assert colours > 50, colours
print(f"grain {g}: partners {partners}, {len(z['grains'])} grains, {z['contacts']} contacts, 14 arrows, {colours} colours")
PY

# The 3D grain stress tensor as ParaView reads it (the 2D one: tests/cli/paraview.sh).
check_exit "3D: pvbatch reads final.xdmf" 0 "$scratch/pv3.txt" \
  pvrun "$tools/pv_packing.py" "$scratch/d3/final.xdmf" --summary "$scratch/packing3.json"
check_python "3D: stress is a 9-component tensor with the file's range" "$scratch/pys.txt" \
  "$scratch/d3/final.h5" "$scratch/packing3.json" <<'PY'
import json, os, sys
sys.path.insert(0, os.environ["GRANPACK_SOURCE_DIR"] + "/jobs/tools")
import numpy as np
import granpack_io as gio
p, s = gio.read_packing(sys.argv[1]), json.load(open(sys.argv[2]))
a = s["grids"]["particles"]["point_arrays"]
assert a["stress"]["components"] == 9, a["stress"]
sxx = np.asarray(p.network["stress"]).reshape(p.n, -1)[:, 0]
assert np.allclose(a["stress"]["range"], [sxx.min(), sxx.max()], rtol=1e-12), (a["stress"]["range"], sxx.min(), sxx.max())
# The trace over 3 is the mean stress the file also stores.
t = np.asarray(p.network["stress"]).reshape(p.n, 3, 3).trace(axis1=1, axis2=2) / 3
assert np.allclose(t, p.network["mean_stress"], rtol=1e-12, atol=1e-9 * abs(t).max()), abs(t - p.network["mean_stress"]).max()
for k in ("net_force", "angular_velocity", "velocity"):
    assert a[k]["components"] == 3, (k, a[k])
print("stress: 9 components, range", a["stress"]["range"])
PY

# Refusals come before ParaView is imported: plain python3 gives them.
check_refused "pv_modes.py on a packing (no modes)" 2 "holds no mode_k" "$scratch/nomodes.txt" \
  /usr/bin/python3 "$tools/pv_modes.py" "$scratch/d3/final.xdmf"
check_refused "pv_modes.py --mode 5 of 3" 2 "mode 5: the file holds modes 0 to 2" "$scratch/mode5.txt" \
  /usr/bin/python3 "$tools/pv_modes.py" "$scratch/modes2.xdmf" --mode 5 --png "$scratch/x.png"
check_refused "pv_modes.py on a missing file" 2 "nope.xdmf: no such file" "$scratch/nope.txt" \
  /usr/bin/python3 "$tools/pv_modes.py" "$scratch/nope.xdmf"
check_refused "pv_modes.py --mode divalent on the FCC crystal (no divalent grain)" 2 "holds no divalent rolling" \
  "$scratch/nodiv.txt" /usr/bin/python3 "$tools/pv_modes.py" "$scratch/modes3.xdmf" --mode divalent --png "$scratch/x.png"
partner=$(/usr/bin/python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["divalent_grains"][0]["neighbours"][0])' "$scratch/std.json")
check_refused "pv_modes.py --mode divalent --grain on a partner (not divalent)" 2 \
  "--grain $partner: not a divalent grain of the file \(it has 1 divalent grains, e.g. \[$grain\]\)" \
  "$scratch/notdiv.txt" /usr/bin/python3 "$tools/pv_modes.py" "$scratch/modesd.xdmf" --mode divalent \
  --grain "$partner" --png "$scratch/x.png"
check_refused "pv_modes.py --grain not in the file" 2 "--grain 99999: the modes file holds no grain of that id" \
  "$scratch/nogr.txt" /usr/bin/python3 "$tools/pv_modes.py" "$scratch/modesd.xdmf" --grain 99999 --png "$scratch/x.png"
check_refused "pv_modes.py --grain without --png" 2 "give --png" "$scratch/nopng.txt" \
  /usr/bin/python3 "$tools/pv_modes.py" "$scratch/modesd.xdmf" --mode divalent --grain "$grain"
check_refused "pv_modes.py --packing of other grains" 2 "not the grains of the modes file" "$scratch/otherp.txt" \
  /usr/bin/python3 "$tools/pv_modes.py" "$scratch/modesd.xdmf" --mode divalent --grain "$grain" \
  --packing "$scratch/d3/final.h5" --png "$scratch/x.png"
check "no picture of a refused mode" "[ ! -e '$scratch/x.png' ]"

checks_done paraview_modes
