"""The elastic block on the polar-orthotropic plane as an Exudyn model (the fe_block scene).

The scene (mesh, contact law, the drive, columns, ledger, its rigid limit) is
``exu_aniso.scenes.fe_block`` (read its module docstring). Here: the body is the full linear FE
body (``exu_aniso.engines.exudyn_adapter.fem.AddLinearFEBody``: one ObjectGenericODE2 of NodePoints) or
Exudyn's ObjectFFRFreducedOrder of the same mesh (``exudyn.FEM.ObjectFFRFreducedOrderInterface``,
its modes from Exudyn's FEMinterface); the contact is one ``mbs.CreateAnisotropicContact`` on the
bottom face's mesh nodes; the driver is a light mass point whose three coordinates follow the
prescribed displacement (``ObjectConnectorCoordinate`` with an offset function), and each top node
is tied to its place on the driver by a ``CartesianSpringDamper`` (C++: no Python per node).

Run ``python -m exu_aniso.models.fe_block`` for a plot of the default scene.
"""
from __future__ import annotations

import numpy as np
import exudyn as exu
from exudyn.FEM import HCBstaticModeSelection, ObjectFFRFreducedOrderInterface
from exudyn.itemInterface import (MarkerBodyPosition, MarkerNodeCoordinate, MarkerNodePosition,
                                  MarkerSuperElementPosition, NodePointGround, ObjectConnectorCartesianSpringDamper,
                                  ObjectConnectorCoordinate, SensorBody, SensorNode, SensorObject,
                                  VObjectConnectorCartesianSpringDamper)

import exu_aniso  # noqa: F401  (binds mbs.CreateAnisotropicContact)
from exu_aniso.engines import energy
from exu_aniso.engines.exudyn_adapter.fem import AddLinearFEBody, FEMinterfaceOf, FloatingFrameMotion
from exu_aniso.engines.exudyn_adapter.runner import (HistoryOutputs, RunScene, SceneView, SettingsInfo,
                                                     SimulationSettingsFor)
from exu_aniso.scenes.fe_block import (DRIVER_MASS_FACTOR, FeBlockParams, contact_columns, drive, fe_block_contact_law,
                                      fe_block_energy, fe_block_mesh, fe_block_summary, top_stiffness)
from exu_aniso.util.validation import check_instance


NEWTON_TOLERANCE = 1e-8
"""Newton's relative and absolute tolerance of the scene: the drive's springs (k ~ 100 E size) leave
the residual a round-off floor of about 1e-16 k size, which the package's 1e-10 falls below as E
grows (E 1e7, 1e8 with 3 x 3 x 3 cells: the step collapses in the first milliseconds; 1e-8 and 1e-6
give the same forces to 1e-6, measured)."""


def ReducedBasis(p, mesh):
    """The FEMinterface of the mesh with the reduced body's modes (FeBlockParams.basis, modes): the
    Craig-Bampton static modes of every top and bottom node coordinate (their rigid-body content to
    the frame: ElasticMesh.without_rigid_motion) plus p.modes fixed-interface eigenmodes, or p.modes
    free-free eigenmodes."""
    fem = FEMinterfaceOf(mesh)
    if p.basis == "eigenmodes":
        fem.ComputeEigenmodes(p.modes, excludeRigidBodyModes=6, useSparseSolver=False)
        return fem
    fem.ComputeHurtyCraigBamptonModes([list(mesh.node_sets["top"]), list(mesh.node_sets["bottom"])], p.modes,
                                      useSparseSolver=False, computationMode=HCBstaticModeSelection.allBoundaryNodes)
    fem.modeBasis["matrix"] = mesh.without_rigid_motion(fem.modeBasis["matrix"])
    return fem


