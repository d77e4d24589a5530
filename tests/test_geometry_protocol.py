"""The surface protocol (exu_aniso.geometry): every surface module against oracles that do not come
from the module itself: finite differences of the chart, projection round trips, Gaussian and mean
curvature from differential geometry, limits (zero taper = cylinder), holonomy of parallel transport
around a parallel of the sphere and of the cone (with its convergence order), step independence
of the slip increment, and objectivity under a rigid motion of surface and point together."""
from __future__ import annotations

import math

import numpy as np
import pytest

from exu_aniso.geometry import Cone, Cylinder, Helicoid, Plane, Sphere, Torus
from exu_aniso.geometry import core

RNG = np.random.default_rng(7)

THREAD_BOX = [(-7, 7), (0.6 * 4.513e-3, 1.4 * 4.513e-3)]     # (phi, r) of an M10 thread's flank

# surfaces with the part of the chart where the tests draw coordinates (away from poles and axes)
SURFACES = [
    (Plane(), [(-1, 1), (-1, 1)]),
    (Plane("polar"), [(0.2, 2.0), (-3, 3)]),
    (Plane(side="back"), [(-1, 1), (-1, 1)]),
    (Cylinder(0.5, side="inside"), [(-3, 3), (-1, 1)]),
    (Cylinder(0.5, axis_point=(0.1, -0.2, 0.3), axis_direction=(1, 2, 2), side="outside"), [(-3, 3), (-1, 1)]),
    (Cone(0.3, 0.5), [(-3, 3), (-0.5, 0.5)]),
    (Cone(-0.2, 0.4, axis_direction=(0, 1, 1), side="inside"), [(-3, 3), (-0.5, 0.5)]),
    (Sphere(0.7), [(-3, 3), (0.3, 2.8)]),
    (Sphere(0.7, center=(1, 2, 3), axis_direction=(1, 0, 0), side="inside"), [(-3, 3), (0.3, 2.8)]),
    (Torus(1.0, 0.3), [(-3, 3), (-3, 3)]),
    (Torus(1.0, 0.3, axis_direction=(0, 0, -1), side="inside"), [(-3, 3), (-3, 3)]),
    # an M10 thread's flanks (P 1.5 mm, d2 9.026 mm, 60 deg) over two turns each way, r off the axis
    (Helicoid(1.5e-3, math.pi / 3, 9.026e-3), THREAD_BOX),
    (Helicoid(1.5e-3, math.pi / 3, 9.026e-3, hand="left", side="backward"), THREAD_BOX),
    (Helicoid(1.5e-3, math.pi / 3, 9.026e-3, axis_point=(0.01, -0.02, 0.03), axis_direction=(1, -2, 2),
              flank_of="bolt"), THREAD_BOX),
    (Helicoid(1.5e-3, 0.0, 9.026e-3, hand="left", flank_of="bolt", side="backward"), THREAD_BOX),  # plain
]
IDS = [repr(s) for s, _ in SURFACES]


def _draw(box, n=6):
    return [np.array([RNG.uniform(*box[0]), RNG.uniform(*box[1])]) for _ in range(n)]


def _length(s):
    """Length scale of the normal offsets of the round trip: 1 m, except the helicoid's pitch (its
    sheets lie one pitch apart axially; a point farther than about half a pitch from the flank is
    closer to the next turn)."""
    return s.pitch if isinstance(s, Helicoid) else 1.0


def _chart(s, xi):
    return [np.array(v) for v in core.chart(s.params, float(xi[0]), float(xi[1]))]


def check_chart_derivatives(chart, xi, h=1e-6):
    """rho_i and rho_ij of chart(xi) -> (rho, rho_1, rho_2, rho_11, rho_12, rho_22) against central
    differences of rho and rho_i (shared with tests/test_geometry_user_surfaces.py)."""
    r, r1, r2, r11, r12, r22 = chart(xi)
    d = [(np.array(chart(xi + h * e)) - np.array(chart(xi - h * e))) / (2 * h) for e in np.eye(2)]
    scale = 1.0 + np.abs(r).max()
    np.testing.assert_allclose(d[0][0], r1, atol=1e-8 * scale)
    np.testing.assert_allclose(d[1][0], r2, atol=1e-8 * scale)
    np.testing.assert_allclose(d[0][1], r11, atol=1e-7 * scale)
    np.testing.assert_allclose(d[1][1], r12, atol=1e-7 * scale)
    np.testing.assert_allclose(d[0][2], r12, atol=1e-7 * scale)
    np.testing.assert_allclose(d[1][2], r22, atol=1e-7 * scale)


