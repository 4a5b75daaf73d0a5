#!/usr/bin/env bash
# jobs/tools/ar_tables.py (docs/ar-tables.md) on the small ensemble fixture
# tests/data/ensemble/C_ensemble.json (states A and C): table IV shows C's Phi as mean ± sd of
# the fixture's five values, [AR]'s 0.635 ± 0.002 and the deviation computed here
# independently; the check against the tolerances declared in docs/reproduction.md passes on
# the fixture and fails (exit 1, naming the cell) once C's z* is shifted by 5 sd; a missing
# ensemble file, a missing key and a malformed tolerance line give exit 2 with a message
# naming the file (and line or key); fig. 4 is written from A's P(f).
# ctest: PROCESSORS 1   (one process at a time: ctest -j2 runs another test beside it)
set -u
: "${GRANPACK_SOURCE_DIR:?}"
tool="$GRANPACK_SOURCE_DIR/jobs/tools/ar_tables.py"
fixture="$GRANPACK_SOURCE_DIR/tests/data/ensemble/C_ensemble.json"
tolerances="$GRANPACK_SOURCE_DIR/docs/reproduction.md"
py=/usr/bin/python3
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
cli_scratch
export MPLCONFIGDIR="$scratch/mpl"
states=(--state "A=$fixture:A" --state "C=$fixture:C")

# (1) Table IV: the C rows, and the expected cells computed from the fixture's values.
"$py" "$tool" --tables IV "${states[@]}" > "$scratch/iv.md" 2> "$scratch/iv.err"
rc=$?; check "table IV: exit 0 ($(tail -2 "$scratch/iv.err"))" "[ $rc -eq 0 ]"
"$py" - "$fixture" > "$scratch/expected.txt" <<'PY'
import json, math, statistics, sys
v = json.load(open(sys.argv[1]))["analysis"]["C"]["/phi"]["values"]
m, s = statistics.mean(v), statistics.stdev(v)
dev = (m - 0.635) / math.sqrt(s * s / len(v) + 0.002 ** 2 / 5)  # [AR] table IV, C: 0.635 ± 0.002
print(f"{m:.4f} ± {s:.4f}")
print(f"{dev:+.2f}")
PY
ours=$(sed -n 1p "$scratch/expected.txt"); dev=$(sed -n 2p "$scratch/expected.txt")
check "table IV: C ours row has Phi = $ours ($(grep '^| C | ours' "$scratch/iv.md"))" \
  "grep -qF '| C | ours (K=5) | $ours |' '$scratch/iv.md'"
check "table IV: C [AR] row has 0.635 ± 0.002 and 4.56 ± 0.03" \
  "grep -qF '| C | [AR] | 0.635 ± 0.002 | 4.56 ± 0.03 |' '$scratch/iv.md'"
check "table IV: C dev row has $dev ($(grep '^| C | dev' "$scratch/iv.md"))" \
  "grep -qF '| C | dev | $dev |' '$scratch/iv.md'"
check "table IV: states not given are printed as 'not run'" \
  "grep -qF '| Z | ours | not run |' '$scratch/iv.md'"
check "table IV: A' row from the text (0.6422 ± 0.0002), n. d. where [AR] give nothing" \
  "grep -qF \"| A' | [AR] | 0.6422 ± 0.0002 | n. d. |\" '$scratch/iv.md'"
check "no traceback" "! grep -q Traceback '$scratch/iv.err'"

# (2) The CI check: within tolerance, then C's z* shifted by 5 sd.
check_exit "check on the fixture" 0 "$scratch/ok.txt" "$py" "$tool" --check "$tolerances" "${states[@]}"
check "check on the fixture: 15 cells of A and C checked" \
  "grep -q '15 cells checked' '$scratch/ok.txt'"
"$py" - "$fixture" "$scratch/shifted.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
s = d["analysis"]["C"]["/z_star"]
shift = 5 * s["sd"]
s["values"] = [v + shift for v in s["values"]]
s["mean"] += shift
json.dump(d, open(sys.argv[2], "w"))
PY
check_exit "check with C z* + 5 sd" 1 "$scratch/bad.txt" \
  "$py" "$tool" --check "$tolerances" --state "A=$scratch/shifted.json:A" --state "C=$scratch/shifted.json:C"
check "check with C z* + 5 sd: names the cell ($(grep FAIL "$scratch/bad.txt"))" \
  "grep -q '^FAIL table IV C z\*: ours .* \[AR\] 4.56 ± 0.03, dev +[0-9.]*, allowed |dev| <= [0-9.]*' '$scratch/bad.txt'"
check "check with C z* + 5 sd: only that cell fails" "[ \$(grep -c '^FAIL' '$scratch/bad.txt') -eq 1 ]"

# (3) Bad input: exit 2 with a message naming the file, key or line.
check_refused "missing ensemble file, named" 2 "nowhere/ensemble.json: no such file" "$scratch/miss.txt" \
  "$py" "$tool" --check "$tolerances" --state "C=$scratch/nowhere/ensemble.json:C"
check_exit "missing ensemble file when printing" 2 "$scratch/miss_tables.txt" \
  "$py" "$tool" --tables IV --state "C=$scratch/nowhere/ensemble.json:C"
"$py" - "$fixture" "$scratch/nokey.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
del d["analysis"]["C"]["/Z_2"]
json.dump(d, open(sys.argv[2], "w"))
PY
check_refused "missing key, naming file and key" 2 "nokey.json: analysis 'C' has no value for key '/Z_2'" \
  "$scratch/nokey.txt" "$py" "$tool" --check "$tolerances" --state "C=$scratch/nokey.json:C"
sed 's/^| C | Φ | 2 |/| C | Φ | two |/' "$tolerances" > "$scratch/tol.md"
line=$(grep -n '^| C | Φ | two |' "$scratch/tol.md" | cut -d: -f1)
check_refused "malformed tolerance, naming file and line $line" 2 "tol.md line $line: tolerance 'two' is not allowed" \
  "$scratch/tol.txt" "$py" "$tool" --check "$scratch/tol.md" "${states[@]}"
sed 's/^| C | Φ | 2 |/| C | M3 | 2 |/' "$tolerances" > "$scratch/tol2.md"
check_refused "unknown quantity in the tolerances, listing the allowed ones" 2 \
  "no \[AR\] value for quantity 'M3'; allowed for C: " "$scratch/tol2.txt" "$py" "$tool" --check "$scratch/tol2.md" "${states[@]}"

# Fig. 4 from A's P(f); the figures that have no input are skipped with a note.
"$py" "$tool" --tables IV "${states[@]}" --figures "$scratch/figs" > /dev/null 2> "$scratch/figs.txt"
rc=$?; check "figures: exit 0 ($(tail -2 "$scratch/figs.txt"))" "[ $rc -eq 0 ]"
check "figures: fig4.png is a non-empty PNG" "is_png '$scratch/figs/fig4.png'"
check "figures: fig1.png is a non-empty PNG" "is_png '$scratch/figs/fig1.png'"
check "figures: fig. 2 skipped with a note" "grep -q 'skipped: fig. 2' '$scratch/figs.txt'"

checks_done ar_tables
