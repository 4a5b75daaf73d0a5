#!/usr/bin/python3
"""2D structures whose density correlations are known, written as granpack configuration files
(docs/hdf5-schema.md) for `granpack analyze` ([GRC] sec. V; docs/analysis.md, "Validation").

  bcca   ballistic cluster-cluster aggregation of n monodisperse disks in a periodic square cell
         at solid fraction Phi, run until one cluster is left (a gel): d_F = 1.55 +- 0.02
         ([GRC] sec. V D, after Jullien and Meakin). Clusters are picked with equal
         probability and move on straight lines in random directions until they touch another
         one, then stick rigidly.
  blobs  fractal blobs of a chosen number of disks (hierarchical ballistic cluster-cluster
         aggregation in free space: pairs of equal clusters collide on random straight lines),
         each rotated at random and placed at a random position in a periodic cell; `--overlap
         allow` places them independently (a Poisson set of blobs, whose I(k) is the blobs'
         own), `--overlap reject` refuses a placement where a disk overlaps a placed one.
         Known: the blobs' d_F = 1.515 +- 0.017 (mass-radius relation of 16 such blobs of 1024
         disks over their hierarchy, clusters of 16 to 1024 disks; bootstrap error) and their
         radius of gyration R_g; eq. (27) for one blob would have R_g^2 = d_F (d_F + 1) xi^2 / 2,
         so xi_eq27 = R_g (2 / (d_F (d_F + 1)))^(1/2) (the blobs' cut-off is not exactly
         exponential: the fitted xi is proportional to R_g with a factor that
         tests/cli/known_structures.sh measures).
  holes  a triangular lattice of disks at spacing 0.85 a (their union covers the plane: the
         covering radius 0.85/sqrt(3) a < a/2) with circular holes cut out: the disks whose
         centres lie within R + a/2 of a hole centre are removed, so each hole contains the
         disk of radius R and lies inside the disk of radius R + a/2 + 0.85 a/sqrt(3).
         Known: each hole's R_H (eq. 29) and <R>_w (eq. 30), computed here from the disks by a
         local raster twice as fine as `--check-mesh` (a/200 by default).

Each call writes OUT.h5 (no contacts, grains at rest; the deck in /deck names this tool) and
OUT.known.json with the known answers and the generator's own measurements.

  /usr/bin/python3 jobs/tools/known_structures.py bcca --n 1500 --phi 0.10 --seed 1 -o g.h5
  /usr/bin/python3 jobs/tools/known_structures.py blobs --blob 128 --count 12 --phi 0.08 -o b.h5
  /usr/bin/python3 jobs/tools/known_structures.py holes --radii 2 3.5 5 --cell 40 -o h.h5
"""
import argparse
import json
import math
import sys

import numpy as np

import granpack_io as gio

A = 1.0e-3  # disk diameter a (m); every length below is in units of a unless it says m
DENSITY = 2500.0


# ---------------------------------------------------------------------------------------------
# Ballistic motion: the distance a set of disks travels along u before one of them touches
# one of another set (all of diameter 1).