@pytest.mark.parametrize("s,box", SURFACES, ids=IDS)
def test_chart_derivatives_equal_finite_differences(s, box):
    for xi in _draw(box):
        check_chart_derivatives(lambda q: _chart(s, q), xi)


@pytest.mark.parametrize("s,box", SURFACES, ids=IDS)
def test_projection_round_trip(s, box):
    """A point placed at rho(xi) + xi3 n (inside the curvature radius) projects back to (xi, xi3);
    periodic coordinates agree modulo their period."""
    for xi in _draw(box):
        g = s.at(xi)
        for xi3 in (-0.05 * _length(s), 0.0, 0.08 * _length(s)):
            p = s.project(g.point + xi3 * g.n)
            d = s.increment(xi, p.xi)
            assert np.all(np.abs(d) < 1e-10), (xi, p.xi)
            assert p.xi3 == pytest.approx(xi3, abs=1e-12)
            np.testing.assert_allclose(p.n, g.n, atol=1e-12)


@pytest.mark.parametrize("s,box", SURFACES, ids=IDS)
def test_gaussian_and_mean_curvature(s, box):
    """K = det h / det m and H = tr(m^-1 h) / 2 from the chart equal the textbook values of the
    surface (they do not depend on the chart); H changes sign with the side."""
    for xi in _draw(box):
        g = s.at(xi)
        K = np.linalg.det(g.h) / np.linalg.det(g.m)
        H = 0.5 * np.trace(g.m_inv @ g.h)
        side = 1.0 if getattr(s, "side", "front") in ("outside", "front", "forward") else -1.0
        if isinstance(s, Plane):
            K0, H0 = 0.0, 0.0
        elif isinstance(s, Cylinder):
            K0, H0 = 0.0, -0.5 / s.radius
        elif isinstance(s, Cone):
            r = s.radius + math.tan(s.half_angle) * xi[1]
            K0, H0 = 0.0, -0.5 * math.cos(s.half_angle) / r
        elif isinstance(s, Sphere):
            K0, H0 = 1.0 / s.radius ** 2, -1.0 / s.radius
        elif isinstance(s, Helicoid):
            # x = (r cos phi, r sin phi, h phi + c r) (the shift -c r2 changes nothing), chart (phi, r):
            # E = r^2 + h^2, F = h c, G = 1 + c^2, W^2 = E G - F^2; for the unit normal
            # N = (r c e_r + h e_phi - r e_z) / W: L = x_phiphi . N = -r^2 c / W, M = x_phir . N = h / W,
            # N_rr = 0; K = (L N_rr - M^2) / W^2, H = (E N_rr - 2 F M + G L) / (2 W^2). N points
            # backward (N_z = -r / W < 0): the forward side's normal is -N, so H0 = -H(N)
            h = (1.0 if s.hand == "right" else -1.0) * s.pitch / (2 * math.pi)
            c = (math.tan(s.flank_angle / 2) * (1.0 if s.side == "forward" else -1.0)
                 * (1.0 if s.flank_of == "nut" else -1.0))
            r = xi[1]
            E, F, G = r * r + h * h, h * c, 1.0 + c * c
            W = math.sqrt(E * G - F * F)
            L, M, N = -r * r * c / W, h / W, 0.0
            K0, H0 = (L * N - M * M) / W ** 2, -(E * N - 2 * F * M + G * L) / (2 * W ** 2)
        else:
            R, a = s.major_radius, s.minor_radius
            w = R + a * math.cos(xi[1])
            K0, H0 = math.cos(xi[1]) / (a * w), -0.5 * (1.0 / a + math.cos(xi[1]) / w)
        assert K == pytest.approx(K0, abs=1e-9 * (1 + abs(K0)))
        assert H == pytest.approx(side * H0, abs=1e-9 * (1 + abs(H0)))


def test_cone_with_zero_taper_is_the_cylinder():
    cone, cyl = Cone(0.0, 0.5, axis_direction=(1, 1, 0)), Cylinder(0.5, axis_direction=(1, 1, 0), side="outside")
    for x in RNG.normal(size=(10, 3)):
        a, b = cone.project(x), cyl.project(x)
        assert np.array_equal(a.xi, b.xi) and a.xi3 == b.xi3
        assert np.array_equal(a.n, b.n) and np.array_equal(a.h, b.h) and np.array_equal(a.christoffel, b.christoffel)


