#!/usr/bin/python3
"""One line per case from BASE/<case>/report.json: the last `compress` stage's Phi, z, z_int
(every interaction, distant pairs included: [GRC]'s z with cohesion), z* and x0 ([AR]'s
rattler rule), steps and wall seconds. Used by the jobs/runs/ sweeps.

    /usr/bin/python3 jobs/tools/case_table.py BASE CASE... [--stage NAME] [--mean]

--stage NAME  the stage of that name instead of the last compress stage (e.g. P0)
--mean        a last line with the mean and sample standard deviation of Phi and z_int over
              the cases that have a report (samples of one deck: jobs/runs/seeds.sh)
"""
import json
import os
import sys


def fmt(v, width, prec):
    return f"{v:{width}.{prec}f}" if isinstance(v, (int, float)) else f"{'-':>{width}}"


def mean_sd(values):
    m = sum(values) / len(values)
    if len(values) < 2:
        return m, None
    return m, (sum((v - m) ** 2 for v in values) / (len(values) - 1)) ** 0.5


def main(argv):
    mean = "--mean" in argv
    argv = [a for a in argv if a != "--mean"]
    stage = None
    if "--stage" in argv:
        i = argv.index("--stage")
        if i + 1 >= len(argv):
            sys.exit("case_table: --stage needs a stage name")
        stage = argv[i + 1]
        del argv[i:i + 2]
    if len(argv) < 2:
        sys.exit(__doc__)
    base, cases = argv[0], argv[1:]
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
    main(sys.argv[1:])
