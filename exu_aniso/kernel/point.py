"""The covariant contact kernel for one slave point on any surface of the protocol, compiled with
numba and composed from the surface's chart (``geometry._core``), the adhesion and friction nets
(``nets``) and the return maps (``law.return_map``). Python
callers (the numpy reference) call the same compiled function, so both engines evaluate one
definition.

Symbols (papers' notation): x the slave point, (xi1, xi2) the convective coordinates
of its closest point C, xi3 the normal gap, rho_i, n, m_ij, h_ij, A_ij = m_ij - xi3 h_ij; T the
tangential traction, N the normal traction (<= 0), B = -C adhesion (negative definite), F friction.
Tensors and the traction are stored by their components in the orthonormal tangent frame
(a_1, a_2) of C (``nets.tangent_frame``), which the law treats as the papers' metric-free case.

One step from the converged history (T_n in the frame at the anchor xi_n):

1. project x (hint xi_n); open if xi3 >= 0 (a sticking history is released: T.C^-1 T / 2 is
   booked as dissipated);
2. the coordinate increment d xi = xi - xi_n, periodic coordinates unwrapped to the branch
   closest to the prediction (A^-1 rho^T v dt); a branch farther than a quarter period from the
   prediction is an unresolved step (status 3) that the engine must refine;
3. T_n is carried to C by parallel transport along d xi (midpoint rule, second order); the slip
   increment is d xi^i rho_i at the midpoint, carried from there to C the same way, so steady
   sliding does not depend on the step;
4. T_tr = T_n + B slip, T = return map (seed / exact / radial), N = eps_N xi3 + d_N n.v;
5. the force on the slave point is the one conjugate to the slip of C: G^T T - N n, with
   G = E^T rho A^-1 rho^T (2 x 3); a tangential dashpot -d_T (v - n (n.v)) while loaded;
6. the tangent df/dx: chain rule through q = (xi1, xi2, xi3) with d xi / dx = A^-1 rho^T and
   d xi3 / dx = n; the law's derivative analytic (dT/dp of the return map); the derivatives of the
   surface quantities (transported traction, slip, B, F, n, G) with respect to xi by central
   differences of their analytic definitions (they are smooth in xi; the only non-smooth part, the
   return map, is differentiated analytically at the state itself; central stencil, ~1e-10).

All geometry is done in the surface's local frame; x, v in and f, df/dx, df/dv out are in the
master frame.
"""
from __future__ import annotations

import math
import sys
import time
import warnings
from collections import namedtuple

import numpy as np
from numba import njit, types
from numba.extending import intrinsic, overload

from exu_aniso.kernel.nodes import NODE_KINDS, LinearSlave, node_coordinates_of
from exu_aniso.kernel.sets import LinearMap, evaluate_group, evaluate_linear, evaluate_pair, evaluate_set
from exu_aniso.kernel.sets import S_J, S_LAW, S_VEC, Y_DV, Y_F, Y_GAP, Y_INFO, Y_KX, Y_ROWS, Y_V, Y_X
from exu_aniso.kernel.sets import point_states as sets_point_states
from exu_aniso.kernel.stored import StoredArguments, _deref, machine_address
from exu_aniso.geometry import _core
from exu_aniso.geometry._core import add, dot, local_chart, scale, sub
from exu_aniso.law.history import (H_ACTIVE, H_DISSIPATED, H_NORMAL, H_SLIP, H_STATUS, H_T1, H_T2, H_XI1,
                                      H_XI2, N_HISTORY, OPEN, SLIP, STICK, UNRESOLVED)
from exu_aniso.law.return_maps import MAPS, return_map, run_time, sliding_force, sticks, trial_norm
from exu_aniso.fields.nets import physical, physical_pair, tangent_frame

LawParams = namedtuple("LawParams", ("eps_N", "d_N", "d_T", "method"))
# central difference step of the surface quantities in xi, relative to the local length scale
# (angles: in radians); the central stencil's error is ~ step^2 (truncation) + eps / step
# (round-off), ~1e-10 relative: Newton needs no more (a fourth-order stencil, ~1e-12, cost twice the
# surface-term evaluations, the larger part of a Jacobian call)
XI_STEP = 1e-5


@njit(cache=True)
def _rot_to_local(p, v):
    return (dot(v, p.ex), dot(v, p.ey), dot(v, p.ez))


@njit(cache=True)
def _A_inv(r1, r2, r11, r12, r22, n, xi3):
    m11, m12, m22 = dot(r1, r1), dot(r1, r2), dot(r2, r2)
    h11, h12, h22 = dot(r11, n), dot(r12, n), dot(r22, n)
    a11, a12, a22 = m11 - xi3 * h11, m12 - xi3 * h12, m22 - xi3 * h22
    idet = 1.0 / (a11 * a22 - a12 * a12)
    return a22 * idet, -a12 * idet, a11 * idet, h11, h12, h22


@njit(cache=True)
def _contra(r1, r2, w):
    """Contravariant components of the tangent vector w in the basis (r1, r2)."""
    m11, m12, m22 = dot(r1, r1), dot(r1, r2), dot(r2, r2)
    idet = 1.0 / (m11 * m22 - m12 * m12)
    b1, b2 = dot(w, r1), dot(w, r2)
    return (m22 * b1 - m12 * b2) * idet, (m11 * b2 - m12 * b1) * idet


@njit(cache=True)
def anchor_contravariant(sp, xn1, xn2, Tn1, Tn2):
    """Contravariant components at the anchor xi_n of the stored traction (physical components in
    the anchor's tangent frame): what parallel transport carries. Computed once per evaluation,
    not in every stencil point of the tangent. On a chart with a constant metric the physical
    components themselves (transport changes neither, and the frame has the same components in
    (rho_1, rho_2) everywhere): surface_terms takes them as they are."""
    if (Tn1 == 0.0 and Tn2 == 0.0) or _core.constant_metric(sp):
        return Tn1, Tn2
    rn, rn1, rn2, _, _, _ = local_chart(sp, xn1, xn2)
    b1, b2, _ = tangent_frame(rn1, rn2)
    return _contra(rn1, rn2, add(scale(Tn1, b1), scale(Tn2, b2)))


@njit(cache=True)
def surface_terms(sp, netB, netF, xi1, xi2, xi3, xn1, xn2, tn1, tn2):
    """The quantities at C(xi1, xi2) (unwrapped coordinates) for the stored state: anchor xi_n and
    the traction's contravariant components (tn1, tn2) there (``anchor_contravariant``):
    transported traction (2), slip (2), B (3, negative definite), F (3), n (3), G (6, rows of the
    2 x 3 matrix), all in the local frame. Smooth in xi: the kernel differences them for the tangent."""
    r, r1, r2, a1, a2, n, M, _, _ = _chart_at(sp, xi1, xi2, xi3)
    return _surface_terms_at(sp, netB, netF, xi1, xi2, xn1, xn2, tn1, tn2, r, r1, r2, a1, a2, n, M)


