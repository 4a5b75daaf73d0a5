"""An independent reference for the elastic tensor of `granpack stiffness` on 3D Hertz packings
(tests/cli/ar_moduli.sh), written from the contact list of the file alone, not from the C++
blocks:

- the forces of the strained packing are Hertz's, N = N0 (h / h0)^(3/2) from each contact's
  stored force N0 and overlap h0 (so k_n = dN/dh = 3 N / (2 h) needs no material constant);
- a strain eps moves the branch vectors as r -> (1 - eps) r (compression positive, [AR] and
  docs/stiffness.md "The elastic tensor"), the cell volume as det(1 - eps);
- sigma = sum f (x) r / volume of the strained cell; c_IJ = d sigma_I / d gamma_J (engineering
  shear strains) by central differences of sigma.

affine_tensor: every grain follows the strain (= `elastic_tensor.c_affine`).
relaxed_tensor (frictionless only): the grains relax to first order: u(gamma) = gamma w_J with
H w_J = d f / d gamma_J, H the Hessian of the contact energy (k_n n n^T - (N / r)(1 - n n^T) per
contact, assembled here) and d f / d gamma_J the finite-difference change of the net forces
under the affine strain; then c_IJ is the central difference of sigma along (gamma e_J, gamma
w_J). This is the linear response about the given configuration, the quantity the Schur
complement of the stiffness matrix gives (= `elastic_tensor.c`).
bulk_affine_trace: (2/3) P + sum k_n r^2 / (9 V), the affine bulk modulus of any packing, with
or without friction (an isotropic strain changes no contact direction and no tangential force,
and T . r = 0).
"""
import numpy as np
import scipy.sparse
import scipy.sparse.linalg

VOIGT = ((0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1))


def strain(J, g):
    """The strain tensor of Voigt component J with amplitude g (engineering shear: eps = g/2)."""
    e = np.zeros((3, 3))
    a, b = VOIGT[J]
    if a == b:
        e[a, a] = g
    else:
        e[a, b] = e[b, a] = g / 2
    return e


