#!/usr/bin/env bash
# ctest: PROCESSORS 1
# The rattler flags of the treatments of [AR] sec. III C in the written files
# (docs/visualisation.md, docs/hdf5-schema.md "/network"): a 120-grain frictional 3D packing on
# 1 rank, written before and after a fix_rattlers stage (treatment II). Before: /network/rattler
# (treatment I's iterated rule; treatment III removes these grains) = granpack_io's rattlers(),
# /network/fixed_rattler all 0. After: fixed_rattler = 1 on exactly the grains fix_rattlers
# pushed (as many as its report's `rattlers`, the grains flagged `rattler` before it), which moved,
# while every other grain stayed where it was, bit for bit; the sidecar shows fixed_rattler. A
# restart from the checkpoint written after fix_rattlers keeps the flags (/run_state). A `read`
# stage keeps them too: of after.h5 (its /network/fixed_rattler: a write stage after the read
# writes the same flags, a compress stage after that clears them) and of the checkpoint (its
# /run_state list).
set -u
: "${GRANPACK_EXE:?}" "${GRANPACK_SOURCE_DIR:?}"
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
cli_scratch
export PYTHONPATH="$GRANPACK_SOURCE_DIR/jobs/tools:$PYTHONPATH"

deck=$scratch/fix.toml
{ small_deck 3 120 3; cat <<'TOML'
checkpoint_every_steps = 0
[[stage]]
kind = "random"
phi = 0.45
[[stage]]
kind = "compress"
pressure = 1.0e4
inertia_max = 1.0e-2
quench_interval = 20000
[[stage]]
kind = "write"
file = "before.h5"
[[stage]]
kind = "fix_rattlers"
max_steps = 4000
[[stage]]
kind = "write"
file = "after.h5"
TOML
} > "$deck"
out=$scratch/run
check_exit "1-rank run: compress, write, fix_rattlers, write" 0 "$scratch/run.txt" \
  granpack_on 1 run "$deck" -o "$out" || checks_stop rattler_flags "$scratch/run.txt"
# The checkpoint written between fix_rattlers and the last write stage, restarted into a new
# directory: only that write stage runs again, from the restored state and /run_state.
check_exit "restart from the checkpoint after fix_rattlers" 0 "$scratch/restart.txt" \
  granpack_on 1 run "$deck" -o "$scratch/again" --restart "$out/checkpoint.h5"
# Decks of the same [sample] and [material] whose first stage reads a file: read_deck DECK
# FILE STAGES (the TOML of the stages after the read).
read_deck() {
  { sed '/^\[\[stage\]\]/,$d' "$deck"
    printf '[[stage]]\nkind = "read"\nfile = "%s"\n%s\n' "$2" "$3"; } > "$1"
}
read_deck "$scratch/reread.toml" "$out/after.h5" '[[stage]]
kind = "write"
file = "reread.h5"
[[stage]]
kind = "compress"
pressure = 1.0e4
max_steps = 20'
check_exit "read after.h5, write, compress" 0 "$scratch/reread.txt" \
  granpack_on 1 run "$scratch/reread.toml" -o "$scratch/reread"
read_deck "$scratch/fromcp.toml" "$out/checkpoint.h5" '[[stage]]
kind = "write"
file = "fromcp.h5"'
check_exit "read the checkpoint after fix_rattlers, write" 0 "$scratch/fromcp.txt" \
  granpack_on 1 run "$scratch/fromcp.toml" -o "$scratch/fromcp"

/usr/bin/python3 - "$out" "$scratch/again" "$scratch" > "$scratch/py.txt" 2>&1 <<'PY'
import json, sys
import numpy as np
import granpack_io as gio
from checks import check
out, again, scratch = sys.argv[1], sys.argv[2], sys.argv[3]
b = gio.read_packing(f"{out}/before.h5")
a = gio.read_packing(f"{out}/after.h5")
rep = json.load(open(f"{out}/report.json"))["stages"]
pushed = int(rep[3]["values"]["rattlers"])
rb = b.network["rattler"] == 1
check(f"before: rattler (treatment I) = rattlers() ({rb.sum()} of {b.n})",
      np.array_equal(rb, b.rattlers()) and rb.sum() > 0)
check("before: fixed_rattler all 0", b.network["fixed_rattler"].shape == (b.n,) and not b.network["fixed_rattler"].any())
ob, oa = np.argsort(b.grains["id"]), np.argsort(a.grains["id"])
fixed = (a.network["fixed_rattler"] == 1)[oa]
check(f"after: {fixed.sum()} fixed rattlers = fix_rattlers' report ({pushed})", fixed.sum() == pushed > 0)
check("after: they are the grains flagged rattler before", np.array_equal(fixed, rb[ob]))
moved = np.any(a.grains["position"][oa] != b.grains["position"][ob], axis=1)
check(f"the fixed rattlers moved ({moved[fixed].sum()} of {fixed.sum()}), no other grain did (bit for bit)",
      moved[fixed].sum() > 0 and not moved[~fixed].any())
print(f"after fix_rattlers, {int((a.network['rattler'] == 1).sum())} grains are rattlers by the iterated rule")
x = open(f"{out}/after.xdmf").read()
check("after.xdmf shows fixed_rattler", ">after.h5:/network/fixed_rattler<" in x)
g = gio.read_packing(f"{again}/after.h5")
check("restarted after fix_rattlers: the same after.h5, fixed_rattler flags included",
      np.array_equal(g.grains["position"], a.grains["position"])
      and np.array_equal(g.network["fixed_rattler"], a.network["fixed_rattler"]))
def flagged(p):
    return set(p.grains["id"][p.network["fixed_rattler"] == 1].tolist())
want = flagged(a)
for name, path in [("read after.h5, write", "reread/reread.h5"),
                   ("read the checkpoint, write", "fromcp/fromcp.h5")]:
    r = gio.read_packing(f"{scratch}/{path}")
    check(f"{name}: the same {len(want)} fixed rattlers", flagged(r) == want)
f = gio.read_packing(f"{scratch}/reread/final.h5")
check("read after.h5, then compress: no fixed rattler", not f.network["fixed_rattler"].any())
PY
checks_from "rattler flag checks" "$scratch/py.txt" $?
checks_done rattler_flags
