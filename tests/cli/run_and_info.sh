#!/usr/bin/env bash
# End to end: `granpack run` of the main deck on 2 ranks writes report.json (with every
# required key), final.h5 + final.xdmf and log.txt; `granpack info` reads the file written by
# 2 ranks on 1 rank; `granpack stiffness` on a packing without contacts refuses it (exit 2);
# MPI-IO hints (GRANPACK_MPIIO_HINTS) reach the writes without changing a bit of the file, and
# a malformed hints string stops the run at start-up with exit 2 and nothing written.
# It runs as a user's job does, with Open MPI's own transports (UCX), binding and kill timeout,
# not the quicker ones tests/CMakeLists.txt sets for the rest of the suite.
set -u
unset OMPI_MCA_pml OMPI_MCA_btl OMPI_MCA_btl_vader_eager_limit OMPI_MCA_hwloc_base_binding_policy \
  OMPI_MCA_odls_base_sigkill_timeout
: "${GRANPACK_EXE:?}" "${GRANPACK_SOURCE_DIR:?}"
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
cli_scratch

out="$scratch/main"
cat > "$scratch/lattice.toml" <<'TOML'
[sample]
dimension = 3
n = 256
diameter = 1.0e-3
[material]
density = 2500.0
young_modulus = 70.0e9
poisson_ratio = 0.3
friction = 0.3
damping = 0.98
[[stage]]
kind = "lattice"
phi = 0.60
[[stage]]
kind = "write"
file = "lattice.h5"
TOML
check_exit "run" 0 "$scratch/run.txt" granpack_on 2 run "$scratch/lattice.toml" -o "$out"
for f in report.json final.h5 final.xdmf lattice.h5 lattice.xdmf log.txt; do check "$f written" "[ -s '$out/$f' ]"; done
check "no temporary files left" "[ -z \"\$(ls '$out' | grep -i tmp)\" ]"
check "log.txt ends with why the run ended" "[ \"\$(tail -n 1 '$out/log.txt')\" = 'finished (exit 0)' ]"
check_python "report.json has every key and phi = 0.60" "$scratch/py.txt" "$out/report.json" <<'PY'
import json, math, sys
r = json.load(open(sys.argv[1]))
for k in ["version", "dimension", "n", "ranks", "stages"]:
    assert k in r, k
assert r["dimension"] == 3 and r["n"] == 256 and r["ranks"] == 2, r
need = ["name", "kind", "steps", "time", "equilibrated", "phi", "pressure", "kappa",
        "inertia_max", "z", "z_star", "x0", "wall_seconds"]
for s in r["stages"]:
    missing = [k for k in need if k not in s]
    assert not missing, missing
# the lattice stage must produce exactly the requested solid fraction
assert abs(r["stages"][0]["phi"] - 0.60) < 1e-12, r["stages"][0]["phi"]
PY

check_exit "info on 1 rank" 0 "$scratch/info.txt" "$GRANPACK_EXE" info "$out/final.h5"
check "info names dimension and n: $(cat "$scratch/info.txt")" \
  "grep -q 'dimension' '$scratch/info.txt' && grep -q '256' '$scratch/info.txt'"

check_refused "stiffness of a packing without contacts" 2 "no backbone" "$scratch/a.txt" \
  "$GRANPACK_EXE" stiffness "$out/final.h5"
with_hints() { GRANPACK_MPIIO_HINTS="romio_cb_write=enable, cb_nodes=1;cb_buffer_size=1048576" "$@"; }
check_exit "run with MPI-IO hints" 0 "$scratch/hints.txt" with_hints granpack_on 2 run "$scratch/lattice.toml" -o "$scratch/hints"
check "the file written with hints is the same bit for bit" 'same_state "$out/final.h5" "$scratch/hints/final.h5"'
bad_hints() { GRANPACK_MPIIO_HINTS="cb_nodes" "$@"; }
check_refused "a malformed GRANPACK_MPIIO_HINTS" 2 "GRANPACK_MPIIO_HINTS=\"cb_nodes\": 'cb_nodes' is not key=value" \
  "$scratch/bad_hints.txt" bad_hints granpack_on 2 run "$scratch/lattice.toml" -o "$scratch/bad_hints"
check "nothing written with malformed hints" '[ ! -e "$scratch/bad_hints" ]'
check_refused "info on a missing file" 2 "does_not_exist.h5" "$scratch/i.txt" \
  "$GRANPACK_EXE" info "$scratch/does_not_exist.h5"

check_refused "--version" 0 "granpack" "$scratch/version.txt" "$GRANPACK_EXE" --version
checks_done "run and info"