@njit(cache=True, inline="always")
def _surface_terms_at(sp, netB, netF, xi1, xi2, xn1, xn2, tn1, tn2, r, r1, r2, a1, a2, n, M):
    """surface_terms given the chart (r, r1, r2), the frame (a1, a2, n) and A^-1 (M, as _A_inv
    returns it) at C: contact_point has them already."""
    d1, d2 = xi1 - xn1, xi2 - xn2
    # T_n: contravariant at xi_n -> transport -> physical components at xi (a constant metric: the
    # physical components unchanged, anchor_contravariant)
    Tt1, Tt2 = (tn1, tn2) if _core.constant_metric(sp) else (0.0, 0.0)
    if (tn1 != 0.0 or tn2 != 0.0) and not _core.constant_metric(sp):
        t1, t2 = _core.transport(sp, xn1, xn2, d1, d2, tn1, tn2)
        w = add(scale(t1, r1), scale(t2, r2))
        Tt1, Tt2 = dot(w, a1), dot(w, a2)
    # slip: d xi at the midpoint, carried to C
    s1, s2 = _core.transport(sp, xn1 + 0.5 * d1, xn2 + 0.5 * d2, 0.5 * d1, 0.5 * d2, d1, d2)
    w = add(scale(s1, r1), scale(s2, r2))
    S1, S2 = dot(w, a1), dot(w, a2)
    (c11, c12, c22), (f11, f12, f22) = physical_pair(netB, netF, xi1, xi2, r, r1, r2, a1, a2)
    # G = E^T rho A^-1 rho^T
    M11, M12, M22 = M[0], M[1], M[2]
    e11, e12 = dot(a1, r1), dot(a1, r2)
    e21, e22 = dot(a2, r1), dot(a2, r2)
    g11, g12 = e11 * M11 + e12 * M12, e11 * M12 + e12 * M22      # row 1 of E^T rho A^-1
    g21, g22 = e21 * M11 + e22 * M12, e21 * M12 + e22 * M22
    G1 = add(scale(g11, r1), scale(g12, r2))
    G2 = add(scale(g21, r1), scale(g22, r2))
    return (Tt1, Tt2, S1, S2, -c11, -c12, -c22, f11, f12, f22, n[0], n[1], n[2],
            G1[0], G1[1], G1[2], G2[0], G2[1], G2[2])


# the surface terms (surface_terms) by position: transported traction (2), slip (2), B (11, 12, 22),
# F (11, 12, 22), n (3), G's first and second row (3 each)
ST_T1, ST_T2, ST_S1, ST_S2 = 0, 1, 2, 3
ST_B11, ST_B12, ST_B22, ST_F11, ST_F12, ST_F22 = 4, 5, 6, 7, 8, 9
ST_N, ST_G1, ST_G2 = 10, 13, 16                  # the first of three each
_NT = 19            # number of surface terms


@njit(cache=True)
def net_at(sp, net, xi1, xi2):
    """Components (p11, p12, p22) of a net's positive tensor (C = -B or F) in the tangent frame at
    (xi1, xi2)."""
    r, r1, r2, _, _, _ = local_chart(sp, xi1, xi2)
    a1, a2, _ = tangent_frame(r1, r2)
    return physical(net, xi1, xi2, r, r1, r2, a1, a2)


@njit(cache=True)
def net_at_batch(sp, net, anchors, out):
    """net_at at every row (xi1, xi2) of anchors (K, 2) into out (K, 3), in one call."""
    for k in range(anchors.shape[0]):
        c = net_at(sp, net, anchors[k, 0], anchors[k, 1])
        out[k, 0], out[k, 1], out[k, 2] = c[0], c[1], c[2]


# A history row inside the kernel: a tuple of N_HISTORY numbers in the order of
# law.history.HISTORY_FIELDS, read from and written to the (K, 9) arrays by name (row_at, put_row:
# functions of their own, called). The force loop makes no array view of a point's rows and passes
# no array to a function inlined at numba IR: either costs an atomic reference count up and down per
# point, which numba's pruning does not remove across the law's branches (perf on the native force
# call of the 256-point block: NRT_incref/decref 10.5% of the samples, 8 calls per point; 0.8% without).
assert (H_T1, H_T2, H_XI1, H_XI2, H_ACTIVE, H_DISSIPATED, H_SLIP, H_STATUS, H_NORMAL) == tuple(range(N_HISTORY))


@njit(cache=True, inline="always")
def history_row(T1, T2, xi1, xi2, active, dissipated, slip, status, normal):
    """A history row (tuple, HISTORY_FIELDS order) from its fields."""
    return (T1, T2, xi1, xi2, active, dissipated, slip, status, normal)


@njit(cache=True)
def row_at(H, k):
    """Row k of a history array H (K, 9) as a tuple."""
    return history_row(H[k, H_T1], H[k, H_T2], H[k, H_XI1], H[k, H_XI2], H[k, H_ACTIVE], H[k, H_DISSIPATED],
                       H[k, H_SLIP], H[k, H_STATUS], H[k, H_NORMAL])


@njit(cache=True)
def put_row(H, k, h):
    """Row k of a history array H (K, 9) = the tuple h."""
    H[k, H_T1], H[k, H_T2], H[k, H_XI1], H[k, H_XI2] = h[H_T1], h[H_T2], h[H_XI1], h[H_XI2]
    H[k, H_ACTIVE], H[k, H_DISSIPATED], H[k, H_SLIP] = h[H_ACTIVE], h[H_DISSIPATED], h[H_SLIP]
    H[k, H_STATUS], H[k, H_NORMAL] = h[H_STATUS], h[H_NORMAL]


@njit(cache=True)
def stored_energy(sp, netB, active, xi1, xi2, T1, T2):
    """The adhesion spring's energy T . C^-1 T / 2 [J] of a history row's traction (T1, T2) at its
    anchor (xi1, xi2), C = -B there; 0 for a row not in contact (active 0)."""
    if not active > 0.5:
        return 0.0
    r, r1, r2, _, _, _ = local_chart(sp, xi1, xi2)
    a1, a2, _ = tangent_frame(r1, r2)
    c11, c12, c22 = physical(netB, xi1, xi2, r, r1, r2, a1, a2)
    det = c11 * c22 - c12 * c12
    return 0.5 * (c22 * T1 * T1 - 2.0 * c12 * T1 * T2 + c11 * T2 * T2) / det


@njit(cache=True)
def stored_energy_batch(sp, netB, H, out):
    """stored_energy of every row of H (K, 9) into out (K,), in one call (the energy ledger: every
    point of every sample)."""
    for k in range(H.shape[0]):
        out[k] = stored_energy(sp, netB, H[k, H_ACTIVE], H[k, H_XI1], H[k, H_XI2], H[k, H_T1], H[k, H_T2])


@njit(cache=True, inline="always")
def _chart_at(sp, xi1, xi2, xi3):
    """What the kernel needs of the chart at the contact point C (local frame): rho, rho_1, rho_2, the
    frame a_1, a_2, n (on the slave's side), A^-1 and h_ij as (A^-1_11, A^-1_12, A^-1_22, h11, h12,
    h22), and the rows X1, X2 of d xi / dx = A^-1 rho^T."""
    return _frame_at(sp, local_chart(sp, xi1, xi2), xi3)


