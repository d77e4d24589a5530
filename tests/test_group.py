"""A group: one contact set over several rigid bodies (bodyNumber = a list of them, the same local
points on each), one Exudyn object and one compiled call.

Oracles: a group is the same model as one contact set per body, so every run is held equal to the
separate sets (coordinates and histories to round-off, Newton iterations) on every rigid node
type; the group's numpy route equals its compiled route; the group's sparse Jacobian is the
separate sets' Jacobians on its diagonal blocks and its force couples no two bodies; Exudyn's
dense and sparse linear solvers agree; bad lists get a named error.
"""
import numpy as np
import pytest
import exudyn as exu
from exudyn.itemInterface import LoadCoordinate, MarkerNodeCoordinate, NodeRigidBody2D, ObjectRigidBody2D
from exudyn.utilities import InertiaCuboid

import exu_aniso  # noqa: F401  (binds mbs.CreateAnisotropicContact)
from exu_aniso.engines.exudyn_adapter.commit import SETS_KEY
from exu_aniso.engines.exudyn_adapter.runner import SolveTimed
from exu_aniso.scenes.block import BlockParams, block_contact_law, block_points

NODE_TYPES = {"EP": exu.NodeType.RotationEulerParameters, "RotVecLG": exu.NodeType.RotationRotationVector}


def _cubes(M, group, node="EP", implementation="auto", t_end=0.05, solver=exu.LinearSolverType.EigenSparse,
           return_map="exact"):
    """M cubes on the plane, each pushed by its own constant force (so they slide differently):
    one contact set per cube, or one group over all of them."""
    p = BlockParams(model="full", points="corners", return_map=return_map)
    law = block_contact_law(p)
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    a, gap = p.size, -p.normal_load / p.eps_n
    local = block_points(p)
    if node == "2D":
        local[:, 2] = gap
    bodies, contacts = [], []
    for i in range(M):
        if node == "2D":                      # planar: local z = the held height over the plane
            nd = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=[3 * a * i, 0.0, 0.0]))
            o = mbs.AddObject(ObjectRigidBody2D(nodeNumber=nd, mass=p.mass, inertia=p.mass * a * a / 6.0))
        else:
            o = mbs.CreateRigidBody(inertia=InertiaCuboid(density=p.mass / a ** 3, sideLengths=[a] * 3),
                                    referencePosition=[3 * a * i, 0.0, 0.5 * a + gap], gravity=[0, 0, -9.81],
                                    nodeType=NODE_TYPES[node])
        load = [p.force * (2.0 + 0.7 * i), p.force * (0.5 - 0.3 * i), 0.0 if node == "2D" else -p.normal_load]
        if node == "2D":
            for c in range(2):
                mbs.AddLoad(LoadCoordinate(markerNumber=mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=nd, coordinate=c)),
                                           load=load[c]))
        else:
            mbs.CreateForce(itemNumber=o, loadVector=load)
        bodies.append(o)
        if not group:
            contacts.append(mbs.CreateAnisotropicContact(bodyNumber=o, localPoints=local, contactLaw=law,
                                                         implementation=implementation))
    if group:
        contacts.append(mbs.CreateAnisotropicContact(bodyNumber=bodies, localPoints=local, contactLaw=law,
                                                     implementation=implementation))
    mbs.Assemble()
    ss = exu.SimulationSettings()
    ss.timeIntegration.numberOfSteps = int(round(t_end / 1e-3))
    ss.timeIntegration.endTime = t_end
    ss.timeIntegration.verboseMode = 0
    ss.solution.file.write = False
    ss.solution.sensors.writePeriod = 0
    ss.linearSolver.solverType = solver
    n = ss.timeIntegration.newton
    n.useModifiedNewton = False
    n.relativeTolerance = n.absoluteTolerance = 1e-10
    return mbs, ss, contacts


def _run(*args, **kw):
    mbs, ss, contacts = _cubes(*args, **kw)
    _, steps, iters, _ = SolveTimed(mbs, ss, exu.DynamicSolverType.GeneralizedAlpha)
    H = np.concatenate([c["historyAt"](mbs, exu.ConfigurationType.Current) for c in contacts])
    return mbs, np.asarray(mbs.systemData.GetODE2Coordinates()), H, iters / steps, contacts


# a group's kernel is compiled per node kind (7-19 s each): the default run takes Euler parameters (the
# kind of the other group tests and of the benchmarks' cubes); -m slow the others
NODES = ["EP", pytest.param("RotVecLG", marks=pytest.mark.slow), pytest.param("2D", marks=pytest.mark.slow)]


@pytest.mark.parametrize("node", NODES)
def test_group_is_the_separate_sets(node):
    _, q1, H1, it1, _ = _run(3, False, node)
    mbs, q2, H2, it2, contacts = _run(3, True, node)
    assert np.abs(q2 - q1).max() <= 1e-12 * max(1.0, np.abs(q1).max())
    assert np.abs(H2 - H1).max() <= 1e-9 * max(1.0, np.abs(H1).max())
    assert it2 == it1                        # full Newton: the group's Jacobian is as good
    assert H2[:, 7].max() == 2.0             # the test slides (status 2 somewhere)
    cs = mbs.variables[SETS_KEY]
    assert len(cs) == 1 and cs[0].K == 12 and contacts[0]["implementation"] == "compiled"


