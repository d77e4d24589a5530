"""Compiled contact-set kernel (numba): the transport formulation of ``ContactLaw.evaluate`` and
the rigid-body point kinematics of the Exudyn glue, written point by point in scalar form.

Why it exists: inside Exudyn the contact law runs in user functions that are called 5-6 times per
time step. The numpy route (``contact.ContactLaw``) spends ~100 numpy calls per evaluation, which
is ~50x the cost of Exudyn's own C++ spring-damper at the same points. Here the same formulas are
compiled once (``numba.njit(cache=True)``; the first call of a session compiles or loads the
cache) and one call evaluates a whole contact set: positions of the body-fixed points, projection,
tensor fields, return map with its consistent derivative, and the generalized force, Jacobian or
history candidate of the node. ``tests/test_fastpath.py`` holds every route equal to
``ContactLaw.evaluate`` and to the numpy glue.

Symbols follow ``exu_aniso.law`` / ``exu_aniso.contact`` (read those docstrings): T traction in
the transport frame, T_tr trial, N normal traction (<= 0), B adhesion (negative definite), F
friction, dT = dT/dp with p = (T_tr1, T_tr2, |N|, b11, b12, b22, f11, f12, f22).

Packed parameters (``pack_law``): surface ``sp`` = [kind (0 plane, 1 cylinder), R, sign,
axis_point(3), e1(3), e2(3), a(3)]; fields ``bp``/``fp`` = [polar flag, c11, c12, c22 (constant
physical components of the positive tensor), l1, l2, r_c^2, sign]; law ``lp`` = [eps_N, d_N,
map (0 seed, 1 exact, 2 radial), d_T]. Node kinds of ``evaluate_set`` (rigid bodies): 0
``NodeRigidBody2D``, 1 screw joint (``NodeGenericODE2`` with (psi, z)), 2 ``NodeRigidBodyRotVecLG``,
3 ``NodeRigidBodyEP``. Linear slaves (``evaluate_linear``): every point linear in the coordinates,
x = c + S q_total with a constant S (mass points: S = I; ANCF cables: Hermite shape functions), so
Jp = S and dJp/dq = 0.
This module needs no Exudyn.
"""
from __future__ import annotations

import math
import sys

import numpy as np
from numba import njit, types
from numba.extending import overload

from .law import _KAPPA_MAXIT, _KAPPA_RTOL, RETURN_MAPS
from .surfaces import Cylinder

MAP_CODES = {"seed": 0, "exact": 1, "radial": 2}
NODE_KINDS = {"RigidBody2D": 0, "GenericODE2": 1, "RigidBodyRotVecLG": 2, "RigidBodyEP": 3}
NODE_COORDINATES = (3, 2, 6, 7)
SCRATCH_SLOTS = 19   # (slots, 9, 9) scratch: 0-8 point kernel, 9-17 set kernel, 18 Jacobian
assert set(MAP_CODES) == set(RETURN_MAPS)


def pack_law(law):
    """(sp, bp, fp, lp) float arrays of a ContactLaw (transport formulation only)."""
    if law.formulation != "transport":
        raise ValueError("the compiled contact kernel implements formulation='transport' only; "
                         f"got {law.formulation!r}")
    s = law.surface
    sp = np.zeros(16)
    if s.kind == "cylinder":
        sp[0], sp[1], sp[2] = 1.0, s.radius, s.sign
        sp[3:6] = s.axis_point
        sp[6:9], sp[9:12], sp[12:15] = s.axes[0], s.axes[1], s.axes[2]

    def field(f):
        p = np.zeros(8)
        if f._const is None:
            p[0] = 1.0
            p[4], p[5] = f.lam
            p[6] = f.core_radius ** 2
        else:
            p[1:4] = f._const
        p[7] = f.sign
        return p

    lp = np.array([law.eps_N, law.d_N, float(MAP_CODES[law.return_map]), law.d_T])
    return sp, field(law.adhesion), field(law.friction), lp


# ----------------------------------------------------------------------------------------------
# tensor fields and the three return maps (scalar ports of fields.TensorField.physical and law)

@njit(cache=True)
def _field(p, u0, u1, P, dP):
    """Physical components P = (p11, p12, p22) of B or F at C and dP/du (3, 2)."""
    if p[0] == 0.0:
        for c in range(3):
            P[c] = p[7] * p[1 + c]
            dP[c, 0] = 0.0
            dP[c, 1] = 0.0
        return
    x, y, rc2 = u0, u1, p[6]
    d = x * x + y * y + rc2
    if not d < np.inf:
        raise ValueError("point coordinates too large or not finite for the polar field: x^2 + y^2 overflows")
    if not d > 0.0:
        raise ValueError("polar orthotropy is undefined at the polar origin (x = y = 0); set core_radius > 0")
    M0, M1, M2 = (x * x + 0.5 * rc2) / d, x * y / d, (y * y + 0.5 * rc2) / d
    l1, l2, sg = p[4], p[5], p[7]
    P[0] = sg * (l2 + (l1 - l2) * M0)
    P[1] = sg * (l1 - l2) * M1
    P[2] = sg * (l2 + (l1 - l2) * M2)
    k = sg * (l1 - l2)
    dP[0, 0] = k * (2 * x - 2 * x * M0) / d
    dP[0, 1] = k * (-2 * y * M0) / d
    dP[1, 0] = k * (y - 2 * x * M1) / d
    dP[1, 1] = k * (x - 2 * y * M1) / d
    dP[2, 0] = k * (-2 * x * M2) / d
    dP[2, 1] = k * (2 * y - 2 * y * M2) / d


@njit(cache=True)
def _quad(s11, s12, s22, x1, x2):
    return s11 * x1 * x1 + 2.0 * s12 * x1 * x2 + s22 * x2 * x2


