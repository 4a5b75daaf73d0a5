#!/usr/bin/python3
"""Table of run_bench.sh: particle-steps/s per rank of both codes (best of the tries of each),
ratio, 1 -> 2 efficiency.
usage: summarize.py OUT_DIR SIZE... (run_bench.sh calls it)"""
import argparse
import glob
import os
import re
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
import granpack_io as gio  # noqa: E402


def main(argv):
    ap = argparse.ArgumentParser(
        prog="summarize.py", description="Table of run_bench.sh: particle-steps/s per rank of "
        "granpack and LAMMPS (best of the tries of each), ratio, 1 -> 2 ranks efficiency.")
    ap.add_argument("out", metavar="OUT_DIR", help="run_bench.sh's output directory")
    ap.add_argument("sizes", metavar="SIZE", nargs="+",
                    help="grain counts: the subdirectories OUT_DIR/SIZE")
    a = ap.parse_args(argv)
    if not os.path.isdir(a.out):
        ap.error(f"OUT_DIR {a.out}: no such directory")
    try:
        summarize(a.out, a.sizes)
    except gio.GranpackFileError as e:
        gio.fail("summarize.py", e)


def summarize(out, sizes):
    print(f"{'n':>8} {'ranks':>5} {'granpack':>12} {'LAMMPS':>12} {'ratio':>6}   granpack breakdown "
          "(forces/neigh/comm/integr. % of wall;\n"
          f"{'':>48}of the comm., the waits for the step's slowest force pass)")
    for size in sizes:
        d = os.path.join(out, size)
        rate = {}
        for np in (1, 2):
            gps = [gio.read_bench(f) for f in glob.glob(os.path.join(d, f"granpack_np{np}_*.json"))]
            lmp_rates = []
            for f in glob.glob(os.path.join(d, f"lammps_np{np}_*.log")):
                m = re.search(r"Loop time of (\S+) on (\d+) procs for (\d+) steps with (\d+) atoms",
                              open(f).read())
                if m:
                    lmp_rates.append(int(m[4]) * int(m[3]) / float(m[1]) / int(m[2]))
            if not gps or not lmp_rates:
                continue
            gp = max(gps, key=lambda g: g["particle_steps_per_s_per_rank"])
            lmp_rate = max(lmp_rates)
            rate[np] = (gp["particle_steps_per_s_per_rank"], lmp_rate)
            w = gp["wall"]
            parts = "/".join(f"{100 * gp[k] / w:.0f}" for k in ("forces", "neighbor", "comm", "integrate"))
            # Of the communication, the waits for the step's slowest force pass (bench's per-step
            # balance; absent from files of older versions).
            if "forces_step_max" in gp:
                parts += f", of which waits {100 * (gp['forces_step_max'] - gp['forces']) / w:.0f}"
            print(f"{gp['n']:>8} {np:>5} {rate[np][0]:>12.4g} {lmp_rate:>12.4g} "
                  f"{rate[np][0] / lmp_rate:>6.2f}   {parts}  ({gp['rebuilds']} rebuilds, "
                  f"{gp['bytes_per_grain']:.0f} B/grain; best of {len(gps)} and {len(lmp_rates)} tries)")
        if 1 in rate and 2 in rate:
            print(f"{'':>8} parallel efficiency 1->2 ranks: granpack {rate[2][0] / rate[1][0]:.1%}, "
                  f"LAMMPS {rate[2][1] / rate[1][1]:.1%}")


if __name__ == "__main__":
    main(sys.argv[1:])
