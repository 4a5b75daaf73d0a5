#!/usr/bin/env python3
"""Tables VII and VIII of [AR] (appendix D) beside ours, from `granpack analyze --json` files.

For each d_c in 1.1-1.4 a, the fractions (%) of grains whose local (Q4, Q6) lies within
+-0.05 of the experimental sample's most frequent pair (dis), of the fcc pair
(0.191, 0.574) and of the hcp pair (0.097, 0.485) (docs/analysis-order.md).
Usage: /usr/bin/python3 jobs/tools/order_tables.py STATE=analysis.json ...  (STATE: A, A', B, C, D)
Prints Markdown tables to paste into docs/reproduction.md.
"""
import argparse

import granpack_io as gio

# [AR] tables VII-VIII: (dis, fcc, hcp) in %, "<0.01" written as 0.
PAPER = {
    "A": {"1.10": (32, 0, 4), "1.20": (37, 0, 5), "1.30": (43, 0, 8), "1.40": (46, 0, 12)},
    "A'": {"1.10": (31, 0, 5), "1.20": (40, 0, 6), "1.30": (45, 0, 10), "1.40": (48, 0, 15)},
    "C": {"1.10": (31, 0, 4), "1.20": (37, 0, 5), "1.30": (43, 0, 8), "1.40": (46, 0, 13)},
    "B": {"1.10": (30, 0, 2.7), "1.20": (38, 0, 7.6), "1.30": (43, 0, 10), "1.40": (46, 0, 10)},
}
# The experimental sample each state is compared with (table VII: F; table VIII: D for B).
WINDOW = {"A": "aste_F", "A'": "aste_F", "C": "aste_F", "B": "aste_D", "D": "aste_B"}


def state_file(arg):
    """STATE=analysis.json -> (STATE, the analysis as a dict); the state must have a window."""
    if "=" not in arg:
        raise argparse.ArgumentTypeError(f"'{arg}' is not STATE=analysis.json")
    state, path = arg.split("=", 1)
    if state not in WINDOW:
        raise argparse.ArgumentTypeError(f"unknown state '{state}' (one of {', '.join(WINDOW)})")
    try:
        analysis = gio.read_analysis(path)
    except gio.GranpackFileError as e:
        raise argparse.ArgumentTypeError(str(e)) from None
    if not isinstance(analysis.get("order"), dict):
        raise argparse.ArgumentTypeError(f"{path}: no 'order' section")
    return state, analysis


def main():
    ap = argparse.ArgumentParser(prog="order_tables.py", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("states", nargs="+", type=state_file, metavar="STATE=analysis.json",
                    help="a state's label (A, A', B, C, D) and its analysis JSON")
    states = ap.parse_args().states
    print("| state | d_c/a | dis % (ours / [AR]) | fcc % (ours / [AR]) | hcp % (ours / [AR]) |")
    print("|---|---|---|---|---|")
    for state, analysis in states:
        order = analysis["order"]
        for dc in ("1.10", "1.20", "1.30", "1.40"):
            w = order[dc]["windows"][WINDOW[state]]
            ours = (100 * w["dis"], 100 * w["fcc"], 100 * w["hcp"])
            paper = PAPER.get(state, {}).get(dc)
            cells = []
            for k in range(3):
                ref = "–" if paper is None else ("<0.01" if paper[k] == 0 else f"{paper[k]:g}")
                cells.append(f"{ours[k]:.1f} / {ref}")
            print(f"| {state} | {float(dc):.1f} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
