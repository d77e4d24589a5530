"""User surfaces (SurfaceOfRevolution, ParametricSurface) against oracles that are not the module
itself: finite differences of the chart, projection round trips on both sides, textbook curvature of
surfaces of revolution and of graphs, the built-in Sphere, Cone and Torus in the same or another
chart (covariance: gap, normal, closest point, Gaussian curvature, parallel transport along the same
physical path), the compiled path against the plain Python fallback, Newton's iterates from a hint,
and the clear errors."""
from __future__ import annotations

import math
import pickle

import numpy as np
import pytest
from numba import njit

from exu_aniso.geometry import Cone, ParametricSurface, Sphere, SurfaceOfRevolution, Torus

RNG = np.random.default_rng(11)
TWO_PI = 2 * math.pi
R_SPHERE = 0.7


# --- user functions -----------------------------------------------------------------------------

def sphere_profile(z):
    r = math.sqrt(R_SPHERE * R_SPHERE - z * z)
    return r, -z / r, -R_SPHERE * R_SPHERE / r ** 3


def wavy_profile(z):
    return 0.5 + 0.1 * math.sin(3 * z), 0.3 * math.cos(3 * z), -0.9 * math.sin(3 * z)


def cone_profile(z):                 # Cone(half_angle=0.3, radius=0.5)
    return 0.5 + math.tan(0.3) * z, math.tan(0.3), 0.0


SIZES = {"R": 0.7}


def sphere_profile_dict(z):          # a dict lookup: numba cannot compile it
    R = SIZES["R"]
    r = math.sqrt(R * R - z * z)
    return r, -z / r, -R * R / r ** 3


def torus_point(phi, psi):
    R, a = 1.0, 0.3
    cf, sf, cs, ss = math.cos(phi), math.sin(phi), math.cos(psi), math.sin(psi)
    w = R + a * cs
    x = np.array([w * cf, w * sf, a * ss])
    dx = np.array([[-w * sf, w * cf, 0.0], [-a * ss * cf, -a * ss * sf, a * cs]])
    ddx = np.array([[[-w * cf, -w * sf, 0.0], [a * ss * sf, -a * ss * cf, 0.0]],
                    [[a * ss * sf, -a * ss * cf, 0.0], [-a * cs * cf, -a * cs * sf, -a * ss]]])
    return x, dx, ddx


class TorusSizes:                    # a Python class instance: numba cannot compile its use
    major, minor = 1.0, 0.3


TORUS_SIZES = TorusSizes()


def torus_point_class(phi, psi):
    R, a = TORUS_SIZES.major, TORUS_SIZES.minor
    cf, sf, cs, ss = math.cos(phi), math.sin(phi), math.cos(psi), math.sin(psi)
    w = R + a * cs
    return ([w * cf, w * sf, a * ss],
            [[-w * sf, w * cf, 0.0], [-a * ss * cf, -a * ss * sf, a * cs]],
            [[[-w * cf, -w * sf, 0.0], [a * ss * sf, -a * ss * cf, 0.0]],
             [[a * ss * sf, -a * ss * cf, 0.0], [-a * cs * cf, -a * cs * sf, -a * ss]]])


@njit(cache=True)       # a helper of a compiled user function must be a numba function itself
def _g(x, y):
    """The graph z = g(x, y) = 0.2 sin x cos y with its derivatives g_x, g_y, g_xx, g_xy, g_yy."""
    s, c, sy, cy = math.sin(x), math.cos(x), math.sin(y), math.cos(y)
    return 0.2 * s * cy, 0.2 * c * cy, -0.2 * s * sy, -0.2 * s * cy, -0.2 * c * sy, -0.2 * s * cy


def skew_graph_point(u, v):
    """The graph of g in the skew chart (x, y) = (u + 0.3 v, v): m_12 != 0."""
    x, y = u + 0.3 * v, v
    g, gx, gy, gxx, gxy, gyy = _g(x, y)
    d1 = (1.0, 0.0, gx)
    d2 = (0.3, 1.0, 0.3 * gx + gy)
    d11 = (0.0, 0.0, gxx)
    d12 = (0.0, 0.0, 0.3 * gxx + gxy)
    d22 = (0.0, 0.0, 0.09 * gxx + 0.6 * gxy + gyy)
    return np.array([x, y, g]), np.array([d1, d2]), np.array([[d11, d12], [d12, d22]])


