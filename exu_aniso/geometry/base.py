"""The Python face of a surface: construction with checked arguments, and the protocol's compiled
functions (``core``) called on the surface's parameter tuple. The numpy reference uses these
methods; compiled kernels call the ``core`` functions with ``surface.params`` directly. A user
surface whose function numba cannot compile (``compiled = False``) runs the same functions as plain
Python (``Surface.protocol``)."""
from __future__ import annotations

import math
import types
from dataclasses import dataclass

import numpy as np

from exu_aniso.util.validation import check_vector
from . import core

TWO_PI = 2.0 * math.pi


def plain_python_of(module, overrides=None, own_only=False):
    """The numba functions of module as plain Python: each one's py_func, re-bound to a copy of the
    module's globals in which the other numba functions are plain Python too (a py_func alone still
    calls the compiled helpers, and they cannot type a surface numba cannot compile). The registry
    (_CHART, _GUESS) is shared; the constants are those at import. own_only: only the functions
    defined in module itself (imported ones stay compiled); overrides: names replaced in the copy
    (e.g. another module's plain-Python twin)."""
    ns = dict(vars(module))
    for name, f in vars(module).items():
        g = getattr(f, "py_func", None)
        if callable(g) and (not own_only or g.__module__ == module.__name__):
            ns[name] = types.FunctionType(g.__code__, ns, g.__name__, g.__defaults__, g.__closure__)
    ns.update(overrides or {})
    return types.SimpleNamespace(**ns)


CORE_PYTHON = plain_python_of(core)

_STATUS_TEXT = {
    1: "the Newton iteration of the closest point projection did not converge",
    2: "the slave point sits at a centre of curvature (A = m - xi3 h is singular): the closest point "
       "is not unique there",
    3: "the chart is singular at the closest point (rho_1 x rho_2 = 0: a pole, an axis or an apex), "
       "where the normal and the surface basis are undefined",
}


def placement(name, axis_point, axis_direction):
    """origin, ex, ey, ez (3-tuples) of a local frame whose z axis is axis_direction. ex is the
    master-frame axis least aligned with the axis, made orthogonal to it (as on the Cylinder), so
    phi = 0 lies in a predictable place."""
    o = check_vector("axis_point", axis_point, 3)
    a = check_vector("axis_direction", axis_direction, 3)
    na = float(np.linalg.norm(a))
    if not na > 0.0:
        raise ValueError(f"{name}: axis_direction must be a non-zero vector; got {a.tolist()}")
    a = a / na
    ref = np.eye(3)[int(np.argmin(np.abs(a)))]
    e1 = ref - (ref @ a) * a
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(a, e1)
    return tuple(map(float, o)), tuple(map(float, e1)), tuple(map(float, e2)), tuple(map(float, a))


def side_sign(name, side, allowed, natural):
    """sign of n = sign rho_1 x rho_2 / |.|: natural is the sign that gives the first allowed side."""
    if side not in allowed:
        raise ValueError(f"{name}: side must be {' or '.join(repr(s) for s in allowed)}; got {side!r}")
    return float(natural if side == allowed[0] else -natural)


@dataclass
class Point:
    """Surface quantities at one point of the chart (papers' symbols; see geometry.core)."""

    xi: np.ndarray          # (2,) surface coordinates
    xi3: float              # signed normal gap of the projected point (0 for Surface.at)
    point: np.ndarray       # rho (3,)
    rho: np.ndarray         # (2, 3) rows rho_1, rho_2
    n: np.ndarray           # (3,) unit normal towards the slave side
    m: np.ndarray           # (2, 2) metric
    m_inv: np.ndarray       # (2, 2) inverse metric
    h: np.ndarray           # (2, 2) curvature h_ij = rho_ij . n
    christoffel: np.ndarray  # (2, 2, 2) Gamma^k_ij as [k, i, j]


class Surface:
    """Base of every surface: ``params`` is its parameter namedtuple (registered in core)."""

    name = "Surface"
    compiled = True         # False: a user surface numba could not compile (runs in plain Python)

    def __init__(self, params):
        self.params = params

    @property
    def protocol(self):
        """The protocol's functions for this surface: compiled (core) or their plain Python twins."""
        return core if self.compiled else CORE_PYTHON

    @property
    def periods(self):
        return self.params.period1, self.params.period2

    @property
    def limits(self):
        """((lo1, hi1), (lo2, hi2)): the open coordinate box where the chart is regular (a pole, an
        axis or an apex lies on its boundary); unbounded by default. Graphics draw inside it."""
        return (-math.inf, math.inf), (-math.inf, math.inf)

    def at(self, xi, xi3=0.0):
        """Surface quantities at chart coordinates xi."""
        xi = check_vector("xi", xi, 2)
        r, r1, r2, n, m, M, h, G1, G2 = self.protocol.geometry(self.params, float(xi[0]), float(xi[1]))
        sym = lambda a: np.array([[a[0], a[1]], [a[1], a[2]]])  # noqa: E731
        return Point(np.array(xi, dtype=float), float(xi3), np.array(r), np.array([r1, r2]), np.array(n),
                     sym(m), sym(M), sym(h), np.array([sym(G1), sym(G2)]))

    def project(self, x, hint=None):
        """Closest point projection of the point x (master frame); hint: the last projection's xi.
        Raises ValueError with the reason where the projection is undefined."""
        x = check_vector("x", x, 3)
        h1, h2 = (math.nan, math.nan) if hint is None else map(float, check_vector("hint", hint, 2))
        xi1, xi2, xi3, status = self.protocol.project(self.params, tuple(map(float, x)), h1, h2)
        if status:
            raise ValueError(f"{self!r}: no closest point for the slave point {np.asarray(x).tolist()}: "
                             f"{_STATUS_TEXT[status]}")
        return self.at((xi1, xi2), xi3)

    def gap_and_normal(self, x):
        """Normal gap xi3 and unit normal of the point x without raising: the gap is defined at a
        centre of curvature too (a point on a hole's axis is R away from its wall), the normal is
        NaN there; both are NaN where the chart is singular at the closest point."""
        f = self.protocol
        xi1, xi2, xi3, status = f.project(self.params, tuple(map(float, x)), math.nan, math.nan)
        if status:
            return xi3, np.full(3, np.nan)
        return xi3, np.array(f.geometry(self.params, xi1, xi2)[3])

    def transport(self, xi, dxi, t):
        """Parallel transport of the tangent vector with contravariant components t from xi along
        the coordinate increment dxi (second order)."""
        return np.array(self.protocol.transport(self.params, float(xi[0]), float(xi[1]), float(dxi[0]),
                                                float(dxi[1]), float(t[0]), float(t[1])))

    def slip(self, xi, dxi):
        """Displacement of the contact point along the surface for the coordinate increment dxi."""
        return np.array(self.protocol.slip_vector(self.params, float(xi[0]), float(xi[1]), float(dxi[0]),
                                                  float(dxi[1])))

    def increment(self, xi_old, xi_new, predicted=(0.0, 0.0)):
        """Coordinate increment from xi_old to xi_new, periodic coordinates unwrapped to the branch
        closest to the predicted increment."""
        d = np.asarray(xi_new, dtype=float) - np.asarray(xi_old, dtype=float)
        return np.array([core.unwrap(P, float(d[i]), float(predicted[i]))[0] for i, P in enumerate(self.periods)])
