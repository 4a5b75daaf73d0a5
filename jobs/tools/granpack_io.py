"""granpack_io: every granpack file read into numpy arrays with names and units (h5py + numpy).

    import sys; sys.path.insert(0, "jobs/tools")        # this file's directory
    import granpack_io as gio
    p = gio.read_packing("out/main/final.h5")            # grains, contacts, cell, parameters
    print(p.n, p.nc, p.units["contacts/normal_force"], p.coordination().mean())
    net = p.net_force()                                  # (n, dim) N: ~0 on non-rattlers

What it reads (docs/visualisation.md, "The Python reader"; the files: docs/hdf5-schema.md,
docs/report.md, docs/analysis.md, docs/stiffness.md):
  read_packing(FILE.h5)     configurations, checkpoints, postmortems -> Packing
  read_analysis(FILE)       `granpack analyze --json/--h5` output -> nested dict (curves as arrays)
  read_report(report.json)  stages of a run -> Report (stage table as arrays, with units)
  read_stiffness(FILE.json) `granpack stiffness --json` -> dict, modes as id arrays
  read_ensemble(ensemble.json) -> dict
  read_bench(FILE.json)     `granpack bench --json` -> dict (units in BENCH_UNITS)
  read(FILE)                any of the above, chosen by the file's content
  write_packing(FILE.h5, ...) a granpack configuration from arrays (synthetic structures, copies)

Errors in the input raise GranpackFileError naming the file and the object (exit code 2 in the
tools through `fail`). Rows of a packing stay in file order; `p.row_of(ids)` maps ids to rows.

The tools of jobs/tools and jobs/bench read granpack's files only through these functions (no
json.load or h5py of their own). From a shell script (jobs/bench/run_bench.sh):
  python3 jobs/tools/granpack_io.py value FILE KEY   # repr() of a top-level value of FILE
"""
import argparse
import json
import math
from pathlib import Path

import numpy as np

try:
    import h5py
except ImportError:  # pragma: no cover - Debian: apt-get install python3-h5py
    h5py = None

DISTANT = 4  # /contacts/flags bits (include/granpack/core/contact_store.h)
SLIDING = 1
ROLLING_PLASTIC = 2

PARTICLE_SETS = ("id", "radius", "mass", "inertia", "scaled_position", "position", "velocity",
                 "angular_velocity", "orientation")
CONTACT_SETS = ("first", "second", "normal_force", "tangential_force", "rolling", "flags", "age")

# Units of the stored datasets (docs/hdf5-schema.md); 2D forces are per metre of thickness.
UNITS = {
    "cell/length": "m", "cell/rate": "m/s",
    "particles/id": "1", "particles/radius": "m", "particles/mass": "kg",
    "particles/inertia": "kg m^2", "particles/scaled_position": "1", "particles/position": "m",
    "particles/velocity": "m/s", "particles/angular_velocity": "rad/s",
    "particles/orientation": "rad (2D) / 1 (3D quaternion w, x, y, z)",
    "contacts/first": "1", "contacts/second": "1", "contacts/normal_force": "N",
    "contacts/tangential_force": "N", "contacts/rolling": "rad", "contacts/flags": "1",
    "contacts/age": "steps", "time": "s", "step": "1",
}
# Units of what Packing derives (methods and properties of the same name).
DERIVED_UNITS = {
    "branch": "m", "distance": "m", "normal": "1", "overlap": "m", "attraction": "N",
    "total_normal_force": "N", "contact_force": "N", "tangential_magnitude": "N",
    "coordination": "1", "cluster_ids": "1", "net_force": "N", "net_moment": "N m", "stress": "Pa",
    "pressure": "Pa", "phi": "1", "volume": "m^dim",
}
# Units of what read_modes gives (its dict's keys; "divalent_grains/..." for that dict's). A
# mode is a shape: (u, ell theta) has unit norm, so u is per unit amplitude (1) and theta per
# metre of amplitude (rad/m); eigenvalues are over <k_n>.
MODES_UNITS = {
    "eigenvalues": "1 (over mean_kn)", "id": "1", "position": "m", "radius": "m",
    "backbone": "1", "displacement": "1 (per unit mode amplitude)",
    "rotation": "rad/m (per unit mode amplitude)", "rotation_length": "m", "mean_kn": "N/m",
    "dimension": "1", "cell_length": "m", "divalent": "1",
    "divalent_grains/grain": "1", "divalent_grains/neighbours": "1",
    "divalent_grains/contact_points": "m",
    "divalent_grains/displacement": "1 (per unit mode amplitude)",
    "divalent_grains/rotation": "rad/m (per unit mode amplitude)",
}
# Units of `granpack bench --json` (src/app/bench.cpp, docs/performance.md): times are wall
# seconds of the timed steps (forces_max: the slowest rank's; forces_step_max: the sum over the
# steps of each step's slowest force pass), skin the Verlet skin in metres.
BENCH_UNITS = {"code": "text", "n": "1", "ranks": "1", "steps": "1", "dt": "s", "skin": "m",
               "wall": "s", "particle_steps_per_s_per_rank": "1/s", "forces": "s",
               "forces_max": "s", "forces_step_max": "s", "neighbor": "s", "comm": "s",
               "integrate": "s", "rebuilds": "1", "static_pressure": "Pa",
               "static_contacts": "1", "rss_max_bytes": "B", "bytes_per_grain": "B",
               "ghosts": "1", "ghosts_max": "1", "owned_max": "1"}