def BuildFeBlock(p: FeBlockParams, jacobian="analytic", implementation="auto", newton="modified",
                 newtonTolerance=NEWTON_TOLERANCE, show=True):
    """Build the fe_block scene; returns dict with SC, mbs, simulationSettings, solverType, params,
    mesh, body (oBody, and nodes for the full body; oBody, nRigid, nModal, basis for the reduced),
    contact, sensors, oDriver, constraints. Options as BuildBlock; show: draw the plane's net and the
    contact points (Exudyn draws the deformed body itself)."""
    check_instance("p", p, FeBlockParams)
    SC = SceneView(exu.SystemContainer())
    mbs = SC.AddSystem()
    mesh = fe_block_mesh(p)
    origin = np.array([p.x0, p.y0, 0.0])
    top, bottom = mesh.node_sets["top"], mesh.node_sets["bottom"]
    sensors = {}
    if p.model == "full":
        fe = AddLinearFEBody(mbs, mesh, position=origin, stiffnessDamping=p.stiffness_damping)
        body = dict(oBody=fe["oBody"], nodes=fe["nodes"])

        def marker(j):
            return mbs.AddMarker(MarkerNodePosition(nodeNumber=fe["nodes"][j]))
        for name, ovt in (("sQ", "Coordinates"), ("sV", "Coordinates_t")):
            sensors[name] = mbs.AddSensor(SensorBody(bodyNumber=fe["oBody"], storeInternal=True,
                                                     outputVariableType=getattr(exu.OutputVariableType, ovt)))
    else:
        fem = ReducedBasis(p, mesh)
        ffrf = ObjectFFRFreducedOrderInterface(fem).AddObjectFFRFreducedOrder(
            mbs, positionRef=origin.tolist(), stiffnessProportionalDamping=p.stiffness_damping,
            color=[0.55, 0.65, 0.8, 1.0])
        body = dict(oBody=ffrf["oFFRFreducedOrder"], nRigid=ffrf["nRigidBody"], nModal=ffrf["nGenericODE2"],
                    basis=np.asarray(fem.modeBasis["matrix"]))

        def marker(j):
            return mbs.AddMarker(MarkerSuperElementPosition(bodyNumber=body["oBody"], meshNodeNumbers=[int(j)],
                                                            weightingFactors=[1.0]))
        for node, key in ((body["nRigid"], "Rigid"), (body["nModal"], "Modal")):
            for ovt in ("Coordinates", "Coordinates_t"):
                sensors[f"s{key}{ovt}"] = mbs.AddSensor(SensorNode(nodeNumber=node, storeInternal=True,
                                                                   outputVariableType=getattr(exu.OutputVariableType,
                                                                                              ovt)))
    # the driver: a light mass point at the top face's centre, its coordinates prescribed
    top_centre = origin + np.array([0.0, 0.0, p.size])
    oDriver = mbs.CreateMassPoint(referencePosition=top_centre.tolist(), mass=DRIVER_MASS_FACTOR * mesh.total_mass,
                                  show=False)
    nDriver = mbs.GetObject(oDriver)["nodeNumber"]
    mGround = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=mbs.AddNode(NodePointGround()), coordinate=0))
    constraints = []
    last = {}

    def prescribed(t):
        """The drive's displacement and velocity at t as lists, evaluated once per time for the six
        offset functions (Exudyn calls them at every Newton iteration)."""
        if last.get("t") != t:
            u, v = drive(p, t)
            last.update(t=t, value=(u[0].tolist(), v[0].tolist()))
        return last["value"]
    for i in range(3):
        def offset(mbs, t, itemNumber, lOffset, i=i):
            return prescribed(t)[0][i]

        def offset_t(mbs, t, itemNumber, lOffset, i=i):      # the index-2 solvers hold the velocity
            return prescribed(t)[1][i]
        m = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=nDriver, coordinate=i))
        constraints.append(mbs.AddObject(ObjectConnectorCoordinate(markerNumbers=[mGround, m],
                                                                   offsetUserFunction=offset,
                                                                   offsetUserFunction_t=offset_t)))
    k = top_stiffness(p)
    for j in top:
        mD = mbs.AddMarker(MarkerBodyPosition(bodyNumber=oDriver, localPosition=(mesh.nodes[j] + origin
                                                                                  - top_centre).tolist()))
        mbs.AddObject(ObjectConnectorCartesianSpringDamper(markerNumbers=[mD, marker(j)], stiffness=[k] * 3,
                                                           visualization=VObjectConnectorCartesianSpringDamper(
                                                               show=False)))
    contact = mbs.CreateAnisotropicContact(name="bottomContact", bodyNumber=body["oBody"], localPoints=bottom,
                                           contactLaw=fe_block_contact_law(p), jacobian=jacobian,
                                           implementation=implementation, show=show, storeHistory=True,
                                           graphicsSize=max(abs(p.x0), abs(p.y0)) + p.travel + p.size)
    sensors["sDriverPosition"] = mbs.AddSensor(SensorNode(nodeNumber=nDriver, storeInternal=True,
                                                          outputVariableType=exu.OutputVariableType.Position))
    sensors["sDriverVelocity"] = mbs.AddSensor(SensorNode(nodeNumber=nDriver, storeInternal=True,
                                                          outputVariableType=exu.OutputVariableType.Velocity))
    sensors["sDrive"] = [mbs.AddSensor(SensorObject(objectNumber=c, storeInternal=True,
                                                    outputVariableType=exu.OutputVariableType.Force))
                         for c in constraints]
    mbs.Assemble()
    ss, st = SimulationSettingsFor(p, newtonTolerance=newtonTolerance, newton=newton)
    return dict(SC=SC, mbs=mbs, simulationSettings=ss, solverType=st, params=p, mesh=mesh, body=body,
                contact=contact, sensors=sensors, oDriver=oDriver, constraints=constraints)


