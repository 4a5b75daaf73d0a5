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
import argparse
import itertools

import numpy as np

import granpack_io as gio

PROG = "replicate.py"


def replicate(src, reps):
    """src: a granpack_io.Packing; returns (grains, contacts, cell lengths) of the copy."""
    dim = src.dimension
    if len(reps) != dim or any(k < 1 for k in reps):
        gio.fail(PROG, f"give {dim} factors >= 1, got {reps}")
    reps = np.array(reps)
    copies = list(itertools.product(*[range(k) for k in reps]))
    L = src.cell_length
    p, c = src.grains, src.contacts
    nc = src.nc
    stride = int(p["id"].max()) + 1
    s = p["scaled_position"]

    out_p = {k: [] for k in gio.PARTICLE_SETS}
    out_c = {k: [] for k in gio.CONTACT_SETS}
    # Minimum-image shift of each contact (in cells of the original): j's image near i.
    ri, rj = src.i, src.j
    shift = -np.rint(s[rj] - s[ri]).astype(np.int64) if nc else np.zeros((0, dim), np.int64)
    for ci, cc in enumerate(copies):
        cc = np.array(cc)
        out_p["id"].append(p["id"] + ci * stride)
        for k in gio.PARTICLE_SETS[1:]:
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
    grains = {k: np.concatenate(v).astype(p[k].dtype) for k, v in out_p.items()}
    contacts = {k: (np.concatenate(v) if v else c[k]).astype(c[k].dtype) for k, v in out_c.items()}
    return grains, contacts, L * reps


def main():
    ap = argparse.ArgumentParser(prog=PROG, description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("input", help="a granpack configuration or checkpoint (.h5)")
    ap.add_argument("output", help="the replicated configuration (.h5), overwritten")
    ap.add_argument("factors", type=int, nargs="+", help="KX KY [KZ]: copies along each axis")
    args = ap.parse_args()
    try:
        src = gio.read_packing(args.input)
    except gio.GranpackFileError as e:
        gio.fail(PROG, e)
    grains, contacts, length = replicate(src, args.factors)
    attrs = {k: v for k, v in src.raw_attrs.items() if k not in ("n_particles", "n_contacts")}
    attrs["kind"] = "configuration"
    gio.write_packing(args.output, src.dimension, length, grains, contacts, attrs=attrs,
                      deck=src.deck, cell_rate=src.cell_rate * np.array(args.factors),
                      parameters=src.raw_parameters)


if __name__ == "__main__":
    main()
