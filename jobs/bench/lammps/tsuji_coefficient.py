#!/usr/bin/python3
"""The 'restitution coefficient' e to give LAMMPS's `damping tsuji` so that its damping equals
granpack's fraction zeta of critical damping (see in.granular): alpha(e) = 2 zeta sqrt(3/2).
usage: tsuji_coefficient.py [ZETA]   (default 0.98, the decks' damping)"""
import argparse
import math
import sys


def main(argv):
    ap = argparse.ArgumentParser(
        prog="tsuji_coefficient.py", description="The e of LAMMPS's `damping tsuji` whose "
        "alpha(e) = 2 zeta sqrt(3/2) equals granpack's damping, zeta of critical (bisection).")
    ap.add_argument("zeta", nargs="?", type=float, default=0.98,
                    help="granpack's damping, a fraction of critical (default 0.98)")
    zeta = ap.parse_args(argv).zeta
    target = 2.0 * zeta * math.sqrt(1.5)
    c = [1.2728, -4.2783, 11.087, -22.348, 27.467, -18.022, 4.8218]
    alpha = lambda e: sum(ci * e**i for i, ci in enumerate(c))  # noqa: E731
    lo, hi = -1.0, 1.0  # alpha decreases monotonically on [-1, 1]
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if alpha(mid) > target else (lo, mid)
    print(f"zeta = {zeta}: alpha = {target:.10f}, e = {lo!r} (alpha(e) = {alpha(lo):.10f})")


if __name__ == "__main__":
    main(sys.argv[1:])