@njit(cache=True, inline="always")
def _frame_at(sp, chart, xi3):
    """_chart_at from the local chart at C (the projection's)."""
    r, r1, r2, r11, r12, r22 = chart
    a1, a2, nu = tangent_frame(r1, r2)
    n = scale(sp.sign, nu)
    M = _A_inv(r1, r2, r11, r12, r22, n, xi3)
    X1 = add(scale(M[0], r1), scale(M[1], r2))
    X2 = add(scale(M[1], r1), scale(M[2], r2))
    return r, r1, r2, a1, a2, n, M, X1, X2


@njit(cache=True, inline="always")
def _normal_traction(law, xi3, n, vl):
    """N = eps_N xi3 + d_N n.v, clipped to <= 0: (N, loaded, n.v)."""
    vn = dot(n, vl)
    N = law.eps_N * xi3 + law.d_N * vn
    loaded = N < 0.0
    return (N if loaded else 0.0), loaded, vn


@njit(cache=True, inline="always")
def _trial(st):
    """The trial traction T_tr = T_n (transported) + B slip and the tensors B, F from the surface terms."""
    Ttr1 = st[ST_T1] + st[ST_B11] * st[ST_S1] + st[ST_B12] * st[ST_S2]
    Ttr2 = st[ST_T2] + st[ST_B12] * st[ST_S1] + st[ST_B22] * st[ST_S2]
    return Ttr1, Ttr2, (st[ST_B11], st[ST_B12], st[ST_B22]), (st[ST_F11], st[ST_F12], st[ST_F22])


@njit(cache=True)
def point_tangent(sp, netB, netF, law, state, Kx, Dv, W):
    """df/dx Kx and df/dv Dv (3, 3, master frame) of the law at a point's state (step 6 of the
    module docstring), state as contact_force returns it: the slave point y and its velocity vl
    (local frame), the contact point (xi1, xi2, xi3) (unwrapped), the anchor xn with the traction's
    contravariant components tn there, active. The quantities at C and the return map (with dT/dp,
    into W[0, 0:2]) are evaluated again from these, the same functions on the same numbers as the
    force (a Jacobian call is rare): a function of its own with few arguments, compiled once per
    law, so that the force path holds none of this code and keeps nothing alive for it. A point that
    did not reach the law (state[0] = 0: open, or its step unresolved) gets Kx = Dv = 0."""
    for i in range(3):
        for j in range(3):
            Kx[i, j] = 0.0
            Dv[i, j] = 0.0
    if not state[0] > 0.5:
        return
    y, vl = (state[1], state[2], state[3]), (state[4], state[5], state[6])
    xi1, xi2, xi3, xn1, xn2, tn1, tn2 = state[7], state[8], state[9], state[10], state[11], state[12], state[13]
    active = state[14] > 0.5
    r, r1, r2, a1, a2, n, M, X1, X2 = _chart_at(sp, xi1, xi2, xi3)
    M11, M12, M22, h11, h12, h22 = M
    st = _surface_terms_at(sp, netB, netF, xi1, xi2, xn1, xn2, tn1, tn2, r, r1, r2, a1, a2, n, M)
    N, loaded, vn = _normal_traction(law, xi3, n, vl)
    G1 = (st[ST_G1], st[ST_G1 + 1], st[ST_G1 + 2])
    G2 = (st[ST_G2], st[ST_G2 + 1], st[ST_G2 + 2])
    dTd = law.d_T if loaded else 0.0
    dT = W[0, 0:2, :]
    Ttr1, Ttr2, B, F = _trial(st)
    T1, T2 = return_map(law.method, Ttr1, Ttr2, -N, B, F, dT, run_time(True))[:2]
    # surface terms differenced in xi (at fixed xi3); G also depends on xi3 (analytic)
    Kl = W[0, 2:5, 0:3]
    Dl = W[0, 5:8, 0:3]
    dS = W[1].reshape(81)[:2 * _NT].reshape((2, _NT))
    dq = W[2].reshape(81)[:_NT]
    # step: XI_STEP of the local length scale (the point's distance from the local origin, at
    # most the smallest radius of curvature); an angle coordinate steps XI_STEP radians
    m11, m22 = dot(r1, r1), dot(r2, r2)
    kappa = math.sqrt(h11 * h11 / (m11 * m11) + 2.0 * h12 * h12 / (m11 * m22) + h22 * h22 / (m22 * m22))
    ell = max(math.sqrt(dot(y, y)), 1e-9)
    if kappa * ell > 1.0:
        ell = 1.0 / kappa
    for i in range(2):
        period = sp.period1 if i == 0 else sp.period2
        hs = XI_STEP if period > 0.0 else XI_STEP * ell / math.sqrt(m11 if i == 0 else m22)
        e1, e2 = hs * (i == 0), hs * (i == 1)
        # a new contact anchors at the current point: the anchor moves with it (no slip)
        m1, m2 = (0.0, 0.0) if active else (e1, e2)
        # central difference (f(h) - f(-h)) / 2 h
        a = surface_terms(sp, netB, netF, xi1 + e1, xi2 + e2, xi3, xn1 + m1, xn2 + m2, tn1, tn2)
        b = surface_terms(sp, netB, netF, xi1 - e1, xi2 - e2, xi3, xn1 - m1, xn2 - m2, tn1, tn2)
        for k in range(_NT):
            dS[i, k] = (a[k] - b[k]) / (2.0 * hs)
    # dG/dxi3 = E^T rho A^-1 h A^-1 rho^T
    Ah11 = M11 * h11 + M12 * h12
    Ah12 = M11 * h12 + M12 * h22
    Ah21 = M12 * h11 + M22 * h12
    Ah22 = M12 * h12 + M22 * h22
    W11, W12 = Ah11 * M11 + Ah12 * M12, Ah11 * M12 + Ah12 * M22
    W21, W22 = Ah21 * M11 + Ah22 * M12, Ah21 * M12 + Ah22 * M22   # A^-1 h A^-1
    e11, e12, e21, e22 = dot(a1, r1), dot(a1, r2), dot(a2, r1), dot(a2, r2)
    q11, q12 = e11 * W11 + e12 * W21, e11 * W12 + e12 * W22
    q21, q22 = e21 * W11 + e22 * W21, e21 * W12 + e22 * W22
    dG3_1 = add(scale(q11, r1), scale(q12, r2))
    dG3_2 = add(scale(q21, r1), scale(q22, r2))
    for j in range(3):
        X1j, X2j, nj = X1[j], X2[j], n[j]
        for k in range(_NT):
            dq[k] = dS[0, k] * X1j + dS[1, k] * X2j
        dn = (dq[ST_N], dq[ST_N + 1], dq[ST_N + 2])
        dNj = 0.0
        if loaded:
            dNj = law.eps_N * nj + law.d_N * dot(dn, vl)
        # p = (Ttr1, Ttr2, |N|, b11, b12, b22, f11, f12, f22)
        dTtr1 = (dq[ST_T1] + dq[ST_B11] * st[ST_S1] + dq[ST_B12] * st[ST_S2] + st[ST_B11] * dq[ST_S1]
                 + st[ST_B12] * dq[ST_S2])
        dTtr2 = (dq[ST_T2] + dq[ST_B12] * st[ST_S1] + dq[ST_B22] * st[ST_S2] + st[ST_B12] * dq[ST_S1]
                 + st[ST_B22] * dq[ST_S2])
        dp = (dTtr1, dTtr2, -dNj, dq[ST_B11], dq[ST_B12], dq[ST_B22], dq[ST_F11], dq[ST_F12], dq[ST_F22])
        dT1 = 0.0
        dT2 = 0.0
        for k in range(9):
            dT1 += dT[0, k] * dp[k]
            dT2 += dT[1, k] * dp[k]
        dG1 = add((dq[ST_G1], dq[ST_G1 + 1], dq[ST_G1 + 2]), scale(nj, dG3_1))
        dG2 = add((dq[ST_G2], dq[ST_G2 + 1], dq[ST_G2 + 2]), scale(nj, dG3_2))
        col = add(add(scale(T1, dG1), scale(T2, dG2)), add(scale(dT1, G1), scale(dT2, G2)))
        col = sub(col, add(scale(dNj, n), scale(N, dn)))
        if dTd > 0.0:
            col = add(col, scale(dTd, add(scale(vn, dn), scale(dot(vl, dn), n))))
        for i in range(3):
            Kl[i, j] = col[i]
    # df/dv: N through d_N n.v, the dashpot
    dNv = law.d_N if loaded else 0.0
    for j in range(3):
        dT1 = -dT[0, 2] * dNv * n[j]
        dT2 = -dT[1, 2] * dNv * n[j]
        for i in range(3):
            Dl[i, j] = dT1 * G1[i] + dT2 * G2[i] - n[i] * dNv * n[j] - dTd * ((i == j) - n[i] * n[j])
    # to the master frame: K = R Kl R^T with R = [ex ey ez] (columns)
    R0, R1, R2 = sp.ex, sp.ey, sp.ez
    for i in range(3):
        Ri = (R0[i], R1[i], R2[i])
        for j in range(3):
            Rj = (R0[j], R1[j], R2[j])
            k = 0.0
            d = 0.0
            for a in range(3):
                for b in range(3):
                    k += Ri[a] * Kl[a, b] * Rj[b]
                    d += Ri[a] * Dl[a, b] * Rj[b]
            Kx[i, j] = k
            Dv[i, j] = d


