"""Checks on every surface of the protocol through the particle scene: a mass
point on Plane, Cylinder, Cone, Sphere, Torus, SurfaceOfRevolution and ParametricSurface, inside and
outside.

* parity: Exudyn (exu_aniso/models/particle.py) against the numpy reference (exu_aniso.engines.reference), the
  trajectory to 1e-6 relative in the norm
      e_x = max_n |x_exu(t_n) - x_ref(t_n)|_2 / max_n |x_ref(t_n) - x_ref(0)|_2   (position: relative
      to the distance travelled, stricter than relative to |x|),
      e_v = max_n |v_exu(t_n) - v_ref(t_n)|_2 / max_n |v_ref(t_n)|_2;
  every run both sticks and slides, and its energy ledger closes (energy_ok) on both engines;
* covariance: the same sphere as Sphere, SurfaceOfRevolution and ParametricSurface gives one path;
* limits: a Cone of half angle 0 is the Cylinder to the last bit; a Sphere of radius R tends to the
  Plane like 1/R;
* objectivity at system level: the surface carried by a rigid body in uniform translation or
  rotation, with the point's initial state carried along, gives the fixed master's path relative
  to the body.

The scenes keep the contact resolved (no impacts): an impact under-resolved by the step (a point
hitting a cone's rising generator at dt = 5e-4 s against the 2 ms penalty period) amplifies the
engines' 1e-9 differences of Newton round-off into percent differences within a few bounces, and
opens the ledger (which says so); that is sensitivity, not a defect, and is left out here.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

exu = pytest.importorskip("exudyn")

from exu_aniso.law.history import SLIP, STICK  # noqa: E402
from exu_aniso.models.particle import RunParticle  # noqa: E402
from exu_aniso.scenes.particle import simulate_particle  # noqa: E402
from exu_aniso.scenes.particle import (ParticleParams, gravity_vector, initial_state,  # noqa: E402
                                      particle_contact_law)

R, A, MASS, EPS_N, G = 0.5, 0.2, 0.1, 1e6, 9.81
PEN = MASS * G / EPS_N                    # static penetration under the weight [m]
BETA = math.radians(10.0)                 # cone half angle
PARITY = 1e-6


def _X(r):
    return np.column_stack([r.trajectory[k] for k in ("x", "y", "z")])


def _V(r):
    return np.column_stack([r.trajectory[k] for k in ("vx", "vy", "vz")])


def errors(a, b):
    """(e_x, e_v) of the module docstring, b the reference."""
    ex = np.max(np.linalg.norm(_X(a) - _X(b), axis=1)) / np.max(np.linalg.norm(_X(b) - _X(b)[0], axis=1))
    ev = np.max(np.linalg.norm(_V(a) - _V(b), axis=1)) / np.max(np.linalg.norm(_V(b), axis=1))
    return float(ex), float(ev)


def scene(surface, side, **kw):
    """A point at rest-penetration on the top (outside) or the bottom (inside) of the surface,
    pressed by gravity, launched at 0.2 m/s along it (0.1 m/s across): it slides, friction (mu 0.3)
    stops it, and it sticks (on the outside of a curved surface where tan(slope) < mu). The plane's
    back side is a ceiling: no gravity, a softer contact (eps_n 1e4, 10 ms of contact) that the point
    hits obliquely and leaves again (slides while pressed, sticks at the turn)."""
    top = side == "outside"
    s = 1.0 if top else -1.0
    base = dict(case="free", surface=surface, side=side, mu_1=0.3, mu_2=0.3, t_end=0.15, dt=5e-4, radius=R,
                minor_radius=A, vx0=0.2, vy0=0.1, vz0=0.0)
    if surface == "plane":
        if top:
            base.update(x0=0.1, z0=-PEN)
        else:
            base.update(gravity=0.0, eps_n=1e4, z0=-1e-4, vx0=0.3, vz0=0.2, dt=2e-4, t_end=0.05)
    elif surface == "cone":                # along the generator of the top (bottom) line
        base.update(half_angle=math.degrees(BETA), vx0=0.2 * math.cos(BETA), vz0=s * 0.2 * math.sin(BETA),
                    z0=s * (R - s * PEN))
    elif surface == "torus":               # the top (bottom) of the tube
        base.update(x0=R, z0=s * (A - s * PEN), vx0=0.1, vy0=0.2)
    else:
        base.update(z0=s * (R - s * PEN))
    base.update(kw)
    return ParticleParams(**base)


def both(p, **exu_options):
    return RunParticle(p, **exu_options), simulate_particle(p)


def check_run(e, b, stick_and_slip=True):
    ex, ev = errors(e, b)
    assert e.summary["steps"] == b.summary["steps"]
    assert ex <= PARITY and ev <= PARITY, (ex, ev)
    status = set(b.trajectory["status"].astype(int))
    if stick_and_slip:
        assert {STICK, SLIP} <= status, status
    for r in (e, b):
        assert r.summary["energy_ok"], r.summary["energy"]
    return ex, ev


SURFACES = ["plane", "cylinder", "cone", "sphere", "torus", "revolution", "parametric"]


@pytest.mark.parametrize("side", ["outside", "inside"])
@pytest.mark.parametrize("surface", SURFACES)
def test_parity_and_ledger_on_every_surface(surface, side):
    """Measured (this test's scenes): e_x <= 6.1e-12, e_v <= 2.7e-11 over all 14 (the Newton
    tolerance 1e-10 of both engines); energy residuals <= 2.3e-8, but 2.5e-4 for the plane's ceiling
    bounce (the penalty impact over 50 steps)."""
    e, b = both(scene(surface, side))
    check_run(e, b)


def user_paraboloid(u, v):
    """z = 0.5 (u^2 + 0.5 v^2) - 0.2: a bowl of one's own (ParametricSurface, chart (u, v) = (x, y))."""
    x = np.array([u, v, 0.5 * (u * u + 0.5 * v * v) - 0.2])
    dx = np.array([[1.0, 0.0, u], [0.0, 1.0, 0.5 * v]])
    ddx = np.array([[[0.0, 0.0, 1.0], [0.0, 0.0, 0.0]], [[0.0, 0.0, 0.0], [0.0, 0.0, 0.5]]])
    return x, dx, ddx


