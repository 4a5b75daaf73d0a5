#!/usr/bin/env bash
# End to end: `granpack stiffness` on 2 ranks on the Hertz FCC crystal (run here from the CI
# deck): exit 0, the table, every required JSON key with the crystal's values (only the 3
# trivial mechanisms, H from eq. 19, positive definite); the --modes files of the crystal (3D
# and 2D) and of tests/data/D_n500_divalent.h5 (its divalent grains' free rolling as fields);
# bad arguments and files exit 2; the
# same crystal with cohesion (3D, friction, no rolling resistance) is analysed as an
# interaction network: rigid, 3 rows per contact, H by [GRC] eq. (19), a cubic tensor.
set -u
: "${GRANPACK_EXE:?}" "${GRANPACK_SOURCE_DIR:?}"
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
cli_scratch

check_exit "fcc run" 0 "$scratch/run.txt" granpack_on 2 run "$GRANPACK_SOURCE_DIR/jobs/decks/ci/fcc_hertz.toml" -o "$scratch/fcc" -q
check_exit "stiffness" 0 "$scratch/s.txt" granpack_on 2 stiffness "$scratch/fcc/final.h5" --json "$scratch/s.json"
check "table printed once" "[ \$(grep -c 'mechanisms k' '$scratch/s.txt') -eq 1 ]"
check_python "JSON keys and FCC values" "$scratch/py.txt" "$scratch/s.json" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
need = ["mechanisms", "trivial_mechanisms", "divalent_mechanisms", "H", "H_over_Nf", "isostatic",
        "positive_definite", "virtual_work_residual", "bulk_modulus", "bulk_modulus_eq30",
        "shear_modulus_diag", "partition", "timings_seconds", "divalent_grains", "rattler_grains",
        "elastic_tensor"]
missing = [k for k in need if k not in j]
assert not missing, missing
assert j["ranks"] == 2 and j["n"] == 256, (j["ranks"], j["n"])
assert j["mechanisms"] == 3 and j["trivial_mechanisms"] == 3 and j["divalent_mechanisms"] == 0, j["mechanisms"]
assert j["H"] == 3 * 1536 + 3 - (6 * 256 + 3), j["H"]
assert j["positive_definite"] is True and j["isostatic"] is False
assert j["virtual_work_residual"] < 1e-3, j["virtual_work_residual"]
assert j["bulk_modulus"] > 0 and j["shear_modulus_diag"] > 0
PY

# --modes: the softest modes of the stiffened K(1) as fields (docs/stiffness.md). The pinned
# grain's translations are exact eigenvectors of eigenvalue <k_n> (its rows and columns are
# <k_n> 1): that mode must sit on the JSON's pinned_grain alone, which checks the way the
# rows of both ranks are put back onto grain ids; the other modes are unit vectors in
# (u, theta ell), orthogonal, with the eigenvalues the JSON reports.
check_exit "stiffness --modes 4" 0 "$scratch/sm.txt" granpack_on 2 stiffness "$scratch/fcc/final.h5" \
  --json "$scratch/sm.json" --modes 4 --modes-file "$scratch/modes.h5"
check_python "modes file: eigenvalues, unit and orthogonal modes, the pinned grain's mode" \
  "$scratch/pym.txt" "$scratch/sm.json" "$scratch/modes.h5" "$scratch/modes.xdmf" <<'PY'