# Units of the report's stage entries (docs/report.md).
STAGE_UNITS = {"steps": "1", "time": "s", "phi": "1", "pressure": "Pa", "kappa": "1",
               "inertia_max": "1", "z": "1", "z_star": "1", "x0": "1", "x2": "1", "z2": "1",
               "wall_seconds": "s", "equilibrated": "bool"}


class GranpackFileError(Exception):
    """A file that is missing, unreadable or not what it should be; the message names it."""


def fail(prog, error, code=2):
    """For tools: prints `prog: error: message` on stderr and exits with `code` (2: bad input)."""
    import sys
    print(f"{prog}: error: {error}", file=sys.stderr)
    sys.exit(code)


def _need_h5py():
    if h5py is None:
        raise GranpackFileError("h5py is not installed (Debian: apt-get install python3-h5py)")


def _open_h5(path):
    _need_h5py()
    p = Path(path)
    if not p.exists():
        raise GranpackFileError(f"{path}: no such file")
    try:
        return h5py.File(p, "r")
    except OSError as e:
        raise GranpackFileError(f"{path}: not a readable HDF5 file ({e})") from None


def _text(v):
    if isinstance(v, bytes):
        return v.rstrip(b"\0").decode("utf-8", errors="replace")
    if isinstance(v, np.ndarray) and v.shape == ():
        return _text(v[()])
    return str(v)


def _attr_value(v):
    if isinstance(v, bytes):
        return _text(v)
    if isinstance(v, np.generic):
        return v.item()
    return v


