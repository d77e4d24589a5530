"""The contact history in place, on Exudyn's own memory (exudyn_adapter.contact_set.SystemViews).

The compiled sets read the last accepted history from a view of the StartOfStep data coordinates,
write the candidate into a view of the Current ones, and read q, q_t from views of the Current
ODE2 coordinates; Exudyn's accept (Current -> StartOfStep) is the commit, its reject the rollback.
Checked here: with Newton capped at 3 iterations (many forced step reductions) the accepted step
times and the results are those of the previous implementation (Get/Set of whole vectors in the
post-Newton function, lists copied in every callback); the views are Exudyn's vectors; the q, q_t
lists Exudyn passes are the views' numbers; a grown, re-assembled system gets fresh views. A moving
master (its coordinates two ranges of the ODE2 vector, gathered from the views by a compiled loop):
the gathered numbers are Exudyn's lists at every force and Jacobian call under forced step
reductions, also with the master first in the vector, and the run equals, bit for bit, the same run
copying the lists (the set's direct force and jacobian functions).

The REF_ numbers were produced with the package of commit 378a822 (the branch history-in-place
before the history moved into place): the scenes of the two tests below, solved by ``_solve`` and
read out as there, in a Python process importing that commit's exu_aniso (exudyn 1.13.6). The
numpy route and the separate sets of test_group's ``_cubes`` gave the same step times and
bit-identical results on both commits as well.
"""
from __future__ import annotations

import numpy as np
import pytest
import exudyn as exu
from exudyn.itemInterface import MassPoint, NodeGenericData, NodePoint
from exudyn.utilities import InertiaCuboid

import exu_aniso  # noqa: F401  (binds mbs.CreateAnisotropicContact)
from exu_aniso import Adhesion, Friction, Plane
from exu_aniso.engines.exudyn_adapter.commit import SETS_KEY
from exu_aniso.models.block import BuildBlock
from exu_aniso.scenes.block import BlockParams, block_contact_law

from test_group import _cubes

MAX_ITERATIONS = 3          # Newton capped: steps are reduced (the block: 100 nominal, 394 accepted)
TOL = 1e-10

# accepted step sizes as (size in units of 1e-3 / 64 s, number of consecutive steps), from t = 0
REF_BLOCK_STEPS = [(64, 55), (32, 7), (8, 332)]
REF_BLOCK_Q = [-4.666492405766429e-05, 0.006827821157244785, -1.8132774882501485e-10, -2.2803856275070002e-05,
               -2.9345465360467617e-05, 2.9486254791059336e-07, 0.00675310188767759, 0.006827821157244785,
               0.010000000000000111]
REF_BLOCK_H = [-0.014216406415285229, -0.5117836747975408, 0.4506331807334368, -0.0438458476877865, 1.0,
               0.0021265409340727693, 0.004148548421410772, 2.0, -1.7066036316504967, -0.0206342840832372,
               -0.5189664695222558, 0.5506240596617797, -0.04249525811133453, 1.0, 0.002877814991094573,
               0.005458035053853604, 2.0, -1.731255068722695, 0.022978374400234248, -0.9592434142287456,
               0.5492734700818667, 0.05749562064479456, 1.0, 0.0035292112831908366, 0.0037004532791106316, 2.0,
               -3.198395315416949, -0.0014767244718850846, -0.9521220183172975, 0.4492825911535237,
               0.056145031068342593, 1.0, 0.0022602281587411643, 0.0024022634970214036, 2.0, -3.1737438783447507]
REF_BLOCK_DISSIPATION = (0.010793795367099342, 1.4936200581632901, 395)   # last value, sum, rows of sDissipation

REF_GROUP_STEPS = [(64, 19), (32, 10), (64, 2), (32, 10), (64, 19)]
REF_GROUP_Q = [0.007471117963327674, 0.0027277291306125953, -1.9296449265334407e-05, -1.6903179960352181e-07,
               -6.67652185529855e-06, 0.00013117180816780833, 0.0005664035234629906, 0.010256559255628914,
               0.0011142606717794291, -1.9160895789322246e-05, -2.5545504905886093e-07, -4.4924145266697125e-06,
               0.0001742522362149689, 0.0006931998336516114, 0.014437665026709385, -0.0005663935407641661,
               -1.923263705551673e-05, -6.843431104950927e-08, 1.63370013968279e-06, 0.00019000746526798184,
               -0.0003174320583889305]