@pytest.mark.parametrize("side", ["front", "back"])
def test_parity_on_a_parametric_surface_of_ones_own(side):
    """A ParametricSurface that is no sphere: the paraboloid bowl, the point inside it (front: above
    the graph, pressed by gravity) or hanging under it (back: gravity 0, pressed by its launch)."""
    from exu_aniso.geometry import ParametricSurface
    surf = ParametricSurface(user_paraboloid, side=side, bounds=((-1.0, 1.0), (-1.0, 1.0)))
    front = side == "front"
    # launched along the surface (vz = grad z . (vx, vy) = 0.05 * 0.2); from below also 0.05 m/s into it
    p = ParticleParams(case="free", surface="plane", mu_1=0.3, t_end=0.15, dt=5e-4, x0=0.05, y0=0.0,
                       z0=(0.5 * 0.05 ** 2 - 0.2) - (PEN if front else 1e-4), vx0=0.2, vy0=0.1,
                       vz0=0.01 if front else 0.06, gravity=G if front else 0.0, eps_n=EPS_N if front else 1e4)
    law = particle_contact_law(p, surface=surf)
    e, b = RunParticle(p, contactLaw=law), simulate_particle(p, law=law)
    check_run(e, b, stick_and_slip=front)
    assert SLIP in set(b.trajectory["status"].astype(int))


MAPS_SCENE = dict(adhesion="orthotropic", eps_1=1e5, eps_2=1e4, net_angle=30.0, mu_1=0.3, vx0=0.3, vy0=0.2)


@pytest.mark.parametrize("return_map", ["seed", "exact", "radial"])
def test_return_maps_on_the_sphere(return_map):
    """Orthotropic adhesion (1e5 / 1e4 N/m at 30 deg to the chart's lines, so C F is no multiple of
    the identity and the maps differ) with isotropic friction in a spherical bowl: each map gives the
    same path on both engines; the point slides and sticks in every run. Measured e_x, e_v <= 3.5e-11.

    With orthotropic friction as well (mu 0.2 / 0.5) the seed map's kinks make Exudyn's plain Newton
    fail in a few steps (it cuts them: 305 steps for 300, same for the torus), where the reference's
    line search converges (README, reference docstring): the step sequences differ, so the paths do;
    exact and radial keep parity there too (test_parity_with_orthotropic_friction)."""
    e, b = both(scene("sphere", "inside", return_map=return_map, **MAPS_SCENE))
    check_run(e, b)


