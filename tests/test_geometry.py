"""Plane and cylinder of the surface protocol against oracles of their own (closest point projection
reconstructing the point, its derivative from metric and curvature, gap sign and normal, revolutions
counted across the chart's seam by the contact history) and the tensor fields as nets (papers'
formulas in the orthonormal tangent frame: polar eq. 8 in both charts of the plane, the spiral's
pitch on the cylinder and lead on the cone, the polar core). Chart derivatives, round trips from the
chart, curvature, transport and increment unwrapping: tests/test_geometry_protocol.py."""
import math

import numpy as np
import pytest

from exu_aniso import Adhesion, ContactLaw, Friction
from exu_aniso.law.history import SLIP, UNRESOLVED
from exu_aniso.geometry import Cone, Cylinder, Plane, Sphere, core

SURFACES = [Plane("cartesian"), Plane("polar"), Plane(side="back"),
            Cylinder(0.2, axis_point=(0.1, -0.3, 0.5), axis_direction=(0.3, -0.2, 1.0), side="inside"),
            Cylinder(0.2, axis_point=(0.1, -0.3, 0.5), axis_direction=(1.0, 0.2, 0.1), side="outside")]


def sample_points(surface, rng, k=20):
    """Points around the surface: on both sides of the plane, at 0.5 to 1.5 R from the cylinder axis."""
    if isinstance(surface, Plane):
        return np.c_[rng.uniform(-2, 2, (k, 2)), rng.uniform(-0.1, 0.1, k)]
    rad, ang = 0.2 * rng.uniform(0.5, 1.5, k), rng.uniform(-4, 4, k)
    loc = np.c_[rad * np.cos(ang), rad * np.sin(ang), rng.uniform(-1, 1, k)]
    return loc @ surface.axes + surface.axis_point


@pytest.mark.parametrize("surface", SURFACES, ids=repr)
def test_projection_reconstructs_the_point(surface):
    """x = rho(xi) + xi3 n for any point x; n unit and normal to rho_i; m = rho rho^T and its
    inverse; h_ij = rho_ij . n from the chart's second derivatives."""
    rng = np.random.default_rng(0)
    for x in sample_points(surface, rng):
        p = surface.project(x)
        np.testing.assert_allclose(p.point + p.xi3 * p.n, x, atol=1e-12)
        assert np.allclose(p.rho @ p.n, 0.0, atol=1e-12) and abs(np.linalg.norm(p.n) - 1) < 1e-14
        np.testing.assert_allclose(p.m, p.rho @ p.rho.T, atol=1e-14)
        np.testing.assert_allclose(p.m @ p.m_inv, np.eye(2), atol=1e-12)
        _, _, _, r11, r12, r22 = map(np.array, core.chart(surface.params, *map(float, p.xi)))
        rho2 = np.array([[r11, r12], [r12, r22]])
        np.testing.assert_allclose(p.h, rho2 @ p.n, atol=1e-14)


@pytest.mark.parametrize("surface", SURFACES, ids=repr)
def test_projection_derivative_uses_metric_and_curvature(surface):
    """d xi / d x = (m - xi3 h)^-1 rho (closest point condition), checked by differences (periodic
    coordinates through surface.increment): this pins rho_i, m and h together (h_11 = +R inside,
    -R outside on the cylinder)."""
    rng = np.random.default_rng(1)
    for x in sample_points(surface, rng, 5):
        p = surface.project(x)
        J = np.linalg.solve(p.m - p.xi3 * p.h, p.rho)
        for j in range(3):
            e = np.zeros(3)
            e[j] = 1e-6
            d = surface.increment(surface.project(x - e).xi, surface.project(x + e).xi) / 2e-6
            np.testing.assert_allclose(d, J[:, j], atol=1e-6 * np.abs(J).max())
    if isinstance(surface, Cylinder):
        h11 = surface.project(sample_points(surface, rng, 1)[0]).h[0, 0]
        assert h11 == pytest.approx(surface.radius if surface.side == "inside" else -surface.radius)


