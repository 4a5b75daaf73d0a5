#!/usr/bin/env bash
# Smoke test of `granpack bench` (docs/performance.md) on the committed n = 4000 A packing,
# 20 steps (a few seconds): the report and JSON are written, the static pressure is the
# packing's 10 kPa and is the same on 1 and 2 ranks, the static-force and LAMMPS data files
# hold every grain, a bad --replicate is refused with exit code 2, and the default 2-rank run
# (through the shared-memory window) ends as the same 20 steps with --halo messages. The full benchmark
# (jobs/bench/run_bench.sh, with LAMMPS) is not a CI test.
set -u
: "${GRANPACK_EXE:?}" "${GRANPACK_SOURCE_DIR:?}"
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
cli_scratch
packing="$GRANPACK_SOURCE_DIR/docs/data/A_n4000_seed1.h5"

for np in 1 2; do
  check_exit "bench on $np rank(s)" 0 "$scratch/np$np.txt" granpack_on $np bench "$packing" --steps 20 \
    --json "$scratch/np$np.json" --static-forces "$scratch/forces$np.txt" --lammps-data "$scratch/bench$np.data"
  check "report on $np rank(s)" "grep -q 'particle-steps/s per rank' '$scratch/np$np.txt'"
  check "static forces of every grain ($np)" "[ \$(grep -vc '^#' '$scratch/forces$np.txt') -eq 4000 ]"
  check "LAMMPS data file ($np)" "grep -q '^4000 atoms' '$scratch/bench$np.data'"
done
check_python "1 and 2 ranks agree on the static state" "$scratch/py.txt" "$scratch/np1.json" "$scratch/np2.json" <<'PY'
import json, sys
a, b = (json.load(open(f)) for f in sys.argv[1:3])
assert a["n"] == b["n"] == 4000 and a["ranks"] == 1 and b["ranks"] == 2, (a, b)
assert abs(a["static_pressure"] - 1e4) < 1.0, a["static_pressure"]
assert abs(a["static_pressure"] - b["static_pressure"]) < 1e-9 * 1e4, (a, b)
assert a["static_contacts"] == b["static_contacts"], (a, b)
# dt comes from the mean overlap, a global sum whose order depends on the rank count.
assert abs(a["dt"] - b["dt"]) < 1e-12 * a["dt"] and a["particle_steps_per_s_per_rank"] > 0, (a["dt"], b["dt"])
PY
check_refused "--replicate 0 refused" 2 "replicate" "$scratch/bad.txt" granpack_on 1 bench "$packing" --replicate 0 1 1
# --halo messages (jobs/bench/run_bench.sh HALO=...): the default 2-rank run above went through
# the shared-memory window (the 2 ranks share this node); through messages the 20 steps end the
# same (pressure and contacts).
check_exit "bench --halo messages on 2 ranks" 0 "$scratch/msg.txt" granpack_on 2 bench "$packing" \
  --steps 20 --halo messages --json "$scratch/msg.json"
check_python "the shared-memory halo (default) gives the message run's end state" "$scratch/shm_py.txt" \
  "$scratch/msg.json" "$scratch/np2.json" <<'PY'
import json, sys
m, s = (json.load(open(f)) for f in sys.argv[1:3])
assert m["halo"] == "messages" and s["halo"] == "shared_memory", (m["halo"], s["halo"])
for key in ("static_pressure", "static_contacts", "dt", "rebuilds"):
    assert m[key] == s[key], (key, m[key], s[key])
PY
check_refused "--halo shm refused" 2 "halo" "$scratch/bad_halo.txt" granpack_on 1 bench "$packing" --halo shm

checks_done bench_smoke