@pytest.mark.parametrize("return_map", ["exact", "radial"])
def test_parity_with_orthotropic_friction(return_map):
    e, b = both(scene("torus", "inside", return_map=return_map, friction="orthotropic", mu_1=0.2, mu_2=0.5,
                      **{k: v for k, v in MAPS_SCENE.items() if k != "mu_1"}))
    check_run(e, b)


def test_return_maps_differ():
    """The three maps are three laws in that scene (so the parity above tests three things)."""
    ends = {m: _X(simulate_particle(scene("sphere", "inside", return_map=m, **MAPS_SCENE)))[-1]
            for m in ("seed", "exact", "radial")}
    for a, b in (("seed", "exact"), ("exact", "radial"), ("seed", "radial")):
        assert np.linalg.norm(ends[a] - ends[b]) > 1e-5, (a, b, ends)


# ----------------------------------------------------------------------------------------------
# covariance and limits

def test_covariance_sphere_revolution_parametric():
    """The departure scene on the same sphere in three routes: Sphere (chart (phi, theta), closed-form
    projection), SurfaceOfRevolution (chart (phi, z), Newton in z) and ParametricSurface (the
    Sphere's chart written by hand, Newton from a grid search). Tolerance 1e-8 relative (e_x, e_v):
    the geometry is the same exactly; the routes differ in round-off, in the projection's Newton
    iterations and in the tangents' central differences (step relative to the chart's coordinates),
    so each engine's Newton (tolerance 1e-10) stops at iterates that differ at that level, and the
    sliding path carries it along. Measured e_x: 2.2e-12 (revolution), 1.6e-12 (parametric); the
    departure angles differ by 2.2e-8 and 1.1e-8 deg."""
    p = ParticleParams(t_end=1.0, dt=5e-4)
    ref = simulate_particle(p)
    for surface in ("revolution", "parametric"):
        other = simulate_particle(p.with_overrides(surface=surface))
        ex, ev = errors(other, ref)
        assert ex <= 1e-8 and ev <= 1e-8, (surface, ex, ev)
        assert abs(other.summary["departure_angle_deg"] - ref.summary["departure_angle_deg"]) < 1e-6


@pytest.mark.parametrize("side", ["outside", "inside"])
def test_cone_of_zero_half_angle_is_the_cylinder(side):
    """The same numbers to round-off (both engines): the cone's chart at slope 0 is the cylinder's
    term by term; the cylinder declares a constant metric and skips the parallel transport that the
    cone carries out with Christoffel symbols that vanish up to round-off. That round-off moves the
    iterate where each step's Newton (tolerance 1e-10) stops: measured 4e-16 in x, 2e-13 m/s in vx,
    4e-10 relative in the normal force; bound 1e-8 of the range of each vector (position, velocity)
    or scalar, as the other chart-parity tests here."""
    p = scene("cylinder", side)
    q = p.with_overrides(surface="cone", half_angle=0.0)
    for run in (simulate_particle, RunParticle):
        a, b = run(p), run(q)
        for group in (("x", "y", "z"), ("vx", "vy", "vz"), ("normal_force",), ("dissipated_energy",)):
            scale = max(np.abs(b.trajectory[k]).max() for k in group)     # of the vector, not a component
            for k in group:
                np.testing.assert_allclose(a.trajectory[k], b.trajectory[k], rtol=0, atol=1e-8 * scale, err_msg=k)


