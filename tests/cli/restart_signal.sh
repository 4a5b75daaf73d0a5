#!/usr/bin/env bash
# Stop signals and restart checks:
#  - SIGUSR1 to mpiexec (forwarded to the ranks, as a batch script does) and SIGTERM to the
#    ranks themselves (as srun/Slurm do): each stops the run with exit code 75 after writing
#    a checkpoint (at the next list rebuild). The ranks are held at a chosen step of the
#    compression (GRANPACK_FAULT=hold:N, docs/long-jobs.md) until the signal comes, so it lands
#    inside the stage on any machine and any load (a sleep before the signal did not: on a
#    fast idle machine the run had finished);
#  - the stopped 2-rank run continues on 1 rank and reaches the same equilibrium state
#    statistically (the rank count changes the order of floating-point sums, so not bitwise):
#    Phi within 0.01 and z* within 0.2 of the uninterrupted run, i.e. about 3 standard
#    deviations of the difference of two independent samples (this deck over seeds 1, 3, 4
#    and 2026: sd(Phi) = 0.0026, sd(z*) = 0.050); the continuation shares the history up to
#    the stop, so it usually lands much closer;
#  - a restart whose deck changed is refused (exit 2, naming what changed), unless only later
#    stages changed and --allow-deck-change is given; a configuration is not a checkpoint.
set -u
: "${GRANPACK_EXE:?}" "${GRANPACK_SOURCE_DIR:?}"
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
cli_scratch 'pkill -9 -f -- "$scratch/" 2>/dev/null'   # on exit, also kill -9 this test's ranks
deck=$scratch/gas.toml
# The CI gas deck as it is (the random stage relaxes for ~1800 steps, compress takes ~130000):
# held after step 3000, the run stops at the next neighbour-list rebuild, where its checkpoint
# is taken (docs/long-jobs.md), at most 1000 steps later.
hold=3000
cp "$GRANPACK_SOURCE_DIR/jobs/decks/ci/gas_small.toml" "$deck"
cat >> "$deck" <<'TOML'

[[stage]]
name = "out"
kind = "write"
file = "compressed.h5"
TOML

check_exit "uninterrupted run" 0 "$scratch/whole.txt" granpack_on 2 run "$deck" -o "$scratch/whole" -q \
  || checks_stop "restart signal"

# Waits until both ranks hold at step $hold (the line GRANPACK_FAULT=hold prints); 300 s at
# most, a guard against a hang, not a timing.
wait_holding() { wait_until 3000 0.1 "[ \$(grep -c 'holds at step $hold until a stop signal' '$1') -ge 2 ]"; }

# 1. SIGUSR1 to mpiexec.
GRANPACK_FAULT=hold:$hold mpiexec -n 2 "$GRANPACK_EXE" run "$deck" -o "$scratch/usr1" -q > "$scratch/usr1.txt" 2>&1 &
pid=$!
wait_holding "$scratch/usr1.txt"
# A second run into the same directory is refused (DIR/.lock) before it touches log.txt.
check_exit "second run into a busy directory refused" 2 "$scratch/second.txt" \
  granpack_on 1 run "$deck" -o "$scratch/usr1" -q
check "  with a message naming the directory, the first run's log intact" \
  'grep -q "another granpack run is writing into $scratch/usr1" "$scratch/second.txt" &&
   head -n 1 "$scratch/usr1/log.txt" | grep -q "^granpack "' || tail -3 "$scratch/second.txt"
kill -USR1 $pid
wait $pid; code=$?
c=$("$GRANPACK_EXE" info "$scratch/usr1/checkpoint.h5" 2>/dev/null | sed -n 's/^time: .*(step \([0-9]*\))$/\1/p')
check "SIGUSR1: exit $code (expected 75), 'stopped on request', a checkpoint at step ${c:-none} ($hold to $((hold + 1000)))" \
  '[ $code -eq 75 ] && grep -q "stopped on request" "$scratch/usr1.txt" && [ -n "$c" ] && [ "$c" -ge $hold ] &&
   [ "$c" -le $((hold + 1000)) ]' || tail -5 "$scratch/usr1.txt"