BOUNDS_TORUS = ((-math.pi, math.pi), (-math.pi, math.pi))

# surfaces with the part of the chart where the tests draw coordinates (away from poles and axes)
SURFACES = [
    (SurfaceOfRevolution(sphere_profile), [(-3, 3), (-0.5, 0.5)]),
    (SurfaceOfRevolution(wavy_profile, axis_point=(0.1, -0.2, 0.3), axis_direction=(1, 2, 2), side="inside"),
     [(-3, 3), (-1, 1)]),
    (SurfaceOfRevolution(sphere_profile_dict, side="inside"), [(-3, 3), (-0.5, 0.5)]),
    (ParametricSurface(torus_point, periods=(TWO_PI, TWO_PI), bounds=BOUNDS_TORUS), [(-3, 3), (-3, 3)]),
    (ParametricSurface(torus_point_class, side="back", periods=(TWO_PI, TWO_PI), bounds=BOUNDS_TORUS),
     [(-3, 3), (-3, 3)]),
    (ParametricSurface(skew_graph_point, bounds=((-2, 2), (-2, 2))), [(-1, 1), (-1, 1)]),
]
IDS = [f"{s!r}-{'compiled' if s.compiled else 'python'}" for s, _ in SURFACES]
REV_SPHERE, REV_WAVY, REV_SPHERE_PY, PAR_TORUS, PAR_TORUS_PY, PAR_GRAPH = (s for s, _ in SURFACES)


def _draw(box, n=5):
    return [np.array([RNG.uniform(*box[0]), RNG.uniform(*box[1])]) for _ in range(n)]


def _chart(s, xi):
    return [np.array(v) for v in s.protocol.chart(s.params, float(xi[0]), float(xi[1]))]


def test_compiled_where_numba_can_and_python_where_it_cannot():
    assert REV_SPHERE.compiled and REV_WAVY.compiled and PAR_TORUS.compiled and PAR_GRAPH.compiled
    assert REV_SPHERE.compile_error is None
    assert not REV_SPHERE_PY.compiled and "SIZES" in REV_SPHERE_PY.compile_error
    assert not PAR_TORUS_PY.compiled and "TORUS_SIZES" in PAR_TORUS_PY.compile_error


@pytest.mark.parametrize("s,box", SURFACES, ids=IDS)
def test_chart_derivatives_equal_finite_differences(s, box):
    from test_geometry_protocol import check_chart_derivatives
    for xi in _draw(box):
        check_chart_derivatives(lambda q: _chart(s, q), xi)


@pytest.mark.parametrize("s,box", SURFACES, ids=IDS)
def test_projection_round_trip_on_both_sides(s, box):
    """rho(xi) + xi3 n projects back to (xi, xi3) for xi3 of either sign (slave on either side),
    without a hint (revolution: Newton from the point's z; parametric: start search over the
    bounds) and with the hint of a nearby earlier projection."""
    for xi in _draw(box):
        g = s.at(xi)
        for xi3 in (-0.06, 0.0, 0.05):
            x = g.point + xi3 * g.n
            for hint in (None, xi + 0.05):
                p = s.project(x, hint=hint)
                assert np.all(np.abs(s.increment(xi, p.xi)) < 1e-10), (xi, p.xi, hint)
                assert p.xi3 == pytest.approx(xi3, abs=1e-12)
                np.testing.assert_allclose(p.n, g.n, atol=1e-12)


@pytest.mark.parametrize("s", [REV_SPHERE, REV_WAVY, REV_SPHERE_PY], ids=repr)
def test_revolution_curvature_is_the_textbook_one(s):
    """K = -r'' / (r (1 + r'^2)^2), H = -(1 / (r sqrt(1 + r'^2)) - r'' / (1 + r'^2)^1.5) / 2 on the
    outside (the sign of H turns with the side)."""
    side = 1.0 if s.side == "outside" else -1.0
    for phi, z in _draw([(-3, 3), (-0.5, 0.5)]):
        r, dr, ddr = s.profile(z)
        q = 1.0 + dr * dr
        g = s.at((phi, z))
        K = np.linalg.det(g.h) / np.linalg.det(g.m)
        H = 0.5 * np.trace(g.m_inv @ g.h)
        assert K == pytest.approx(-ddr / (r * q * q), rel=1e-12)
        assert H == pytest.approx(-0.5 * side * (1 / (r * math.sqrt(q)) - ddr / q ** 1.5), rel=1e-12)


