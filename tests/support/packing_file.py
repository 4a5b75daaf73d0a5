"""A granpack configuration file (docs/hdf5-schema.md) read into numpy arrays, with the
contact geometry recomputed from the positions: the tests check the engine's files with it,
independently of the engine."""
import h5py
import numpy as np


class Packing:
    def __init__(self, path):
        with h5py.File(path, "r") as f:
            ids = f["particles/id"][:]
            at = {g: k for k, g in enumerate(ids)}
            self.L = f["cell/length"][:]
            self.x = f["particles/scaled_position"][:] * self.L
            self.R = f["particles/radius"][:]
            self.first = np.array([at[g] for g in f["contacts/first"][:]], dtype=int)
            self.second = np.array([at[g] for g in f["contacts/second"][:]], dtype=int)
            self.Ne = f["contacts/normal_force"][:]
            self.T = f["contacts/tangential_force"][:]
            self.flags = f["contacts/flags"][:]
        r = self.x[self.second] - self.x[self.first]
        self.r = r - self.L * np.round(r / self.L)  # nearest image: branch vectors
        self.dist = np.sqrt((self.r ** 2).sum(1))
        self.n = self.r / self.dist[:, None]
        self.h = self.R[self.first] + self.R[self.second] - self.dist  # overlap (< 0: gap)
        self.distant = (self.flags & 4) != 0

    def clusters(self):
        """Number of connected clusters of the stored pairs (contacts and distant ones)."""
        parent = list(range(len(self.x)))

        def find(i):
            while parent[i] != i:
                parent[i] = parent[parent[i]]
                i = parent[i]
            return i

        for i, j in zip(self.first, self.second):
            parent[find(i)] = find(j)
        return len({find(i) for i in range(len(self.x))})

    def static_balance(self, F0, D0):
        """[GRC]'s static forces without rolling resistance: N = N^e + N^a along n (N^a = -F0
        in contact, -F0 (1 - g/D0) across a gap g) plus T, on the second grain of each pair.
        Returns (N per pair, net force per grain, net moment per grain, stress tensor); the
        moment arm runs to the middle of the overlap."""
        Na = np.where(self.distant, -F0 * (1 + self.h / D0), -F0)
        N = self.Ne + Na
        F = N[:, None] * self.n + self.T
        net = np.zeros_like(self.x)
        np.add.at(net, self.second, F)
        np.add.at(net, self.first, -F)
        cross = lambda b, f: b[:, 0] * f[:, 1] - b[:, 1] * f[:, 0]
        mom = np.zeros(len(self.x))
        arm_second = -(self.R[self.second] - 0.5 * self.h)[:, None] * self.n
        arm_first = (self.R[self.first] - 0.5 * self.h)[:, None] * self.n
        np.add.at(mom, self.second, cross(arm_second, F))
        np.add.at(mom, self.first, cross(arm_first, -F))
        sigma = (F[:, :, None] * self.r[:, None, :]).sum(0) / np.prod(self.L)
        return N, net, mom, sigma