def test_large_sphere_tends_to_the_plane():
    """A point sliding over the top of a sphere of radius R against the same on the plane z = 0
    (positions relative to the top): the difference of the paths is the curvature's effect, gravity's
    tangential part g s / R and the normal force's m v^2 / R, so it falls like 1/R. Measured
    (reference, 0.3 s): R * max|dx| = 0.04460, 0.04412, 0.04407 m^2 for R = 10, 100, 1000."""
    base = dict(case="free", mu_1=0.3, t_end=0.3, dt=5e-4, vx0=0.0, vy0=1.0, vz0=0.0, x0=0.0, y0=0.0)
    flat = simulate_particle(ParticleParams(surface="plane", z0=-PEN, **base))
    Xp = _X(flat)
    scaled = []
    for radius in (10.0, 100.0, 1000.0):
        curved = simulate_particle(ParticleParams(surface="sphere", radius=radius, z0=radius - PEN, **base))
        Xs = _X(curved) - np.array([0.0, 0.0, radius])
        scaled.append(radius * np.max(np.linalg.norm(Xs - Xp, axis=1)))
    assert scaled[0] > 1e-4                     # not zero: the test can see the curvature
    np.testing.assert_allclose(scaled[1:], scaled[0], rtol=0.05)


# ----------------------------------------------------------------------------------------------
# moving master: objectivity at system level

def _moving_master_run(p, velocity, omega, master_mass=1e9, implementation="auto", jacobian="analytic", stats=None):
    """The scene p with its surface carried by a rigid body (RotVecLG node, mass master_mass, a
    sphere's inertia, no gravity) that starts at c0 = (0.3, -0.2, 0.1) with the velocity ``velocity``
    and the angular velocity ``omega`` (world): it moves uniformly (a torque-free sphere; the
    contact's reaction moves it by m/M ~ 1e-10). The point starts at c0 + x0 with V + v0 + omega x x0.
    In the rotating case the point also gets the inertial forces of the master's frame and gravity
    turned with it, m [Q g + 2 omega x (v - V - omega x r) + omega x (omega x r)], r = x - c, from the
    master's actual state (a GenericODE2 on both nodes), so the path relative to the master solves
    the fixed master's equations. implementation, jacobian: of the contact (CreateAnisotropicContact);
    stats: a dict to receive 'steps', 'newton_iterations' and 'implementation'. Returns (t, x relative
    to the master (n, 3))."""
    from exudyn.itemInterface import ObjectGenericODE2, SensorNode
    from exudyn.rigidBodyUtilities import InertiaSphere, RotationVector2RotationMatrix
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    c0 = np.array([0.3, -0.2, 0.1])
    V, W = np.asarray(velocity, float), np.asarray(omega, float)
    oM = mbs.CreateRigidBody(inertia=InertiaSphere(master_mass, 1.0), referencePosition=c0.tolist(),
                             initialVelocity=V.tolist(), initialAngularVelocity=W.tolist(),
                             nodeType=exu.NodeType.RotationRotationVector, gravity=[0.0, 0.0, 0.0])
    nM = mbs.GetObject(oM)["nodeNumber"]
    x0, v0 = initial_state(p)
    oP = mbs.CreateMassPoint(referencePosition=(c0 + x0).tolist(),
                             initialVelocity=(V + v0 + np.cross(W, x0)).tolist(),
                             mass=p.mass, gravity=[0.0, 0.0, 0.0])
    nP = mbs.GetObject(oP)["nodeNumber"]
    g = gravity_vector(p)
    m = p.mass

    def inertial(mbs, t, itemNumber, q, q_t):
        q, q_t = np.asarray(q), np.asarray(q_t)
        xp, vp = c0 + x0 + q[0:3], q_t[0:3]
        c = c0 + q[3:6]
        Q = RotationVector2RotationMatrix(q[6:9])
        w = Q @ q_t[6:9]                         # Lie-group node: local angular velocity
        r = xp - c
        f = np.zeros(9)
        f[0:3] = m * (Q @ g + 2.0 * np.cross(w, vp - q_t[3:6] - np.cross(w, r)) + np.cross(w, np.cross(w, r)))
        return f

    mbs.AddObject(ObjectGenericODE2(nodeNumbers=[nP, nM], massMatrix=np.zeros((9, 9)), forceUserFunction=inertial))
    contact = mbs.CreateAnisotropicContact(bodyNumber=oP, localPoints=[[0.0, 0.0, 0.0]],
                                           contactLaw=particle_contact_law(p), masterBodyNumber=oM, show=False,
                                           implementation=implementation, jacobian=jacobian)
    sens = {k: mbs.AddSensor(SensorNode(nodeNumber=n, storeInternal=True, outputVariableType=getattr(
        exu.OutputVariableType, o))) for k, n, o in (("P", nP, "Position"), ("C", nM, "Position"),
                                                     ("A", nM, "RotationMatrix"))}
    mbs.Assemble()
    from exu_aniso.engines.exudyn_adapter.runner import SimulationSettingsFor
    # Newton tolerance 1e-8 instead of the scene's 1e-10: away from the origin the round-off of the
    # absolute coordinates (x - c at |x| ~ 0.5 m: 1e-16 m) times eps_n is ~1e-10 of the contact force,
    # and at 1e-10 Exudyn's Newton then fails now and then and cuts the step (246 steps for 200 with
    # the master at rest at c0; 201 with c0 = 0)
    ss, st = SimulationSettingsFor(p, newtonTolerance=1e-8)
    mbs.SolveDynamic(ss, solverType=st)
    if stats is not None:
        it = mbs.sys["dynamicSolver"].it
        stats.update(steps=int(it.currentStepIndex) - 1, newton_iterations=int(it.newtonStepsCount),
                     implementation=contact["implementation"])
    P = mbs.GetSensorStoredData(sens["P"])
    C = mbs.GetSensorStoredData(sens["C"])[:, 1:]
    Q = mbs.GetSensorStoredData(sens["A"])[:, 1:].reshape(-1, 3, 3)
    return P[:, 0], np.einsum("nji,nj->ni", Q, P[:, 1:] - C)


