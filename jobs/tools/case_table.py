#!/usr/bin/python3
"""One line per case from BASE/<case>/report.json: the last `compress` stage's Phi, z, z_int
(every interaction, distant pairs included: [GRC]'s z with cohesion), z* and x0 ([AR]'s
rattler rule), steps and wall seconds. Used by the jobs/runs/ sweeps.

    /usr/bin/python3 jobs/tools/case_table.py BASE CASE...
"""
import json
import os
import sys


def fmt(v, width, prec):
    return f"{v:{width}.{prec}f}" if isinstance(v, (int, float)) else f"{'-':>{width}}"


def main(argv):
    if len(argv) < 2:
        sys.exit(__doc__)
    base, cases = argv[0], argv[1:]
    print(f"{'case':>22} {'Phi':>8} {'z':>6} {'z_int':>6} {'z*':>6} {'x0':>6} {'steps':>9} {'wall s':>8}")
    for c in cases:
        try:
            with open(os.path.join(base, c, "report.json")) as f:
                r = json.load(f)
        except OSError:
            print(f"{c:>22}  (no report.json)")
            continue
        s = [s for s in r["stages"] if s["kind"] == "compress"][-1]
        z_int = s.get("values", {}).get("z_interactions")
        print(f"{c:>22} {s['phi']:8.4f} {fmt(s.get('z'), 6, 3)} {fmt(z_int, 6, 3)} "
              f"{fmt(s.get('z_star'), 6, 3)} {fmt(s.get('x0'), 6, 3)} {s['steps']:9d} "
              f"{s['wall_seconds']:8.0f}")


if __name__ == "__main__":
    main(sys.argv[1:])
