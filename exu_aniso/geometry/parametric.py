"""A user surface given by its parametrisation x(xi1, xi2) in the master frame (local frame = master
frame: origin 0, axes identity), chart (xi1, xi2).

The user's ``point(xi1, xi2)`` returns x (3,), dx/dxi (2, 3) (rows rho_1, rho_2) and d2x/dxi2
(2, 2, 3) (rho_ij; [0, 1] is read as rho_12); n = sign rho_1 x rho_2 / |.| with sign +1 on side
"front", -1 on "back". The closest point has no closed form: Newton (``core.project``) starts from
the hint (the last projection) or, without one, from the nearest node of a coarse grid of
(SEARCH + 1)^2 points over ``bounds``; with neither, the projection raises. Newton may converge to a
closest point outside the bounds (they only seed it). Compilation and the plain Python fallback as
in revolution.py (a cfunc of a fixed signature in the parameter tuple; ``compiled``,
``compile_error``).
"""
from __future__ import annotations

import math
from collections import namedtuple

import numpy as np
from numba import njit, types

from exu_aniso.util.validation import check_nonnegative
from . import core
from .base import Surface, side_sign
from .revolution import compile_user_function, python_function

FIELDS = core.COMMON_FIELDS + ("point", "lower1", "upper1", "lower2", "upper2")
ParametricParams = namedtuple("ParametricParams", FIELDS)
PythonParametricParams = namedtuple("PythonParametricParams", FIELDS)

_V3 = types.UniTuple(types.float64, 3)
POINT_SIGNATURE = types.UniTuple(_V3, 6)(types.float64, types.float64)

# intervals per coordinate of the start search over the bounds
SEARCH = 24

_NAN6 = ((math.nan,) * 3,) * 6
_FRAME = ((0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))


def _point_adaptor(f):
    def point_tuples(xi1, xi2):
        try:
            x, dx, ddx = f(xi1, xi2)
        except Exception:       # a cfunc cannot raise: NaN, and the chart raises
            return _NAN6
        if not (len(x) == 3 and len(dx) == 2 and len(dx[0]) == 3 and len(dx[1]) == 3 and len(ddx) == 2
                and len(ddx[0]) == 2 and len(ddx[1]) == 2 and len(ddx[0][0]) == 3 and len(ddx[0][1]) == 3
                and len(ddx[1][1]) == 3):
            return _NAN6
        return ((float(x[0]), float(x[1]), float(x[2])),
                (float(dx[0][0]), float(dx[0][1]), float(dx[0][2])),
                (float(dx[1][0]), float(dx[1][1]), float(dx[1][2])),
                (float(ddx[0][0][0]), float(ddx[0][0][1]), float(ddx[0][0][2])),
                (float(ddx[0][1][0]), float(ddx[0][1][1]), float(ddx[0][1][2])),
                (float(ddx[1][1][0]), float(ddx[1][1][1]), float(ddx[1][1][2])))
    return point_tuples


def _checked_point(point):
    """The user function for the plain Python path: six float 3-tuples, or a ValueError naming 'point'."""
    def point_tuples(xi1, xi2):
        try:
            out = point(xi1, xi2)
        except Exception as e:
            raise ValueError(f"ParametricSurface: point(xi1, xi2) raised {e!r} at "
                             f"xi = ({xi1!r}, {xi2!r})") from e
        try:
            x, dx, ddx = (np.asarray(a, dtype=float) for a in out)
            ok = x.shape == (3,) and dx.shape == (2, 3) and ddx.shape == (2, 2, 3)
        except (TypeError, ValueError):
            ok = False
        if not ok:
            raise ValueError(f"ParametricSurface: point(xi1, xi2) must return x (3,), dx/dxi (2, 3) and "
                             f"d2x/dxi2 (2, 2, 3); got {out!r} at xi = ({xi1!r}, {xi2!r})")
        v = lambda a: (float(a[0]), float(a[1]), float(a[2]))  # noqa: E731
        return v(x), v(dx[0]), v(dx[1]), v(ddx[0, 0]), v(ddx[0, 1]), v(ddx[1, 1])
    return point_tuples


