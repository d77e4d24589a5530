"""Helicoid about the local z axis: the flank of a screw thread, chart (phi, r).

rho = (r cos phi, r sin phi, h phi + c (r - r2)) with the lead per radian h = +-P / (2 pi) (right /
left hand), r2 = d2 / 2 the pitch radius and the flank slope c = +-tan(beta / 2) (beta the full
thread angle; the sign from the flank's part and side, see Helicoid). In cylindrical components
(e_r, e_phi, e_z) at phi:

  rho_1 = r e_phi + h e_z,  rho_2 = e_r + c e_z,  rho_11 = -r e_r,  rho_12 = e_phi,  rho_22 = 0,
  m = [[r^2 + h^2, h c], [h c, 1 + c^2]],  det m = W^2 = r^2 (1 + c^2) + h^2,
  rho_1 x rho_2 = r c e_r + h e_phi - r e_z,  K = -h^2 / W^4 (a ruled surface of negative curvature).

beta = 0 is the plain (right) helicoid, whose normal has no radial component. phi is not periodic:
phi and phi + 2 pi are the same azimuth one pitch apart, on the next turn. The chart is regular on
the axis too (|rho_1 x rho_2| >= |h| > 0), but there the flank of a real thread does not exist, and a
c != 0 surface continued to r < 0 is not the thread's flank: the chart is meant for r > 0 (limits).

The closest point by Newton from the point of the sheet nearest in z at the point's own azimuth
and radius: a point of a thread is always within half a pitch, axially, of its flank, so the nearest
sheet (not the previous projection) picks the turn.
"""
from __future__ import annotations

import math
from collections import namedtuple

from numba import njit

from exu_aniso.util.validation import check_positive, check_real
from . import core
from .base import TWO_PI, Surface, placement, side_sign

HelicoidParams = namedtuple("HelicoidParams", core.COMMON_FIELDS + ("lead_per_radian", "flank_slope",
                                                                      "pitch_radius"))

_Z = (0.0, 0.0, 0.0)


@njit(cache=True)
def chart(p, phi, r):
    h, c = p.lead_per_radian, p.flank_slope
    cf, sf = math.cos(phi), math.sin(phi)
    return ((r * cf, r * sf, h * phi + c * (r - p.pitch_radius)),
            (-r * sf, r * cf, h),
            (cf, sf, c),
            (-r * cf, -r * sf, 0.0),
            (-sf, cf, 0.0),
            _Z)


@njit(cache=True)
def guess(p, y, xi1, xi2):
    h, c = p.lead_per_radian, p.flank_slope
    rho = math.hypot(y[0], y[1])
    a = math.atan2(y[1], y[0])
    if xi1 == xi1:
        # a point in contact (its last projection as the hint) stays on its turn: it cannot cross the
        # flank, and a Newton iterate that moves it by half a pitch must not land it on the next turn
        return a + TWO_PI * math.floor((xi1 - a) / TWO_PI + 0.5), rho, False
    # no hint: the turn whose sheet at azimuth a and radius rho lies nearest in z (floor(q + 0.5): round)
    q = ((y[2] - c * (rho - p.pitch_radius)) / h - a) / TWO_PI
    return a + TWO_PI * math.floor(q + 0.5), rho, False


core.register(HelicoidParams, chart, guess)


def lead_angle(pitch, radius):
    """Lead angle lambda [rad] of a helix of lead ``pitch`` [m per turn] at ``radius`` [m]:
    tan lambda = P / (2 pi r) (at the pitch diameter d2 of a thread: P / (pi d2))."""
    return math.atan(pitch / (TWO_PI * radius))


def normal_flank_angle(flank_angle, lead):
    """beta_n [rad], a thread's flank in the section normal to the helix: tan beta_n = tan(beta / 2)
    cos lambda, with beta the full thread angle [rad] (metric: pi/3) and lambda the lead angle [rad]
    (VDI 2230, ISO 16047; a metric thread's 30 deg becomes slightly less)."""
    return math.atan(math.tan(0.5 * flank_angle) * math.cos(lead))