def _node_motion(model):
    """From the stored sensors, per sample: (t, X, V, kinetic, strain, f_d, q) with every mesh node's
    global position X and velocity V (n, N, 3), the body's kinetic and strain energy (n,) [J], and
    its damping force f_d (n, m) over its coordinates q (n, m) (the nodes' displacements of the full
    body, the modal coordinates of the reduced one), whose work the caller integrates."""
    mbs, S, mesh, p = model["mbs"], model["sensors"], model["mesh"], model["params"]
    origin = np.array([p.x0, p.y0, 0.0])
    if p.model == "full":
        Q, Qt = mbs.GetSensorStoredData(S["sQ"]), mbs.GetSensorStoredData(S["sV"])
        t, U, V = Q[:, 0], Q[:, 1:], Qt[:, 1:]
        X = (mesh.nodes + origin)[None] + U.reshape(len(t), -1, 3)
        fd = p.stiffness_damping * (mesh.stiffness @ V.T).T
        return t, X, V.reshape(len(t), -1, 3), mesh.kinetic_energy(V), mesh.strain_energy(U), fd, U
    R, Rt = mbs.GetSensorStoredData(S["sRigidCoordinates"]), mbs.GetSensorStoredData(S["sRigidCoordinates_t"])
    E, Et = mbs.GetSensorStoredData(S["sModalCoordinates"]), mbs.GetSensorStoredData(S["sModalCoordinates_t"])
    t = R[:, 0]
    ref = np.asarray(mbs.GetNodeParameter(model["body"]["nRigid"], "referenceCoordinates"), dtype=float)
    Psi = model["body"]["basis"]
    eta, eta_t = E[:, 1:], Et[:, 1:]
    m = FloatingFrameMotion(mesh, Psi, ref + R[:, 1:], Rt[:, 1:], eta, eta_t)
    return t, m.X, m.V, m.kinetic, m.strain, p.stiffness_damping * eta_t @ m.modal_stiffness, eta


