"""Spatial rigid nodes: q = (p, rotation coordinates), x = p + A b for a body-local point b.

``RotationVector``: Exudyn's ``NodeRigidBodyRotVecLG``, rotation vector theta (A by Rodrigues'
formula, G = I: Exudyn's Lie-group integrator updates it by the local increment, so derivatives
by the rotation coordinates are taken by the local increment A -> A (I + [dtheta]x)).
``EulerParameters``: Exudyn's ``NodeRigidBodyEP``, e = (e0, e1, e2, e3) (A quadratic in e, not
normalised; G = 2 [-e_v, e0 I - [e_v]x]; derivatives by e itself, so dx/de = dA/de b is not Jp
along e: the position Jacobian Jx differs from Jp there).

With omega_local = G q_t_rot: v = p_t + A (omega_local x b), Jp = [I, -A [b]x G]; the
generalized force of the points' forces f is (sum f, G^T sum b x A^T f). The functions follow the
node protocol of ``exu_aniso.kernel.nodes``; the master's (``master_derivatives``,
``master_rate``, ``master_normalisation``) serve a moving master (``kernel.sets.evaluate_pair``)."""
from __future__ import annotations

import math

from numba import njit


@njit(cache=True, inline="always")
def _rotation_vector(qt, A, G):
    """A = I + sin(a)/a [t]x + (1 - cos(a))/a^2 [t]x^2 (t = qt[3:6], a = |t|) and G = I."""
    t0, t1, t2 = qt[3], qt[4], qt[5]
    a = math.sqrt(t0 * t0 + t1 * t1 + t2 * t2)
    K = ((0.0, -t2, t1), (t2, 0.0, -t0), (-t1, t0, 0.0))
    if a < 1e-8:
        c1, c2 = 1.0, 0.5
    else:
        c1, c2 = math.sin(a) / a, (1.0 - math.cos(a)) / (a * a)
    for i in range(3):
        for j in range(3):
            K2ij = K[i][0] * K[0][j] + K[i][1] * K[1][j] + K[i][2] * K[2][j]
            A[i, j] = c1 * K[i][j] + c2 * K2ij + (1.0 if i == j else 0.0)
            G[i, j] = 1.0 if i == j else 0.0


@njit(cache=True, inline="always")
def _euler_parameters(qt, A, G):
    """A(e) (quadratic in e = qt[3:7]) and G(e) = 2 [-e_v, e0 I - [e_v]x] (omega_local = G e_t)."""
    e0, e1, e2, e3 = qt[3], qt[4], qt[5], qt[6]
    A[0, 0], A[0, 1], A[0, 2] = e0 * e0 + e1 * e1 - e2 * e2 - e3 * e3, 2 * (e1 * e2 - e0 * e3), 2 * (e1 * e3 + e0 * e2)
    A[1, 0], A[1, 1], A[1, 2] = 2 * (e1 * e2 + e0 * e3), e0 * e0 - e1 * e1 + e2 * e2 - e3 * e3, 2 * (e2 * e3 - e0 * e1)
    A[2, 0], A[2, 1], A[2, 2] = 2 * (e1 * e3 - e0 * e2), 2 * (e2 * e3 + e0 * e1), e0 * e0 - e1 * e1 - e2 * e2 + e3 * e3
    G[0, 0], G[0, 1], G[0, 2], G[0, 3] = -2 * e1, 2 * e0, 2 * e3, -2 * e2
    G[1, 0], G[1, 1], G[1, 2], G[1, 3] = -2 * e2, -2 * e3, 2 * e0, 2 * e1
    G[2, 0], G[2, 1], G[2, 2], G[2, 3] = -2 * e3, 2 * e2, -2 * e1, 2 * e0


@njit(cache=True, inline="always")
def _ep_derivatives(qt, q_t, dA, Gt):
    """Derivatives of the Euler-parameter kinematics at total coordinates qt (e = qt[3:7], not
    normalised): dA[m, 3 i + j] = dA_ij/de_m (A is quadratic in e) and Gt (3, 4) = G(de/dt). G is
    linear in e with G(e) e_t = -G(e_t) e, so d(omega_local)/de = -G(e_t)."""
    e0, e1, e2, e3 = qt[3], qt[4], qt[5], qt[6]
    rows = ((e0, -e3, e2, e3, e0, -e1, -e2, e1, e0),
            (e1, e2, e3, e2, -e1, -e0, e3, e0, -e1),
            (-e2, e1, e0, e1, e2, e3, -e0, e3, -e2),
            (-e3, -e0, e1, e0, -e3, e2, e1, e2, e3))
    for m in range(4):
        for c in range(9):
            dA[m, c] = 2.0 * rows[m][c]
    d0, d1, d2, d3 = q_t[3], q_t[4], q_t[5], q_t[6]
    Gt[0, 0], Gt[0, 1], Gt[0, 2], Gt[0, 3] = -2 * d1, 2 * d0, 2 * d3, -2 * d2
    Gt[1, 0], Gt[1, 1], Gt[1, 2], Gt[1, 3] = -2 * d2, -2 * d3, 2 * d0, 2 * d1
    Gt[2, 0], Gt[2, 1], Gt[2, 2], Gt[2, 3] = -2 * d3, 2 * d2, -2 * d1, 2 * d0


