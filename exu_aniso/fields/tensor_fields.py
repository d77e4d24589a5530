"""Tensor fields for the adhesion tensor B and the friction tensor F on a master surface.

Both are orthotropic fields ``P = lambda_1 e1 e1 + lambda_2 e2 e2`` built on a direction field
``e1(C)`` of the surface (e2 = e1 rotated by +90 deg in the tangent plane):

* adhesion: ``C = -B`` with ``lambda_k = eps_k`` (tangential penalty stiffness, N/m per point),
  ``B = -C`` (the papers' sign);
* friction: ``F`` with ``lambda_k = 1 / mu_k**2`` (mu_k: Coulomb coefficients along e_k).

Direction fields:

* ``isotropic``:   lambda_1 = lambda_2 (any surface);
* ``orthotropic``: e1 at a constant angle from the xi1 coordinate line, towards xi2 (plane:
  from e_x towards e_y; cylinder, cone, any surface of revolution: from the circumference
  towards the axis);
* ``polar``:       plane only, e1 = e_r, e2 = e_phi about the origin (papers' eq. 8). Undefined at
  the origin; with ``core_radius = r_c > 0`` the projector e_r e_r is regularised to
  ``(x x^T + r_c^2/2 I) / (|x|^2 + r_c^2)`` (smooth, SPD kept, isotropic mean at the origin,
  relative deviation from the exact field ~ (r_c/r)^2). With r_c = 0 evaluating at the origin
  raises ValueError;
* ``field``:       the user's function of the surface coordinates, ``function(xi1, xi2) ->
  (value_1, value_2, angle)``: stiffnesses eps_1, eps_2 [N/m] (adhesion) or coefficients mu_1,
  mu_2 (friction) and the angle [rad] of e1 from the xi1 coordinate line towards xi2, as plain
  floats. Compiled with numba when it can be (as ParametricSurface); otherwise the contact runs
  in plain Python (``cfunc`` None, ``compile_error`` says why). Periodic coordinates arrive
  unwrapped (an angle may exceed 2 pi): the function should be periodic in them;
* ``spiral``:      any surface of revolution, e1 along the helix of constant lead (given by the
  lead, or by the helix angle alpha at the radius of a Cylinder or Cone: lead 2 pi R tan alpha);
  e1 = cos(alpha) e_phi + sin(alpha) e_z on a cylinder (papers' second example).

A field here is a description; ``exu_aniso.fields.nets.net_of(field, surface)`` turns it into the net the
contact kernel evaluates (principal values and the direction of e1 at a surface point).
"""
from __future__ import annotations

import math

import numpy as np

from exu_aniso.util.validation import check_in_range, check_nonnegative, check_positive, check_real, check_spd

_ADHESION, _FRICTION = "adhesion", "friction"


class TensorField:
    """An orthotropic tensor field (adhesion B or friction F); build it with Adhesion / Friction."""

    def __init__(self, kind, pattern, lam, angle=0.0, core_radius=0.0, matrix=None, label=""):
        self.kind = kind
        self.pattern = pattern
        self.lam = lam                  # eigenvalues of the positive tensor (C or F)
        self.angle = angle
        self.core_radius = core_radius
        self.label = label
        if matrix is not None:          # constant components given directly (positive tensor)
            self._const = np.array(matrix, dtype=float)
        elif pattern in ("isotropic", "orthotropic", "spiral") and angle is not None:
            c, s = math.cos(angle), math.sin(angle)
            l1, l2 = lam
            self._const = np.array([l1 * c * c + l2 * s * s, (l1 - l2) * c * s, l1 * s * s + l2 * c * c])
        else:
            self._const = None

    def __repr__(self):
        return f"{'Adhesion' if self.kind == _ADHESION else 'Friction'}.{self.label}"


_USER_SIGNATURE = None


