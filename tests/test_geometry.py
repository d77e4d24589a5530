"""Surfaces (closest point projection, wrap-around, transport) and tensor fields (papers' formulas)."""
import math

import numpy as np
import pytest

from exu_aniso import Adhesion, Friction
from exu_aniso.surfaces import Cylinder, Plane  # the transport kernel's surfaces
from exu_aniso.surfaces import wrap_angle

SURFACES = [Plane("cartesian"), Plane("polar"),
            Cylinder(0.2, axis_point=(0.1, -0.3, 0.5), axis_direction=(0.3, -0.2, 1.0), side="inside"),
            Cylinder(0.2, axis_point=(0.1, -0.3, 0.5), axis_direction=(1.0, 0.2, 0.1), side="outside")]


def sample_points(surface, rng, k=20):
    if surface.kind == "plane":
        return np.c_[rng.uniform(-2, 2, (k, 2)), rng.uniform(-0.1, 0.1, k)]
    loc = np.c_[0.2 * rng.uniform(0.5, 1.5, k) * np.cos(rng.uniform(-4, 4, k)), np.zeros(k), rng.uniform(-1, 1, k)]
    ang = rng.uniform(-4, 4, k)
    loc[:, 1] = loc[:, 0] * np.sin(ang)
    loc[:, 0] = loc[:, 0] * np.cos(ang)
    return loc @ surface.axes + surface.axis_point


@pytest.mark.parametrize("surface", SURFACES, ids=repr)
def test_projection_reconstructs_the_point(surface):
    rng = np.random.default_rng(0)
    for x in sample_points(surface, rng):
        p = surface.project(x)
        np.testing.assert_allclose(p.point + p.xi3 * p.n, x, atol=1e-12)
        assert np.allclose(p.rho @ p.n, 0.0, atol=1e-12) and abs(np.linalg.norm(p.n) - 1) < 1e-14
        np.testing.assert_allclose(p.m, p.rho @ p.rho.T, atol=1e-14)
        np.testing.assert_allclose(p.m @ p.m_inv, np.eye(2), atol=1e-12)
        np.testing.assert_allclose(p.h, p.rho2 @ p.n, atol=1e-14)


@pytest.mark.parametrize("surface", SURFACES, ids=repr)
def test_projection_derivative_uses_metric_and_curvature(surface):
    """d xi / d x = (m - xi3 h)^-1 rho (closest point condition), checked by differences: this
    pins rho_i, m and h together (h_11 = +R inside, -R outside on the cylinder)."""
    rng = np.random.default_rng(1)
    angle = 0 if surface.kind == "cylinder" else (1 if surface.coordinates == "polar" else None)
    for x in sample_points(surface, rng, 5):
        p = surface.project(x)
        J = np.linalg.solve(p.m - p.xi3 * p.h, p.rho)
        for j in range(3):
            e = np.zeros(3)
            e[j] = 1e-6
            d = surface.project(x + e).xi - surface.project(x - e).xi
            if angle is not None:
                d[angle] = wrap_angle(d[angle])
            d /= 2e-6
            np.testing.assert_allclose(d, J[:, j], atol=1e-6 * np.abs(J).max())
    if surface.kind == "cylinder":
        h11 = surface.project(sample_points(surface, rng, 1)[0]).h[0, 0]
        assert h11 == pytest.approx(surface.radius if surface.side == "inside" else -surface.radius)


def test_cylinder_gap_sign_and_normal():
    hole = Cylinder(1.0)
    p = hole.project([1.1, 0.0, 0.3])
    assert p.xi3 == pytest.approx(-0.1) and np.allclose(p.n, [-1, 0, 0])     # inside: n towards the axis
    shaft = Cylinder(1.0, side="outside")
    p = shaft.project([0.9, 0.0, 0.3])
    assert p.xi3 == pytest.approx(-0.1) and np.allclose(p.n, [1, 0, 0])


def test_wraparound_increments_are_small():
    cyl = Cylinder(0.5)
    u_old = np.array([[math.pi - 0.01, 0.0]])
    u_new = np.array([[-math.pi + 0.02, 0.1]])
    np.testing.assert_allclose(cyl.increment(u_new, u_old), [[0.5 * 0.03, 0.1]], atol=1e-12)
    assert cyl.continue_coordinates(u_new, u_old)[0, 0] == pytest.approx(math.pi + 0.02)
    x = np.array([[-0.5, 1e-9, 0.0], [-0.5, -1e-9, 0.0]])
    u = cyl.frame(x).u
    assert abs(cyl.increment(u[1:], u[:1])[0, 0]) < 1e-8