@njit(cache=True, inline="always")
def frame_rv(q, q_t, ref, tangent, qt, A, G, dA, Gt):
    for i in range(q.shape[0]):
        qt[i] = ref[i] + q[i]
    _rotation_vector(qt, A, G)


@njit(cache=True, inline="always")
def frame_ep(q, q_t, ref, tangent, qt, A, G, dA, Gt):
    """With tangent also dA/de and G(e_t) (_ep_derivatives)."""
    for i in range(q.shape[0]):
        qt[i] = ref[i] + q[i]
    _euler_parameters(qt, A, G)
    if tangent:
        _ep_derivatives(qt, q_t, dA, Gt)


@njit(cache=True, inline="always")
def motion(qt, q_t, G, nq):
    """(0, 0, 0, omega_local) with omega_local = G q_t_rot."""
    w0 = w1 = w2 = 0.0
    for j in range(nq - 3):
        w0 += G[0, j] * q_t[3 + j]
        w1 += G[1, j] * q_t[3 + j]
        w2 += G[2, j] * q_t[3 + j]
    return 0.0, 0.0, 0.0, w0, w1, w2


@njit(cache=True, inline="always")
def point_xv(qt, q_t, A, motion, bx, by, bz):
    w0, w1, w2 = motion[3], motion[4], motion[5]
    u0, u1, u2 = w1 * bz - w2 * by, w2 * bx - w0 * bz, w0 * by - w1 * bx
    x = (qt[0] + A[0, 0] * bx + A[0, 1] * by + A[0, 2] * bz, qt[1] + A[1, 0] * bx + A[1, 1] * by + A[1, 2] * bz,
         qt[2] + A[2, 0] * bx + A[2, 1] * by + A[2, 2] * bz)
    v = (q_t[0] + A[0, 0] * u0 + A[0, 1] * u1 + A[0, 2] * u2, q_t[1] + A[1, 0] * u0 + A[1, 1] * u1 + A[1, 2] * u2,
         q_t[2] + A[2, 0] * u0 + A[2, 1] * u1 + A[2, 2] * u2)
    return x, v, 0.0, 0.0


@njit(cache=True, inline="always")
def moment(A, F0, F1, F2, bx, by, bz, ax, ay):
    """The local moment b x A^T F."""
    g0 = A[0, 0] * F0 + A[1, 0] * F1 + A[2, 0] * F2
    g1 = A[0, 1] * F0 + A[1, 1] * F1 + A[2, 1] * F2
    g2 = A[0, 2] * F0 + A[1, 2] * F1 + A[2, 2] * F2
    return by * g2 - bz * g1, bz * g0 - bx * g2, bx * g1 - by * g0


@njit(cache=True, inline="always")
def forces(G, nq, Q, F0, F1, F2, M0, M1, M2):
    """Q = (F, G^T M) (= sum Jp^T f, Jp_rot = -A [b]x G)."""
    Q[0], Q[1], Q[2] = F0, F1, F2
    for j in range(nq - 3):
        Q[3 + j] = G[0, j] * M0 + G[1, j] * M1 + G[2, j] * M2


@njit(cache=True, inline="always")
def point_rv(qt, q_t, A, G, dA, bx, by, bz, tangent, x, v, Jp, Jx, wl):
    """x, v, Jp = [I, -A [b]x G]; wl = omega_local."""
    nr = Jp.shape[1] - 3
    for i in range(3):
        wl[i] = 0.0
        for j in range(nr):
            wl[i] += G[i, j] * q_t[3 + j]
    xp, vp, _, _ = point_xv(qt, q_t, A, (0.0, 0.0, 0.0, wl[0], wl[1], wl[2]), bx, by, bz)
    for i in range(3):
        x[i], v[i] = xp[i], vp[i]
    for j in range(nr):                # [b]x G
        s0 = -bz * G[1, j] + by * G[2, j]
        s1 = bz * G[0, j] - bx * G[2, j]
        s2 = -by * G[0, j] + bx * G[1, j]
        for i in range(3):
            Jp[i, 3 + j] = -(A[i, 0] * s0 + A[i, 1] * s1 + A[i, 2] * s2)
    for i in range(3):
        for j in range(3):
            Jp[i, j] = 1.0 if i == j else 0.0