class Packing:
    """One granpack configuration (or checkpoint) in numpy arrays. Attributes:
    path, dimension, kind, time (s), step, stage_index, stage_name, version, attrs (all root
    attributes), cell_length (m), cell_rate (m/s), grains and contacts (dicts of arrays named as
    the datasets, file order), parameters (dict of /parameters, None in older files), deck (text),
    run_state (dict, checkpoints only), network (the /network datasets, {} if none), units
    (dataset -> unit). Derived quantities follow the
    sign conventions of docs/hdf5-schema.md: the normal n points from `first` to `second`, the
    force f = (N^e + N^a) n + T acts on `second`, -f on `first`."""

    def __init__(self, path, f):
        self.path = str(path)
        a = {k: _attr_value(v) for k, v in f.attrs.items()}
        if a.get("format") != "granpack":
            raise GranpackFileError(f"{path}: not a granpack file (no root attribute format = "
                                    "\"granpack\")")
        for k in ("dimension", "kind", "time", "step"):
            if k not in a:
                raise GranpackFileError(f"{path}: missing root attribute {k}")
        self.attrs = a
        self.raw_attrs = dict(f.attrs)  # numpy types kept: for write_packing
        self.dimension = int(a["dimension"])
        if self.dimension not in (2, 3):
            raise GranpackFileError(f"{path}: root attribute dimension = {self.dimension} "
                                    "(2 or 3 expected)")
        self.kind, self.time, self.step = a["kind"], float(a["time"]), int(a["step"])
        self.stage_index = int(a.get("stage_index", 0))
        self.stage_name = a.get("stage_name", "")
        self.version = a.get("granpack_version", "")
        self.units = dict(UNITS)
        self.cell_length = self._read(f, "cell/length").astype(float)
        self.cell_rate = self._read(f, "cell/rate").astype(float)
        if self.cell_length.shape != (self.dimension,) or not np.all(self.cell_length > 0):
            raise GranpackFileError(f"{path}: /cell/length is not {self.dimension} positive lengths")
        self.grains = {k: self._read(f, "particles/" + k) for k in PARTICLE_SETS}
        self.contacts = {k: self._read(f, "contacts/" + k) for k in CONTACT_SETS}
        for k, v in self.grains.items():
            if len(v) != len(self.grains["id"]):
                raise GranpackFileError(f"{path}: /particles/{k} has {len(v)} rows, "
                                        f"/particles/id {len(self.grains['id'])}")
        for k, v in self.contacts.items():
            if len(v) != len(self.contacts["first"]):
                raise GranpackFileError(f"{path}: /contacts/{k} has {len(v)} rows, "
                                        f"/contacts/first {len(self.contacts['first'])}")
        # Optional datasets written by newer versions (e.g. /contacts/branch) are kept too.
        for group, store in (("particles", self.grains), ("contacts", self.contacts)):
            for k in f.get(group, {}):
                if k not in store and isinstance(f[group][k], h5py.Dataset):
                    store[k] = f[group][k][()]
                    unit = f[group][k].attrs.get("unit")
                    if unit is not None:
                        self.units[f"{group}/{k}"] = _text(unit)
        # /network (configurations written by granpack run: docs/hdf5-schema.md): {} if absent.
        self.network = {}
        for k, v in (f["network"].items() if "network" in f else ()):
            self.network[k] = v[()]
            if "unit" in v.attrs:
                self.units["network/" + k] = _text(v.attrs["unit"])
        self.raw_parameters = dict(f["parameters"].attrs) if "parameters" in f else None
        self.parameters = ({k: _attr_value(v) for k, v in self.raw_parameters.items()}
                           if self.raw_parameters is not None else None)
        self.deck = _text(f["deck"][()]) if "deck" in f else ""
        self.run_state = json.loads(_text(f["run_state"][()])) if "run_state" in f else None
        self.i = self.row_of(self.contacts["first"], "/contacts/first")
        self.j = self.row_of(self.contacts["second"], "/contacts/second")

    def _read(self, f, name):
        if name not in f:
            raise GranpackFileError(f"{self.path}: missing dataset /{name}")
        try:
            return f[name][()]
        except (OSError, ValueError, TypeError) as e:
            raise GranpackFileError(f"{self.path}: cannot read /{name} ({e})") from None

    # --- sizes and lookup -----------------------------------------------------------------
    @property
    def n(self):
        return len(self.grains["id"])

    @property
    def nc(self):
        return len(self.contacts["first"])

    def row_of(self, ids, what="ids"):
        """Rows of the grains with these global ids (GranpackFileError for an unknown id)."""
        ids = np.asarray(ids, dtype=np.int64)
        order = np.argsort(self.grains["id"], kind="stable")
        sorted_ids = self.grains["id"][order]
        k = np.clip(np.searchsorted(sorted_ids, ids), 0, max(self.n - 1, 0))
        if ids.size and (self.n == 0 or not np.all(sorted_ids[k] == ids)):
            bad = ids[sorted_ids[k] != ids][:3] if self.n else ids[:3]
            raise GranpackFileError(f"{self.path}: {what} holds ids not in /particles/id "
                                    f"(e.g. {bad.tolist()})")
        return order[k]

    # --- geometry -------------------------------------------------------------------------
    @property
    def volume(self):
        return float(np.prod(self.cell_length))

    @property
    def radius(self):
        return self.grains["radius"].astype(float)

    @property
    def diameter(self):
        """a: the largest diameter (the length unit of [AR] and [GRC])."""
        return 2.0 * float(self.radius.max()) if self.n else 0.0

    @property
    def phi(self):
        r = self.radius
        v = math.pi * r ** 2 if self.dimension == 2 else 4.0 / 3.0 * math.pi * r ** 3
        return float(v.sum()) / self.volume

    @property
    def branch(self):
        """r_12 = minimum-image vector from `first` to `second` (nc, dim), m."""
        s = self.grains["scaled_position"].astype(float)
        d = s[self.j] - s[self.i]
        return (d - np.round(d)) * self.cell_length

    @property
    def distance(self):
        return np.sqrt((self.branch ** 2).sum(axis=1))

    @property
    def normal(self):
        d = self.distance
        return self.branch / np.where(d > 0, d, 1.0)[:, None]

    @property
    def overlap(self):
        """h = R_1 + R_2 - |r_12| (negative: the gap of a distant pair), m."""
        r = self.radius
        return r[self.i] + r[self.j] - self.distance

    @property
    def distant(self):
        return (self.contacts["flags"].astype(np.int64) & DISTANT) != 0

    @property
    def sliding(self):
        return (self.contacts["flags"].astype(np.int64) & SLIDING) != 0

    # --- forces ---------------------------------------------------------------------------
    def law(self):
        """The contact law and stress target in force: /parameters, or for files written before
        it existed the stored deck's [material] with its `set` stages up to stage_index replayed
        (friction, cohesion; docs/hdf5-schema.md, "Parameters"). Numbers, 0 where unknown."""
        if self.parameters:
            return self.parameters
        if not hasattr(self, "_replayed"):
            self._replayed = replay_deck(self.deck, self.stage_index)
        return self._replayed

    def _param(self, key):
        v = self.law().get(key, 0.0)
        return float(v) if isinstance(v, (int, float)) and not isinstance(v, bool) else 0.0

    @property
    def attraction(self):
        """N^a of [GRC] eq. 4-5: -F0 in contact, -F0 (1 - g/D0) across a gap g; 0 without
        cohesion (or in files without /parameters)."""
        f0, d0 = self._param("cohesion_force"), self._param("cohesion_range")
        if f0 == 0:
            return np.zeros(self.nc)
        gap = -self.overlap
        far = -f0 * np.clip(1.0 - gap / d0, 0.0, 1.0) if d0 > 0 else np.zeros(self.nc)
        return np.where(self.distant, far, -f0)

    @property
    def total_normal_force(self):
        """N = N^e + N^a (> 0 repulsive, < 0 attractive), N."""
        return self.contacts["normal_force"].astype(float) + self.attraction

    @property
    def tangential_magnitude(self):
        return np.sqrt((self.contacts["tangential_force"].astype(float) ** 2).sum(axis=1))

    @property
    def contact_force(self):
        """f = N n + T exerted by `first` on `second` (nc, dim), N."""
        return self.total_normal_force[:, None] * self.normal + \
            self.contacts["tangential_force"].astype(float)

    def coordination(self, carrying_only=False):
        """Contacts per grain (distant pairs excluded); carrying_only: N^e > 0 only."""
        keep = ~self.distant
        if carrying_only:
            keep &= self.contacts["normal_force"] > 0
        return (np.bincount(self.i[keep], minlength=self.n) +
                np.bincount(self.j[keep], minlength=self.n))

    def cluster_ids(self):
        """Each grain's cluster in the stored interaction network (every contact, distant
        cohesive pairs included): the smallest id among the grains joined to it, as
        /network/cluster_id. Returns an int64 array (n)."""
        label = self.grains["id"].astype(np.int64).copy()
        while True:  # each pass moves the smallest id one contact further
            m = np.minimum(label[self.i], label[self.j])
            new = label.copy()
            np.minimum.at(new, self.i, m)
            np.minimum.at(new, self.j, m)
            if np.array_equal(new, label):
                return label
            label = new

    def net_force(self):
        """Sum of the contact forces on each grain (n, dim), N (viscous parts not stored)."""
        f = self.contact_force
        net = np.zeros((self.n, self.dimension))
        np.add.at(net, self.j, f)
        np.add.at(net, self.i, -f)
        return net

    def net_moment(self):
        """Sum of the static contact moments about each grain's centre, N m: (n, 3) in 3D, (n,)
        in 2D (about z). Each contact force acts at the middle of the overlap, at (R - h/2) n
        from the centres (the dynamics' branch vectors), plus [GRC]'s rolling moment -K_r
        dtheta on `second` (+K_r dtheta on `first`; K_r from law()), as /network/net_moment."""
        f, n = self.contact_force, self.normal
        h = self.overlap
        arm_i = (self.radius[self.i] - 0.5 * h)[:, None] * n      # centre of first -> point
        arm_j = -(self.radius[self.j] - 0.5 * h)[:, None] * n     # centre of second -> point
        gamma = -self._param("rolling_stiffness") * self.contacts["rolling"].astype(float)
        if self.dimension == 2:
            def cross(b, g):  # about z
                return b[:, 0] * g[:, 1] - b[:, 1] * g[:, 0]
            gamma = gamma.reshape(-1)
            net = np.zeros(self.n)
        else:
            cross = np.cross
            net = np.zeros((self.n, 3))
        np.add.at(net, self.j, cross(arm_j, f) + gamma)
        np.add.at(net, self.i, cross(arm_i, -f) - gamma)
        return net

    def stress(self):
        """Static stress sigma = (1/V) sum f (x) r_12 (dim, dim), Pa."""
        return np.einsum("ka,kb->ab", self.contact_force, self.branch) / self.volume

    @property
    def pressure(self):
        return float(np.trace(self.stress())) / self.dimension

    def carrying(self, threshold=1e-4):
        """Contacts that carry force ([AR] sec. III B): N^e > threshold x a^(dim-1) P, P the
        file's pressure_target, else the measured pressure; distant pairs never do. Bool (nc)."""
        p = self._param("pressure_target") or abs(self.pressure)
        cut = threshold * self.diameter ** (self.dimension - 1) * p
        return (self.contacts["normal_force"] > cut) & ~self.distant

    def rattlers(self, threshold=1e-4, min_contacts=None):
        """The iterative rattler rule of [AR] sec. III B: a contact carries force when N^e >
        threshold x a^(dim-1) P (P the file's pressure_target, else the measured pressure);
        grains with fewer than min_contacts (dim + 1 without friction, 2 with: derived from
        /parameters friction) carrying contacts with non-rattlers are rattlers, iterated.
        Returns a bool array (n)."""
        if min_contacts is None:
            mu = self._param("friction")
            min_contacts = self.dimension + 1 if mu == 0 else 2
        keep = self.carrying(threshold)
        i, j = self.i[keep], self.j[keep]
        alive = np.ones(self.n, bool)
        while True:
            both = alive[i] & alive[j]
            count = np.bincount(i[both], minlength=self.n) + np.bincount(j[both], minlength=self.n)
            still = alive & (count >= min_contacts)
            if np.array_equal(still, alive):
                return ~alive
            alive = still


