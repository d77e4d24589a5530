"""The surface protocol: everything the contact law needs from a surface, derived once from its chart.

A surface module (plane.py, cylinder.py, ...) gives only what is particular to it, in the surface's
own local frame:

* a parameter type, a ``namedtuple`` with the common fields ``origin, ex, ey, ez`` (the local frame
  in the master frame: x = origin + x_l ex + y_l ey + z_l ez), ``sign`` (+1 or -1, chosen so that
  ``n = sign (rho_1 x rho_2) / |rho_1 x rho_2|`` points to the slave side) and ``period1, period2``
  (the period of a periodic coordinate, e.g. 2 pi for an angle; 0 for none), plus its own sizes;
* ``chart(p, xi1, xi2)``: the point rho and its first and second derivatives rho_1, rho_2, rho_11,
  rho_12, rho_22 in the local frame, as 3-tuples;
* ``guess(p, y, xi1, xi2)``: the closest point projection of the local point y, in closed form where
  one exists (then it returns ``exact=True``), else a starting point for Newton (``exact=False``);
  xi1, xi2 are the previous projection (a hint; NaN when there is none).

It registers them with ``register(ParamsType, chart, guess)``. This module composes the rest from
the registered chart, with the papers' symbols:

  m_ij = rho_i . rho_j (metric), m^ij its inverse, n the unit normal, h_ij = rho_ij . n (curvature),
  Gamma^k_ij = m^kl rho_ij . rho_l (Christoffel symbols of the second kind), xi3 = (r_s - rho) . n
  the signed normal gap, A_ij = m_ij - xi3 h_ij (the matrix of the projection's Newton iteration and
  of its linearisation d xi^i / d r_s = (A^-1)^ij rho_j).

Dispatch is by the parameter type at compile time (``numba.extending.overload`` looks the surface
up in the registry, the way MuJoCo MJX keys collision functions by geometry): the compiled kernel of
a plane and that of a torus are separate specialisations of the same functions, each cached on disk
by numba, and there is no type switch at run time. Python callers (the numpy reference) call the same
compiled functions.
"""
from __future__ import annotations

import math

from numba import njit
from numba.extending import overload

COMMON_FIELDS = ("origin", "ex", "ey", "ez", "sign", "period1", "period2")

_CHART = {}
_GUESS = {}
_CONSTANT_METRIC = {}

# Newton of the closest point projection: relative tolerance on the gradient and iteration limit
PROJECTION_TOL = 1e-13
PROJECTION_MAXIT = 50
# det(A) / det(m) below this: the slave point sits at a centre of curvature (cylinder axis, sphere
# centre), where the closest point is not unique
SINGULAR_A = 1e-12


def register(params_type, chart, guess, constant_metric=False):
    """Make a surface known to the protocol: params_type is its namedtuple class, chart and guess
    its compiled (numba.njit) local functions.

    constant_metric: a fact about the chart, known at compile time: the metric m_ij is the same at
    every point (a Cartesian plane; a cylinder in (angle, axial) coordinates). Then every Christoffel
    symbol vanishes and parallel transport leaves contravariant components unchanged, so the kernel
    skips the transport's chart evaluations. ``tests/test_geometry_protocol.py`` checks every
    declaration against the chart's own Christoffel symbols."""
    missing = [f for f in COMMON_FIELDS if f not in params_type._fields]
    if missing:
        raise TypeError(f"surface parameters {params_type.__name__} lack the common fields {missing}")
    _CHART[params_type] = chart
    _GUESS[params_type] = guess
    _CONSTANT_METRIC[params_type] = bool(constant_metric)


def local_chart(p, xi1, xi2):
    """rho, rho_1, rho_2, rho_11, rho_12, rho_22 (local frame) of the surface p. In compiled code the
    registry resolves it at compile time (overload below); called from Python (the ``py_func`` of
    the functions here, for a surface numba cannot compile) it looks the surface up at run time."""
    return _CHART[type(p)](p, xi1, xi2)


