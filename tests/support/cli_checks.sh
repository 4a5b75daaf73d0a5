# Shared by the tests/cli scripts that tally named checks (sourced, not run).
#
# cli_scratch [CLEANUP]: makes $scratch, removed when the script exits (after running the shell
#   command CLEANUP, if given: e.g. killing runs of the test still in progress).
# check NAME CONDITION: evaluates CONDITION (a shell expression, in single quotes when it
#   should see the values at check time); counts a pass, or prints "FAIL: NAME" and counts a
#   failure. Every check runs, so one failure does not hide the others. Returns non-zero on a
#   failure, so that `check ... || cat LOG` shows the evidence.
# checks_from LABEL FILE RC: the checks of a Python block that wrote one line per check to
#   FILE, "ok: NAME" (a pass) or "FAIL: NAME" (printed, a failure), counted as check does;
#   other lines (numbers for the log, a traceback) are printed. RC is the block's exit status:
#   one more check, "LABEL ran to the end", fails when it is not 0 (the block stopped early).
#   The block writes its lines with check() of tests/support/checks.py (`from checks import
#   check`: this file puts tests/support on PYTHONPATH).
# checks_stop LABEL [LOG]: after a failed check that the following ones cannot do without (a
#   run whose files they read): prints the end of LOG, the tally marked "(stopped early)", and
#   ends the script with exit code 1.
# checks_done LABEL [NOTE]: prints "LABEL: P passed, F failed [NOTE]" and returns non-zero if
#   any check failed; the script ends with it, so it is the test's exit status.
#
# Running things and checking how they end:
# granpack_on NP ARGS...: `granpack ARGS` on NP MPI ranks (mpiexec; stdin from /dev/null).
# check_exit NAME CODE LOG CMD...: runs CMD (stdin from /dev/null), its output to LOG, its exit
#   status in $rc; one check "NAME: exit $rc (expected CODE)" (CODE '!0': any non-zero status),
#   the end of LOG printed on a failure. Returns non-zero on a failure (`|| checks_stop ...`).
# check_refused NAME CODE PATTERN LOG CMD...: check_exit, and one more check that LOG matches
#   PATTERN (grep -E) and holds no Python traceback, LOG printed on a failure.
# check_python NAME LOG [ARGS...]: runs the Python block on stdin (a here-document) with ARGS,
#   its output to LOG; one check NAME that it exits 0 (its asserts held), LOG printed otherwise.
# same_state A.h5 B.h5, same_report A.json B.json: tests/support/same_state.py, same_report.py
#   (exit 0: the same state bit for bit; the same stage values, wall times aside).
# is_png FILE: FILE is a non-empty PNG. big_png FILE MIN_BYTES: a PNG of at least 300 x 300
#   pixels and MIN_BYTES.
# now, elapsed T0: a time stamp, and the seconds since the stamp T0 (two decimals).
# wait_until TRIES INTERVAL CONDITION: evaluates CONDITION up to TRIES times, INTERVAL seconds
#   apart; returns 0 as soon as it holds, 1 when it never did or when the run whose pid is
#   $pid (if set) has ended first.
cli_scratch() {
  scratch=$(mktemp -d)
  trap "${1:+$1; }"'rm -rf "$scratch"' EXIT
}
# The Python blocks import tests/support/*.py; no bytecode is written into the source tree.
export PYTHONPATH="$GRANPACK_SOURCE_DIR/tests/support${PYTHONPATH:+:$PYTHONPATH}"
export PYTHONDONTWRITEBYTECODE=1
fail=0; pass=0
check() {
  if eval "$2"; then pass=$((pass+1)); else echo "FAIL: $1"; fail=$((fail+1)); return 1; fi
}
checks_from() {
  local line
  while IFS= read -r line || [ -n "$line" ]; do
    case $line in
      "ok: "*) pass=$((pass+1)) ;;
      "FAIL: "*) echo "$line"; fail=$((fail+1)) ;;
      *) printf '%s\n' "$line" ;;
    esac
  done < "$2"
  check "$1 ran to the end (exit $3)" "[ $3 -eq 0 ]"
}
checks_stop() {
  [ -n "${2:-}" ] && tail -20 "$2"
  checks_done "$1" "(stopped early)"
  exit 1
}
checks_done() {
  echo "$1: $pass passed, $fail failed${2:+ $2}"
  [ "$fail" -eq 0 ]
}

