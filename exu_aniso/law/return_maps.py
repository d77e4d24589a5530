"""Anisotropic Coulomb contact law for one slave point: trial traction and three return maps.

Conventions (the same text stands in docs/guide/conventions.md)
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
* Component storage: the maps of this module work with components of T (covariant), B
  (covariant) and F (contravariant) in any surface basis; the formulas need no metric once B
  and F are given in components. The contact kernel (``exu_aniso.kernel.point``) passes them in the
  orthonormal tangent frame of the contact point and transports the history covariantly.
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

The default, ``DEFAULT_RETURN_MAP``, is ``"exact"`` everywhere a map can be left out: ``ContactLaw``,
``mbs.CreateAnisotropicContact`` (``returnMap``), the Python maps below and the scenes' parameters. Two
scenes choose ``"radial"`` and say so in their parameter table: the block and the screw, the papers'
examples, whose point is sliding steered by the adhesion net (the polar block's curved path, the
screw's advance along the thread); under ``"exact"`` with an isotropic friction the block slides
straight along its push (``exu-aniso run block --set return_map=exact``; the two headings:
docs/guide/conventions.md).

Each map returns the derivative of T with respect to the nine law inputs
``p = (T_tr1, T_tr2, |N|, b11, b12, b22, f11, f12, f22)`` (a symmetric component enters both
off-diagonal entries), from which ``exu_aniso.kernel.contact_law`` builds the consistent tangent.

One definition: the maps are scalar functions compiled with numba (``return_map``), called as
they are by the compiled contact kernel and, through ``return_map_point`` / ``return_map_batch``,
by Python (the numpy reference, studies and tests).

Each map is a type (``Seed``, ``Exact``, ``Radial``: named tuples without fields; ``MAPS`` maps the
names to them): ``return_map`` resolves the map by the type of its ``method`` at compile time
(``slide`` and ``unloaded_direction``, overloads keyed by the map), so a compiled kernel holds the
code of its own map only.
"""
from __future__ import annotations

import math
from collections import namedtuple
from dataclasses import dataclass

import numpy as np
from numba import njit, types
from numba.extending import overload

from exu_aniso.law.history import SLIP, STICK  # noqa: F401  (the states the maps return)
from exu_aniso.util.validation import check_array, check_definite_components, check_nonnegative, check_vector

RETURN_MAPS = ("seed", "exact", "radial")
DEFAULT_RETURN_MAP = "exact"         # the one default (module doc)
Seed = namedtuple("Seed", ())        # papers' closed form
Exact = namedtuple("Exact", ())      # associated backward Euler (closest point projection)
Radial = namedtuple("Radial", ())    # backward Euler of the non-associated radial slip rule
MAPS = {"seed": Seed(), "exact": Exact(), "radial": Radial()}
N_PARAMS = 9  # T_tr1, T_tr2, |N|, b11, b12, b22, f11, f12, f22

_KAPPA_RTOL = 2e-16 * 4  # target |sqrt(T.F T) - |N|| <= 8.9e-16 |N|; forming T = (I + kappa C F)^-1 T_tr
#                          limits it to ~eps cond(C F) (tests/test_fuzz_law.py's _round_off allows for it)
_KAPPA_MAXIT = 200
assert set(MAPS) == set(RETURN_MAPS)


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
# the three maps at one point (compiled; dT = dT/dp with p as in the module docstring)

@njit(cache=True)
def _quad(s11, s12, s22, x1, x2):
    """x . S x for a symmetric S = (s11, s12, s22)."""
    return s11 * x1 * x1 + 2.0 * s12 * x1 * x2 + s22 * x2 * x2



@njit(cache=True, inline="always")
def trial_norm(t1, t2, F):
    """sqrt(T_tr . F T_tr) of the trial traction (t1, t2), F = (f11, f12, f22)."""
    return math.sqrt(max(_quad(F[0], F[1], F[2], t1, t2), 0.0))


@njit(cache=True, inline="always")
def trial_slip(t1, t2, N, F):
    """The slip function at the trial state, Phi_tr = sqrt(T_tr . F T_tr) - |N| (N = |N|): the
    point sticks when it is <= 0 (return_map's test; the force loops test it without the root:
    sticks)."""
    return trial_norm(t1, t2, F) - N


