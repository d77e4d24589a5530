"""Property-based fuzzing (hypothesis) of the geometry kernels and the tensor fields on them: the
plane and cylinder of the surface protocol (projection, chart round trip, tangent frame) and tensor
fields as nets (positive definite with their principal axes; one tensor in either chart of the
plane). The strategies, the hard corners they reach and the default and slow runs:
tests/_fuzz.py.
"""
import math

import numpy as np
import pytest
from _fuzz import (EPS, angles, check_many_cases, check_property, fields, law_inputs, log_uniform,
                   points_near, property_registry, surface_kind_of, surfaces, sym_matrix, unit)
from hypothesis import assume
from hypothesis import strategies as st

from exu_aniso import Adhesion, ContactLaw, Friction
from exu_aniso.geometry import Cylinder, Plane
from exu_aniso.law.return_maps import RETURN_MAPS, return_map_point

PROPERTIES, prop = property_registry()


# ----------------------------------------------------------------------------------------------
# surfaces

def _axis_geometry(surface, x):
    """Distance from the axis and radial unit vector, computed here (not by the class)."""
    a = surface.axes[2]
    d = x - surface.axis_point
    radial = d - (d @ a) * a
    rho = np.linalg.norm(radial)
    return rho, radial / rho


@st.composite
def _surface_point(draw):
    s = draw(surfaces())
    return s, draw(points_near(s))


@prop("surface_projection", _surface_point())
def check_projection(surface, x):
    """projection on the surface, x = C + xi3 n, n unit and oriented, gap sign, metric SPD, h, chart round trip"""
    if isinstance(surface, Plane) and surface.coordinates == "polar":
        assume(math.hypot(x[0], x[1]) > 0.0)
    p = surface.project(x)
    scale = np.linalg.norm(x) + (surface.radius + np.linalg.norm(surface.axis_point)
                                 if isinstance(surface, Cylinder) else 0.0)
    assert abs(np.linalg.norm(p.n) - 1.0) <= 4 * EPS
    np.testing.assert_allclose(p.point + p.xi3 * p.n, x, rtol=0, atol=1e-13 * scale)
    if isinstance(surface, Plane):
        assert p.point[2] == 0.0
        if surface.coordinates == "cartesian":      # xi3 is z itself, n = e_z exactly
            assert np.array_equal(p.n, [0.0, 0.0, 1.0]) and p.xi3 == x[2]
        else:   # the polar chart normalises rho_1 x rho_2 = r (c^2 + s^2) e_z and forms xi3 through the
            #     rotation by phi: a few ulp (n_z = 1 - eps, xi3 = 0.75 -> 0.7499999999999999 seen)
            np.testing.assert_allclose(p.n, [0.0, 0.0, 1.0], rtol=0, atol=4 * EPS)
            assert abs(p.xi3 - x[2]) <= 4 * EPS * scale
        np.testing.assert_array_equal(p.h, np.zeros((2, 2)))
    else:
        R = surface.radius
        rho, e_rad = _axis_geometry(surface, x)
        tol = 1e-13 * scale / rho                       # conditioning of the direction near the axis
        np.testing.assert_allclose(p.n, surface.sign * e_rad, rtol=0, atol=tol)  # hole: towards the axis
        assert abs(p.xi3 - surface.sign * (rho - R)) <= 1e-13 * scale    # xi3 <= 0 is penetration
        assert abs(_axis_geometry(surface, p.point)[0] - R) <= 1e-13 * scale
        h_expected = R if surface.side == "inside" else -R
        np.testing.assert_allclose(p.h, [[h_expected, 0.0], [0.0, 0.0]], rtol=1e-13, atol=1e-13 * R)
    assert np.all(np.abs(p.rho @ p.n) <= 1e-13 * np.linalg.norm(p.rho, axis=1))
    ev = np.linalg.eigvalsh(p.m)
    assert ev[0] > 0.0 and np.allclose(p.m, p.m.T, rtol=0, atol=0)
    np.testing.assert_allclose(p.m_inv @ p.m, np.eye(2), rtol=0, atol=1e-12)
    q = surface.at(p.xi)
    np.testing.assert_allclose(q.point, p.point, rtol=0, atol=1e-13 * scale)
    np.testing.assert_allclose(q.rho, p.rho, rtol=0, atol=1e-13 * np.abs(p.rho).max())