def _path_error(p, velocity, omega):
    fixed = _X(simulate_particle(p))
    t, rel = _moving_master_run(p, velocity, omega)
    assert len(t) == len(fixed)
    return float(np.max(np.linalg.norm(rel - fixed, axis=1)) / np.max(np.linalg.norm(fixed - fixed[0], axis=1)))


# a moving master's kernel per surface (26 s each cold): the torus's in the slow run
MOVING_SURFACES = ["sphere", pytest.param("torus", marks=pytest.mark.slow)]


@pytest.mark.parametrize("surface", MOVING_SURFACES)
def test_uniformly_moving_master_changes_nothing(surface):
    """Uniform translation (Galilean): the trapezoidal rule is exactly invariant, so the relative
    path equals the fixed master's to the Newton tolerance (the moving master's Jacobian changes only
    the iterates). Tolerance 1e-6 (e_x); measured 9.3e-12 (sphere), 7.1e-12 (torus) on the compiled
    route (its analytic Jacobian; 9.8e-12 and 1.1e-11 on the numpy route, Exudyn's numerical one)."""
    p = scene(surface, "inside", t_end=0.1)
    assert _path_error(p, (0.5, -0.3, 0.2), (0.0, 0.0, 0.0)) <= 1e-6


@pytest.mark.parametrize("surface", MOVING_SURFACES)
def test_uniformly_rotating_master_converges_to_the_fixed_one(surface):
    """Uniform rotation (2 rad/s about a skew axis, with a translation): the rate form of the law is
    objective, and what is left is the time discretisation: the trapezoidal rule applied in the
    rotating frame is not the same discrete map as in the master's frame, an O(dt^2) difference.
    Measured e_x at dt = 5e-4, 2.5e-4, 1.25e-4 s: 4.04e-6, 1.02e-6, 2.55e-7 (sphere), 3.91e-6, 1.01e-6,
    2.52e-7 (torus): a factor 4 per halving."""
    w = 2.0 * np.array([0.3, 0.5, 1.0]) / np.linalg.norm([0.3, 0.5, 1.0])
    errs = [_path_error(scene(surface, "inside", t_end=0.1, dt=dt), (0.5, -0.3, 0.2), w) for dt in (5e-4, 2.5e-4)]
    assert errs[0] < 1e-5, errs
    assert 0.2 * errs[0] < errs[1] < 0.3 * errs[0], errs        # second order: a factor 4