def _user(kind, function):
    """A field from the user's function(xi1, xi2) -> (value_1, value_2, angle) (see the module docstring)."""
    global _USER_SIGNATURE
    from numba import types

    from exu_aniso.geometry.revolution import compile_user_function, python_function
    name = "Adhesion" if kind == _ADHESION else "Friction"
    if not callable(function):
        raise TypeError(f"{name}.field: function must be a function (xi1, xi2) -> (value_1, value_2, angle); "
                        f"got {function!r}")
    if _USER_SIGNATURE is None:
        _USER_SIGNATURE = types.UniTuple(types.float64, 3)(types.float64, types.float64)
    f = TensorField(kind, "user", None, angle=None,
                    label=f"field({getattr(function, '__name__', function)})")
    f.function = function
    f.cfunc, f.compile_error = compile_user_function(function, _USER_SIGNATURE, _user_adaptor)
    f.python = _checked_user(name, python_function(function))
    return f


def _user_adaptor(fn):
    def triple(xi1, xi2):
        try:
            v = fn(xi1, xi2)
        except Exception:       # a cfunc cannot raise: NaN, and the net raises
            return math.nan, math.nan, math.nan
        if len(v) != 3:
            return math.nan, math.nan, math.nan
        return float(v[0]), float(v[1]), float(v[2])
    return triple


def _checked_user(name, function):
    """The user function for the plain Python path: three floats, or a ValueError naming it."""
    def triple(xi1, xi2):
        try:
            v = function(xi1, xi2)
            a, b, c = (float(x) for x in v)
        except Exception as e:
            raise ValueError(f"{name}.field: function(xi1, xi2) must return 3 numbers (value_1, value_2, angle); "
                             f"at xi = ({xi1!r}, {xi2!r}) it gave {e!r}") from e
        return a, b, c
    return triple


ADHESION_RANGE = (1e-12, 1e16)
"""Adhesion stiffness per point [N/m]: beyond it the sticking stiffness against a double's
resolution of a chart makes the surface's chart look singular, below it nothing sticks."""

FRICTION_RANGE = (1e-9, 1e3)
"""Friction coefficient [-]: F holds 1 / mu^2, which leaves the doubles outside it."""


def _in_range(name, value, bounds, what):
    """A positive value within bounds (util.validation.check_in_range, the error saying what they are)."""
    return check_in_range(name, check_positive(name, value), *bounds, why=what)


def _pair(kind, n1, v1, n2, v2):
    if kind == _ADHESION:
        what = "an adhesion stiffness per point [N/m]"
        return _in_range(n1, v1, ADHESION_RANGE, what), _in_range(n2, v2, ADHESION_RANGE, what)
    what = "a friction coefficient; F holds 1 / mu^2"
    return 1.0 / _in_range(n1, v1, FRICTION_RANGE, what) ** 2, 1.0 / _in_range(n2, v2, FRICTION_RANGE, what) ** 2


def _helix(helix_angle):
    a = check_real("helix_angle", helix_angle)
    if not -0.5 * math.pi < a < 0.5 * math.pi:
        raise ValueError(f"helix_angle must lie in (-pi/2, pi/2) rad; got {a!r}")
    return a


def _orthotropic(kind, n1, v1, n2, v2, angle):
    """Constant orthotropy: v1 along e1 at angle [rad] in the transport frame, v2 across."""
    return TensorField(kind, "orthotropic", _pair(kind, n1, v1, n2, v2), angle=check_real("angle", angle),
                       label=f"orthotropic({v1}, {v2}, angle={angle})")


def _polar(kind, n1, v1, n2, v2, core_radius):
    """Polar orthotropy on a plane: v1 radial, v2 circumferential, regularized within core_radius [m]."""
    return TensorField(kind, "polar", _pair(kind, n1, v1, n2, v2),
                       core_radius=check_nonnegative("core_radius", core_radius),
                       label=f"polar({v1}, {v2}, core_radius={core_radius})")


def _spiral(kind, n1, v1, n2, v2, helix_angle, lead):
    """A spiral net given by its helix angle (at the surface's radius: Cylinder, Cone) or by its
    lead [m of the second surface coordinate per turn] (any surface of revolution)."""
    lam = _pair(kind, n1, v1, n2, v2)
    if (helix_angle is None) == (lead is None):
        raise ValueError(f"spiral: give exactly one of helix_angle [rad] and lead [m per turn]; got "
                         f"helix_angle={helix_angle!r}, lead={lead!r}")
    if lead is not None:
        f = TensorField(kind, "spiral", lam, angle=None, label=f"spiral({v1}, {v2}, lead={lead})")
        f.lead = check_real("lead", lead)
        return f
    a = _helix(helix_angle)
    return TensorField(kind, "spiral", lam, angle=a, label=f"spiral({v1}, {v2}, helix_angle={a})")