@njit(cache=True, inline="always")
def point_ep(qt, q_t, A, G, dA, bx, by, bz, tangent, x, v, Jp, Jx, wl):
    """point_rv and, with tangent, Jx = dx/dq = [I, dA/de_m b]."""
    point_rv(qt, q_t, A, G, dA, bx, by, bz, tangent, x, v, Jp, Jx, wl)
    if tangent:
        for i in range(3):
            for j in range(3):
                Jx[i, j] = Jp[i, j]
            for m in range(4):
                Jx[i, 3 + m] = dA[m, 3 * i] * bx + dA[m, 3 * i + 1] * by + dA[m, 3 * i + 2] * bz


@njit(cache=True, inline="always")
def position_jacobian_rv(spare, Jp):
    """dx/dq is Jp (derivatives by the local increment)."""
    return Jp


@njit(cache=True, inline="always")
def position_jacobian_ep(spare, Jp):
    """dx/de = dA/de b differs from Jp: point_ep writes it into spare."""
    return spare


@njit(cache=True)
def rotation_columns(nq):
    return 3, nq - 3


@njit(cache=True)
def velocity_column_rv(c, q_t, A, dA, Gt, Jp, wl, bx, by, bz):
    """dv/dtheta_c by the local increment: -A (u x e_c), u = omega_local x b."""
    u0, u1, u2 = wl[1] * bz - wl[2] * by, wl[2] * bx - wl[0] * bz, wl[0] * by - wl[1] * bx
    m = c - 3
    x0 = 0.0 if m == 0 else (-u2 if m == 1 else u1)
    x1 = u2 if m == 0 else (0.0 if m == 1 else -u0)
    x2 = -u1 if m == 0 else (u0 if m == 1 else 0.0)
    return (-(A[0, 0] * x0 + A[0, 1] * x1 + A[0, 2] * x2), -(A[1, 0] * x0 + A[1, 1] * x1 + A[1, 2] * x2),
            -(A[2, 0] * x0 + A[2, 1] * x1 + A[2, 2] * x2))


@njit(cache=True)
def velocity_column_ep(c, q_t, A, dA, Gt, Jp, wl, bx, by, bz):
    """dv/de_m: dA/de_m u + A (b x G(e_t) e_m), u = omega_local x b."""
    u0, u1, u2 = wl[1] * bz - wl[2] * by, wl[2] * bx - wl[0] * bz, wl[0] * by - wl[1] * bx
    m = c - 3
    g0, g1, g2 = Gt[0, m], Gt[1, m], Gt[2, m]
    y0, y1, y2 = by * g2 - bz * g1, bz * g0 - bx * g2, bx * g1 - by * g0
    return (dA[m, 0] * u0 + dA[m, 1] * u1 + dA[m, 2] * u2 + A[0, 0] * y0 + A[0, 1] * y1 + A[0, 2] * y2,
            dA[m, 3] * u0 + dA[m, 4] * u1 + dA[m, 5] * u2 + A[1, 0] * y0 + A[1, 1] * y1 + A[1, 2] * y2,
            dA[m, 6] * u0 + dA[m, 7] * u1 + dA[m, 8] * u2 + A[2, 0] * y0 + A[2, 1] * y1 + A[2, 2] * y2)


@njit(cache=True)
def geometric_rv(A, G, dA, Jp, f, bx, by, bz, Kq):
    """By the local increment: d(Jp_rot e_a)/dtheta_c . f = -(A (b delta_ac - e_a b_c)) . f."""
    fb0 = A[0, 0] * f[0] + A[1, 0] * f[1] + A[2, 0] * f[2]
    fb1 = A[0, 1] * f[0] + A[1, 1] * f[1] + A[2, 1] * f[2]
    fb2 = A[0, 2] * f[0] + A[1, 2] * f[1] + A[2, 2] * f[2]
    fbv = (fb0, fb1, fb2)
    bv = (bx, by, bz)
    bf = bx * fb0 + by * fb1 + bz * fb2
    for i in range(3):
        for j in range(3):
            Kq[3 + i, 3 + j] += fbv[i] * bv[j] - (bf if i == j else 0.0)


