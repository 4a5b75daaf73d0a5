#!/usr/bin/python3
"""The table of ci_bands.sh: Phi, z*, x0, x2 and Z(2) of each state of the CI decks
(AC_small, B_small, D_small; their compress and pressure_steps stages with a z*) with the mean
and standard deviation over the seeds, from WORK/out_<deck>_<seed>/report.json.

  /usr/bin/python3 jobs/tools/ci_bands.py WORK SEED [SEED ...]
"""
import argparse
import statistics as st

import granpack_io as gio

DECKS = ("AC_small", "B_small", "D_small")
KEYS = ("phi", "z_star", "x0", "x2", "z2")


def main(argv=None):
    ap = argparse.ArgumentParser(prog="ci_bands.py", description=__doc__.split("\n\n")[0])
    ap.add_argument("work", help="ci_bands.sh's directory of runs")
    ap.add_argument("seeds", nargs="+", metavar="SEED")
    a = ap.parse_args(argv)
    rows = {}
    try:
        for seed in a.seeds:
            for deck in DECKS:
                for s in gio.read_report(f"{a.work}/out_{deck}_{seed}/report.json").stages:
                    if s["z_star"] is not None and s["kind"] in ("compress", "pressure_steps"):
                        rows.setdefault(s["name"], []).append(s)
    except gio.GranpackFileError as e:
        gio.fail("ci_bands.py", e)
    print("state  " + "  ".join(f"{k:>17}" for k in KEYS))
    for name, ss in rows.items():
        cells = []
        for k in KEYS:
            v = [s[k] for s in ss]
            sd = st.stdev(v) if len(v) > 1 else 0.0
            cells.append(f"{st.mean(v):9.4f} ± {sd:6.4f}")
        print(f"{name:6} " + "  ".join(cells) + "   values: " + " ".join(
            f"{s['phi']:.4f}/{s['z_star']:.3f}/{s['x0']:.3f}" for s in ss))


if __name__ == "__main__":
    main()
