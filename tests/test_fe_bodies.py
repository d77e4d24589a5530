"""Linear finite-element bodies as slaves: the mesh and its matrices (scikit-fem), Exudyn's
FEMinterface of them, the full FE body (ObjectGenericODE2 of NodePoints) with contact on its
surface nodes, and oracles:

* the assembly: the mass is rho V; K has the six rigid-body modes as its null space; the patch test
  (a uniaxial stress field is reproduced exactly: no force on interior nodes, the top face's force
  E eps A);
* a frictionless elastic block pressed by w onto the plane: Exudyn's static solution with the
  contact equals the FE static solution of the same mesh with the penalty as springs under the
  bottom nodes (scipy) to round-off, and approaches the rigid support (bottom u_z = 0) like 1/eps_N;
* the energy ledger of a block pushed over a rough plane closes with the strain energy as a stored
  term and the Rayleigh damping's dissipation beside the contact's.

* a reduced-order body (ObjectFFRFreducedOrder) converges to the full one as modes are added: with
  Craig-Bampton's static modes of every loaded node (top and bottom faces) it is the full body's
  static solution to round-off; with free-free eigenmodes it misses the local compliance and
  approaches slowly (the contact then takes what the missing compliance would have);
* the reduced body's contact points are where Exudyn puts its mesh nodes.

The Jacobian of the contact on mesh nodes against finite differences: tests/test_jacobian_nodes.py
(node kinds "FEMesh" and "FFRF")."""
import sys

import numpy as np
import pytest

exu = pytest.importorskip("exudyn")
pytest.importorskip("skfem")
import scipy.sparse.linalg as sla  # noqa: E402
from exudyn.FEM import HCBstaticModeSelection, ObjectFFRFreducedOrderInterface  # noqa: E402
from exudyn.itemInterface import (LoadForceVector, MarkerBodyPosition, MarkerNodeCoordinate,  # noqa: E402
                                  MarkerNodePosition, MarkerSuperElementPosition, NodePointGround,
                                  ObjectConnectorCartesianSpringDamper, ObjectConnectorCoordinate, ObjectGround,
                                  SensorBody)

import exu_aniso  # noqa: E402,F401
from exu_aniso import Adhesion, Friction, Plane  # noqa: E402
from exu_aniso.engines import energy  # noqa: E402
from exu_aniso.engines.exudyn_adapter.fem import FEMinterfaceOf, AddLinearFEBody  # noqa: E402
from exu_aniso.fe import block_mesh  # noqa: E402
from exu_aniso.law.history import HISTORY_FIELDS, N_HISTORY  # noqa: E402

NORMAL = HISTORY_FIELDS.index("normal")
SIZE = (0.1, 0.1, 0.05)


# --- the mesh and its matrices -------------------------------------------------------------------

def test_mass_and_rigid_body_modes():
    mesh = block_mesh(SIZE, (3, 2, 2), E=2e6, nu=0.3, rho=1200.0)
    assert mesh.total_mass == pytest.approx(1200.0 * 0.1 * 0.1 * 0.05, rel=1e-12)
    X = mesh.nodes
    modes = []
    for i in range(3):
        t = np.zeros_like(X)
        t[:, i] = 1.0
        modes.append(t.ravel())
        w = np.zeros(3)
        w[i] = 1.0
        modes.append(np.cross(w, X).ravel())           # infinitesimal rotation about axis i
    scale = abs(mesh.stiffness).max() * np.abs(X).max()
    for u in modes:
        assert np.abs(mesh.stiffness @ u).max() < 1e-10 * scale
    assert mesh.strain_energy(modes[1]) < 1e-12 * scale * 0.05
    # and nothing else: the seventh eigenvalue is a deformation's
    vals = np.linalg.eigvalsh(mesh.stiffness.toarray())
    assert np.all(np.abs(vals[:6]) < 1e-8 * vals[-1]) and vals[6] > 1e-4 * vals[-1]


