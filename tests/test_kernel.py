"""The covariant contact kernel (exu_aniso.kernel.point) on the surface protocol: closed-form sticking
steps on the plane and the cylinder (where the frame is parallel), consistent tangent against
finite differences on curved surfaces, objectivity under a rigid motion of master and slave
together, and the zero-taper cone equal to the cylinder."""
from __future__ import annotations

import math

import numpy as np
import pytest

from exu_aniso import Adhesion, ContactLaw, Friction
from exu_aniso import geometry as geo
from _suite import covering

MAPS = ("seed", "exact", "radial")
RNG = np.random.default_rng(11)


def _inside(surface, box, depth=1e-4):
    xi = np.array([RNG.uniform(*box[0]), RNG.uniform(*box[1])])
    g = surface.at(xi)
    return g.point - g.n * RNG.uniform(0.1, 1.0) * depth


def _history(law, x, v, active=True):
    """A converged history row near x: anchored at a nearby point, with a traction of the size of
    the friction limit (so some evaluations stick and some slip)."""
    st = law.evaluate(x[None, :] + RNG.normal(size=3) * 2e-5, v[None, :], None, tangent=False, dt=1e-3)
    H = st.history.copy()
    if active and H[0, 4] > 0.5:
        H[0, 0:2] = RNG.normal(size=2) * 3.0
    return H


def _rot(angle):
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s], [s, c]])


def _B(eps_1, eps_2, angle):
    R = _rot(angle)
    return -R @ np.diag([eps_1, eps_2]) @ R.T