check "SIGUSR1: log.txt says why the run ended" \
  'tail -n 1 "$scratch/usr1/log.txt" | grep -q "^stopped (exit 75): stopped on request"' \
  || tail -2 "$scratch/usr1/log.txt"

# 2. SIGTERM to every rank.
GRANPACK_FAULT=hold:$hold mpiexec -n 2 "$GRANPACK_EXE" run "$deck" -o "$scratch/term" -q > "$scratch/term.txt" 2>&1 &
pid=$!
wait_holding "$scratch/term.txt"
# Only the ranks (mpiexec itself would end the job on SIGTERM, as it documents).
for p in $(pgrep -f -- "-o $scratch/term "); do
  [ "$(cat /proc/$p/comm 2>/dev/null)" = granpack ] && kill -TERM $p
done
wait $pid; code=$?
check "SIGTERM: exit $code (expected 75), a checkpoint" '[ $code -eq 75 ] && [ -f "$scratch/term/checkpoint.h5" ]' \
  || tail -5 "$scratch/term.txt"

# 3. Continue the SIGUSR1 run on 1 rank.
if check_exit "1-rank continuation" 0 "$scratch/continue.txt" \
     granpack_on 1 run "$deck" -o "$scratch/usr1" --restart "$scratch/usr1/checkpoint.h5" -q; then
  check_python "1-rank continuation: the same equilibrium as the uninterrupted run (phi, z*)" "$scratch/continue_py.txt" \
    "$scratch/whole/report.json" "$scratch/usr1/report.json" <<'PY'
import json, sys
a, b = (json.load(open(p))["stages"] for p in sys.argv[1:3])
assert [s["name"] for s in a] == [s["name"] for s in b]
x, y = a[1], b[1]
assert y["equilibrated"] is True, "not equilibrated"
assert abs(x["phi"] - y["phi"]) < 0.01, ("phi", x["phi"], y["phi"])
assert abs(x["z_star"] - y["z_star"]) < 0.2, ("z*", x["z_star"], y["z_star"])
print(f"1-rank continuation: phi {y['phi']:.4f} vs {x['phi']:.4f}, z* {y['z_star']:.3f} vs {x['z_star']:.3f}")
PY
  cat "$scratch/continue_py.txt"
fi

# 4. Refusals.
sed 's/^friction = 0.3/friction = 0.5/' "$deck" > "$scratch/changed.toml"
check_refused "changed material refused" 2 '\[material\]' "$scratch/changed.txt" \
  granpack_on 2 run "$scratch/changed.toml" -o "$scratch/term" --restart "$scratch/term/checkpoint.h5" -q
sed 's/^file = "compressed.h5"/file = "other.h5"/' "$deck" > "$scratch/later.toml"
check_refused "changed later stage refused without the flag, naming --allow-deck-change" 2 "allow-deck-change" \
  "$scratch/later_refused.txt" \
  granpack_on 2 run "$scratch/later.toml" -o "$scratch/term" --restart "$scratch/term/checkpoint.h5" -q
# Accepted with the flag: the run gets past the checks and restarts (then stopped, to save time).
mpiexec -n 2 "$GRANPACK_EXE" run "$scratch/later.toml" -o "$scratch/term" --restart "$scratch/term/checkpoint.h5" \
  --allow-deck-change -q > "$scratch/later.txt" 2>&1 &
pid=$!
wait_until 300 0.1 'grep -q "restart from" "$scratch/term/log.txt"'
kill -USR1 $pid 2>/dev/null
wait $pid; code=$?
check "changed later stage accepted with --allow-deck-change: exit $code (expected 75 or 0)" \
  '[ $code -eq 75 ] || [ $code -eq 0 ]' || tail -5 "$scratch/later.txt"
check_refused "a configuration refused as a checkpoint" 2 "not a checkpoint" "$scratch/x.txt" \
  granpack_on 2 run "$deck" -o "$scratch/x" --restart "$scratch/whole/final.h5" -q
check "a refused restart wrote nothing into its output directory" '[ ! -e "$scratch/x/log.txt" ]'

checks_done "restart signal"
