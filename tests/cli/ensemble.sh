#!/usr/bin/env bash
# `granpack run --samples` and `granpack ensemble` end to end (issue 26): a two-sample ensemble
# of a small deck on 2 ranks (1 rank per sample) writes OUT/sample_1, OUT/sample_2, and each
# sample's files equal, bit for bit, the same seed run alone on 1 rank; on 4 ranks
# (oversubscribed) with --ranks-per-sample 2 a sample equals the seed alone on 2 ranks;
# `ensemble --analyze` gives the mean and sample sd of the reports' numbers; --restart skips
# finished samples and continues one from its checkpoint to the same bits; bad options exit 2.
set -u
: "${GRANPACK_EXE:?}" "${GRANPACK_SOURCE_DIR:?}"
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
cli_scratch
same() { same_state "$1" "$2" > /dev/null; }

# 256 soft frictional grains: an ed_gas stage (its own seed), 4000 steps of compression and a
# written file.
deck="$scratch/small.toml"
cat > "$deck" <<'TOML'
[sample]
dimension = 3
n = 256
diameter = 1.0e-3
seed = 1
[material]
density = 2500.0
young_modulus = 2.88e8
poisson_ratio = 0.3
friction = 0.3
damping = 0.98
[output]
quiet = true
[[stage]]
kind = "lattice"
lattice = "fcc"
phi = 0.45
cells = [4, 4, 4]
[[stage]]
name = "melt"
kind = "ed_gas"
collisions_per_grain = 20
[[stage]]
kind = "compress"
pressure = 1.0e4
inertia_max = 1.0e-2
max_steps = 4000   # short: the test is about identical files, not about equilibrium
[[stage]]
kind = "write"
file = "S.h5"
TOML

ens="$scratch/ens"
check_exit "2-sample ensemble on 2 ranks" 0 "$scratch/ens.txt" granpack_on 2 run "$deck" --samples 2 -o "$ens"
for s in 1 2; do
  for f in report.json final.h5 S.h5 log.txt; do check "sample_$s/$f written" "[ -s '$ens/sample_$s/$f' ]"; done
  check "terminal lines of sample $s are marked" "grep -q '^\[sample $s\] ' '$scratch/ens.txt'"
done
for s in 1 2; do
  check_exit "seed $s alone" 0 "$scratch/alone$s.txt" granpack_on 1 run "$deck" --seed $s -o "$scratch/alone$s"
  check "sample $s = seed $s alone on 1 rank (final.h5, bit for bit)" "same '$ens/sample_$s/final.h5' '$scratch/alone$s/final.h5'"
  check "sample $s = seed $s alone on 1 rank (S.h5, bit for bit)" "same '$ens/sample_$s/S.h5' '$scratch/alone$s/S.h5'"
done
check "the two samples differ" "! same '$ens/sample_1/final.h5' '$ens/sample_2/final.h5'"
check_python "the stored deck of sample 2 says seed 2" "$scratch/deck_py.txt" "$ens" <<'PY'
import sys, h5py
d = h5py.File(sys.argv[1] + "/sample_2/final.h5")["deck"][()].decode()
assert "seed = 2  # granpack run --seed 2 (the deck says 1)" in d, d
PY

# Two samples of 2 ranks each on 4 ranks: each equals its seed alone on 2 ranks.
check_exit "2 samples x 2 ranks on 4 ranks" 0 "$scratch/ens4.txt" \
  granpack_on 4 run "$deck" --samples 2 --ranks-per-sample 2 -o "$scratch/ens4"
granpack_on 2 run "$deck" --seed 2 -o "$scratch/alone2_np2" > /dev/null 2>&1
check "sample 2 of 2 ranks = seed 2 alone on 2 ranks" "same '$scratch/ens4/sample_2/final.h5' '$scratch/alone2_np2/final.h5'"

# The statistics.
check_exit "ensemble --analyze" 0 "$scratch/summary.txt" granpack_on 2 ensemble "$ens" --analyze
check "analysis files written" "[ -s '$ens/sample_1/S.analysis.json' ] && [ -s '$ens/sample_2/S.analysis.json' ]"
check_python "ensemble.json: mean and sample sd of the samples' values" "$scratch/stats_py.txt" "$ens" <<'PY'
import json, sys
import numpy as np
d = sys.argv[1]
e = json.load(open(d + "/ensemble.json"))
assert e["format"] == "granpack-ensemble" and e["K"] == 2 and e["seeds"] == [1, 2], e["seeds"]
for stem, key, src in [("report", "/stages/compress/phi", None), ("S", "/z_star", "S.analysis.json")]:
    if src is None:
        vals = [[s for s in json.load(open(f"{d}/sample_{k}/report.json"))["stages"]
                 if s["name"] == "compress"][0]["phi"] for k in (1, 2)]
        st = e["report"][key]
    else:
        vals = [json.load(open(f"{d}/sample_{k}/{src}"))[key[1:]] for k in (1, 2)]
        st = e["analysis"][stem][key]
    assert st["K"] == 2 and st["values"] == vals, (st, vals)
    assert abs(st["mean"] - np.mean(vals)) <= 1e-15 * abs(st["mean"]), st
    assert abs(st["sd"] - np.std(vals, ddof=1)) <= 1e-12 * st["sd"], st
    assert st["sd"] > 0
