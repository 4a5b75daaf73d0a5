#!/usr/bin/env bash
# Where a stage's wall time goes (report.json wall_split, md_classes; docs/report.md), on 2
# ranks: an FCC lattice melted by ed_gas and grown by ls_compress (event-driven), compressed
# from that gas without contacts by MD with checkpoints inside the stage every 2000 steps, then
# written. Only signs and sums of the times are checked, never their values:
#  - event_driven > 0 exactly in the two event-driven stages, 0 elsewhere; the MD phases > 0
#    only in compress;
#  - io > 0 in compress (its checkpoints) and in write, 0 in the stages that wrote nothing;
#  - every stage's parts add up to its wall_seconds, with other >= 0;
#  - compress: dense + loose steps = its steps, particle-steps = steps x n in each class, both
#    classes present (it starts from a gas without contacts and ends at z >= 2), the classes'
#    seconds within the MD phases; no md_classes in the stages without MD;
#  - the log has the split line for every stage and the classes line for compress;
#  - a restart from the last checkpoint reads the finished stages' entries back whole.
set -u
: "${GRANPACK_EXE:?}" "${GRANPACK_SOURCE_DIR:?}"
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
cli_scratch
cat > "$scratch/deck.toml" <<'TOML'
[sample]
dimension = 3
n = 256
diameter = 1.0e-3
seed = 7
[material]
density = 2500.0
normal_law = "hertz"
young_modulus = 2.88e8   # kappa = 1000 at 10 kPa (as jobs/decks/ci/gas_small.toml): short contact time
poisson_ratio = 0.3
friction = 0.3
damping = 0.98
[[stage]]
kind = "lattice"
phi = 0.45
[[stage]]
name = "melt"
kind = "ed_gas"
collisions_per_grain = 20
[[stage]]
name = "ls"
kind = "ls_compress"
phi = 0.55
[[stage]]
kind = "compress"
pressure = 1.0e4
inertia_max = 1.0e-2
max_steps = 6000   # z is about 5 by then; the test needs no equilibrium
[[stage]]
kind = "write"
file = "packing.h5"
TOML
out=$scratch/run
check_exit "run on 2 ranks" 0 "$scratch/run.txt" granpack_on 2 run "$scratch/deck.toml" -o "$out" \
  --checkpoint-every-steps 2000 --checkpoint-every-seconds 0 --quiet || checks_stop stage_timing "$scratch/run.txt"
check "a checkpoint inside compress" "grep -q 'inside the stage' '$out/log.txt'" || cat "$out/log.txt"
# The last checkpoint (after compress): the write stage again, the others from the checkpoint.
check_exit "restart from the checkpoint after compress" 0 "$scratch/restart.txt" granpack_on 2 run \
  "$scratch/deck.toml" -o "$scratch/restart" --restart "$out/checkpoint.h5" --quiet
/usr/bin/python3 - "$out" "$scratch/restart" > "$scratch/py.txt" 2>&1 <<'PY'
import json, sys
from checks import check
out, restart = sys.argv[1:3]
r = json.load(open(f"{out}/report.json"))
n, stages = r["n"], {s["name"]: s for s in r["stages"]}
check("stages: " + " ".join(stages), list(stages) == ["lattice", "melt", "ls", "compress", "write"])
md = ["forces", "neighbor", "comm", "integrate"]
parts = md + ["io", "event_driven"]
for name, s in stages.items():
    w = s.get("wall_split")
    if not w:
        check(f"{name}: wall_split present", False)
        continue
    check(f"{name}: wall_split has the parts and other", set(w) == set(parts + ["other"]))
    listed = sum(w[k] for k in parts)
    check(f"{name}: no part negative, other {w['other']} >= 0", min(w.values()) >= 0)
    check(f"{name}: the parts {listed} fit in wall_seconds {s['wall_seconds']}", listed <= s["wall_seconds"])
    check(f"{name}: the parts and other add up to wall_seconds",
          abs(listed + w["other"] - s["wall_seconds"]) <= 1e-9 * s["wall_seconds"])
    ed = name in ("melt", "ls")
    check(f"{name}: event_driven {w['event_driven']} {'> 0' if ed else '= 0'}",
          (w["event_driven"] > 0) == ed)
    wrote = name in ("compress", "write")
    check(f"{name}: io {w['io']} {'> 0' if wrote else '= 0'}", (w["io"] > 0) == wrote)
    mdstage = name == "compress"
    check(f"{name}: MD phases {[w[k] for k in md]} {'> 0' if mdstage else '= 0'}",
          all((w[k] > 0) == mdstage for k in md))
    check(f"{name}: md_classes {'present' if mdstage else 'absent'}", ("md_classes" in s) == mdstage)
c = stages["compress"]
w, p, m = c["wall_split"], c["phase_seconds"], c["md_classes"]
check("compress: wall_split's MD phases are phase_seconds'", all(w[k] == p[k] for k in md))
d, l = m["dense"], m["loose"]
check(f"compress: threshold {m['dense_contacts_per_grain']} contacts per grain", m["dense_contacts_per_grain"] == 1)
check(f"compress: dense {d['steps']} + loose {l['steps']} steps = {c['steps']}", d["steps"] + l["steps"] == c["steps"])
check("compress: particle-steps = steps x n in each class",
      d["particle_steps"] == d["steps"] * n and l["particle_steps"] == l["steps"] * n)
check(f"compress: from a gas to a packing (z {c['z']}): both classes", d["steps"] > 0 and l["steps"] > 0 and c["z"] >= 2)
for k in (d, l):
    check(f"compress: rate {k['particle_steps_per_second']} = particle-steps / seconds",
          k["seconds"] > 0 and abs(k["particle_steps_per_second"] * k["seconds"] - k["particle_steps"]) <= 1e-9 * k["particle_steps"])
check("compress: the classes' seconds within the MD phases",
      d["seconds"] + l["seconds"] <= (1 + 1e-9) * sum(w[k] for k in md))
log = open(f"{out}/log.txt").read().splitlines()
check("log: a split line per stage", sum(x.startswith("  time (s, mean over ranks):") for x in log) == 5)
cl = [x for x in log if x.startswith("  MD steps: dense ")]
check(f"log: one classes line, for compress: {cl}", len(cl) == 1 and f"dense {d['steps']} (" in cl[0])
again = {s["name"]: s for s in json.load(open(f"{restart}/report.json"))["stages"]}
check("restart: the finished stages' timing read back from the checkpoint",
      all(again[k].get(x) == stages[k].get(x) for k in ("melt", "ls", "compress")
          for x in ("wall_split", "md_classes", "phase_seconds")))
check("restart: its write stage timed anew (io > 0)", again["write"]["wall_split"]["io"] > 0)
PY
checks_from "the report checks" "$scratch/py.txt" $?
checks_done "stage timing"