def local_guess(p, y, xi1, xi2):
    """Closest point (xi1, xi2, exact) of the local point y; dispatch as local_chart."""
    return _GUESS[type(p)](p, y, xi1, xi2)


def _lookup(table, p, what):
    cls = getattr(p, "instance_class", None)
    if cls not in table:
        raise TypeError(f"no {what} registered for surface parameters {p}")
    return table[cls]


def constant_metric(p):
    """The surface's compile-time fact ``constant_metric`` (register); in compiled code a constant."""
    return _CONSTANT_METRIC[type(p)]


@overload(constant_metric)
def _constant_metric(p):
    if _lookup(_CONSTANT_METRIC, p, "chart"):
        return lambda p: True
    return lambda p: False


@overload(local_chart)
def _local_chart(p, xi1, xi2):
    f = _lookup(_CHART, p, "chart")
    return lambda p, xi1, xi2: f(p, xi1, xi2)


@overload(local_guess)
def _local_guess(p, y, xi1, xi2):
    f = _lookup(_GUESS, p, "projection")
    return lambda p, y, xi1, xi2: f(p, y, xi1, xi2)


# --- 3-vectors as tuples (no allocation in compiled code) -------------------------------------

@njit(cache=True)
def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


@njit(cache=True)
def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


@njit(cache=True)
def scale(s, a):
    return (s * a[0], s * a[1], s * a[2])


@njit(cache=True)
def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@njit(cache=True)
def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


@njit(cache=True)
def to_global(p, v):
    """Direction v (local components) in the master frame."""
    return (v[0] * p.ex[0] + v[1] * p.ey[0] + v[2] * p.ez[0],
            v[0] * p.ex[1] + v[1] * p.ey[1] + v[2] * p.ez[1],
            v[0] * p.ex[2] + v[1] * p.ey[2] + v[2] * p.ez[2])


@njit(cache=True)
def to_local(p, x):
    """Point x (master frame) in the local frame."""
    d = sub(x, p.origin)
    return (dot(d, p.ex), dot(d, p.ey), dot(d, p.ez))


# --- the composed protocol -------------------------------------------------------------------

@njit(cache=True)
def chart(p, xi1, xi2):
    """rho, rho_1, rho_2, rho_11, rho_12, rho_22 in the master frame."""
    r, r1, r2, r11, r12, r22 = local_chart(p, xi1, xi2)
    return (add(p.origin, to_global(p, r)), to_global(p, r1), to_global(p, r2), to_global(p, r11),
            to_global(p, r12), to_global(p, r22))


@njit(cache=True)
def metric(r1, r2):
    """m_11, m_12, m_22 and the inverse m^11, m^12, m^22."""
    m11, m12, m22 = dot(r1, r1), dot(r1, r2), dot(r2, r2)
    idet = 1.0 / (m11 * m22 - m12 * m12)
    return m11, m12, m22, m22 * idet, -m12 * idet, m11 * idet


@njit(cache=True)
def normal(p, r1, r2):
    c = cross(r1, r2)
    return scale(p.sign / math.sqrt(dot(c, c)), c)