def test_many_revolutions_are_counted():
    cyl = Cylinder(0.5)
    u = np.array([[0.0, 0.0]])
    for phi in np.linspace(0, 20 * math.pi, 2001)[1:]:
        u = cyl.continue_coordinates(np.array([[wrap_angle(phi), 0.0]]), u)
    assert u[0, 0] == pytest.approx(20 * math.pi, rel=1e-12)


def test_constant_component_transport_on_cylinder_has_no_drift():
    """A tangent vector carried once around the cylinder in 1000 steps, both by keeping its
    (e_phi, e_z) components (transport route) and by rotating the 3D vector (chart route)."""
    cyl = Cylinder(0.3, axis_direction=(0.2, 0.1, 1.0))
    xi = np.array([0.4, 0.1])
    p0 = cyl.at(xi)
    vec0 = 2.0 * p0.rho[0] / cyl.radius - 0.7 * p0.rho[1]
    vec = vec0.copy()
    for phi in 0.4 + np.linspace(0, 2 * math.pi, 1001)[1:]:
        new = np.array([wrap_angle(phi), 0.1])
        vec = cyl.transport_vector(vec, xi, new)
        xi = new
        comps = cyl.at(xi).rho @ vec / np.array([cyl.radius**2, 1.0]) * np.array([cyl.radius, 1.0])
        np.testing.assert_allclose(comps, [2.0, -0.7], atol=1e-12)
    np.testing.assert_allclose(vec, vec0, atol=1e-12)


def test_singular_points_raise_clear_errors():
    with pytest.raises(ValueError, match="polar origin"):
        Plane("polar").project([0.0, 0.0, -0.1])
    with pytest.raises(ValueError, match="cylinder axis"):
        Cylinder(1.0).project([0.0, 0.0, 2.0])
    with pytest.raises(ValueError, match="cylinder axis"):
        Cylinder(1.0, side="outside").frame(np.array([[0.0, 0.0, 2.0]]))
    assert Cylinder(1.0).gap(np.array([[0.0, 0.0, 2.0]]))[0] == 1.0   # the gap itself is defined


# ---------------------------------------------------------------------------------------------
# fields

def test_polar_adhesion_matches_papers_eq8_in_cartesian_and_is_diagonal_in_polar():
    er, ephi = 3e4, 5e2
    field = Adhesion.polar(er, ephi)
    for x, y in [(0.3, 0.4), (-1.0, 0.2), (0.0, -2.0)]:
        B = field.components(Plane("cartesian"), (x, y))
        ref = -1 / (x * x + y * y) * np.array([[er * x * x + ephi * y * y, (er - ephi) * x * y],
                                               [(er - ephi) * x * y, er * y * y + ephi * x * x]])
        np.testing.assert_allclose(B, ref, rtol=1e-13)
        r = math.hypot(x, y)
        np.testing.assert_allclose(field.components(Plane("polar"), (r, math.atan2(y, x))),
                                   np.diag([-er, -ephi * r * r]), rtol=1e-12, atol=1e-9)


def test_polar_friction_contravariant_components():
    F = Friction.polar(0.2, 0.5).components(Plane("polar"), (2.0, 0.3))
    np.testing.assert_allclose(F, np.diag([1 / 0.2**2, 1 / (0.5**2 * 4.0)]), rtol=1e-12, atol=1e-12)


def test_spiral_components_and_pitch():
    """Paper 2, Fig. 1: B = -(eps1 e1 e1 + eps2 e2 e2), e1 = cos a e_phi + sin a e_z; in the
    (phi, z) chart b_11 carries R^2, b_12 carries R. The helix e1 advances 2 pi R tan a per turn."""
    R, a, e1, e2 = 0.01, math.radians(12.0), 1e4, 3e6
    cyl = Cylinder(R)
    b = Adhesion.spiral(e1, e2, a).components(cyl, (0.7, 0.0))
    c, s = math.cos(a), math.sin(a)
    np.testing.assert_allclose(b, -np.array([[R * R * (e1 * c * c + e2 * s * s), R * (e1 - e2) * s * c],
                                             [R * (e1 - e2) * s * c, e1 * s * s + e2 * c * c]]), rtol=1e-12)
    # the e1 direction in (phi, z): dz/dphi = R tan a
    w, v = np.linalg.eigh(-b / np.array([[R * R, R], [R, 1.0]]))
    e1_dir = v[:, np.argmin(np.abs(w - e1))]
    assert 2 * math.pi * R * e1_dir[1] / e1_dir[0] == pytest.approx(2 * math.pi * R * math.tan(a), rel=1e-10)