@njit(cache=True)
def chart(p, xi1, xi2):
    out = p.point(xi1, xi2)
    s = 0.0
    for v in out:
        s += v[0] + v[1] + v[2]
    if not math.isfinite(s):
        raise ValueError("ParametricSurface: point(xi1, xi2) must return finite x (3,), dx/dxi (2, 3) and "
                         "d2x/dxi2 (2, 2, 3); it did not at xi =", xi1, xi2)
    return out


@njit(cache=True)
def guess(p, y, xi1, xi2):
    if math.isfinite(xi1) and math.isfinite(xi2):
        return xi1, xi2, False
    if not (p.lower1 < p.upper1 and p.lower2 < p.upper2):
        raise ValueError("ParametricSurface: the projection needs a hint (the last closest point) or "
                         "bounds=((a1, b1), (a2, b2)) to search for a start")
    best, g1, g2 = math.inf, math.nan, math.nan
    for i in range(SEARCH + 1):
        a = p.lower1 + (p.upper1 - p.lower1) * i / SEARCH
        for j in range(SEARCH + 1):
            b = p.lower2 + (p.upper2 - p.lower2) * j / SEARCH
            r = p.point(a, b)[0]
            d = (r[0] - y[0]) ** 2 + (r[1] - y[1]) ** 2 + (r[2] - y[2]) ** 2
            if d < best:
                best, g1, g2 = d, a, b
    return g1, g2, False


core.register(ParametricParams, chart, guess)
core.register(PythonParametricParams, chart.py_func, guess.py_func)


class ParametricSurface(Surface):
    """The surface x(xi1, xi2) of the user's ``point(xi1, xi2) -> (x, dx/dxi (2, 3), d2x/dxi2
    (2, 2, 3))`` in the master frame. side "front" (n = rho_1 x rho_2 / |.|) or "back" (-n);
    periods: the period of each coordinate (0: none), e.g. (2 pi, 0) for an angle; bounds
    ((a1, b1), (a2, b2)): where to search for Newton's start when the projection has no hint
    (required for ``project(x)`` without hint and ``gap_and_normal``).

    ``compiled`` tells whether numba compiled ``point`` (once per process); if not, the surface
    runs in plain Python and ``compile_error`` gives numba's reason."""

    name = "ParametricSurface"

    def __init__(self, point, side="front", periods=(0.0, 0.0), bounds=None):
        if not callable(point):
            raise TypeError(f"ParametricSurface: point must be a function (xi1, xi2) -> (x, dx/dxi, "
                            f"d2x/dxi2); got {point!r}")
        self.point = point
        self.side = side
        self._arguments = (point, side, periods, bounds)
        sign = side_sign("ParametricSurface", side, ("front", "back"), 1.0)
        try:
            P1, P2 = periods
        except (TypeError, ValueError):
            raise ValueError(f"ParametricSurface: periods must be two numbers >= 0; "
                             f"got {periods!r}") from None
        P1, P2 = check_nonnegative("periods[0]", P1), check_nonnegative("periods[1]", P2)
        if bounds is None:
            box = (math.nan,) * 4
        else:
            try:
                box = np.asarray(bounds, dtype=float)
                ok = (box.shape == (2, 2) and bool(np.all(np.isfinite(box)))
                      and bool(np.all(box[:, 0] < box[:, 1])))
            except (TypeError, ValueError):
                ok = False
            if not ok:
                raise ValueError(f"ParametricSurface: bounds must be ((a1, b1), (a2, b2)) with finite a < b; "
                                 f"got {bounds!r}")
            box = tuple(map(float, box.ravel()))
        self.bounds = None if bounds is None else ((box[0], box[1]), (box[2], box[3]))
        compiled, self.compile_error = compile_user_function(point, POINT_SIGNATURE, _point_adaptor)
        self.compiled = compiled is not None
        if self.compiled:
            params = ParametricParams(*_FRAME, sign, P1, P2, compiled, *box)
        else:
            params = PythonParametricParams(*_FRAME, sign, P1, P2, _checked_point(python_function(point)),
                                            *box)
        super().__init__(params)

    def __reduce__(self):
        # the cfunc does not pickle; the surface does wherever its function does (rebuilt, recompiled)
        return ParametricSurface, self._arguments

    def __repr__(self):
        return (f"ParametricSurface(point={getattr(self.point, '__name__', self.point)}, side={self.side!r}, "
                f"periods={list(self.periods)}, bounds={self.bounds})")