@njit(cache=True, inline="always")
def sticks(t1, t2, N, F):
    """trial_slip(t1, t2, N, F) <= 0 without the square root: T_tr . F T_tr <= N^2 (N = |N| >= 0).
    The force loops' test: the same answer except within a rounding of the slip limit."""
    return _quad(F[0], F[1], F[2], t1, t2) <= N * N


def run_time(flag):
    """flag as a run-time bool: a literal True or False would compile every function it reaches
    (the return maps) once more."""
    return flag


@overload(run_time)
def _run_time(flag):
    if isinstance(flag, types.Literal):
        return (lambda flag: True) if flag.literal_value else (lambda flag: False)
    return lambda flag: flag


@njit(cache=True, inline="always")
def _radial_traction(t1, t2, N, s):
    """The radial map's traction N T_tr / s, s = sqrt(T_tr . F T_tr)."""
    return N * t1 / s, N * t2 / s


@njit(cache=True)
def _radial(t1, t2, N, f11, f12, f22, dT, tangent):
    s = math.sqrt(_quad(f11, f12, f22, t1, t2))
    T1, T2 = _radial_traction(t1, t2, N, s)
    if not tangent:
        return T1, T2, 0.0
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
    return T1, T2, 0.0



@njit(cache=True)
def _seed(t1, t2, N, b11, b12, b22, f11, f12, f22, dT, tangent):
    u1, u2 = f11 * t1 + f12 * t2, f12 * t1 + f22 * t2          # F T_tr
    h1, h2 = b11 * u1 + b12 * u2, b12 * u1 + b22 * u2          # T_hat = B F T_tr
    s = math.sqrt(_quad(f11, f12, f22, h1, h2))
    g1, g2 = f11 * h1 + f12 * h2, f12 * h1 + f22 * h2          # F T_hat
    a = -N / s
    if not tangent:
        return a * h1, a * h2, 0.0
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
def _exact(t1, t2, N, b11, b12, b22, f11, f12, f22, dT, tangent):
    c11, c12, c22 = -b11, -b12, -b22
    a11, a12 = c11 * f11 + c12 * f12, c11 * f12 + c12 * f22          # A = C F
    a21, a22 = c12 * f11 + c22 * f12, c12 * f12 + c22 * f22
    tr, det = a11 + a22, a11 * a22 - a12 * a21
    # tr^2 - 4 det written as (a11 - a22)^2 + 4 a12 a21: no cancellation when the eigenvalues of C F
    # nearly coincide (the naive form loses digits in g_min there, which capped kappa below the root)
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
    if not tangent:
        return T1, T2, kappa
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



def slide(method, t1, t2, N, B, F, dT, tangent):
    """(T1, T2, kappa) of a sliding point (Phi_tr > 0, N = |N| > 0) by the map ``method`` (Seed(),
    Exact() or Radial()), and dT/dp into dT when tangent; resolved at compile time by the map's
    type."""
    raise NotImplementedError("slide is resolved at compile time by the type of the map")


def unloaded_direction(method, t1, t2, B, F):
    """The direction (d1, d2) of the limit traction a map returns as |N| -> 0 at the trial traction
    (t1, t2) (a point sliding without load returns T = 0 with dT/d|N| = d / sqrt(d.F d)): radial
    T_tr, seed -B F T_tr, exact F^-1 C^-1 T_tr. Resolved at compile time by the map's type."""
    raise NotImplementedError("unloaded_direction is resolved at compile time by the type of the map")


@overload(slide, inline="always")
def _slide(method, t1, t2, N, B, F, dT, tangent):
    cls = getattr(method, "instance_class", None)
    if cls is Radial:
        return lambda method, t1, t2, N, B, F, dT, tangent: _radial(t1, t2, N, F[0], F[1], F[2], dT, tangent)
    if cls is Seed:
        return lambda method, t1, t2, N, B, F, dT, tangent: _seed(t1, t2, N, B[0], B[1], B[2], F[0], F[1], F[2],
                                                                  dT, tangent)
    if cls is Exact:
        return lambda method, t1, t2, N, B, F, dT, tangent: _exact(t1, t2, N, B[0], B[1], B[2], F[0], F[1], F[2],
                                                                   dT, tangent)
    return None


