"""Surface of revolution about the local z axis with a user profile r(z), chart (phi, z).

rho = (r cos phi, r sin phi, z), rho_1 = r e_phi, rho_2 = r' e_r + e_z, rho_11 = -r e_r,
rho_12 = r' e_phi, rho_22 = r'' e_r, with r, r' = dr/dz, r'' = d2r/dz2 from the profile;
rho_1 x rho_2 = r (e_r - r' e_z), outward where r > 0. The closest point lies in the meridian
half-plane of the point (phi from its azimuth, for any profile); z by Newton (the guess gives the
hint's z, else the point's own z, and ``exact=False``: ``core.project`` iterates). The axis (r = 0)
is singular; a point on the axis has no unique closest point (status 2).

User surfaces and numba. The user's function is compiled when numba can: ``numba.njit`` of the
function, wrapped in an adaptor that turns its result into float tuples, compiled as a
``numba.cfunc`` of a fixed signature. The parameter tuple holds that cfunc, which numba types as a
first-class function of its signature (``FunctionType``), the same type for every profile: the
protocol's kernels (``core``, cached on disk) are compiled once for all surfaces of revolution,
and only the user's function is compiled again in each process (numba cannot cache a lambda or a
closure across processes). A dispatcher in the tuple would also work, but numba types it by the
function object itself, so every process would compile the kernels afresh and append never reused
entries to their disk cache. A cfunc cannot raise: the adaptor returns NaN where the user's function
raises or returns the wrong number of values, and the chart raises the ValueError. Where numba cannot
compile the function (a Python-only feature: a dict, a class instance, a plain Python helper, a bound
method), the surface takes the plain Python path (``compiled = False``, ``compile_error`` says why):
its parameter tuple holds a checked Python wrapper of the function and ``Surface.protocol`` runs
``core`` as plain Python.
"""
from __future__ import annotations

import math
import re
from collections import namedtuple

from numba import cfunc, njit, types
from numba.core.dispatcher import Dispatcher

from . import core
from .base import TWO_PI, Surface, placement, side_sign

# compiled (profile: a cfunc) and plain Python (profile: a checked Python function) parameters
RevolutionParams = namedtuple("RevolutionParams", core.COMMON_FIELDS + ("profile",))
PythonRevolutionParams = namedtuple("PythonRevolutionParams", core.COMMON_FIELDS + ("profile",))

PROFILE_SIGNATURE = types.UniTuple(types.float64, 3)(types.float64)

_ANSI = re.compile(r"\x1b\[[0-9;]*m")


def compile_user_function(function, signature, adaptor):
    """(cfunc, None) where numba compiles ``adaptor(njit(function))`` to the signature, else
    (None, numba's reason). Shared by the user surfaces (revolution, parametric)."""
    try:
        jitted = function if isinstance(function, Dispatcher) else njit(function)
        return cfunc(signature)(adaptor(jitted)), None
    except Exception as e:      # any failure of the attempt: the plain Python path
        return None, _ANSI.sub("", f"{type(e).__name__}: {e}").strip()


def python_function(function):
    """The plain Python function behind a user function (its py_func if it is a numba dispatcher)."""
    return function.py_func if isinstance(function, Dispatcher) else function


def _profile_adaptor(f):
    def profile_tuple(z):
        try:
            v = f(z)
        except Exception:       # a cfunc cannot raise: NaN, and the chart raises
            return math.nan, math.nan, math.nan
        if len(v) != 3:
            return math.nan, math.nan, math.nan
        return float(v[0]), float(v[1]), float(v[2])
    return profile_tuple


def _checked_profile(profile):
    """The profile for the plain Python path: three floats, or a ValueError naming 'profile'."""
    def profile_tuple(z):
        try:
            v = profile(z)
        except Exception as e:
            raise ValueError(f"SurfaceOfRevolution: profile(z) raised {e!r} at z = {z!r}") from e
        try:
            r, dr, ddr = (float(a) for a in v)
        except (TypeError, ValueError):
            raise ValueError(f"SurfaceOfRevolution: profile(z) must return 3 numbers (r, dr/dz, d2r/dz2); "
                             f"got {v!r} at z = {z!r}") from None
        return r, dr, ddr
    return profile_tuple


@njit(cache=True)
def chart(p, phi, z):
    r, dr, ddr = p.profile(z)
    if not (r > 0.0 and math.isfinite(r) and math.isfinite(dr) and math.isfinite(ddr)):
        raise ValueError("SurfaceOfRevolution: profile(z) must return 3 finite numbers (r, dr/dz, d2r/dz2) "
                         "with r > 0; it did not at z =", z)
    c, s = math.cos(phi), math.sin(phi)
    return ((r * c, r * s, z), (-r * s, r * c, 0.0), (dr * c, dr * s, 1.0), (-r * c, -r * s, 0.0),
            (-dr * s, dr * c, 0.0), (ddr * c, ddr * s, 0.0))


@njit(cache=True)
def guess(p, y, phi, z):
    if not math.isfinite(z):
        z = y[2]
    return math.atan2(y[1], y[0]), z, False


core.register(RevolutionParams, chart, guess)
core.register(PythonRevolutionParams, chart.py_func, guess.py_func)


class SurfaceOfRevolution(Surface):
    """Surface of revolution about the axis through axis_point along axis_direction, with the
    profile ``profile(z) -> (r, dr/dz, d2r/dz2)`` (plain floats; z measured along the axis from
    axis_point, r > 0 the distance from the axis). Chart (phi, z), phi periodic (2 pi) from the same
    reference direction as the Cylinder's. Side "outside" (slave outside, n away from the axis) or
    "inside".

    ``compiled`` tells whether numba compiled the profile (once per process); if not, the surface
    runs in plain Python and ``compile_error`` gives numba's reason. The projection starts Newton
    from the hint's z, else from the point's own z: the profile must be defined there."""

    name = "SurfaceOfRevolution"

    def __init__(self, profile, axis_point=(0.0, 0.0, 0.0), axis_direction=(0.0, 0.0, 1.0), side="outside"):
        if not callable(profile):
            raise TypeError(f"SurfaceOfRevolution: profile must be a function z -> (r, dr/dz, d2r/dz2); "
                            f"got {profile!r}")
        self.profile = profile
        self.side = side
        self._arguments = (profile, axis_point, axis_direction, side)
        # rho_1 x rho_2 = r (e_r - r' e_z): outward where r > 0
        sign = side_sign("SurfaceOfRevolution", side, ("outside", "inside"), 1.0)
        frame = placement("SurfaceOfRevolution", axis_point, axis_direction)
        compiled, self.compile_error = compile_user_function(profile, PROFILE_SIGNATURE, _profile_adaptor)
        self.compiled = compiled is not None
        if self.compiled:
            params = RevolutionParams(*frame, sign, TWO_PI, 0.0, compiled)
        else:
            params = PythonRevolutionParams(*frame, sign, TWO_PI, 0.0,
                                            _checked_profile(python_function(profile)))
        super().__init__(params)

    def __reduce__(self):
        # the cfunc does not pickle; the surface does wherever its profile does (rebuilt, recompiled)
        return SurfaceOfRevolution, self._arguments

    def __repr__(self):
        p = self.params
        return (f"SurfaceOfRevolution(profile={getattr(self.profile, '__name__', self.profile)}, "
                f"axis_point={list(p.origin)}, axis_direction={list(p.ez)}, side={self.side!r})")