def test_graph_curvature_does_not_depend_on_the_skew_chart():
    """The graph z = g(x, y) in the skew chart (m_12 != 0): K and H equal the graph's formulas in
    (x, y), with the normal (-g_x, -g_y, 1) / |.| of side "front"."""
    for u, v in _draw([(-1, 1), (-1, 1)]):
        _, gx, gy, gxx, gxy, gyy = _g(u + 0.3 * v, v)
        w = 1.0 + gx * gx + gy * gy
        g = PAR_GRAPH.at((u, v))
        np.testing.assert_allclose(g.n, np.array([-gx, -gy, 1.0]) / math.sqrt(w), atol=1e-14)
        assert abs(g.m[0, 1]) > 0.1
        K = np.linalg.det(g.h) / np.linalg.det(g.m)
        H = 0.5 * np.trace(g.m_inv @ g.h)
        assert K == pytest.approx((gxx * gyy - gxy * gxy) / w ** 2, abs=1e-13)
        H0 = ((1 + gy * gy) * gxx - 2 * gx * gy * gxy + (1 + gx * gx) * gyy) / (2 * w ** 1.5)
        assert H == pytest.approx(H0, abs=1e-13)


# --- covariance: the same surface in another description ----------------------------------------

def _sphere_points(center, axis, n=8):
    """Points 0.3 R to 1.5 R from the centre at latitudes up to asin(0.6). Closer to the poles the
    chart (phi, z) of a sphere degenerates (dr/dz -> infinity) and Newton in z from the equator or
    from the point's own z overshoots past the pole (out of the profile's domain: a clear error)."""
    out = []
    while len(out) < n:
        d = RNG.normal(size=3)
        d /= np.linalg.norm(d)
        if abs(d @ axis) <= 0.6:
            out.append(np.array(center) + RNG.uniform(0.3, 1.5) * R_SPHERE * d)
    return out


def _sphere_pair(side):
    frame = dict(axis_direction=(1, 2, 2))
    return (Sphere(R_SPHERE, center=(0.1, 0.2, 0.3), side=side, **frame),
            SurfaceOfRevolution(sphere_profile, axis_point=(0.1, 0.2, 0.3), side=side, **frame))


@pytest.mark.parametrize("side", ["outside", "inside"])
def test_sphere_as_surface_of_revolution_is_the_sphere(side):
    """Sphere (phi, theta) and the surface of revolution r = sqrt(R^2 - z^2) (phi, z = R cos theta):
    the same gap, normal, closest point and Gaussian curvature 1/R^2 away from the poles."""
    sph, rev = _sphere_pair(side)
    for x in _sphere_points(sph.params.origin, sph.params.ez):
        a = sph.project(x)
        # Newton from the equator, and from the point's own z where the profile is defined there
        z = (x - sph.params.origin) @ sph.params.ez
        for p in (rev.project(x, hint=h) for h in [(0.0, 0.0)] + ([None] if abs(z) < 0.9 * R_SPHERE else [])):
            assert p.xi3 == pytest.approx(a.xi3, abs=1e-13)
            np.testing.assert_allclose(p.n, a.n, atol=1e-13)
            np.testing.assert_allclose(p.point, a.point, atol=1e-13)
            assert p.xi[0] == pytest.approx(a.xi[0], abs=1e-12)                       # the same phi
            assert p.xi[1] == pytest.approx(R_SPHERE * math.cos(a.xi[1]), abs=1e-12)  # z = R cos theta
            for g in (a, p):
                assert np.linalg.det(g.h) / np.linalg.det(g.m) == pytest.approx(1 / R_SPHERE ** 2, rel=1e-12)