@overload(unloaded_direction, inline="always")
def _unloaded_direction(method, t1, t2, B, F):
    cls = getattr(method, "instance_class", None)
    if cls is Radial:
        return lambda method, t1, t2, B, F: (t1, t2)
    if cls is Seed:
        def seed(method, t1, t2, B, F):
            u1, u2 = F[0] * t1 + F[1] * t2, F[1] * t1 + F[2] * t2
            return -(B[0] * u1 + B[1] * u2), -(B[1] * u1 + B[2] * u2)
        return seed
    if cls is Exact:
        def exact(method, t1, t2, B, F):
            c11, c12, c22 = -B[0], -B[1], -B[2]
            dc = c11 * c22 - c12 * c12
            v1, v2 = (c22 * t1 - c12 * t2) / dc, (-c12 * t1 + c11 * t2) / dc
            df = F[0] * F[2] - F[1] * F[1]
            return (F[2] * v1 - F[1] * v2) / df, (-F[1] * v1 + F[0] * v2) / df
        return exact
    return None


@njit(cache=True)
def return_map(method, t1, t2, N, B, F, dT, tangent):
    """Return map at one point, the one definition of the three maps. method: the map (MAPS:
    Seed(), Exact() or Radial(); its type selects the code at compile time); (t1, t2) trial
    traction T_tr, N = |N| >= 0, B = (b11, b12, b22), F = (f11, f12, f22). Returns (T1, T2, state
    STICK | SLIP, slip1, slip2, dissipation, kappa, phi_trial) and fills dT (2, 9) = dT/dp when
    tangent (else dT is left as it is: a force-only call does no derivative work). No input checks
    (callers pass validated fields; return_map_point checks)."""
    if tangent:
        for a in range(2):
            for j in range(9):
                dT[a, j] = 0.0
    phi = trial_slip(t1, t2, N, F)
    if phi <= 0.0:
        if tangent:
            dT[0, 0] = 1.0
            dT[1, 1] = 1.0
        return t1, t2, STICK, 0.0, 0.0, 0.0, 0.0, phi
    if N == 0.0:                      # sliding without load: T = 0, dT/d|N| = limit direction
        T1, T2, kappa = 0.0, 0.0, 0.0
        d1, d2 = unloaded_direction(method, t1, t2, B, F)
        s = math.sqrt(_quad(F[0], F[1], F[2], d1, d2))
        if s > 0.0 and tangent:
            dT[0, 2], dT[1, 2] = d1 / s, d2 / s
    else:
        T1, T2, kappa = slide(method, t1, t2, N, B, F, dT, tangent)
    s1, s2 = _slip_increment(B, T1, T2, t1, t2)
    return T1, T2, SLIP, s1, s2, -(T1 * s1 + T2 * s2), kappa, phi


@njit(cache=True, inline="always")
def _slip_increment(B, T1, T2, t1, t2):
    """The slip increment C^-1 (T - T_tr) of a sliding point, C = -B."""
    c11, c12, c22 = -B[0], -B[1], -B[2]
    det = c11 * c22 - c12 * c12
    d1, d2 = T1 - t1, T2 - t2
    return (c22 * d1 - c12 * d2) / det, (-c12 * d1 + c11 * d2) / det


@njit(cache=True, inline="always")
def sliding_force(method, t1, t2, N, B, F, s, dT):
    """return_map's (T1, T2, SLIP, slip1, slip2) of a point that slides (Phi_tr > 0) for a force
    call: no derivatives, s = trial_norm(t1, t2, F) given, and the radial map's traction inline (a
    call per sliding point less); the other maps through return_map. The same numbers as
    return_map. Compiled (and inlined into compiled callers) also where the kernel runs as plain
    Python, like the maps."""
    return _sliding(method, t1, t2, N, B, F, s, dT)


def _sliding(method, t1, t2, N, B, F, s, dT):
    raise NotImplementedError("resolved at compile time by the type of the map")