@njit(cache=True)
def _radial(t1, t2, N, f11, f12, f22, dT):
    s = math.sqrt(_quad(f11, f12, f22, t1, t2))
    g1, g2 = f11 * t1 + f12 * t2, f12 * t1 + f22 * t2
    a = N / s
    s2 = s * s
    dT[0, 0], dT[1, 0] = a * (1.0 - t1 * g1 / s2), a * (-t2 * g1 / s2)
    dT[0, 1], dT[1, 1] = a * (-t1 * g2 / s2), a * (1.0 - t2 * g2 / s2)
    dT[0, 2], dT[1, 2] = t1 / s, t2 / s
    c = -N / (2.0 * s2 * s)
    q = (t1 * t1, 2.0 * t1 * t2, t2 * t2)
    for j in range(3):
        dT[0, 6 + j], dT[1, 6 + j] = c * q[j] * t1, c * q[j] * t2
    return N * t1 / s, N * t2 / s, 0.0


@njit(cache=True)
def _seed(t1, t2, N, b11, b12, b22, f11, f12, f22, dT):
    u1, u2 = f11 * t1 + f12 * t2, f12 * t1 + f22 * t2          # F T_tr
    h1, h2 = b11 * u1 + b12 * u2, b12 * u1 + b22 * u2          # T_hat = B F T_tr
    s = math.sqrt(_quad(f11, f12, f22, h1, h2))
    g1, g2 = f11 * h1 + f12 * h2, f12 * h1 + f22 * h2          # F T_hat
    a = -N / s
    s2 = s * s
    # dT for a perturbation d of T_hat: a (d - h (g.d)/s^2)
    BF = (b11 * f11 + b12 * f12, b11 * f12 + b12 * f22, b12 * f11 + b22 * f12, b12 * f12 + b22 * f22)
    D1 = (BF[0], BF[1], 0.0, u1, u2, 0.0)
    D2 = (BF[2], BF[3], 0.0, 0.0, u1, u2)
    for j in range(6):
        if j == 2:
            dT[0, 2], dT[1, 2] = -h1 / s, -h2 / s
            continue
        w = (g1 * D1[j] + g2 * D2[j]) / s2
        dT[0, j], dT[1, j] = a * (D1[j] - h1 * w), a * (D2[j] - h2 * w)
    c = N / (2.0 * s2 * s)
    E1 = (t1, t2, 0.0)
    E2 = (0.0, t1, t2)
    q = (h1 * h1, 2.0 * h1 * h2, h2 * h2)
    for j in range(3):
        d1, d2 = b11 * E1[j] + b12 * E2[j], b12 * E1[j] + b22 * E2[j]
        w = (g1 * d1 + g2 * d2) / s2
        dT[0, 6 + j] = a * (d1 - h1 * w) + c * q[j] * h1
        dT[1, 6 + j] = a * (d2 - h2 * w) + c * q[j] * h2
    return -N * h1 / s, -N * h2 / s, 0.0


@njit(cache=True)
def _exact(t1, t2, N, b11, b12, b22, f11, f12, f22, dT):
    c11, c12, c22 = -b11, -b12, -b22
    a11, a12 = c11 * f11 + c12 * f12, c11 * f12 + c12 * f22          # A = C F
    a21, a22 = c12 * f11 + c22 * f12, c12 * f12 + c22 * f22
    tr, det = a11 + a22, a11 * a22 - a12 * a21
    # tr^2 - 4 det written as (a11 - a22)^2 + 4 a12 a21: no cancellation when the eigenvalues of C F
    # nearly coincide (the naive form loses ~1e-12 in g_min there, which capped kappa below the root)
    g_max = 0.5 * (tr + math.sqrt(abs((a11 - a22) * (a11 - a22) + 4.0 * a12 * a21)))
    g_min = det / g_max
    s_tr = math.sqrt(_quad(f11, f12, f22, t1, t2))
    lo = 0.0
    hi = (s_tr / N - 1.0) / g_min * (1.0 + 1e-13)   # bracket with a margin over round-off
    kappa = lo
    for _ in range(_KAPPA_MAXIT):
        m11, m12, m21, m22 = 1.0 + kappa * a11, kappa * a12, kappa * a21, 1.0 + kappa * a22
        dm = m11 * m22 - m12 * m21
        T1, T2 = (m22 * t1 - m12 * t2) / dm, (-m21 * t1 + m11 * t2) / dm
        q = _quad(f11, f12, f22, T1, T2)
        s = math.sqrt(q)
        if abs(s - N) <= _KAPPA_RTOL * N:
            break
        if s > N:
            lo = kappa
        else:
            hi = kappa
        r1, r2 = a11 * T1 + a12 * T2, a21 * T1 + a22 * T2
        d1, d2 = -(m22 * r1 - m12 * r2) / dm, -(-m21 * r1 + m11 * r2) / dm
        g1, g2 = f11 * T1 + f12 * T2, f12 * T1 + f22 * T2
        dpsi = -(g1 * d1 + g2 * d2) / (s * q)
        psi = 1.0 / s - 1.0 / N
        new = kappa - psi / dpsi
        if new <= lo:
            new = 0.5 * (lo + hi)
        if new >= hi:
            new = 0.5 * (lo + hi)
        if abs(new - kappa) <= 4e-16 * abs(kappa):
            kappa = new
            break
        kappa = new
    m11, m12, m21, m22 = 1.0 + kappa * a11, kappa * a12, kappa * a21, 1.0 + kappa * a22
    dm = m11 * m22 - m12 * m21
    T1, T2 = (m22 * t1 - m12 * t2) / dm, (-m21 * t1 + m11 * t2) / dm
    u1, u2 = f11 * T1 + f12 * T2, f12 * T1 + f22 * T2              # F T
    w1, w2 = (m22 * u1 - m21 * u2) / dm, (-m12 * u1 + m11 * u2) / dm  # M^-T F T
    AT1, AT2 = a11 * T1 + a12 * T2, a21 * T1 + a22 * T2
    den = w1 * AT1 + w2 * AT2
    mA1, mA2 = (m22 * AT1 - m12 * AT2) / dm, (-m21 * AT1 + m11 * AT2) / dm
    # column p: perturbation r of M T = T_tr (+ tFt in the constraint, dN of |N|)
    R1 = (1.0, 0.0, 0.0, kappa * u1, kappa * u2, 0.0)
    R2 = (0.0, 1.0, 0.0, 0.0, kappa * u1, kappa * u2)
    E1 = (T1, T2, 0.0)
    E2 = (0.0, T1, T2)
    tq = (T1 * T1, 2.0 * T1 * T2, T2 * T2)
    for j in range(9):
        tFt, dN = 0.0, 0.0
        if j < 6:
            r1, r2 = R1[j], R2[j]
            if j == 2:
                dN = 1.0
        else:
            e1, e2 = E1[j - 6], E2[j - 6]
            r1, r2 = -kappa * (c11 * e1 + c12 * e2), -kappa * (c12 * e1 + c22 * e2)
            tFt = tq[j - 6]
        dk = (2.0 * (w1 * r1 + w2 * r2) + tFt - 2.0 * N * dN) / (2.0 * den)
        x1, x2 = (m22 * r1 - m12 * r2) / dm, (-m21 * r1 + m11 * r2) / dm
        dT[0, j], dT[1, j] = x1 - dk * mA1, x2 - dk * mA2
    return T1, T2, kappa