def test_patch_test_uniaxial_stress():
    """u = eps (nu x, nu y, -z) is uniaxial stress sigma_zz = -E eps: trilinear elements represent it
    exactly, so K u vanishes at every node off the top and bottom faces and the top face's nodal
    forces sum to -E eps A."""
    E, nu, eps = 3e6, 0.25, 1e-3
    mesh = block_mesh(SIZE, (3, 3, 3), E=E, nu=nu)
    X = mesh.nodes
    u = (eps * np.column_stack([nu * X[:, 0], nu * X[:, 1], -X[:, 2]])).ravel()
    f = (mesh.stiffness @ u).reshape(-1, 3)
    inside = np.setdiff1d(np.arange(mesh.number_of_nodes), np.concatenate([mesh.node_sets["top"],
                                                                            mesh.node_sets["bottom"]]))
    assert np.abs(f[inside]).max() < 1e-9 * E * eps * SIZE[0]
    assert f[mesh.node_sets["top"], 2].sum() == pytest.approx(-E * eps * SIZE[0] * SIZE[1], rel=1e-10)
    assert np.abs(f[mesh.node_sets["top"], :2].sum(axis=0)).max() < 1e-9 * E * eps * SIZE[0] * SIZE[1]


def test_bad_mesh_arguments_name_the_rule():
    with pytest.raises(ValueError, match=r"nu \(Poisson's ratio\) must lie in \(-1, 0.5\)"):
        block_mesh(SIZE, (1, 1, 1), nu=0.5)
    with pytest.raises(ValueError, match=r"E \(Young's modulus \[Pa\]\) must be > 0"):
        block_mesh(SIZE, (1, 1, 1), E=-1.0)
    with pytest.raises(ValueError, match=r"cells\[2\] must be an integer >= 1"):
        block_mesh(SIZE, (1, 1, 0))
    with pytest.raises(ValueError, match=r"size\[0\] must be > 0"):
        block_mesh((0.0, 1.0, 1.0), (1, 1, 1))
    with pytest.raises(ValueError, match="must be finite"):
        block_mesh(SIZE, (1, 1, 1), rho=float("nan"))


def test_without_scikit_fem_the_error_says_how_to_install_it(monkeypatch):
    monkeypatch.setitem(sys.modules, "skfem", None)
    with pytest.raises(ImportError, match=r'pip install "\.\[fem\]"'):
        block_mesh(SIZE, (1, 1, 1))


def test_feminterface_holds_the_mesh_in_exudyns_conventions():
    """Hex8 in Exudyn's (Abaqus C3D8) order: the bottom face counter-clockwise seen from +z, then the top
    face above it; Exudyn's own eigenmode solver finds the six rigid-body modes of the free body and
    its node search finds the bottom face."""
    mesh = block_mesh(SIZE, (2, 3, 2))
    fem = FEMinterfaceOf(mesh)
    for hexa in fem.elements[0]["Hex8"]:
        P = mesh.nodes[hexa]
        assert np.ptp(P[:4, 2]) == 0.0 and np.ptp(P[4:, 2]) == 0.0 and P[4, 2] > P[0, 2]
        np.testing.assert_allclose(P[4:, :2], P[:4, :2])
        d = P[1:4, :2] - P[0, :2]
        area = 0.5 * sum(d[i, 0] * d[i + 1, 1] - d[i, 1] * d[i + 1, 0] for i in (0, 1))
        assert area > 0.0
    fem.ComputeEigenmodes(10, excludeRigidBodyModes=0, useSparseSolver=False)
    ev = np.asarray(fem.GetEigenFrequenciesHz())
    assert np.all(ev[:6] < 1e-3 * ev[6])
    bottom = fem.GetNodesInPlane([0, 0, 0], [0, 0, 1])
    assert sorted(bottom) == sorted(mesh.node_sets["bottom"].tolist())


# --- the contact on mesh nodes ---------------------------------------------------------------------

def _body(mesh, **kw):
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    return SC, mbs, AddLinearFEBody(mbs, mesh, **kw)


def _law_kw(eps_n=1e6, mu=1e-9):
    return dict(surface=Plane(), adhesion=Adhesion.isotropic(1e2), friction=Friction.isotropic(mu),
                normalStiffness=eps_n)


def test_mesh_nodes_by_index_or_by_position():
    mesh = block_mesh(SIZE, (2, 2, 1))
    bottom = mesh.node_sets["bottom"]
    _, mbs, body = _body(mesh, position=(0.2, 0.0, 0.0))
    c1 = mbs.CreateAnisotropicContact(bodyNumber=body["oBody"], localPoints=bottom.tolist(), **_law_kw())
    c2 = mbs.CreateAnisotropicContact(bodyNumber=body["oBody"], localPoints=mesh.nodes[bottom] + [0.2, 0.0, 0.0],
                                      **_law_kw())
    assert c1["meshNodes"] == c2["meshNodes"] == bottom.tolist()
    assert [int(n) for n in mbs.GetObject(c1["oContact"])["nodeNumbers"]] == [int(body["nodes"][j]) for j in bottom]
    X, _, _ = c1["pointsAndMasterPose"](mbs)
    np.testing.assert_allclose(X, mesh.nodes[bottom] + [0.2, 0.0, 0.0])