class Adhesion:
    """Adhesion tensor fields B = -(eps_1 e1 e1 + eps_2 e2 e2); stiffnesses in N/m (per point)."""

    @staticmethod
    def isotropic(stiffness):
        l1, l2 = _pair(_ADHESION, "stiffness", stiffness, "stiffness", stiffness)
        return TensorField(_ADHESION, "isotropic", (l1, l2), label=f"isotropic({stiffness})")

    @staticmethod
    def orthotropic(eps_1, eps_2, angle=0.0):
        """Constant orthotropy; angle [rad] of e1 in the transport frame."""
        return _orthotropic(_ADHESION, "eps_1", eps_1, "eps_2", eps_2, angle)

    @staticmethod
    def polar(eps_r, eps_phi, core_radius=0.0):
        """Polar orthotropy on a plane (papers' eq. 8): radial eps_r, circumferential eps_phi."""
        return _polar(_ADHESION, "eps_r", eps_r, "eps_phi", eps_phi, core_radius)

    @staticmethod
    def spiral(eps_1, eps_2, helix_angle=None, lead=None):
        """Spiral orthotropy: eps_1 along the helix, eps_2 across; the helix by its angle [rad] at
        the surface's radius (Cylinder, Cone) or by its lead [m per turn] (any surface of revolution)."""
        return _spiral(_ADHESION, "eps_1", eps_1, "eps_2", eps_2, helix_angle, lead)

    @staticmethod
    def field(function):
        """A field of the user's: function(xi1, xi2) -> (eps_1, eps_2, angle) [N/m, N/m, rad] at
        every surface point, angle of e1 from the xi1 coordinate line towards xi2."""
        return _user(_ADHESION, function)

    @staticmethod
    def from_matrix(B):
        """Constant B given by its 2x2 transport-frame components, papers' sign (negative definite)."""
        b = check_spd("B", B, sign=-1.0)
        return TensorField(_ADHESION, "matrix", None, matrix=[-b[0], -b[1], -b[2]], label=f"from_matrix({b})")


class Friction:
    """Friction tensor fields F = e1 e1 / mu_1^2 + e2 e2 / mu_2^2 (Coulomb coefficients mu_k > 0)."""

    @staticmethod
    def isotropic(mu):
        lam = _pair(_FRICTION, "mu", mu, "mu", mu)
        return TensorField(_FRICTION, "isotropic", lam, label=f"isotropic({mu})")

    @staticmethod
    def orthotropic(mu_1, mu_2, angle=0.0):
        """Constant orthotropy, as Adhesion.orthotropic (mu_1 along e1, mu_2 across)."""
        return _orthotropic(_FRICTION, "mu_1", mu_1, "mu_2", mu_2, angle)

    @staticmethod
    def polar(mu_r, mu_phi, core_radius=0.0):
        """Polar orthotropy on a plane, as Adhesion.polar (mu_r radial, mu_phi circumferential)."""
        return _polar(_FRICTION, "mu_r", mu_r, "mu_phi", mu_phi, core_radius)

    @staticmethod
    def spiral(mu_1, mu_2, helix_angle=None, lead=None):
        """Spiral friction net, as Adhesion.spiral (mu_1 along the helix, mu_2 across)."""
        return _spiral(_FRICTION, "mu_1", mu_1, "mu_2", mu_2, helix_angle, lead)

    @staticmethod
    def field(function):
        """A field of the user's: function(xi1, xi2) -> (mu_1, mu_2, angle) at every surface point,
        angle [rad] of e1 from the xi1 coordinate line towards xi2."""
        return _user(_FRICTION, function)

    @staticmethod
    def from_matrix(F):
        """Constant F given by its 2x2 transport-frame components (symmetric positive definite)."""
        f = check_spd("F", F)
        return TensorField(_FRICTION, "matrix", None, matrix=list(f), label=f"from_matrix({f})")