def replay_deck(deck_text, stage_index):
    """friction, cohesion_force, cohesion_range, damping of a stored deck's [material] after its
    `set` stages up to stage_index; {} if the deck is not valid TOML."""
    import tomllib
    try:
        deck = tomllib.loads(deck_text)
    except tomllib.TOMLDecodeError:
        return {}
    mat = deck.get("material") if isinstance(deck.get("material"), dict) else {}
    keys = ("friction", "cohesion_force", "cohesion_range", "damping")
    law = {k: mat[k] for k in keys if isinstance(mat.get(k), (int, float))}
    stages = deck.get("stage") if isinstance(deck.get("stage"), list) else []
    for st in stages[:stage_index + 1]:
        if isinstance(st, dict) and st.get("kind") == "set":
            law.update({k: st[k] for k in keys if isinstance(st.get(k), (int, float))})
    return law


def read_packing(path):
    """A granpack configuration, checkpoint or postmortem (.h5) -> Packing."""
    with _open_h5(path) as f:
        return Packing(path, f)


class Trajectory:
    """The snapshots of OUT/trajectory.h5 ([output] trajectory_every, docs/visualisation.md).
    Attributes: path, dimension, deck (text), steps and times (arrays, in step order), groups
    (the snapshots' HDF5 groups). len(t) snapshots; t[k] (or t.at_step(s)) reads snapshot k as a
    Packing (whose deck is the file's); iterating gives every snapshot in turn."""

    def __init__(self, path, f):
        self.path = str(path)
        a = {k: _attr_value(v) for k, v in f.attrs.items()}
        if a.get("format") != "granpack" or a.get("kind") != "trajectory":
            raise GranpackFileError(f"{path}: not a granpack trajectory (root attributes format = "
                                    "\"granpack\", kind = \"trajectory\" expected)")
        self.dimension = int(a.get("dimension", 0))
        self.deck = _text(f["deck"][()]) if "deck" in f else ""
        if "snapshots" not in f:
            raise GranpackFileError(f"{path}: missing group /snapshots")
        names = sorted(f["snapshots"].keys())
        self.groups = ["/snapshots/" + k for k in names]
        try:
            self.steps = np.array([int(f[g].attrs["step"]) for g in self.groups], dtype=np.int64)
            self.times = np.array([float(f[g].attrs["time"]) for g in self.groups], dtype=float)
        except KeyError as e:
            raise GranpackFileError(f"{path}: a snapshot without the attribute {e}") from None

    def __len__(self):
        return len(self.groups)

    def __getitem__(self, k):
        g = self.groups[k]
        with _open_h5(self.path) as f:
            p = Packing(f"{self.path}:{g}", f[g])
        p.deck = self.deck
        return p

    def __iter__(self):
        return (self[k] for k in range(len(self)))

    def at_step(self, step):
        k = np.flatnonzero(self.steps == step)
        if not k.size:
            raise GranpackFileError(f"{self.path}: no snapshot at step {step} "
                                    f"(steps {self.steps.tolist()[:10]})")
        return self[int(k[0])]