@pytest.mark.parametrize("points,message", [
    ([0, 0], "lists a mesh node more than once"),
    ([0, 1000], r"localPoints\[1\] = 1000 is not a mesh node index"),
    ([[0.011, 0.0, 0.0]], r"localPoints\[0\] = \[0.011, 0.0, 0.0\] is not a node of the finite-element body"),
])
def test_bad_mesh_points_name_the_point(points, message):
    mesh = block_mesh(SIZE, (2, 2, 1))
    _, mbs, body = _body(mesh)
    with pytest.raises(ValueError, match=message):
        mbs.CreateAnisotropicContact(bodyNumber=body["oBody"], localPoints=points, **_law_kw())


def _pressed_block(mesh, w, eps_n):
    """Exudyn's static solution of the block's top face moved down by w [m] (all three coordinates
    of every top node prescribed) onto a frictionless plane under its bottom nodes: (total normal
    force from the contact history [N], the top face's reaction [N])."""
    _, mbs, body = _body(mesh)
    mG = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=mbs.AddNode(NodePointGround()), coordinate=0))
    top_z = []
    for j in mesh.node_sets["top"]:
        for i, offset in enumerate((0.0, 0.0, -w)):
            m = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=body["nodes"][j], coordinate=i))
            o = mbs.AddObject(ObjectConnectorCoordinate(markerNumbers=[mG, m], offset=offset))
            if i == 2:
                top_z.append(o)
    c = mbs.CreateAnisotropicContact(bodyNumber=body["oBody"], localPoints=mesh.node_sets["bottom"],
                                     **_law_kw(eps_n))
    N = _static_normal_force(mbs, c)
    return N, sum(float(mbs.GetObjectOutput(o, exu.OutputVariableType.Force)) for o in top_z)


def _static_normal_force(mbs, contact):
    """Assemble and solve mbs statically (Newton to 1e-12, sparse); the total normal force of the
    contact's points [N] from its history."""
    mbs.Assemble()
    ss = exu.SimulationSettings()
    ss.staticSolver.newton.relativeTolerance = ss.staticSolver.newton.absoluteTolerance = 1e-12
    ss.linearSolver.solverType = exu.LinearSolverType.EigenSparse
    ss.staticSolver.verboseMode = 0
    mbs.SolveStatic(ss)
    H = np.asarray(mbs.GetNodeOutput(contact["nData"], exu.OutputVariableType.Coordinates)).reshape(-1, N_HISTORY)
    return -float(H[:, NORMAL].sum())


def _fe_static(mesh, w, eps_n=None):
    """The same problem by the FE matrices alone (scipy): the top face prescribed, the bottom nodes
    on springs eps_n in z (eps_n None: u_z = 0, a rigid frictionless support). The total normal force
    on the bottom face [N]."""
    n = mesh.number_of_coordinates
    top, bottom = mesh.node_sets["top"], mesh.node_sets["bottom"]
    K = mesh.stiffness.tolil()
    fixed = [3 * top, 3 * top + 1, 3 * top + 2]
    if eps_n is None:
        fixed.append(3 * bottom + 2)
    else:
        for j in bottom:
            K[3 * j + 2, 3 * j + 2] += eps_n
    K = K.tocsr()
    fixed = np.concatenate(fixed)
    u = np.zeros(n)
    u[3 * top + 2] = -w
    free = np.setdiff1d(np.arange(n), fixed)
    u[free] = sla.spsolve(K[free][:, free].tocsc(), -(K[free][:, fixed] @ u[fixed]))
    if eps_n is None:
        return float((mesh.stiffness @ u)[3 * bottom + 2].sum())
    return float(-eps_n * u[3 * bottom + 2].sum())