class HertzNetwork:
    """The force-carrying contacts of a packing, as `granpack stiffness` keeps them: N^e above
    the file's force threshold, neither grain a rattler (ids from the stiffness JSON)."""

    def __init__(self, p, threshold, rattler_ids):
        assert p.dimension == 3
        rattler = np.zeros(p.n, bool)
        if len(rattler_ids):
            rattler[p.row_of(rattler_ids)] = True
        n0 = p.contacts["normal_force"].astype(float)
        keep = (n0 > threshold) & ~p.distant & ~rattler[p.i] & ~rattler[p.j]
        self.i, self.j = p.i[keep], p.j[keep]
        self.r0 = p.branch[keep]
        self.n0, self.h0 = n0[keep], p.overlap[keep]
        assert np.all(self.h0 > 0), "a force-carrying contact without overlap"
        self.rsum = (p.radius[self.i] + p.radius[self.j])
        self.t = p.contacts["tangential_force"].astype(float)[keep]
        self.volume = p.volume
        # unknowns: 3 per backbone grain, one grain pinned (the 3 translations)
        back = np.unique(np.concatenate([self.i, self.j]))
        self.col = -np.ones(p.n, np.int64)
        self.col[back[1:]] = np.arange(len(back) - 1)
        self.m = 3 * (len(back) - 1)
        self.n = p.n

    def kn(self):
        return 1.5 * self.n0 / self.h0

    def forces(self, eps, u):
        """r, N, n of every contact under strain eps and grain displacements u (n, 3)."""
        r = self.r0 @ (np.eye(3) - eps).T + u[self.j] - u[self.i]
        d = np.sqrt((r * r).sum(1))
        h = self.rsum - d
        assert np.all(h > 0), "a contact opened: strain step too large"
        return r, self.n0 * (h / self.h0) ** 1.5, r / d[:, None], d

    def stress(self, eps, u, tangential=False):
        r, N, n, _ = self.forces(eps, u)
        f = N[:, None] * n + (self.t if tangential else 0.0)
        return np.einsum("ka,kb->ab", f, r) / (self.volume * np.linalg.det(np.eye(3) - eps))

    def net(self, eps, u):
        """Net contact force on each grain (n, 3) (f = N n acts on `second`)."""
        _, N, n, _ = self.forces(eps, u)
        f = N[:, None] * n
        out = np.zeros((self.n, 3))
        np.add.at(out, self.j, f)
        np.add.at(out, self.i, -f)
        return out

    def hessian(self):
        """d(-net force)/du on the unpinned backbone grains (sparse, m x m)."""
        r, N, n, d = self.forces(np.zeros((3, 3)), np.zeros((self.n, 3)))
        k = 1.5 * N / (self.rsum - d)
        nn = n[:, :, None] * n[:, None, :]
        S = k[:, None, None] * nn - (N / d)[:, None, None] * (np.eye(3) - nn)
        rows, cols, vals = [], [], []
        for a, b, sign in ((self.i, self.i, 1), (self.j, self.j, 1), (self.i, self.j, -1),
                           (self.j, self.i, -1)):
            ca, cb = self.col[a], self.col[b]
            ok = (ca >= 0) & (cb >= 0)
            for x in range(3):
                for y in range(3):
                    rows.append(3 * ca[ok] + x)
                    cols.append(3 * cb[ok] + y)
                    vals.append(sign * S[ok, x, y])
        return scipy.sparse.csc_matrix(
            (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
            shape=(self.m, self.m))

    def vec(self, field):
        """(n, 3) -> the unknowns (pinned and rattler grains dropped)."""
        out = np.zeros(self.m)
        ok = self.col >= 0
        out[(3 * self.col[ok])[:, None] + np.arange(3)] = field[ok]
        return out

    def field(self, x):
        out = np.zeros((self.n, 3))
        ok = self.col >= 0
        out[ok] = x[(3 * self.col[ok])[:, None] + np.arange(3)]
        return out


def voigt(s):
    return np.array([s[a, b] for a, b in VOIGT])


def affine_tensor(net, g=1e-8, tangential=False):
    zero = np.zeros((net.n, 3))
    return np.column_stack([(voigt(net.stress(strain(J, g), zero, tangential)) -
                             voigt(net.stress(strain(J, -g), zero, tangential))) / (2 * g)
                            for J in range(6)])


def relaxed_tensor(net, g=1e-8):
    """The first-order relaxed tensor, and the largest residual |H w - df/dgamma| / |df/dgamma|."""
    zero = np.zeros((net.n, 3))
    H = net.hessian()
    lu = scipy.sparse.linalg.splu(H)
    cols, worst = [], 0.0
    for J in range(6):
        df = net.vec((net.net(strain(J, g), zero) - net.net(strain(J, -g), zero)) / (2 * g))
        w = lu.solve(df)
        worst = max(worst, np.linalg.norm(H @ w - df) / np.linalg.norm(df))
        u = net.field(w)
        cols.append((voigt(net.stress(strain(J, g), g * u)) -
                     voigt(net.stress(strain(J, -g), -g * u))) / (2 * g))
    return np.column_stack(cols), worst, lu


def isotropic_pressure_response(net, lu, g=1e-8):
    """B = dP / d(tr eps) under eps = g 1 with the grains relaxed to first order: the pressure
    response to an isotropic strain, measured directly (not from the tensor)."""
    zero = np.zeros((net.n, 3))
    e = np.eye(3)
    df = net.vec((net.net(g * e, zero) - net.net(-g * e, zero)) / (2 * g))
    u = net.field(lu.solve(df))
    p = lambda s: np.trace(s) / 3
    return (p(net.stress(g * e, g * u)) - p(net.stress(-g * e, -g * u))) / (2 * 3 * g)


def bulk_affine_trace(net, pressure):
    return 2.0 / 3.0 * pressure + (net.kn() * (net.r0 ** 2).sum(1)).sum() / (9 * net.volume)


def hill_averages(c):
    """B_V, G_V, B_R, G_R of the symmetric part of c (textbook forms, Hill 1952)."""
    c = 0.5 * (c + c.T)
    s = np.linalg.inv(c)
    d, o, sh = (lambda m: (m[0, 0] + m[1, 1] + m[2, 2], m[0, 1] + m[0, 2] + m[1, 2],
                           m[3, 3] + m[4, 4] + m[5, 5]))(c)
    ds, os_, shs = (lambda m: (m[0, 0] + m[1, 1] + m[2, 2], m[0, 1] + m[0, 2] + m[1, 2],
                               m[3, 3] + m[4, 4] + m[5, 5]))(s)
    return ((d + 2 * o) / 9, (d - o + 3 * sh) / 15, 1 / (ds + 2 * os_),
            15 / (4 * ds - 4 * os_ + 3 * shs))