def _carry(s, path, v0):
    """Carry the tangent vector v0 (master frame) along the vertices of path (chart coordinates)
    by the surface's transport; the vector at the end in the master frame."""
    g = s.at(path[0])
    t = g.m_inv @ (g.rho @ v0)
    for a, b in zip(path[:-1], path[1:]):
        t = s.transport(a, b - a, t)
    return s.at(path[-1]).rho.T @ t


def _both_paths(theta, phi, n):
    th, ph = np.linspace(*theta, n + 1), np.linspace(*phi, n + 1)
    return np.column_stack([ph, th]), np.column_stack([ph, R_SPHERE * np.cos(th)])


def test_transport_is_the_same_in_both_charts_of_the_sphere():
    """The same physical path (the same vertices, converted between the charts): along a parallel
    both transports agree to round-off (z = R cos theta is a constant rescaling there); along a
    general path they differ by the O(step^2) of the midpoint rule and converge to each other."""
    sph, rev = _sphere_pair("outside")
    g = sph.at((0.2, 1.0))
    v0 = 0.6 * g.rho[0] / np.linalg.norm(g.rho[0]) + 0.8 * g.rho[1] / np.linalg.norm(g.rho[1])
    ps, pr = _both_paths((1.0, 1.0), (0.2, 2.0), 7)
    np.testing.assert_allclose(_carry(rev, pr, v0), _carry(sph, ps, v0), atol=1e-13)
    g = sph.at((0.3, 0.9))
    v0 = g.rho[1] / np.linalg.norm(g.rho[1])
    errs = []
    for n in (16, 32, 64, 128):
        ps, pr = _both_paths((0.9, 1.6), (0.3, 1.5), n)
        errs.append(np.linalg.norm(_carry(rev, pr, v0) - _carry(sph, ps, v0)))
    orders = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert errs[-1] < 3e-6 and np.all(orders > 1.9), (errs, orders)


@pytest.mark.parametrize("side", ["outside", "inside"])
def test_cone_as_surface_of_revolution_is_the_cone(side):
    """A linear profile is the Cone in the same chart (phi, z): its closed-form projection and the
    Newton projection of the surface of revolution agree to 1e-12."""
    frame = dict(axis_point=(0.3, -0.1, 0.2), axis_direction=(0, 1, 1), side=side)
    cone, rev = Cone(0.3, 0.5, **frame), SurfaceOfRevolution(cone_profile, **frame)
    for x in np.array(frame["axis_point"]) + 0.4 * RNG.normal(size=(10, 3)):
        a, b = cone.project(x), rev.project(x)
        assert b.xi3 == pytest.approx(a.xi3, abs=1e-12)
        np.testing.assert_allclose(b.n, a.n, atol=1e-12)
        np.testing.assert_allclose(b.point, a.point, atol=1e-12)
        np.testing.assert_allclose(b.xi, a.xi, atol=1e-12)
        np.testing.assert_allclose(b.h, a.h, atol=1e-12)
        np.testing.assert_allclose(b.christoffel, a.christoffel, atol=1e-12)


@pytest.mark.parametrize("s", [PAR_TORUS, PAR_TORUS_PY], ids=lambda s: "compiled" if s.compiled else "python")
def test_torus_as_parametric_surface_is_the_torus(s):
    """torus_point gives the chart of Torus(1, 0.3) in the master frame: the same projection (start
    search over the bounds, then Newton; the torus: closed form) and the same surface quantities."""
    torus = Torus(1.0, 0.3, side="outside" if s.side == "front" else "inside")
    for x in RNG.normal(scale=0.7, size=(10, 3)):
        a = torus.project(x)
        if abs(a.xi3) > 0.25:          # within the tube's radius of it, where the closest point is unique
            continue
        b = s.project(x)
        assert np.all(np.abs(s.increment(a.xi, b.xi)) < 1e-12)
        assert b.xi3 == pytest.approx(a.xi3, abs=1e-13)
        for f in ("point", "n", "m", "h", "christoffel"):
            np.testing.assert_allclose(getattr(b, f), getattr(a, f), atol=1e-12, err_msg=f)
        t, d = np.array([0.4, -1.3]), np.array([0.2, -0.1])
        np.testing.assert_allclose(s.transport(a.xi, d, t), torus.transport(a.xi, d, t), atol=1e-12)
        np.testing.assert_allclose(s.slip(a.xi, d), torus.slip(a.xi, d), atol=1e-12)