def test_frictionless_pressed_block_equals_the_fe_static_solution():
    """Exudyn's contact on the bottom nodes = the FE solution with the penalty as springs (1e-10), the
    top face's reaction balances it; against a rigid support the error falls like 1/eps_N (the
    compliance of the penalty in series with the block's: a factor 10 per decade, to 2 %)."""
    mesh = block_mesh(SIZE, (3, 3, 2), E=1e6, nu=0.3)
    w = 1e-3
    rigid = _fe_static(mesh, w)
    assert 0.9 * rigid < 1e6 * w * SIZE[0] * SIZE[1] / SIZE[2] < rigid      # above E w A / h: the lateral restraint
    errors = []
    for eps_n in (1e6, 1e7, 1e8):
        N, reaction = _pressed_block(mesh, w, eps_n)
        assert N == pytest.approx(_fe_static(mesh, w, eps_n), rel=1e-10)
        assert reaction == pytest.approx(-N, rel=1e-10)
        errors.append((rigid - N) / rigid)
    assert errors[0] > 0.0
    for a, b in zip(errors, errors[1:]):
        assert b > 0.0 and a / b == pytest.approx(10.0, rel=0.02)


def test_energy_ledger_closes_with_the_strain_energy():
    """A block under gravity pushed over a rough plane (mu 0.3, push 0.5 m g on the top face) for
    0.3 s with stiffness-proportional damping: work of the push = kinetic (v.M v / 2) + gravity's
    potential + strain (u.K u / 2) + contact stored + dissipated (friction, from the history) + the
    damping's work (the trapezoid of D v over the steps); the trapezoidal rule keeps the books to round-off
    for constant M, K and D (relative residual below 1e-9; measured 5.2e-13)."""
    mesh = block_mesh(SIZE, (2, 2, 1), E=1e6, nu=0.3, rho=1000.0)
    beta, dt, t_end, mu = 1e-3, 1e-3, 0.3, 0.3
    SC, mbs, body = _body(mesh, stiffnessDamping=beta)
    m, g = mesh.total_mass, 9.81
    gravity = np.zeros(mesh.number_of_coordinates)
    gravity[2::3] = -g
    f_g = mesh.mass @ gravity
    top = mesh.node_sets["top"]
    f_push = np.zeros(mesh.number_of_coordinates)
    f_push[3 * top] = 0.5 * m * g / len(top)
    f = f_g + f_push
    for j, nd in enumerate(body["nodes"]):
        mbs.AddLoad(LoadForceVector(markerNumber=mbs.AddMarker(MarkerNodePosition(nodeNumber=nd)),
                                    loadVector=f[3 * j:3 * j + 3].tolist()))
    c = mbs.CreateAnisotropicContact(bodyNumber=body["oBody"], localPoints=mesh.node_sets["bottom"],
                                     surface=Plane(), adhesion=Adhesion.isotropic(1e4),
                                     friction=Friction.isotropic(mu), normalStiffness=1e5, storeHistory=True)
    sQ = mbs.AddSensor(SensorBody(bodyNumber=body["oBody"], outputVariableType=exu.OutputVariableType.Coordinates,
                                  storeInternal=True))
    sV = mbs.AddSensor(SensorBody(bodyNumber=body["oBody"], outputVariableType=exu.OutputVariableType.Coordinates_t,
                                  storeInternal=True))
    mbs.Assemble()
    ss, solver = exu_aniso.RecommendedSimulationSettings(endTime=t_end, stepSize=dt, solver="trapezoidal")
    ss.solution.sensors.writePeriod = dt
    mbs.SolveDynamic(ss, solverType=solver)
    U = mbs.GetSensorStoredData(sQ)[:, 1:]
    V = mbs.GetSensorStoredData(sV)[:, 1:]
    H = mbs.GetSensorStoredData(c["sHistory"])[:, 1:].reshape(len(U), -1, N_HISTORY)
    assert len(U) == round(t_end / dt) + 1
    bottom = mesh.node_sets["bottom"]
    idx = (3 * bottom[:, None] + np.arange(3)).ravel()
    X = (mesh.nodes[bottom].ravel() + U[:, idx]).reshape(len(U), -1, 3)
    XV = V[:, idx].reshape(len(U), -1, 3)
    stored, dissipated = energy.contact_energy(c["law"], X, XV, H)
    D = beta * mesh.stiffness
    f_d = (D @ V.T).T                                   # the damping forces, their work as the push's
    damping = np.concatenate([[0.0], np.cumsum(np.einsum("ni,ni->n", 0.5 * (f_d[1:] + f_d[:-1]), np.diff(U, axis=0)))])
    work_in = (U - U[0]) @ f_push
    books = (mesh.kinetic_energy(V) - (U - U[0]) @ f_g + mesh.strain_energy(U) - mesh.strain_energy(U[0])
             + stored - stored[0] + dissipated - dissipated[0] + damping)
    residual = np.abs(work_in - books).max() / np.abs(work_in).max()
    assert np.mean(np.abs(X[-1, :, 0] - X[0, :, 0])) > 0.01             # it slid
    assert (dissipated[-1] - dissipated[0]) > 0.5 * work_in[-1]         # mostly into friction
    assert mesh.strain_energy(U[-1]) > 0.0 and damping[-1] > 0.0
    assert residual < 1e-9, residual


