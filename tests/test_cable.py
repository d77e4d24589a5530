"""ANCF cables as contact slaves: ObjectANCFCable2D and ObjectANCFCable through
mbs.CreateAnisotropicContact(bodyNumber=<element or list of elements>, localPoints=[[x, 0, 0], ...]).

Oracles:
1. kinematics: the linear slave's positions and velocities (Exudyn's Hermite shape functions,
   x = S q) equal Exudyn's own output (GetObjectOutputBody Position / Velocity) at random states;
2. the analytic Jacobian equals central differences of the force user function (both routes, every
   return map, with and without normal damping), and the compiled route equals the numpy route to
   round-off, in the Jacobian and over a short run;
3. physics: a straight cable lying on a plane under gravity carries its weight (sum of the normal
   forces = m g); on an incline of angle a with isotropic mu it stays for mu > tan(a) and slides at
   g (sin(a) - mu cos(a)) for mu < tan(a); the dissipation is >= 0 and never decreases; Exudyn's
   cable energies (KineticEnergy, PotentialEnergy) close the ledger of a contact run;
4. Newton iterations: the analytic Jacobian needs no more than Exudyn's numerical one;
5. bad input gets an error naming the parameter and the rule.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

exu = pytest.importorskip("exudyn")
from exudyn.itemInterface import (NodePoint2DSlope1, NodePointSlope1, ObjectANCFCable,  # noqa: E402
                                  ObjectANCFCable2D, ObjectMassPoint2D, NodePoint2D, SensorBody, SensorNode)

import exu_aniso  # noqa: E402,F401
from exu_aniso import Adhesion, Friction  # noqa: E402
from exu_aniso.engines.exudyn_adapter import contact_set, create_contact, slaves  # noqa: E402
from exu_aniso.kernel.contact_law import ContactLaw  # noqa: E402
from exu_aniso.geometry import Plane  # noqa: E402

SOS = exu.ConfigurationType.StartOfStep
H_LENGTH = 1e-9          # FD step of a coordinate (positions [m], slopes [-]); penetrations ~1e-5 m
H_VELOCITY = 1e-7
RTOL = 1e-6
RHO_A, EA, EI = 0.2, 1e5, 1e-3          # rope: mass per length [kg/m], axial [N], bending [N m^2] stiffness


def tilted_plane(angle):
    """The plane through the origin whose normal is (-sin a, cos a, 0): the x axis turned by a about z
    (the Plane of exu_aniso.geometry with its local frame turned; xi1 runs down-slope reversed, along
    (cos a, sin a, 0), xi2 along -z)."""
    p = Plane()
    c, s = math.cos(angle), math.sin(angle)
    p.params = p.params._replace(ex=(c, s, 0.0), ey=(0.0, 0.0, -1.0), ez=(-s, c, 0.0))
    return p


def cable2d(mbs, start, direction, length, n_elements, q0=None, v0=None):
    """A straight ObjectANCFCable2D rope of n_elements; returns (elements, nodes)."""
    d = np.asarray(direction, dtype=float) / np.linalg.norm(direction)
    L = length / n_elements
    nodes = []
    for i in range(n_elements + 1):
        p = np.asarray(start, dtype=float) + i * L * d
        kw = {}
        if q0 is not None:
            kw["initialCoordinates"] = list(q0[i])
        if v0 is not None:
            kw["initialVelocities"] = list(v0[i])
        nodes.append(mbs.AddNode(NodePoint2DSlope1(referenceCoordinates=[p[0], p[1], d[0], d[1]], **kw)))
    elements = [mbs.AddObject(ObjectANCFCable2D(nodeNumbers=[nodes[i], nodes[i + 1]], length=L, massPerLength=RHO_A,
                                                axialStiffness=EA, bendingStiffness=EI))
                for i in range(n_elements)]
    return elements, nodes


# --- 1. kinematics against Exudyn ----------------------------------------------------------------

@pytest.mark.parametrize("dim", [2, 3])
def test_points_equal_exudyn_output(dim):
    rng = np.random.default_rng(1)
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    L = 0.7
    Node, Obj = (NodePoint2DSlope1, ObjectANCFCable2D) if dim == 2 else (NodePointSlope1, ObjectANCFCable)
    nodes, elements = [], []
    for i in range(3):
        ref = np.concatenate([[i * L, 0.1 * i, 0.0][:dim], [1.0, 0.1, 0.05][:dim]])
        nodes.append(mbs.AddNode(Node(referenceCoordinates=list(ref),
                                      initialCoordinates=list(rng.normal(scale=0.05, size=2 * dim)),
                                      initialVelocities=list(rng.normal(scale=0.5, size=2 * dim)))))
    for i in range(2):
        elements.append(mbs.AddObject(Obj(nodeNumbers=[nodes[i], nodes[i + 1]], length=L, massPerLength=1.0,
                                          axialStiffness=100.0, bendingStiffness=1.0)))
    mbs.Assemble()
    slave = slaves.LinearSlave(mbs, elements)
    assert slave.n == 3 * 2 * dim
    b = np.array([[x, 0.0, 0.0] for x in (0.0, 0.13, L / 2, 0.61, L)])
    x, v, Jp, _ = slave.points(slave.q0, slave.v0, b)
    for e, o in enumerate(elements):
        for j, bj in enumerate(b):
            k = e * len(b) + j
            pos = mbs.GetObjectOutputBody(o, exu.OutputVariableType.Position, localPosition=list(bj))
            vel = mbs.GetObjectOutputBody(o, exu.OutputVariableType.Velocity, localPosition=list(bj))
            np.testing.assert_allclose(x[k], pos, rtol=0, atol=1e-14)
            np.testing.assert_allclose(v[k], vel, rtol=0, atol=1e-14)
    # linear in q: Jp (ref + q) = x for every point
    np.testing.assert_allclose(np.einsum("kij,j->ki", Jp, slave.ref + slave.q0), x, rtol=0, atol=1e-14)


# --- 2. Jacobian: finite differences and route parity ---------------------------------------------

def _scene(dim, implementation, return_map, d_N, seed=5):
    """A 2-element cable pressed into a plane at a random state (some points stick, some slide):
    2D cable on a tilted Plane (its local frame turned), 3D cable on the Plane z = 0."""
    rng = np.random.default_rng(seed)
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    L = 0.3
    if dim == 2:
        a = 0.3
        surface = tilted_plane(a)
        t, nrm = np.array([math.cos(a), math.sin(a)]), np.array([-math.sin(a), math.cos(a)])
        nodes = [mbs.AddNode(NodePoint2DSlope1(referenceCoordinates=list(np.concatenate([i * L * t, t]))))
                 for i in range(3)]
        Obj = ObjectANCFCable2D
    else:
        surface = Plane()
        t, nrm = np.array([1.0, 0.0, 0.0]), np.array([0.0, 0.0, 1.0])
        nodes = [mbs.AddNode(NodePointSlope1(referenceCoordinates=list(np.concatenate([i * L * t, t]))))
                 for i in range(3)]
        Obj = ObjectANCFCable
    elements = [mbs.AddObject(Obj(nodeNumbers=[nodes[i], nodes[i + 1]], length=L, massPerLength=1.0,
                                  axialStiffness=1e3, bendingStiffness=1.0)) for i in range(2)]
    law = ContactLaw(surface, Adhesion.orthotropic(2e4, 5e3, angle=0.4), Friction.orthotropic(0.2, 0.5, angle=0.4),
                     1e5, d_N, return_map)
    points = [[x, 0.0, 0.0] for x in (0.04, 0.15, 0.26)]
    c = create_contact.CreateAnisotropicContact(mbs, elements, points, contactLaw=law, implementation=implementation,
                                      storeSensors=False)
    assert c["implementation"] == implementation
    cs = mbs.variables["exu_aniso_contact_sets"][-1]
    mbs.Assemble()
    nc = 2 * dim
    q = np.zeros(cs.slave.n)
    for i in range(3):                  # every node pushed 1-3e-5 into the plane, slopes perturbed
        tangential = rng.normal(scale=1e-3, size=dim)
        tangential -= (tangential @ nrm) * nrm
        q[i * nc:i * nc + dim] = -rng.uniform(1e-5, 3e-5) * nrm + tangential
        q[i * nc + dim:(i + 1) * nc] = rng.normal(scale=1e-5, size=dim)
    qt = rng.normal(scale=0.1, size=cs.slave.n)
    for i in range(3):                  # normal velocities small: the dashpot must not lift a point
        v = qt[i * nc:i * nc + dim]
        qt[i * nc:i * nc + dim] = v - (v @ nrm) * nrm + rng.normal(scale=0.005) * nrm
        qt[i * nc + dim:(i + 1) * nc] *= 0.01
    st = cs.state(mbs, q, qt, None, tangent=False)[0]
    H = st.history.copy()
    N = np.abs(H[:, 8])
    assert np.all(N > 0)
    K = cs.K
    d = rng.normal(size=(K, 2))
    d /= np.linalg.norm(d, axis=1)[:, None]
    H[:, 0:2] = np.where(np.arange(K) % 2 == 0, 0.02, 3.0)[:, None] * N[:, None] * d
    H[:, 2:4] += rng.normal(scale=1e-7, size=(K, 2))
    status = contact_set.ContactSet.state(cs, mbs, q, qt, H, tangent=False)[0].status
    assert set(status) == {1, 2}, status
    data = np.asarray(mbs.systemData.GetDataCoordinates(configuration=SOS), dtype=float)
    data[np.asarray(mbs.systemData.GetNodeLTGData(cs.nData), dtype=int)] = H.ravel()
    mbs.systemData.SetDataCoordinates(data, configuration=SOS)
    return mbs, cs, q, qt, H


def _fd(cs, mbs, q, qt, H):
    def Q(qq, vv):
        return np.array(cs.force(mbs, 0.0, 0, qq, vv), dtype=float)
    status0 = contact_set.ContactSet.state(cs, mbs, q, qt, H, tangent=False)[0].status
    n = len(q)
    Jq, Jv = np.zeros((n, n)), np.zeros((n, n))
    for c in range(n):
        e = np.zeros(n)
        e[c] = H_LENGTH
        for qq in (q + e, q - e):
            np.testing.assert_array_equal(contact_set.ContactSet.state(cs, mbs, qq, qt, H, tangent=False)[0].status, status0)
        Jq[:, c] = -(Q(q + e, qt) - Q(q - e, qt)) / (2 * H_LENGTH)
        ev = e * (H_VELOCITY / H_LENGTH)
        Jv[:, c] = -(Q(q, qt + ev) - Q(q, qt - ev)) / (2 * H_VELOCITY)
    return Jq, Jv


@pytest.mark.parametrize("d_N", [0.0, 40.0], ids=["undamped", "damped"])
@pytest.mark.parametrize("return_map", ["seed", "exact", "radial"])
@pytest.mark.parametrize("implementation", ["numpy", "compiled"])
@pytest.mark.parametrize("dim", [2, 3])
def test_cable_jacobian_equals_finite_differences(dim, implementation, return_map, d_N):
    mbs, cs, q, qt, H = _scene(dim, implementation, return_map, d_N)
    Jq_fd, Jv_fd = _fd(cs, mbs, q, qt, H)
    Jq = np.array(cs.jacobian(mbs, 0.0, 0, q, qt, 1.0, 0.0), dtype=float)
    Jv = np.array(cs.jacobian(mbs, 0.0, 0, q, qt, 0.0, 1.0), dtype=float)
    Qmax = np.abs(np.array(cs.force(mbs, 0.0, 0, q, qt))).max()
    floor_q = 100 * np.finfo(float).eps * Qmax / H_LENGTH
    floor_v = 100 * np.finfo(float).eps * Qmax / H_VELOCITY
    eq = max(np.abs(Jq - Jq_fd).max() - floor_q, 0.0) / np.abs(Jq_fd).max()
    assert eq <= RTOL, f"-dQ/dq differs from FD by {eq:.2e} relative"
    if d_N > 0.0 and dim == 3:          # the 3D cable's points move along the normal: damping acts
        assert np.abs(Jv_fd).max() > 1e3 * floor_v
    ev = max(np.abs(Jv - Jv_fd).max() - floor_v, 0.0) / max(np.abs(Jv_fd).max(), floor_v)
    assert ev <= RTOL, f"-dQ/dq_t differs from FD by {ev:.2e} relative"


@pytest.mark.parametrize("dim", [2, 3])
def test_compiled_equals_numpy_jacobian_and_force(dim):
    out = {}
    for impl in ("numpy", "compiled"):
        mbs, cs, q, qt, H = _scene(dim, impl, "exact", 40.0)
        out[impl] = (np.array(cs.force(mbs, 0.0, 0, q, qt)), np.array(cs.jacobian(mbs, 0.0, 0, q, qt, 0.7, 0.3)))
    for a, b in zip(out["numpy"], out["compiled"]):
        assert np.abs(a - b).max() <= 1e-10 * np.abs(a).max()


# --- 3. physics ----------------------------------------------------------------------------------

def _rope_on_incline(angle, mu, t_end, dt=2e-4, implementation="auto", jacobian="analytic", n_elements=4,
                     length=1.0, solver=exu.DynamicSolverType.TrapezoidalIndex2, normalDamping=2.0,
                     newton_tolerance=1e-10):
    """A straight 2D rope lying on the incline (normal (-sin a, cos a, 0)) under gravity -y, pressed
    in by the penetration that carries its weight; returns (time, mean displacement along the slope,
    sum of normal tractions per sample, dissipation per sample, energies, contact dict, mbs,
    solver)."""
    g = 9.81
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    t = np.array([math.cos(angle), math.sin(angle)])
    nrm = np.array([-math.sin(angle), math.cos(angle)])
    n_points = 3
    eps_N = 1e4
    K = n_points * n_elements
    pen = RHO_A * length * g * math.cos(angle) / (K * eps_N)
    q0 = [list(-pen * nrm) + [0.0, 0.0]] * (n_elements + 1)
    elements, nodes = cable2d(mbs, (0, 0), t, length, n_elements, q0=q0)
    Lel = length / n_elements
    for o in elements:
        mbs.AddLoad(exu.itemInterface.LoadMassProportional(
            markerNumber=mbs.AddMarker(exu.itemInterface.MarkerBodyMass(bodyNumber=o)), loadVector=[0, -g, 0]))
    c = create_contact.CreateAnisotropicContact(mbs, elements, [[(i + 0.5) * Lel / n_points, 0, 0] for i in range(n_points)],
                                      surface=tilted_plane(angle), adhesion=Adhesion.isotropic(1e4),
                                      friction=Friction.isotropic(mu), normalStiffness=eps_N,
                                      normalDamping=normalDamping,
                                      implementation=implementation, jacobian=jacobian, storeHistory=True)
    sN = [mbs.AddSensor(SensorNode(nodeNumber=n, outputVariableType=exu.OutputVariableType.Coordinates,
                                   storeInternal=True)) for n in nodes]
    sV = [mbs.AddSensor(SensorNode(nodeNumber=n, outputVariableType=exu.OutputVariableType.Coordinates_t,
                                   storeInternal=True)) for n in nodes]
    sE = [mbs.AddSensor(SensorBody(bodyNumber=o, localPosition=[0, 0, 0], storeInternal=True,
                                   outputVariableType=getattr(exu.OutputVariableType, v)))
          for o in elements for v in ("KineticEnergy", "PotentialEnergy")]
    mbs.Assemble()
    s = exu.SimulationSettings()
    s.timeIntegration.numberOfSteps = int(round(t_end / dt))
    s.timeIntegration.endTime = t_end
    s.timeIntegration.newton.relativeTolerance = newton_tolerance
    s.timeIntegration.newton.absoluteTolerance = newton_tolerance
    s.timeIntegration.verboseMode = 0
    s.solution.file.write = False
    s.solution.sensors.writePeriod = dt
    s.timeIntegration.newton.useModifiedNewton = False
    mbs.SolveDynamic(s, solverType=solver, storeSolver=True)
    H = mbs.GetSensorStoredData(c["sHistory"])
    time = H[:, 0]
    H = H[:, 1:].reshape(len(time), -1, 9)
    Q = np.array([mbs.GetSensorStoredData(x)[:, 1:] for x in sN])           # (nodes, n, 4)
    slide = np.mean(Q[:, :, 0:2] @ t, axis=0)
    diss = mbs.GetSensorStoredData(c["sDissipation"])[:, 1]
    E = sum(mbs.GetSensorStoredData(x)[:, 1] for x in sE)
    # contact points per sample (the set's own linear map), for the ledger
    cs = mbs.variables["exu_aniso_contact_sets"][-1]
    Qt = np.array([mbs.GetSensorStoredData(x)[:, 1:] for x in sV])
    q_all, qt_all = Q.transpose(1, 0, 2).reshape(len(time), -1), Qt.transpose(1, 0, 2).reshape(len(time), -1)
    XV = [cs.slave.points(qq, vv, cs.points)[:2] for qq, vv in zip(q_all, qt_all)]
    mbs.variables["test_points"] = (np.array([a for a, _ in XV]), np.array([b for _, b in XV]), H)
    return time, slide, H[:, :, 8].sum(axis=1), diss, E, c, mbs, Q


def test_rope_on_a_plane_carries_its_weight():
    # normal damping near critical for a point's share of the mass (2 sqrt(eps_N m_k) = 26 N s/m)
    time, slide, N, diss, E, c, mbs, _ = _rope_on_incline(0.0, 0.3, 0.1, normalDamping=20.0)
    W = RHO_A * 1.0 * 9.81
    assert -N[-1] == pytest.approx(W, rel=1e-6)          # static: the normal tractions carry the weight
    assert np.max(np.abs(slide)) < 1e-9                  # nothing drives it sideways


@pytest.mark.parametrize("implementation", ["compiled", "numpy"])
def test_rope_on_an_incline_sticks_above_tan_alpha(implementation):
    a = math.radians(20.0)
    mu = 1.3 * math.tan(a)
    time, slide, N, diss, E, c, mbs, _ = _rope_on_incline(a, mu, 0.2, implementation=implementation)
    W = RHO_A * 9.81
    # held by the adhesion springs only: m g sin(a) / (K eps_T) per point, 12 points
    creep = W * math.sin(a) / (12 * 1e4)
    # released from T = 0 the rope swings on its adhesion springs (twice the static creep, and a little
    # slip at the first swing, where the spring force overshoots mu N); sliding would cover
    # g (sin a - mu cos a) t^2 / 2 ~ 1e-2 m in these 0.2 s at mu = 0.6 tan(a)
    assert np.max(np.abs(slide)) < 4.0 * creep, (np.max(np.abs(slide)), creep)
    assert np.all(np.diff(diss) >= -1e-15)
    assert diss[-1] < mu * W * math.cos(a) * 4.0 * creep       # friction over at most the bounded swing
    half = len(time) // 2
    assert diss[-1] - diss[half] <= 1e-3 * diss[-1]             # and no slip in the second half: it sticks


def test_rope_on_an_incline_slides_below_tan_alpha():
    a = math.radians(20.0)
    mu = 0.6 * math.tan(a)
    time, slide, N, diss, E, c, mbs, _ = _rope_on_incline(a, mu, 0.3)
    late = time > 0.1
    acc = 2.0 * np.polyfit(time[late], slide[late], 2)[0]
    expected = -9.81 * (math.sin(a) - mu * math.cos(a))         # down the slope: -t
    assert acc == pytest.approx(expected, rel=2e-3), (acc, expected)
    # energy: dissipation >= 0 and never decreasing; the ledger (Exudyn's cable energies, gravity,
    # contact stored + dissipated) closes
    assert np.all(np.diff(diss) >= -1e-14) and diss[-1] > 0.0
    from exu_aniso.engines import energy
    height = slide * math.sin(a)                        # of the centre of mass (a straight rope, along t)
    X, V, Hs = mbs.variables["test_points"]
    stored, dissipated = energy.contact_energy(c["law"], X, V, Hs)     # friction + dashpot, penalty + adhesion
    assert np.all(dissipated >= -1e-15)
    # change of cable (kinetic + elastic) + gravity potential + contact stored + dissipated = 0
    total = (E - E[0]) + RHO_A * 9.81 * (height - height[0]) + (stored - stored[0]) + dissipated
    scale = RHO_A * 9.81 * abs(height[-1] - height[0])
    assert abs(total[-1]) < 1e-2 * scale, (total[-1], scale)


def test_compiled_equals_numpy_over_a_run():
    """30 steps of the sliding rope: the two routes agree to round-off over the first 20 steps
    (measured 3e-18 m), then part at the Newton tolerance: their residuals differ by round-off, and
    once one route stops Newton an iteration earlier than the other (step 26 of this run, measured
    since the numpy route sums Jp^T f as a matrix product; step 40 before) the difference is the
    Newton tolerance's (1.4e-8 m at most, measured), carried on by the sliding dynamics."""
    a = math.radians(20.0)
    runs = [_rope_on_incline(a, 0.6 * math.tan(a), 0.006, implementation=impl) for impl in ("compiled", "numpy")]
    assert np.abs(runs[0][7]).max() > 1e-5                       # it moved
    np.testing.assert_allclose(runs[0][7][:, :21], runs[1][7][:, :21], rtol=0, atol=1e-15)
    np.testing.assert_allclose(runs[0][7], runs[1][7], rtol=0, atol=1e-7)
    np.testing.assert_allclose(runs[0][3], runs[1][3], rtol=0, atol=1e-9)
    assert runs[0][3][-1] > 0.0


