#!/usr/bin/python3
"""loose_phase.sh's line for one run: the last stage with md_classes in REPORT (report.json):
steps and particle-steps per second of the loose and dense classes, MD wall seconds, the force
phase in wall and CPU seconds, and the run's CPU seconds (user + system, the last two numbers of
CPU_FILE, /usr/bin/time -f "%U %S").

  /usr/bin/python3 jobs/bench/loose_line.py REPORT NAME NP WHICH TRY LOAD CPU_FILE
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
import granpack_io as gio  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(prog="loose_line.py", description=__doc__.split("\n\n")[0])
    ap.add_argument("report", help="the run's report.json")
    ap.add_argument("name", help="the deck's name (printed)")
    ap.add_argument("np", help="ranks (printed)")
    ap.add_argument("which", help="before or after (printed)")
    ap.add_argument("try_", metavar="try", help="the try's number (printed)")
    ap.add_argument("load", help="the load average at the start (printed)")
    ap.add_argument("cpu", metavar="CPU_FILE", help="/usr/bin/time -f '%%U %%S' output")
    a = ap.parse_args(argv)
    try:
        stages = gio.read_report(a.report).stages
    except gio.GranpackFileError as e:
        gio.fail("loose_line.py", e)
    cpu = sum(float(x) for x in open(a.cpu).read().split()[-2:])
    s = [s for s in stages if s.get("md_classes")][-1]
    c, ph = s["md_classes"], s["phase_seconds"]
    md = sum(ph[k] for k in ("forces", "neighbor", "comm", "integrate"))

    def rate(k):
        return c[k]["particle_steps_per_second"] or 0.0

    print(f"{a.name} np{a.np} {a.which:6s} try {a.try_} load {a.load}: loose "
          f"{c['loose']['steps']} steps {rate('loose'):.3e}/s, dense {c['dense']['steps']} steps "
          f"{rate('dense'):.3e}/s, MD wall {md:.2f} s, forces {ph['forces']:.2f} s "
          f"(CPU {ph['forces_cpu']:.2f} s), run CPU {cpu:.2f} s", flush=True)


if __name__ == "__main__":
    main()