# --- the plain Python path ----------------------------------------------------------------------

@pytest.mark.parametrize("compiled,python", [
    (REV_SPHERE, SurfaceOfRevolution(sphere_profile_dict)),
    (PAR_TORUS, ParametricSurface(torus_point_class, periods=(TWO_PI, TWO_PI), bounds=BOUNDS_TORUS)),
], ids=["revolution", "parametric"])
def test_python_path_gives_the_numbers_of_the_compiled_path(compiled, python):
    assert compiled.compiled and not python.compiled
    for x in _sphere_points((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), 5):
        a, b = compiled.project(x), python.project(x)
        assert b.xi3 == pytest.approx(a.xi3, abs=1e-12)
        for f in ("xi", "point", "n", "m", "h", "christoffel"):
            np.testing.assert_allclose(getattr(b, f), getattr(a, f), atol=1e-12, err_msg=f)
        t, d = np.array([0.4, -1.3]), np.array([0.2, -0.1])
        np.testing.assert_allclose(python.transport(a.xi, d, t), compiled.transport(a.xi, d, t), atol=1e-12)
        np.testing.assert_allclose(python.slip(a.xi, d), compiled.slip(a.xi, d), atol=1e-12)
        np.testing.assert_allclose(python.gap_and_normal(x)[1], compiled.gap_and_normal(x)[1], atol=1e-12)


def test_a_numba_function_is_used_as_it_is_and_a_surface_pickles():
    s = SurfaceOfRevolution(njit(wavy_profile))
    assert s.compiled
    x = (0.2, 0.7, 0.1)
    assert s.project(x).xi3 == pytest.approx(SurfaceOfRevolution(wavy_profile).project(x).xi3, abs=1e-15)
    t = pickle.loads(pickle.dumps(PAR_GRAPH))
    assert t.compiled and t.bounds == PAR_GRAPH.bounds
    np.testing.assert_array_equal(t.project(x).point, PAR_GRAPH.project(x).point)


# --- Newton -------------------------------------------------------------------------------------

class _Recorder:
    """Records the coordinates a user function is called with (a Python side effect: the surface
    runs in plain Python, so the calls are those of the projection itself)."""

    def __init__(self, f):
        self.f, self.calls = f, []

    def profile(self, z):
        self.calls.append(z)
        return self.f(z)

    def point(self, u, v):
        self.calls.append((u, v))
        return self.f(u, v)


def test_newton_from_the_hint_converges_quadratically_in_a_few_iterations():
    """Revolution: the projection of a point 0.02 away from the last one, from the last one's z,
    takes at most 4 iterations, each error about the square of the one before. Parametric: the
    same from the hint in at most 5."""
    rec = _Recorder(wavy_profile)
    s = SurfaceOfRevolution(rec.profile)
    assert not s.compiled
    x = np.array([0.45, 0.3, 0.2])
    p0 = s.project(x)
    rec.calls.clear()
    p1 = s.project(x + [0.01, -0.01, 0.01], hint=p0.xi)
    iterates = rec.calls[:-2]                 # then the final chart and Surface.at
    z = p1.xi[1]
    errs = [abs(c - z) for c in iterates]
    assert 2 <= len(iterates) <= 5, errs
    for e0, e1 in zip(errs[:-1], errs[1:]):
        assert e1 <= 10 * e0 * e0 + 1e-15, errs

    rec = _Recorder(torus_point)
    s = ParametricSurface(rec.point, periods=(TWO_PI, TWO_PI))
    assert not s.compiled
    y = np.array([0.9, 0.6, 0.25])
    hint = Torus(1.0, 0.3).project(y - [0.01, 0.02, 0.0]).xi
    rec.calls.clear()
    p = s.project(y, hint=hint)
    errs = [np.abs(np.subtract(c, p.xi)).max() for c in rec.calls[:-2]]
    assert 2 <= len(errs) <= 5, errs
    for e0, e1 in zip(errs[:-1], errs[1:]):
        assert e1 <= 10 * e0 * e0 + 1e-15, errs
    assert p.xi3 == pytest.approx(Torus(1.0, 0.3).project(y).xi3, abs=1e-14)