def test_analytic_jacobian_needs_no_more_newton_iterations():
    """At Newton tolerance 1e-9 (no step is reduced with either Jacobian; measured 375 analytic and
    379 numerical iterations in 250 steps). At 1e-10 both routes hit the round-off floor of the
    residual in some steps and Exudyn reduces them (356 and 349 steps): not a Jacobian comparison."""
    a = math.radians(20.0)
    its = {}
    for jac in ("analytic", "numerical"):
        mbs = _rope_on_incline(a, 0.6 * math.tan(a), 0.05, jacobian=jac, newton_tolerance=1e-9)[6]
        it = mbs.sys["dynamicSolver"].it
        its[jac] = (int(it.newtonStepsCount), int(it.currentStepIndex))
    assert its["analytic"][1] == its["numerical"][1] == 251, its
    assert its["analytic"][0] <= its["numerical"][0], its


# --- 5. bad input ----------------------------------------------------------------------------------

def test_bad_cable_input_is_named():
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    elements, _ = cable2d(mbs, (0, 0), (1, 0), 1.0, 2)
    n = mbs.AddNode(NodePoint2D(referenceCoordinates=[0, 0]))
    o = mbs.AddObject(ObjectMassPoint2D(nodeNumber=n, mass=1.0))
    kw = dict(surface=Plane(), adhesion=Adhesion.isotropic(1e3), friction=Friction.isotropic(0.3),
              normalStiffness=1e4)
    with pytest.raises(ValueError, match=r"localPoints x of an ANCF cable element must lie in \[0, L\]"):
        mbs.CreateAnisotropicContact(bodyNumber=elements, localPoints=[[0.6, 0, 0]], show=False, **kw)
    with pytest.raises(ValueError, match=r"localPoints of ANCF cable elements are \[x, 0, 0\]"):
        mbs.CreateAnisotropicContact(bodyNumber=elements[0], localPoints=[[0.1, 0.01, 0]], show=False, **kw)
    with pytest.raises(ValueError, match="bodyNumber must hold either ANCF cable elements.*bodyNumber\\[2\\]"):
        mbs.CreateAnisotropicContact(bodyNumber=elements + [o], localPoints=[[0.1, 0, 0]], show=False, **kw)
    with pytest.raises(ValueError, match="more than once"):
        mbs.CreateAnisotropicContact(bodyNumber=[elements[0], elements[0]], localPoints=[[0.1, 0, 0]], show=False,
                                     **kw)
    with pytest.raises(ValueError, match="empty list"):
        mbs.CreateAnisotropicContact(bodyNumber=[], localPoints=[[0.1, 0, 0]], show=False, **kw)
    with pytest.raises(ValueError, match=r"bodyNumber\[1\] must be an existing object"):
        mbs.CreateAnisotropicContact(bodyNumber=[elements[0], 99], localPoints=[[0.1, 0, 0]], show=False, **kw)