REF_GROUP_H = (-73.12480872779581, 158.26036736187524)                    # sum, sum of |.|
REF_GROUP_DISSIPATION = (0.17654981844474554, 3.507257359525621, 61)


def _solve(mbs, ss, solver, contacts):
    """Solve with Newton capped; accepted step times [s], final ODE2 coordinates, history, dissipation."""
    ss.timeIntegration.newton.maxIterations = MAX_ITERATIONS
    ss.timeIntegration.minimumStepSize = 1e-9
    times = []
    mbs.SetPostStepUserFunction(lambda mbs, t: times.append(mbs.systemData.GetTime()) or True)
    mbs.SolveDynamic(ss, solverType=solver)
    H = np.concatenate([c["historyAt"](mbs, exu.ConfigurationType.Current).ravel() for c in contacts])
    diss = np.concatenate([mbs.GetSensorStoredData(c["sDissipation"])[:, 1] for c in contacts])
    return np.array(times), np.asarray(mbs.systemData.GetODE2Coordinates()), H, diss


def _steps(times):
    """Run lengths of the accepted step sizes in units of 1e-3 / 64 s (exact: all are such multiples)."""
    u = np.round(np.asarray(times) * 64000.0)
    assert np.max(np.abs(u - np.asarray(times) * 64000.0)) < 1e-6 and u[0] == 0.0
    runs = []
    for h in np.diff(u).astype(int):
        if runs and runs[-1][0] == h:
            runs[-1][1] += 1
        else:
            runs.append([int(h), 1])
    return [tuple(r) for r in runs]


def _block(**kw):
    m = BuildBlock(BlockParams(model="full", t_end=0.1), **kw)
    return m, m["mbs"]


def test_block_with_forced_step_reductions_equals_the_previous_implementation():
    m, mbs = _block()
    times, q, H, diss = _solve(mbs, m["simulationSettings"], m["solverType"], [m["contact"]])
    assert _steps(times) == REF_BLOCK_STEPS
    assert np.max(np.abs(q - REF_BLOCK_Q)) < TOL
    assert np.max(np.abs(H - REF_BLOCK_H)) < TOL
    last, total, rows = REF_BLOCK_DISSIPATION
    assert len(diss) == rows and abs(diss[-1] - last) < TOL and abs(diss.sum() - total) < TOL
    # the set's total (nTotal, written through its view) is the sum of the points' dissipated energy
    assert abs(diss[-1] - H[5::9].sum()) < 1e-14


def test_group_with_forced_step_reductions_equals_the_previous_implementation():
    mbs, ss, contacts = _cubes(3, True, t_end=0.05)
    times, q, H, diss = _solve(mbs, ss, exu.DynamicSolverType.GeneralizedAlpha, contacts)
    assert _steps(times) == REF_GROUP_STEPS
    assert np.max(np.abs(q - REF_GROUP_Q)) < TOL
    assert abs(H.sum() - REF_GROUP_H[0]) < TOL and abs(np.abs(H).sum() - REF_GROUP_H[1]) < TOL
    last, total, rows = REF_GROUP_DISSIPATION
    assert len(diss) == rows and abs(diss[-1] - last) < TOL and abs(diss.sum() - total) < TOL


def _shares(view, vector):
    return np.shares_memory(view, vector)


def test_views_are_exudyns_vectors():
    m, mbs = _block()
    m["simulationSettings"].timeIntegration.endTime = 0.01
    m["simulationSettings"].timeIntegration.numberOfSteps = 10
    mbs.SolveDynamic(m["simulationSettings"], solverType=m["solverType"])
    cs = mbs.variables[SETS_KEY][0]
    sd, CUR, SOS = mbs.systemData, exu.ConfigurationType.Current, exu.ConfigurationType.StartOfStep
    assert not cs._gathered                                   # one body: its coordinates are one range
    assert _shares(cs._q, sd.GetODE2Coordinates(configuration=CUR, copy=False))
    assert _shares(cs._q_t, sd.GetODE2Coordinates_t(configuration=CUR, copy=False))
    assert _shares(cs._V.data, sd.GetDataCoordinates(configuration=CUR, copy=False))
    assert _shares(cs._h0, sd.GetDataCoordinates(configuration=SOS, copy=False))
    np.testing.assert_array_equal(cs._h0, cs.history(mbs, SOS))