@overload(_sliding, inline="always")
def _sliding_by_map(method, t1, t2, N, B, F, s, dT):
    if getattr(method, "instance_class", None) is Radial:
        def radial(method, t1, t2, N, B, F, s, dT):
            T1, T2 = (0.0, 0.0) if N == 0.0 else _radial_traction(t1, t2, N, s)
            s1, s2 = _slip_increment(B, T1, T2, t1, t2)
            return T1, T2, SLIP, s1, s2
        return radial
    return lambda method, t1, t2, N, B, F, s, dT: return_map(method, t1, t2, N, B, F, dT, run_time(False))[:5]



@njit(cache=True)
def _return_map_many(method, T_tr, N, B, F, tangent, T, dT, state, slip, D, kappa, phi):
    """return_map for K points into the output arrays (dT only when tangent)."""
    d = np.zeros((2, N_PARAMS))
    for k in range(T_tr.shape[0]):
        r = return_map(method, T_tr[k, 0], T_tr[k, 1], N[k], B[k], F[k], d, tangent)
        T[k, 0], T[k, 1], state[k], slip[k, 0], slip[k, 1], D[k], kappa[k], phi[k] = r
        if tangent:
            dT[k] = d


def return_map_point(T_tr, N_abs, B, F, method=DEFAULT_RETURN_MAP, tangent=True):
    """Return map for one point (``return_map`` with input checks and a LawResult).

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
    r = _return_map_rows(np.reshape(np.asarray(T_tr, dtype=float), (1, 2)), [float(N_abs)], [B], [F], method,
                         tangent)
    return LawResult(r.T[0], int(r.state[0]), r.slip[0], float(r.dissipation[0]), float(r.kappa[0]),
                     float(r.phi_trial[0]), None if r.dT is None else r.dT[0])


def return_map_batch(T_tr, N_abs, B, F, method=DEFAULT_RETURN_MAP, tangent=True):
    """Return map for K points at once. Shapes: T_tr (K, 2), N_abs (K,), B and F (K, 3).

    Same function as return_map_point, one compiled loop; a point with |N| = 0 and a non-zero
    trial traction returns T = 0 (sliding without load).
    Bad input raises ValueError/TypeError naming the argument, as in return_map_point.
    """
    check_return_map(method, "method")
    K = check_array("T_tr", T_tr, (None, 2)).shape[0]
    N = check_array("N_abs", N_abs, (K,))
    if np.any(N < 0.0):
        raise ValueError(f"N_abs must be >= 0 (it is |N|); got {N[N < 0.0][:5].tolist()}")
    check_definite_components("B", B, sign=-1.0, shape=(K, 3))
    check_definite_components("F", F, shape=(K, 3))
    return _return_map_rows(T_tr, N_abs, B, F, method, tangent)


def _return_map_rows(T_tr, N_abs, B, F, method, tangent):
    """return_map_batch on checked inputs: one compiled loop over the rows."""
    T_tr = np.ascontiguousarray(T_tr, dtype=float)
    K = T_tr.shape[0]
    N = np.ascontiguousarray(N_abs, dtype=float).reshape(K)
    B = np.ascontiguousarray(B, dtype=float).reshape(K, 3)
    F = np.ascontiguousarray(F, dtype=float).reshape(K, 3)
    T, slip, D, kappa, phi = np.empty((K, 2)), np.empty((K, 2)), np.empty(K), np.empty(K), np.empty(K)
    state = np.empty(K, dtype=np.int64)
    dT = np.zeros((K, 2, N_PARAMS))
    _return_map_many(MAPS[method], T_tr, N, B, F, bool(tangent), T, dT, state, slip, D, kappa, phi)
    return LawResult(T, state, slip, D, kappa, phi, dT if tangent else None)


def slip_function(T, N_abs, F):
    """Phi = sqrt(T.F T) - |N| (papers' eq. 6/5) for one point; F as (f11, f12, f22)."""
    return math.sqrt(_quad(F[0], F[1], F[2], T[0], T[1])) - N_abs


def elastic_energy(T, B):
    """Stored tangential energy 1/2 T.C^-1 T with C = -B (rate form: exact for constant B)."""
    c11, c12, c22 = -B[0], -B[1], -B[2]
    det = c11 * c22 - c12 * c12
    return 0.5 * _quad(c22 / det, -c12 / det, c11 / det, T[0], T[1])