def read_trajectory(path):
    """A trajectory file (OUT/trajectory.h5) -> Trajectory."""
    with _open_h5(path) as f:
        return Trajectory(path, f)


def _h5_to_dict(g):
    out = {k: _attr_value(v) for k, v in g.attrs.items()}
    for k, item in g.items():
        out[k] = _h5_to_dict(item) if isinstance(item, h5py.Group) else item[()]
    return out


def _arrays(x):
    """Lists of numbers (and of equal-length number lists) become numpy arrays, recursively."""
    if isinstance(x, dict):
        return {k: _arrays(v) for k, v in x.items()}
    if isinstance(x, list):
        if x and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in x):
            return np.asarray(x, dtype=float)
        if x and all(isinstance(v, list) for v in x):
            try:
                a = np.asarray(x, dtype=float)
                if a.ndim == 2:
                    return a
            except (TypeError, ValueError):
                pass
        return [_arrays(v) for v in x]
    return x


def _read_json(path):
    p = Path(path)
    if not p.exists():
        raise GranpackFileError(f"{path}: no such file")
    try:
        text = p.read_text()
    except (OSError, UnicodeDecodeError) as e:
        raise GranpackFileError(f"{path}: cannot read ({e})") from None
    try:
        return json.loads(text)
    except json.JSONDecodeError as e:
        raise GranpackFileError(f"{path}: not JSON ({e})") from None