@njit(cache=True)
def _return_map(method, t1, t2, N, B, F, dT):
    """Return map at one point: (T1, T2, sliding flag, slip1, slip2, dissipation); fills dT (2, 9)."""
    for a in range(2):
        for j in range(9):
            dT[a, j] = 0.0
    phi = math.sqrt(max(_quad(F[0], F[1], F[2], t1, t2), 0.0)) - N
    if phi <= 0.0:
        dT[0, 0] = 1.0
        dT[1, 1] = 1.0
        return t1, t2, 0, 0.0, 0.0, 0.0
    if N == 0.0:                      # sliding without load: T = 0, dT/d|N| = limit direction
        T1, T2 = 0.0, 0.0
        if method == 2:
            d1, d2 = t1, t2
        elif method == 0:
            u1, u2 = F[0] * t1 + F[1] * t2, F[1] * t1 + F[2] * t2
            d1, d2 = -(B[0] * u1 + B[1] * u2), -(B[1] * u1 + B[2] * u2)
        else:
            c11, c12, c22 = -B[0], -B[1], -B[2]
            dc = c11 * c22 - c12 * c12
            v1, v2 = (c22 * t1 - c12 * t2) / dc, (-c12 * t1 + c11 * t2) / dc
            df = F[0] * F[2] - F[1] * F[1]
            d1, d2 = (F[2] * v1 - F[1] * v2) / df, (-F[1] * v1 + F[0] * v2) / df
        s = math.sqrt(_quad(F[0], F[1], F[2], d1, d2))
        if s > 0.0:
            dT[0, 2], dT[1, 2] = d1 / s, d2 / s
    elif method == 2:
        T1, T2, _ = _radial(t1, t2, N, F[0], F[1], F[2], dT)
    elif method == 0:
        T1, T2, _ = _seed(t1, t2, N, B[0], B[1], B[2], F[0], F[1], F[2], dT)
    else:
        T1, T2, _ = _exact(t1, t2, N, B[0], B[1], B[2], F[0], F[1], F[2], dT)
    c11, c12, c22 = -B[0], -B[1], -B[2]
    det = c11 * c22 - c12 * c12
    d1, d2 = T1 - t1, T2 - t2
    s1, s2 = (c22 * d1 - c12 * d2) / det, (-c12 * d1 + c11 * d2) / det
    return T1, T2, 1, s1, s2, -(T1 * s1 + T2 * s2)


@njit(cache=True)
def _wrap(a):
    return math.pi - (math.pi - a) % (2.0 * math.pi)


BRANCH_TOLERANCE = Cylinder.BRANCH_TOLERANCE


@njit(cache=True)
def _release(h, bp, hn, S):
    """Contact lost (``ContactLaw.released_energy``): T . C^-1 T / 2 at the anchor of an active
    history row h is booked as dissipated in hn[5]."""
    if not h[4] > 0.5:
        return
    Bp, dB = S[8, 5, :3], S[4, :3, :2]
    _field(bp, h[2], h[3], Bp, dB)
    c11, c12, c22 = -Bp[0], -Bp[1], -Bp[2]
    det = c11 * c22 - c12 * c12
    hn[5] += 0.5 * _quad(c22 / det, -c12 / det, c11 / det, h[0], h[1])


# ----------------------------------------------------------------------------------------------
# one contact point: ContactLaw.evaluate (transport formulation) for a single row