def test_cylinder_gap_sign_and_normal():
    hole = Cylinder(1.0)
    p = hole.project([1.1, 0.0, 0.3])
    assert p.xi3 == pytest.approx(-0.1) and np.allclose(p.n, [-1, 0, 0])     # inside: n towards the axis
    shaft = Cylinder(1.0, side="outside")
    p = shaft.project([0.9, 0.0, 0.3])
    assert p.xi3 == pytest.approx(-0.1) and np.allclose(p.n, [1, 0, 0])


def test_the_gap_on_the_axis_is_defined_and_the_normal_is_not():
    """On the axis every phi is equally close: project raises, but the gap is R (hole: open) or -R
    (shaft: inside it) and the normal NaN, also through ContactLaw.gap_and_normal."""
    for side, gap in (("inside", 1.0), ("outside", -1.0)):
        g, n = Cylinder(1.0, side=side).gap_and_normal([0.0, 0.0, 2.0])
        assert g == gap and np.all(np.isnan(n))
    law = ContactLaw(Cylinder(1.0), Adhesion.isotropic(1.0), Friction.isotropic(0.3), 1.0)
    g, n = law.gap_and_normal([[0.0, 0.0, 2.0], [0.5, 0.0, 0.0], [1.5, 0.0, 0.0]])
    np.testing.assert_allclose(g, [1.0, 0.5, -0.5], atol=1e-15)
    assert np.all(np.isnan(n[:2])) and np.allclose(n[2], [-1.0, 0.0, 0.0])   # normal only in contact


def test_many_revolutions_are_counted():
    """Ten turns about the cylinder in steps of 0.01 rad: the increments between successive
    projections (wrapped at phi = +-pi by atan2) add up to 20 pi, and the contact history's anchor,
    unwrapped across the seam, counts the revolutions."""
    cyl = Cylinder(0.5)
    phis = np.linspace(0.0, 20 * math.pi, 6284)
    xs = np.c_[0.501 * np.cos(phis), 0.501 * np.sin(phis), np.zeros_like(phis)]
    total, xi = 0.0, cyl.project(xs[0]).xi
    for x in xs[1:]:
        new = cyl.project(x).xi
        assert -math.pi <= new[0] <= math.pi
        total += cyl.increment(xi, new)[0]
        xi = new
    assert total == pytest.approx(20 * math.pi, rel=1e-12)
    law = ContactLaw(cyl, Adhesion.isotropic(1e3), Friction.isotropic(0.3), 1e5)
    H = law.initial_history(1)
    for x in xs:
        H = law.evaluate(x[None, :], None, H, tangent=False).history
    assert H[0, 4] == 1.0 and H[0, 2] == pytest.approx(20 * math.pi, rel=1e-12)


def test_more_than_half_a_turn_per_step_is_resolved_by_the_velocity():
    """The branch of the periodic coordinate comes from the prediction v dt (ContactLaw.evaluate):
    0.7 turn in one step with the velocity of that turn advances the anchor by 0.7 turn; without a
    prediction the nearest branch (-0.3 turn) is a quarter period or more away from it: the step is
    UNRESOLVED (the engine must refine it)."""
    R, dist, dt = 0.5, 0.501, 1e-3
    cyl = Cylinder(R)
    law = ContactLaw(cyl, Adhesion.isotropic(1e3), Friction.isotropic(0.3), 1e5)
    H = law.evaluate([[dist, 0.0, 0.0]]).history
    phi = 0.7 * 2 * math.pi
    x = np.array([[dist * math.cos(phi), dist * math.sin(phi), 0.0]])
    v = dist * phi / dt * np.array([[-math.sin(phi), math.cos(phi), 0.0]])    # e_phi dist dphi/dt
    st = law.evaluate(x, v, H, tangent=False, dt=dt)
    assert st.status[0] == SLIP and st.history[0, 2] == pytest.approx(phi, rel=1e-12)
    np.testing.assert_allclose(st.history[0, 6], (R * phi) - np.linalg.norm(st.traction[0]) / 1e3, rtol=1e-9)
    assert law.evaluate(x, None, H, tangent=False).status[0] == UNRESOLVED


# ---------------------------------------------------------------------------------------------
# fields as nets: components in the orthonormal tangent frame (a_1 = rho_1/|rho_1|, a_2 = nu x a_1)