def read_analysis(path, arrays=True):
    """`granpack analyze` output, --json (JSON) or --h5 (HDF5, io/json_hdf5.h) -> nested dict;
    curves and histograms as numpy arrays (g_r, z_h, P_f, x_i, order, density ...); the keys,
    and their units, of docs/analysis.md. arrays=False: a JSON file's lists stay lists (for
    tools that check each value themselves)."""
    if str(path).endswith((".h5", ".hdf5")):
        with _open_h5(path) as f:
            if f.attrs.get("format") == "granpack":
                raise GranpackFileError(f"{path}: a packing, not an analysis (use read_packing)")
            return _h5_to_dict(f)
    d = _read_json(path)
    if not isinstance(d, dict):
        raise GranpackFileError(f"{path}: not an analysis (a JSON object expected)")
    return _arrays(d) if arrays else d


def read_modes(path):
    """`granpack stiffness --modes K --modes-file FILE.h5` (docs/stiffness.md) -> dict:
    'eigenvalues' (K, over <k_n>, ascending), 'id', 'position' (n, dim; m), 'radius', 'backbone'
    (n, bool: off the backbone a grain is at rest in every mode), 'displacement' (K, n, dim),
    'rotation' (K, n, 3 in 3D, K, n in 2D; rad; None without rotations), 'rotation_length'
    (ell: each mode has unit norm in (u, theta ell)), 'mean_kn', 'dimension', 'cell_length'
    (dim; m; None in files written before it), 'divalent' (n, bool) and, when the packing has
    divalent grains (3D, friction), 'divalent_grains': a dict of 'grain' (m ids), 'neighbours'
    (m, 2 ids, ascending), 'contact_points' (m, 2, 3: from the grain's centre, m, in the order
    of the neighbours), 'displacement' and 'rotation' (n, 3: every divalent grain's free
    rolling about the line through its two contact points, each of unit norm in (u, theta ell),
    every other grain at rest); None without; 'units' (key -> unit, a copy of MODES_UNITS:
    the file itself, JSON stored as HDF5, carries no unit attributes)."""
    with _open_h5(path) as f:
        if _text(f.attrs.get("kind", "")) != "stiffness_modes":
            raise GranpackFileError(f"{path}: not a stiffness modes file (kind != stiffness_modes)")
        d = _h5_to_dict(f)
    m, g = d["modes"], d["grains"]
    k = len(m["eigenvalue_over_mean_kn"])
    rot = [m[str(i)].get("rotation") for i in range(k)]
    n = len(g["id"])
    divalent = None
    if "divalent" in d:
        v = d["divalent"]
        divalent = {"grain": np.asarray(v["grain"]).astype(np.int64),
                    "neighbours": np.asarray(v["neighbours"]).astype(np.int64).reshape(-1, 2),
                    "contact_points": np.asarray(v["contact_points"]).reshape(-1, 2, 3),
                    "displacement": np.asarray(v["rolling"]["displacement"]),
                    "rotation": np.asarray(v["rolling"]["rotation"])}
    return {"eigenvalues": np.asarray(m["eigenvalue_over_mean_kn"]),
            "id": np.asarray(g["id"]).astype(np.int64), "position": np.asarray(g["position"]),
            "radius": np.asarray(g["radius"]), "backbone": np.asarray(g["backbone"]) == 1,
            "displacement": np.array([m[str(i)]["displacement"] for i in range(k)]),
            "rotation": None if k == 0 or rot[0] is None else np.array(rot),
            "rotation_length": float(d["rotation_length"]), "mean_kn": float(d["mean_kn"]),
            "dimension": int(d["dimension"]),
            "cell_length": np.asarray(d["cell_length"]) if "cell_length" in d else None,
            "divalent": (np.asarray(g["divalent"]) == 1 if "divalent" in g
                         else np.zeros(n, dtype=bool)),
            "divalent_grains": divalent, "units": dict(MODES_UNITS)}