@pytest.mark.parametrize("return_map", MAPS)
def test_sticking_step_on_the_plane_is_the_closed_form(return_map):
    """Plane z = 0, constant orthotropic B: a sticking step from the anchor xi_n with traction T_n
    to x gives T = T_n + B (x_t - xi_n) (the frame is constant, transport is the identity), N =
    eps_N xi3 and the force (T, -N) on the slave point; the candidate anchors at x_t."""
    law = ContactLaw(geo.Plane(), Adhesion.orthotropic(1e4, 1e2, 0.3), Friction.isotropic(10.0), 1e5,
                     return_map=return_map)
    for _ in range(8):
        xn, du = RNG.uniform(-1, 1, 2), RNG.normal(size=2) * 1e-4
        Tn = RNG.normal(size=2)
        x = np.array([*(xn + du), -RNG.uniform(1e-5, 1e-4)])
        H = np.zeros((1, 9))
        H[0, 0:2], H[0, 2:4], H[0, 4] = Tn, xn, 1.0
        st = law.evaluate(x[None, :], np.zeros((1, 3)), H, dt=1e-3)
        T = Tn + _B(1e4, 1e2, 0.3) @ du
        assert st.status[0] == 1                                  # STICK (|T| << mu |N|)
        np.testing.assert_allclose(st.traction[0], T, rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(st.force[0], [T[0], T[1], -1e5 * x[2]], rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(st.history[0, 2:4], x[:2], rtol=0, atol=1e-15)


@pytest.mark.parametrize("side", ("inside", "outside"))
def test_sticking_step_on_the_cylinder_is_the_closed_form(side):
    """Cylinder of radius R about z: the frame (e_phi, e_z) is parallel on the cylinder, so a
    sticking step keeps the components of T_n and adds B (R dphi, dz); the force conjugate to the
    slip of the contact point is T_1 R / r e_phi + T_2 e_z + |N| n at the slave's radius r."""
    R, eps = 0.5, (1e4, 3e2, -0.4)
    law = ContactLaw(geo.Cylinder(R, side=side), Adhesion.orthotropic(*eps), Friction.isotropic(10.0), 1e5)
    sgn = 1.0 if side == "outside" else -1.0            # n = sgn e_r
    for _ in range(8):
        phin, zn = RNG.uniform(-3, 3), RNG.uniform(-1, 1)
        dphi, dz, d = RNG.normal() * 2e-4, RNG.normal() * 1e-4, RNG.uniform(1e-5, 1e-4)
        r = R - sgn * d                                  # penetration d into the wall
        phi, z = phin + dphi, zn + dz
        x = np.array([r * math.cos(phi), r * math.sin(phi), z])
        Tn = RNG.normal(size=2)
        H = np.zeros((1, 9))
        H[0, 0:2], H[0, 2:4], H[0, 4] = Tn, (phin, zn), 1.0
        st = law.evaluate(x[None, :], np.zeros((1, 3)), H, dt=1e-3)
        T = Tn + _B(*eps) @ np.array([R * dphi, dz])
        e_r, e_phi = np.array([math.cos(phi), math.sin(phi), 0.0]), np.array([-math.sin(phi), math.cos(phi), 0.0])
        f = T[0] * R / r * e_phi + T[1] * np.array([0.0, 0.0, 1.0]) + 1e5 * d * sgn * e_r
        assert st.status[0] == 1
        np.testing.assert_allclose(st.traction[0], T, rtol=1e-10, atol=1e-10)
        np.testing.assert_allclose(st.force[0], f, rtol=1e-10, atol=1e-10)
        np.testing.assert_allclose(st.history[0, 2:4], (phi, z), rtol=0, atol=1e-12)


CURVED = [
    (geo.Plane(), [(0.2, 1.0), (-1, 1)], Adhesion.polar(1e4, 1e2, 1e-3), Friction.polar(0.3, 0.6, 1e-3)),
    (geo.Plane(), [(0.2, 1.0), (-1, 1)], Adhesion.orthotropic(1e4, 1e2, 0.3), Friction.orthotropic(0.3, 0.6, -0.2)),
    (geo.Cylinder(0.5, side="inside"), [(-3, 3), (-1, 1)], Adhesion.spiral(1e3, 1e5, 0.2),
     Friction.spiral(0.2, 0.5, 0.2)),
    (geo.Cylinder(0.5, axis_direction=(1, 1, 0), side="outside"), [(-3, 3), (-1, 1)],
     Adhesion.spiral(1e3, 1e5, -0.4), Friction.isotropic(0.3)),
    (geo.Cone(0.3, 0.5), [(-3, 3), (-0.4, 0.4)], Adhesion.spiral(1e3, 1e5, 0.25), Friction.orthotropic(0.2, 0.6, 0.4)),
    (geo.Cone(-0.2, 0.4, axis_direction=(0, 1, 1), side="inside"), [(-3, 3), (-0.4, 0.4)],
     Adhesion.isotropic(1e4), Friction.spiral(0.2, 0.6, 0.3)),
    (geo.Sphere(0.6), [(-3, 3), (0.4, 2.7)], Adhesion.orthotropic(1e4, 3e2, 0.7), Friction.orthotropic(0.3, 0.5, 0.1)),
    (geo.Sphere(0.6, center=(0.1, 0.2, 0.3), axis_direction=(1, 0, 1), side="inside"), [(-3, 3), (0.4, 2.7)],
     Adhesion.orthotropic(2e3, 1e4, -0.3), Friction.isotropic(0.4)),
    (geo.Torus(1.0, 0.3), [(-3, 3), (-3, 3)], Adhesion.orthotropic(1e4, 3e2, 0.2), Friction.orthotropic(0.2, 0.5, 0.8)),
    (geo.Torus(1.0, 0.3, side="inside"), [(-3, 3), (-3, 3)], Adhesion.isotropic(1e4), Friction.isotropic(0.3)),
]


def _fd(law, x, v, H, dt, wrt, h):
    J = np.zeros((3, 3))
    for j in range(3):
        e = np.zeros(3)
        e[j] = h
        xp, xm, vp, vm = (x + e, x - e, v, v) if wrt == "x" else (x, x, v + e, v - e)
        fp = law.evaluate(xp[None, :], vp[None, :], H, tangent=False, dt=dt).force[0]
        fm = law.evaluate(xm[None, :], vm[None, :], H, tangent=False, dt=dt).force[0]
        J[:, j] = (fp - fm) / (2 * h)
    return J


# every surface and net of CURVED and every map in the default run (each pair its own compiled law), the
# exact map where it can (the laws other tests compile); -m slow: all
TANGENT_CASES = covering([(k, m) for k in range(len(CURVED)) for m in MAPS], [0, 1],
                         ids=[f"{CURVED[k][0]!r}-{m}" for k in range(len(CURVED)) for m in MAPS],
                         prefer=lambda case: case[1] == "exact")


@pytest.mark.parametrize("index,return_map", TANGENT_CASES)
def test_tangent_equals_finite_differences_on_curved_surfaces(index, return_map):
    """df/dx and df/dv of the kernel against central differences of its force, with the history
    fixed (active and new contacts, stick and slip, normal and tangential dashpots)."""
    case = CURVED[index]
    s, box, A, F = case
    law = ContactLaw(s, A, F, 1e5, normal_damping=2.0, tangential_damping=1.0, return_map=return_map)
    checked = 0
    for trial in range(10):
        x = _inside(s, box)
        v = RNG.normal(size=3) * 0.1
        H = _history(law, x, v, active=trial % 4 != 0)
        st = law.evaluate(x[None, :], v[None, :], H, tangent=True, dt=1e-3)
        if st.status[0] == 0:
            continue
        # stay on the state's side of the stick/slip switch: skip states within the FD step of it
        near = [law.evaluate((x + d)[None, :], v[None, :], H, tangent=False, dt=1e-3).status[0]
                for d in np.eye(3) * 2e-9]
        if any(k != st.status[0] for k in near):
            continue
        Kfd = _fd(law, x, v, H, 1e-3, "x", 1e-9)
        Dfd = _fd(law, x, v, H, 1e-3, "v", 1e-6)
        ks = np.abs(Kfd).max()
        np.testing.assert_allclose(st.stiffness[0], Kfd, rtol=0, atol=2e-5 * ks)
        np.testing.assert_allclose(st.damping[0], Dfd, rtol=0, atol=1e-6 * (np.abs(Dfd).max() + 1.0))
        checked += 1
    assert checked >= 5


@pytest.mark.parametrize("case", CURVED[4::2], ids=lambda c: repr(c[0]))   # the curved ones (the plane is z = 0)
def test_objectivity_under_a_rigid_motion(case):
    """Moving the master surface and the slave point (position, velocity, history in the master's
    coordinates) together by a rigid motion leaves traction, N and status unchanged and turns the
    force with the motion."""
    s, box, A, F = case
    p = s.params
    th = 0.9
    c, sn = math.cos(th), math.sin(th)
    Q = np.array([[1, 0, 0], [0, c, -sn], [0, sn, c]])       # about x: the chart's reference axis stays
    o = np.array([0.4, -0.7, 1.1])
    moved = type(s)(**_moved_args(s, Q, o))
    law0 = ContactLaw(s, A, F, 1e5, normal_damping=1.0, return_map="exact")
    law1 = ContactLaw(moved, A, F, 1e5, normal_damping=1.0, return_map="exact")
    for _ in range(5):
        x = _inside(s, box)
        v = RNG.normal(size=3) * 0.1
        H = _history(law0, x, v)
        a = law0.evaluate(x[None, :], v[None, :], H, tangent=True, dt=1e-3)
        b = law1.evaluate((o + Q @ x)[None, :], (Q @ v)[None, :], H, tangent=True, dt=1e-3)
        assert a.status[0] == b.status[0]
        np.testing.assert_allclose(b.history, a.history, rtol=1e-9, atol=1e-12)
        np.testing.assert_allclose(b.force[0], Q @ a.force[0], rtol=0, atol=1e-9 * np.abs(a.force).max())
        np.testing.assert_allclose(b.stiffness[0], Q @ a.stiffness[0] @ Q.T, rtol=0,
                                   atol=1e-7 * np.abs(a.stiffness).max())
    assert p is s.params


def _moved_args(s, Q, o):
    p = s.params
    base = np.array(p.origin)
    if isinstance(s, geo.Cone):
        return dict(half_angle=s.half_angle, radius=s.radius, axis_point=o + Q @ base,
                    axis_direction=Q @ np.array(p.ez), side=s.side)
    if isinstance(s, geo.Sphere):
        return dict(radius=s.radius, center=o + Q @ base, axis_direction=Q @ np.array(p.ez), side=s.side)
    return dict(major_radius=s.major_radius, minor_radius=s.minor_radius, center=o + Q @ base,
                axis_direction=Q @ np.array(p.ez), side=s.side)


def test_zero_taper_cone_equals_the_cylinder():
    A, F = Adhesion.spiral(1e3, 1e5, 0.2), Friction.orthotropic(0.2, 0.5, 0.3)
    cone = ContactLaw(geo.Cone(0.0, 0.5, side="inside"), A, F, 1e5, return_map="radial")
    cyl = ContactLaw(geo.Cylinder(0.5, side="inside"), A, F, 1e5, return_map="radial")
    for _ in range(8):
        x = _inside(cyl.surface, [(-3, 3), (-1, 1)])
        v = RNG.normal(size=3) * 0.1
        H = _history(cyl, x, v)
        a = cone.evaluate(x[None, :], v[None, :], H, tangent=True, dt=1e-3)
        b = cyl.evaluate(x[None, :], v[None, :], H, tangent=True, dt=1e-3)
        # equal to round-off: the cylinder declares a constant metric and skips the transport that
        # the cone carries out (its Christoffel symbols vanish at zero taper up to round-off)
        scale = np.abs(b.force).max()
        np.testing.assert_allclose(a.force, b.force, rtol=1e-13, atol=1e-15 * scale)
        np.testing.assert_allclose(a.history, b.history, rtol=1e-13, atol=1e-15 * np.abs(b.history).max())
        np.testing.assert_allclose(a.stiffness, b.stiffness, rtol=1e-9, atol=1e-9)


def test_contact_on_a_pole_or_axis_is_a_clear_error():
    law = ContactLaw(geo.Cylinder(0.5, side="outside"), Adhesion.isotropic(1e3), Friction.isotropic(0.3), 1e5)
    with pytest.raises(ValueError, match="centre of curvature"):
        law.evaluate(np.array([[0.0, 0.0, 0.2]]))          # on the axis of a shaft: inside it, no closest point
    hole = ContactLaw(geo.Cylinder(0.5, side="inside"), Adhesion.isotropic(1e3), Friction.isotropic(0.3), 1e5)
    st = hole.evaluate(np.array([[0.0, 0.0, 0.2]]))        # on the axis of a hole: gap R, open
    assert st.status[0] == 0 and st.force[0].tolist() == [0.0, 0.0, 0.0]


SIZES = {"r": 0.5}


def _python_only_profile(z):          # a dict lookup: numba cannot compile it
    return SIZES["r"] + 0.1 * z, 0.1, 0.0


def _profile(z):
    return 0.5 + 0.1 * z, 0.1, 0.0


@pytest.mark.parametrize("profile", [_profile, _python_only_profile], ids=["compiled", "plain-python"])
def test_user_surface_of_revolution_equals_the_cone(profile):
    """The same cone as SurfaceOfRevolution (compiled, or plain Python when numba cannot compile the
    profile): the kernel gives the forces, tangent and history of geo.Cone."""
    s = geo.SurfaceOfRevolution(profile)
    assert s.compiled == (profile is _profile)
    A, F = Adhesion.isotropic(1e4), Friction.orthotropic(0.2, 0.5, 0.3)
    a = ContactLaw(s, A, F, 1e5, return_map="exact")
    b = ContactLaw(geo.Cone(math.atan(0.1), 0.5), A, F, 1e5, return_map="exact")
    for _ in range(4):
        x = _inside(b.surface, [(-3, 3), (-0.3, 0.3)])
        v = RNG.normal(size=3) * 0.1
        H = _history(b, x, v)
        sa = a.evaluate(x[None, :], v[None, :], H, tangent=True, dt=1e-3)
        sb = b.evaluate(x[None, :], v[None, :], H, tangent=True, dt=1e-3)
        np.testing.assert_allclose(sa.force, sb.force, rtol=0, atol=1e-10 * (1 + np.abs(sb.force).max()))
        np.testing.assert_allclose(sa.history, sb.history, rtol=1e-10, atol=1e-12)
        np.testing.assert_allclose(sa.stiffness, sb.stiffness, rtol=0, atol=1e-8 * np.abs(sb.stiffness).max())


def test_spiral_by_lead_equals_spiral_by_helix_angle():
    """On a cylinder of radius R the helix angle alpha and the lead 2 pi R tan(alpha) are the same
    net; on a cone the helix angle is taken at its radius (z = 0)."""
    alpha = 0.2
    for surface in (geo.Cylinder(0.5, side="inside"), geo.Cone(0.1, 0.5, side="inside")):
        lead = 2 * math.pi * 0.5 * math.tan(alpha)
        a = ContactLaw(surface, Adhesion.spiral(1e3, 1e5, helix_angle=alpha), Friction.spiral(0.2, 0.5, helix_angle=alpha),
                       1e5, return_map="radial")
        b = ContactLaw(surface, Adhesion.spiral(1e3, 1e5, lead=lead), Friction.spiral(0.2, 0.5, lead=lead), 1e5,
                       return_map="radial")
        for _ in range(4):
            x = _inside(surface, [(-3, 3), (-0.3, 0.3)])
            v = RNG.normal(size=3) * 0.1
            H = _history(a, x, v)
            np.testing.assert_allclose(b.evaluate(x[None, :], v[None, :], H, dt=1e-3).force,
                                       a.evaluate(x[None, :], v[None, :], H, dt=1e-3).force, rtol=1e-12, atol=1e-12)
    with pytest.raises(ValueError, match="exactly one of helix_angle"):
        Adhesion.spiral(1e3, 1e5)
    with pytest.raises(ValueError, match="needs an angle as the first surface coordinate"):
        ContactLaw(geo.Plane(), Adhesion.spiral(1e3, 1e5, lead=0.1), Friction.isotropic(0.3), 1e5)


def test_a_point_in_contact_thrown_to_a_centre_of_curvature_is_an_unresolved_step():
    """A point in contact at the last step that a Newton iterate puts on the shaft's axis (its centre of
    curvature) is no user error: it gives no force, keeps its history, and has the status UNRESOLVED,
    which makes the engines reject the step and repeat it smaller. A new point there stays an error
    (test_contact_on_a_pole_or_axis_is_a_clear_error)."""
    from exu_aniso.law.history import UNRESOLVED
    law = ContactLaw(geo.Cylinder(0.5, side="outside"), Adhesion.isotropic(1e3), Friction.isotropic(0.3), 1e5)
    H = law.initial_history(1)
    H[0, 2:5] = [0.3, 0.2, 1.0]                     # active, anchored at (phi, z) = (0.3, 0.2)
    H[0, 0:2] = [1.5, -0.5]
    st = law.evaluate(np.array([[0.0, 0.0, 0.2]]), None, H)
    assert st.status[0] == UNRESOLVED and st.force[0].tolist() == [0.0, 0.0, 0.0]
    np.testing.assert_array_equal(st.history[0, :7], H[0, :7])