def test_group_numpy_route_equals_compiled():
    _, q1, H1, _, _ = _run(3, True, "EP", implementation="compiled")
    _, q2, H2, _, _ = _run(3, True, "EP", implementation="numpy")
    assert np.abs(q2 - q1).max() <= 1e-11 * max(1.0, np.abs(q1).max())
    assert np.abs(H2 - H1).max() <= 1e-8 * max(1.0, np.abs(H1).max())


def test_group_dense_and_sparse_solvers_agree():
    _, q1, _, _, _ = _run(2, True, "EP", solver=exu.LinearSolverType.EigenSparse)
    _, q2, _, _, _ = _run(2, True, "EP", solver=exu.LinearSolverType.EigenDense)
    assert np.abs(q2 - q1).max() <= 1e-12 * max(1.0, np.abs(q1).max())


@pytest.mark.parametrize("node", NODES)
def test_group_sparse_jacobian_is_the_separate_sets_blocks(node):
    """After sliding a while: J (the CSR matrix Exudyn gets) holds each body's set Jacobian (those are
    checked against differences and the numpy route in test_jacobian_nodes / test_fastpath) on its
    diagonal block and nothing else; and the group's force has no coupling between bodies
    (central differences across blocks vanish)."""
    mbs, _, _, _, _ = _run(3, True, node, t_end=0.02)
    grp = mbs.variables[SETS_KEY][0]
    q = np.asarray(mbs.systemData.GetODE2Coordinates())[grp.ltgODE2]
    q_t = np.asarray(mbs.systemData.GetODE2Coordinates_t())[grp.ltgODE2]
    t = mbs.systemData.GetTime() + 1e-3
    J = grp.jacobian(mbs, t, 0, q, q_t, 0.7, 0.3).toarray()
    Q = np.array(grp.force(mbs, t, 0, q, q_t))
    mbs1, _, _, _, _ = _run(3, False, node, t_end=0.02)
    sets = mbs1.variables[SETS_KEY]
    n = q.shape[0]
    nq = n // 3
    blocks = np.zeros((n, n))
    for j, cs in enumerate(sets):
        sl = slice(j * nq, (j + 1) * nq)
        blocks[sl, sl] = cs.jacobian(mbs1, t, 0, q[sl], q_t[sl], 0.7, 0.3)
        assert np.allclose(cs.force(mbs1, t, 0, q[sl], q_t[sl]), Q[sl], rtol=1e-13, atol=1e-12)
    assert np.abs(J - blocks).max() <= 1e-12 * np.abs(blocks).max()
    for c in range(nq):                   # a coordinate of body 0 moves no other body's force
        qp = q.copy()
        qp[c] += 1e-6
        assert np.array_equal(np.array(grp.force(mbs, t, 0, qp, q_t))[nq:], Q[nq:])


def _two_cubes_and(extra):
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    p = BlockParams(model="full")
    a = p.size
    bodies = [mbs.CreateRigidBody(inertia=InertiaCuboid(density=1000.0, sideLengths=[a] * 3),
                                  referencePosition=[i * 3 * a, 0.0, 0.5 * a], nodeType=NODE_TYPES["EP"])
              for i in range(2)]
    bodies.append(extra(mbs))
    return mbs, bodies, block_contact_law(p), block_points(p)


@pytest.mark.parametrize("extra, words", [
    (lambda mbs: mbs.CreateRigidBody(inertia=InertiaCuboid(density=1000.0, sideLengths=[0.1] * 3),
                                     nodeType=NODE_TYPES["RotVecLG"]), ("bodyNumber", "one type", "RigidBodyRotVecLG")),
    (lambda mbs: mbs.CreateMassPoint(mass=1.0), ("bodyNumber[2]", "ObjectMassPoint", "rigid bodies")),
    (lambda mbs: 0, ("bodyNumber", "more than once", "[0, 1, 0]")),
])
def test_bad_group_gets_a_named_error(extra, words):
    mbs, bodies, law, points = _two_cubes_and(extra)
    with pytest.raises(ValueError) as info:
        mbs.CreateAnisotropicContact(bodyNumber=bodies, localPoints=points, contactLaw=law)
    missing = [w for w in words if w not in str(info.value)]
    assert not missing, f"message {str(info.value)!r} lacks {missing}"


def test_group_on_a_moving_master_is_refused():
    mbs, bodies, law, points = _two_cubes_and(
        lambda mbs: mbs.CreateRigidBody(inertia=InertiaCuboid(density=1000.0, sideLengths=[1.0, 1.0, 0.1]),
                                        nodeType=NODE_TYPES["EP"]))
    with pytest.raises(ValueError, match="group.*masterBodyNumber None"):
        mbs.CreateAnisotropicContact(bodyNumber=bodies[:2], localPoints=points, contactLaw=law,
                                     masterBodyNumber=bodies[2])