granpack_on() { local np=$1; shift; mpiexec -n "$np" "$GRANPACK_EXE" "$@" < /dev/null; }
check_exit() {
  local name=$1 code=$2 log=$3; shift 3
  "$@" < /dev/null > "$log" 2>&1
  rc=$?
  check_rc "$name" "$code" "$log"
}
# start_bg LOG CMD...: CMD in the background (stdin from /dev/null, output to LOG), its pid in
# $bg_pid; check_bg NAME CODE LOG PID waits for it and checks its exit code as check_exit does.
# Two 1-rank runs side by side fill both processors of a test that holds two.
start_bg() { local log=$1; shift; "$@" < /dev/null > "$log" 2>&1 & bg_pid=$!; }
check_bg() {
  wait "$4"
  rc=$?
  check_rc "$1" "$2" "$3"
}
# check_rc NAME CODE LOG: $rc against CODE ('!0': any failure), the log's tail on a mismatch.
check_rc() {
  local name=$1 code=$2 log=$3
  if [ "$code" = '!0' ]; then
    check "$name: exit $rc (expected non-zero)" "[ $rc -ne 0 ]" || { tail -20 "$log"; return 1; }
  else
    check "$name: exit $rc (expected $code)" "[ $rc -eq $code ]" || { tail -20 "$log"; return 1; }
  fi
}
check_refused() {
  local name=$1 code=$2 pattern=$3 log=$4; shift 4
  check_exit "$name" "$code" "$log" "$@"
  local status=$?
  check "$name: the message matches /$pattern/" \
    'grep -Eq -- "$pattern" "$log" && ! grep -q Traceback "$log"' || { head -c 2000 "$log"; echo; return 1; }
  return $status
}
check_python() {
  local name=$1 log=$2; shift 2
  /usr/bin/python3 - "$@" > "$log" 2>&1
  local status=$?
  check "$name" "[ $status -eq 0 ]" || { cat "$log"; return 1; }
}
same_state() { /usr/bin/python3 "$GRANPACK_SOURCE_DIR/tests/support/same_state.py" "$1" "$2"; }
same_report() { /usr/bin/python3 "$GRANPACK_SOURCE_DIR/tests/support/same_report.py" "$1" "$2"; }
is_png() { [ -s "$1" ] && [ "$(head -c 8 "$1" | od -An -tx1 | tr -d ' \n')" = "89504e470d0a1a0a" ]; }
big_png() {
  local wh
  wh=$(/usr/bin/python3 -c 'import struct, sys
b = open(sys.argv[1], "rb").read(24)
if b[:8] == b"\x89PNG\r\n\x1a\n": print("%dx%d" % struct.unpack(">II", b[16:24]))' "$1" 2>/dev/null)
  [ -n "$wh" ] && [ "${wh%x*}" -ge 300 ] && [ "${wh#*x}" -ge 300 ] && [ "$(stat -c %s "$1")" -ge "$2" ]
}
now() { date +%s.%N; }
elapsed() { awk -v a="$1" -v b="$(date +%s.%N)" 'BEGIN { printf "%.2f", b - a }'; }
wait_until() {
  local tries=$1 interval=$2 condition=$3 _
  for _ in $(seq 1 "$tries"); do
    eval "$condition" && return 0
    [ -n "${pid:-}" ] && ! kill -0 "$pid" 2>/dev/null && return 1
    sleep "$interval"
  done
  return 1
}
# The ParaView tests: skipped (exit 77) where pvbatch or Xvfb is absent; pvrun runs pvbatch on
# a private virtual X server (Debian's ParaView draws through X only: jobs/tools/with_xvfb.sh).
require_pvbatch() {
  local tool
  for tool in pvbatch Xvfb; do
    if ! command -v "$tool" > /dev/null; then
      echo "SKIPPED: $tool not found (apt-get install paraview python3-paraview xvfb; bash jobs/setup.sh test does)"
      exit 77
    fi
  done
}
pvrun() { bash "$GRANPACK_SOURCE_DIR/jobs/tools/with_xvfb.sh" pvbatch "$@"; }
# small_deck DIM N SEED: prints the [sample], [material] and [output] head of a tiny test deck
#   (grains of 1 mm, density 2500, friction 0.3, quiet log): in 2D linear springs of 1e3 N/m
#   with damping 0.5, soft enough for quick runs; in 3D Hertz glass-like grains softened to
#   E = 2.88e8 Pa with [AR]'s damping 0.98. The caller appends its own [output] keys and stages:
#   { small_deck 3 120 3; cat <<'TOML' ... TOML
#   } > "$deck"
small_deck() {
  printf '[sample]\ndimension = %s\nn = %s\ndiameter = 1.0e-3\nseed = %s\n' "$1" "$2" "$3"
  printf '[material]\ndensity = 2500.0\n'
  if [ "$1" = 2 ]; then
    printf 'normal_law = "linear"\nnormal_stiffness = 1.0e3\nfriction = 0.3\ndamping = 0.5\n'
  else
    printf 'normal_law = "hertz"\nyoung_modulus = 2.88e8\npoisson_ratio = 0.3\n'
    printf 'friction = 0.3\ndamping = 0.98\n'
  fi
  printf '[output]\nlog_every = 100000\n'
}
# run_killed NP DECK OUT STEP: `granpack run DECK -o OUT -q` on NP ranks, killed by itself at
#   step STEP (GRANPACK_FAULT=step:STEP, docs/long-jobs.md), its output in OUT.killed.txt; one
#   check that it died there. The caller restarts it from OUT/checkpoint.h5.
run_killed() {
  GRANPACK_FAULT=step:$4 granpack_on "$1" run "$2" -o "$3" -q > "$3.killed.txt" 2>&1
  local rc=$?
  check "the run killed at step $4 died (exit $rc)" \
    "[ $rc -ne 0 ] && grep -q 'killed itself' '$3.killed.txt'" || tail -5 "$3.killed.txt"
}