# --- the reduced-order body (floating frame of reference) ----------------------------------------

def test_a_basis_without_rigid_motion():
    """mesh.without_rigid_motion: mass-orthonormal, mass-orthogonal to the six rigid-body modes, and
    spanning the rest of what it was given (the rigid modes plus it span the input)."""
    mesh = block_mesh(SIZE, (2, 2, 1))
    R = mesh.rigid_body_modes()
    rng = np.random.default_rng(1)
    given = np.concatenate([R @ rng.normal(size=(6, 4)), rng.normal(size=(mesh.number_of_coordinates, 10))], axis=1)
    P = mesh.without_rigid_motion(given)
    M = mesh.mass.toarray()
    assert P.shape[1] == 10
    np.testing.assert_allclose(P.T @ M @ P, np.eye(10), atol=1e-10)
    assert np.abs(P.T @ M @ R).max() < 1e-10 * np.abs(M @ R).max()
    both = np.concatenate([R, P], axis=1)
    coef = np.linalg.lstsq(both, given, rcond=None)[0]
    assert np.abs(both @ coef - given).max() < 1e-9 * np.abs(given).max()


def _reduced(mesh, modes, position=(0.0, 0.0, 0.0)):
    """(SC, mbs, oFFRF) of mesh as an ObjectFFRFreducedOrder: modes = the number of free-free
    eigenmodes, or a list of node sets whose every coordinate gets a static (Craig-Bampton) mode."""
    fem = FEMinterfaceOf(mesh)
    if isinstance(modes, int):
        fem.ComputeEigenmodes(modes, excludeRigidBodyModes=6, useSparseSolver=False)
    else:
        fem.ComputeHurtyCraigBamptonModes([list(m) for m in modes], 0, useSparseSolver=False,
                                          computationMode=HCBstaticModeSelection.allBoundaryNodes)
        fem.modeBasis["matrix"] = mesh.without_rigid_motion(fem.modeBasis["matrix"])
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    o = ObjectFFRFreducedOrderInterface(fem).AddObjectFFRFreducedOrder(mbs, positionRef=list(position))
    return SC, mbs, o["oFFRFreducedOrder"]


def test_reduced_contact_points_are_exudyns_mesh_nodes():
    mesh = block_mesh(SIZE, (2, 2, 1))
    _, mbs, o = _reduced(mesh, 5, position=(0.3, 0.1, 0.0))
    bottom = mesh.node_sets["bottom"]
    c = mbs.CreateAnisotropicContact(bodyNumber=o, localPoints=mesh.nodes[bottom], **_law_kw())
    assert c["meshNodes"] == bottom.tolist() and c["implementation"] == "compiled"     # the law compiled
    mbs.Assemble()
    sd = mbs.systemData
    q = np.random.default_rng(2).normal(scale=1e-2, size=sd.ODE2Size())
    nR = mbs.GetObject(o)["nodeNumbers"][0]
    ltg = sd.GetNodeLTGODE2(nR)
    e = np.asarray(mbs.GetNodeParameter(nR, "referenceCoordinates"))[3:7] + q[ltg[3:7]]
    q[ltg[3:7]] = e / np.linalg.norm(e) - np.asarray(mbs.GetNodeParameter(nR, "referenceCoordinates"))[3:7]
    sd.SetODE2Coordinates(q, configuration=exu.ConfigurationType.Current)
    X = c["pointsAndMasterPose"](mbs, exu.ConfigurationType.Current)[0]
    for k, j in enumerate(bottom):
        exudyns = mbs.GetObjectOutputSuperElement(o, exu.OutputVariableType.Position, int(j),
                                                  configuration=exu.ConfigurationType.Current)
        np.testing.assert_allclose(X[k], exudyns, rtol=0, atol=1e-15)
    assert mbs.CreateAnisotropicContact(bodyNumber=o, localPoints=bottom, implementation="numpy",
                                        **_law_kw())["implementation"] == "numpy"


