#!/usr/bin/env bash
# [numerics] halo end to end (docs/deck.md, docs/performance.md "The shared-memory halo"): two
# CI decks, 3D (gas_small: a random gas compressed to 10 kPa, some 50 000 steps with many
# rebuilds of the ghost lists) and 2D (hex_linear), each run on 2 ranks through the
# shared-memory window (the deck as it is: the default) and through messages (the deck with
# halo = "messages" added). The halo's transport must change nothing: the final states are the
# same bit for bit (same_state.py) and so are the reports' stage values (same_report.py); the
# log does not claim a fallback to messages (both ranks are on this node).
set -u
: "${GRANPACK_EXE:?}" "${GRANPACK_SOURCE_DIR:?}"
. "$GRANPACK_SOURCE_DIR/tests/support/cli_checks.sh"
cli_scratch

for deck in gas_small hex_linear; do
  src="$GRANPACK_SOURCE_DIR/jobs/decks/ci/$deck.toml"
  check "$deck has no [numerics] table of its own" '! grep -q "^\[numerics\]" "$src"'
  { cat "$src"; printf '\n[numerics]\nhalo = "messages"\n'; } > "$scratch/$deck.toml"
  check_exit "$deck through messages" 0 "$scratch/$deck.m.txt" \
    granpack_on 2 run "$scratch/$deck.toml" -o "$scratch/$deck.m" -q || continue
  check_exit "$deck through shared memory (the default)" 0 "$scratch/$deck.s.txt" \
    granpack_on 2 run "$src" -o "$scratch/$deck.s" -q || continue
  check "$deck: the same final state bit for bit" \
    'same_state "$scratch/$deck.m/final.h5" "$scratch/$deck.s/final.h5" > "$scratch/$deck.same.txt"' \
    || cat "$scratch/$deck.same.txt"
  check "$deck: the same stage values" \
    'same_report "$scratch/$deck.m/report.json" "$scratch/$deck.s/report.json" > "$scratch/$deck.rep.txt"' \
    || cat "$scratch/$deck.rep.txt"
  check "$deck: no fallback to messages on one node" '! grep -q "several nodes" "$scratch/$deck.s/log.txt"'
done
checks_done halo_shared_memory
