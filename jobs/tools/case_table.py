#!/usr/bin/python3
"""One line per case from BASE/<case>/report.json: the last `compress` stage's Phi, z, z_int
(every interaction, distant pairs included: [GRC]'s z with cohesion), z* and x0 ([AR]'s
rattler rule), steps and wall seconds. Used by the jobs/runs/ sweeps.

With --ensemble BASE2 [BASE3 ...] (the same cases run with other seeds, e.g. out/2d/table2_seed2
from SEED=2 bash jobs/runs/method1_sweep.sh 2), one line per case over every base that has its
report: K, and the mean and sample standard deviation (ddof = 1) of Phi, z and z_int.

With --against II|III, the same as a markdown table beside [GRC]'s table II or III
(jobs/tools/grc_paper.py; the tables of docs/reproduction-2d.md): the deviation in % and in
combined standard errors, (ours - theirs) / sqrt(sd_ours^2/K + sd_GRC^2). A case [GRC] do not
have exits 2.
"""
import argparse
import os
import statistics
import sys

import granpack_io as gio
import grc_paper as grc


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


def gather(bases, cases, stage):
    """Per case: {"phi": [...], "z": [...], "z_int": [...], "skipped": [base names]} over the
    bases that hold its report with an equilibrated stage."""
    out = {}
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
        out[c] = {"phi": phis, "z": zs, "z_int": zints, "skipped": skipped}
    return out


def ensemble_table(bases, cases, stage):
    """Per case: K samples (the bases with a report and an equilibrated stage) and mean +- sd."""
    def cell(values, prec):
        if not values:
            return f"{'-':>17}"
        m, sd = mean_sd(values)
        return f"{m:{prec + 3}.{prec}f} +- {sd:.{prec}f}" if sd is not None else f"{m:{prec + 3}.{prec}f}" + " " * (prec + 5)
    print(f"{'case':>22} {'K':>2} {'Phi':>17} {'z':>15} {'z_int':>15}  not equilibrated")
    for c, v in gather(bases, cases, stage).items():
        print(f"{c:>22} {len(v['phi']):2d} {cell(v['phi'], 4)} {cell(v['z'], 3)} "
              f"{cell(v['z_int'], 3)}  {' '.join(v['skipped'])}")


def deviation(values, paper):
    """(ours - theirs) in % of theirs, and in combined standard errors sqrt(sd^2/K + sd_GRC^2):
    [GRC] do not state their sample count, so their sd counts as one sample's (with K = 1 the
    bracket is the distance in [GRC]'s sd alone)."""
    m, sd = mean_sd(values)
    pm, psd = paper
    se = (((sd or 0.0) ** 2 / len(values)) + psd ** 2) ** 0.5
    return 100.0 * (m - pm) / pm, (m - pm) / se


def against_table(bases, cases, stage, table):
    """A markdown table of the ensemble beside [GRC]'s table II or III (jobs/tools/grc_paper.py):
    one row per case, mean +- sd of Phi and z ([GRC]'s z: Z_KEY), the deviation in % and, in
    brackets, in combined standard errors; then how many cases lie within 2 of them."""
    paper = grc.TABLES[table]
    zkey = grc.Z_KEY[table]
    unknown = [c for c in cases if c not in paper]
    if unknown:
        print(f"case_table.py: --against {table}: no [GRC] value for case(s) {' '.join(unknown)} "
              f"(known: {' '.join(paper)})", file=sys.stderr)
        return 2

    def cell(values, prec):
        m, sd = mean_sd(values)
        return f"{m:.{prec}f}" + (f" ± {sd:.{prec}f}" if sd is not None else "")

    def dev(values, ref):
        pct, n = deviation(values, ref)
        return f"{pct:+.1f} % ({n:+.1f})".replace("-", "−"), abs(n) <= 2.0

    zname = "z" if zkey == "z" else "z_int"
    print(f"| Φ_I | μ | RR | K | Φ ours | Φ [GRC] | dev. Φ | {zname} ours | z [GRC] | dev. z |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    columns = (("phi", "phi", 4), (zkey, "z", 3))  # (our key, [GRC]'s key, decimals)
    within, counted = {"phi": 0, "z": 0}, {"phi": 0, "z": 0}
    # The same counts without the cells grc_paper.SUSPECT doubts, and the doubts to print.
    within_sound, counted_sound, notes = {"phi": 0, "z": 0}, {"phi": 0, "z": 0}, []
    suspect = grc.SUSPECT.get(table, {})
    for c, v in gather(bases, cases, stage).items():
        phi_i, mu, rr = c.split("-")
        row = [phi_i, mu, "yes" if rr == "rr" else "no", str(len(v["phi"]))]
        for ours, theirs, prec in columns:
            ref = paper[c][theirs]
            doubt = suspect.get((c, theirs))
            mark = " ‡" if doubt else ""
            if doubt and doubt not in notes:
                notes.append(doubt)
            if v[ours]:
                d, ok = dev(v[ours], ref)
                row += [cell(v[ours], prec), f"{ref[0]} ± {ref[1]}{mark}", d]
                counted[theirs] += 1
                within[theirs] += ok
                if not doubt:
                    counted_sound[theirs] += 1
                    within_sound[theirs] += ok
            else:
                row += ["–", f"{ref[0]} ± {ref[1]}{mark}", ""]
        print("| " + " | ".join(row) + " |")
    print(f"\nwithin 2 combined standard errors: Φ {within['phi']} of {counted['phi']}, "
          f"z {within['z']} of {counted['z']}")
    if counted_sound != counted:
        print(f"without the cells marked ‡: Φ {within_sound['phi']} of {counted_sound['phi']}, "
              f"z {within_sound['z']} of {counted_sound['z']}")
    for n in notes:
        print(f"‡ {n}")
    return 0


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
    ap.add_argument("--against", choices=sorted(grc.TABLES),
                    help="print a markdown table beside [GRC]'s table II or III (mean +- sd, "
                         "deviation in %% and in combined standard errors; with or without "
                         "--ensemble)")
    args = ap.parse_args(argv)
    if args.against:
        return against_table([args.base] + (args.ensemble or []), args.cases, args.stage,
                             args.against)
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
    sys.exit(main(None))
