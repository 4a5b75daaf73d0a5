#!/usr/bin/env bash
# jobs/tools/case_table.py, the table printer of the jobs/runs sweeps (method1_sweep.sh,
# seeds.sh, collapse_study.sh): on synthetic report.json files whose answers are known,
#  - one line per case from BASE/<case>/report.json and from BASE/<case>.report.json (the
#    layout of the reports committed under docs/data/2d/table2, table3), the last compress
#    stage or the one --stage names;
#  - --ensemble: K, mean and sample standard deviation (ddof = 1) per case over the bases that
#    hold its report, a stage that did not equilibrate left out and named;
#  - the committed table II reports of docs/data/2d/table2 read as one base (K = 1 per case).
# ctest: PROCESSORS 1
set -u
: "${GRANPACK_SOURCE_DIR:?}"
tool="$GRANPACK_SOURCE_DIR/jobs/tools/case_table.py"
py=/usr/bin/python3
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
cli_scratch

# Three seeds of two cases; seed 3 of case "b" did not equilibrate; seed 2 lacks case "b".
$py - "$scratch" <<'PY'
import json, os, sys
root = sys.argv[1]
def report(path, phi, z, z_int, equilibrated=True):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    stages = [{"name": "P0", "kind": "compress", "phi": 0.1, "z": 1.0, "steps": 5,
               "wall_seconds": 1.0, "equilibrated": True, "values": {"z_interactions": 1.5}},
              {"name": "P0.01", "kind": "compress", "phi": phi, "z": z, "steps": 10,
               "wall_seconds": 2.0, "equilibrated": equilibrated,
               "values": {"z_interactions": z_int}}]
    json.dump({"stages": stages}, open(path, "w"))
report(f"{root}/s1/a.report.json", 0.70, 3.0, 3.2)          # the committed layout
report(f"{root}/s2/a/report.json", 0.72, 3.1, 3.3)          # a run directory
report(f"{root}/s3/a/report.json", 0.74, 3.2, 3.4)
report(f"{root}/s1/b.report.json", 0.50, 2.0, 2.5)
report(f"{root}/s3/b/report.json", 0.90, 2.9, 2.9, equilibrated=False)
PY

check_exit "one line per run" 0 "$scratch/single.log" $py "$tool" "$scratch/s2" a
check "the run directory's last compress stage" 'grep -Eq "^ +a +0\.7200 +3\.100 +3\.300" "$scratch/single.log"' ||
  cat "$scratch/single.log"
check_exit "the committed layout, --stage P0" 0 "$scratch/stage.log" $py "$tool" "$scratch/s1" a --stage P0
check "--stage picks P0" 'grep -Eq "^ +a +0\.1000 +1\.000 +1\.500" "$scratch/stage.log"' || cat "$scratch/stage.log"

check_exit "--ensemble" 0 "$scratch/ens.log" $py "$tool" "$scratch/s1" a b --ensemble "$scratch/s2" "$scratch/s3"
# a: 0.70, 0.72, 0.74 -> mean 0.72, sd 0.02; z 3.1 +- 0.1; z_int 3.3 +- 0.1
check "case a: K 3, Phi 0.7200 +- 0.0200, z 3.100 +- 0.100, z_int 3.300 +- 0.100" \
  'grep -Eq "^ +a +3 +0\.7200 \+- 0\.0200 +3\.100 \+- 0\.100 +3\.300 \+- 0\.100" "$scratch/ens.log"' ||
  cat "$scratch/ens.log"
# b: seed 1 only (seed 2 has none, seed 3 did not equilibrate and is named)
check "case b: K 1, the unequilibrated seed named" \
  'grep -Eq "^ +b +1 +0\.5000 +2\.000 +2\.500 +s3$" "$scratch/ens.log"' || cat "$scratch/ens.log"

check_exit "the committed table II" 0 "$scratch/t2.log" $py "$tool" \
  "$GRANPACK_SOURCE_DIR/docs/data/2d/table2" 0.13-0.15-norr 0.36-0.5-rr --ensemble "$scratch/none"
check "table II, 0.13-0.15-norr: K 1, Phi 0.8264 (docs/reproduction-2d.md)" \
  'grep -Eq "^ +0\.13-0\.15-norr +1 +0\.8264 +3\.100" "$scratch/t2.log"' || cat "$scratch/t2.log"

# --against: the committed table II at K = 3 beside [GRC] (the table of docs/reproduction-2d.md).
t2q="$GRANPACK_SOURCE_DIR/docs/data/2d/table2_quench"
check_exit "--against II" 0 "$scratch/against.log" $py "$tool" "$t2q/seed1" 0.36-0.5-norr \
  0.13-0.5-norr --ensemble "$t2q/seed2" "$t2q/seed3" --against II
# 0.36-0.5-norr: 0.8046 +- 0.00045 (K = 3) against 0.811 +- 0.001: -0.79 %, -6.2 combined SE
check "0.36-0.5-norr: Phi -0.8 % (-6.2), z -1.0 % (-1.2)" \
  'grep -Fq "| 0.36 | 0.5 | no | 3 | 0.8046 ± 0.0005 | 0.811 ± 0.001 | −0.8 % (−6.2) | 2.623 ± 0.020 | 2.65 ± 0.02 | −1.0 % (−1.2) |" "$scratch/against.log"' ||
  cat "$scratch/against.log"
check "the count within 2: Phi 1 of 2, z 2 of 2" \
  'grep -Fq "within 2 combined standard errors: Φ 1 of 2, z 2 of 2" "$scratch/against.log"' ||
  cat "$scratch/against.log"
# A cell grc_paper.SUSPECT doubts (table III, Phi_I = 0.13 with RR: z repeats another row) is
# marked, explained and counted apart; a sound cell beside it is not marked.
t3="$GRANPACK_SOURCE_DIR/docs/data/2d/table3"
check_exit "--against III with a doubted cell" 0 "$scratch/suspect.log" $py "$tool" "$t3" \
  0.13-0.15-rr 0.36-0.5-norr --against III
check "the doubted z is marked, the sound one not" \
  'grep -Fq "| 3.189 ± 0.008 ‡ |" "$scratch/suspect.log" && grep -Fq "| 3.103 ± 0.006 |" "$scratch/suspect.log"' ||
  cat "$scratch/suspect.log"
check "the counts with and without the doubted cell, and the reason" \
  'grep -Fq "without the cells marked ‡: Φ" "$scratch/suspect.log" && grep -Fq "z 0 of 1" "$scratch/suspect.log" && grep -q "^‡ .*repeats row 0.5244 without RR" "$scratch/suspect.log"' ||
  cat "$scratch/suspect.log"
# K = 1 (synthetic seed 2 alone of case a is unknown to [GRC]): the case name is refused.
check_exit "--against with a case [GRC] do not have" 2 "$scratch/unknown.log" $py "$tool" \
  "$scratch/s2" a --against III
check "the refusal names the case" 'grep -q "no \[GRC\] value for case(s) a" "$scratch/unknown.log"' ||
  cat "$scratch/unknown.log"

checks_done "case_table"