class Report:
    """report.json of a run: raw (the dict), stages (list of dicts) and stage_table()."""

    def __init__(self, path, raw):
        self.path, self.raw = str(path), raw
        if not isinstance(raw.get("stages"), list):
            raise GranpackFileError(f"{path}: no 'stages' list (not a granpack report.json)")
        self.stages = raw["stages"]
        self.units = dict(STAGE_UNITS)

    def stage_table(self):
        """Per-stage arrays: name, kind (str arrays) and every number of STAGE_UNITS (NaN where
        null or absent)."""
        t = {"name": np.array([s.get("name", "") for s in self.stages]),
             "kind": np.array([s.get("kind", "") for s in self.stages])}
        for k in STAGE_UNITS:
            t[k] = np.array([np.nan if s.get(k) is None else float(s[k]) for s in self.stages])
        return t


def read_report(path):
    """report.json of `granpack run` -> Report."""
    raw = _read_json(path)
    if not isinstance(raw, dict):
        raise GranpackFileError(f"{path}: not a granpack report.json")
    return Report(path, raw)


def read_stiffness(path):
    """`granpack stiffness --json` -> dict (docs/stiffness.md); its grain lists as int64 arrays:
    'modes' (other_mechanism_grains: one id array per unexpected mechanism), 'rattler_ids'
    (rattler_grains) and 'divalent_ids' (the divalent grains, first id of each divalent_grains
    entry)."""
    d = _read_json(path)
    if not isinstance(d, dict) or "mechanisms" not in d:
        raise GranpackFileError(f"{path}: no 'mechanisms' (not a granpack stiffness JSON)")
    d["modes"] = [np.asarray(m, dtype=np.int64) for m in d.get("other_mechanism_grains") or []]
    d["rattler_ids"] = np.asarray(d.get("rattler_grains") or [], dtype=np.int64)
    div = d.get("divalent_grains") or []
    d["divalent_ids"] = np.asarray([e[0] if isinstance(e, list) else
                                    e.get("grain", -1) if isinstance(e, dict) else e
                                    for e in div], dtype=np.int64)
    return d


def mode_field(packing, modes):
    """Per grain of `packing`: the index of the first mode (list of id arrays) it belongs to,
    -1 if none; a field to colour grains by mechanism."""
    field = np.full(packing.n, -1, dtype=np.int64)
    for k, ids in enumerate(modes):
        rows = packing.row_of(ids, f"mode {k}")
        field[rows] = np.where(field[rows] < 0, k, field[rows])
    return field


def read_ensemble(path):
    """ensemble.json of `granpack ensemble` (docs/cli.md, docs/ar-tables.md) -> dict as stored:
    'format' ("granpack-ensemble"), 'format_version', 'report' and 'analysis' (per configuration
    stem, per JSON pointer of report.json or the analysis: the per-sample 'values' with 'mean',
    'sd', in the unit of the quantity they collect, docs/report.md and docs/analysis.md)."""
    d = _read_json(path)
    if not isinstance(d, dict) or d.get("format") != "granpack-ensemble":
        raise GranpackFileError(f"{path}: not a granpack ensemble file (\"format\" must be "
                                "\"granpack-ensemble\")")
    return d


def read_bench(path):
    """`granpack bench --json` (docs/cli.md) -> dict as stored: n, ranks, steps, dt, skin,
    wall, particle_steps_per_s_per_rank, the phases' seconds (forces, forces_max,
    forces_step_max, neighbor, comm, integrate), rebuilds, static_pressure, bytes_per_grain ...
    (units: BENCH_UNITS; older files lack some keys)."""
    d = _read_json(path)
    if not isinstance(d, dict) or "particle_steps_per_s_per_rank" not in d:
        raise GranpackFileError(f"{path}: no 'particle_steps_per_s_per_rank' (not a "
                                "`granpack bench --json` file)")
    return d


def read(path):
    """Any granpack file, by content: a packing (.h5 with format = granpack), an analysis (.h5
    otherwise, or JSON with 'phi'), `stiffness --modes` fields (.h5, kind = stiffness_modes), a
    report (JSON with 'stages'), a stiffness result (JSON with 'mechanisms'), an ensemble (JSON
    with format = granpack-ensemble) or a bench result (JSON with
    'particle_steps_per_s_per_rank')."""
    if str(path).endswith((".h5", ".hdf5")):
        with _open_h5(path) as f:
            if f.attrs.get("format") == "granpack":
                if _text(f.attrs.get("kind", "")) == "trajectory":
                    return Trajectory(path, f)
                return Packing(path, f)
            modes = _text(f.attrs.get("kind", "")) == "stiffness_modes"
        return read_modes(path) if modes else read_analysis(path)
    d = _read_json(path)
    if isinstance(d, dict):
        if d.get("format") == "granpack-ensemble":
            return d
        if isinstance(d.get("stages"), list):
            return Report(path, d)
        if "mechanisms" in d:
            return read_stiffness(path)
        if "particle_steps_per_s_per_rank" in d:
            return d
        return _arrays(d)
    raise GranpackFileError(f"{path}: not a granpack JSON file (an object expected)")


