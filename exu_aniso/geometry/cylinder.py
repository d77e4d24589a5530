"""Circular cylinder of radius R about the local z axis, chart (phi, z).

rho = (R cos phi, R sin phi, z), rho_1 = R e_phi, rho_2 = e_z, m = diag(R^2, 1), Gamma = 0 (the
coordinate basis is parallel: the surface is developable and the chart is its unrolling). Closest
point in closed form; undefined on the axis (every phi is equally close).
"""
from __future__ import annotations

import math
from collections import namedtuple

import numpy as np
from numba import njit

from exu_aniso.util.validation import check_positive
from . import core
from .base import TWO_PI, Surface, placement, side_sign

CylinderParams = namedtuple("CylinderParams", core.COMMON_FIELDS + ("radius",))

_Z = (0.0, 0.0, 0.0)


@njit(cache=True)
def chart(p, phi, z):
    R = p.radius
    c, s = math.cos(phi), math.sin(phi)
    return (R * c, R * s, z), (-R * s, R * c, 0.0), (0.0, 0.0, 1.0), (-R * c, -R * s, 0.0), _Z, _Z


@njit(cache=True)
def guess(p, y, xi1, xi2):
    return math.atan2(y[1], y[0]), y[2], True


core.register(CylinderParams, chart, guess, constant_metric=True)


class Cylinder(Surface):
    """Cylinder of radius R about the axis through axis_point along axis_direction; side "inside"
    (a hole: slave inside, n towards the axis) or "outside" (a shaft)."""

    name = "Cylinder"

    def __init__(self, radius, axis_point=(0.0, 0.0, 0.0), axis_direction=(0.0, 0.0, 1.0), side="inside"):
        self.radius = check_positive("radius", radius)
        self.side = side
        sign = side_sign("Cylinder", side, ("outside", "inside"), 1.0)   # rho_1 x rho_2 = R e_r
        super().__init__(CylinderParams(*placement("Cylinder", axis_point, axis_direction), sign, TWO_PI, 0.0,
                                        self.radius))

    @property
    def axis_point(self):
        return np.array(self.params.origin)

    @property
    def sign(self):
        """+1 for a shaft (n = e_r), -1 for a hole (n towards the axis)."""
        return self.params.sign

    @property
    def axes(self):
        """Rows e_ref (phi = 0), e_ref2, e_axis."""
        p = self.params
        return np.array([p.ex, p.ey, p.ez])

    def __repr__(self):
        p = self.params
        return (f"Cylinder(radius={self.radius}, axis_point={list(p.origin)}, axis_direction={list(p.ez)}, "
                f"side={self.side!r})")