def test_a_reduced_body_says_which_routes_it_has():
    """The floating frame's contact: the law compiled at its points on a fixed surface ("auto" and
    "compiled" report "compiled"); on a moving master only the numpy route, and asking for
    "compiled" there, or for native callbacks at all, is an error that names the rule."""
    from exudyn.utilities import InertiaCuboid
    mesh = block_mesh(SIZE, (1, 1, 1))
    _, mbs, o = _reduced(mesh, 3)
    bottom = mesh.node_sets["bottom"]
    master = mbs.CreateRigidBody(inertia=InertiaCuboid(1000.0, [0.1] * 3), referencePosition=[0.0, 0.0, -0.1])
    assert mbs.CreateAnisotropicContact(bodyNumber=o, localPoints=bottom, masterBodyNumber=master,
                                        **_law_kw())["implementation"] == "numpy"
    with pytest.raises(ValueError, match="no route for an ObjectFFRFreducedOrder slave on a moving master"):
        mbs.CreateAnisotropicContact(bodyNumber=o, localPoints=bottom, masterBodyNumber=master,
                                     implementation="compiled", **_law_kw())
    with pytest.raises(ValueError, match="ObjectFFRFreducedOrder slave has no native callback"):
        mbs.CreateAnisotropicContact(bodyNumber=o, localPoints=bottom, nativeCallbacks=True, **_law_kw())


def _pressed_on_springs(mesh, body, w, eps_n, k_top=1e8):
    """Static normal force [N] of the block's top nodes pulled down by w [m] by springs k_top [N/m]
    (a spring per node and direction to its pressed position: a reduced body cannot take one
    constraint per node), onto a frictionless plane under its bottom nodes; body: "full" or the
    _reduced argument."""
    top, bottom = mesh.node_sets["top"], mesh.node_sets["bottom"]
    if body == "full":
        _, mbs, fe = _body(mesh)
        o = fe["oBody"]

        def marker(j):
            return mbs.AddMarker(MarkerNodePosition(nodeNumber=fe["nodes"][j]))
    else:
        _, mbs, o = _reduced(mesh, body)

        def marker(j):
            return mbs.AddMarker(MarkerSuperElementPosition(bodyNumber=o, meshNodeNumbers=[int(j)],
                                                            weightingFactors=[1.0]))
    g = mbs.AddObject(ObjectGround())
    for j in top:
        mG = mbs.AddMarker(MarkerBodyPosition(bodyNumber=g, localPosition=(mesh.nodes[j] + [0.0, 0.0, -w]).tolist()))
        mbs.AddObject(ObjectConnectorCartesianSpringDamper(markerNumbers=[mG, marker(j)], stiffness=[k_top] * 3))
    return _static_normal_force(mbs, mbs.CreateAnisotropicContact(bodyNumber=o, localPoints=bottom, **_law_kw(eps_n)))


def test_the_reduced_body_converges_to_the_full_body():
    """The pressed block on springs (3 x 3 x 2 cells): Craig-Bampton's static modes of every top and
    bottom coordinate (90 after the rigid motion goes to the frame) give the full body's normal
    force to round-off (measured 4e-12); free-free eigenmodes converge towards it from above as they
    are added, slowly: with few the block is nearly rigid and the contact penalty takes all of w
    (6 modes: 73 times the full force; 96 modes: +8 %, measured)."""
    mesh = block_mesh(SIZE, (3, 3, 2), E=1e6, nu=0.3)
    w, eps_n = 1e-3, 1e6
    full = _pressed_on_springs(mesh, "full", w, eps_n)
    cb = _pressed_on_springs(mesh, [mesh.node_sets["top"], mesh.node_sets["bottom"]], w, eps_n)
    assert cb == pytest.approx(full, rel=1e-9)
    errors = [(_pressed_on_springs(mesh, m, w, eps_n) - full) / full for m in (6, 24, 96)]
    assert errors[0] > 10.0 and errors[-1] > 0.0
    assert errors[0] > errors[1] > errors[2] and errors[2] < 0.2, errors