@njit(cache=True)
def geometry(p, xi1, xi2):
    """Surface quantities at (xi1, xi2): rho, rho_1, rho_2, n (master frame), metric (m11, m12, m22),
    inverse metric (M11, M12, M22), curvature (h11, h12, h22) and Christoffel symbols
    (G1 = Gamma^1_(11, 12, 22), G2 = Gamma^2_(11, 12, 22)). The scalars are computed in the local
    frame, where they do not pick up the round-off of the rotation (a cylinder's Gamma is exactly 0
    on any axis)."""
    r, r1, r2, r11, r12, r22 = local_chart(p, xi1, xi2)
    m11, m12, m22, M11, M12, M22 = metric(r1, r2)
    n = normal(p, r1, r2)
    h = (dot(r11, n), dot(r12, n), dot(r22, n))
    # rho_ij . rho_l, then raise l with m^kl
    a11, a12, a22 = dot(r11, r1), dot(r12, r1), dot(r22, r1)
    b11, b12, b22 = dot(r11, r2), dot(r12, r2), dot(r22, r2)
    G1 = (M11 * a11 + M12 * b11, M11 * a12 + M12 * b12, M11 * a22 + M12 * b22)
    G2 = (M12 * a11 + M22 * b11, M12 * a12 + M22 * b12, M12 * a22 + M22 * b22)
    return (add(p.origin, to_global(p, r)), to_global(p, r1), to_global(p, r2), to_global(p, n),
            (m11, m12, m22), (M11, M12, M22), h, G1, G2)


@njit(cache=True)
def project(p, x, xi1, xi2):
    """Closest point projection of the point x (master frame): (xi1, xi2, xi3, status).

    status 0: converged; 1: Newton did not converge in PROJECTION_MAXIT iterations; 2: A = m - xi3 h
    is singular or not positive definite (the point lies at or beyond a centre of curvature, where
    the closest point is not unique or not a minimum); 3: the chart is singular at the projection
    (rho_1 x rho_2 = 0: a pole, an axis, an apex), where the normal and the basis are undefined.
    xi1, xi2 in: the last projection as a hint (NaN: none)."""
    g1, g2, gap, status, _ = project_local(p, to_local(p, x), xi1, xi2)
    return g1, g2, gap, status


@njit(cache=True)
def project_local(p, y, xi1, xi2):
    """project for the point y given in the surface's local frame (to_local), also returning the
    local chart (rho, rho_1, rho_2, rho_11, rho_12, rho_22) at the closest point, which a caller
    then need not evaluate again: (xi1, xi2, xi3, status, chart)."""
    g1, g2, exact = local_guess(p, y, xi1, xi2)
    status = 0
    if not exact:
        status = 1
        for _ in range(PROJECTION_MAXIT):
            r, r1, r2, r11, r12, r22 = local_chart(p, g1, g2)
            d = sub(r, y)                                   # rho - y = -xi3 n
            f1, f2 = dot(d, r1), dot(d, r2)                 # gradient of |rho - y|^2 / 2
            a11 = dot(r1, r1) + dot(d, r11)                 # A_ij = m_ij - xi3 h_ij
            a12 = dot(r1, r2) + dot(d, r12)
            a22 = dot(r2, r2) + dot(d, r22)
            det = a11 * a22 - a12 * a12
            if not (det > 0.0 and a11 > 0.0):
                status = 2
                break
            s1 = (a22 * f1 - a12 * f2) / det
            s2 = (a11 * f2 - a12 * f1) / det
            g1 -= s1
            g2 -= s2
            moved = add(scale(s1, r1), scale(s2, r2))
            if math.sqrt(dot(moved, moved)) <= PROJECTION_TOL * (math.sqrt(dot(y, y)) + math.sqrt(dot(r, r))):
                status = 0
                break
    ch = local_chart(p, g1, g2)
    r, r1, r2, r11, r12, r22 = ch
    c = cross(r1, r2)
    cc = math.sqrt(dot(c, c))
    if not cc > 1e-300:
        return g1, g2, math.nan, 3, ch
    if status == 0:     # closed forms too: the projection must be a regular minimum, A > 0
        d = sub(r, y)
        a11 = dot(r1, r1) + dot(d, r11)
        a12 = dot(r1, r2) + dot(d, r12)
        a22 = dot(r2, r2) + dot(d, r22)
        m11, m22 = dot(r1, r1), dot(r2, r2)
        if not (a11 > 0.0 and a11 * a22 - a12 * a12 > SINGULAR_A * (m11 * m22)):
            status = 2
    return g1, g2, p.sign * dot(sub(y, r), c) / cc, status, ch