def FeBlockTrajectory(model):
    """Trajectory dict (scenes.fe_block.COLUMNS without the ledger), the bottom nodes' X, V (n, K, 3),
    the history H (n, K, 9) and the ledger's terms, from the stored sensors of a solved model."""
    mbs, S, mesh, p = model["mbs"], model["sensors"], model["mesh"], model["params"]
    t, X, V, kinetic, strain, fd, q = _node_motion(model)
    bottom, top = mesh.node_sets["bottom"], mesh.node_sets["top"]
    D, Dv = mbs.GetSensorStoredData(S["sDriverPosition"])[:, 1:], mbs.GetSensorStoredData(S["sDriverVelocity"])[:, 1:]
    Fc = np.column_stack([mbs.GetSensorStoredData(s)[:, 1] for s in S["sDrive"]])
    # the springs' forces on the block's top nodes: k (their place on the driver - the node)
    origin = np.array([p.x0, p.y0, 0.0])
    offsets = mesh.nodes[top] + origin - (origin + np.array([0.0, 0.0, p.size]))
    stretch = (D[:, None, :] + offsets[None]) - X[:, top]
    k = top_stiffness(p)
    F = k * stretch.sum(axis=1)
    diss, _, H = HistoryOutputs(mbs, model["contact"])
    stick, slip = contact_columns(H)
    u_top, _ = drive(p, t)
    traj = dict(t=t, x_top=p.x0 + u_top[:, 0], y_top=p.y0 + u_top[:, 1],
                x_bottom=X[:, bottom, 0].mean(axis=1), y_bottom=X[:, bottom, 1].mean(axis=1),
                z_bottom=X[:, bottom, 2].mean(axis=1), force_x=F[:, 0], force_y=F[:, 1], force_z=F[:, 2],
                stick_fraction=stick, slip_fraction=slip, strain_energy=strain, dissipated_energy=diss)
    # the drive's work: the constraints' force on the driver along its path (trapezoid); Exudyn's Force
    # output of a coordinate constraint is the multiplier, the force on its second marker's negative
    work_in = -energy.work_trapezoid(Fc, D)
    damping = energy.work_trapezoid(fd, q)
    m_driver = DRIVER_MASS_FACTOR * mesh.total_mass
    terms = dict(kinetic=kinetic + 0.5 * m_driver * np.sum(Dv ** 2, axis=1), strain=strain,
                 springs=0.5 * k * np.sum(stretch ** 2, axis=(1, 2)), damping=damping, work_in=work_in)
    return traj, X[:, bottom], V[:, bottom], H, terms


def RunFeBlock(p: FeBlockParams = None, progress=False, snapshot=None, solutionFile=None, **options):
    """Build and solve the fe_block scene; returns exu_aniso.engines.result.Result (trajectory,
    summary = scenes.fe_block.fe_block_summary with the energy ledger, params, info). options: see
    BuildFeBlock. progress, snapshot, solutionFile: as RunBlock."""
    p = FeBlockParams() if p is None else p
    model = BuildFeBlock(p, **options)

    def partial(failure):
        traj = FeBlockTrajectory(model)[0]
        return traj, fe_block_summary(traj, p, float("nan"), failure.steps, failure.newton_iterations)

    def complete(wall, steps, iters, info):
        traj, Xb, Vb, H, terms = FeBlockTrajectory(model)
        summary = fe_block_summary(traj, p, wall, steps, iters)
        summary.update(fe_block_energy(p, traj, Xb, Vb, H, **terms))
        info.update(**SettingsInfo(model["simulationSettings"], [model["contact"]]))
        return traj, summary
    return RunScene(model, p, "fe_block", [model["contact"]], partial, complete, progress, snapshot, solutionFile)


if __name__ == "__main__":
    import matplotlib.pyplot as plt

    from exu_aniso.scenes.fe_block import PlotFeBlock

    result = RunFeBlock(FeBlockParams(), progress=True)
    print({k: v for k, v in result.summary.items() if not isinstance(v, dict)})
    fig = plt.figure(figsize=(11, 4.5))
    PlotFeBlock(result.trajectory, result.params, fig)
    fig.tight_layout()
    plt.show()