NO_STATE = (0.0,) * 15      # contact_force's state of a point that did not reach the law
NO_FORCE = (0.0, 0.0, 0.0)


@njit(cache=True)
def contact_point(sp, netB, netF, law, x, v, h, dt, tangent, f, Kx, Dv, hn, W):
    """Force f (3), df/dx Kx (3, 3), df/dv Dv (3, 3) (when tangent) on the slave point at x with
    velocity v (master frame, relative to the master), and the history candidate hn (9) from the
    converged history h (9): traction (2, frame at the anchor), anchor xi (2, unwrapped), active,
    dissipated energy, slip distance, status, N. dt: time since h (predicts the branch of periodic
    coordinates). W: scratch of shape (3, 9, 9) (no allocation per call). Returns the status (OPEN,
    STICK, SLIP, UNRESOLVED: kernel.history) and the normal gap xi3. contact_force, then
    point_tangent: what the set kernels do, in two loops over their points (point_states)."""
    status, xi3, state, fc, row = contact_force(sp, netB, netF, law, (x[0], x[1], x[2]), (v[0], v[1], v[2]),
                                                row_at(h.reshape((1, N_HISTORY)), 0), dt, W[0, 0:2, :])
    for i in range(3):
        f[i] = fc[i]
    put_row(hn.reshape((1, N_HISTORY)), 0, row)
    if tangent:
        point_tangent(sp, netB, netF, law, state, Kx, Dv, W)
    return status, xi3


# inlined into the set kernels' loop over the points (numba IR level): a call per point cost ~0.1 us of
# reference counting of its array arguments and stack set-up (K = 16 points, mode 0, 4.75 -> 3.41 us)
@njit(cache=True, inline="always")
def contact_force(sp, netB, netF, law, x, v, h, dt, dT):
    """contact_point's force and history candidate, without derivatives: x, v (3-tuples), h the
    converged history row (a tuple: history_row); dT (2, 9): any scratch (a force call's return map
    does not write it). Returns (status, xi3, state, f, hn): f (3-tuple) the force, hn the history
    candidate row (tuple), state what point_tangent needs, (reached, y (3), v (3) in the surface's
    local frame, xi1, xi2, xi3, xn1, xn2, tn1, tn2, active), reached = 1 for a point that got to the
    law (NO_STATE otherwise)."""
    active = h[H_ACTIVE] > 0.5
    hint1, hint2 = (h[H_XI1], h[H_XI2]) if active else (math.nan, math.nan)
    y = _core.to_local(sp, (x[0], x[1], x[2]))
    xi1, xi2, xi3, pstat, chart = _core.project_local(sp, y, hint1, hint2)
    if not xi3 < 0.0:                      # open (a gap that is NaN or undefined counts below)
        if xi3 >= 0.0:
            # the accumulated columns kept, the rest reset; a sticking history is released: its
            # T . C^-1 T / 2 at the anchor is booked as dissipated
            released = stored_energy(sp, netB, h[H_ACTIVE], h[H_XI1], h[H_XI2], h[H_T1], h[H_T2])
            return OPEN, xi3, NO_STATE, NO_FORCE, history_row(0.0, 0.0, 0.0, 0.0, 0.0, h[H_DISSIPATED] + released,
                                                              h[H_SLIP], float(OPEN), 0.0)
    if pstat == 2 and not active:
        raise ValueError("slave point at a centre of curvature of the surface (on the cylinder axis, a cone's axis, "
                         "a sphere's centre or a torus's centre circle): the closest point is not unique there")
    if pstat == 1 or pstat == 2:
        # Newton's projection did not converge, or a point in contact at the last step lies at a centre of
        # curvature: a Newton iterate put it far off the surface. It gives no force in this iterate and
        # keeps its history; if the converged state is still so, the engine rejects the step and repeats
        # it with a smaller one (UNRESOLVED). A new point at a centre of curvature is an error (above).
        return UNRESOLVED, xi3, NO_STATE, NO_FORCE, history_row(h[H_T1], h[H_T2], h[H_XI1], h[H_XI2], h[H_ACTIVE],
                                                                h[H_DISSIPATED], h[H_SLIP], float(UNRESOLVED),
                                                                h[H_NORMAL])
    if pstat == 3 or not xi3 < 0.0:
        raise ValueError("the surface chart is singular at the closest point of a slave point in contact (a pole of "
                         "the sphere's chart, the polar origin, a cone's apex): choose axis_direction so that the "
                         "path avoids it")
    vl = _rot_to_local(sp, (v[0], v[1], v[2]))
    # the frame, A^-1 and d xi / dx = A^-1 rho^T (rows X1, X2) from the projection's chart, local frame
    r, r1, r2, a1, a2, n, M, X1, X2 = _frame_at(sp, chart, xi3)
    # anchor and increment: periodic coordinates to the branch of the predicted increment
    status = STICK
    if active:
        p1, p2 = dot(X1, vl) * dt, dot(X2, vl) * dt
        d1, e1 = _core.unwrap(sp.period1, xi1 - h[H_XI1], p1)
        d2, e2 = _core.unwrap(sp.period2, xi2 - h[H_XI2], p2)
        if (sp.period1 > 0.0 and e1 > 0.25 * sp.period1) or (sp.period2 > 0.0 and e2 > 0.25 * sp.period2):
            status = UNRESOLVED
        xn1, xn2, Tn1, Tn2 = h[H_XI1], h[H_XI2], h[H_T1], h[H_T2]
        xi1, xi2 = xn1 + d1, xn2 + d2
    else:
        xn1, xn2, Tn1, Tn2 = xi1, xi2, 0.0, 0.0
    tn1, tn2 = anchor_contravariant(sp, xn1, xn2, Tn1, Tn2)
    # the chart, frame and A^-1 at C taken above at the projection's coordinates: the unwrapped ones
    # name the same point (a periodic coordinate another branch, up to round-off)
    st = _surface_terms_at(sp, netB, netF, xi1, xi2, xn1, xn2, tn1, tn2, r, r1, r2, a1, a2, n, M)
    N, loaded, vn = _normal_traction(law, xi3, n, vl)
    Ttr1, Ttr2, B, F = _trial(st)
    if sticks(Ttr1, Ttr2, -N, F):
        # a sticking point: return_map's result without the call
        T1, T2, state, sl1, sl2 = Ttr1, Ttr2, STICK, 0.0, 0.0
    else:
        T1, T2, state, sl1, sl2 = sliding_force(law.method, Ttr1, Ttr2, -N, B, F, trial_norm(Ttr1, Ttr2, F), dT)
    if state == SLIP and status != UNRESOLVED:
        status = SLIP
    G1 = (st[ST_G1], st[ST_G1 + 1], st[ST_G1 + 2])
    G2 = (st[ST_G2], st[ST_G2 + 1], st[ST_G2 + 2])
    dTd = law.d_T if loaded else 0.0
    fl = sub(add(scale(T1, G1), scale(T2, G2)), scale(N, n))
    fl = sub(fl, scale(dTd, sub(vl, scale(vn, n))))
    fg = _core.to_global(sp, fl)
    # energy removed by the return map in the step (trapezoidal, as contact.ContactLaw)
    D = -0.5 * ((st[ST_T1] + T1) * sl1 + (st[ST_T2] + T2) * sl2)
    slipped = math.sqrt(sl1 * sl1 + sl2 * sl2) if state == SLIP else 0.0
    hn = history_row(T1, T2, xi1, xi2, 1.0, h[H_DISSIPATED] + D, h[H_SLIP] + slipped, float(status), N)
    return status, xi3, (1.0, y[0], y[1], y[2], vl[0], vl[1], vl[2], xi1, xi2, xi3, xn1, xn2, tn1, tn2,
                         1.0 if active else 0.0), (fg[0], fg[1], fg[2]), hn


