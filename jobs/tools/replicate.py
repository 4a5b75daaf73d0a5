#!/usr/bin/env python3
"""Replicate a periodic granpack configuration kx x ky (x kz) times, contacts included.

The copy of an equilibrated packing is itself equilibrated (the cell is periodic, every grain
sees the same neighbours and forces), so it gives larger packings with known properties for
timings (e.g. `granpack stiffness` at n = 32000 from an n = 4000 state) without simulating
them. Copy c of grain `id` gets id + c * (max id + 1). A contact (i, j) of the original joins
i in copy c to the image of j in the copy that the minimum-image shift of the pair points to.
When the new ids reverse the order of a pair, the pair is stored swapped (first < second, as
docs/hdf5-schema.md requires): the normal then points the other way, so the tangential force
and the relative rolling rotation, both given for the second grain, change sign; N^e does
not. Everything else (attributes, /deck) is copied; /run_state is dropped (the result is a
configuration, not a checkpoint).

Usage: /usr/bin/python3 jobs/tools/replicate.py IN.h5 OUT.h5 KX KY [KZ]
"""
import itertools
import sys

import h5py
import numpy as np

PARTICLE_SETS = ["id", "radius", "mass", "inertia", "scaled_position", "position", "velocity",
                 "angular_velocity", "orientation"]
CONTACT_SETS = ["first", "second", "normal_force", "tangential_force", "rolling", "flags", "age"]


def replicate(src, dst, reps):
    dim = int(src.attrs["dimension"])
    if len(reps) != dim or any(k < 1 for k in reps):
        sys.exit(f"replicate.py: give {dim} factors >= 1, got {reps}")
    if src.attrs["kind"] != "configuration" and src.attrs["kind"] != "checkpoint":
        sys.exit("replicate.py: not a granpack configuration")
    reps = np.array(reps)
    copies = list(itertools.product(*[range(k) for k in reps]))
    ncopy = len(copies)
    L = src["cell/length"][:]
    p = {k: src["particles/" + k][:] for k in PARTICLE_SETS}
    c = {k: src["contacts/" + k][:] for k in CONTACT_SETS}
    n, nc = len(p["id"]), len(c["first"])
    stride = int(p["id"].max()) + 1
    row = {int(g): r for r, g in enumerate(p["id"])}
    s = p["scaled_position"]

    out_p = {k: [] for k in PARTICLE_SETS}
    out_c = {k: [] for k in CONTACT_SETS}
    # Minimum-image shift of each contact (in cells of the original): j's image near i.
    ri = np.array([row[int(g)] for g in c["first"]], dtype=np.int64)
    rj = np.array([row[int(g)] for g in c["second"]], dtype=np.int64)
    shift = -np.rint(s[rj] - s[ri]).astype(np.int64) if nc else np.zeros((0, dim), np.int64)
    for ci, cc in enumerate(copies):
        cc = np.array(cc)
        out_p["id"].append(p["id"] + ci * stride)
        for k in PARTICLE_SETS[1:]:
            out_p[k].append(p[k])
        out_p["scaled_position"][-1] = (s + cc) / reps
        out_p["position"][-1] = out_p["scaled_position"][-1] * (L * reps)
        if nc == 0:
            continue
        # Copy of j: the copy cc + (wrap of s_j + shift) taken modulo the replication.
        cj = (cc + np.floor(s[rj] + shift).astype(np.int64)) % reps
        cj_index = np.ravel_multi_index(cj.T, reps)
        a = c["first"] + ci * stride
        b = c["second"] + cj_index * stride
        swap = a > b
        sign = np.where(swap, -1.0, 1.0)
        out_c["first"].append(np.where(swap, b, a))
        out_c["second"].append(np.where(swap, a, b))
        out_c["tangential_force"].append(c["tangential_force"] * sign[:, None])
        out_c["rolling"].append(c["rolling"] * sign[:, None])
        for k in ("normal_force", "flags", "age"):
            out_c[k].append(c[k])

    for k, v in src.attrs.items():
        dst.attrs[k] = v
    dst.attrs["n_particles"] = np.int64(n * ncopy)
    dst.attrs["n_contacts"] = np.int64(nc * ncopy)
    dst.attrs["kind"] = "configuration"
    src.copy("deck", dst)
    for group, names, data in (("particles", PARTICLE_SETS, out_p), ("contacts", CONTACT_SETS, out_c)):
        for k in names:
            arr = np.concatenate(data[k]) if data[k] else src[group + "/" + k][:]
            ds = dst.create_dataset(group + "/" + k, data=arr.astype(src[group + "/" + k].dtype))
            for ak, av in src[group + "/" + k].attrs.items():
                ds.attrs[ak] = av
    for k in ("length", "rate"):
        ds = dst.create_dataset("cell/" + k, data=src["cell/" + k][:] * reps)
        for ak, av in src["cell/" + k].attrs.items():
            ds.attrs[ak] = av


def main():
    if len(sys.argv) not in (5, 6):
        sys.exit(__doc__.strip().splitlines()[-1])
    reps = [int(x) for x in sys.argv[3:]]
    with h5py.File(sys.argv[1], "r") as src, h5py.File(sys.argv[2], "w") as dst:
        replicate(src, dst, reps)


if __name__ == "__main__":
    main()
