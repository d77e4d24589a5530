"""Tensor fields on any surface of the protocol (exu_aniso.geometry): principal values and the
direction of principal axis 1 as functions of the surface point, relative to the coordinate lines.

A field is a namedtuple of parameters; its compiled function ``principal(f, xi1, xi2, r, r1, r2, a1,
a2)`` takes the surface coordinates of the contact point C, the local chart data there (rho, rho_1,
rho_2 in the surface's local frame) and the tangent frame (a_1, a_2) below, which the caller has
computed once for both fields, and returns ``(lambda_1, lambda_2, c, s)``: the principal values of the positive tensor (C = -B for
adhesion, F for friction) and the direction e_1 = c a_1 + s a_2 in the orthonormal tangent frame
of C,

    a_1 = rho_1 / |rho_1|,  a_2 = nu x a_1,  nu = rho_1 x rho_2 / |rho_1 x rho_2|

(a_2 lies on the side of rho_2, whatever side of the surface the slave is on). Components in that
frame: ``physical(f, xi1, xi2, r, r1, r2, a1, a2) = (p11, p12, p22)``. Registry dispatch by the parameter type, as for
the surfaces (``geometry.core``).

Fields:

* ``IsotropicNet(l1, l2)``: l1 = l2, no direction;
* ``OrthotropicNet(l1, l2, angle)``: e_1 at ``angle`` from the xi1 coordinate line at every point;
* ``PolarNet(l1, l2, rc2)``: on a plane, e_1 = e_r about the local origin (papers' eq. 8); the core
  radius r_c regularises the origin as ``fields.Adhesion.polar`` does: principal values
  l2 + (l1 - l2) (r^2 + r_c^2/2)/(r^2 + r_c^2) along e_r and l2 + (l1 - l2) (r_c^2/2)/(r^2 + r_c^2)
  along e_phi (equal at the origin);
* ``SpiralNet(l1, l2, lead)``: a constant-lead spiral on a surface whose first coordinate is the
  angle about an axis (cylinder, cone, sphere, torus, any surface of revolution): e_1 along
  w = rho_1 + lead / (2 pi) rho_2, the curve that advances ``lead`` in xi2 per turn. On a cylinder
  of radius R with helix angle alpha: lead = 2 pi R tan(alpha);
* ``UserNet(function, inverse_square)``: the user's ``function(xi1, xi2) -> (value_1, value_2,
  angle)`` (``Adhesion.field`` / ``Friction.field``): principal values (stiffnesses, or friction
  coefficients when inverse_square: lambda = 1 / mu^2) and e_1 at ``angle`` [rad] from the xi1
  coordinate line towards xi2, at every point. Compiled to a numba cfunc when numba can (once, when
  the field is made); otherwise ``PythonUserNet`` runs it as plain Python (and the contact with it).
"""
from __future__ import annotations

import math
from collections import namedtuple

from numba import njit
from numba.extending import overload

from exu_aniso.geometry.core import cross, dot

IsotropicNet = namedtuple("IsotropicNet", ("l1", "l2"))
UserNet = namedtuple("UserNet", ("function", "inverse_square"))
PythonUserNet = namedtuple("PythonUserNet", ("function", "inverse_square"))
OrthotropicNet = namedtuple("OrthotropicNet", ("l1", "l2", "angle"))
PolarNet = namedtuple("PolarNet", ("l1", "l2", "rc2"))
SpiralNet = namedtuple("SpiralNet", ("l1", "l2", "lead"))

_PRINCIPAL = {}


def register(params_type, principal):
    _PRINCIPAL[params_type] = principal


def principal(f, xi1, xi2, r, r1, r2, a1, a2):
    """(lambda_1, lambda_2, c, s) of field f at the chart point xi with chart data (r, r1, r2) and
    the tangent frame (a1, a2) there; dispatch by type."""
    return _PRINCIPAL[type(f)](f, xi1, xi2, r, r1, r2, a1, a2)


