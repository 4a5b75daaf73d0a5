#!/usr/bin/python3
"""Static cross-check: per-grain contact forces and pressure of granpack vs LAMMPS on the same
configuration, grains at rest (so only the elastic Hertz forces act in both codes).
usage: compare_static.py granpack_static.txt forces.dump lammps_static.log (run_bench.sh calls it)"""
import argparse
import math
import os
import sys


def main(argv):
    ap = argparse.ArgumentParser(
        prog="compare_static.py", description="Per-grain net forces and pressure of granpack vs "
        "LAMMPS on the same configuration, grains at rest (run_bench.sh's static check).")
    ap.add_argument("gp_file", metavar="granpack_static.txt",
                    help="`granpack bench --static-forces` output: '# pressure P' and rows 'id fx fy fz'")
    ap.add_argument("dump_file", metavar="forces.dump",
                    help="LAMMPS dump with 'ITEM: ATOMS id fx fy fz' (ids from 1)")
    ap.add_argument("log_file", metavar="lammps_static.log",
                    help="LAMMPS log with a line 'STATIC_PRESSURE P'")
    a = ap.parse_args(argv)
    for f in (a.gp_file, a.dump_file, a.log_file):
        if not os.path.isfile(f):
            ap.error(f"{f}: no such file")
    compare(a.gp_file, a.dump_file, a.log_file)


def compare(gp_file, dump_file, log_file):
    gp = {}
    with open(gp_file) as f:
        for line in f:
            if line.startswith("# pressure"):
                gp_pressure = float(line.split()[2])
            if line.startswith("#"):
                continue
            i, fx, fy, fz = line.split()
            gp[int(i)] = (float(fx), float(fy), float(fz))
    lmp = {}
    with open(dump_file) as f:
        lines = f.read().splitlines()
    start = lines.index("ITEM: ATOMS id fx fy fz") + 1
    for line in lines[start:]:
        i, fx, fy, fz = line.split()
        lmp[int(i) - 1] = (float(fx), float(fy), float(fz))
    lmp_pressure = None
    with open(log_file) as f:
        for line in f:
            if line.startswith("STATIC_PRESSURE"):
                lmp_pressure = float(line.split()[1])
    assert set(gp) == set(lmp), "the two codes hold different grains"
    diff2 = ref2 = 0.0
    worst = 0.0
    fmax = max(math.sqrt(sum(c * c for c in v)) for v in gp.values())
    for i, g in gp.items():
        l = lmp[i]
        d = math.sqrt(sum((a - b) ** 2 for a, b in zip(g, l)))
        diff2 += d * d
        ref2 += sum(c * c for c in g)
        worst = max(worst, d)
    print(f"static check, n = {len(gp)}: P granpack {gp_pressure:.10g} Pa, LAMMPS {lmp_pressure:.10g} Pa, "
          f"relative difference {abs(gp_pressure - lmp_pressure) / abs(lmp_pressure):.3e}; per-grain net "
          f"force: rms difference / rms force {math.sqrt(diff2 / ref2):.3e}, max difference / max force "
          f"{worst / fmax:.3e} (max difference {worst:.3e} N; the net forces are the equilibrium residuals, "
          f"~1e-4 of a contact force, so these ratios measure round-off in sums of ~6 contact forces)")


if __name__ == "__main__":
    main(sys.argv[1:])
