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
def point_xv(k, idx, Sm, c, ref, q, q_t, x, v):
    """x = c_k + S_k (ref + q)[idx_k], v = S_k q_t[idx_k]."""
    for i in range(3):
        xi, vi = c[k, i], 0.0
        for a in range(idx.shape[1]):
            g = idx[k, a]
            xi += Sm[k, i, a] * (ref[g] + q[g])
            vi += Sm[k, i, a] * q_t[g]
        x[i], v[i] = xi, vi


@njit(cache=True)
def points_xv(idx, Sm, c, ref, q, q_t, X, V, L):
    """point_xv at every point into X, V (K, 3); L (K, 2) = 0 (no lever arm)."""
    for k in range(idx.shape[0]):
        point_xv(k, idx, Sm, c, ref, q, q_t, X[k], V[k])
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
    point_xv(k, idx, Sm, c, ref, q, q_t, x, v)
    for i in range(3):
        for a in range(m):
            Jp[i, a] = Sm[k, i, a]
