"""CreateAnisotropicContact: moving master (action = reaction), sensors, argument checks."""
import numpy as np
import pytest

exu = pytest.importorskip("exudyn")
from exudyn.utilities import InertiaCuboid  # noqa: E402

from exu_aniso import Adhesion, Friction  # noqa: E402
from exu_aniso.geometry import Plane
from exu_aniso.law.history import HISTORY_FIELDS  # noqa: E402
from exu_aniso.engines.exudyn_adapter.create_contact import CreateAnisotropicContact, HistoryComponent  # noqa: E402


def two_body_system(return_map="exact"):
    """A 1 kg cube sliding on a free 10 kg plate (the master surface moves): no external load."""
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    a = 0.05
    eps_n = 1e5
    plate = mbs.CreateRigidBody(inertia=InertiaCuboid(1000.0, [1.0, 1.0, 0.01]), referencePosition=[0.0, 0.0, 0.0],
                                initialVelocity=[0.0, 0.0, 0.0], initialAngularVelocity=[0.0, 0.0, 0.3],
                                nodeType=exu.NodeType.RotationRotationVector, returnDict=True)
    block = mbs.CreateRigidBody(inertia=InertiaCuboid(1000.0, [0.1, 0.1, 0.1]), referencePosition=[0.1, 0.05, a - 2e-4],
                                initialVelocity=[0.4, -0.2, 0.0], initialAngularVelocity=[0.0, 0.0, 1.0],
                                nodeType=exu.NodeType.RotationRotationVector, returnDict=True)
    pts = np.array([[sx * a, sy * a, -a] for sx in (-1, 1) for sy in (-1, 1)])
    h = CreateAnisotropicContact(mbs, bodyNumber=block["bodyNumber"], localPoints=pts, surface=Plane(),
                                 adhesion=Adhesion.orthotropic(2e4, 5e3, 0.3), friction=Friction.orthotropic(0.2, 0.5),
                                 normalStiffness=eps_n, normalDamping=50.0, returnMap=return_map,
                                 masterBodyNumber=plate["bodyNumber"], storeHistory=True)
    return SC, mbs, plate, block, h


def momenta(mbs, bodies):
    P = np.zeros(3)
    L = np.zeros(3)
    for b in bodies:
        n = b["nodeNumber"]
        m = 1000.0 * (1.0 * 1.0 * 0.01 if b is bodies[0] else 0.1**3)
        x = mbs.GetNodeOutput(n, exu.OutputVariableType.Position)
        v = mbs.GetNodeOutput(n, exu.OutputVariableType.Velocity)
        A = mbs.GetNodeOutput(n, exu.OutputVariableType.RotationMatrix).reshape(3, 3)
        w = mbs.GetNodeOutput(n, exu.OutputVariableType.AngularVelocity)
        J = InertiaCuboid(1000.0, [1.0, 1.0, 0.01] if b is bodies[0] else [0.1, 0.1, 0.1]).Inertia()
        P += m * v
        L += m * np.cross(x, v) + A @ J @ A.T @ w
    return P, L


# a moving master's kernel per map (26 s each cold): the radial one in the slow run, the maps of moving
# masters in the default run are tests/test_moving_master_compiled.py's
@pytest.mark.parametrize("return_map", ["exact", pytest.param("radial", marks=pytest.mark.slow)])
def test_moving_master_gets_the_reaction_momentum_is_conserved(return_map):
    SC, mbs, plate, block, h = two_body_system(return_map)
    mbs.Assemble()
    P0, L0 = momenta(mbs, [plate, block])
    ss = exu.SimulationSettings()
    ss.timeIntegration.numberOfSteps = 300
    ss.timeIntegration.endTime = 0.3
    ss.timeIntegration.newton.useModifiedNewton = False
    ss.timeIntegration.verboseMode = 0
    ss.solution.file.write = False
    mbs.SolveDynamic(ss, solverType=exu.DynamicSolverType.TrapezoidalIndex2)
    P1, L1 = momenta(mbs, [plate, block])
    diss = mbs.GetSensorValues(h["sDissipation"])
    assert float(np.ravel(diss)[0]) > 1e-3                   # the block slid on the plate
    # the total (a C++ sensor of the set's dissipation node) is the sum over the points' history, every step
    D, Hs = mbs.GetSensorStoredData(h["sDissipation"]), mbs.GetSensorStoredData(h["sHistory"])
    col = 1 + HISTORY_FIELDS.index("dissipated_energy")
    np.testing.assert_allclose(D[:, 1], Hs[:, col::len(HISTORY_FIELDS)].sum(axis=1), rtol=1e-14, atol=0)
    assert D.shape[0] == Hs.shape[0] > 10                     # every sensor period (10 ms) of 0.3 s
    np.testing.assert_allclose(P1, P0, atol=1e-9 * 0.5)       # internal forces only: exact pairs
    np.testing.assert_allclose(L1, L0, atol=2e-3 * np.linalg.norm(L0))  # moment of the tangential pair: xi3 n x T


