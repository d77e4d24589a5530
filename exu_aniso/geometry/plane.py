"""Plane z_l = 0 of its local frame, in Cartesian (x, y) or polar (r, phi) coordinates.

Cartesian: rho = (xi1, xi2, 0), rho_1 = e_x, rho_2 = e_y, m = I, no curvature, Gamma = 0.
Polar: rho = r (cos phi, sin phi, 0), rho_1 = e_r, rho_2 = r e_phi, m = diag(1, r^2),
Gamma^1_22 = -r, Gamma^2_12 = 1/r; singular at r = 0. Side "front": slave on +z_l.
"""
from __future__ import annotations

import math
from collections import namedtuple

from numba import njit

from . import core
from .base import TWO_PI, Surface, side_sign

CartesianPlaneParams = namedtuple("CartesianPlaneParams", core.COMMON_FIELDS)
PolarPlaneParams = namedtuple("PolarPlaneParams", core.COMMON_FIELDS)

_Z = (0.0, 0.0, 0.0)


@njit(cache=True)
def cartesian_chart(p, xi1, xi2):
    return (xi1, xi2, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), _Z, _Z, _Z


@njit(cache=True)
def cartesian_guess(p, y, xi1, xi2):
    return y[0], y[1], True


@njit(cache=True)
def polar_chart(p, r, phi):
    c, s = math.cos(phi), math.sin(phi)
    return ((r * c, r * s, 0.0), (c, s, 0.0), (-r * s, r * c, 0.0), _Z, (-s, c, 0.0), (-r * c, -r * s, 0.0))


@njit(cache=True)
def polar_guess(p, y, xi1, xi2):
    return math.hypot(y[0], y[1]), math.atan2(y[1], y[0]), True


core.register(CartesianPlaneParams, cartesian_chart, cartesian_guess, constant_metric=True)
core.register(PolarPlaneParams, polar_chart, polar_guess)


class Plane(Surface):
    """The plane z = 0 of the master frame, normal +z on side "front" (slave above it).

    coordinates: "cartesian" -> xi = (x, y); "polar" -> xi = (r, phi) about the origin."""

    name = "Plane"

    def __init__(self, coordinates="cartesian", side="front"):
        if coordinates not in ("cartesian", "polar"):
            raise ValueError(f"Plane: coordinates must be 'cartesian' or 'polar'; got {coordinates!r}")
        self.coordinates = coordinates
        self.side = side
        # rho_1 x rho_2 = +e_z in both charts (polar: e_r x r e_phi = r e_z)
        sign = side_sign("Plane", side, ("front", "back"), 1.0)
        frame = ((0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
        if coordinates == "cartesian":
            super().__init__(CartesianPlaneParams(*frame, sign, 0.0, 0.0))
        else:
            super().__init__(PolarPlaneParams(*frame, sign, 0.0, TWO_PI))

    @property
    def limits(self):
        return ((0.0, math.inf), (-math.inf, math.inf)) if self.coordinates == "polar" else super().limits

    def __repr__(self):
        return f"Plane(coordinates={self.coordinates!r}, side={self.side!r})"
