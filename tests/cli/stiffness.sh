#!/usr/bin/env bash
# End to end: `granpack stiffness` on 2 ranks on the Hertz FCC crystal (run here from the CI
# deck): exit 0, the table, every required JSON key with the crystal's values (only the 3
# trivial mechanisms, H from eq. 19, positive definite); bad arguments and files exit 2; the
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
