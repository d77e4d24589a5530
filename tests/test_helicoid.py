"""The Helicoid (a screw thread's flank, exu_aniso.geometry.helicoid) against oracles computed here from
its definition, not from the module: the exact flank normal in cylindrical components, the flank
angle in the section normal to the helix (tan beta_n = tan(beta / 2) cos lambda), the screw symmetry,
the next turn one pitch up the axis, the plain helicoid and the cone of a vanishing pitch. The chart's
derivatives, the projection round trip, the curvature and the objectivity are in
tests/test_geometry_protocol.py.

Sizes: an M10 thread (P = 1.5 mm, d2 = 9.026 mm, beta = 60 deg). The projection's Newton stops at a
relative step of 1e-13 of |y| + |rho| (about 1e-2 m here), so coordinates and gaps come back to
about 1e-15 m; the tolerances below (1e-12 on r and the gap, 1e-10 rad on phi, 1e-12 on unit
vectors) leave a margin of a few hundred for the round-off of the frames."""
from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from exu_aniso.geometry import Cone, Helicoid

P, D2, BETA = 1.5e-3, 9.026e-3, math.pi / 3
R2 = D2 / 2
COMBOS = list(itertools.product(("right", "left"), ("nut", "bolt"), ("forward", "backward")))
IDS = ["-".join(c) for c in COMBOS]


def _spec(hand, flank_of, side, beta=BETA, pitch=P):
    """h and c of the specification, and the side sign (rho_1 x rho_2 points to -z: forward = -1)."""
    h = (1.0 if hand == "right" else -1.0) * pitch / (2 * math.pi)
    c = math.tan(beta / 2) * (1.0 if side == "forward" else -1.0) * (1.0 if flank_of == "nut" else -1.0)
    return h, c, (-1.0 if side == "forward" else 1.0)


def _cyl(phi):
    """e_r, e_phi, e_z at azimuth phi (default placement: the local frame is the master frame)."""
    return (np.array([math.cos(phi), math.sin(phi), 0.0]), np.array([-math.sin(phi), math.cos(phi), 0.0]),
            np.array([0.0, 0.0, 1.0]))


def _exact(h, c, sign, phi, r):
    """rho and the unit normal toward the slave from the definition: (r c, h, -r) / W in (e_r, e_phi, e_z)."""
    er, ep, ez = _cyl(phi)
    W = math.sqrt(r * r * (1 + c * c) + h * h)
    return r * er + (h * phi + c * (r - R2)) * ez, sign * (r * c * er + h * ep - r * ez) / W


def test_default_placement_is_the_master_frame():
    """The oracles below use the default placement's local frame as the master frame."""
    p = Helicoid(P, BETA, D2).params
    assert (p.origin, p.ex, p.ey, p.ez) == ((0.0,) * 3, (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))


@pytest.mark.parametrize("hand,flank_of,side", COMBOS, ids=IDS)
def test_sliding_along_the_helix_projects_to_the_exact_flank(hand, flank_of, side):
    """A point slid along the helix of radius r over two turns, 10 um off the flank on either side,
    projects back to (phi, r, gap), with the exact flank normal; forward: the normal points +z."""
    s = Helicoid(P, BETA, D2, hand=hand, flank_of=flank_of, side=side)
    h, c, sign = _spec(hand, flank_of, side)
    assert (s.lead_per_radian, s.flank_slope) == pytest.approx((h, c), rel=1e-15)
    for r in (0.8 * R2, R2, 1.15 * R2):
        for phi in np.linspace(0.0, 4 * math.pi, 29):
            rho, n = _exact(h, c, sign, phi, r)
            assert (n[2] > 0) == (side == "forward")
            for g in (1e-5, -1e-5):
                p = s.project(rho + g * n)
                assert p.xi[0] == pytest.approx(phi, abs=1e-10)
                assert p.xi[1] == pytest.approx(r, abs=1e-12)
                assert p.xi3 == pytest.approx(g, abs=1e-12)
                np.testing.assert_allclose(p.n, n, atol=1e-12)


def test_the_flank_rises_outward_on_the_forward_side_of_a_nut():
    """The sign rule of c: a bolt's tooth on the forward side of a nut's flank narrows outward, so
    that flank's z rises with r; the bolt's flank or the backward side falls."""
    for flank_of, side, rising in (("nut", "forward", True), ("bolt", "backward", True),
                                   ("bolt", "forward", False), ("nut", "backward", False)):
        s = Helicoid(P, BETA, D2, flank_of=flank_of, side=side)
        dz = s.at((0.3, 1.1 * R2)).point[2] - s.at((0.3, 0.9 * R2)).point[2]
        assert (dz > 0) == rising and abs(dz) == pytest.approx(0.2 * R2 * math.tan(BETA / 2), rel=1e-12)


