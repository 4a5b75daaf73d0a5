#!/usr/bin/env bash
# Checkpoint/restart on the same rank count is exact, and checkpoints survive kill -9.
#  1. Run a short deck (random gas -> compress -> two pressure steps) uninterrupted on 2
#     ranks with a checkpoint every 150 steps.
#  2. Run it again, but kill -9 every rank at random instants (seeded), many times: after each
#     kill the newest checkpoint.h5 must be readable (`granpack info`), and the run goes on
#     with --restart from it (or from scratch if no checkpoint was written yet).
#  3. The final.h5 of the killed-and-restarted chain equals the uninterrupted one bit for bit
#     (tests/support/same_state.py; particles sorted by id, contacts by key).
# Kills that landed while a checkpoint was being written are counted (the temp file was
# there): the previous checkpoint must still be the readable one.
set -u
: "${GRANPACK_EXE:?}" "${GRANPACK_SOURCE_DIR:?}"
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
. "$GRANPACK_SOURCE_DIR/tests/support/restart_chain.sh"
cli_scratch 'pkill -9 -f -- "$scratch/" 2>/dev/null'   # on exit, also kill -9 this test's ranks
RANDOM=2026
deck=$scratch/restart.toml
sed -e 's/^log_every = .*/log_every = 500/' "$GRANPACK_SOURCE_DIR/jobs/decks/ci/gas_small.toml" > "$deck"
sed -i 's/^inertia_max = 1.0e-2$/inertia_max = 1.0e-2\nmax_steps = 15000/' "$deck"
cat >> "$deck" <<'TOML'

[[stage]]
name = "qs"
kind = "pressure_steps"
factor = 1.5
count = 3
inertia_max = 1.0e-2
max_steps = 3000
TOML
# run_deck and start_leg (tests/support/restart_chain.sh) put "-o OUT " on the command line,
# by which pkill finds the run's mpiexec and ranks.
np=2
run_options=(--checkpoint-every-steps 150 --checkpoint-every-seconds 0)

t0=$(now)
check_exit "the uninterrupted run" 0 "$scratch/whole.txt" run_deck "$scratch/whole" || checks_stop "restart kill"
# Kill delays scale with the machine's speed: 10 to 25 % of the uninterrupted wall time.
wall=$(elapsed $t0)

out=$scratch/chain
kills=0 during_write=0 restarts=0 fresh=0
# leg: a leg in the background, from the newest checkpoint if there is one.
leg() {
  if [ -f "$out/checkpoint.h5" ]; then
    start_leg --restart "$out/checkpoint.h5"
    restarts=$((restarts + 1))
  else
    start_leg
    fresh=$((fresh + 1))
  fi
}
# After a kill: the newest checkpoint must be a complete, readable file.
after_kill() {
  kills=$((kills + 1))
  wait $pid 2>/dev/null
  check "after kill $kills the checkpoint is readable (or none was written yet)" \
    '! [ -f "$out/checkpoint.h5" ] || "$GRANPACK_EXE" info "$out/checkpoint.h5" > "$scratch/info.txt" 2>&1' \
    || checks_stop "restart kill" "$scratch/info.txt"
}
# Phase 1: kills at random instants. Five: their delays (seed 2026) add up to 0.89 of the
# uninterrupted wall time, so the chain cannot finish here and phase 2 always runs (with eight,
# whose delays add up to 1.4, a loaded machine let the chain finish in phase 1 and the test
# failed its own "did not test" check).
for attempt in $(seq 1 5); do
  leg
  sleep "$(awk -v r=$RANDOM -v w=$wall 'BEGIN { printf "%.2f", w * (0.10 + 0.15 * r / 32767) }')"
  if ! kill -0 $pid 2>/dev/null; then wait $pid; break; fi   # finished before the kill
  pkill -9 -f -- "-o $out " 2>/dev/null
  [ -f "$out/checkpoint.h5.tmp" ] && during_write=$((during_write + 1))
  after_kill
done
# Phase 2: kills aimed at the write itself: as soon as the temporary file appears.
for attempt in $(seq 1 4); do
  [ -f "$out/final.h5" ] && break
  leg
  for _ in $(seq 1 500); do
    if [ -f "$out/checkpoint.h5.tmp" ]; then
      pkill -9 -f -- "-o $out " 2>/dev/null; during_write=$((during_write + 1)); break
    fi
    kill -0 $pid 2>/dev/null || break
    sleep 0.01
  done
  if kill -0 $pid 2>/dev/null; then pkill -9 -f -- "-o $out " 2>/dev/null; fi
  after_kill
done
if [ ! -f "$out/final.h5" ]; then
  restarts=$((restarts + 1))
  check_exit "the last restart" 0 "$scratch/last.txt" run_deck "$out" --restart "$out/checkpoint.h5" \
    || checks_stop "restart kill"
fi
echo "uninterrupted run: $wall s; kill -9: $kills kills ($during_write while a checkpoint was being written), $restarts restarts, $fresh fresh starts"
check "the killed-and-restarted chain ends as the uninterrupted run (final.h5 bit for bit)" \
  'same_state "$scratch/whole/final.h5" "$out/final.h5"' \
  || tail -30 "$scratch/chain.txt"
# The restarted run's report has every stage once, in order.
check_python "report.json of the restarted chain: every stage once, in order, the same steps and phi" \
  "$scratch/report_py.txt" "$scratch/whole/report.json" "$out/report.json" <<'PY'
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:3])
na, nb = [s["name"] for s in a["stages"]], [s["name"] for s in b["stages"]]
assert na == nb, (na, nb)
for x, y in zip(a["stages"], b["stages"]):
    assert x["steps"] == y["steps"] and x["phi"] == y["phi"], (x["name"], x["steps"], y["steps"])
PY
check "the test tested: $kills kills (at least 6), $during_write during a write (at least 2)" \
  '! { [ $kills -lt 6 ] || [ $during_write -lt 2 ]; }'
checks_done "restart kill"