@njit(cache=True)
def gap_and_normal_batch(p, X, gap, n):
    """Normal gap gap[k] and unit normal n[k] of the points X (K, 3) (master frame), as
    Surface.gap_and_normal point by point, in one call (the energy ledger projects every point of
    every sample): n[k] is NaN where the point is not in contact or the projection has a status."""
    for k in range(X.shape[0]):
        xi1, xi2, xi3, status = project(p, (X[k, 0], X[k, 1], X[k, 2]), math.nan, math.nan)
        gap[k] = xi3
        if status == 0 and xi3 < 0.0:
            nk = geometry(p, xi1, xi2)[3]
            n[k, 0], n[k, 1], n[k, 2] = nk[0], nk[1], nk[2]
        else:
            n[k, 0], n[k, 1], n[k, 2] = math.nan, math.nan, math.nan


@njit(cache=True)
def unwrap(period, d, predicted):
    """The branch of a coordinate increment d of a coordinate with this period (0: none) closest to
    the predicted increment (e.g. from the velocity); (increment, distance to the prediction)."""
    if period > 0.0:
        d = d - period * math.floor((d - predicted) / period + 0.5)
    return d, abs(d - predicted)


@njit(cache=True)
def christoffel(p, xi1, xi2):
    """Gamma^1_(11, 12, 22) and Gamma^2_(11, 12, 22) at (xi1, xi2), from the local chart only."""
    r, r1, r2, r11, r12, r22 = local_chart(p, xi1, xi2)
    m11, m12, m22 = dot(r1, r1), dot(r1, r2), dot(r2, r2)
    idet = 1.0 / (m11 * m22 - m12 * m12)
    M11, M12, M22 = m22 * idet, -m12 * idet, m11 * idet
    a11, a12, a22 = dot(r11, r1), dot(r12, r1), dot(r22, r1)
    b11, b12, b22 = dot(r11, r2), dot(r12, r2), dot(r22, r2)
    return ((M11 * a11 + M12 * b11, M11 * a12 + M12 * b12, M11 * a22 + M12 * b22),
            (M12 * a11 + M22 * b11, M12 * a12 + M22 * b12, M12 * a22 + M22 * b22))


@njit(cache=True)
def transport(p, xi1, xi2, d1, d2, t1, t2):
    """Parallel transport of the tangent vector with contravariant components (t1, t2) at (xi1, xi2)
    along the coordinate line segment to (xi1 + d1, xi2 + d2): dt^k = -Gamma^k_ij t^i dxi^j,
    integrated by the midpoint rule (second order in the step). Returns the components at the end
    (unchanged on a surface whose chart has a constant metric: every Gamma vanishes)."""
    if constant_metric(p):
        return t1, t2
    G1, G2 = christoffel(p, xi1, xi2)
    h1 = t1 - 0.5 * ((G1[0] * t1 + G1[1] * t2) * d1 + (G1[1] * t1 + G1[2] * t2) * d2)
    h2 = t2 - 0.5 * ((G2[0] * t1 + G2[1] * t2) * d1 + (G2[1] * t1 + G2[2] * t2) * d2)
    G1, G2 = christoffel(p, xi1 + 0.5 * d1, xi2 + 0.5 * d2)
    return (t1 - ((G1[0] * h1 + G1[1] * h2) * d1 + (G1[1] * h1 + G1[2] * h2) * d2),
            t2 - ((G2[0] * h1 + G2[1] * h2) * d1 + (G2[1] * h1 + G2[2] * h2) * d2))


@njit(cache=True)
def slip_vector(p, xi1, xi2, d1, d2):
    """Displacement of the contact point along the surface for the coordinate increment (d1, d2):
    rho_i(mid) d^i, second order in the step (a chord projected on a tangent plane is not)."""
    r1, r2 = chart(p, xi1 + 0.5 * d1, xi2 + 0.5 * d2)[1:3]
    return add(scale(d1, r1), scale(d2, r2))