def test_sensors_plot_and_history_components(tmp_path):
    SC, mbs, plate, block, h = two_body_system()
    mbs.Assemble()
    ss = exu.SimulationSettings()
    ss.timeIntegration.numberOfSteps = 50
    ss.timeIntegration.endTime = 0.05
    ss.timeIntegration.verboseMode = 0
    ss.solution.sensors.writePeriod = 0.0
    ss.solution.file.write = False
    mbs.SolveDynamic(ss)
    data = mbs.GetSensorStoredData(h["sHistory"])
    assert data.shape == (51, 1 + 4 * len(HISTORY_FIELDS))            # every step stored
    status = data[1, 1 + HistoryComponent(2, "status")]     # after the first step (no load: it bounces off later)
    assert status in (1.0, 2.0)                               # stick or slip, in contact
    assert data[1, 1 + HistoryComponent(0, "normal")] < 0.0
    import matplotlib
    matplotlib.use("Agg")
    mbs.PlotSensor(sensorNumbers=[h["sHistory"], h["sDissipation"]],
                   components=[HistoryComponent(0, "traction_1"), 0], closeAll=True,
                   fileName=str(tmp_path / "sensors.png"))
    assert (tmp_path / "sensors.png").exists()
    with pytest.raises(ValueError, match="field must be one of"):
        HistoryComponent(0, "force")


def test_argument_errors():
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    b = mbs.CreateRigidBody(inertia=InertiaCuboid(1000.0, [0.1, 0.1, 0.1]), returnDict=True)
    g = mbs.CreateGround()
    with pytest.raises(ValueError, match="give normalStiffness"):
        CreateAnisotropicContact(mbs, bodyNumber=b["bodyNumber"], localPoints=[[0, 0, 0]], surface=Plane(),
                                 adhesion=Adhesion.isotropic(1.0), friction=Friction.isotropic(0.3))
    with pytest.raises(ValueError, match="localPoints must have shape"):
        CreateAnisotropicContact(mbs, bodyNumber=b["bodyNumber"], localPoints=[[0, 0]], surface=Plane(),
                                 adhesion=Adhesion.isotropic(1.0), friction=Friction.isotropic(0.3), normalStiffness=1.0)
    with pytest.raises(ValueError, match="jacobian must be"):
        CreateAnisotropicContact(mbs, bodyNumber=b["bodyNumber"], localPoints=[[0, 0, 0]], surface=Plane(),
                                 adhesion=Adhesion.isotropic(1.0), friction=Friction.isotropic(0.3), normalStiffness=1.0,
                                 jacobian="exact")
    with pytest.raises((ValueError, KeyError)):
        CreateAnisotropicContact(mbs, bodyNumber=g, localPoints=[[0, 0, 0]], surface=Plane(),
                                 adhesion=Adhesion.isotropic(1.0), friction=Friction.isotropic(0.3), normalStiffness=1.0)


def test_history_sensor_only_when_asked_for():
    """storeHistory (default False): the 9-per-point history sensor is opt-in, so memory per step does
    not grow with the points unless asked; the dissipation sensor (one number) stays with storeSensors."""
    for store, keys in ((False, {"sDissipation"}), (True, {"sDissipation", "sHistory"})):
        SC, mbs, plate, block, h = two_body_system()
        h2 = CreateAnisotropicContact(mbs, bodyNumber=block["bodyNumber"], localPoints=[[0.0, 0.0, -0.1]],
                                      surface=Plane(), adhesion=Adhesion.isotropic(1e3),
                                      friction=Friction.isotropic(0.3), normalStiffness=1e4, storeHistory=store)
        assert {k for k in h2 if k.startswith("s")} == keys
        n = mbs.systemData.NumberOfSensors()
        CreateAnisotropicContact(mbs, bodyNumber=block["bodyNumber"], localPoints=[[0.0, 0.0, -0.1]],
                                 surface=Plane(), adhesion=Adhesion.isotropic(1e3), friction=Friction.isotropic(0.3),
                                 normalStiffness=1e4, storeSensors=False, storeHistory=store)
        assert mbs.systemData.NumberOfSensors() == n + store


