"""A linear slave as the moving-master pair sees it (``kernel.sets.evaluate_pair``): mass points and
ANCF cables, every point linear in the slave's coordinates, x_k = c_k + S_k q_total[idx_k] with a
constant S_k (3, m) over the m coordinates idx_k (a mass point: S = I; a cable: the Hermite shape
functions of its element at the point). It has no frame and no rotation coordinates, its point
Jacobian S_k is constant (no geometric or velocity terms), and each point's force goes to its own
coordinates through S_k^T. The node protocol's functions (``exu_aniso.kernel.nodes``) say so; the
point functions take the points' (idx, S, c)."""
from __future__ import annotations

from numba import njit


@njit(cache=True)
def frame(q, q_t, ref, tangent, qt, A, G, dA, Gt):
    """No frame."""


@njit(cache=True, inline="always")
def position_jacobian(spare, Jp):
    return Jp


@njit(cache=True)
def rotation_columns(nq):
    return 0, 0


@njit(cache=True)
def velocity_column(c, q_t, A, dA, Gt, Jp, wl, bx, by, bz):
    """v = S q_t with constant S: no dependence on q."""
    return 0.0, 0.0, 0.0


@njit(cache=True)
def geometric(A, G, dA, Jp, f, bx, by, bz, Kq):
    """Constant S: no geometric term."""


@njit(cache=True, inline="always")
def point_xv(k, idx, Sm, c, ref, q, q_t):
    """(x, v) = (c_k + S_k (ref + q)[idx_k], S_k q_t[idx_k]) as 3-tuples."""
    x0, x1, x2, v0, v1, v2 = c[k, 0], c[k, 1], c[k, 2], 0.0, 0.0, 0.0
    for a in range(idx.shape[1]):
        g = idx[k, a]
        p, r = ref[g] + q[g], q_t[g]
        x0, x1, x2 = x0 + Sm[k, 0, a] * p, x1 + Sm[k, 1, a] * p, x2 + Sm[k, 2, a] * p
        v0, v1, v2 = v0 + Sm[k, 0, a] * r, v1 + Sm[k, 1, a] * r, v2 + Sm[k, 2, a] * r
    return (x0, x1, x2), (v0, v1, v2)


@njit(cache=True)
def points_xv(idx, Sm, c, ref, q, q_t, X, V, L):
    """point_xv at every point into X, V (K, 3); L (K, 2) = 0 (no lever arm)."""
    for k in range(idx.shape[0]):
        x, v = point_xv(k, idx, Sm, c, ref, q, q_t)
        X[k, 0], X[k, 1], X[k, 2] = x[0], x[1], x[2]
        V[k, 0], V[k, 1], V[k, 2] = v[0], v[1], v[2]
        L[k, 0], L[k, 1] = 0.0, 0.0


@njit(cache=True)
def generalized_force(idx, Sm, F, Q):
    """Q[idx_k] += S_k^T F_k for the global point forces F (K, 3)."""
    for k in range(idx.shape[0]):
        for a in range(idx.shape[1]):
            Q[idx[k, a]] += Sm[k, 0, a] * F[k, 0] + Sm[k, 1, a] * F[k, 1] + Sm[k, 2, a] * F[k, 2]


@njit(cache=True, inline="always")
def point(k, idx, Sm, c, ref, q, q_t, x, v, Jp, cols):
    """point_xv, Jp = S_k and the point's columns cols[:m] = idx_k."""
    m = idx.shape[1]
    for a in range(m):
        cols[a] = idx[k, a]
    xp, vp = point_xv(k, idx, Sm, c, ref, q, q_t)
    for i in range(3):
        x[i], v[i] = xp[i], vp[i]
    for i in range(3):
        for a in range(m):
            Jp[i, a] = Sm[k, i, a]
