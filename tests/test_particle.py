"""Mass points as slaves (ObjectMassPoint through mbs.CreateAnisotropicContact(bodyNumber=<mass
point>, localPoints=[[0, 0, 0]])) on curved surfaces, against textbook mechanics:

* a point coasting inside a spherical cavity without gravity: N = m v^2 / R, so
  dv/dt = -mu v^2 / R and v = v0 exp(-mu psi) with psi the angle travelled;
* a point sliding down a rough sphere from its top: v' = g sin(theta) - mu N / m with
  N = m (g cos(theta) - v^2 / R); it leaves the sphere where N = 0 (the departure angle, solved
  here with scipy);
* a mass point on an inclined cylinder's top line slides at g (sin(a) - mu cos(a)).

Penalty effects are bounded by the tolerances, which the step refinement shows to fall."""
from __future__ import annotations

import math

import numpy as np
import pytest

exu = pytest.importorskip("exudyn")

import exu_aniso  # noqa: E402,F401
from exu_aniso import Adhesion, Friction  # noqa: E402
from exu_aniso.geometry import Cylinder, Sphere  # noqa: E402


def _run(surface, r0, v0, mass, mu, eps_n, eps_t, dt, t_end, gravity=(0.0, 0.0, 0.0), implementation="auto",
         stop=None):
    from exudyn.utilities import SensorNode
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    o = mbs.CreateMassPoint(referencePosition=list(r0), initialVelocity=list(v0), mass=mass, gravity=list(gravity))
    mbs.CreateAnisotropicContact(bodyNumber=o, localPoints=[[0.0, 0.0, 0.0]], surface=surface,
                                 adhesion=Adhesion.isotropic(eps_t), friction=Friction.isotropic(mu),
                                 normalStiffness=eps_n, returnMap="exact", implementation=implementation, show=False)
    n = mbs.GetObject(o)["nodeNumber"]
    sP = mbs.AddSensor(SensorNode(nodeNumber=n, outputVariableType=exu.OutputVariableType.Position, storeInternal=True))
    sV = mbs.AddSensor(SensorNode(nodeNumber=n, outputVariableType=exu.OutputVariableType.Velocity, storeInternal=True))
    mbs.Assemble()
    s = exu.SimulationSettings()
    s.timeIntegration.numberOfSteps = int(round(t_end / dt))
    s.timeIntegration.endTime = t_end
    s.timeIntegration.newton.relativeTolerance = 1e-10
    s.timeIntegration.verboseMode = 0
    s.solution.file.write = False
    s.solution.sensors.writePeriod = dt                 # every step (the default samples every 10 ms)
    mbs.SolveDynamic(s, solverType=exu.DynamicSolverType.TrapezoidalIndex2)
    return mbs.GetSensorStoredData(sP), mbs.GetSensorStoredData(sV)


def _cavity(dt, implementation="auto"):
    R, v0, mu = 0.5, 2.0, 0.3
    P, V = _run(Sphere(R, side="inside"), (R, 0.0, 0.0), (0.0, v0, 0.0), 0.1, mu, 1e6, 1e5, dt, 0.5,
                implementation=implementation)
    psi = np.unwrap(np.arctan2(P[:, 2], P[:, 1]))
    psi -= psi[0]
    speed = np.linalg.norm(V[:, 1:], axis=1)
    return np.max(np.abs(speed - v0 * np.exp(-mu * psi)) / (v0 * np.exp(-mu * psi))), psi[-1], P, V


def test_coasting_in_a_spherical_cavity():
    err, psi_end, P, V = _cavity(1e-4)
    assert psi_end > 1.5                    # a quarter turn and more, slowing down
    assert err < 1e-2, err                  # penalty (m v^2 / R eps_n ~ 1e-6 m) and the step
    err_fine, _, _, _ = _cavity(3e-5)
    assert err_fine < 0.5 * err, (err, err_fine)


def test_mass_point_compiled_equals_numpy_route():
    _, _, P1, V1 = _cavity(1e-4, implementation="compiled")
    _, _, P2, V2 = _cavity(1e-4, implementation="numpy")
    np.testing.assert_allclose(P1, P2, rtol=0, atol=1e-12)
    np.testing.assert_allclose(V1, V2, rtol=0, atol=1e-10)


def _departure_angle(mu, R, g=9.81, v0=0.5):
    """theta (from the top) where N = m (g cos(theta) - v^2/R) reaches 0, sliding with friction."""
    from scipy.integrate import solve_ivp

    def rhs(t, y):
        th, v = y
        N = g * math.cos(th) - v * v / R
        return [v / R, g * math.sin(th) - mu * max(N, 0.0)]

    def leave(t, y):
        return g * math.cos(y[0]) - y[1] ** 2 / R
    leave.terminal = True
    sol = solve_ivp(rhs, (0.0, 10.0), [0.0, v0], events=leave, rtol=1e-11, atol=1e-13)
    return float(sol.y_events[0][0][0])


@pytest.mark.parametrize("mu", [0.05, 0.15])
def test_departure_from_a_rough_sphere(mu):
    """The chart's pole is put on the x axis so the path over the top (the y-z plane) stays on its
    equator, away from the poles."""
    R, g, v0 = 0.5, 9.81, 0.5
    sphere = Sphere(R, axis_direction=(1.0, 0.0, 0.0), side="outside")
    eps_n = 1e6
    z0 = R - 0.1 * (g - v0 * v0 / R) / eps_n          # the penetration that carries N = m (g - v0^2/R)
    P, V = _run(sphere, (0.0, 0.0, z0), (0.0, v0, 0.0), 0.1, mu, eps_n, 1e5, 2e-4, 1.5, gravity=(0, 0, -g))
    r = np.linalg.norm(P[:, 1:], axis=1)
    theta = np.arctan2(P[:, 2], P[:, 3])
    left = np.nonzero(r > R + 1e-4)[0]                # clearly off the surface
    assert left.size, "the point never left the sphere"
    k = left[0]
    # where the normal force vanished: the last sample still pressed (r < R)
    pressed = np.nonzero(r[:k] < R)[0][-1]
    expected = _departure_angle(mu, R, g, v0)
    print(f"mu {mu}: departure {math.degrees(theta[pressed]):.3f} deg, oracle {math.degrees(expected):.3f} deg")
    assert abs(theta[pressed] - expected) < math.radians(0.1)      # measured: 0.03 deg (penalty, dt)


def test_sliding_down_an_inclined_cylinder():
    """A mass point on the top line of a cylinder whose axis is inclined by a: along the axis it
    accelerates at g (sin(a) - mu cos(a)) (the normal force is m g cos(a))."""
    a, mu, g, R = math.radians(30.0), 0.3, 9.81, 0.2
    axis = np.array([math.cos(a), 0.0, -math.sin(a)])          # down the slope
    up = np.array([math.sin(a), 0.0, math.cos(a)])             # the top line's normal
    eps_n = 1e6
    r0 = R * up - up * (0.1 * g * math.cos(a) / eps_n)
    P, V = _run(Cylinder(R, axis_direction=tuple(axis), side="outside"), r0, (0.0, 0.0, 0.0), 0.1, mu, eps_n, 1e6,
                1e-4, 0.3, gravity=(0, 0, -g))
    s = (P[:, 1:] - r0) @ axis
    t = P[:, 0]
    acc = np.polyfit(t[t > 0.05], s[t > 0.05], 2)[0] * 2.0
    expected = g * (math.sin(a) - mu * math.cos(a))
    assert acc == pytest.approx(expected, rel=1e-3), (acc, expected)