@njit(cache=True)
def contact_point(x, v, h, sp, bp, fp, lp, tangent, dt, f, Kx, Dv, hn, S):
    """Force f (3) on the slave point, df/dx Kx (3, 3), df/dv Dv (3, 3) (when tangent) and the
    history candidate hn (9) from position x, velocity v and converged history h (9); dt > 0 is
    the time since h and predicts the branch of the cylinder angle (``Cylinder.resolve``).
    S: scratch array of shape (>= 9, 9, 9). Returns the status (0 open, 1 stick, 2 slip,
    3 unresolved)."""
    for i in range(9):
        hn[i] = h[i]
    for i in (0, 1, 2, 3, 4, 7, 8):
        hn[i] = 0.0
    for i in range(3):
        f[i] = 0.0
        for j in range(3):
            Kx[i, j] = 0.0
            Dv[i, j] = 0.0
    cyl = sp[0] == 1.0
    # scratch views of S (no allocation and no reshape in the hot loop)
    n, Bp, Fp, dNdx, dNdv = S[8, 0, :3], S[8, 1, :3], S[8, 2, :3], S[8, 3, :3], S[8, 4, :3]
    E = S[0, :3, :2]
    dudx = S[1, :2, :3]
    dE0 = S[2, :3, :3]                # d a_1 / dx (a_2 is constant on both surfaces)
    dn = S[3, :3, :3]
    dB = S[4, :3, :2]
    dF = S[5, :3, :2]
    dT = S[6, :2, :9]
    dp = S[7, :9, :3]
    for i in range(3):
        n[i] = 0.0
        for j in range(3):
            dE0[i, j] = 0.0
            dn[i, j] = 0.0
            if j < 2:
                E[i, j] = 0.0
                dudx[j, i] = 0.0
    if not cyl:
        gap = x[2]
        if not gap < 0.0:
            _release(h, bp, hn, S)
            return 0
        n[2] = 1.0
        E[0, 0] = 1.0
        E[1, 1] = 1.0
        dudx[0, 0] = 1.0
        dudx[1, 1] = 1.0
        u0, u1 = x[0], x[1]
    else:
        R, sg = sp[1], sp[2]
        l0 = l1 = l2 = 0.0
        for i in range(3):
            di = x[i] - sp[3 + i]
            l0 += di * sp[6 + i]
            l1 += di * sp[9 + i]
            l2 += di * sp[12 + i]
        dist = math.hypot(l0, l1)
        gap = sg * (dist - R)
        if not gap < 0.0:
            _release(h, bp, hn, S)
            return 0
        if dist <= 1e-14 * R:
            raise ValueError("Cylinder: slave point on the cylinder axis; the closest point projection is not unique")
        c, s = l0 / dist, l1 / dist
        for i in range(3):
            er = c * sp[6 + i] + s * sp[9 + i]
            ep = -s * sp[6 + i] + c * sp[9 + i]
            n[i] = sg * er
            E[i, 0] = ep
            E[i, 1] = sp[12 + i]
            dudx[0, i] = R * ep / dist
            dudx[1, i] = sp[12 + i]
        for i in range(3):
            for j in range(3):
                er_i = c * sp[6 + i] + s * sp[9 + i]
                dphi_j = E[j, 0] / dist
                dE0[i, j] = -er_i * dphi_j
                dn[i, j] = sg * E[i, 0] * dphi_j
        u0, u1 = math.atan2(s, c), l2
    eps_N, d_N, method, d_T = lp[0], lp[1], int(lp[2]), lp[3]
    vn = n[0] * v[0] + n[1] * v[1] + n[2] * v[2]
    N = eps_N * gap
    if d_N > 0.0:
        N += d_N * vn
    loaded = N < 0.0
    if not loaded:
        N = 0.0
        d_T = 0.0
    active = h[4] > 0.5
    unresolved = False
    tn1, tn2, du1, du2, dphi = 0.0, 0.0, 0.0, 0.0, 0.0
    if active:
        tn1, tn2 = h[0], h[1]
        if cyl:
            dphi = _wrap(u0 - h[2])
            if dt > 0.0:                  # branch of dphi from the predicted increment du_dx v dt / R
                pred = (dudx[0, 0] * v[0] + dudx[0, 1] * v[1] + dudx[0, 2] * v[2]) * dt / sp[1]
                dphi += 2.0 * math.pi * round((pred - dphi) / (2.0 * math.pi))
                unresolved = abs(dphi - pred) > BRANCH_TOLERANCE
            du1, du2 = sp[1] * dphi, u1 - h[3]
        else:
            du1, du2 = u0 - h[2], u1 - h[3]
    _field(bp, u0, u1, Bp, dB)
    _field(fp, u0, u1, Fp, dF)
    t1 = tn1 + Bp[0] * du1 + Bp[1] * du2
    t2 = tn2 + Bp[1] * du1 + Bp[2] * du2
    T1, T2, sliding, s1, s2, D = _return_map(method, t1, t2, -N, Bp, Fp, dT)
    # force conjugate to the slip of C (du_dx^T T), normal -N n, tangential dashpot -d_T (v - n vn)
    for i in range(3):
        f[i] = dudx[0, i] * T1 + dudx[1, i] * T2 - N * n[i] - d_T * (v[i] - n[i] * vn)
    if tangent:
        for j in range(3):
            dNdx[j] = 0.0
            dNdv[j] = 0.0
        if loaded:
            for j in range(3):
                dNdx[j] = eps_N * n[j]
                dNdv[j] = d_N * n[j]
                if d_N > 0.0:
                    for i in range(3):
                        dNdx[j] += d_N * v[i] * dn[i, j]
        for j in range(3):
            for c in range(3):
                dp[3 + c, j] = dB[c, 0] * dudx[0, j] + dB[c, 1] * dudx[1, j]
                dp[6 + c, j] = dF[c, 0] * dudx[0, j] + dF[c, 1] * dudx[1, j]
            i0, i1 = (dudx[0, j], dudx[1, j]) if active else (0.0, 0.0)
            dp[0, j] = Bp[0] * i0 + Bp[1] * i1 + dp[3, j] * du1 + dp[4, j] * du2
            dp[1, j] = Bp[1] * i0 + Bp[2] * i1 + dp[4, j] * du1 + dp[5, j] * du2
            dp[2, j] = -dNdx[j]
        for j in range(3):
            g1 = 0.0
            g2 = 0.0
            for k in range(9):
                g1 += dT[0, k] * dp[k, j]
                g2 += dT[1, k] * dp[k, j]
            w1 = -dT[0, 2] * dNdv[j]
            w2 = -dT[1, 2] * dNdv[j]
            vdn = v[0] * dn[0, j] + v[1] * dn[1, j] + v[2] * dn[2, j]
            for i in range(3):
                # d(du_dx[0])/dx = -R (e_r e_phi^T + e_phi e_r^T) / d^2 on the cylinder, 0 on the plane
                d2u = 0.0
                if cyl:
                    er_i, er_j = sp[2] * n[i], sp[2] * n[j]          # e_r = sign n
                    d2u = -sp[1] * (er_i * E[j, 0] + E[i, 0] * er_j) / (dist * dist)
                Kx[i, j] = (dudx[0, i] * g1 + dudx[1, i] * g2 - n[i] * dNdx[j] + d2u * T1 - N * dn[i, j]
                            + d_T * (dn[i, j] * vn + n[i] * vdn))
                Dv[i, j] = (dudx[0, i] * w1 + dudx[1, i] * w2 - n[i] * dNdv[j]
                            - d_T * ((1.0 if i == j else 0.0) - n[i] * n[j]))
    a0, a1 = u0, u1
    if active and cyl:
        a0 = h[2] + dphi
    # dissipation with the integrator's trapezoidal quadrature: -(T_n + T)/2 . dxi_sl
    D = -0.5 * ((tn1 + T1) * s1 + (tn2 + T2) * s2)
    hn[0], hn[1], hn[2], hn[3], hn[4] = T1, T2, a0, a1, 1.0
    hn[5] = h[5] + D
    hn[6] = h[6] + math.hypot(s1, s2)
    status = 2 if sliding else 1
    if unresolved:
        status = 3
    hn[7] = float(status)
    hn[8] = N
    return status