@st.composite
def _chart_point(draw):
    s = draw(surfaces())
    if isinstance(s, Plane):
        if s.coordinates == "cartesian":
            xi = (draw(unit(-10, 10)), draw(unit(-10, 10)))
        else:
            xi = (draw(log_uniform(-6, 1)), draw(angles))
        return s, np.array(xi), draw(unit(-1.0, 1.0))
    R = s.radius
    lo, hi = (-1.0, 0.9) if s.side == "inside" else (-0.9, 1.0)
    return s, np.array([draw(angles), R * draw(unit(-10, 10))]), R * draw(unit(lo, hi))


@prop("surface_chart_round_trip", _chart_point())
def check_chart_round_trip(surface, xi, xi3):
    """project(at(xi).point + xi3 n) gives xi (angles modulo their period: surface.increment) and xi3 back"""
    c = surface.at(xi)
    p = surface.project(c.point + xi3 * c.n)
    size = np.linalg.norm(c.point) + abs(xi3) + (surface.radius if isinstance(surface, Cylinder) else 0.0)
    assert abs(p.xi3 - xi3) <= 1e-13 * size
    d = surface.increment(xi, p.xi)
    if isinstance(surface, Plane) and surface.coordinates == "cartesian":
        np.testing.assert_allclose(d, 0.0, rtol=0, atol=1e-13 * size)
    elif isinstance(surface, Plane):
        assert abs(d[0]) <= 1e-13 * size
        assert abs(d[1]) <= 1e-13 * size / xi[0]
    else:
        dist = surface.radius + surface.sign * xi3           # distance of the point from the axis
        assert abs(d[0]) <= 1e-13 * size / dist
        assert abs(d[1]) <= 1e-13 * size


def _probe_law(surface, adhesion=None, friction=None):
    """A ContactLaw on surface (for its frames and field components)."""
    return ContactLaw(surface, adhesion or Adhesion.isotropic(1.0), friction or Friction.isotropic(1.0), 1.0)


@st.composite
def _frame_case(draw):
    s = draw(surfaces())
    K = draw(st.integers(1, 4))
    return s, np.array([draw(points_near(s, rel_min=1e-2, origin=False)) for _ in range(K)])


@prop("surface_tangent_frame", _frame_case())
def check_tangent_frame(surface, x):
    """traction frame orthonormal, tangent, a_1 along rho_1, a_2 on the side of rho_2, n of the projection; dxi/dx = (m - xi3 h)^-1 rho = differences"""
    E, n = _probe_law(surface).traction_frames(x)
    scale = np.abs(x).max() + (surface.radius + np.abs(surface.axis_point).max()
                               if isinstance(surface, Cylinder) else 1.0)
    h = 1e-6 * scale
    for k in range(x.shape[0]):
        p = surface.project(x[k])
        Ek = E[k]
        np.testing.assert_allclose(Ek.T @ Ek, np.eye(2), rtol=0, atol=1e-14)
        assert np.all(np.abs(n[k] @ Ek) <= 1e-14)
        np.testing.assert_allclose(n[k], p.n, rtol=0, atol=1e-13)
        r1, r2 = p.rho
        np.testing.assert_allclose(Ek[:, 0], r1 / np.linalg.norm(r1), rtol=0, atol=1e-14)
        assert Ek[:, 1] @ r2 > 0.0
        J = np.linalg.solve(p.m - p.xi3 * p.h, p.rho)          # d xi / d x (2, 3)
        for j in range(3):
            e = np.zeros(3)
            e[j] = h
            d = surface.increment(surface.project(x[k] - e).xi, surface.project(x[k] + e).xi) / (2 * h)
            np.testing.assert_allclose(d, J[:, j], rtol=0, atol=1e-6 * (1 + np.abs(J).max()))


# ----------------------------------------------------------------------------------------------
# tensor fields (nets of exu_aniso.fields.nets, through ContactLaw.adhesion_components / friction_components)

def positive_components(law, kind, xi):
    """C = -B (adhesion) or F (friction) at chart coordinates xi, 2x2 in the tangent frame."""
    c = -law.adhesion_components(xi[None, :])[0] if kind == "adhesion" else law.friction_components(xi[None, :])[0]
    return sym_matrix(c)


@st.composite
def _field_case(draw):
    surface = draw(surfaces(("cartesian", "inside", "outside")))
    kind = draw(st.sampled_from(["adhesion", "friction"]))
    field = draw(fields(kind, surface_kind_of(surface)))
    if isinstance(surface, Plane):
        r = draw(st.one_of(log_uniform(-6, 1), st.just(0.0) if field[4] > 0 else st.nothing()))
        phi = draw(angles)
        xi = np.array([r * math.cos(phi), r * math.sin(phi)])
    else:
        xi = np.array([draw(angles) + 2 * math.pi * draw(st.integers(-3, 3)), surface.radius * draw(unit(-10, 10))])
    return surface, kind, field, xi