def write_packing(path, dimension, cell_length, grains, contacts=None, attrs=None, deck="",
                  cell_rate=None, dtypes=None, parameters=None):
    """Writes a granpack configuration (docs/hdf5-schema.md) with h5py: grains/contacts are
    dicts of arrays named as the datasets (missing particle fields: zeros; `position` from
    scaled_position; missing contacts: none), attrs extra root attributes (e.g. time, step,
    stage_name, granpack_version), parameters the attributes of /parameters (e.g. a Packing's
    raw_parameters; None: no group). Serial; for synthetic structures and copies, not for runs."""
    _need_h5py()
    dim = int(dimension)
    rd, od = (1, 1) if dim == 2 else (3, 4)
    L = np.asarray(cell_length, dtype=float)
    n = len(grains["id"])
    g = dict(grains)
    g.setdefault("position", np.asarray(g["scaled_position"], dtype=float) * L)
    for k, cols in (("velocity", dim), ("angular_velocity", rd), ("orientation", od)):
        g.setdefault(k, np.zeros((n, cols)))
    c = dict(contacts or {})
    nc = len(c.get("first", ()))
    for k, shape, dt in (("first", (nc,), np.int64), ("second", (nc,), np.int64),
                         ("normal_force", (nc,), float), ("tangential_force", (nc, dim), float),
                         ("rolling", (nc, rd), float), ("flags", (nc,), np.uint32),
                         ("age", (nc,), np.int64)):
        c.setdefault(k, np.zeros(shape, dt))
    types = {"id": np.int64, "first": np.int64, "second": np.int64, "age": np.int64,
             "flags": np.uint32}
    types.update(dtypes or {})
    with h5py.File(path, "w") as f:
        root = {"format": "granpack", "format_version": np.int32(1),
                "granpack_version": "granpack_io.py", "dimension": np.int32(dim),
                "n_particles": np.int64(n), "n_contacts": np.int64(nc), "time": 0.0,
                "step": np.int64(0), "stage_index": np.int32(0), "stage_name": "",
                "kind": "configuration"}
        root.update(attrs or {})
        root["n_particles"], root["n_contacts"] = np.int64(n), np.int64(nc)
        for k, v in root.items():
            f.attrs[k] = v
        text = deck.encode() if isinstance(deck, str) else bytes(deck)
        f.create_dataset("deck", data=np.array(text, dtype=f"S{max(len(text), 1)}"))

        def put(name, data):
            key = name.split("/")[1]
            arr = np.asarray(data, dtype=types.get(key, float))
            unit = ("rad" if dim == 2 else "1") if key == "orientation" else UNITS[name]
            f.create_dataset(name, data=arr).attrs["unit"] = unit

        put("cell/length", L)
        put("cell/rate", np.zeros(dim) if cell_rate is None else cell_rate)
        for k in PARTICLE_SETS:
            put("particles/" + k, g[k])
        for k in CONTACT_SETS:
            put("contacts/" + k, c[k])
        if parameters is not None:
            g = f.create_group("parameters")
            for k, v in parameters.items():
                g.attrs[k] = v


def main(argv=None):
    """`granpack_io.py value FILE KEY`: prints repr() of FILE's top-level KEY (any granpack JSON
    file, read as `read` does: a report's keys are its raw dict's); exit 2 on bad input."""
    ap = argparse.ArgumentParser(prog="granpack_io.py", description="Values of granpack files "
                                 "for shell scripts (the reader itself: import granpack_io).")
    sub = ap.add_subparsers(dest="command", required=True)
    v = sub.add_parser("value", help="print repr() of a top-level value of a JSON file")
    v.add_argument("file")
    v.add_argument("key")
    a = ap.parse_args(argv)
    try:
        d = read(a.file)
        d = d.raw if isinstance(d, Report) else d
        if not isinstance(d, dict) or a.key not in d:
            raise GranpackFileError(f"{a.file}: no key '{a.key}'")
    except GranpackFileError as e:
        fail("granpack_io.py", e)
    print(repr(d[a.key]))


if __name__ == "__main__":
    main()
