#!/usr/bin/env bash
# Checkpoints that contradict themselves are refused with exit 2 and a message naming the file
# and what is wrong, before anything runs, on 2 ranks (issue 31, "Inconsistent files
# accepted"). A real checkpoint (the CI gas deck killed by GRANPACK_FAULT=step:6500, with a
# checkpoint every 3000 steps, taken at the next neighbour-list rebuild: inside compress) is
# copied and damaged with h5py:
# - a grain id twice, a contact naming a grain the file does not hold (before: the restart ran,
#   or failed later in an internal check);
# - one grain fewer than the deck's n (ran);
# - a domain grid that does not fit the rank count (aborted inside MPI_Cart_create);
# - a cell mass of 0 or < 0 in the compress stage's frame (ran forever);
# - a stage index past the deck's end (ran nothing and wrote a final.h5);
# - a NaN force (analyze printed nan) and negative forces everywhere (analyze aborted with
#   "type must be number, but is number"), through `run --restart` and `analyze`.
# The untouched checkpoint still restarts (stopped at once by the hold fault, to save time).
set -u
: "${GRANPACK_EXE:?}" "${GRANPACK_SOURCE_DIR:?}"
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
cli_scratch
deck=$GRANPACK_SOURCE_DIR/jobs/decks/ci/gas_small.toml
run=$scratch/run
GRANPACK_FAULT=step:6500 granpack_on 2 run "$deck" -o "$run" -q --checkpoint-every-steps 3000 \
  --checkpoint-every-seconds 0 > "$scratch/run.txt" 2>&1
check "the checkpoint to damage (inside compress)" \
  '"$GRANPACK_EXE" info "$run/checkpoint.h5" | grep -q "^stage: *1 .compress."' \
  || { tail "$scratch/run.txt"; checks_stop "bad checkpoints"; }

check_python "damaged copies written" "$scratch/damage.txt" "$run/checkpoint.h5" "$scratch" <<'PY'
import json, shutil, sys
import h5py
import numpy as np
src, out = sys.argv[1], sys.argv[2]

def damaged(name, change):
    path = f"{out}/{name}.h5"
    shutil.copy(src, path)
    with h5py.File(path, "r+") as f:
        change(f)

def edit_state(f, change):
    state = json.loads(f["run_state"][()])
    change(state)
    del f["run_state"]
    f["run_state"] = np.bytes_(json.dumps(state))

def poke(dset, change):
    def f_(f):
        a = f[dset][...]
        change(a)
        f[dset][...] = a
    return f_

def fewer(f):  # drop the last grain (and its contacts), consistently with the counts
    n = f.attrs["n_particles"] - 1
    gone = f["particles/id"][n]
    keep = (f["contacts/first"][...] != gone) & (f["contacts/second"][...] != gone)
    for group, rows in (("particles", slice(0, n)), ("contacts", keep)):
        for k in list(f[group]):
            data, attrs = f[f"{group}/{k}"][...][rows], dict(f[f"{group}/{k}"].attrs)
            del f[f"{group}/{k}"]
            f[f"{group}/{k}"] = data
            f[f"{group}/{k}"].attrs.update(attrs)
    f.attrs["n_particles"], f.attrs["n_contacts"] = n, int(keep.sum())

def cell_mass(hexbits):
    return lambda f: edit_state(f, lambda s: s["frames"][0].__setitem__("cell_mass", hexbits))

damaged("duplicate_id", poke("particles/id", lambda a: a.__setitem__(-1, a[0])))
damaged("missing_grain", poke("contacts/second", lambda a: a.__setitem__(0, 10**6)))
damaged("fewer_grains", fewer)
damaged("grid", lambda f: edit_state(f, lambda s: s.__setitem__("grid", [3, 1, 1])))
damaged("cell_mass_zero", cell_mass("0x0000000000000000"))
damaged("cell_mass_negative", cell_mass("0xbf50000000000000"))
damaged("stage_past_end", lambda f: edit_state(f, lambda s: s.__setitem__("stage_index", 9)))
damaged("nan_force", poke("contacts/normal_force", lambda a: a.__setitem__(3, np.nan)))
damaged("negative_forces", poke("contacts/normal_force", lambda a: np.negative(np.abs(a), out=a)))
PY

# refused NAME PATTERN: `run --restart` of the damaged copy NAME.h5 exits 2, its message
# naming the file and matching PATTERN; no final.h5.
refused() {
  local name=$1 pattern=$2
  check_refused "restart from $name.h5 refused" 2 "$name\.h5: .*$pattern" "$scratch/$name.txt" \
    timeout 120 mpiexec -n 2 "$GRANPACK_EXE" run "$deck" -o "$scratch/o_$name" -q --restart "$scratch/$name.h5"
  check "$name: no final.h5" '[ ! -e "$scratch/o_$name/final.h5" ]'
}
refused duplicate_id "particle id [0-9]+ appears 2 times in /particles/id"
refused missing_grain "a contact names grain 1000000, which /particles/id does not hold"
refused fewer_grains "holds 499 grains, but its deck's \[sample\] n = 500"
refused grid "domain grid \(3 x 1 x 1\) does not fit its rank count 2"
refused stage_past_end "stage_index 9 \(inside the stage\) is past the end of the deck"
refused nan_force "/contacts/normal_force row 3 holds nan"
refused negative_forces "/contacts/normal_force row [0-9]+ = -.*never negative"
# The frame's cell mass is read when the compress stage resumes: the message names the frame.
for name in cell_mass_zero cell_mass_negative; do
  check_refused "restart from $name.h5 refused" 2 "compress frame holds cell_mass = .*need a positive finite mass" \
    "$scratch/$name.txt" timeout 120 mpiexec -n 2 "$GRANPACK_EXE" run "$deck" -o "$scratch/o_$name" -q \
    --restart "$scratch/$name.h5"
done
for name in nan_force negative_forces duplicate_id; do
  check_refused "analyze $name.h5 refused" 2 "$name\.h5: " "$scratch/a_$name.txt" \
    timeout 120 mpiexec -n 2 "$GRANPACK_EXE" analyze "$scratch/$name.h5"
done

# The undamaged checkpoint restarts (held at its next step and stopped: exit 75).
next=$(( $("$GRANPACK_EXE" info "$run/checkpoint.h5" | sed -n 's/^time: .*(step \([0-9]*\))$/\1/p') + 1 ))
GRANPACK_FAULT=hold:$next mpiexec -n 2 "$GRANPACK_EXE" run "$deck" -o "$scratch/o_good" -q \
  --restart "$run/checkpoint.h5" < /dev/null > "$scratch/good.txt" 2>&1 &
pid=$!
wait_until 3000 0.1 "[ \$(grep -c 'holds at step $next ' '$scratch/good.txt') -ge 2 ]"
kill -USR1 $pid 2>/dev/null
wait $pid; code=$?; pid=
check "the undamaged checkpoint restarts (exit $code, expected 75)" '[ $code -eq 75 ]' || tail "$scratch/good.txt"
checks_done "bad checkpoints"