@pytest.mark.parametrize("jacobian", ["analytic", "numerical"])
def test_lists_exudyn_passes_are_the_views(jacobian):
    """Every force call sees q, q_t lists equal to the views the compiled set reads (Exudyn's
    numerical Jacobian included: it perturbs the system's Current coordinates)."""
    m, mbs = _block(jacobian=jacobian)
    cs = mbs.variables[SETS_KEY][0]
    calls = [0]

    def force(mbs, t, itemNumber, q, q_t):
        Q = cs.force_in_place(mbs, t, itemNumber, q, q_t)
        assert not cs._gathered
        np.testing.assert_array_equal(cs._q, q)
        np.testing.assert_array_equal(cs._q_t, q_t)
        calls[0] += 1
        return Q

    mbs.SetObjectParameter(m["contact"]["oContact"], "forceUserFunction", force)
    mbs.Assemble()
    ss = m["simulationSettings"]
    ss.timeIntegration.endTime = 0.02
    ss.timeIntegration.numberOfSteps = 20
    mbs.SolveDynamic(ss, solverType=m["solverType"])
    assert calls[0] > 40


def _with_extra_items(mbs):
    """An uncoupled mass point (3 ODE2 coordinates) and a data node (50 data coordinates): the
    system's vectors grow, so Exudyn reallocates them."""
    nd = mbs.AddNode(NodePoint(referenceCoordinates=[5.0, 0.0, 0.0]))
    mbs.AddObject(MassPoint(mass=1.0, nodeNumber=nd))
    mbs.AddNode(NodeGenericData(initialCoordinates=[0.0] * 50, numberOfDataCoordinates=50))


def test_grown_and_reassembled_system_gets_fresh_views():
    m, mbs = _block()
    ss = m["simulationSettings"]
    ss.timeIntegration.endTime = 0.02
    ss.timeIntegration.numberOfSteps = 20
    mbs.SolveDynamic(ss, solverType=m["solverType"])
    cs = mbs.variables[SETS_KEY][0]
    before = cs._V
    _with_extra_items(mbs)
    mbs.Assemble()
    mbs.SolveDynamic(ss, solverType=m["solverType"])
    assert cs._V is not before and cs._V.sizes == (mbs.systemData.ODE2Size(), mbs.systemData.DataSize())
    assert _shares(cs._V.data, mbs.systemData.GetDataCoordinates(configuration=exu.ConfigurationType.Current,
                                                                 copy=False))
    q, H = np.asarray(mbs.systemData.GetODE2Coordinates()), m["contact"]["historyAt"](mbs, exu.ConfigurationType.Current)

    m2, mbs2 = _block()                               # the same system, built grown from the start
    _with_extra_items(mbs2)
    mbs2.Assemble()
    mbs2.SolveDynamic(ss, solverType=m2["solverType"])
    np.testing.assert_array_equal(q, mbs2.systemData.GetODE2Coordinates())
    np.testing.assert_array_equal(H, m2["contact"]["historyAt"](mbs2, exu.ConfigurationType.Current))


# --- a moving master: the object's coordinates are two ranges, gathered from the views --------------

def _moving_master(jacobian="analytic", speed=0.05):
    """The full block (t_end 0.1 s) on a free plate (a rigid body of 1e9 kg moving uniformly at
    (speed, -speed/2, 0), as studies' plate_builder): a moving-master set over the block's and the
    plate's coordinates, two ranges of the ODE2 vector (the drive's nodes lie between them)."""
    p = BlockParams(model="full", t_end=0.1)

    def build(mbs, oBlock, localPoints):
        oPlate = mbs.CreateRigidBody(inertia=InertiaCuboid(1e9 / 0.02, [1.0, 1.0, 0.02]),
                                     referencePosition=[0.0, 0.0, 0.0],
                                     initialVelocity=[speed, -0.5 * speed, 0.0],
                                     nodeType=exu.NodeType.RotationEulerParameters, gravity=[0.0, 0.0, 0.0])
        return mbs.CreateAnisotropicContact(name="blockContact", bodyNumber=oBlock, localPoints=localPoints,
                                            contactLaw=block_contact_law(p), masterBodyNumber=oPlate,
                                            jacobian=jacobian, show=False, storeHistory=True)
    m = BuildBlock(p, contactBuilder=build)
    return m, m["mbs"]