# ----------------------------------------------------------------------------------------------
# a contact set on one Exudyn node: the node kinematics of kernel.sets.evaluate_set with this kernel

CovariantLaw = namedtuple("CovariantLaw", ("surface", "adhesion", "friction", "law"))


# The law of a set's kernel: contact_force inlined into one loop over the points, and a Jacobian call's
# point_tangent in a second loop, in a function of its own compiled once per law (tangent a run-time
# flag). Inlined into every loop of the set kernels instead (and with derivatives), the law was copied
# and compiled several times per kernel: the block's first compilation 35 -> 24 s.
@overload(sets_point_states)
def _point_states_covariant(law, Y, H, Hn, first, count, dt, tangent, S):
    if getattr(law, "instance_class", None) is CovariantLaw:
        def impl(law, Y, H, Hn, first, count, dt, tangent, S):
            W = S[S_LAW:S_LAW + 3]
            dT = W[0, 0:2, :]
            sp, netB, netF, lp = law.surface, law.adhesion, law.friction, law.law
            ncontact = 0
            unresolved = False
            for k in range(first, first + count):
                # by element, no view of a row (see history_row)
                x = (Y[k, Y_X, 0], Y[k, Y_X, 1], Y[k, Y_X, 2])
                v = (Y[k, Y_V, 0], Y[k, Y_V, 1], Y[k, Y_V, 2])
                st, xi3, state, f, hn = contact_force(sp, netB, netF, lp, x, v, row_at(H, k), dt, dT)
                Y[k, Y_F, 0], Y[k, Y_F, 1], Y[k, Y_F, 2] = f[0], f[1], f[2]
                Y[k, Y_INFO, 2] = st
                Y[k, Y_GAP, 0] = xi3
                ncontact += st > 0
                unresolved |= st == UNRESOLVED
                if tangent:                # the state for the second loop, in the rows of df/dx and df/dv;
                    _put_state(Y, k, state)    # a Jacobian call keeps the last residual's candidate
                else:
                    put_row(Hn, k, hn)
            if tangent:
                for k in range(first, first + count):
                    state = _get_state(Y, k)
                    point_tangent(sp, netB, netF, lp, state, Y[k, Y_KX:Y_KX + 3], Y[k, Y_DV:Y_DV + 3], W)
            return ncontact, unresolved
        return impl
    return None


# ----------------------------------------------------------------------------------------------
# A set's kernel calls its law through an address: the set kernels (kernel.sets, below) are compiled
# once per node kind and the law (law_entry) once per surface, nets and return map, and neither holds
# the other's code. Compiled into one unit per (law, node kind), every new pairing compiled the set
# kernel again (docs/guide/decisions.md).

LawCall = namedtuple("LawCall", ("entry", "law"))
LawCall.__doc__ = """What a set's kernel gets for its law, two int64 addresses: ``entry``, the machine code of
law_entry compiled for the law bundle's type; ``law``, the bundle stored (kernel.stored.StoredArguments)."""

_F3, _F2 = types.float64[:, :, ::1], types.float64[:, ::1]
# law_entry's arguments after the bundle's pointer: Y, H, Hn, first, count, dt, tangent, S (kernel.sets.point_states)
LAW_ARGS = (_F3, _F2, _F2, types.int64, types.int64, types.float64, types.boolean, _F3)


@njit(cache=True)
def law_entry(law, Y, H, Hn, first, count, dt, tangent, S):
    """kernel.sets.point_states of the law bundle at the pointer ``law`` (a CPointer of its type): the
    number of points in contact, or -1 minus that number when a point's step is unresolved."""
    ncontact, unresolved = sets_point_states(_deref(law), Y, H, Hn, first, count, dt, tangent, S)
    return -1 - ncontact if unresolved else ncontact


