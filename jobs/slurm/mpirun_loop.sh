#!/usr/bin/env bash
# Without a batch system: run a deck under mpirun and continue it from its checkpoint until
# it is done, e.g. on a workstation that may be rebooted or when limiting each leg to a
# wall time (docs/long-jobs.md).
#
#   bash jobs/slurm/mpirun_loop.sh DECK OUT [NP] [LEG_SECONDS]
#
# LEG_SECONDS (default: unlimited) stops each leg with SIGUSR1 after that many seconds, to
# exercise the chain or to share the machine; granpack exits 75 ("checkpointed, resubmit")
# and the loop continues from OUT/checkpoint.h5. Ctrl-C (or SIGTERM to this script: a
# script started in the background with & ignores SIGINT) stops the loop after a checkpoint.
set -u
deck=${1:?usage: mpirun_loop.sh DECK OUT [NP] [LEG_SECONDS]}
out=${2:?usage: mpirun_loop.sh DECK OUT [NP] [LEG_SECONDS]}
np=${3:-2}
leg=${4:-0}
granpack=${GRANPACK:-$(dirname "$0")/../../build/granpack}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
stop=0
trap 'stop=1; [ -n "${pid:-}" ] && kill -USR1 $pid' INT TERM
while :; do
  args=(run "$deck" -o "$out" --quiet)
  [ -f "$out/checkpoint.h5" ] && [ ! -f "$out/final.h5" ] && args+=(--restart "$out/checkpoint.h5")
  mpirun -np "$np" "$granpack" "${args[@]}" &
  pid=$!
  if [ "$leg" -gt 0 ]; then (sleep "$leg"; kill -USR1 $pid 2>/dev/null) & timer=$!; fi
  wait $pid; code=$?
  while kill -0 $pid 2>/dev/null; do wait $pid; code=$?; done
  [ "$leg" -gt 0 ] && kill $timer 2>/dev/null
  case $code in
    0) echo "done: $out/final.h5"; exit 0 ;;
    75) [ $stop -eq 1 ] && { echo "stopped; continue later with the same command"; exit 75; }
        echo "checkpointed; continuing" ;;
    *) echo "granpack failed (exit $code); see $out/log.txt"; exit $code ;;
  esac
done