@pytest.mark.parametrize("implementation", ["compiled", "numpy"])
def test_generalized_force_is_the_sum_of_the_point_forces(implementation):
    """The returned dict's generalizedForce(q, q_t, history) on the planar block (x, y, theta) is
    (sum f_x, sum f_y, sum (A b x f)_z) of ContactLaw.evaluate at the block's points moved with the
    body (dt = 0), and leaves the set's own state alone (the solve continues unchanged)."""
    from exu_aniso.engines.exudyn_adapter.runner import SolveTimed
    from exu_aniso.models.block import BuildBlock
    from exu_aniso.scenes.block import BlockParams
    m = BuildBlock(BlockParams(t_end=0.05, points="corners"), implementation=implementation)
    mbs, contact = m["mbs"], m["contact"]
    SolveTimed(mbs, m["simulationSettings"], m["solverType"])
    q = np.array(mbs.GetNodeOutput(m["nBlock"], exu.OutputVariableType.Coordinates))
    q_t = np.array(mbs.GetNodeOutput(m["nBlock"], exu.OutputVariableType.Coordinates_t))
    H = contact["historyAt"](mbs, exu.ConfigurationType.Current)
    assert np.count_nonzero(H[:, HISTORY_FIELDS.index("active")]) == 4
    ref = np.array(mbs.GetNodeParameter(m["nBlock"], "referenceCoordinates"))
    x0, y0, th = ref + q
    c, s = np.cos(th), np.sin(th)
    b = np.asarray(contact["points"], dtype=float)
    arm = np.column_stack([c * b[:, 0] - s * b[:, 1], s * b[:, 0] + c * b[:, 1], np.zeros(len(b))])
    x = arm + [x0, y0, 0.0]
    x[:, 2] = b[:, 2]
    v = np.column_stack([q_t[0] - q_t[2] * arm[:, 1], q_t[1] + q_t[2] * arm[:, 0], np.zeros(len(b))])
    f = contact["law"].evaluate(x, v, H, tangent=False, dt=0.0).force
    expected = [f[:, 0].sum(), f[:, 1].sum(), np.sum(arm[:, 0] * f[:, 1] - arm[:, 1] * f[:, 0])]
    Q = contact["generalizedForce"](q, q_t, H)
    assert np.max(np.abs(Q - expected)) <= 1e-12 * np.max(np.abs(expected))
    assert np.max(np.abs(expected)) > 0.1                    # a loaded contact, not zeros
    # samples at once (what post-processing over a run does): each row as the call on that sample alone
    qs = np.array([q, q + [1e-4, -2e-4, 1e-2], q])
    q_ts = np.array([q_t, 2.0 * q_t, q_t + 0.1])
    Hs = np.stack([H, H, np.zeros_like(H)])
    Qs = contact["generalizedForce"](qs, q_ts, Hs.reshape(3, -1))
    assert Qs.shape == (3, 3)
    for n in range(3):
        assert np.array_equal(Qs[n], contact["generalizedForce"](qs[n], q_ts[n], Hs[n]))
    assert not np.array_equal(Qs[0], Qs[1])
    with pytest.raises(ValueError, match="over the same samples"):
        contact["generalizedForce"](qs, q_ts, Hs[:2])


def test_initial_history_of_the_compiled_set_equals_the_numpy_set():
    """Points in contact at t = 0 start sticking there: the compiled set takes the initial history
    from its own kernel, the numpy set from ContactLaw.evaluate; the same rows."""
    from exu_aniso.models.block import BuildBlock
    from exu_aniso.scenes.block import BlockParams
    rows = []
    for implementation in ("compiled", "numpy"):
        m = BuildBlock(BlockParams(model="full", points="grid:3"), implementation=implementation)
        rows.append(np.array(m["mbs"].GetNodeParameter(m["contact"]["nData"], "initialCoordinates")))
    assert np.count_nonzero(rows[0][HISTORY_FIELDS.index("active")::len(HISTORY_FIELDS)]) == 9
    assert np.max(np.abs(rows[0] - rows[1])) <= 1e-14 * np.max(np.abs(rows[1]))
