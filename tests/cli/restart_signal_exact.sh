#!/usr/bin/env bash
# ctest: RANKS 1 2   (one ctest entry per rank count: GRANPACK_TEST_RANKS)
# A checkpoint taken because of a stop signal, at any step, continues to the same bits as the
# run that never stopped (issue 31; docs/long-jobs.md, "Bit-for-bit continuation").
#  1. A short deck (random gas -> compress -> three pressure steps) runs uninterrupted, with no
#     checkpoint inside a stage, on 1 and on 2 ranks.
#  2. The same deck is stopped by SIGUSR1 three times, at steps drawn at random (the seed is
#     printed, so a failure can be replayed with GRANPACK_TEST_SEED), and restarted after
#     each stop. The ranks are held at the drawn step until the signal comes
#     (GRANPACK_FAULT=hold:N), so the signal lands where the draw says, on any machine load.
#  3. final.h5 of the chain equals the uninterrupted one bit for bit (tests/support/
#     same_state.py) and report.json has the same stage values.
# Load balancing is on, with a threshold (1.001) that any difference between the ranks' grain
# counts exceeds: on 2 ranks the cut plane moves at most rebuilds (checked), and the chain must
# still continue bit for bit (the checkpoint stores the cuts; every move is a function of the
# positions, never of a clock).
set -u
: "${GRANPACK_EXE:?}" "${GRANPACK_SOURCE_DIR:?}"
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
. "$GRANPACK_SOURCE_DIR/tests/support/restart_chain.sh"
restart_scratch   # $scratch, $pid, stop_run, and the EXIT trap
deck=$scratch/restart.toml
short_deck "$deck"
printf '\n[numerics]\nload_balance = true\nload_balance_threshold = 1.001\n' >> "$deck"
run_options=(--checkpoint-every-seconds 0)

seed=${GRANPACK_TEST_SEED:-$(( $(date +%s) % 100000 ))}
echo "random stop steps drawn with GRANPACK_TEST_SEED=$seed"

# chain NP: the uninterrupted run, then the chain of stops at three drawn steps and restarts.
chain() {
  np=$1 whole=$scratch/whole$1 out=$scratch/chain$1
  check_exit "$np rank(s): uninterrupted run" 0 "$whole.txt" run_deck "$whole" || return
  if [ "$np" -gt 1 ]; then
    local moved
    moved=$(sed -n 's/^  load balance: cut planes moved at \([0-9]*\) rebuilds.*/\1/p' "$whole/log.txt" | awk '{ n += $1 } END { print n + 0 }')
    check "$np rank(s): the load balancer moved the cut planes (at $moved rebuilds)" '[ "${moved:-0}" -gt 0 ]' || return
  fi
  # Each stop is drawn after the previous checkpoint and 1050 steps before the end at the
  # latest: its checkpoint waits up to 1000 steps for a neighbour-list rebuild, and a stop
  # with no rebuild left before the end lets the run finish (exit 0, final.h5), as it should.
  local from last s c k restart=()
  from=$(sed -n 's/^  done: phi .*, steps \([0-9]*\),.*/\1/p' "$whole/log.txt" | head -n 1)
  last=$(( $(final_step "$whole/final.h5") - 1050 ))
  echo "$np rank(s): $((last + 1050)) steps; the random stage ends at step $from"
  for k in 1 2 3; do
    # A checkpoint late in the run leaves no room for a further stop (rare): fewer stops.
    [ "$from" -lt "$last" ] || { echo "$np rank(s): no room for stop $k after step $from"; break; }
    s=$(/usr/bin/python3 -c "import random; r = random.Random($seed * 10 + $np * 3 + $k)
lo = $from + 1; hi = min($last, lo + max(1, ($last - $from) // (4 - $k)))
print(r.randrange(lo, hi + 1))")
    : > "$scratch/chain.txt"
    GRANPACK_FAULT=hold:$s start_leg "${restart[@]}"
    wait_until 3000 0.1 "[ \$(grep -c 'holds at step $s until a stop signal' '$scratch/chain.txt') -ge $np ]"
    kill -USR1 $pid
    wait $pid; code=$?; pid=
    # The checkpoint waits for the next neighbour-list rebuild (docs/long-jobs.md), at most
    # 1000 steps.
    c=$(final_step "$out/checkpoint.h5")
    check "$np rank(s): SIGUSR1 at step $s: exit $code (expected 75), checkpoint at step $c (expected $s to $((s + 1000)))" \
      '[ $code -eq 75 ] && [ "$c" -ge "$s" ] && [ "$c" -le $((s + 1000)) ]' || { tail "$scratch/chain.txt"; return; }
    restart=(--restart "$out/checkpoint.h5") from=$c
  done
  check_exit "$np rank(s): last restart" 0 "$scratch/last.txt" run_deck "$out" "${restart[@]}" || return
  check "$np rank(s): the chain ends as the uninterrupted run (final.h5 bit for bit, report.json)" \
    'same_run "$whole" "$out" "$np"'
}
over_ranks
checks_done "restart signal exact"
