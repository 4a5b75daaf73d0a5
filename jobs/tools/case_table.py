#!/usr/bin/python3
"""One line per case from BASE/<case>/report.json: the last `compress` stage's Phi, z, z_int
(every interaction, distant pairs included: [GRC]'s z with cohesion), z* and x0 ([AR]'s
rattler rule), steps and wall seconds. Used by the jobs/runs/ sweeps.
"""
import argparse
import json
import os
import statistics


def fmt(v, width, prec):
    return f"{v:{width}.{prec}f}" if isinstance(v, (int, float)) else f"{'-':>{width}}"


def mean_sd(values):
    """Mean and sample standard deviation (None for one value)."""
    return statistics.mean(values), statistics.stdev(values) if len(values) > 1 else None


def main(argv):
    ap = argparse.ArgumentParser(prog="case_table.py", description=__doc__)
    ap.add_argument("base")
    ap.add_argument("cases", nargs="+")
    ap.add_argument("--stage", metavar="NAME",
                    help="the stage of that name instead of the last compress stage (e.g. P0)")
    ap.add_argument("--mean", action="store_true",
                    help="a last line with the mean and sample standard deviation of Phi and "
                         "z_int over the cases that have a report")
    args = ap.parse_args(argv)
    base, cases, stage, mean = args.base, args.cases, args.stage, args.mean
    phis, zs = [], []
    print(f"{'case':>22} {'Phi':>8} {'z':>6} {'z_int':>6} {'z*':>6} {'x0':>6} {'steps':>9} {'wall s':>8}")
    for c in cases:
        try:
            with open(os.path.join(base, c, "report.json")) as f:
                r = json.load(f)
        except OSError:
            print(f"{c:>22}  (no report.json)")
            continue
        chosen = [s for s in r["stages"]
                  if (s["name"] == stage if stage else s["kind"] == "compress")]
        if not chosen:
            print(f"{c:>22}  (no stage {stage or 'of kind compress'})")
            continue
        s = chosen[-1]
        z_int = s.get("values", {}).get("z_interactions")
        phis.append(s["phi"])
        if isinstance(z_int, (int, float)):
            zs.append(z_int)
        print(f"{c:>22} {s['phi']:8.4f} {fmt(s.get('z'), 6, 3)} {fmt(z_int, 6, 3)} "
              f"{fmt(s.get('z_star'), 6, 3)} {fmt(s.get('x0'), 6, 3)} {s['steps']:9d} "
              f"{s['wall_seconds']:8.0f}")
    if mean and phis:
        mp, sp = mean_sd(phis)
        sd = f" sd {sp:.4f}" if sp is not None else ""
        zline = ""
        if zs:
            mz, sz = mean_sd(zs)
            zline = f"  z_int {mz:.3f}" + (f" sd {sz:.3f}" if sz is not None else "")
        print(f"{'mean of ' + str(len(phis)):>22}  Phi {mp:.4f}{sd}{zline}")


if __name__ == "__main__":
    main(None)
