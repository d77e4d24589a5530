"""Torus about the local z axis: a tube of radius a (minor) whose centre line is the circle of
radius R (major) in the plane z = 0. Chart (phi, psi): phi about the axis, psi around the tube
from the outer equator towards +z.

rho = ((R + a cos psi) cos phi, (R + a cos psi) sin phi, a sin psi),
rho_1 = (R + a cos psi) e_phi, rho_2 = a (-sin psi e_r + cos psi e_z),
m = diag((R + a cos psi)^2, a^2), h = diag(-(R + a cos psi) cos psi, -a) on the outside.

The closest point is in closed form: phi from the point's azimuth, psi from its position in the
meridian plane relative to the tube's centre circle. Undefined on the centre circle (every psi is
equally close) and on the axis (every phi); with a < R the chart is regular everywhere on the torus.
This module is the worked example of docs/adding_a_surface.md.
"""
from __future__ import annotations

import math
from collections import namedtuple

from numba import njit

from exu_aniso.util.validation import check_positive, check_vector
from . import core
from .base import TWO_PI, Surface, placement, side_sign

TorusParams = namedtuple("TorusParams", core.COMMON_FIELDS + ("major_radius", "minor_radius"))


@njit(cache=True)
def chart(p, phi, psi):
    R, a = p.major_radius, p.minor_radius
    cf, sf = math.cos(phi), math.sin(phi)
    cs, ss = math.cos(psi), math.sin(psi)
    w = R + a * cs                                     # distance of the point from the axis
    return ((w * cf, w * sf, a * ss),
            (-w * sf, w * cf, 0.0),
            (-a * ss * cf, -a * ss * sf, a * cs),
            (-w * cf, -w * sf, 0.0),
            (a * ss * sf, -a * ss * cf, 0.0),
            (-a * cs * cf, -a * cs * sf, -a * ss))


@njit(cache=True)
def guess(p, y, xi1, xi2):
    return math.atan2(y[1], y[0]), math.atan2(y[2], math.hypot(y[0], y[1]) - p.major_radius), True


core.register(TorusParams, chart, guess)


class Torus(Surface):
    """Torus with major radius R (centre circle of the tube) and minor radius a < R (the tube)
    about the axis through center along axis_direction; side "outside" (slave outside the tube) or
    "inside" (slave inside the tube, e.g. a ball in a toroidal groove)."""

    name = "Torus"

    def __init__(self, major_radius, minor_radius, center=(0.0, 0.0, 0.0), axis_direction=(0.0, 0.0, 1.0),
                 side="outside"):
        self.major_radius = check_positive("major_radius", major_radius)
        self.minor_radius = check_positive("minor_radius", minor_radius)
        if not self.minor_radius < self.major_radius:
            raise ValueError(f"Torus: minor_radius must be < major_radius (a ring torus); got "
                             f"{self.minor_radius!r} >= {self.major_radius!r}")
        check_vector("center", center, 3)
        self.side = side
        # rho_1 x rho_2 = w a (cos psi e_r + sin psi e_z): away from the tube's centre line
        sign = side_sign("Torus", side, ("outside", "inside"), 1.0)
        super().__init__(TorusParams(*placement("Torus", center, axis_direction), sign, TWO_PI, TWO_PI,
                                     self.major_radius, self.minor_radius))

    def __repr__(self):
        p = self.params
        return (f"Torus(major_radius={self.major_radius}, minor_radius={self.minor_radius}, center={list(p.origin)}, "
                f"axis_direction={list(p.ez)}, side={self.side!r})")