def contact_distance(moving, fixed, u, reach, box=None):
    """Smallest t in [0, reach] with |moving_i + t u - fixed_j| = 1 for some i, j (minimum
    image in `box` if given; valid while reach + 1 < box / 2), or inf."""
    best = math.inf
    chunk = max(1, 400000 // max(1, len(fixed)))
    for s in range(0, len(moving), chunk):
        b = fixed[None, :, :] - moving[s:s + chunk, None, :]
        if box is not None:
            b -= box * np.round(b / box)
        bu = b[..., 0] * u[0] + b[..., 1] * u[1]
        near = (bu > -1.0) & (bu < reach + 1.0)
        if not near.any():
            continue
        bu = bu[near]
        bb = (b[..., 0] ** 2 + b[..., 1] ** 2)[near]
        disc = bu * bu - bb + 1.0
        ok = disc >= 0
        if not ok.any():
            continue
        t = bu[ok] - np.sqrt(disc[ok])
        t = t[t >= -1e-9]
        if t.size:
            best = min(best, float(t.min()))
    return best if best <= reach else math.inf


def random_unit(rng):
    th = rng.uniform(0, 2 * math.pi)
    return np.array([math.cos(th), math.sin(th)])


def rotate(x, rng):
    th = rng.uniform(0, 2 * math.pi)
    c, s = math.cos(th), math.sin(th)
    return x @ np.array([[c, s], [-s, c]])


def gyration_radius(x):
    """R_g of a set of unit disks (their own gyration a^2/8 included)."""
    return math.sqrt(((x - x.mean(0)) ** 2).sum(1).mean() + 0.125)


# ---------------------------------------------------------------------------------------------
# bcca: periodic cell, one cluster in the end.

def sequential_gas(n, box, rng):
    """n non-overlapping unit disks placed one by one at random in a periodic square box."""
    x = np.empty((n, 2))
    cell = max(1, int(box // 1.0))
    size = box / cell
    grid = {}
    k = 0
    while k < n:
        p = rng.uniform(0, box, 2)
        ci, cj = int(p[0] // size) % cell, int(p[1] // size) % cell
        clash = False
        for di in (-1, 0, 1):
            for dj in (-1, 0, 1):
                for q in grid.get(((ci + di) % cell, (cj + dj) % cell), ()):
                    d = x[q] - p
                    d -= box * np.round(d / box)
                    if d @ d < 1.0:
                        clash = True
                        break
        if clash:
            continue
        x[k] = p
        grid.setdefault((ci, cj), []).append(k)
        k += 1
    return x


def bcca(n, phi, rng, log=None):
    box = math.sqrt(n * math.pi / 4 / phi)
    x = sequential_gas(n, box, rng)
    label = np.arange(n)
    members = {i: [i] for i in range(n)}
    reach = min(box / 2 - 1.5, 10.0)
    snapshot = []  # (N, R_g) of the clusters when n/4, n/16, n/64 clusters are left
    marks = {n // 4, n // 16, n // 64}
    while len(members) > 1:
        keys = list(members)
        c = keys[rng.integers(len(keys))]
        idx = np.array(members[c])
        others = np.flatnonzero(label != c)
        u = random_unit(rng)
        travelled = 0.0
        while True:
            t = contact_distance(x[idx], x[others], u, reach, box)
            if t < math.inf:
                x[idx] += t * u
                break
            x[idx] += reach * u
            travelled += reach
            if travelled > 50 * box:  # a direction that keeps missing: take another one
                u, travelled = random_unit(rng), 0.0
        # The cluster touched: merge every cluster it touches now (usually one).
        b = x[others][None, :, :] - x[idx][:, None, :]
        b -= box * np.round(b / box)
        touching = np.unique(label[others[((b ** 2).sum(2) < 1.0 + 1e-9).any(0)]])
        for o in touching:
            # Keep the merged cluster's coordinates unwrapped: shift the other cluster to the
            # image that touches this one.
            oi = np.array(members[o])
            d = x[oi][None, :, :] - x[idx][:, None, :]
            shift = d - box * np.round(d / box) - d
            hit = np.unravel_index(np.argmin(((d + shift) ** 2).sum(2)), shift.shape[:2])
            x[oi] += shift[hit]
            members[c].extend(members.pop(o))
            label[oi] = c
            idx = np.array(members[c])
        if len(members) in marks:
            marks.discard(len(members))
            snapshot += [(len(m), gyration_radius(x[m])) for m in members.values() if len(m) >= 4]
    if log:
        log(f"bcca: {n} disks, box {box:.2f} a, one cluster")
    return x % box, np.array([box, box]), snapshot


def mass_radius_dimension(pairs, smallest=16):
    """d_F from (N, R_g) of many clusters: clusters grouped by N in factors of sqrt(2), the
    slope of log N against log of the group's rms R_g over the groups with N >= smallest (a fit
    through the scattered single clusters would be biased low by their scatter in R_g), or None
    with fewer than 3 groups."""
    if not pairs:
        return None
    m = np.array(pairs)
    group = np.floor(2 * np.log2(m[:, 0])).astype(int)
    N, R = [], []
    for g in np.unique(group):
        s = m[group == g]
        if s[:, 0].min() >= smallest and len(s) >= 3:
            N.append(np.exp(np.log(s[:, 0]).mean()))
            R.append(math.sqrt((s[:, 1] ** 2).mean()))
    if len(N) < 3:
        return None
    return float(np.polyfit(np.log(R), np.log(N), 1)[0])


# ---------------------------------------------------------------------------------------------
# blobs: hierarchical ballistic aggregates in free space, placed in a periodic cell.

def hierarchical_blob(size, rng):
    """An aggregate of `size` (a power of 2) unit disks, centred on its centre of mass, and the
    (N, R_g) of every cluster made on the way."""
    clusters = [np.zeros((1, 2)) for _ in range(size)]
    history = []
    while len(clusters) > 1:
        merged = []
        for a, b in zip(clusters[0::2], clusters[1::2]):
            a = rotate(a - a.mean(0), rng)
            b = rotate(b - b.mean(0), rng)
            ra = np.sqrt((a ** 2).sum(1)).max() + 0.5
            rb = np.sqrt((b ** 2).sum(1)).max() + 0.5
            while True:  # B comes from far along -u with a random impact parameter; retry misses
                u = random_unit(rng)
                perp = np.array([-u[1], u[0]])
                start = -(ra + rb + 1.0) * u + rng.uniform(-(ra + rb), ra + rb) * perp
                t = contact_distance(b + start, a, u, 2 * (ra + rb + 1.0))
                if t < math.inf:
                    c = np.vstack([a, b + start + t * u])
                    break
            history.append((len(c), gyration_radius(c)))
            merged.append(c)
        clusters = merged
    x = clusters[0]
    return x - x.mean(0), history


def place_blobs(blob, count, phi, overlap, rng):
    n = blob * count
    box = math.sqrt(n * math.pi / 4 / phi)
    placed, rg2, history = [], [], []
    for _ in range(count):
        x, h = hierarchical_blob(blob, rng)
        history += h
        rg2.append(gyration_radius(x) ** 2)
        for _ in range(10000):
            y = rotate(x, rng) + rng.uniform(0, box, 2)
            if overlap == "allow" or not placed:
                break
            others = np.vstack(placed)
            d = y[:, None, :] - others[None, :, :]
            d -= box * np.round(d / box)
            if not ((d ** 2).sum(2) < 1.0).any():
                break
        else:
            sys.exit("known_structures.py: blobs: no room for another blob without overlap; lower --phi")
        placed.append(y)
    return np.vstack(placed) % box, np.array([box, box]), math.sqrt(np.mean(rg2)), history


# ---------------------------------------------------------------------------------------------
# holes: a covering lattice with holes cut out.

SPACING = 0.85


def lattice_with_holes(cell, radii, rng, check_mesh):
    nx = max(2, int(round(cell / SPACING)))
    ny = max(2, 2 * int(round(cell / (SPACING * math.sqrt(3)))))
    L = np.array([nx * SPACING, ny * SPACING * math.sqrt(3) / 2])
    i, j = np.meshgrid(np.arange(nx), np.arange(ny), indexing="ij")
    x = np.stack([(i + 0.5 * (j % 2)) * SPACING, j * SPACING * math.sqrt(3) / 2], -1).reshape(-1, 2)
    centres = []
    for R in radii:  # hole centres at random, holes (with their scallops) 2 a apart at least
        for _ in range(100000):
            c = rng.uniform(0, 1, 2) * L
            ok = all(np.linalg.norm((c - q) - L * np.round((c - q) / L)) > R + Rq + 2 * 0.5 + 2 * SPACING + 2
                     for q, Rq in centres)
            if ok and R + 0.5 + SPACING < min(L) / 2 - 1:
                break
        else:
            sys.exit("known_structures.py: holes: no room for the holes; enlarge --cell")
        centres.append((c, R))
    keep = np.ones(len(x), bool)
    for c, R in centres:
        d = x - c
        d -= L * np.round(d / L)
        keep &= (d ** 2).sum(1) > (R + 0.5) ** 2
    x = x[keep]
    # Each hole's R_H (eq. 29), from a raster of the disks around it at spacing check_mesh / 2,
    # each disk marking the nodes of its bounding box.
    h = check_mesh / 2
    holes = []
    for c, R in centres:
        ext = R + 0.5 + SPACING
        m = int(math.ceil(ext / h))
        g = (np.arange(2 * m + 1) - m) * h
        solid = np.zeros((len(g), len(g)), bool)
        d = x - c
        d -= L * np.round(d / L)
        for q in d[(np.abs(d) < ext + 1).all(1)]:
            i0, i1 = np.searchsorted(g, q[0] - 0.5), np.searchsorted(g, q[0] + 0.5)
            j0, j1 = np.searchsorted(g, q[1] - 0.5), np.searchsorted(g, q[1] + 0.5)
            gx, gy = np.meshgrid(g[i0:i1] - q[0], g[j0:j1] - q[1], indexing="ij")
            solid[i0:i1, j0:j1] |= gx ** 2 + gy ** 2 < 0.25
        gx, gy = np.meshgrid(g, g, indexing="ij")
        empty = ~solid & (gx ** 2 + gy ** 2 < ext ** 2)  # inside the bound: only this hole
        p = np.stack([gx[empty], gy[empty]], -1)
        RH = math.sqrt(2 * ((p - p.mean(0)) ** 2).sum(1).mean())
        holes.append({"centre_over_a": c.tolist(), "R_cut_over_a": R, "R_H_over_a": RH,
                      "area_over_a2": len(p) * h * h})
    w = np.array([q["area_over_a2"] for q in holes])
    Rw = float((w * np.array([q["R_H_over_a"] for q in holes])).sum() / w.sum())
    return x, L, holes, Rw


# ---------------------------------------------------------------------------------------------
# Output.

def deck_text(n, seed, command):
    return (f"# Generated by jobs/tools/known_structures.py ({command}): disks at rest, no contacts.\n"
            f"[sample]\ndimension = 2\nn = {n}\ndiameter = {A!r}\ndistribution = \"monodisperse\"\n"
            f"seed = {seed}\n\n[material]\ndensity = {DENSITY!r}\nnormal_law = \"linear\"\n"
            "normal_stiffness = 1.0e5\nfriction = 0.5\ndamping = 0.5\n\n"
            "[[stage]]\nkind = \"read\"\nfile = \"generated.h5\"\n")


def write_packing(path, x, L, seed, command):
    """x, L in units of a."""
    n = len(x)
    Lm = L * A
    s = (x / L) % 1.0
    r = np.full(n, A / 2)
    mass = DENSITY * math.pi * r ** 2  # per metre of thickness
    gio.write_packing(path, 2, Lm, {"id": np.arange(n, dtype=np.int64), "radius": r, "mass": mass,
                                    "inertia": mass * r ** 2 / 2, "scaled_position": s},
                      attrs={"granpack_version": "known_structures.py", "stage_name": "generated"},
                      deck=deck_text(n, seed, command))


def main(argv):
    ap = argparse.ArgumentParser(prog="known_structures.py", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="kind", required=True)
    p = sub.add_parser("bcca", help="ballistic cluster-cluster aggregation gel")
    p.add_argument("--n", type=int, default=1500)
    p.add_argument("--phi", type=float, default=0.10)
    p = sub.add_parser("blobs", help="fractal blobs of known size")
    p.add_argument("--blob", type=int, default=128, help="disks per blob (a power of 2)")
    p.add_argument("--count", type=int, default=12, help="number of blobs")
    p.add_argument("--phi", type=float, default=0.08)
    p.add_argument("--overlap", choices=["allow", "reject"], default="allow")
    p = sub.add_parser("holes", help="a covering lattice with circular holes")
    p.add_argument("--radii", type=float, nargs="+", default=[2.0, 3.5, 5.0], help="hole radii R / a")
    p.add_argument("--cell", type=float, default=40.0, help="cell side / a (rounded to the lattice)")
    p.add_argument("--check-mesh", type=float, default=0.01, help="mesh spacing / a of the analysis")
    for p in sub.choices.values():
        p.add_argument("--seed", type=int, default=1)
        p.add_argument("-o", "--output", required=True, help="OUT.h5 (and OUT.known.json)")
    args = ap.parse_args(argv)
    rng = np.random.default_rng(args.seed)
    command = " ".join([args.kind] + [f"--{k.replace('_', '-')} " + (" ".join(map(str, v)) if isinstance(v, list) else str(v))
                                      for k, v in vars(args).items() if k not in ("kind", "output")])
    known = {"kind": args.kind, "command": command, "seed": args.seed}
    if args.kind == "bcca":
        x, L, snapshot = bcca(args.n, args.phi, rng)
        # The mass-radius d_F of the clusters on the way (a check of the generator: 1.54-1.56
        # at Phi = 0.03, n = 3000; at Phi >= 0.05 the clusters crowd before they grow large).
        known.update({"d_F": 1.55, "d_F_error": 0.02, "d_F_source": "[GRC] sec. V D (BCCA, 2D)",
                      "d_F_mass_radius": mass_radius_dimension(snapshot)})
    elif args.kind == "blobs":
        if args.blob < 2 or args.blob & (args.blob - 1):
            ap.error("--blob must be a power of 2")
        x, L, rg, history = place_blobs(args.blob, args.count, args.phi, args.overlap, rng)
        d = 1.515
        known.update({"d_F": d, "d_F_error": 0.017,
                      "d_F_source": "mass-radius of hierarchical BCCA, 16 blobs of 1024 disks",
                      "d_F_mass_radius_this_sample": mass_radius_dimension(history),
                      "R_g_over_a": rg, "xi_eq27_over_a": rg * math.sqrt(2 / (d * (d + 1))),
                      "blob": args.blob, "count": args.count, "overlap": args.overlap})
    else:
        x, L, holes, Rw = lattice_with_holes(args.cell, args.radii, rng, args.check_mesh)
        known.update({"R_w_over_a": Rw, "holes": holes, "lattice_spacing_over_a": SPACING})
    known.update({"n": len(x), "phi": len(x) * math.pi / 4 / float(L[0] * L[1]), "L_over_a": L.tolist()})
    write_packing(args.output, x, L, args.seed, command)
    stem = args.output[:-3] if args.output.endswith(".h5") else args.output
    with open(stem + ".known.json", "w") as f:
        json.dump(known, f, indent=1)
    print(json.dumps({k: v for k, v in known.items() if k != "holes"}))


if __name__ == "__main__":
    main(sys.argv[1:])
