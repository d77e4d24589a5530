"""Circular cone about the local z axis: r(z) = radius + z tan(half_angle), chart (phi, z).

rho = (r cos phi, r sin phi, z), rho_1 = r e_phi, rho_2 = r' e_r + e_z with r' = tan(half_angle).
The generator is a straight line, so the closest point is in closed form (foot of the
perpendicular in the meridian plane). A half angle of 0 is the Cylinder exactly. The apex (r = 0)
is singular. On a cone the coordinate basis is not parallel: a vector carried once around a
parallel turns by 2 pi sin(half_angle) against it (Gamma^1_12 = r'/r, Gamma^2_11 = -r r'/(1+r'^2)).
"""
from __future__ import annotations

import math
from collections import namedtuple

from numba import njit

from exu_aniso.util.validation import check_positive, check_real
from . import core
from .base import TWO_PI, Surface, placement, side_sign

ConeParams = namedtuple("ConeParams", core.COMMON_FIELDS + ("radius", "slope"))

_Z = (0.0, 0.0, 0.0)


@njit(cache=True)
def chart(p, phi, z):
    r = p.radius + p.slope * z
    t = p.slope
    c, s = math.cos(phi), math.sin(phi)
    return ((r * c, r * s, z), (-r * s, r * c, 0.0), (t * c, t * s, 1.0), (-r * c, -r * s, 0.0),
            (-t * s, t * c, 0.0), _Z)


@njit(cache=True)
def guess(p, y, xi1, xi2):
    t = p.slope
    rho = math.hypot(y[0], y[1])
    return math.atan2(y[1], y[0]), ((rho - p.radius) * t + y[2]) / (1.0 + t * t), True


core.register(ConeParams, chart, guess)


class Cone(Surface):
    """Cone r(z) = radius + z tan(half_angle) about the axis through axis_point along axis_direction
    (z measured from axis_point); side "outside" (a tapered shaft) or "inside" (a tapered hole)."""

    name = "Cone"

    def __init__(self, half_angle, radius, axis_point=(0.0, 0.0, 0.0), axis_direction=(0.0, 0.0, 1.0),
                 side="outside"):
        a = check_real("half_angle", half_angle)
        if not abs(a) < 0.5 * math.pi:
            raise ValueError(f"Cone: half_angle must lie in (-pi/2, pi/2) rad; got {a!r}")
        self.half_angle = a
        self.radius = check_positive("radius", radius)
        self.side = side
        # rho_1 x rho_2 = r (e_r - r' e_z): outward where r > 0
        sign = side_sign("Cone", side, ("outside", "inside"), 1.0)
        super().__init__(ConeParams(*placement("Cone", axis_point, axis_direction), sign, TWO_PI, 0.0,
                                    self.radius, math.tan(a)))

    @property
    def limits(self):
        """z on the side of the apex r(z) = 0 where r > 0 (all z for zero taper)."""
        t = self.params.slope
        if t == 0.0:
            return (-math.inf, math.inf), (-math.inf, math.inf)
        z_apex = -self.radius / t
        return (-math.inf, math.inf), ((z_apex, math.inf) if t > 0.0 else (-math.inf, z_apex))

    def __repr__(self):
        p = self.params
        return (f"Cone(half_angle={self.half_angle}, radius={self.radius}, axis_point={list(p.origin)}, "
                f"axis_direction={list(p.ez)}, side={self.side!r})")
