"""The covariant contact kernel for one slave point on any surface of the protocol, compiled with
numba and composed from the surface's chart (``geometry.core``), the adhesion and friction nets
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

The kernel reads downward from here: the law at a point (this module), the law as a set's kernel
calls it (``law_call``), the sets packed for their compiled call (``packed_sets``) and the compile
management (``compiling``).
"""
from __future__ import annotations

import math
from collections import namedtuple

from numba import njit

from exu_aniso.geometry import core
from exu_aniso.geometry.core import add, dot, local_chart, scale, sub
from exu_aniso.law.history import (H_ACTIVE, H_DISSIPATED, H_NORMAL, H_SLIP, H_STATUS, H_T1, H_T2, H_XI1,
                                      H_XI2, N_HISTORY, OPEN, SLIP, STICK, UNRESOLVED)
from exu_aniso.law.return_maps import return_map, run_time, sliding_force, sticks, trial_norm
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
    if (Tn1 == 0.0 and Tn2 == 0.0) or core.constant_metric(sp):
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
    Tt1, Tt2 = (tn1, tn2) if core.constant_metric(sp) else (0.0, 0.0)
    if (tn1 != 0.0 or tn2 != 0.0) and not core.constant_metric(sp):
        t1, t2 = core.transport(sp, xn1, xn2, d1, d2, tn1, tn2)
        w = add(scale(t1, r1), scale(t2, r2))
        Tt1, Tt2 = dot(w, a1), dot(w, a2)
    # slip: d xi at the midpoint, carried to C
    s1, s2 = core.transport(sp, xn1 + 0.5 * d1, xn2 + 0.5 * d2, 0.5 * d1, 0.5 * d2, d1, d2)
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
    y = core.to_local(sp, (x[0], x[1], x[2]))
    xi1, xi2, xi3, pstat, chart = core.project_local(sp, y, hint1, hint2)
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
        d1, e1 = core.unwrap(sp.period1, xi1 - h[H_XI1], p1)
        d2, e2 = core.unwrap(sp.period2, xi2 - h[H_XI2], p2)
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
    fg = core.to_global(sp, fl)
    # energy removed by the return map in the step (trapezoidal, as contact.ContactLaw)
    D = -0.5 * ((st[ST_T1] + T1) * sl1 + (st[ST_T2] + T2) * sl2)
    slipped = math.sqrt(sl1 * sl1 + sl2 * sl2) if state == SLIP else 0.0
    hn = history_row(T1, T2, xi1, xi2, 1.0, h[H_DISSIPATED] + D, h[H_SLIP] + slipped, float(status), N)
    return status, xi3, (1.0, y[0], y[1], y[2], vl[0], vl[1], vl[2], xi1, xi2, xi3, xn1, xn2, tn1, tn2,
                         1.0 if active else 0.0), (fg[0], fg[1], fg[2]), hn


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
        from exu_aniso.geometry.base import CORE_PYTHON, plain_python_of
        nets_python = plain_python_of(nets, own_only=True)
        _PLAIN = plain_python_of(sys.modules[__name__], own_only=True,
                               overrides={"core": CORE_PYTHON, "local_chart": CORE_PYTHON.local_chart,
                                          "physical": nets_python.physical,
                                          "physical_pair": nets_python.physical_both,
                                          "tangent_frame": nets_python.tangent_frame})
    return _PLAIN