def test_large_sphere_is_locally_the_plane():
    """Near its pole a sphere of radius L looks like the plane z = L: gap and normal differ by O(1/L)."""
    x = np.array([0.1, -0.2, 0.03])
    for L in (1e2, 1e4, 1e6):
        s = Sphere(L, center=(0, 0, -L))
        p = s.project(x)
        assert abs(p.xi3 - 0.03) < 0.1 / L and np.linalg.norm(p.n - [0, 0, 1]) < 0.3 / L


@pytest.mark.parametrize("s,x,why", [
    (Cylinder(0.5), (0.0, 0.0, 0.3), "centre of curvature"),
    (Sphere(0.5), (0.0, 0.0, 0.0), "singular"),           # the centre: also the chart's pole direction
    (Sphere(0.5), (0.0, 0.0, 0.9), "chart is singular"),  # above the pole
    (Plane("polar"), (0.0, 0.0, 0.2), "chart is singular"),
    (Torus(1.0, 0.3), (1.0, 0.0, 0.0), "centre of curvature"),
])
def test_undefined_projection_is_a_clear_error(s, x, why):
    with pytest.raises(ValueError, match=why):
        s.project(x)


def _wrap(a):
    return (a + math.pi) % (2 * math.pi) - math.pi


def _loop_turn(s, xi0, d, n):
    """Carry the unit vector e_1-direction once around the closed coordinate line from xi0 with
    increment d per step (n steps); return the angle it turned against the start (orthonormal frame)."""
    g0 = s.at(xi0)
    t = g0.m_inv @ (g0.rho @ (g0.rho[0] / np.linalg.norm(g0.rho[0])))
    xi = np.array(xi0, dtype=float)
    for _ in range(n):
        t = s.transport(xi, d, t)
        xi = xi + d
    v0 = g0.rho[0] / np.linalg.norm(g0.rho[0])
    v = s.at(xi).rho.T @ t
    w = np.cross(g0.n, v0)
    return math.atan2(v @ w, v @ v0), np.linalg.norm(v)


@pytest.mark.parametrize("theta", [0.4, 1.0, 2.2])
def test_sphere_holonomy_second_order(theta):
    """A vector carried around the parallel theta turns by 2 pi (1 - cos theta) (mod 2 pi); the
    error of the midpoint transport falls at second order in the step."""
    s = Sphere(0.8)
    exact = 2 * math.pi * (1 - math.cos(theta))
    errs = []
    for n in (16, 32, 64, 128):
        turn, length = _loop_turn(s, (0.0, theta), np.array([2 * math.pi / n, 0.0]), n)
        errs.append(min(abs(_wrap(turn - sg * exact)) for sg in (1.0, -1.0)))   # orientation of the loop
        assert length == pytest.approx(1.0, abs=5e-2)
    orders = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert errs[-1] < 5e-3 and np.all(orders > 1.8), (errs, orders)


def test_cone_holonomy_is_two_pi_sin_half_angle():
    beta = 0.35
    s = Cone(beta, 0.5)
    turn, _ = _loop_turn(s, (0.0, 0.2), np.array([2 * math.pi / 256, 0.0]), 256)
    target = 2 * math.pi * math.sin(beta)
    assert min(abs(_wrap(turn - sg * target)) for sg in (1.0, -1.0)) < 1e-4


@pytest.mark.parametrize("s,box", SURFACES, ids=IDS)
def test_constant_metric_fact_matches_the_chart(s, box):
    """The compile-time fact constant_metric (the kernel then skips parallel transport) is declared
    exactly where the chart's metric is the same everywhere: every Christoffel symbol vanishes at
    every drawn point, and transport over a finite step leaves the components unchanged. A
    surface with a varying metric must not declare it (it would carry tractions wrongly)."""
    declared = core.constant_metric(s.params)
    gammas = [np.abs(np.array(core.christoffel(s.params, *map(float, xi)))).max() for xi in _draw(box)]
    metrics = [np.array(core.geometry(s.params, *map(float, xi))[4]) for xi in _draw(box)]
    constant = max(gammas) < 1e-12 and np.ptp(np.array(metrics), axis=0).max() < 1e-12
    assert declared == constant, (declared, max(gammas))
    if declared:
        t = np.array([0.3, -1.2])
        assert np.array_equal(s.transport((0.4, 0.1), (1.7, -0.9), t), t)


@pytest.mark.parametrize("s", [Plane(), Cylinder(0.5), Cylinder(0.3, axis_direction=(1, 0, 1))], ids=repr)
def test_parallel_coordinate_basis_transports_exactly(s):
    t = np.array([0.3, -1.2])
    assert np.array_equal(s.transport((0.4, 0.1), (1.7, -0.9), t), t)