# ----------------------------------------------------------------------------------------------
# rigid-body kinematics and the assembled contact set

@njit(cache=True)
def _rotation(kind, qt, A, G):
    """Rotation matrix A and G (omega_local = G d(rotation coordinates)/dt) at total coordinates."""
    if kind == 2:
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
        return
    e0, e1, e2, e3 = qt[3], qt[4], qt[5], qt[6]
    A[0, 0], A[0, 1], A[0, 2] = e0 * e0 + e1 * e1 - e2 * e2 - e3 * e3, 2 * (e1 * e2 - e0 * e3), 2 * (e1 * e3 + e0 * e2)
    A[1, 0], A[1, 1], A[1, 2] = 2 * (e1 * e2 + e0 * e3), e0 * e0 - e1 * e1 + e2 * e2 - e3 * e3, 2 * (e2 * e3 - e0 * e1)
    A[2, 0], A[2, 1], A[2, 2] = 2 * (e1 * e3 - e0 * e2), 2 * (e2 * e3 + e0 * e1), e0 * e0 - e1 * e1 - e2 * e2 + e3 * e3
    G[0, 0], G[0, 1], G[0, 2], G[0, 3] = -2 * e1, 2 * e0, 2 * e3, -2 * e2
    G[1, 0], G[1, 1], G[1, 2], G[1, 3] = -2 * e2, -2 * e3, 2 * e0, 2 * e1
    G[2, 0], G[2, 1], G[2, 2], G[2, 3] = -2 * e3, 2 * e2, -2 * e1, 2 * e0


@njit(cache=True)
def _ep_derivatives(qt, q_t, dA, Gt):
    """Derivatives of the Euler-parameter kinematics of _rotation at total coordinates qt (e =
    qt[3:7], not normalised): dA[m, 3 i + j] = dA_ij/de_m (A is quadratic in e) and Gt (3, 4) =
    G(de/dt). G is linear in e with G(e) e_t = -G(e_t) e, so d(omega_local)/de = -G(e_t)."""
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


def point_law(law, x, v, h, tangent, dt, f, Kx, Dv, hn, S):
    """The contact law at one point for the set kernel: resolved at compile time by the type of
    ``law``: the packed arrays (sp, bp, fp, lp) of the transport kernel of this module (plane and
    cylinder), or the covariant bundle of ``exu_aniso.kernel`` (every surface of the protocol)."""
    raise NotImplementedError("point_law is resolved at compile time")


@overload(point_law)
def _point_law_packed(law, x, v, h, tangent, dt, f, Kx, Dv, hn, S):
    if isinstance(law, types.BaseTuple) and len(law) == 4 and isinstance(law[0], types.Array):
        def impl(law, x, v, h, tangent, dt, f, Kx, Dv, hn, S):
            return contact_point(x, v, h, law[0], law[1], law[2], law[3], tangent, dt, f, Kx, Dv, hn, S)
        return impl
    return None