@pytest.mark.parametrize("beta", [math.pi / 3, math.radians(29.0), math.radians(80.0)])
@pytest.mark.parametrize("hand,flank_of,side", COMBOS[::3], ids=IDS[::3])
def test_normal_flank_angle(beta, hand, flank_of, side):
    """In the section normal to the pitch helix (spanned by e_r and b, the unit vector normal to the
    helix tangent t = r2 e_phi + h e_z in the e_phi, e_z plane) the flank profile makes the angle
    beta_n with e_r, i.e. the normal projected onto the section makes beta_n with b:
    tan beta_n = |n . e_r| / |n . b| = tan(beta / 2) cos lambda, tan lambda = P / (pi d2)."""
    s = Helicoid(P, beta, D2, hand=hand, flank_of=flank_of, side=side)
    lam = math.atan(P / (math.pi * D2))
    target = math.atan(math.tan(beta / 2) * math.cos(lam))
    for phi in (0.0, 1.0, 5.0):
        g = s.at((phi, R2))
        er, _, _ = _cyl(phi)
        t = g.rho[0] / np.linalg.norm(g.rho[0])             # the helix r = r2 is the line xi2 = const
        b = np.cross(t, er)                                 # in the normal section, normal to e_r
        angle = math.atan2(abs(g.n @ er), abs(g.n @ b))
        assert abs(g.n @ t) < 1e-14                          # n lies in the normal section (round-off)
        assert angle == pytest.approx(target, abs=1e-13)
    assert s.normal_flank_angle() == pytest.approx(target, abs=1e-15)
    assert s.lead_angle() == pytest.approx(lam, abs=1e-15)
    assert s.lead_angle(2 * R2) == pytest.approx(math.atan(P / (2 * math.pi * D2)), abs=1e-15)


def test_metric_thread_normal_flank_angle_value():
    """M10 x 1.5: lambda = atan(1.5 / (pi 9.026)) = 3.028 deg, beta_n = 29.965 deg (VDI 2230 tables:
    lead angle 3.03 deg)."""
    s = Helicoid(P, BETA, D2)
    assert math.degrees(s.lead_angle()) == pytest.approx(3.028, abs=5e-4)
    assert math.degrees(s.normal_flank_angle()) == pytest.approx(29.965, abs=5e-4)


def _screw_motion(s, theta, x):
    """Rotation by theta about the axis (origin, ez) and translation h theta along it."""
    o, ez = np.array(s.params.origin), np.array(s.params.ez)
    v = x - o
    c, sn = math.cos(theta), math.sin(theta)
    v = v * c + np.cross(ez, v) * sn + ez * (ez @ v) * (1 - c)        # Rodrigues
    return o + v + s.lead_per_radian * theta * ez


@pytest.mark.parametrize("hand", ["right", "left"])
def test_screw_motion_maps_the_flank_onto_itself(hand):
    """The thread's screw symmetry: rho(phi, r) moved by the screw motion theta lies on the flank at
    (phi + theta, r) (gap 0), and the normal turns with the rotation."""
    s = Helicoid(P, BETA, D2, axis_point=(0.02, -0.01, 0.005), axis_direction=(2, 1, -2), hand=hand,
                 flank_of="bolt")
    for phi, r in ((0.2, 0.9 * R2), (-3.0, 1.2 * R2), (6.0, R2)):
        g = s.at((phi, r))
        for theta in (0.5, -2.0, 7.0):
            p = s.project(_screw_motion(s, theta, g.point))
            assert p.xi3 == pytest.approx(0.0, abs=1e-12)
            assert p.xi[0] == pytest.approx(phi + theta, abs=1e-10)
            assert p.xi[1] == pytest.approx(r, abs=1e-12)
            o = np.array(s.params.origin)
            turned = _screw_motion(s, theta, o + g.n) - _screw_motion(s, theta, o)
            np.testing.assert_allclose(p.n, turned, atol=1e-12)


@pytest.mark.parametrize("hand", ["right", "left"])
def test_one_pitch_up_the_axis_is_the_next_turn(hand):
    """rho(phi, r) + g n + P e_axis projects to (phi +- 2 pi, r, g): one turn on for a right hand
    thread, one turn back for a left hand one (its h < 0)."""
    s = Helicoid(P, BETA, D2, axis_direction=(0, 1, 1), hand=hand, side="backward")
    ez = np.array(s.params.ez)
    turn = 2 * math.pi * (1.0 if hand == "right" else -1.0)
    for phi, r, g in ((0.4, R2, 2e-5), (-2.5, 0.7 * R2, -3e-5)):
        q = s.at((phi, r))
        for k in (1, 2, -1):
            p = s.project(q.point + g * q.n + k * P * ez)
            assert p.xi[0] == pytest.approx(phi + k * turn, abs=1e-10)
            assert p.xi[1] == pytest.approx(r, abs=1e-12) and p.xi3 == pytest.approx(g, abs=1e-12)


