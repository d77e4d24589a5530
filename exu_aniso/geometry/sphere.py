"""Sphere of radius R about its centre, chart (phi, theta): phi about the axis (as on the Cylinder),
theta the polar angle from the axis direction.

rho = R (sin theta cos phi, sin theta sin phi, cos theta), rho_1 = R sin theta e_phi,
rho_2 = R e_theta, m = diag(R^2 sin^2 theta, R^2). The poles (theta = 0, pi) are singular points of
the chart; the centre is a centre of curvature (no unique closest point). A vector carried once
around the parallel theta turns by 2 pi (1 - cos theta) against the coordinate basis (holonomy).
"""
from __future__ import annotations

import math
from collections import namedtuple

from numba import njit

from exu_aniso.util.validation import check_positive, check_vector
from . import core
from .base import TWO_PI, Surface, placement, side_sign

SphereParams = namedtuple("SphereParams", core.COMMON_FIELDS + ("radius",))


@njit(cache=True)
def chart(p, phi, theta):
    R = p.radius
    cp, sp = math.cos(phi), math.sin(phi)
    ct, st = math.cos(theta), math.sin(theta)
    return ((R * st * cp, R * st * sp, R * ct),
            (-R * st * sp, R * st * cp, 0.0),
            (R * ct * cp, R * ct * sp, -R * st),
            (-R * st * cp, -R * st * sp, 0.0),
            (-R * ct * sp, R * ct * cp, 0.0),
            (-R * st * cp, -R * st * sp, -R * ct))


@njit(cache=True)
def guess(p, y, xi1, xi2):
    return math.atan2(y[1], y[0]), math.atan2(math.hypot(y[0], y[1]), y[2]), True


core.register(SphereParams, chart, guess)


class Sphere(Surface):
    """Sphere of radius R about center; side "outside" (a ball) or "inside" (a spherical cavity);
    axis_direction sets the chart's pole (theta = 0)."""

    name = "Sphere"

    def __init__(self, radius, center=(0.0, 0.0, 0.0), axis_direction=(0.0, 0.0, 1.0), side="outside"):
        self.radius = check_positive("radius", radius)
        self.side = side
        check_vector("center", center, 3)
        # rho_1 x rho_2 = R^2 sin(theta) (e_phi x e_theta) = -R^2 sin(theta) e_r: inward
        sign = side_sign("Sphere", side, ("outside", "inside"), -1.0)
        super().__init__(SphereParams(*placement("Sphere", center, axis_direction), sign, TWO_PI, 0.0,
                                      self.radius))

    @property
    def limits(self):
        return (-math.inf, math.inf), (0.0, math.pi)      # the chart's poles

    def __repr__(self):
        p = self.params
        return f"Sphere(radius={self.radius}, center={list(p.origin)}, axis_direction={list(p.ez)}, side={self.side!r})"