@njit(cache=True)
def evaluate_set(kind, q, q_t, ref, b, H, law, mode, fq, fv, dt, Q, J, Hn, S):
    """One contact set on one node. q, q_t: node coordinates (without reference values), ref:
    reference coordinates, b (K, 3) body-local points, H (K, 9) converged history, dt time since
    H [s] (0: no branch prediction), S: scratch of shape (SCRATCH_SLOTS, 9, 9).
    mode 0: Q (n,) = generalized force sum Jp^T f;
    mode 1: J (n, n) = -(fq dQ/dq + fv dQ/dq_t) (Exudyn's ODE2 Jacobian convention), complete
            for every node kind: with v = Jp q_t,
            dQ/dq = sum Jp^T Kx Jp + sum f . dJp/dq + sum Jp^T Dv (dJp/dq q_t), dQ/dq_t = sum Jp^T Dv Jp
            (lever arms and point velocities turning with the body; see exudyn_glue
            _BodyKinematics.point_derivatives; rotation-vector nodes by the local increment);
    mode 2: Hn (K, 9) = history candidate. Returns the number of points in contact."""
    nq = q.shape[0]
    K = b.shape[0]
    # scratch views of S (slots 0-8 belong to contact_point)
    A, G, Jp, Kx, Dv, Mg = S[9, :3, :3], S[10, :3, :4], S[11, :3, :nq], S[12, :3, :3], S[13, :3, :3], S[14, :3, :3]
    Kq, Dq = S[15, :nq, :nq], S[16, :nq, :nq]
    qt, x, v, f, wl, hn = S[17, 0, :nq], S[17, 1, :3], S[17, 2, :3], S[17, 3, :3], S[17, 4, :3], S[17, 5, :9]
    for i in range(3):
        for j in range(3):
            Mg[i, j] = 0.0
        for j in range(nq):
            Jp[i, j] = 0.0
    for i in range(nq):
        for j in range(nq):
            Kq[i, j] = 0.0
            Dq[i, j] = 0.0
    for i in range(nq):
        qt[i] = ref[i] + q[i]
    if kind == 2 or kind == 3:
        _rotation(kind, qt, A, G)
    nr = nq - 3
    tangent = mode == 1
    # EP derivatives (mode 1): dA/de_m in rows 3-6 of slot 14, G(e_t) in rows 3-5 of slot 10
    dA, Gt = S[14, 3:7, :9], S[10, 3:6, :4]
    if tangent and kind == 3:
        _ep_derivatives(qt, q_t, dA, Gt)
    # dx/dq: Jp except for Euler parameters (rows 6-8 of slot 17; see exudyn_glue._PointTangent)
    Jx = S[17, 6:9, :nq] if kind == 3 else Jp
    if mode == 0:
        for i in range(nq):
            Q[i] = 0.0
    geo = 0.0
    ncontact = 0
    for k in range(K):
        bx, by, bz = b[k, 0], b[k, 1], b[k, 2]
        if kind == 0 or kind == 1:
            r = 2 if kind == 0 else 0
            c, s = math.cos(qt[r]), math.sin(qt[r])
            ax, ay = c * bx - s * by, s * bx + c * by
            w = q_t[r]
            for i in range(3):
                for j in range(nq):
                    Jp[i, j] = 0.0
            if kind == 0:
                x[0], x[1], x[2] = qt[0] + ax, qt[1] + ay, bz
                v[0], v[1], v[2] = q_t[0] - w * ay, q_t[1] + w * ax, 0.0
                Jp[0, 0] = 1.0
                Jp[1, 1] = 1.0
                Jp[0, 2] = -ay
                Jp[1, 2] = ax
            else:
                x[0], x[1], x[2] = ax, ay, bz + qt[1]
                v[0], v[1], v[2] = -w * ay, w * ax, q_t[1]
                Jp[0, 0] = -ay
                Jp[1, 0] = ax
                Jp[2, 1] = 1.0
        else:
            # omega_local = G q_t_rot; x = p + A b; v = p_t + A (omega_local x b); Jp_rot = -A [b]x G
            for i in range(3):
                wl[i] = 0.0
                for j in range(nr):
                    wl[i] += G[i, j] * q_t[3 + j]
            cb = (wl[1] * bz - wl[2] * by, wl[2] * bx - wl[0] * bz, wl[0] * by - wl[1] * bx)
            for i in range(3):
                x[i] = qt[i] + A[i, 0] * bx + A[i, 1] * by + A[i, 2] * bz
                v[i] = q_t[i] + A[i, 0] * cb[0] + A[i, 1] * cb[1] + A[i, 2] * cb[2]
            # [b]x G
            for j in range(nr):
                s0 = -bz * G[1, j] + by * G[2, j]
                s1 = bz * G[0, j] - bx * G[2, j]
                s2 = -by * G[0, j] + bx * G[1, j]
                for i in range(3):
                    Jp[i, 3 + j] = -(A[i, 0] * s0 + A[i, 1] * s1 + A[i, 2] * s2)
            for i in range(3):
                for j in range(3):
                    Jp[i, j] = 1.0 if i == j else 0.0
            if tangent and kind == 3:          # dx/de_m = dA/de_m b (Euler parameters: not Jp along e)
                for i in range(3):
                    for j in range(3):
                        Jx[i, j] = Jp[i, j]
                    for m in range(4):
                        Jx[i, 3 + m] = dA[m, 3 * i] * bx + dA[m, 3 * i + 1] * by + dA[m, 3 * i + 2] * bz
        st = point_law(law, x, v, H[k], tangent, dt, f, Kx, Dv, hn, S)
        if st > 0:
            ncontact += 1
        if mode == 2:
            for i in range(9):
                Hn[k, i] = hn[i]
            continue
        if mode == 0:
            for j in range(nq):
                Q[j] += Jp[0, j] * f[0] + Jp[1, j] * f[1] + Jp[2, j] * f[2]
            continue
        if st == 0:
            continue
        # Kq += Jp^T Kx Jp, Dq += Jp^T Dv Jp
        for a in range(nq):
            for i in range(3):
                if Jp[i, a] == 0.0:
                    continue
                for j in range(3):
                    ka = Jp[i, a] * Kx[i, j]
                    da = Jp[i, a] * Dv[i, j]
                    for c2 in range(nq):
                        Kq[a, c2] += ka * Jx[j, c2]
                        Dq[a, c2] += da * Jp[j, c2]
        # velocity of the points turning with the body: Kq[:, c] += Jp^T Dv dv/dq_c (Dv = 0 without damping)
        damped = False
        for i in range(3):
            for j in range(3):
                if Dv[i, j] != 0.0:
                    damped = True
        if damped:
            u0 = u1 = u2 = 0.0
            if kind >= 2:                      # u = omega_local x b
                u0, u1, u2 = wl[1] * bz - wl[2] * by, wl[2] * bx - wl[0] * bz, wl[0] * by - wl[1] * bx
            c0 = 2 if kind == 0 else (0 if kind == 1 else 3)
            nc = 1 if kind <= 1 else nr
            for c in range(c0, c0 + nc):
                if kind <= 1:                  # d(w (-a_y, a_x))/drot = w (-a_x, -a_y), a_x = Jp[1, r], a_y = -Jp[0, r]
                    w = q_t[c0]
                    d0, d1, d2 = -w * Jp[1, c0], w * Jp[0, c0], 0.0
                elif kind == 2:                # -A (u x e_c)
                    m = c - 3
                    x0 = 0.0 if m == 0 else (-u2 if m == 1 else u1)
                    x1 = u2 if m == 0 else (0.0 if m == 1 else -u0)
                    x2 = -u1 if m == 0 else (u0 if m == 1 else 0.0)
                    d0 = -(A[0, 0] * x0 + A[0, 1] * x1 + A[0, 2] * x2)
                    d1 = -(A[1, 0] * x0 + A[1, 1] * x1 + A[1, 2] * x2)
                    d2 = -(A[2, 0] * x0 + A[2, 1] * x1 + A[2, 2] * x2)
                else:                          # dA/de_m u + A (b x G(e_t) e_m)
                    m = c - 3
                    g0, g1, g2 = Gt[0, m], Gt[1, m], Gt[2, m]
                    y0, y1, y2 = by * g2 - bz * g1, bz * g0 - bx * g2, bx * g1 - by * g0
                    d0 = dA[m, 0] * u0 + dA[m, 1] * u1 + dA[m, 2] * u2 + A[0, 0] * y0 + A[0, 1] * y1 + A[0, 2] * y2
                    d1 = dA[m, 3] * u0 + dA[m, 4] * u1 + dA[m, 5] * u2 + A[1, 0] * y0 + A[1, 1] * y1 + A[1, 2] * y2
                    d2 = dA[m, 6] * u0 + dA[m, 7] * u1 + dA[m, 8] * u2 + A[2, 0] * y0 + A[2, 1] * y1 + A[2, 2] * y2
                e0 = Dv[0, 0] * d0 + Dv[0, 1] * d1 + Dv[0, 2] * d2
                e1 = Dv[1, 0] * d0 + Dv[1, 1] * d1 + Dv[1, 2] * d2
                e2 = Dv[2, 0] * d0 + Dv[2, 1] * d1 + Dv[2, 2] * d2
                for a in range(nq):
                    Kq[a, c] += Jp[0, a] * e0 + Jp[1, a] * e1 + Jp[2, a] * e2
        if kind == 0:
            geo -= Jp[1, 2] * f[0] - Jp[0, 2] * f[1]
        elif kind == 1:
            geo -= Jp[1, 0] * f[0] - Jp[0, 0] * f[1]
        elif kind == 2:
            fb0 = A[0, 0] * f[0] + A[1, 0] * f[1] + A[2, 0] * f[2]
            fb1 = A[0, 1] * f[0] + A[1, 1] * f[1] + A[2, 1] * f[2]
            fb2 = A[0, 2] * f[0] + A[1, 2] * f[1] + A[2, 2] * f[2]
            fbv = (fb0, fb1, fb2)
            bv = (bx, by, bz)
            bf = bx * fb0 + by * fb1 + bz * fb2
            for i in range(3):
                for j in range(3):
                    Mg[i, j] += fbv[i] * bv[j] - (bf if i == j else 0.0)
        elif kind == 3:
            # EP: Q_rot = G^T (b x A^T f); d/de_m at fixed f = dG/de_m^T c + G^T (b x dA/de_m^T f),
            # c = b x A^T f; G is linear in e, G(e)^T c = 2 Mc e with Mc = [[0, -c^T], [c, -[c]x]]
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
    if mode == 1:
        if kind == 0:
            Kq[2, 2] += geo
        elif kind == 1:
            Kq[0, 0] += geo
        elif kind == 2:
            for i in range(3):
                for j in range(3):
                    Kq[3 + i, 3 + j] += Mg[i, j]
        for i in range(nq):
            for j in range(nq):
                J[i, j] = -(fq * Kq[i, j] + fv * Dq[i, j])
    return ncontact