def components(field, surface, xi):
    """The positive tensor (C = -B or F) of a field at chart coordinates xi, as a 2x2 matrix in
    the tangent frame."""
    law = ContactLaw(surface, field if field.kind == "adhesion" else Adhesion.isotropic(1.0),
                     field if field.kind == "friction" else Friction.isotropic(1.0), 1.0)
    c = (law.friction_components if field.kind == "friction" else lambda a: -law.adhesion_components(a))(
        np.array([xi], dtype=float))[0]
    return np.array([[c[0], c[1]], [c[1], c[2]]])


def test_polar_adhesion_matches_papers_eq8_in_cartesian_and_is_diagonal_in_polar():
    """Papers' eq. 8 in the frame (e_x, e_y) of the Cartesian chart; diag(eps_r, eps_phi) in the
    frame (e_r, e_phi) of the polar chart, at the same points (B by law.adhesion_components)."""
    er, ephi = 3e4, 5e2
    field = Adhesion.polar(er, ephi)
    cart = ContactLaw(Plane("cartesian"), field, Friction.isotropic(0.3), 1.0)
    polar = ContactLaw(Plane("polar"), field, Friction.isotropic(0.3), 1.0)
    for x, y in [(0.3, 0.4), (-1.0, 0.2), (0.0, -2.0)]:
        b = cart.adhesion_components([[x, y]])[0]
        ref = -1 / (x * x + y * y) * np.array([er * x * x + ephi * y * y, (er - ephi) * x * y,
                                               er * y * y + ephi * x * x])
        np.testing.assert_allclose(b, ref, rtol=1e-13, atol=1e-13 * er)
        b = polar.adhesion_components([[math.hypot(x, y), math.atan2(y, x)]])[0]
        np.testing.assert_allclose(b, [-er, 0.0, -ephi], rtol=1e-13, atol=1e-12 * er)


def test_polar_friction_components():
    """F = e_r e_r / mu_r^2 + e_phi e_phi / mu_phi^2: diagonal in the polar chart's frame, turned
    by phi in the Cartesian chart's frame."""
    mr, mp, phi = 0.2, 0.5, 0.3
    Fp = components(Friction.polar(mr, mp), Plane("polar"), (2.0, phi))
    np.testing.assert_allclose(Fp, np.diag([1 / mr**2, 1 / mp**2]), rtol=1e-12, atol=1e-12)
    Q = np.array([[math.cos(phi), -math.sin(phi)], [math.sin(phi), math.cos(phi)]])
    Fc = components(Friction.polar(mr, mp), Plane(), (2.0 * math.cos(phi), 2.0 * math.sin(phi)))
    np.testing.assert_allclose(Fc, Q @ Fp @ Q.T, rtol=1e-12, atol=1e-12 / mr**2)


@pytest.mark.parametrize("side", ["inside", "outside"])
def test_spiral_components_and_pitch(side):
    """Paper 2, Fig. 1: B = -(eps1 e1 e1 + eps2 e2 e2), e1 = cos a e_phi + sin a e_z in the frame
    (e_phi, e_z) of the cylinder (either side, any axis); e1 advances 2 pi R tan a per turn."""
    R, a, e1, e2 = 0.01, math.radians(12.0), 1e4, 3e6
    cyl = Cylinder(R, axis_point=(0.1, 0.0, 0.2), axis_direction=(0.2, -0.4, 1.0), side=side)
    C = components(Adhesion.spiral(e1, e2, a), cyl, (0.7, 0.003))
    c, s = math.cos(a), math.sin(a)
    np.testing.assert_allclose(C, [[e1 * c * c + e2 * s * s, (e1 - e2) * s * c],
                                   [(e1 - e2) * s * c, e1 * s * s + e2 * c * c]], rtol=1e-12)
    g = cyl.at((0.7, 0.003))
    a1 = g.rho[0] / np.linalg.norm(g.rho[0])
    np.testing.assert_allclose(np.cross(np.cross(g.rho[0], g.rho[1]) / R, a1), cyl.axes[2], atol=1e-14)  # a_2 = e_z
    w, v = np.linalg.eigh(C)
    d = v[:, np.argmin(np.abs(w - e1))]                 # e1 in (e_phi, e_z): dz / (R dphi) = d_2 / d_1
    assert 2 * math.pi * R * d[1] / d[0] == pytest.approx(2 * math.pi * R * math.tan(a), rel=1e-10)


