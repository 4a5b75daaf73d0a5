#!/usr/bin/env bash
# The committed [AR] ensembles keep table IV true (issue 26): every state listed in
# docs/data/ensembles/states.txt is checked by jobs/tools/ar_tables.py --check against the
# tolerances that docs/reproduction.md declares ("Table IV tolerances (checked by CI)"), and
# each committed ensemble.json must agree with its committed per-sample reports (mean, sample
# sd and K of every compress stage's Phi and z*, recomputed here), so a summary can be neither
# hand-edited nor left stale when samples are added.
# ctest: PROCESSORS 1   (one process at a time: ctest -j2 runs another test beside it)
set -u
: "${GRANPACK_SOURCE_DIR:?}"
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
cli_scratch
export MPLCONFIGDIR="$scratch/mpl"
ens="$GRANPACK_SOURCE_DIR/docs/data/ensembles"
manifest="$ens/states.txt"
check "manifest $manifest exists" "[ -s '$manifest' ]"

args=()
while read -r state source; do
  [[ -z "$state" || "$state" == \#* ]] && continue
  args+=(--state "$state=$ens/$source")
done < "$manifest"
check "the manifest names at least one state" "[ ${#args[@]} -gt 0 ]"

check_python "ensemble.json files agree with their sample reports" "$scratch/consistency.txt" "$ens" <<'PY'
import glob, json, math, os, statistics, sys
ens = sys.argv[1]
bad = 0
for path in sorted(glob.glob(os.path.join(ens, "*", "ensemble.json"))):
    e = json.load(open(path))
    d = os.path.dirname(path)
    reports = {s: json.load(open(os.path.join(d, f"sample_{s}.report.json"))) for s in e["seeds"]}
    assert e["K"] == len(reports), path
    names = [st["name"] for st in reports[e["seeds"][0]]["stages"] if st["kind"] == "compress"]
    for name in names:
        for key in ("phi", "z_star"):
            vals = [[st for st in reports[s]["stages"] if st["name"] == name][0][key] for s in e["seeds"]]
            got = e["report"][f"/stages/{name}/{key}"]
            sd = statistics.stdev(vals) if len(vals) > 1 else None
            ok = (got["values"] == vals and math.isclose(got["mean"], statistics.mean(vals), rel_tol=1e-14)
                  and (sd is None and got["sd"] is None or math.isclose(got["sd"], sd, rel_tol=1e-12)))
            if not ok:
                bad += 1
                print(f"{path}: /stages/{name}/{key} {got} does not match the sample reports {vals}")
print(f"{bad} mismatches")
sys.exit(1 if bad else 0)
PY
tail -1 "$scratch/consistency.txt"

/usr/bin/python3 "$GRANPACK_SOURCE_DIR/jobs/tools/ar_tables.py" --check "$GRANPACK_SOURCE_DIR/docs/reproduction.md" \
  "${args[@]}" > "$scratch/check.txt" 2> "$scratch/check.err"
rc=$?
check "table IV within the declared tolerances ($(grep -E 'FAIL|cells checked' "$scratch/check.txt" | tr '\n' ';'))" "[ $rc -eq 0 ]"
[ $rc -eq 0 ] || cat "$scratch/check.err"
checks_done ar_table4_committed