PY

# Provenance: each report names the build (the commit of this binary), the summary lists the
# seeds per build, and warns when the samples come from different builds.
commit=$("$GRANPACK_EXE" --version | sed -n 's/.*(commit \([0-9a-f]*\|unknown\).*/\1/p')
check_python "report.json names the build, ensemble.json its seeds ($commit)" "$scratch/build_py.txt" \
  "$ens" "$commit" <<'PY'
import json, sys
d, commit = sys.argv[1], sys.argv[2]
r = json.load(open(d + "/sample_1/report.json"))
assert r["build"]["commit"] == commit and isinstance(r["build"]["dirty"], bool), r["build"]
key = commit + ("+dirty" if r["build"]["dirty"] else "")
assert json.load(open(d + "/ensemble.json"))["builds"] == {key: [1, 2]}
PY
check "one build: no warning" "! grep -q 'different builds' '$scratch/summary.txt'" || cat "$scratch/summary.txt"
cp -r "$ens" "$scratch/mixed"
/usr/bin/python3 - "$scratch/mixed/sample_2/report.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1])); r["build"] = {"commit": "0123456789ab", "dirty": False}
json.dump(r, open(sys.argv[1], "w"))
PY
check_exit "ensemble of samples from two builds" 0 "$scratch/mixed.txt" granpack_on 1 ensemble "$scratch/mixed"
check "... warns and names both" "grep -q 'different builds' '$scratch/mixed.txt' && grep -q '0123456789ab (seeds \[2\])' '$scratch/mixed.txt'" ||
  cat "$scratch/mixed.txt"

# --restart: finished samples are skipped, a new one runs; a sample with only a checkpoint
# continues from it to the same bits as its uninterrupted run.
cp "$ens/sample_1/report.json" "$scratch/report1.json"
check_exit "--restart of the ensemble" 0 "$scratch/restart.txt" granpack_on 2 run "$deck" --samples 3 --restart -o "$ens"
check "finished samples are skipped" "[ \$(grep -c 'skipped' '$scratch/restart.txt') -eq 2 ]"
check "sample 1 untouched" "cmp -s '$ens/sample_1/report.json' '$scratch/report1.json'"
check "sample 3 ran" "[ -s '$ens/sample_3/report.json' ]"
mkdir -p "$scratch/ens_ck/sample_3"
cp "$ens/sample_3/checkpoint.h5" "$scratch/ens_ck/sample_3/"
granpack_on 1 run "$deck" --samples 1 --first-seed 3 --restart -o "$scratch/ens_ck" > /dev/null 2>&1
check "an unfinished sample continues from its checkpoint" "grep -q 'restart from' '$scratch/ens_ck/sample_3/log.txt'"
check "... to the same bits" "same '$ens/sample_3/final.h5' '$scratch/ens_ck/sample_3/final.h5'"

# Bad options: exit 2 with a message, nothing run. Two refusals of the library itself are checked
# in-process on 1 and 2 ranks instead (tests/mpi/ensemble.cpp, EnsembleRefusals.*): a
# --ranks-per-sample that does not divide the job's ranks (nothing written), and `ensemble` of
# a directory without samples.
expect_bad() {  # NAME PATTERN ARGS...
  local name=$1 pattern=$2; shift 2
  check_refused "$name" 2 "$pattern" "$scratch/bad.txt" granpack_on 2 "$@"
}
expect_bad "--seed with --samples" "exclude each other" run "$deck" --samples 2 --seed 3 -o "$scratch/bad1"
expect_bad "--restart FILE with --samples" "takes no file" run "$deck" --samples 2 --restart x.h5 -o "$scratch/bad3"
expect_bad "--first-seed without --samples" "add --samples" run "$deck" --first-seed 4 -o "$scratch/bad4"
check "nothing written for bad options" "[ ! -e '$scratch/bad1' ] && [ ! -e '$scratch/bad3' ]"
# The same seed alone must name the seed when restarted without it.
expect_bad "restart without the sample's seed" "restart with --seed 3" run "$deck" --restart "$ens/sample_3/checkpoint.h5" -o "$scratch/bad5"

checks_done ensemble