def test_spiral_by_lead_advances_the_lead_per_turn_on_a_cone():
    """Followed once around a cone (half angle 0.3) from any height, the field line of e1 of a
    spiral given by its lead rises by the lead (chart (phi, z) orthogonal: dz/dphi =
    (d_2 / |rho_2|) / (d_1 / |rho_1|) with d = e1 in the tangent frame), for either side."""
    lead = 0.05
    for side in ("outside", "inside"):
        cone = Cone(0.3, 0.4, axis_direction=(1.0, 0.5, 0.2), side=side)
        field = Friction.spiral(0.2, 0.6, lead=lead)
        for z0 in (-0.3, 0.0, 0.4):
            n = 64
            z, h = z0, 2 * math.pi / n
            for k in range(n):                          # the midpoint rule (dz/dphi depends on z only)
                def slope(phi, z):
                    g = cone.at((phi, z))
                    w, v = np.linalg.eigh(components(field, cone, (phi, z)))
                    d = v[:, 1]                 # F's larger eigenvalue, 1/mu_1^2, is along e1 (mu_1 < mu_2)
                    return (d[1] / np.linalg.norm(g.rho[1])) / (d[0] / np.linalg.norm(g.rho[0]))
                z = z + h * slope((k + 0.5) * h, z + 0.5 * h * slope(k * h, z))
            assert z - z0 == pytest.approx(lead, rel=1e-10)


def test_equal_polar_values_are_isotropic():
    law = ContactLaw(Plane(), Adhesion.polar(7.0, 7.0), Friction.polar(0.3, 0.3), 1.0)
    anchors = np.array([[0.3, -0.2], [5.0, 1.0]])
    np.testing.assert_allclose(law.adhesion_components(anchors), [[-7.0, 0.0, -7.0]] * 2, atol=1e-13)
    np.testing.assert_allclose(law.friction_components(anchors), [[1 / 0.09, 0.0, 1 / 0.09]] * 2, rtol=1e-14)


def test_polar_core_radius_regularisation():
    """Documented regularisation: isotropic mean (eps_r + eps_phi)/2 at the origin; relative
    deviation from the exact field <= (r_c / r)^2 elsewhere; the exact field raises at the origin."""
    with_core = ContactLaw(Plane(), Adhesion.polar(10.0, 2.0, core_radius=1e-3), Friction.isotropic(0.3), 1.0)
    np.testing.assert_allclose(with_core.adhesion_components([[0.0, 0.0]]), [[-6.0, 0.0, -6.0]], atol=1e-13)
    exact = ContactLaw(Plane(), Adhesion.polar(10.0, 2.0), Friction.isotropic(0.3), 1.0)
    for r in (1e-2, 1e-1, 1.0):
        u = np.array([[r * 0.6, r * 0.8]])
        dev = np.abs(with_core.adhesion_components(u) - exact.adhesion_components(u)).max() / 10.0
        assert 0.0 < dev <= (1e-3 / r) ** 2
    with pytest.raises(ValueError, match="undefined at the polar origin"):
        exact.adhesion_components([[0.0, 0.0]])


def test_fields_refuse_the_wrong_surface():
    with pytest.raises(ValueError, match="polar orthotropy is defined on a Plane only"):
        ContactLaw(Cylinder(1.0), Adhesion.polar(1, 2), Friction.isotropic(0.3), 1.0)
    with pytest.raises(ValueError, match="helix angle needs a Cylinder or a Cone"):
        ContactLaw(Plane(), Adhesion.isotropic(1), Friction.spiral(0.1, 0.2, 0.1), 1.0)


def test_spiral_by_helix_angle_is_refused_on_a_sphere():
    with pytest.raises(ValueError, match="helix angle needs a Cylinder or a Cone"):
        ContactLaw(Sphere(1.0), Adhesion.isotropic(1), Friction.spiral(0.1, 0.2, 0.1), 1.0)


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
    (lambda: Cylinder(1.0, side="top"), "side must be 'outside' or 'inside'"),
    (lambda: Plane("spherical"), "coordinates must be 'cartesian' or 'polar'"),
])
def test_bad_input_is_named(call, match):
    with pytest.raises((ValueError, TypeError), match=match):
        call()