@prop("field_spd_and_principal_axes", _field_case())
def check_field(surface, kind, field, xi):
    """components SPD, eigenvalues lambda_1/2 (polar core: between them), e1 principal in the tangent frame"""
    f, (l1, l2), pattern, angle, rc = field
    law = _probe_law(surface, f if kind == "adhesion" else None, f if kind == "friction" else None)
    M = positive_components(law, kind, xi)
    lo, hi = min(l1, l2), max(l1, l2)
    ev = np.linalg.eigvalsh(M)
    assert ev[0] > 0.0 and M[0, 0] > 0.0 and M[0, 0] * M[1, 1] - M[0, 1] ** 2 > 0.0
    assert lo * (1 - 1e-12) <= ev[0] and ev[1] <= hi * (1 + 1e-12)
    r = math.hypot(*xi)
    if pattern != "polar" or rc == 0.0:
        np.testing.assert_allclose(ev, [lo, hi], rtol=1e-11, atol=1e-11 * hi)
        # e1 in the frame (a_1, a_2): at angle from the xi1 line; the helix angle from e_phi on the
        # cylinder (frame (e_phi, e_z)); e_r = (x, y)/r in the Cartesian plane's frame (e_x, e_y)
        e1 = np.array([math.cos(angle), math.sin(angle)]) if pattern != "polar" else xi / r
        np.testing.assert_allclose(M @ e1, l1 * e1, rtol=0, atol=1e-11 * hi)
    else:   # regularised projector: (x x^T + rc^2/2 I)/(r^2 + rc^2) -> deviation <= (rc/r)^2 relative
        dev = np.abs(ev - [lo, hi]).max() / (hi - lo) if hi > lo else 0.0
        assert dev <= min(1.0, rc * rc / max(r * r, 1e-300)) * (1 + 1e-9) + 1e-12


@st.composite
def _covariance_case(draw):
    adh = draw(fields("adhesion", "plane", ["isotropic", "polar"]))[0]
    fri = draw(fields("friction", "plane", ["isotropic", "polar"]))[0]
    r, phi = draw(log_uniform(-3, 1)), draw(angles)
    charts = [(Plane("cartesian"), np.array([r * math.cos(phi), r * math.sin(phi)])),
              (Plane("polar"), np.array([r, phi]))]
    inputs = draw(law_inputs())
    return adh, fri, charts, inputs, draw(st.sampled_from(RETURN_MAPS))


@prop("field_covariance_polar_vs_cartesian_chart", _covariance_case())
def check_covariance(adh, fri, charts, inputs, method):
    """at one point of the plane the Cartesian and polar charts' frames hold the same B and F (as 3D tensors); return maps in either frame give one 3D traction"""
    T3, N, _, _ = inputs
    T3 = np.array([T3[0], T3[1], 0.0])          # a trial traction, 3D (tangent to the plane)
    tensors, tv = None, None
    for surface, xi in charts:
        law = _probe_law(surface, adh, fri)
        E = law.traction_frames(np.r_[surface.at(xi).point[:2], -1e-3][None, :])[0][0]   # frame at C (3, 2)
        b, f = law.adhesion_components(xi[None, :])[0], law.friction_components(xi[None, :])[0]
        B3, F3 = E @ sym_matrix(b) @ E.T, E @ sym_matrix(f) @ E.T
        if tensors is not None:
            np.testing.assert_allclose(B3, tensors[0], rtol=0, atol=1e-12 * np.abs(tensors[0]).max())
            np.testing.assert_allclose(F3, tensors[1], rtol=0, atol=1e-12 * np.abs(tensors[1]).max())
        T_E = E.T @ T3
        r = return_map_point(T_E, N, tuple(b), tuple(f), method, False)
        v = E @ r.T
        if tv is not None:
            assert r.state == tv[1] or abs(r.phi_trial) <= 1e-10 * max(N, 1e-300)   # on the yield surface
            if r.state == tv[1]:
                np.testing.assert_allclose(v, tv[0], rtol=0, atol=1e-9 * np.linalg.norm(tv[0]) + 1e-300)
        tensors, tv = (B3, F3), (v, r.state)


# ----------------------------------------------------------------------------------------------
# the tests

@pytest.mark.parametrize("name", list(PROPERTIES))
def test_property(name):
    check_property(PROPERTIES, name)


@pytest.mark.slow
def test_properties_many_cases():
    """SLOW_EXAMPLES generated cases per property; run with -s to see the count per property."""
    check_many_cases(PROPERTIES)