@overload(principal)
def _principal(f, xi1, xi2, r, r1, r2, a1, a2):
    fn = _PRINCIPAL[f.instance_class]
    return lambda f, xi1, xi2, r, r1, r2, a1, a2: fn(f, xi1, xi2, r, r1, r2, a1, a2)


@njit(cache=True)
def tangent_frame(r1, r2):
    """a_1, a_2 (unit, in the tangent plane; a_2 on the side of rho_2) and nu."""
    i1 = 1.0 / math.sqrt(dot(r1, r1))      # one division per norm (a division costs ~10 multiplications)
    a1 = (r1[0] * i1, r1[1] * i1, r1[2] * i1)
    c = cross(r1, r2)
    ic = 1.0 / math.sqrt(dot(c, c))
    nu = (c[0] * ic, c[1] * ic, c[2] * ic)
    return a1, cross(nu, a1), nu


@njit(cache=True)
def _isotropic(f, xi1, xi2, r, r1, r2, a1, a2):
    return f.l1, f.l2, 1.0, 0.0


@njit(cache=True)
def _orthotropic(f, xi1, xi2, r, r1, r2, a1, a2):
    return f.l1, f.l2, math.cos(f.angle), math.sin(f.angle)


@njit(cache=True, inline="always")
def _polar_values(f, rho2):
    """The radial and circumferential principal values of a polar net at squared radius rho2."""
    d = rho2 + f.rc2
    if not d > 0.0:
        raise ValueError("polar orthotropy is undefined at the polar origin (x = y = 0); set core_radius > 0")
    if not d < math.inf:
        raise ValueError("point coordinates too large or not finite for the polar field: x^2 + y^2 overflows")
    wd = (f.l1 - f.l2) / d
    return f.l2 + wd * (rho2 + 0.5 * f.rc2), f.l2 + wd * (0.5 * f.rc2)


@njit(cache=True, inline="always")
def _polar_direction(r, a1, a2, rho2):
    """(c, s) of e_r in the frame (a1, a2) at the local point r (e_x at the origin)."""
    if rho2 == 0.0:
        return 1.0, 0.0
    irh = 1.0 / math.sqrt(rho2)
    er = (r[0] * irh, r[1] * irh, 0.0)
    return dot(er, a1), dot(er, a2)


@njit(cache=True)
def _polar(f, xi1, xi2, r, r1, r2, a1, a2):
    rho2 = r[0] * r[0] + r[1] * r[1]
    lr, lp = _polar_values(f, rho2)
    c, s = _polar_direction(r, a1, a2, rho2)
    return lr, lp, c, s


@njit(cache=True)
def _spiral(f, xi1, xi2, r, r1, r2, a1, a2):
    k = f.lead / (2.0 * math.pi)
    w = (r1[0] + k * r2[0], r1[1] + k * r2[1], r1[2] + k * r2[2])
    c, s = dot(w, a1), dot(w, a2)
    inw = 1.0 / math.sqrt(c * c + s * s)
    return f.l1, f.l2, c * inw, s * inw


@njit(cache=True)
def _user(f, xi1, xi2, r, r1, r2, a1, a2):
    v1, v2, angle = f.function(xi1, xi2)
    if not (v1 > 0.0 and v2 > 0.0 and v1 < math.inf and v2 < math.inf and abs(angle) < math.inf):
        raise ValueError("user field: function(xi1, xi2) must return (value_1, value_2, angle) with finite "
                         "values > 0 and a finite angle [rad] (or it raised) at the contact point")
    if f.inverse_square:
        return 1.0 / (v1 * v1), 1.0 / (v2 * v2), math.cos(angle), math.sin(angle)
    return v1, v2, math.cos(angle), math.sin(angle)


register(IsotropicNet, _isotropic)
register(UserNet, _user)
register(PythonUserNet, _user.py_func)
register(OrthotropicNet, _orthotropic)
register(PolarNet, _polar)
register(SpiralNet, _spiral)


@njit(cache=True)
def physical(f, xi1, xi2, r, r1, r2, a1, a2):
    """Components (p11, p12, p22) of the positive tensor in the frame (a_1, a_2)."""
    l1, l2, c, s = principal(f, xi1, xi2, r, r1, r2, a1, a2)
    return _components(l1, l2, c, s)