@intrinsic
def _call_law(typingctx, entry, law, Y, H, Hn, first, count, dt, tangent, S):
    """law_entry at the address ``entry`` with the bundle stored at ``law`` and the rest of its
    arguments (LAW_ARGS: C-contiguous arrays): its result. An exception it raises propagates to the
    caller with its message."""
    for name, got, want in (("Y", Y, _F3), ("H", H, _F2), ("Hn", Hn, _F2), ("S", S, _F3)):
        if not (isinstance(got, types.Array) and got.ndim == want.ndim and got.dtype == want.dtype
                and got.layout == "C"):
            raise TypeError(f"the law's call: {name} is {got}, law_entry takes {want}")
    argtys = (types.voidptr,) + LAW_ARGS

    def codegen(context, builder, sig, llargs):
        fnty = context.call_conv.get_function_type(types.int64, argtys)
        fn = builder.inttoptr(llargs[0], fnty.as_pointer())
        args = [builder.inttoptr(llargs[1], context.get_value_type(types.voidptr))]
        args += [context.cast(builder, v, t, want) for v, t, want in zip(llargs[2:], sig.args[2:], LAW_ARGS)]
        status, result = context.call_conv.call_function(builder, fn, types.int64, argtys, args)
        with builder.if_then(status.is_error, likely=False):
            context.call_conv.return_status_propagate(builder, status)
        return result
    return types.int64(entry, law, Y, H, Hn, first, count, dt, tangent, S), codegen


@overload(sets_point_states)
def _point_states_called(law, Y, H, Hn, first, count, dt, tangent, S):
    if getattr(law, "instance_class", None) is LawCall:
        def impl(law, Y, H, Hn, first, count, dt, tangent, S):
            r = _call_law(law.entry, law.law, Y, H, Hn, first, count, dt, tangent, S)
            return (-1 - r, True) if r < 0 else (r, False)
        return impl
    return None


@njit(cache=True)
def call_law(law, Y, H, Hn, first, count, dt, tangent, S):
    """kernel.sets.point_states through a LawCall ``law``, for a Python caller (ContactLaw.evaluate):
    compiled once, whatever the law; returns (points in contact, any unresolved)."""
    return sets_point_states(law, Y, H, Hn, first, count, dt, tangent, S)


def law_call(bundle):
    """The law bundle (_law_bundle) stored, and law_entry compiled for its type (or loaded from the
    cache; announced when it compiles): (LawCall, the stored bundle, which must outlive every call)."""
    stored = StoredArguments(bundle)
    address = _compiled_address(law_entry, (types.CPointer(stored.type),) + LAW_ARGS, (bundle,))
    return LawCall(address, stored.address), stored