@njit(cache=True)
def geometric_ep(A, G, dA, Jp, f, bx, by, bz, Kq):
    """Q_rot = G^T (b x A^T f); d/de_m at fixed f = dG/de_m^T c + G^T (b x dA/de_m^T f), c = b x A^T f;
    G is linear in e, G(e)^T c = 2 Mc e with Mc = [[0, -c^T], [c, -[c]x]]."""
    fb0 = A[0, 0] * f[0] + A[1, 0] * f[1] + A[2, 0] * f[2]
    fb1 = A[0, 1] * f[0] + A[1, 1] * f[1] + A[2, 1] * f[2]
    fb2 = A[0, 2] * f[0] + A[1, 2] * f[1] + A[2, 2] * f[2]
    cc0, cc1, cc2 = by * fb2 - bz * fb1, bz * fb0 - bx * fb2, bx * fb1 - by * fb0
    Mc = ((0.0, -cc0, -cc1, -cc2), (cc0, 0.0, cc2, -cc1), (cc1, -cc2, 0.0, cc0), (cc2, cc1, -cc0, 0.0))
    for m in range(4):
        g0 = dA[m, 0] * f[0] + dA[m, 3] * f[1] + dA[m, 6] * f[2]     # dA_m^T f
        g1 = dA[m, 1] * f[0] + dA[m, 4] * f[1] + dA[m, 7] * f[2]
        g2 = dA[m, 2] * f[0] + dA[m, 5] * f[1] + dA[m, 8] * f[2]
        y0, y1, y2 = by * g2 - bz * g1, bz * g0 - bx * g2, bx * g1 - by * g0
        for a in range(4):
            Kq[3 + a, 3 + m] += 2.0 * Mc[a][m] + G[0, a] * y0 + G[1, a] * y1 + G[2, a] * y2


# --- a moving master's derivatives (kernel.sets.evaluate_pair) ----------------------------------

@njit(cache=True)
def master_derivatives_rv(qt, q_t, A, dA, Gt):
    """dA_c e_j = A (e_c x e_j): dA[c, 3 i + j] = dA_ij by the local increment of theta_c."""
    for i in range(3):
        a0, a1, a2 = A[i, 0], A[i, 1], A[i, 2]
        dA[0, 3 * i], dA[0, 3 * i + 1], dA[0, 3 * i + 2] = 0.0, a2, -a1
        dA[1, 3 * i], dA[1, 3 * i + 1], dA[1, 3 * i + 2] = -a2, 0.0, a0
        dA[2, 3 * i], dA[2, 3 * i + 1], dA[2, 3 * i + 2] = a1, -a0, 0.0


@njit(cache=True)
def master_derivatives_ep(qt, q_t, A, dA, Gt):
    """dA/de_m and G(e_t) (_ep_derivatives)."""
    _ep_derivatives(qt, q_t, dA, Gt)


@njit(cache=True, inline="always")
def master_rate_rv(Gt, c):
    """dG_c q_t_rot: 0 by the local increment."""
    return 0.0, 0.0, 0.0


@njit(cache=True, inline="always")
def master_rate_ep(Gt, c):
    """dG_c q_t_rot = G(e_c) e_t = -G(e_t) e_c."""
    return -Gt[0, c], -Gt[1, c], -Gt[2, c]


@njit(cache=True)
def master_normalisation_rv(A, G, dA, dAf, F, xr, y0, y1, y2, col0, Kc):
    """Nothing: by the local increment, G and A^T A = I do not vary."""


@njit(cache=True)
def master_normalisation_ep(A, G, dA, dAf, F, xr, y0, y1, y2, col0, Kc):
    """The master's rotation rows of Kc (from column and row col0) for Euler parameters:
    -dG_c^T y - G^T (b x dM_c f), y = b x g, M = A^T A (|e|^4 I, not I off the unit sphere),
    dM_c f = dA_c^T F + A^T dA_c f; G(e)^T y = 2 My e (as geometric_ep); b = xr."""
    My = ((0.0, -y0, -y1, -y2), (y0, 0.0, y2, -y1), (y1, -y2, 0.0, y0), (y2, y1, -y0, 0.0))
    for cc in range(4):
        mf0 = (dA[cc, 0] * F[0] + dA[cc, 3] * F[1] + dA[cc, 6] * F[2]
               + A[0, 0] * dAf[cc, 0] + A[1, 0] * dAf[cc, 1] + A[2, 0] * dAf[cc, 2])
        mf1 = (dA[cc, 1] * F[0] + dA[cc, 4] * F[1] + dA[cc, 7] * F[2]
               + A[0, 1] * dAf[cc, 0] + A[1, 1] * dAf[cc, 1] + A[2, 1] * dAf[cc, 2])
        mf2 = (dA[cc, 2] * F[0] + dA[cc, 5] * F[1] + dA[cc, 8] * F[2]
               + A[0, 2] * dAf[cc, 0] + A[1, 2] * dAf[cc, 1] + A[2, 2] * dAf[cc, 2])
        z0, z1, z2 = xr[1] * mf2 - xr[2] * mf1, xr[2] * mf0 - xr[0] * mf2, xr[0] * mf1 - xr[1] * mf0
        for r in range(4):
            Kc[col0 + r, col0 + cc] -= 2.0 * My[r][cc] + G[0, r] * z0 + G[1, r] * z1 + G[2, r] * z2
