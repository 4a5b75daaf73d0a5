#!/usr/bin/env python3
"""[AR] App. E: counts and fig. 16 from the launch tests of jobs/runs/appendix_e.sh.

  /usr/bin/python3 jobs/tools/appendix_e.py OUT [--ratio 1e-4] [--png docs/figures/appendix_e_fig16.png]

Reads OUT/<level>_<mode>_pick<k>_ratio<r>/report.json (the divalent_launch stage's values) and
its divalent_trajectory.csv; prints one row per test and the counts beside [AR]'s (frozen
network: 8/10 unstable at 1 kPa, 2/10 at 10 kPa; with contact creation none collapsed), and
draws the trajectories in the (f, t) plane (x/D, y/D) as [AR] fig. 16, with the kinetic energy
against time below. The verdicts are the stage's (docs/stiffness.md).
"""
import argparse
import csv
import glob
import os
import re

import granpack_io as gio

AR = {("1kPa", "frozen"): "8/10 unstable", ("10kPa", "frozen"): "2/10 unstable",
      ("1kPa", "free"): "0/10 collapsed", ("10kPa", "free"): "0/10 collapsed"}


def load(out, ratio):
    tests = []
    for d in sorted(glob.glob(os.path.join(out, f"*_pick*_ratio{ratio}"))):
        m = re.match(r"(\w+?)_(frozen|free)_pick(\d+)_ratio", os.path.basename(d))
        rep = os.path.join(d, "report.json")
        if not m or not os.path.exists(rep):
            continue
        stage = [s for s in gio.read_report(rep).stages if s["kind"] == "divalent_launch"][0]
        rows = list(csv.DictReader(open(os.path.join(d, "divalent_trajectory.csv"))))
        tests.append(dict(level=m.group(1), mode=m.group(2), pick=int(m.group(3)),
                          values=stage["values"], steps=stage["steps"], time=stage["time"],
                          rows=rows))
    return tests


def outcome(t):
    """The stage's verdict (docs/stiffness.md), recomputed from the values and the last row, so
    that runs of binaries whose 'arrested' looked at the grain's energy only are judged alike."""
    v, last = t["values"], t["rows"][-1]
    if v["collapsed"]:
        return "collapsed"
    if v["rearranged"]:
        return "rearranged"
    rolling_on = (float(last["grain_kinetic_over_launch"]) >= 1e-2
                  and float(last["grain_contacts"]) == 2
                  and float(last["N_ij_over_F"]) > 0 and float(last["N_ik_over_F"]) > 0)
    return "rolling" if rolling_on else "arrested"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("--ratio", default="1e-4")
    ap.add_argument("--png", default="docs/figures/appendix_e_fig16.png")
    a = ap.parse_args()
    tests = load(a.out, a.ratio)
    print("| P | network | pick | grain | F/a2P | D/a | turns | max Ek/Ek0 | launch contacts closed (min) | new contacts | dPhi | outcome |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for t in sorted(tests, key=lambda t: (t["level"] != "1kPa", t["mode"], t["pick"])):
        v = t["values"]
        print(f"| {t['level']} | {t['mode']} | {t['pick']} | {int(v['grain'])} | "
              f"{v['contact_force_over_a2P']:.2f} | {v['D_over_a']:.3f} | {v['turns_done']:.2f} | "
              f"{v['max_kinetic_over_launch']:.3g} | {int(v['min_launch_contacts_closed'])} / "
              f"{int(v['launch_contacts'])} | {int(v['max_new_contacts'])} | {v['phi_change']:.2g} | "
              f"{outcome(t)} |")
    # How far the grain's contact forces drift in the runs still rolling (the launch's small
    # centrifugal force should leave them unchanged).
    drift = [max(abs(float(r["N_ij_over_F"]) / float(t["rows"][0]["N_ij_over_F"]) - 1)
                 for r in t["rows"]) for t in tests if outcome(t) == "rolling" and t["mode"] == "frozen"]
    if drift:
        print(f"\nrolling frozen runs: largest change of N_ij over the run {100 * max(drift):.2g} %")
    print()
    print("| P | network | tests | collapsed | rearranged | arrested | rolling | [AR] |")
    print("|---|---|---|---|---|---|---|---|")
    for level in ("1kPa", "10kPa"):
        for mode in ("frozen", "free"):
            g = [t for t in tests if t["level"] == level and t["mode"] == mode]
            if not g:
                continue
            c = {k: sum(outcome(t) == k for t in g)
                 for k in ("collapsed", "rearranged", "arrested", "rolling")}
            print(f"| {level} | {mode} | {len(g)} | {c['collapsed']} | {c['rearranged']} | "
                  f"{c['arrested']} | {c['rolling']} | {AR[(level, mode)]} |")
    if not tests:
        return
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    levels = [lv for lv in ("1kPa", "10kPa") if any(t["level"] == lv for t in tests)]
    fig, axes = plt.subplots(2, len(levels), figsize=(5.2 * len(levels), 9.5), squeeze=False,
                             gridspec_kw=dict(height_ratios=[1.3, 1]))
    for col, level in enumerate(levels):
        ax, ax2 = axes[0][col], axes[1][col]
        for t in [t for t in tests if t["level"] == level]:
            x = [float(r["x_over_D"]) for r in t["rows"]]
            y = [float(r["y_over_D"]) for r in t["rows"]]
            # From the first step on (files of the first binary hold 0 at t = 0).
            tt = [float(r["t"]) for r in t["rows"][1:]]
            ek = [float(r["kinetic_over_launch"]) for r in t["rows"][1:]]
            o = outcome(t)
            if t["mode"] == "frozen":
                color = "black" if o in ("collapsed", "rearranged") else "red"
                ax.plot(x, y, "-", color=color, lw=1)
                ax2.semilogy(tt, ek, "-", color=color, lw=1)
            else:
                ax.plot(x, y, ".", color="tab:blue", ms=2)
                ax2.semilogy(tt, ek, ":", color="tab:blue", lw=1)
        ax.plot([1], [0], "ko", ms=4)
        ax.set_aspect("equal")
        ax.set_xlim(-1.6, 1.6)
        ax.set_ylim(-1.6, 1.6)
        ax.set_xlabel("x / D  (along f)")
        ax.set_ylabel("y / D  (along t)")
        ax.set_title(f"D, P = {level}: frozen network (lines: black unstable, red stable),\n"
                     "contact creation (blue dots)", fontsize=9)
        ax2.set_ylim(1e-3, 1e3)
        ax2.set_xlabel("t (s)")
        ax2.set_ylabel("total kinetic energy / launch energy")
    fig.tight_layout()
    fig.savefig(a.png, dpi=110)
    print(f"\nwrote {a.png}")


if __name__ == "__main__":
    main()