def test_slip_along_a_parallel_does_not_depend_on_the_step():
    """Sliding once around the parallel theta: the midpoint slip increments add up to the length
    2 pi R sin(theta) for any step; chords would fall short by a step-dependent amount."""
    R, theta = 0.8, 1.1
    s = Sphere(R)
    for n in (3, 8, 64):
        d = np.array([2 * math.pi / n, 0.0])
        total = sum(np.linalg.norm(s.slip((k * d[0], theta), d)) for k in range(n))
        assert total == pytest.approx(2 * math.pi * R * math.sin(theta), rel=1e-13)


def test_increment_unwraps_periodic_coordinates_towards_the_prediction():
    s = Cylinder(0.5)
    assert s.increment((3.1, 0.0), (-3.1, 0.2))[0] == pytest.approx(2 * math.pi - 6.2)
    # a prediction of almost a full turn selects the long branch
    assert s.increment((0.0, 0.0), (0.1, 0.0), predicted=(2 * math.pi, 0.0))[0] == pytest.approx(0.1 + 2 * math.pi)
    assert Plane().increment((3.1, 0.0), (-3.1, 0.0))[0] == pytest.approx(-6.2)


@pytest.mark.parametrize("make", [
    lambda o, a: Cylinder(0.5, axis_point=o, axis_direction=a),
    lambda o, a: Cone(0.2, 0.5, axis_point=o, axis_direction=a),
    lambda o, a: Sphere(0.5, center=o, axis_direction=a),
    lambda o, a: Torus(1.0, 0.3, center=o, axis_direction=a),
    lambda o, a: Helicoid(0.3, math.pi / 3, 1.0, axis_point=o, axis_direction=a, hand="left"),
])
def test_objectivity_under_a_rigid_motion(make):
    """Moving surface and point together by a rigid motion changes no gap and no surface
    coordinate, and turns the normal with the motion."""
    a0, o0 = np.array([0.0, 0.0, 1.0]), np.zeros(3)
    x0 = np.array([0.2, 0.55, 0.1])
    th = 0.7
    c, sn = math.cos(th), math.sin(th)
    Q = np.array([[1, 0, 0], [0, c, -sn], [0, sn, c]])     # rotation about x: keeps the chart's e_ref
    o1 = np.array([0.3, -1.0, 2.0])
    p0 = make(o0, a0).project(x0)
    p1 = make(o1, Q @ a0).project(o1 + Q @ x0)
    assert p1.xi3 == pytest.approx(p0.xi3, abs=1e-13)
    np.testing.assert_allclose(p1.xi, p0.xi, atol=1e-12)
    np.testing.assert_allclose(p1.n, Q @ p0.n, atol=1e-12)


@pytest.mark.parametrize("bad,match", [
    (lambda: Cone(math.pi / 2, 0.5), "half_angle must lie in"),
    (lambda: Torus(0.3, 0.5), "minor_radius must be < major_radius"),
    (lambda: Sphere(-1.0), "radius must be > 0"),
    (lambda: Sphere(1.0, side="front"), "side must be 'outside' or 'inside'"),
    (lambda: Plane(side="outside"), "side must be 'front' or 'back'"),
    (lambda: Cylinder(1.0, axis_direction=(0, 0, 0)), "axis_direction must be a non-zero vector"),
    (lambda: Torus(1.0, 0.2, center=(0, math.nan, 0)), "center"),
    (lambda: Helicoid(0.0, 1.0, 0.01), "pitch must be > 0"),
    (lambda: Helicoid(-1e-3, 1.0, 0.01), "pitch must be > 0"),
    (lambda: Helicoid(1e-3, math.pi, 0.01), r"flank_angle must lie in \[0, pi\)"),
    (lambda: Helicoid(1e-3, -0.1, 0.01), r"flank_angle must lie in \[0, pi\)"),
    (lambda: Helicoid(1e-3, 1.0, 0.0), "pitch_diameter must be > 0"),
    (lambda: Helicoid(1e-3, 1.0, 0.01, hand="up"), "hand must be 'right' or 'left'"),
    (lambda: Helicoid(1e-3, 1.0, 0.01, side="outside"), "side must be 'forward' or 'backward'"),
    (lambda: Helicoid(1e-3, 1.0, 0.01, flank_of="screw"), "flank_of must be 'nut' or 'bolt'"),
])
def test_bad_arguments_name_the_parameter(bad, match):
    with pytest.raises(ValueError, match=match):
        bad()