@pytest.mark.parametrize("hand,flank_of,side", COMBOS, ids=IDS)
def test_plain_helicoid_has_no_radial_normal(hand, flank_of, side):
    """flank_angle 0 (a square thread's flank): c = 0 and n = +-(h e_phi - r e_z) / W."""
    s = Helicoid(P, 0.0, D2, hand=hand, flank_of=flank_of, side=side)
    assert s.flank_slope == 0.0
    for phi, r in ((0.0, R2), (2.0, 0.6 * R2), (-8.0, 1.3 * R2)):
        g = s.at((phi, r))
        er, _, _ = _cyl(phi)
        assert abs(g.n @ er) < 1e-15
        np.testing.assert_allclose(g.n, _exact(*_spec(hand, flank_of, side, beta=0.0), phi, r)[1], atol=1e-15)


@pytest.mark.parametrize("flank_of", ["nut", "bolt"])
@pytest.mark.parametrize("side", ["forward", "backward"])
def test_vanishing_pitch_is_the_cone(flank_of, side):
    """P -> 0: the flank z = c (r - r2) is the cone r = r2 + z / c, half angle atan(1 / c) (a Cone of
    exu_aniso, chart (phi, z)); the normals agree to O(h / r) and the mean curvature to O(h^2 / r^2):
    with P = 1e-9 m, h / r ~ 4e-8. On either side a nut's flank faces the axis (the inside of that
    cone: the bolt lies inside the nut) and a bolt's flank faces away from it."""
    cone_side = "inside" if flank_of == "nut" else "outside"
    s = Helicoid(1e-9, BETA, D2, flank_of=flank_of, side=side)
    c = s.flank_slope
    cone = Cone(math.atan(1.0 / c), R2, side=cone_side)
    for phi, r in ((0.3, 0.8 * R2), (-1.0, 1.2 * R2)):
        g, k = s.at((phi, r)), cone.at((phi, c * (r - R2)))
        np.testing.assert_allclose(g.point, k.point, atol=1e-9)
        np.testing.assert_allclose(g.n, k.n, atol=1e-7)
        H, Hc = 0.5 * np.trace(g.m_inv @ g.h), 0.5 * np.trace(k.m_inv @ k.h)
        assert H == pytest.approx(Hc, rel=1e-9)


def test_the_axis_lies_on_the_continued_chart():
    """The chart continues through the axis (rho(phi, 0) = (0, 0, h phi - c r2), regular there:
    |rho_1 x rho_2| >= |h|), so a point on the axis projects with gap 0 to r = 0, at
    phi = (z + c r2) / h, on the boundary of limits; the flank of a real thread ends far off the axis
    (at its minor diameter)."""
    s = Helicoid(P, BETA, D2)
    h, c = s.lead_per_radian, s.flank_slope
    assert s.limits == ((-math.inf, math.inf), (0.0, math.inf))
    for z in (0.0, 3e-4, -5e-4):
        p = s.project((0.0, 0.0, z))
        assert p.xi3 == pytest.approx(0.0, abs=1e-15) and p.xi[1] == pytest.approx(0.0, abs=1e-15)
        assert p.xi[0] == pytest.approx((z + c * R2) / h, abs=1e-10)


def test_phi_is_not_periodic_and_repr_lists_the_arguments():
    s = Helicoid(P, BETA, D2, axis_point=(1, 2, 3), hand="left", flank_of="bolt", side="backward")
    assert s.periods == (0.0, 0.0)
    assert s.increment((0.0, R2), (2 * math.pi + 0.1, R2))[0] == pytest.approx(2 * math.pi + 0.1)
    text = repr(s)
    for part in ("Helicoid(pitch=0.0015", "flank_angle=1.047", "pitch_diameter=0.009026",
                 "axis_point=[1.0, 2.0, 3.0]", "axis_direction=[0.0, 0.0, 1.0]", "hand='left'",
                 "flank_of='bolt'", "side='backward'"):
        assert part in text
    assert (s.pitch, s.flank_angle, s.pitch_diameter) == (P, BETA, D2)
    assert (s.hand, s.flank_of, s.side) == ("left", "bolt", "backward")
    with pytest.raises(ValueError, match="r must be > 0"):
        s.lead_angle(0.0)
