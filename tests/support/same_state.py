#!/usr/bin/env python3
"""Are two granpack HDF5 files the same state, bit for bit?

Rows are in no particular order (docs/hdf5-schema.md), so particles are compared after
sorting by id and contacts after sorting by (first, second). Every stored array is compared
exactly (no tolerance): this is the check of a restart on the same rank count.
Usage: same_state.py A.h5 B.h5   (exit 0: identical; 1: the first differences are printed)
"""
import sys

import h5py
import numpy as np


def load(path):
    with h5py.File(path, "r") as f:
        out = {"time": f.attrs["time"], "step": f.attrs["step"],
               "cell/length": f["cell/length"][:], "cell/rate": f["cell/rate"][:]}
        order = np.argsort(f["particles/id"][:], kind="stable")
        for name in ("id", "radius", "mass", "inertia", "scaled_position", "velocity",
                     "angular_velocity", "orientation"):
            out["particles/" + name] = f["particles/" + name][:][order]
        first, second = f["contacts/first"][:], f["contacts/second"][:]
        corder = np.lexsort((second, first))
        for name in ("first", "second", "normal_force", "tangential_force", "rolling", "flags", "age"):
            out["contacts/" + name] = f["contacts/" + name][:][corder]
    return out


def main():
    a, b = load(sys.argv[1]), load(sys.argv[2])
    bad = []
    for key in a:
        x, y = np.asarray(a[key]), np.asarray(b[key])
        if x.shape != y.shape:
            bad.append(f"{key}: shapes {x.shape} and {y.shape}")
        elif x.dtype.kind == "f":
            # Bit patterns, so that -0.0 vs 0.0 or differing NaNs count as differences.
            same = x.view(np.uint64) == y.view(np.uint64) if x.dtype == np.float64 else x == y
            if not np.all(same):
                n = int(np.size(same) - np.count_nonzero(same))
                diff = np.max(np.abs(x - y)) if np.all(np.isfinite(x)) and np.all(np.isfinite(y)) else float("nan")
                bad.append(f"{key}: {n} values differ (largest difference {diff:.3e})")
        elif not np.array_equal(x, y):
            bad.append(f"{key}: differs")
    n = len(a["particles/id"])
    nc = len(a["contacts/first"])
    if bad:
        print(f"{sys.argv[1]} and {sys.argv[2]} differ:")
        for line in bad[:20]:
            print("  " + line)
        return 1
    print(f"identical: {n} particles, {nc} contacts, step {a['step']}, bit for bit")
    return 0


if __name__ == "__main__":
    sys.exit(main())