@njit(cache=True, inline="always")
def _put_state(Y, k, state):
    """contact_force's state of point k (15 numbers) into the 5 rows from Y[k, Y_KX] (df/dx and df/dv's
    rows, written after it is read)."""
    for i in range(15):
        Y[k, Y_KX + i // 3, i % 3] = state[i]


@njit(cache=True, inline="always")
def _get_state(Y, k):
    """The state _put_state wrote."""
    r = Y[k]
    a, b, c, d, e = r[Y_KX], r[Y_KX + 1], r[Y_KX + 2], r[Y_KX + 3], r[Y_KX + 4]
    return (a[0], a[1], a[2], b[0], b[1], b[2], c[0], c[1], c[2], d[0], d[1], d[2], e[0], e[1], e[2])


@njit(cache=True, inline="always")
def _remember(mode, q, q_t, X):
    """Mode 0 (a residual) keeps its state in X (2, n): the candidate in P[2] belongs to it."""
    if mode == 0:
        for i in range(q.shape[0]):
            X[0, i] = q[i]
            X[1, i] = q_t[i]


@njit(cache=True)
def evaluate_covariant(mode, q, q_t, fq, fv, dt, H, ref, law, P, S, Y, X, kind):
    """kernel.sets.evaluate_set (modes 0 force, 1 Jacobian, 2 history candidate) with the covariant
    kernel at every point. H (K, 9): the converged history (the Exudyn glue passes a view of
    Exudyn's StartOfStep data coordinates: nothing is copied per step); P (3, K, 9): body-local
    points, a history buffer for callers without one (CovariantSet.H), the candidate; Y (K, Y_ROWS, 3):
    the point buffer (kernel.sets.point_states); X (2, n): the state (q, q_t) of the last mode-0
    call, whose candidate P[2] holds."""
    nq = q.shape[0]
    _remember(mode, q, q_t, X)
    return evaluate_set(kind, q, q_t, ref, P[0, :, :3], H, law, mode, fq, fv, dt, S[S_VEC, 6, :nq],
                        S[S_J, :nq, :nq], P[2], S, Y)


@njit(cache=True)
def evaluate_covariant_group(mode, q, q_t, fq, fv, dt, H, ref, law, P, S, Y, X, kind, Q, Jb):
    """kernel.sets.evaluate_group (the same points on nb rigid nodes) with the covariant kernel; P (3,
    nb * Kb, 9) with the body-local points in the first Kb rows of P[0]; Jb (nb, nq, nq)."""
    _remember(mode, q, q_t, X)
    Kb = P.shape[1] // Jb.shape[0]
    return evaluate_group(kind, q, q_t, ref, P[0, :Kb, :3], H, law, mode, fq, fv, dt, Q, Jb, P[2], S, Y)


@njit(cache=True)
def evaluate_covariant_linear(mode, q, q_t, fq, fv, dt, H, ref, law, P, S, Y, X, idx, Sm, c, Q, J):
    """kernel.sets.evaluate_linear (a linear slave: mass points, ANCF cables) with the covariant kernel."""
    _remember(mode, q, q_t, X)
    return evaluate_linear(q, q_t, ref, idx, Sm, c, H, law, mode, fq, fv, dt, Q, J, P[2], S, Y)


@njit(cache=True)
def evaluate_covariant_pair(mode, q, q_t, fq, fv, dt, H, ref, law, P, S, Y, X, T, kind, mkind, idx, Sm, c, cols, Q,
                            J):
    """kernel.sets.evaluate_pair (a moving master: the surface on a 3D rigid node) with the covariant kernel;
    P, Y, X as evaluate_covariant."""
    _remember(mode, q, q_t, X)
    return evaluate_pair(kind, mkind, q, q_t, ref, P[0, :, :3], idx, Sm, c, H, law, mode, fq, fv, dt, Q, J, P[2],
                         S, T, cols, Y)


def law_params(contact_law):
    """The law parameters of a ContactLaw for the kernel (LawParams: penalty, dashpots, the return map
    as its type, law.return_maps.MAPS)."""
    return LawParams(float(contact_law.eps_N), float(contact_law.d_N), float(contact_law.d_T),
                     MAPS[contact_law.return_map])


def _law_bundle(contact_law):
    """The law of a ContactLaw packed for the compiled kernels (surface, nets, law parameters; named tuples)."""
    nB, nF = contact_law._nets
    return CovariantLaw(contact_law.surface.params, nB, nF, law_params(contact_law))


class CovariantSet:
    """A contact set on the covariant kernel packed for the compiled call: the law (``bundle``: surface,
    nets, law parameters as named tuples; ``law``: the LawCall the set's kernel gets), points, history
    and outputs. Views: H (converged history, written by the caller), Q, J, Hn."""

    def __init__(self, contact_law, node_kind, ref, points):
        self._take_law(contact_law)
        self.linear = node_kind if isinstance(node_kind, LinearMap) else None
        if self.linear is not None:     # node_kind: a LinearMap (mass points, cables); points unused
            self.kind, nq = LinearSlave(), self.linear.n
            b = np.zeros((self.linear.idx.shape[0], 3))
        else:
            self.kind = NODE_KINDS[node_kind]
            nq = node_coordinates_of(self.kind)
            b = np.asarray(points, dtype=float)
        self.ref = np.asarray(ref, dtype=float)
        self._buffers(b, nq)
        if self.linear is not None:
            self.Q, self.J = np.zeros(nq), np.zeros((nq, nq))
        else:
            self.Q = self.S[S_VEC, 6, :nq]
            self.J = self.S[S_J, :nq, :nq]

        if self.linear is not None:
            lm = self.linear
            self._fn, self.tail = evaluate_covariant_linear, (self.ref, self.law, self.P, self.S, self.Y, self.X,
                                                                lm.idx, lm.S, lm.c, self.Q, self.J)
        else:
            self._fn, self.tail = evaluate_covariant, (self.ref, self.law, self.P, self.S, self.Y, self.X, self.kind)
        self._entry = None

    def _take_law(self, contact_law):
        """The law bundle (``bundle``), its call for the set's kernel (``law``, law_call) and the stored
        bundle the call reads, held as long as the set."""
        self.bundle = _law_bundle(contact_law)
        self.law, self._stored_law = law_call(self.bundle)

    def _buffers(self, b, n):
        """The packed arrays of K points b (K, 3) over n coordinates: P (3, K, 9) (points, converged
        history H, candidate Hn), the scratch S, the point buffer Y (K, Y_ROWS, 3) and X (2, n),
        the state (q, q_t) of the last residual (mode 0), whose candidate Hn holds."""
        from exu_aniso.kernel.sets import SCRATCH_SLOTS
        self.P = np.zeros((3, b.shape[0], 9))
        self.P[0, :, :3] = b
        self.S = np.zeros((SCRATCH_SLOTS, 9, 9))
        self.H, self.Hn = self.P[1], self.P[2]
        self.Y = np.zeros((b.shape[0], Y_ROWS, 3))
        self.X = np.full((2, n), np.nan)

    def evaluate(self, mode, q, q_t, fq, fv, dt):
        """One compiled call (mode: see evaluate_covariant); q, q_t: the set's coordinates. Returns
        the number of points in contact, or -1 when a point's motion in the step is unresolved."""
        q = np.ascontiguousarray(q, dtype=np.float64)
        q_t = np.ascontiguousarray(q_t, dtype=np.float64)
        return self.entry()(int(mode), q, q_t, float(fq), float(fv), float(dt), self.H, *self.tail)

    def entry(self):
        """The compiled function for this set's argument types (``_entry_point``): callers that
        pass C-contiguous float64 q, q_t, an int mode, float fq, fv, dt and a C-contiguous (K, 9)
        float64 history H may call ``entry()(mode, q, q_t, fq, fv, dt, H, *tail)`` directly (the
        Exudyn glue does, with H a view of Exudyn's StartOfStep data coordinates)."""
        if self._entry is None:
            z = np.zeros(self.X.shape[1])
            self._entry = _entry_point(self._fn, (0, z, z, 0.0, 0.0, 0.0, self.H) + self.tail)
        return self._entry


class CovariantPairSet(CovariantSet):
    """A contact set with a moving master (the surface carried by a 3D rigid node) packed for
    kernel.sets.evaluate_pair: the slave (node_kind: a rigid kind's name, or a LinearMap for mass
    points and cables, with the slave's reference coordinates ref) and the master (master_kind
    "RigidBodyRotVecLG" or "RigidBodyEP", reference coordinates master_ref); coordinates are the
    slave's then the master's. The same interface as CovariantSet: H, Q (n,), J (n, n), Hn, X, tail,
    evaluate, entry."""

    def __init__(self, contact_law, node_kind, ref, points, master_kind, master_ref):
        from exu_aniso.kernel.sets import PAIR_SLOTS
        if master_kind not in ("RigidBodyRotVecLG", "RigidBodyEP"):
            raise ValueError(f"a moving master is a 3D rigid node (RigidBodyRotVecLG or RigidBodyEP); got {master_kind!r}")
        self._take_law(contact_law)
        self.mkind = NODE_KINDS[master_kind]
        nm = node_coordinates_of(self.mkind)
        self.linear = node_kind if isinstance(node_kind, LinearMap) else None
        if self.linear is not None:
            lm = self.linear
            self.kind, ns, m = LinearSlave(), lm.n, lm.idx.shape[1]
            b = np.zeros((lm.idx.shape[0], 3))
            idx, Sm, c = lm.idx, lm.S, lm.c
        else:
            self.kind = NODE_KINDS[node_kind]
            ns = m = node_coordinates_of(self.kind)
            b = np.asarray(points, dtype=float)
            idx, Sm, c = np.zeros((b.shape[0], 0), dtype=np.int64), np.zeros((b.shape[0], 3, 0)), np.zeros((b.shape[0], 3))
        n = ns + nm
        self.ref = np.ascontiguousarray(np.concatenate([np.asarray(ref, dtype=float), np.asarray(master_ref, dtype=float)]))
        if self.ref.shape != (n,):
            raise ValueError(f"reference coordinates: {self.ref.shape[0]} for {ns} slave and {nm} master coordinates")
        self._buffers(b, n)
        w = max(9, m + nm)
        self.T = np.zeros((PAIR_SLOTS, w, w))
        self.cols = np.zeros(m + nm, dtype=np.int64)
        self.Q, self.J = np.zeros(n), np.zeros((n, n))
        self._fn = evaluate_covariant_pair
        self.tail = (self.ref, self.law, self.P, self.S, self.Y, self.X, self.T, self.kind, self.mkind, idx, Sm, c,
                     self.cols, self.Q, self.J)
        self._entry = None


class CovariantGroupSet(CovariantSet):
    """A group: the same body-local points on nb rigid nodes of one kind (node_kind), packed for
    kernel.sets.evaluate_group; ref: the nodes' reference coordinates one after the other. The same
    interface as CovariantSet (H, Hn: nb * K rows, body by body; Q (nb * nq,)), but the Jacobian is
    Jb (nb, nq, nq), its diagonal blocks, and J is a scipy CSR matrix over Jb's memory (what the
    Exudyn glue returns: Exudyn adds its nb * nq^2 entries, not (nb nq)^2)."""

    def __init__(self, contact_law, node_kind, ref, points, nb):
        import scipy.sparse as sp

        self._take_law(contact_law)
        self.linear = None
        self.kind = NODE_KINDS[node_kind]
        nq = node_coordinates_of(self.kind)
        n = nb * nq
        b = np.asarray(points, dtype=float)
        self.ref = np.ascontiguousarray(ref, dtype=float)
        if self.ref.shape != (n,):
            raise ValueError(f"reference coordinates: {self.ref.shape[0]} for {nb} nodes of {nq} coordinates")
        self._buffers(np.tile(b, (nb, 1)), n)
        self.Q = np.zeros(n)
        self.Jb = np.zeros((nb, nq, nq))
        rows = np.arange(n)
        indices = (rows // nq * nq)[:, None] + np.arange(nq)[None, :]       # row i: its body's nq columns
        self.J = sp.csr_matrix((self.Jb.reshape(-1), indices.reshape(-1), np.arange(0, n * nq + 1, nq)),
                               shape=(n, n), copy=False)
        if not np.shares_memory(self.J.data, self.Jb):                       # scipy copied: J would go stale
            raise RuntimeError("scipy.sparse.csr_matrix copied the Jacobian blocks; the group needs a view")
        self._fn, self.tail = evaluate_covariant_group, (self.ref, self.law, self.P, self.S, self.Y, self.X, self.kind, self.Q,
                                                         self.Jb)
        self._entry = None


# What a first compilation costs on this 2-core machine [s] (kernel_kind): a law's, a set kernel's on a
# fixed master and on a moving one: the ranges over the scenes' kernels in
# docs/results/compile_times/compile_times.json (python studies/compile_times.py), rounded outward;
# tests/test_compile_cache.py holds them to that file
COMPILE_SECONDS = {"law": (6, 10), "fixed": (0, 9), "moving": (22, 30)}


def kernels_cached(entry=None, sig=None):
    """True if numba's on-disk cache (exu_aniso.util.numba_cache) holds compiled code of the kernel
    ``entry`` (a numba dispatcher; default: law_entry, the laws) for the argument types ``sig`` (a
    tuple of numba types; None: for any types), so that no compilation is needed; False if the
    first call will compile. Reads numba's cache index, a private API: when that fails, it answers
    True (say nothing rather than something wrong)."""
    try:
        cache = (entry or law_entry)._cache
        index = cache._cache_file._load_index()
        if sig is None:
            return bool(index)
        from numba.core.registry import cpu_target
        return cache._index_key(sig, cpu_target.target_context.codegen()) in index
    except Exception:   # noqa: BLE001 - numba internals changed: no announcement
        return True


def kernel_name(args, entry=None):
    """What a kernel's arguments specialise it for, in words: law_entry's law bundle (its surface, nets
    and return map), or a set kernel's node kinds (``entry``: the set kernel, to name a group)."""
    law = next((a for a in args if isinstance(a, CovariantLaw)), None)
    if law is not None:
        return (f"the contact law for {type(law.surface).__name__.replace('Params', '')}, "
                f"{type(law.adhesion).__name__} adhesion, {type(law.friction).__name__} friction, "
                f"{type(law.law.method).__name__.lower()} map")
    kinds = [type(a).__name__ for a in args if type(a).__module__ == NODE_KINDS_MODULE]
    if not kinds or kinds == ["LinearSlave"]:      # mass points, cables, a finite-element body's nodes
        nodes = "a linear slave"
    elif entry is evaluate_covariant_group:
        nodes = f"a group of {kinds[0]} nodes"
    elif len(kinds) == 1:
        nodes = f"{_a(kinds[0])} node"
    else:
        nodes = f"{_a(kinds[0].replace('LinearSlave', 'linear'))} slave on {_a(kinds[-1])} master"
    return f"the contact set kernel for {nodes}"


def _a(word):
    return ("an " if word[0].lower() in "aeiou" else "a ") + word


NODE_KINDS_MODULE = LinearSlave.__module__


def kernel_kind(entry):
    """What the kernel ``entry`` is, as COMPILE_SECONDS names it: "law" (law_entry), "moving" (a set
    on a moving master) or "fixed" (a set on a fixed master)."""
    return "law" if entry is law_entry else "moving" if entry is evaluate_covariant_pair else "fixed"


def announce_compile(stream=None, entry=None, sig=None, args=None):
    """Say, before it happens, that a kernel is being compiled (once per kernel and process), what for
    and how long it takes here (COMPILE_SECONDS); nothing when the cache holds it (kernels_cached).
    True when it announced (the compilation follows)."""
    key = (entry, sig)
    if key in compiled_here or kernels_cached(entry, sig):
        return False
    compiled_here[key] = [kernel_name(args, entry) if args is not None else "a contact kernel", None]
    where = getattr(getattr(entry or evaluate_covariant, "_cache", None), "_cache_path", "numba's cache directory")
    low, high = COMPILE_SECONDS[kernel_kind(entry)]
    print(f"exu_aniso: compiling {compiled_here[key][0]} with numba (about {low}-{high} s on a 2-core machine; "
          f"once per machine: later runs load it from the cache in {where})", file=stream or sys.stderr, flush=True)
    return True


# the set kernels compiled (and announced) in this process: (entry, signature) -> [what for (kernel_name),
# the compilation's wall time [s]]
compiled_here = {}


def _compile(fn, sig, args):
    """Compile the numba dispatcher fn for the argument types sig, or load it from the cache: announced
    (announce_compile) and timed (compiled_here) when it compiles."""
    from numba.core.errors import NumbaIRAssumptionWarning
    announced = sig not in fn.overloads and announce_compile(entry=fn, sig=sig, args=args)
    start = time.perf_counter()
    with warnings.catch_warnings():
        # numba's internal SSA check complains about variables of branches it pruned in the force
        # loop's inlined law (tangent a constant False there); the code is right, the notice is noise
        warnings.simplefilter("ignore", NumbaIRAssumptionWarning)
        fn.compile(sig)
    if announced:
        compiled_here[(fn, sig)][1] = time.perf_counter() - start


def _compiled_address(fn, sig, args):
    """The machine address of fn compiled for sig (_compile; args: values of those types, to name it)."""
    _compile(fn, sig, args)
    return machine_address(fn, sig)[0]


def _entry_point(fn, args):
    """The compiled function of the numba dispatcher fn for the types of args, called directly.

    numba's type dispatch of every call costs ~2 us here (measured: 2 us of dispatch against 0.4 us of
    the compiled call's entry); the types of a set's arguments never change (the caller passes
    C-contiguous float64 arrays, floats and ints), so the dispatch is done once. Falls back to the
    dispatcher if numba's API for it is not there."""
    from numba import typeof
    try:
        sig = tuple(typeof(a) for a in args)
        _compile(fn, sig, args)
        return fn.overloads[sig].entry_point
    except Exception:               # noqa: BLE001 - numba internals changed: dispatch per call
        return fn


_PLAIN = None


def plain_python():
    """This module's kernel as plain Python, for a user surface or field numba cannot compile
    (``ContactLaw.compiled`` False): every compiled function here runs its Python source, calling
    the plain-Python twins of the surface protocol and of the nets (the built-in nets' principal
    functions stay compiled: their arguments are numbers); the return maps stay compiled. Same
    formulas, much slower."""
    global _PLAIN
    if _PLAIN is None:
        import sys

        from exu_aniso.fields import nets
        from exu_aniso.geometry._base import _CORE_PYTHON, _plain_python
        nets_python = _plain_python(nets, own_only=True)
        _PLAIN = _plain_python(sys.modules[__name__], own_only=True,
                               overrides={"_core": _CORE_PYTHON, "local_chart": _CORE_PYTHON.local_chart,
                                          "physical": nets_python.physical,
                                          "physical_pair": nets_python.physical_both,
                                          "tangent_frame": nets_python.tangent_frame})
    return _PLAIN
