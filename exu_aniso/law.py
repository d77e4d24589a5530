"""Anisotropic Coulomb contact law for one slave point: trial traction and three return maps.

Conventions (the same text stands in README.md, section "Conventions")
-----------------------------------------------------------------------
* Units: SI throughout (m, kg, s, N, rad; stiffness in N/m, energy in J). Angles in the public
  API are radians unless a name ends in ``_deg`` (CLI parameters such as ``drive_angle``).
* Gap: ``xi3`` is the signed normal distance of the slave point S from the master surface,
  measured along the master normal ``n``; ``xi3 <= 0`` is penetration, ``xi3 > 0`` is no contact.
* Normal direction: ``n`` points out of the master body, into the side where the slave lives
  (plane z = 0: +z; hole: towards the axis; shaft: away from the axis).
* Normal traction (papers' sign): ``N = eps_N * xi3 (+ d_N * dxi3/dt)`` while ``xi3 < 0``,
  clipped to ``N <= 0`` (no adhesive pull). Compression is negative, ``|N| = -N``.
* Tangential traction: ``T`` is the traction the master exerts on the slave; it opposes the
  slip of S relative to the master. Penalty rate form (papers' eq. 4/5):
  ``dT/dt = B (v_s - v)``, backward Euler: ``T_tr = T_n (transported) + B * du``.
* Sign of B: as in the papers, the adhesion tensor ``B`` is NEGATIVE definite; the tangential
  stiffness ``C = -B`` is positive definite (isotropic: ``B = -eps_T I``). The public API takes
  positive stiffnesses (``eps_1``, ``eps_2``) and builds ``B = -(eps_1 e1 e1 + eps_2 e2 e2)``.
* Friction tensor ``F`` is positive definite, ``Phi = sqrt(T.F T) - |N|``;
  isotropic ``F = I / mu**2``, orthotropic ``F = e1 e1 / mu_1**2 + e2 e2 / mu_2**2``.
* Force on the bodies: the slave point receives ``f = T - N n = T + |N| n``; the master
  receives ``-f`` at the contact point C.
* Component storage: the kernels of this module work with components of T (covariant), B
  (covariant) and F (contravariant) in any surface basis; the formulas need no metric once B
  and F are given in components. The contact-set pipeline (``exu_aniso.contact``) stores the
  history traction in *physical* components of the surface's parallel-transport frame
  (plane: e_x, e_y; cylinder: e_phi, e_z), so keeping the stored components constant is exact
  parallel transport on these flat (developable) surfaces.
* Slip increment and dissipation: ``T = T_tr + C dxi_sl``, i.e. ``dxi_sl = C^-1 (T - T_tr)``;
  the energy dissipated in the step is ``D = -T . dxi_sl``.

Notation (papers' symbols, used inside the kernels)
----------------------------------------------------
``T_tr`` trial traction, ``T`` returned traction, ``N`` normal traction, ``B`` adhesion tensor
(stored as ``(b11, b12, b22)``, negative definite), ``C = -B``, ``F`` friction tensor stored as
``(f11, f12, f22)``, ``Phi`` slip function, ``kappa`` multiplier of the exact map.

Return maps (``method``)
------------------------
``"seed"``   papers' closed form (eq. 9 / eq. 7): ``T = -T_hat |N| / sqrt(T_hat.F T_hat)``,
             ``T_hat = B F T_tr``. Not continuous at Phi = 0+, depends only on the direction of T_tr.
``"exact"``  associated backward Euler (closest point projection in the C^-1 metric):
             ``(I + kappa C F) T = T_tr`` with ``kappa >= 0`` from ``sqrt(T.F T) = |N|``.
``"radial"`` ``T = |N| T_tr / sqrt(T_tr.F T_tr)``: exact backward Euler of the non-associated
             slip rule ``dxi_sl ∝ -C^-1 T``; adhesion steers sliding.

Each map returns the derivative of T with respect to the nine law inputs
``p = (T_tr1, T_tr2, |N|, b11, b12, b22, f11, f12, f22)`` (a symmetric component enters both
off-diagonal entries), from which ``exu_aniso.contact`` builds the consistent tangent.

The arithmetic below is written component-wise so that the same code serves a single point
(Python floats, the fastest for a handful of points) and many points at once (numpy arrays).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .validation import check_array, check_definite_components, check_nonnegative, check_vector

RETURN_MAPS = ("seed", "exact", "radial")
STICK, SLIP = 0, 1
N_PARAMS = 9  # T_tr1, T_tr2, |N|, b11, b12, b22, f11, f12, f22

_KAPPA_RTOL = 2e-16 * 4  # target |sqrt(T.F T) - |N|| <= 8.9e-16 |N|; forming T = (I + kappa C F)^-1 T_tr
#                          limits it to ~eps cond(C F) (3e-12 measured at cond 1.3e5, tests/test_fuzz.py)
_KAPPA_MAXIT = 200


def check_return_map(name, parameter="return_map"):
    """Validate a return-map name; returns it."""
    if not isinstance(name, str) or name not in RETURN_MAPS:
        raise ValueError(f"{parameter} must be one of {RETURN_MAPS}; got {name!r}")
    return name


@dataclass
class LawResult:
    """Outcome of one return map for one point (floats) or many points (arrays, leading axis K).

    T: returned traction (2,) / (K, 2); state: STICK or SLIP; slip: slip increment dxi_sl;
    dissipation: -T . dxi_sl [J per unit traction-displacement]; kappa: multiplier (exact map,
    0 otherwise); phi_trial: Phi at the trial state; dT: dT/dp, (2, 9) / (K, 2, 9).
    """

    T: np.ndarray
    state: object
    slip: np.ndarray
    dissipation: object
    kappa: object
    phi_trial: object
    dT: np.ndarray | None


# ----------------------------------------------------------------------------------------------
# component-wise helpers (work on floats and on numpy arrays alike)

def _mat_vec(m11, m12, m21, m22, x1, x2):
    return m11 * x1 + m12 * x2, m21 * x1 + m22 * x2


def _quad(s11, s12, s22, x1, x2):
    """x . S x for a symmetric S."""
    return s11 * x1 * x1 + 2.0 * s12 * x1 * x2 + s22 * x2 * x2


def _sym_basis():
    """Unit perturbations of a symmetric 2x2 tensor stored as (s11, s12, s22)."""
    return ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))


def _sym_mat_vec(s, x1, x2):
    return s[0] * x1 + s[1] * x2, s[1] * x1 + s[2] * x2


def _slip_radial(t1, t2, N, f11, f12, f22, sqrt, want_dT):
    s = sqrt(_quad(f11, f12, f22, t1, t2))
    T1, T2 = N * t1 / s, N * t2 / s
    dT = None
    if want_dT:
        g1, g2 = _mat_vec(f11, f12, f12, f22, t1, t2)  # F T_tr
        a = N / s
        s2 = s * s
        cols = [
            (a * (1.0 - t1 * g1 / s2), a * (-t2 * g1 / s2)),
            (a * (-t1 * g2 / s2), a * (1.0 - t2 * g2 / s2)),
            (t1 / s, t2 / s),
            (0.0 * s, 0.0 * s), (0.0 * s, 0.0 * s), (0.0 * s, 0.0 * s),
        ]
        c = -N / (2.0 * s2 * s)
        for d in _sym_basis():
            q = _quad(d[0], d[1], d[2], t1, t2)
            cols.append((c * q * t1, c * q * t2))
        dT = cols
    return T1, T2, 0.0 * s, dT


def _slip_seed(t1, t2, N, b11, b12, b22, f11, f12, f22, sqrt, want_dT):
    u1, u2 = _mat_vec(f11, f12, f12, f22, t1, t2)          # F T_tr
    h1, h2 = _mat_vec(b11, b12, b12, b22, u1, u2)          # T_hat = B F T_tr
    s = sqrt(_quad(f11, f12, f22, h1, h2))
    T1, T2 = -N * h1 / s, -N * h2 / s
    dT = None
    if want_dT:
        g1, g2 = _mat_vec(f11, f12, f12, f22, h1, h2)      # F T_hat
        a = -N / s
        s2 = s * s

        def through_hat(d1, d2):  # dT for a perturbation d of T_hat (F fixed)
            w = (g1 * d1 + g2 * d2) / s2
            return a * (d1 - h1 * w), a * (d2 - h2 * w)

        BF = (b11 * f11 + b12 * f12, b11 * f12 + b12 * f22, b12 * f11 + b22 * f12, b12 * f12 + b22 * f22)
        cols = [through_hat(BF[0], BF[2]), through_hat(BF[1], BF[3]), (-h1 / s, -h2 / s)]
        for d in _sym_basis():  # B components: dT_hat = dB F T_tr
            cols.append(through_hat(*_sym_mat_vec(d, u1, u2)))
        c = N / (2.0 * s2 * s)
        for d in _sym_basis():  # F components: dT_hat = B dF T_tr, plus the direct s dependence
            e1, e2 = _sym_mat_vec(d, t1, t2)
            k1, k2 = through_hat(*_mat_vec(b11, b12, b12, b22, e1, e2))
            q = _quad(d[0], d[1], d[2], h1, h2)
            cols.append((k1 + c * q * h1, k2 + c * q * h2))
        dT = cols
    return T1, T2, 0.0 * s, dT


def _exact_solve(t1, t2, N, c11, c12, c22, f11, f12, f22, ops):
    """kappa >= 0 with sqrt(T.F T) = |N|, T = (I + kappa C F)^-1 T_tr (safeguarded Newton).

    In the coordinates y = L^T T (F = L L^T, G = L^T C L) the equation is the secular equation
    ||(I + kappa G)^-1 y_tr|| = |N| of Moré & Sorensen; psi(kappa) = 1/sqrt(T.F T) - 1/|N| is
    concave and increasing (exactly linear when C F ∝ I), so Newton from kappa = 0 approaches the
    root monotonically from below (4-5 iterations to round-off in practice). The bracket
    [0, kappa_hi], kappa_hi from the smallest eigenvalue of C F, with bisection guards round-off.
    Points that have converged are frozen (the batch form iterates until all have).
    """
    a11, a12 = c11 * f11 + c12 * f12, c11 * f12 + c12 * f22          # A = C F
    a21, a22 = c12 * f11 + c22 * f12, c12 * f12 + c22 * f22
    sqrt, where = ops.sqrt, ops.where
    tr, det = a11 + a22, a11 * a22 - a12 * a21
    # tr^2 - 4 det written as (a11 - a22)^2 + 4 a12 a21: no cancellation when the eigenvalues of C F
    # nearly coincide (the naive form loses ~1e-12 in g_min there, which capped kappa below the root)
    g_max = 0.5 * (tr + sqrt(abs((a11 - a22) * (a11 - a22) + 4.0 * a12 * a21)))
    g_min = det / g_max
    s_tr = sqrt(_quad(f11, f12, f22, t1, t2))
    lo = 0.0 * s_tr
    hi = (s_tr / N - 1.0) / g_min * (1.0 + 1e-13)   # bracket with a margin over round-off
    kappa = lo
    for _ in range(_KAPPA_MAXIT):
        m11, m12, m21, m22 = 1.0 + kappa * a11, kappa * a12, kappa * a21, 1.0 + kappa * a22
        dm = m11 * m22 - m12 * m21
        T1, T2 = (m22 * t1 - m12 * t2) / dm, (-m21 * t1 + m11 * t2) / dm
        q = _quad(f11, f12, f22, T1, T2)
        s = sqrt(q)
        done = abs(s - N) <= _KAPPA_RTOL * N
        if ops.all(done):
            break
        # residual sign: s > N means kappa below the root
        below = s > N
        lo = where(below, kappa, lo)
        hi = where(below, hi, kappa)
        # dT/dkappa = -M^-1 A T ; d(1/s)/dkappa = -(F T).dT/dkappa / s^3
        r1, r2 = _mat_vec(a11, a12, a21, a22, T1, T2)
        d1, d2 = -(m22 * r1 - m12 * r2) / dm, -(-m21 * r1 + m11 * r2) / dm
        g1, g2 = _mat_vec(f11, f12, f12, f22, T1, T2)
        dpsi = -(g1 * d1 + g2 * d2) / (s * q)
        psi = 1.0 / s - 1.0 / N
        new = kappa - psi / dpsi
        new = where(new <= lo, 0.5 * (lo + hi), new)
        new = where(new >= hi, 0.5 * (lo + hi), new)
        stalled = abs(new - kappa) <= 4e-16 * abs(kappa)
        kappa = where(done, kappa, new)
        if ops.all(done | stalled):
            break
    m11, m12, m21, m22 = 1.0 + kappa * a11, kappa * a12, kappa * a21, 1.0 + kappa * a22
    dm = m11 * m22 - m12 * m21
    T1, T2 = (m22 * t1 - m12 * t2) / dm, (-m21 * t1 + m11 * t2) / dm
    return kappa, T1, T2, (a11, a12, a21, a22), (m11, m12, m21, m22, dm)


def _slip_exact(t1, t2, N, b11, b12, b22, f11, f12, f22, ops, want_dT):
    c11, c12, c22 = -b11, -b12, -b22
    kappa, T1, T2, A, M = _exact_solve(t1, t2, N, c11, c12, c22, f11, f12, f22, ops)
    dT = None
    if want_dT:
        a11, a12, a21, a22 = A
        m11, m12, m21, m22, dm = M

        def minv(x1, x2):
            return (m22 * x1 - m12 * x2) / dm, (-m21 * x1 + m11 * x2) / dm

        u1, u2 = _mat_vec(f11, f12, f12, f22, T1, T2)              # F T
        w1, w2 = (m22 * u1 - m21 * u2) / dm, (-m12 * u1 + m11 * u2) / dm  # M^-T F T
        AT1, AT2 = _mat_vec(a11, a12, a21, a22, T1, T2)
        den = w1 * AT1 + w2 * AT2
        mAT1, mAT2 = minv(AT1, AT2)

        def column(r1, r2, tFt, dN):
            dk = (2.0 * (w1 * r1 + w2 * r2) + tFt - 2.0 * N * dN) / (2.0 * den)
            x1, x2 = minv(r1, r2)
            return x1 - dk * mAT1, x2 - dk * mAT2

        zero = 0.0 * den
        cols = [column(1.0 + zero, zero, zero, zero), column(zero, 1.0 + zero, zero, zero),
                column(zero, zero, zero, 1.0 + zero)]
        FT1, FT2 = u1, u2
        for d in _sym_basis():   # dA = -dB F: r = -kappa dA T = kappa dB F T
            e1, e2 = _sym_mat_vec(d, FT1, FT2)
            cols.append(column(kappa * e1, kappa * e2, zero, zero))
        for d in _sym_basis():   # dA = C dF: r = -kappa C dF T
            e1, e2 = _sym_mat_vec(d, T1, T2)
            k1, k2 = _mat_vec(c11, c12, c12, c22, e1, e2)
            cols.append(column(-kappa * k1, -kappa * k2, _quad(d[0], d[1], d[2], T1, T2), zero))
        dT = cols
    return T1, T2, kappa, dT


class _FloatOps:
    """Scalar versions of the few non-arithmetic operations the kernels need."""
    sqrt = staticmethod(math.sqrt)
    all = staticmethod(bool)

    @staticmethod
    def where(cond, a, b):
        return a if cond else b


class _ArrayOps:
    sqrt = staticmethod(np.sqrt)
    all = staticmethod(np.all)
    where = staticmethod(np.where)


def _slip(method, t1, t2, N, B, F, ops, want_dT):
    if method == "radial":
        return _slip_radial(t1, t2, N, *F, ops.sqrt, want_dT)
    if method == "seed":
        return _slip_seed(t1, t2, N, *B, *F, ops.sqrt, want_dT)
    return _slip_exact(t1, t2, N, *B, *F, ops, want_dT)


def _slip_and_dissipation(T1, T2, t1, t2, B):
    """dxi_sl = C^-1 (T - T_tr) with C = -B, and D = -T . dxi_sl."""
    c11, c12, c22 = -B[0], -B[1], -B[2]
    det = c11 * c22 - c12 * c12
    d1, d2 = T1 - t1, T2 - t2
    s1, s2 = (c22 * d1 - c12 * d2) / det, (-c12 * d1 + c11 * d2) / det
    return s1, s2, -(T1 * s1 + T2 * s2)


def _zero_normal_limit(method, t1, t2, B, F):
    """Direction dT/d|N| of each map as |N| -> 0 (T itself is 0 there)."""
    if method == "radial":
        d1, d2 = t1, t2
    elif method == "seed":
        u1, u2 = _mat_vec(F[0], F[1], F[1], F[2], t1, t2)
        h1, h2 = _mat_vec(B[0], B[1], B[1], B[2], u1, u2)
        d1, d2 = -h1, -h2
    else:  # kappa -> inf: T ∝ (C F)^-1 T_tr = F^-1 C^-1 T_tr
        c11, c12, c22 = -B[0], -B[1], -B[2]
        dc = c11 * c22 - c12 * c12
        v1, v2 = (c22 * t1 - c12 * t2) / dc, (-c12 * t1 + c11 * t2) / dc
        df = F[0] * F[2] - F[1] * F[1]
        d1, d2 = (F[2] * v1 - F[1] * v2) / df, (-F[1] * v1 + F[0] * v2) / df
    s = math.sqrt(_quad(F[0], F[1], F[2], d1, d2))
    return (d1 / s, d2 / s) if s > 0.0 else (0.0, 0.0)


def return_map_point(T_tr, N_abs, B, F, method="exact", tangent=True):
    """Return map for one point with plain floats.

    T_tr: (T_1, T_2) trial traction; N_abs: |N| >= 0; B: (b11, b12, b22) negative definite;
    F: (f11, f12, f22) positive definite; all in one (any) surface basis, T covariant,
    B covariant, F contravariant components. Returns a LawResult with numpy arrays.
    Bad input (shapes, NaN/inf, |N| < 0, B not negative definite, F not positive definite, unknown
    method) raises ValueError/TypeError naming the argument.
    """
    check_return_map(method, "method")
    check_vector("T_tr", T_tr, 2)
    check_nonnegative("N_abs", N_abs)
    check_definite_components("B", B, sign=-1.0)
    check_definite_components("F", F)
    return _return_map_point(T_tr, N_abs, B, F, method, tangent)


def _return_map_point(T_tr, N_abs, B, F, method="exact", tangent=True):
    """return_map_point without the input checks (kernel path: inputs come from validated fields)."""
    t1, t2 = float(T_tr[0]), float(T_tr[1])
    N = float(N_abs)
    B = tuple(float(b) for b in B)
    F = tuple(float(f) for f in F)
    phi = math.sqrt(max(_quad(*F, t1, t2), 0.0)) - N
    if phi <= 0.0:
        dT = None
        if tangent:
            dT = np.zeros((2, N_PARAMS))
            dT[0, 0] = dT[1, 1] = 1.0
        return LawResult(np.array([t1, t2]), STICK, np.zeros(2), 0.0, 0.0, phi, dT)
    if N == 0.0:
        T1 = T2 = kappa = 0.0
        dT = None
        if tangent:
            dT = np.zeros((2, N_PARAMS))
            dT[:, 2] = _zero_normal_limit(method, t1, t2, B, F)
    else:
        T1, T2, kappa, cols = _slip(method, t1, t2, N, B, F, _FloatOps, tangent)
        dT = np.array(cols, dtype=float).T if tangent else None
    s1, s2, D = _slip_and_dissipation(T1, T2, t1, t2, B)
    return LawResult(np.array([T1, T2]), SLIP, np.array([s1, s2]), D, kappa, phi, dT)


VECTORIZE_MIN_POINTS = 24  # below this many sliding points a loop over plain floats is faster


def return_map_batch(T_tr, N_abs, B, F, method="exact", tangent=True, vectorize=None):
    """Return map for K points at once. Shapes: T_tr (K, 2), N_abs (K,), B and F (K, 3).

    Same formulas as return_map_point; a point with |N| = 0 and a non-zero trial traction
    returns T = 0 (sliding without load). vectorize: True evaluates the sliding points with numpy
    arrays, False loops over return_map_point, None chooses by count (studies/bench_kernels.py
    measured the crossover near 16-32 points).
    Bad input raises ValueError/TypeError naming the argument, as in return_map_point.
    """
    check_return_map(method, "method")
    K = check_array("T_tr", T_tr, (None, 2)).shape[0]
    N = check_array("N_abs", N_abs, (K,))
    if np.any(N < 0.0):
        raise ValueError(f"N_abs must be >= 0 (it is |N|); got {N[N < 0.0][:5].tolist()}")
    check_definite_components("B", B, sign=-1.0, shape=(K, 3))
    check_definite_components("F", F, shape=(K, 3))
    return _return_map_batch(T_tr, N_abs, B, F, method, tangent, vectorize)


def _return_map_batch(T_tr, N_abs, B, F, method="exact", tangent=True, vectorize=None):
    """return_map_batch without the input checks (kernel path of ContactLaw.evaluate)."""
    T_tr = np.asarray(T_tr, dtype=float)
    N = np.asarray(N_abs, dtype=float)
    B = np.asarray(B, dtype=float)
    F = np.asarray(F, dtype=float)
    K = T_tr.shape[0]
    t1, t2 = T_tr[:, 0], T_tr[:, 1]
    phi = np.sqrt(np.maximum(_quad(F[:, 0], F[:, 1], F[:, 2], t1, t2), 0.0)) - N
    slip = phi > 0.0
    T = T_tr.copy()
    kappa = np.zeros(K)
    dxi = np.zeros((K, 2))
    D = np.zeros(K)
    dT = None
    if tangent:
        dT = np.zeros((K, 2, N_PARAMS))
        dT[:, 0, 0] = dT[:, 1, 1] = 1.0
    loaded = slip & (N > 0.0)
    if vectorize is None:
        vectorize = int(np.count_nonzero(loaded)) >= VECTORIZE_MIN_POINTS
    # plain-float loop: all sliding points when not vectorising, else only the rare |N| = 0 ones
    for j in np.nonzero(slip & ~loaded if vectorize else slip)[0]:
        r = _return_map_point(T_tr[j], N[j], B[j], F[j], method, tangent)
        T[j], kappa[j], dxi[j], D[j] = r.T, r.kappa, r.slip, r.dissipation
        if tangent:
            dT[j] = r.dT
    if vectorize and np.any(loaded):
        i = np.nonzero(loaded)[0]
        Bi = tuple(B[i, k] for k in range(3))
        T1, T2, kap, cols = _slip(method, t1[i], t2[i], N[i], Bi, tuple(F[i, k] for k in range(3)),
                                  _ArrayOps, tangent)
        T[i, 0], T[i, 1] = T1, T2
        kappa[i] = kap
        if tangent:
            dT[i] = np.stack([np.stack([np.broadcast_to(c[0], i.shape), np.broadcast_to(c[1], i.shape)],
                                       axis=-1) for c in cols], axis=-1)
        dxi[i, 0], dxi[i, 1], D[i] = _slip_and_dissipation(T1, T2, t1[i], t2[i], Bi)
    return LawResult(T, slip.astype(int), dxi, D, kappa, phi, dT)


def slip_function(T, N_abs, F):
    """Phi = sqrt(T.F T) - |N| (papers' eq. 6/5) for one point; F as (f11, f12, f22)."""
    return math.sqrt(_quad(F[0], F[1], F[2], T[0], T[1])) - N_abs


def elastic_energy(T, B):
    """Stored tangential energy 1/2 T.C^-1 T with C = -B (rate form: exact for constant B)."""
    c11, c12, c22 = -B[0], -B[1], -B[2]
    det = c11 * c22 - c12 * c12
    return 0.5 * _quad(c22 / det, -c12 / det, c11 / det, T[0], T[1])


def elastic_energy_batch(T, B):
    """elastic_energy of K points: T (K, 2), B (K, 3) -> (K,) [J]."""
    T, B = np.asarray(T, dtype=float), np.asarray(B, dtype=float)
    return elastic_energy((T[:, 0], T[:, 1]), (B[:, 0], B[:, 1], B[:, 2]))