def _choice(name, value, allowed):
    if value not in allowed:
        raise ValueError(f"Helicoid: {name} must be {' or '.join(repr(s) for s in allowed)}; got {value!r}")
    return value


class Helicoid(Surface):
    """Flank of a screw thread about the axis through axis_point along axis_direction (z measured
    from axis_point): pitch P [m], flank_angle beta the full thread angle [rad] in [0, pi) (a metric
    thread: pi / 3; 0: a square thread's flank, the plain helicoid), pitch_diameter d2 [m] (the flank
    passes z = h phi at r = d2 / 2), hand "right" or "left", flank_of "nut" or "bolt" (whose thread
    the flank belongs to: the master), side "forward" (the slave lies on the +axis_direction side of
    the flank) or "backward". Chart (phi, r): phi about the axis (as on the Cylinder), not periodic
    (phi + 2 pi is the next turn), r the distance from the axis."""

    name = "Helicoid"

    def __init__(self, pitch, flank_angle, pitch_diameter, axis_point=(0.0, 0.0, 0.0),
                 axis_direction=(0.0, 0.0, 1.0), hand="right", flank_of="nut", side="forward"):
        self.pitch = check_positive("pitch", pitch)
        b = check_real("flank_angle", flank_angle)
        if not 0.0 <= b < math.pi:
            raise ValueError(f"Helicoid: flank_angle must lie in [0, pi) rad (the full thread angle); "
                             f"got {b!r}")
        self.flank_angle = b
        self.pitch_diameter = check_positive("pitch_diameter", pitch_diameter)
        self.hand = _choice("hand", hand, ("right", "left"))
        self.flank_of = _choice("flank_of", flank_of, ("nut", "bolt"))
        self.side = side
        # rho_1 x rho_2 = r c e_r + h e_phi - r e_z: its axial component -r < 0 points backward
        # (-axis_direction) wherever r > 0, so "forward" takes sign = -1
        sign = side_sign("Helicoid", side, ("forward", "backward"), -1.0)
        # the flank's z rises with r (c > 0) on the forward side of a nut's flank: the bolt's tooth
        # lying there narrows outward; a bolt's flank, or the backward side, mirrors it
        self.lead_per_radian = (1.0 if hand == "right" else -1.0) * self.pitch / TWO_PI
        self.flank_slope = (math.tan(0.5 * b) * (1.0 if side == "forward" else -1.0)
                            * (1.0 if flank_of == "nut" else -1.0))
        super().__init__(HelicoidParams(*placement("Helicoid", axis_point, axis_direction), sign, 0.0, 0.0,
                                        self.lead_per_radian, self.flank_slope, 0.5 * self.pitch_diameter))

    @property
    def limits(self):
        """phi unbounded, r > 0 (the axis bounds the flank)."""
        return (-math.inf, math.inf), (0.0, math.inf)

    def lead_angle(self, r=None):
        """Lead angle lambda [rad] of the helix at radius r (default the pitch radius d2 / 2):
        tan lambda = |h| / r = P / (2 pi r)."""
        r = 0.5 * self.pitch_diameter if r is None else check_positive("r", r)
        return lead_angle(self.pitch, r)

    def normal_flank_angle(self):
        """The flank's angle in the section normal to the helix at the pitch radius [rad]
        (the module's ``normal_flank_angle``): half the thread angle seen in that section."""
        return normal_flank_angle(self.flank_angle, self.lead_angle())

    def __repr__(self):
        p = self.params
        return (f"Helicoid(pitch={self.pitch}, flank_angle={self.flank_angle}, "
                f"pitch_diameter={self.pitch_diameter}, axis_point={list(p.origin)}, "
                f"axis_direction={list(p.ez)}, hand={self.hand!r}, flank_of={self.flank_of!r}, "
                f"side={self.side!r})")