@njit(cache=True)
def evaluate_linear(q, q_t, ref, idx, Sm, c, H, law, mode, fq, fv, dt, Q, J, Hn, S):
    """A contact set on a linear slave: point k at x_k = c_k + S_k q_total[idx_k], velocity
    v_k = S_k q_t[idx_k], with constant S_k (3, m) over the m set coordinates idx_k (K, m) (a mass
    point: S = I over its own coordinates, c = b; an ANCF cable: the Hermite shape functions of its
    element at the point). q, q_t, ref: the set's coordinates; H (K, 9) converged history; dt time
    since H; S scratch (SCRATCH_SLOTS, 9, 9), slots 0-8 belong to the point law.
    mode 0: Q (n,) = sum S_k^T f_k; mode 1: J (n, n) = -(fq dQ/dq + fv dQ/dq_t) with
    dQ/dq = sum S^T Kx S and dQ/dq_t = sum S^T Dv S (Jp = S is constant: no geometric terms);
    mode 2: Hn (K, 9) = history candidate. Returns the number of points in contact."""
    K, m = idx.shape[0], idx.shape[1]
    n = q.shape[0]
    x, v, f, hn = S[17, 1, :3], S[17, 2, :3], S[17, 3, :3], S[17, 5, :9]
    Kx, Dv = S[12, :3, :3], S[13, :3, :3]
    tangent = mode == 1
    if mode == 0:
        for i in range(n):
            Q[i] = 0.0
    elif mode == 1:
        for i in range(n):
            for j in range(n):
                J[i, j] = 0.0
    ncontact = 0
    for k in range(K):
        for i in range(3):
            xi, vi = c[k, i], 0.0
            for a in range(m):
                g = idx[k, a]
                xi += Sm[k, i, a] * (ref[g] + q[g])
                vi += Sm[k, i, a] * q_t[g]
            x[i], v[i] = xi, vi
        st = point_law(law, x, v, H[k], tangent, dt, f, Kx, Dv, hn, S)
        if st > 0:
            ncontact += 1
        if mode == 2:
            for i in range(9):
                Hn[k, i] = hn[i]
        elif mode == 0:
            for a in range(m):
                Q[idx[k, a]] += Sm[k, 0, a] * f[0] + Sm[k, 1, a] * f[1] + Sm[k, 2, a] * f[2]
        elif st > 0:
            # J[idx_a, idx_b] -= S_a^T (fq Kx + fv Dv) S_b
            for a in range(m):
                for b in range(m):
                    s_ab = 0.0
                    for i in range(3):
                        if Sm[k, i, a] == 0.0:
                            continue
                        for j in range(3):
                            s_ab += Sm[k, i, a] * (fq * Kx[i, j] + fv * Dv[i, j]) * Sm[k, j, b]
                    J[idx[k, a], idx[k, b]] -= s_ab
    return ncontact