@njit(cache=True)
def physical_both(fB, fF, xi1, xi2, r, r1, r2, a1, a2):
    """physical of both nets of a contact at one point: ((B's net: p11, p12, p22), (F's))."""
    return physical(fB, xi1, xi2, r, r1, r2, a1, a2), physical(fF, xi1, xi2, r, r1, r2, a1, a2)


def physical_pair(fB, fF, xi1, xi2, r, r1, r2, a1, a2):
    """physical_both, where two polar nets share their direction in compiled code (one square root
    and division less per point)."""
    return physical_both(fB, fF, xi1, xi2, r, r1, r2, a1, a2)


@njit(cache=True, inline="always")
def _components(l1, l2, c, s):
    return l1 * c * c + l2 * s * s, (l1 - l2) * c * s, l1 * s * s + l2 * c * c


@overload(physical_pair)
def _physical_pair(fB, fF, xi1, xi2, r, r1, r2, a1, a2):
    if fB.instance_class is PolarNet and fF.instance_class is PolarNet:
        def both_polar(fB, fF, xi1, xi2, r, r1, r2, a1, a2):
            rho2 = r[0] * r[0] + r[1] * r[1]
            c, s = _polar_direction(r, a1, a2, rho2)
            bB, bF = _polar_values(fB, rho2), _polar_values(fF, rho2)
            return _components(bB[0], bB[1], c, s), _components(bF[0], bF[1], c, s)
        return both_polar
    return lambda fB, fF, xi1, xi2, r, r1, r2, a1, a2: physical_both(fB, fF, xi1, xi2, r, r1, r2, a1, a2)


def net_of(field, surface):
    """The net parameters of an exu_aniso.fields.tensor_fields.TensorField (Adhesion.* / Friction.*) on a surface
    of exu_aniso.geometry: principal values of the positive tensor (C or F) and the direction rule.
    A spiral given by its helix angle takes the lead 2 pi r tan(alpha) at the surface's radius r
    (Cylinder, Cone at z = 0)."""
    import numpy as np

    l1, l2 = (None, None) if field.lam is None else map(float, field.lam)
    pattern = field.pattern
    if pattern == "isotropic":
        return IsotropicNet(l1, l2)
    if pattern == "orthotropic":
        return OrthotropicNet(l1, l2, float(field.angle))
    if pattern == "matrix":          # constant components: principal axes of the 2x2 matrix
        c = field._const
        w, V = np.linalg.eigh(np.array([[c[0], c[1]], [c[1], c[2]]]))
        return OrthotropicNet(float(w[1]), float(w[0]), float(math.atan2(V[1, 1], V[0, 1])))
    if pattern == "polar":
        if type(surface).__name__ != "Plane":
            raise ValueError(f"{field!r}: polar orthotropy is defined on a Plane only; got {surface!r}")
        return PolarNet(l1, l2, float(field.core_radius) ** 2)
    if pattern == "user":
        flag = field.kind == "friction"
        return UserNet(field.cfunc, flag) if field.cfunc is not None else PythonUserNet(field.python, flag)
    if pattern == "spiral":
        lead = getattr(field, "lead", None)
        if lead is None:
            from exu_aniso.geometry import Cone, Cylinder
            radius = getattr(surface, "radius", None)
            if not isinstance(surface, (Cylinder, Cone)):
                raise ValueError(f"{field!r}: a spiral given by its helix angle needs a Cylinder or a Cone "
                                 f"(the lead is 2 pi r tan(helix_angle)); give lead= for {surface!r}")
            lead = 2.0 * math.pi * radius * math.tan(field.angle)
        if surface.periods[0] == 0.0:
            raise ValueError(f"{field!r}: a spiral net needs an angle as the first surface coordinate "
                             f"(a surface of revolution); got {surface!r}")
        return SpiralNet(l1, l2, float(lead))
    raise ValueError(f"{field!r}: no net for the field pattern {pattern!r}")
