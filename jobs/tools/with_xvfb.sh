#!/usr/bin/env bash
# Runs a command with DISPLAY set to a private virtual X server (Xvfb), for pvbatch: Debian's
# ParaView renders through X only. pvbatch 5.11 fails now and then (1 run in 4 to 6 here, with
# `xvfb-run -a` as with a server up for seconds) with "bad X server connection" although the
# server is alive: such a run is repeated, up to 5 times, on the same server. The server is
# stopped afterwards.
#   bash jobs/tools/with_xvfb.sh pvbatch jobs/tools/pv_packing.py FILE.xdmf --png out.png
# Exit code: the command's; 2 if Xvfb is missing, 75 if no server came up in 60 s.
set -u
command -v Xvfb > /dev/null || { echo "with_xvfb.sh: Xvfb not found (apt-get install xvfb)" >&2; exit 2; }
display=
for n in $(seq 90 189); do
  # A free number: no lock file; mkdir of our own lock makes the choice atomic between callers.
  if [ ! -e "/tmp/.X$n-lock" ] && mkdir "/tmp/.with_xvfb_$n" 2> /dev/null; then display=$n; break; fi
done
[ -n "$display" ] || { echo "with_xvfb.sh: no free X display number" >&2; exit 75; }
Xvfb ":$display" -screen 0 1280x1024x24 -nolisten tcp > /dev/null 2>&1 &
server=$!
cleanup() { kill "$server" 2> /dev/null; wait "$server" 2> /dev/null; rmdir "/tmp/.with_xvfb_$display"; }
trap cleanup EXIT
for _ in $(seq 1 600); do
  [ -S "/tmp/.X11-unix/X$display" ] && break
  kill -0 "$server" 2> /dev/null || { echo "with_xvfb.sh: Xvfb :$display did not start" >&2; exit 75; }
  sleep 0.1
done
[ -S "/tmp/.X11-unix/X$display" ] || { echo "with_xvfb.sh: Xvfb :$display did not come up in 60 s" >&2; exit 75; }
sleep 0.5 # the socket exists a moment before the server accepts clients
log=$(mktemp)
trap 'cleanup; rm -f "$log"' EXIT
for try in 1 2 3 4 5; do
  DISPLAY=":$display" "$@" > "$log" 2>&1
  rc=$?
  [ $rc -ne 0 ] && grep -q "bad X server connection" "$log" || break
  echo "with_xvfb.sh: try $try: bad X server connection; again" >&2
done
cat "$log"
exit $rc