class LinearMap:
    """The kinematics of a linear slave for the compiled kernels: idx (K, m) int64 set-coordinate
    indices, S (K, 3, m) constant point Jacobians, c (K, 3) offsets; n set coordinates."""

    def __init__(self, idx, S, c, n):
        self.idx = np.ascontiguousarray(idx, dtype=np.int64)
        self.S = np.ascontiguousarray(S, dtype=float)
        self.c = np.ascontiguousarray(c, dtype=float)
        self.n = int(n)


# layout of the packed call: parameters in one float array W (offsets in I), points, history and
# history candidate in P (3, K, 9), scratch and outputs in S; few arguments keep numba's dispatch
# cost (~0.1 us per argument) small next to the kernel itself
_I_KIND, _I_NQ, _I_SP, _I_BP, _I_FP, _I_LP, _I_REF, _I_END = range(8)


_announced = False


def kernels_cached(entry=None):
    """True if numba's on-disk cache (exu_aniso._numba_cache) holds compiled code of the kernel
    ``entry`` (a numba dispatcher; default: this module's evaluate_packed) for the current source;
    False if the first call will compile (10-20 s). Reads numba's cache index, a private API: when
    that fails, it answers True (say nothing rather than something wrong)."""
    try:
        return bool((entry or evaluate_packed)._cache._cache_file._load_index())
    except Exception:   # noqa: BLE001 - numba internals changed: no announcement
        return True


def announce_compile(stream=None, entry=None):
    """Say once per process, before it happens, that the kernels are being compiled."""
    global _announced
    if _announced:
        return
    _announced = True
    if not kernels_cached(entry):
        where = getattr(getattr(entry or evaluate_packed, "_cache", None), "_cache_path", "numba's cache directory")
        print("exu_aniso: compiling the contact kernels with numba, once (10-20 s); later runs load them "
              f"from the cache in {where}", file=stream or sys.stderr, flush=True)


class PackedSet:
    """Parameters, points, history, outputs and scratch of one contact set packed for one kernel
    call with ten arguments: ``evaluate_packed(mode, q, q_t, fq, fv, dt, W, P, S, I)``. Views: ``H``
    (converged history, written by the caller), ``Q``, ``J``, ``Hn`` (outputs)."""

    def __init__(self, law, node_kind, ref, points):
        """node_kind: a rigid node kind (NODE_KINDS) with body-local points (K, 3), or a LinearMap
        (points: ignored, the map holds the K points)."""
        announce_compile(entry=evaluate_packed_linear if isinstance(node_kind, LinearMap) else None)
        sp, bp, fp, lp = pack_law(law)
        self.linear = node_kind if isinstance(node_kind, LinearMap) else None
        if self.linear is not None:
            kind, nq = -1, self.linear.n
            b = np.zeros((self.linear.idx.shape[0], 3))
        else:
            b = np.asarray(points, dtype=float)
            kind = NODE_KINDS[node_kind]
            nq = NODE_COORDINATES[kind]
        K = b.shape[0]
        offs = np.concatenate([[0], np.cumsum([16, 8, 8, 4, nq])]).astype(np.int64)
        self.I = np.array([kind, nq, *offs], dtype=np.int64)
        self.W = np.concatenate([sp, bp, fp, lp, np.asarray(ref, dtype=float)])
        self.P = np.zeros((3, K, 9))
        self.P[0, :, :3] = b
        self.S = np.zeros((SCRATCH_SLOTS, 9, 9))
        self.H, self.Hn = self.P[1], self.P[2]
        if self.linear is not None:
            self.Q, self.J = np.zeros(nq), np.zeros((nq, nq))
        else:
            self.Q = self.S[17, 6, :nq]
            self.J = self.S[18, :nq, :nq]

    def evaluate(self, mode, q, q_t, fq, fv, dt):
        if self.linear is not None:
            lm = self.linear
            return evaluate_packed_linear(mode, q, q_t, fq, fv, dt, self.W, self.P, self.S, self.I, lm.idx, lm.S,
                                          lm.c, self.Q, self.J)
        return evaluate_packed(mode, q, q_t, fq, fv, dt, self.W, self.P, self.S, self.I)


@njit(cache=True)
def evaluate_packed(mode, q, q_t, fq, fv, dt, W, P, S, I):
    """evaluate_set on the arrays packed by PackedSet."""
    nq = I[_I_NQ]
    law = (W[I[_I_SP]:I[_I_BP]], W[I[_I_BP]:I[_I_FP]], W[I[_I_FP]:I[_I_LP]], W[I[_I_LP]:I[_I_REF]])
    return evaluate_set(I[_I_KIND], q, q_t, W[I[_I_REF]:I[_I_END]], P[0, :, :3], P[1], law, mode, fq, fv, dt,
                        S[17, 6, :nq], S[18, :nq, :nq], P[2], S)


@njit(cache=True)
def evaluate_packed_linear(mode, q, q_t, fq, fv, dt, W, P, S, I, idx, Sm, c, Q, J):
    """evaluate_linear on the arrays packed by PackedSet (a linear slave)."""
    law = (W[I[_I_SP]:I[_I_BP]], W[I[_I_BP]:I[_I_FP]], W[I[_I_FP]:I[_I_LP]], W[I[_I_LP]:I[_I_REF]])
    return evaluate_linear(q, q_t, W[I[_I_REF]:I[_I_END]], idx, Sm, c, P[1], law, mode, fq, fv, dt, Q, J, P[2], S)