# --- errors -------------------------------------------------------------------------------------

@pytest.mark.parametrize("s,x", [
    (REV_SPHERE, (0.0, 0.0, 0.0)),           # the centre of the sphere: on the axis
    (REV_SPHERE_PY, (0.0, 0.0, 0.1)),
    (REV_WAVY, (0.1, -0.2, 0.3)),            # on its (tilted) axis
    (PAR_TORUS, (1.0, 0.0, 0.0)),            # on the torus's centre circle
    (PAR_TORUS_PY, (0.0, -1.0, 0.0)),
])
def test_a_point_at_a_centre_of_curvature_is_a_clear_error(s, x):
    with pytest.raises(ValueError, match="centre of curvature"):
        s.project(x)
    xi3, n = s.gap_and_normal(x)
    assert math.isfinite(xi3) and np.all(np.isnan(n))


def _bad_two(z):
    return 1.0, 0.0


def _bad_nan(z):
    return math.nan, 0.0, 0.0


def _bad_four(z):
    return 1.0, 0.0, 0.0, 0.0


def _bad_raises(z):
    if z > 0.5:
        raise ZeroDivisionError("no")
    return 1.0, 0.0, 0.0


def _bad_shape(u, v):
    return np.zeros(3), np.zeros((3, 2)), np.zeros((2, 2, 3))


@pytest.mark.parametrize("make,x,hint,match", [
    (lambda: SurfaceOfRevolution(sphere_profile), (0.1, 0.0, 0.9), None, "profile"),       # r^2 < 0 (pole)
    (lambda: SurfaceOfRevolution(sphere_profile_dict), (0.1, 0.0, 0.9), None, "profile"),  # math domain error
    (lambda: SurfaceOfRevolution(_bad_two), (1.0, 0.0, 0.0), None, "profile"),
    (lambda: SurfaceOfRevolution(_bad_nan), (1.0, 0.0, 0.0), None, "profile"),
    (lambda: SurfaceOfRevolution(_bad_four), (1.0, 0.0, 0.0), None, "profile"),
    (lambda: SurfaceOfRevolution(_bad_raises), (1.0, 0.0, 0.7), None, "profile"),
    (lambda: SurfaceOfRevolution(lambda z: (0.5 - z, -1.0, 0.0)), (0.1, 0.0, 0.8), None, "profile"),   # r < 0
    (lambda: ParametricSurface(_bad_shape), (0.0, 0.0, 1.0), (0.0, 0.0), "point"),
    (lambda: ParametricSurface(torus_point), (1.0, 0.0, 0.5), None, "needs a hint"),
])
def test_a_bad_user_function_is_a_clear_error_at_the_query(make, x, hint, match):
    with pytest.raises(ValueError, match=match):
        make().project(x, hint=hint)


@pytest.mark.parametrize("bad,error,match", [
    (lambda: SurfaceOfRevolution(1.0), TypeError, "profile must be a function"),
    (lambda: SurfaceOfRevolution(wavy_profile, side="front"), ValueError,
     "side must be 'outside' or 'inside'"),
    (lambda: SurfaceOfRevolution(wavy_profile, axis_direction=(0, 0, 0)), ValueError, "axis_direction"),
    (lambda: ParametricSurface("x"), TypeError, "point must be a function"),
    (lambda: ParametricSurface(torus_point, side="outside"), ValueError, "side must be 'front' or 'back'"),
    (lambda: ParametricSurface(torus_point, periods=(-1.0, 0.0)), ValueError, "periods"),
    (lambda: ParametricSurface(torus_point, periods=3.0), ValueError, "periods"),
    (lambda: ParametricSurface(torus_point, bounds=((1, 0), (0, 1))), ValueError, "bounds"),
    (lambda: ParametricSurface(torus_point, bounds=(0, 1)), ValueError, "bounds"),
])
def test_bad_arguments_name_the_parameter(bad, error, match):
    with pytest.raises(error, match=match):
        bad()
