#!/usr/bin/env python3
"""Tables V and VI of [AR] beside ours, from `granpack analyze --json` files.

Table V: percentages x_i of grains with i force-carrying contacts (treatment I, `x_i`).
Table VI: fraction X1 of contacts with N > <N>, mean |T|/N above (M1) and below (M2) <N>,
and the same for contacts touching a 2- or 3-coordinated grain, with their mean normal force
N^(2), N^(3) in units of P a^2 (docs/analysis.md, "strong/weak split").
Usage: /usr/bin/python3 jobs/tools/contact_tables.py STATE=analysis.json ...  (STATE: B, C, D)
Prints Markdown tables to paste into docs/reproduction.md.
"""
import argparse

import granpack_io as gio

# [AR] table V, treatment I: x_0 ... x_10 in %.
TABLE_V = {
    "B": (1.95, 0, 0.05, 0.5, 16.3, 26.9, 27.5, 18.4, 7.1, 1.4, 0.1),
    "C": (13.3, 0, 2.6, 15.1, 26.5, 23.4, 13.2, 4.8, 0.9, 0.15, 0),
    "D": (11.1, 0, 2.4, 13.8, 29.1, 25.6, 13.3, 4.0, 0.7, 0.03, 0),
}
# [AR] table VI: X1, M1, M2, N2, X1(2), M1(2), M2(2), N3, X1(3), M1(3), M2(3); None = n. d.
TABLE_VI = {
    "B": (0.42, 0.016, 0.018, None, None, None, None, 0.23, 0.09, 0.02, 0.01),
    "C": (0.41, 0.14, 0.18, 0.58, 0.19, 0.14, 0.17, 0.24, 0.09, 0.13, 0.04),
    "D": (0.41, 0.16, 0.22, 0.71, 0.22, 0.16, 0.18, 0.26, 0.10, 0.15, 0.05),
}


def fmt(v, digits):
    return "n. d." if v is None else f"{v:.{digits}f}"


def table_v(states):
    print("| x_i (%) | " + " | ".join(f"x_{i}" for i in range(11)) + " |")
    print("|---" * 12 + "|")
    for state, d in states:
        x = d["x_i"]
        ours = [100 * x.get(str(i), 0.0) for i in range(11)]
        print(f"| {state} (I), ours | " + " | ".join(f"{v:.2f}" for v in ours) + " |")
        if state in TABLE_V:
            print(f"| {state} (I), [AR] | " + " | ".join(f"{v:g}" for v in TABLE_V[state]) + " |")


def population(d, key):
    """(N/Pa^2, X1, M1, M2) of contacts touching 2- or 3-coordinated grains, None if absent."""
    p = d.get(key)
    if not p or not p.get("contacts"):
        return (None,) * 4
    return (p["N_over_Pa2"], p["X1"], p["M1"], p["M2"])


def table_vi(states):
    head = ["X1", "M1", "M2", "N(2)", "X1(2)", "M1(2)", "M2(2)", "N(3)", "X1(3)", "M1(3)", "M2(3)"]
    print("| state | " + " | ".join(head) + " |")
    print("|---" * 12 + "|")
    for state, d in states:
        ours = (d["X1"], d["M1"], d["M2"]) + population(d, "divalent_contacts") + population(
            d, "trivalent_contacts")
        print(f"| {state}, ours | " + " | ".join(fmt(v, 3) for v in ours) + " |")
        if state in TABLE_VI:
            print(f"| {state}, [AR] | " + " | ".join(fmt(v, 3) for v in TABLE_VI[state]) + " |")


def state_file(arg):
    """STATE=analysis.json -> (STATE, the analysis as a dict)."""
    if "=" not in arg:
        raise argparse.ArgumentTypeError(f"'{arg}' is not STATE=analysis.json")
    state, path = arg.split("=", 1)
    try:
        return state, gio.read_analysis(path)
    except gio.GranpackFileError as e:
        raise argparse.ArgumentTypeError(str(e)) from None


def main():
    ap = argparse.ArgumentParser(prog="contact_tables.py", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("states", nargs="+", type=state_file, metavar="STATE=analysis.json",
                    help="a state's label (B, C, D: compared with [AR]) and its analysis JSON")
    states = ap.parse_args().states
    print("Table V (treatment I)\n")
    table_v(states)
    print("\nTable VI\n")
    table_vi(states)


if __name__ == "__main__":
    main()