import json, os, sys
import numpy as np
sys.path.insert(0, os.environ["GRANPACK_SOURCE_DIR"] + "/jobs/tools")
import granpack_io as gio
j = json.load(open(sys.argv[1]))
m = gio.read(sys.argv[2])  # by content: read_modes
ev, ell, ids = m["eigenvalues"], m["rotation_length"], m["id"]
assert len(ids) == 256 and m["backbone"].all() and m["displacement"].shape == (4, 256, 3)
modes = list(zip(m["displacement"], m["rotation"]))
assert j["modes_file"] == sys.argv[2], j["modes_file"]
assert np.allclose(ev, j["smallest_eigenvalues_over_mean_kn"][:4], rtol=1e-9, atol=0), (ev, j["smallest_eigenvalues_over_mean_kn"])
V = np.array([np.concatenate([u.ravel(), (r * ell).ravel()]) for u, r in modes])
assert np.allclose(V @ V.T, np.eye(4), atol=1e-9), V @ V.T
k = int(np.argmin(np.abs(ev - 1.0)))
assert abs(ev[k] - 1.0) < 1e-9, ev
a = np.linalg.norm(modes[k][0], axis=1)
on = ids == j["pinned_grain"]
assert abs(a[on][0] - 1) < 1e-9 and a[~on].max() < 1e-9 and np.abs(modes[k][1]).max() < 1e-9, (a[on], a[~on].max())
assert ev[0] < ev[k] and np.linalg.norm(modes[0][0], axis=1).max() < 0.5  # the softest is spread
assert m["divalent_grains"] is None and not m["divalent"].any()  # no divalent grain in FCC
x = open(sys.argv[3]).read()
assert x.count('AttributeType="Vector"') == 8 and "modes.h5:/modes/3/displacement" in x, x
PY
# The divalent grains' free rollings in the modes file (docs/stiffness.md, "Modes as fields"):
# tests/data/D_n500_divalent.h5 (3D, friction) on 2 ranks. Each divalent grain of the JSON
# rolls, alone, about the line through its two contact points: unit (u, theta ell), both
# contact points at rest (u + theta x p = 0), each on the line to its neighbour's nearest image
# within the grain; every other grain at rest; the sidecar carries the two vector arrays.
check_exit "D_n500: stiffness --modes 2 (divalent rolling)" 0 "$scratch/sd.txt" granpack_on 2 stiffness \
  "$GRANPACK_SOURCE_DIR/tests/data/D_n500_divalent.h5" --json "$scratch/sd.json" --modes 2 \
  --modes-file "$scratch/modesd.h5"
check_python "modes file: the divalent grains' rolling, both contact points at rest" "$scratch/pyd.txt" \
  "$scratch/sd.json" "$scratch/modesd.h5" "$GRANPACK_SOURCE_DIR/tests/data/D_n500_divalent.h5" \
  "$scratch/modesd.xdmf" <<'PY'
import os, sys
import numpy as np
sys.path.insert(0, os.environ["GRANPACK_SOURCE_DIR"] + "/jobs/tools")
import granpack_io as gio
j, m, p = gio.read_stiffness(sys.argv[1]), gio.read_modes(sys.argv[2]), gio.read_packing(sys.argv[3])
d, ell = m["divalent_grains"], m["rotation_length"]
assert d is not None and len(d["grain"]) == j["divalent_mechanisms"] >= 1, (d, j["divalent_mechanisms"])
assert d["grain"].tolist() == j["divalent_ids"].tolist(), (d["grain"], j["divalent_ids"])
assert d["neighbours"].tolist() == [e["neighbours"] for e in j["divalent_grains"]], d["neighbours"]
assert np.array_equal(m["divalent"], np.isin(m["id"], d["grain"]))
U, T = d["displacement"], d["rotation"]
assert U.shape == T.shape == (len(m["id"]), 3)
assert not U[~m["divalent"]].any() and not T[~m["divalent"]].any()
assert np.allclose(m["cell_length"], p.cell_length, rtol=1e-15), (m["cell_length"], p.cell_length)
s = p.grains["scaled_position"].astype(float)
for k, g in enumerate(d["grain"]):
    r, c = int(np.flatnonzero(m["id"] == g)[0]), p.row_of([g])[0]
    u, th = U[r], T[r]
    assert abs(np.linalg.norm(np.concatenate([u, ell * th])) - 1) < 1e-12, (g, u, th)
    assert np.linalg.norm(u) > 0.1 and np.linalg.norm(th) > 0, (g, u, th)
    for q, pt in zip(d["neighbours"][k], d["contact_points"][k]):
        nb = p.row_of([q])[0]
        b = (s[nb] - s[c] - np.round(s[nb] - s[c])) * p.cell_length
        n, R = b / np.linalg.norm(b), p.radius[c]
        assert np.linalg.norm(np.cross(pt, n)) < 1e-9 * R and pt @ n > 0, (g, q, pt, n)
        assert R - (R + p.radius[nb] - np.linalg.norm(b)) <= np.linalg.norm(pt) <= R, (g, q, pt)
        assert np.linalg.norm(u + np.cross(th, pt)) < 1e-12 * np.linalg.norm(u), (g, q)  # at rest
x = open(sys.argv[4]).read()
for a in ("divalent_rolling", "divalent_rolling_rotation"):
    assert f'Name="{a}" AttributeType="Vector"' in x, a
assert 'Name="divalent" AttributeType="Scalar"' in x
print(len(d["grain"]), "divalent grains: rolling with both contact points at rest")
PY
check_exit "--modes without --modes-file" 2 "$scratch/bm.txt" "$GRANPACK_EXE" stiffness "$scratch/fcc/final.h5" --modes 2