def _point_on_plate(jacobian="analytic"):
    """A mass point sliding on a plate created before it (rotation-vector node, 1e9 kg, moving; a
    pairing the default run compiles anyway, _suite.DEFAULT_PAIRS): the object's coordinates are
    the point's (after the plate's in the ODE2 vector), then the plate's."""
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    oPlate = mbs.CreateRigidBody(inertia=InertiaCuboid(1e9 / 0.02, [1.0, 1.0, 0.02]),
                                 referencePosition=[0.0, 0.0, 0.0], initialVelocity=[0.02, 0.01, 0.0],
                                 initialAngularVelocity=[0.0, 0.0, 0.3],
                                 nodeType=exu.NodeType.RotationRotationVector, gravity=[0.0, 0.0, 0.0])
    o = mbs.CreateMassPoint(referencePosition=[0.2, 0.1, -1e-4], initialVelocity=[0.3, -0.1, 0.0], mass=1.0,
                            gravity=[0.0, 0.0, -9.81])
    c = mbs.CreateAnisotropicContact(bodyNumber=o, localPoints=[[0.0, 0.0, 0.0]],
                                     surface=Plane(coordinates="polar"),
                                     adhesion=Adhesion.polar(eps_r=1e4, eps_phi=1e3, core_radius=1e-3),
                                     friction=Friction.polar(mu_r=0.3, mu_phi=0.1, core_radius=1e-3),
                                     normalStiffness=1e5, masterBodyNumber=oPlate, jacobian=jacobian,
                                     show=False)
    mbs.Assemble()
    ss = exu.SimulationSettings()
    ss.timeIntegration.endTime = 0.1
    ss.timeIntegration.numberOfSteps = 100
    ss.solution.file.write = False
    ss.timeIntegration.verboseMode = 0
    return mbs, ss, c


def _checking(mbs, contact):
    """Replace the set's force and (analytic) Jacobian functions by ones that call them and assert
    that the coordinates they read (gathered from the views) equal the lists Exudyn passes."""
    cs = mbs.variables[SETS_KEY][0]
    calls = [0, 0]

    def check(q, q_t):
        assert cs._gathered
        np.testing.assert_array_equal(cs._q, q)
        np.testing.assert_array_equal(cs._q_t, q_t)

    def force(mbs, t, itemNumber, q, q_t):
        Q = cs.force_in_place(mbs, t, itemNumber, q, q_t)
        check(q, q_t)
        calls[0] += 1
        return Q

    def jacobian(mbs, t, itemNumber, q, q_t, fODE2, fODE2_t):
        J = cs.jacobian_in_place(mbs, t, itemNumber, q, q_t, fODE2, fODE2_t)
        check(q, q_t)
        calls[1] += 1
        return J

    mbs.SetObjectParameter(contact["oContact"], "forceUserFunction", force)
    if mbs.GetObjectParameter(contact["oContact"], "jacobianUserFunction"):
        mbs.SetObjectParameter(contact["oContact"], "jacobianUserFunction", jacobian)
    mbs.Assemble()
    return cs, calls


@pytest.mark.parametrize("jacobian", ["analytic", "numerical"])
def test_moving_master_lists_exudyn_passes_are_the_gathered_views(jacobian):
    """With Newton capped (forced step reductions), every force and Jacobian call of a moving-master
    set reads q, q_t equal to Exudyn's lists (the numerical Jacobian perturbs the Current
    coordinates: the views see it)."""
    m, mbs = _moving_master(jacobian)
    cs, calls = _checking(mbs, m["contact"])
    times = _solve(mbs, m["simulationSettings"], m["solverType"], [m["contact"]])[0]
    assert cs._gathered and len(_steps(times)) > 1 and len(times) > 150     # 100 nominal steps, reduced
    assert calls[0] > 1000 and (calls[1] > 0) == (jacobian == "analytic")
    mbs, ss, contact = _point_on_plate(jacobian)                            # master first in the ODE2 vector
    cs, calls = _checking(mbs, contact)
    mbs.SolveDynamic(ss)
    assert cs.ltgODE2[0] > cs.ltgODE2[-1] and calls[0] > 200


def test_moving_master_gathered_equals_lists():
    """The moving-master run reading the views (gathered) and the same run copying Exudyn's lists
    (the set's direct force and jacobian, as before the gather) take the same steps, bit for bit."""
    out = []
    for direct in (False, True):
        m, mbs = _moving_master()
        if direct:
            cs = mbs.variables[SETS_KEY][0]
            mbs.SetObjectParameter(m["contact"]["oContact"], "forceUserFunction", cs.force)
            mbs.SetObjectParameter(m["contact"]["oContact"], "jacobianUserFunction", cs.jacobian)
            mbs.Assemble()
        out.append(_solve(mbs, m["simulationSettings"], m["solverType"], [m["contact"]]))
    for a, b in zip(*out):
        np.testing.assert_array_equal(a, b)
    assert len(out[0][0]) > 150