def test_equal_polar_values_are_isotropic():
    P, _ = Adhesion.polar(7.0, 7.0).physical(np.array([[0.3, -0.2], [5.0, 1.0]]))
    np.testing.assert_allclose(P, [[-7.0, 0.0, -7.0]] * 2, atol=1e-13)


def test_polar_core_radius_regularisation():
    """Documented regularisation: isotropic mean (eps_r + eps_phi)/2 at the origin; relative
    deviation from the exact field <= (r_c / r)^2 elsewhere."""
    f = Adhesion.polar(10.0, 2.0, core_radius=1e-3)
    P0, _ = f.physical(np.zeros((1, 2)))
    np.testing.assert_allclose(P0, [[-6.0, 0.0, -6.0]], atol=1e-13)
    exact = Adhesion.polar(10.0, 2.0)
    for r in (1e-2, 1e-1, 1.0):
        u = np.array([[r * 0.6, r * 0.8]])
        dev = np.abs(f.physical(u)[0] - exact.physical(u)[0]).max() / 10.0
        assert dev <= (1e-3 / r) ** 2
    with pytest.raises(ValueError, match="undefined at the polar origin"):
        exact.physical(np.zeros((1, 2)))


def test_polar_field_derivative():
    f = Friction.polar(0.2, 0.7, core_radius=0.05)
    u = np.array([[0.3, -0.1], [0.01, 0.02]])
    P, dP = f.physical(u)
    for j in range(2):
        e = np.zeros(2)
        e[j] = 1e-7
        d = (f.physical(u + e)[0] - f.physical(u - e)[0]) / 2e-7
        np.testing.assert_allclose(dP[:, :, j], d, rtol=1e-6, atol=1e-6 * np.abs(d).max())


def test_fields_refuse_the_wrong_surface():
    from exu_aniso import ContactLaw
    with pytest.raises(ValueError, match="polar orthotropy is defined on a Plane only"):
        ContactLaw(Cylinder(1.0), Adhesion.polar(1, 2), Friction.isotropic(0.3), 1.0)
    with pytest.raises(ValueError, match="spiral orthotropy is defined on a Cylinder only"):
        ContactLaw(Plane(), Adhesion.isotropic(1), Friction.spiral(0.1, 0.2, 0.1), 1.0)


@pytest.mark.parametrize("call, match", [
    (lambda: Adhesion.from_matrix([[-2.0, 0.5], [0.4, -1.0]]), "B must be symmetric"),
    (lambda: Adhesion.from_matrix([[-2.0, 0.0], [0.0, 1.0]]), "B must be negative definite"),
    (lambda: Adhesion.from_matrix([[2.0, 0.0], [0.0, 1.0]]), "negative definite .papers' sign"),
    (lambda: Friction.from_matrix([[1.0, 2.0], [2.0, 1.0]]), "F must be positive definite"),
    (lambda: Friction.from_matrix([[1.0, float("nan")], [0.0, 1.0]]), "F must be finite"),
    (lambda: Friction.from_matrix([[1.0, 0.0, 0.0]]), "F must be a 2x2 matrix"),
    (lambda: Adhesion.isotropic(-1.0), "stiffness must be > 0; got -1.0"),
    (lambda: Adhesion.polar(1.0, float("nan")), "eps_phi must be finite"),
    (lambda: Adhesion.polar(1.0, 1.0, core_radius=-1.0), "core_radius must be >= 0"),
    (lambda: Friction.orthotropic(0.2, 0.0), "mu_2 must be > 0"),
    (lambda: Friction.isotropic("0.3"), "mu must be a real number"),
    (lambda: Friction.spiral(0.2, 0.3, 2.0), "helix_angle must lie in"),
    (lambda: Cylinder(-1.0), "radius must be > 0"),
    (lambda: Cylinder(1.0, axis_direction=(0, 0, 0)), "axis_direction must be a non-zero vector"),
    (lambda: Cylinder(1.0, side="top"), "side must be 'inside'"),
    (lambda: Plane("spherical"), "coordinates must be 'cartesian' or 'polar'"),
])
def test_bad_input_is_named(call, match):
    with pytest.raises((ValueError, TypeError), match=match):
        call()