# --modes in 2D (the triangular crystal of jobs/decks/ci/triangular_linear.toml, friction, so
# rotations): displacements are [n, 2], rotations a scalar per grain, the modes unit and
# orthogonal in (u, theta ell) with the JSON's eigenvalues, the pinned grain's mode on it alone.
check_exit "2D crystal run" 0 "$scratch/run2.txt" granpack_on 1 run \
  "$GRANPACK_SOURCE_DIR/jobs/decks/ci/triangular_linear.toml" -o "$scratch/tri" -q
check_exit "2D stiffness --modes 3" 0 "$scratch/sm2.txt" granpack_on 2 stiffness "$scratch/tri/final.h5" \
  --json "$scratch/sm2.json" --modes 3 --modes-file "$scratch/modes2.h5"
check_python "2D modes file: shapes, unit and orthogonal modes, eigenvalues, the pinned grain" \
  "$scratch/pym2.txt" "$scratch/sm2.json" "$scratch/modes2.h5" "$scratch/modes2.xdmf" <<'PY'
import json, os, sys
import numpy as np
sys.path.insert(0, os.environ["GRANPACK_SOURCE_DIR"] + "/jobs/tools")
import granpack_io as gio
j, m = json.load(open(sys.argv[1])), gio.read_modes(sys.argv[2])
n, ev, ell = len(m["id"]), m["eigenvalues"], m["rotation_length"]
assert m["dimension"] == 2 and n == 128 and m["position"].shape == (n, 2), (m["dimension"], n)
assert m["displacement"].shape == (3, n, 2) and m["rotation"].shape == (3, n), m["rotation"].shape
assert np.allclose(ev, j["smallest_eigenvalues_over_mean_kn"][:3], rtol=1e-9, atol=0), ev
V = np.array([np.concatenate([u.ravel(), r * ell]) for u, r in zip(m["displacement"], m["rotation"])])
assert np.allclose(V @ V.T, np.eye(3), atol=1e-9), V @ V.T
pinned = m["id"] == j["pinned_grain"]
for k in range(3):  # the pinned grain's rows are <k_n> 1: it moves in the eigenvalue-1 modes only
    a = np.linalg.norm(m["displacement"][k][pinned])
    assert (abs(a - 1) < 1e-9) if abs(ev[k] - 1) < 1e-9 else (a < 1e-9), (k, ev[k], a)
x = open(sys.argv[3]).read()
assert 'GeometryType="XY"' in x and x.count('AttributeType="Vector"') == 3, x
assert m["divalent_grains"] is None and not m["divalent"].any() and len(m["cell_length"]) == 2
assert x.count('Name="mode_0_rotation" AttributeType="Scalar"') == 1, x
PY
check_refused "missing file" 2 "does_not_exist.h5" "$scratch/m.txt" "$GRANPACK_EXE" stiffness "$scratch/does_not_exist.h5"
check_exit "bad --null-pivot" 2 "$scratch/b.txt" "$GRANPACK_EXE" stiffness "$scratch/fcc/final.h5" --null-pivot 0

# 3D with cohesion (friction, no rolling resistance): the interaction network of the crystal.
sed -e 's/^friction = .*/friction = 0.3\ncohesion_force = 1.0e-3\ncohesion_range = 1.0e-6/' \
  "$GRANPACK_SOURCE_DIR/jobs/decks/ci/fcc_hertz.toml" > "$scratch/fcc_cohesive.toml"
check_exit "cohesive fcc run" 0 "$scratch/runc.txt" granpack_on 1 run "$scratch/fcc_cohesive.toml" -o "$scratch/fcc_c" -q
check_exit "3D cohesive stiffness" 0 "$scratch/c.txt" \
  "$GRANPACK_EXE" stiffness "$scratch/fcc_c/final.h5" --json "$scratch/c.json"
check "3D cohesive: rigid crystal, 3 rows per contact, H by eq. (19), cubic tensor" \
  "/usr/bin/python3 -c \"
import json, sys
j = json.load(open('$scratch/c.json'))
c = j['elastic_tensor']['c']
ok = (j['network'] == 'interactions' and j['H_relation'] == 'GRC eq. 19' and j['mechanisms'] == 3
      and j['pivoting_mechanisms'] == 0 and j['rigid'] and j['positive_definite']
      and j['G_rows'] == 3 * j['backbone_contacts'] and j['H'] == j['G_rows'] + 3 - j['N_f']
      and abs(c[0][0] - c[2][2]) < 1e-9 * c[0][0] and abs(c[3][3] - c[5][5]) < 1e-9 * c[0][0])
sys.exit(0 if ok else 1)
\""

checks_done stiffness.sh
