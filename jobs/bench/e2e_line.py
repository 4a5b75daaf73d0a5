#!/usr/bin/python3
"""run_bench.sh's line for an end-to-end run (E2E=deck): minutes on 2 ranks, steps, the last
stage's phi and z* from OUT/report.json.

  /usr/bin/python3 jobs/bench/e2e_line.py DECK T0 T1 OUT
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
import granpack_io as gio  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(prog="e2e_line.py", description=__doc__.split("\n\n")[0])
    ap.add_argument("deck", help="the deck's name under jobs/decks (printed)")
    ap.add_argument("t0", type=float, help="start, seconds since the epoch")
    ap.add_argument("t1", type=float, help="end, seconds since the epoch")
    ap.add_argument("out", help="the run's output directory")
    a = ap.parse_args(argv)
    try:
        stages = gio.read_report(os.path.join(a.out, "report.json")).stages
    except gio.GranpackFileError as e:
        gio.fail("e2e_line.py", e)
    last = [s for s in stages if s.get("steps", 0) > 0][-1]
    steps = sum(s.get("steps", 0) for s in stages)
    print(f"[bench] end to end {a.deck}: {(a.t1 - a.t0) / 60:.2f} min on 2 ranks, {steps} steps, "
          f"phi {last.get('phi', float('nan')):.5f}, z* {last.get('z_star', float('nan'))}")


if __name__ == "__main__":
    main()
