#!/usr/bin/python3
"""One line per case from BASE/<case>/report.json: the last `compress` stage's Phi, z, z_int
(every interaction, distant pairs included: [GRC]'s z with cohesion), z* and x0 ([AR]'s
rattler rule), steps and wall seconds. Used by the jobs/runs/ sweeps.

With --ensemble BASE2 [BASE3 ...] (the same cases run with other seeds, e.g. out/2d/table2_seed2
from SEED=2 bash jobs/runs/method1_sweep.sh 2), one line per case over every base that has its
report: K, and the mean and sample standard deviation (ddof = 1) of Phi, z and z_int.
"""
import argparse
import os
import statistics

import granpack_io as gio


def fmt(v, width, prec):
    return f"{v:{width}.{prec}f}" if isinstance(v, (int, float)) else f"{'-':>{width}}"


def mean_sd(values):
    """Mean and sample standard deviation (None for one value)."""
    return statistics.mean(values), statistics.stdev(values) if len(values) > 1 else None


def report_path(base, case):
    """BASE/<case>/report.json (a run directory) or BASE/<case>.report.json (the reports
    committed under docs/data/2d/table2, table3, ...)."""
    run = os.path.join(base, case, "report.json")
    flat = os.path.join(base, case + ".report.json")
    return run if os.path.exists(run) or not os.path.exists(flat) else flat


def read_report(base, case):
    """The stages of the case's report.json (granpack_io.read_report), None if there is no
    report; a report that is not one stops the tool (exit 2)."""
    path = report_path(base, case)
    if not os.path.exists(path):
        return None
    try:
        return gio.read_report(path).raw
    except gio.GranpackFileError as e:
        gio.fail("case_table.py", e)


def chosen_stage(report, stage):
    """The stage named `stage`, or the last compress stage; None if there is none."""
    chosen = [s for s in report["stages"]
              if (s["name"] == stage if stage else s["kind"] == "compress")]
    return chosen[-1] if chosen else None


def ensemble_table(bases, cases, stage):
    """Per case: K samples (the bases with a report and an equilibrated stage) and mean +- sd."""
    def cell(values, prec):
        if not values:
            return f"{'-':>17}"
        m, sd = mean_sd(values)
        return f"{m:{prec + 3}.{prec}f} +- {sd:.{prec}f}" if sd is not None else f"{m:{prec + 3}.{prec}f}" + " " * (prec + 5)
    print(f"{'case':>22} {'K':>2} {'Phi':>17} {'z':>15} {'z_int':>15}  not equilibrated")
    for c in cases:
        phis, zs, zints, skipped = [], [], [], []
        for base in bases:
            r = read_report(base, c)
            s = chosen_stage(r, stage) if r is not None else None
            if s is None:
                continue
            if not s.get("equilibrated", True):
                skipped.append(os.path.basename(os.path.normpath(base)))
                continue
            phis.append(s["phi"])
            if isinstance(s.get("z"), (int, float)):
                zs.append(s["z"])
            z_int = s.get("values", {}).get("z_interactions")
            if isinstance(z_int, (int, float)):
                zints.append(z_int)
        print(f"{c:>22} {len(phis):2d} {cell(phis, 4)} {cell(zs, 3)} {cell(zints, 3)}  "
              f"{' '.join(skipped)}")


def main(argv):
    ap = argparse.ArgumentParser(prog="case_table.py", description=__doc__)
    ap.add_argument("base")
    ap.add_argument("cases", nargs="+")
    ap.add_argument("--stage", metavar="NAME",
                    help="the stage of that name instead of the last compress stage (e.g. P0)")
    ap.add_argument("--mean", action="store_true",
                    help="a last line with the mean and sample standard deviation of Phi and "
                         "z_int over the cases that have a report")
    ap.add_argument("--ensemble", nargs="+", metavar="BASE",
                    help="more bases holding the same cases (other seeds): print mean, sd and "
                         "K per case instead of one line per run")
    args = ap.parse_args(argv)
    if args.ensemble:
        return ensemble_table([args.base] + args.ensemble, args.cases, args.stage)
    base, cases, stage, mean = args.base, args.cases, args.stage, args.mean
    phis, zs = [], []
    print(f"{'case':>22} {'Phi':>8} {'z':>6} {'z_int':>6} {'z*':>6} {'x0':>6} {'steps':>9} {'wall s':>8}")
    for c in cases:
        r = read_report(base, c)
        if r is None:
            print(f"{c:>22}  (no report.json)")
            continue
        s = chosen_stage(r, stage)
        if s is None:
            print(f"{c:>22}  (no stage {stage or 'of kind compress'})")
            continue
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
