#!/usr/bin/env python3
"""z* and x0 of frictional packings against the force threshold that defines a force-carrying
contact: a check that a gap in z* is not a question of definition (docs/reproduction.md, Z).

granpack counts a contact as force-carrying when N^e > 1e-4 a^2 P ([AR]'s equilibrium tolerance)
and removes rattlers (grains with fewer than 2 force-carrying contacts, frictional case) until
none is left. This script redoes that from the file's contacts for several thresholds.

  /usr/bin/python3 jobs/tools/zstar_threshold.py --pressure 1e3 out/ens/Z/sample_*/Z.h5
"""
import argparse

import numpy as np

import granpack_io as gio


def backbone_zstar(path, pressure, threshold, min_contacts):
    try:
        p = gio.read_packing(path)
    except gio.GranpackFileError as e:
        gio.fail("zstar_threshold.py", e)
    force, ids, a = p.contacts["normal_force"], p.grains["id"], p.diameter
    first, second = p.contacts["first"], p.contacts["second"]
    index = np.full(ids.max() + 1, -1)
    index[ids] = np.arange(len(ids))
    keep = force > threshold * a * a * pressure
    i, j = index[first[keep]], index[second[keep]]
    n = len(ids)
    alive = np.ones(n, bool)
    while True:  # rattler removal until stable, as [AR] sec. III A
        both = alive[i] & alive[j]
        count = np.bincount(i[both], minlength=n) + np.bincount(j[both], minlength=n)
        still = alive & (count >= min_contacts)
        if (still == alive).all():
            break
        alive = still
    carrying = (alive[i] & alive[j]).sum()
    x0 = 1.0 - alive.mean()
    return 2.0 * carrying / (n * (1.0 - x0)), x0


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("files", nargs="+", help="packing files (.h5) of one ensemble")
    p.add_argument("--pressure", type=float, required=True, help="the state's pressure P in Pa")
    p.add_argument("--thresholds", type=float, nargs="+", default=[1e-5, 1e-4, 1e-3, 1e-2],
                   help="thresholds in units of a^2 P (default: 1e-5 1e-4 1e-3 1e-2)")
    p.add_argument("--min-contacts", type=int, default=2,
                   help="backbone grains need this many contacts (2 frictional, 4 frictionless 3D)")
    args = p.parse_args()
    print(f"{'threshold (a^2 P)':>18} {'z*':>16} {'x0 (%)':>14}   (mean ± sd over {len(args.files)} files)")
    for t in args.thresholds:
        z, x = np.array([backbone_zstar(f, args.pressure, t, args.min_contacts) for f in args.files]).T
        sd = (lambda v: v.std(ddof=1) if len(v) > 1 else 0.0)
        print(f"{t:>18.0e} {z.mean():>9.4f} ± {sd(z):.4f} {100 * x.mean():>7.2f} ± {100 * sd(x):.2f}")


if __name__ == "__main__":
    main()
