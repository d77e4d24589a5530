"""The elastic screw in a hole with a spiral net as an Exudyn model (the fe_screw scene).

The scene (mesh, contact law, basis, the twist's closed form, summary, ledger, its rigid limit) is
``exu_aniso.scenes.fe_screw`` (read its module docstring). Here: the shank is Exudyn's
ObjectFFRFreducedOrder (``exudyn.FEM.ObjectFFRFreducedOrderInterface``: an Euler-parameter frame and
the modal coordinates) of the mesh with the scene's basis, which vanishes at the head, so that the
frame is the head's rigid motion; the drive is a torsional spring from a driver at constant speed
to the frame's yaw (``AddYawDrive``); the axial load an Exudyn load on the frame's node; the contact
one ``mbs.CreateAnisotropicContact`` on the thread nodes.

Run ``python -m exu_aniso.models.fe_screw`` for a plot of the default scene.
"""
from __future__ import annotations

import numpy as np
import exudyn as exu
from exudyn.FEM import ObjectFFRFreducedOrderInterface
from exudyn.itemInterface import LoadForceVector, MarkerNodePosition, SensorNode

import exu_aniso  # noqa: F401  (binds mbs.CreateAnisotropicContact)
from exu_aniso.engines import energy
from exu_aniso.engines.exudyn_adapter.fem import FEMinterfaceOf, FloatingFrameMotion
from exu_aniso.engines.exudyn_adapter.runner import (AddYawDrive, HistoryOutputs, ModelScript, SceneView,
                                                     SimulationSettingsFor, Unwrap)
from exu_aniso.scenes.fe_screw import (SCENE, FeScrewParams, contact_compliance, fe_screw_basis, fe_screw_columns,
                                      fe_screw_contact_law, fe_screw_mesh, press_fit, ring_twist)
from exu_aniso.util.validation import check_instance


NEWTON_CONTRACTIVITY = 0.5
"""modified Newton's Jacobian refresh of this scene (Exudyn's own threshold; the package's is 0.01,
exu_aniso.engines.exudyn_adapter.solver_settings): Exudyn differentiates the floating-frame body
numerically, one evaluation per mode, so a Jacobian costs more than the extra iterations of a kept one:
at 0.5 a run refreshes it less often than at 0.01 and takes less wall time, with the same torque and
tip twist to Newton's tolerance."""


def BuildFeScrew(p: FeScrewParams, jacobian="analytic", implementation="auto", newton="modified",
                 newtonTolerance=1e-10, show=True):
    """Build the fe_screw scene; returns dict with SC, mbs, simulationSettings, solverType, params,
    mesh, body (oBody, nRigid, nModal, basis), contact, sensors, oDrive. Options as BuildBlock; show:
    draw the hole's net and the contact states (Exudyn draws the deformed shank itself)."""
    check_instance("p", p, FeScrewParams)
    SC = SceneView(exu.SystemContainer())
    mbs = SC.AddSystem()
    mesh = fe_screw_mesh(p)
    fem = FEMinterfaceOf(mesh)
    fem.modeBasis = {"matrix": fe_screw_basis(p, mesh), "type": "NormalModes"}
    ffrf = ObjectFFRFreducedOrderInterface(fem).AddObjectFFRFreducedOrder(
        mbs, positionRef=[0.0, 0.0, 0.0], stiffnessProportionalDamping=p.stiffness_damping,
        color=[0.55, 0.65, 0.8, 1.0])
    body = dict(oBody=ffrf["oFFRFreducedOrder"], nRigid=ffrf["nRigidBody"], nModal=ffrf["nGenericODE2"],
                basis=np.asarray(fem.modeBasis["matrix"]))
    # the shank starts pressed into the hole at rest (scenes.fe_screw.press_fit), before the contact reads it
    mbs.SetNodeParameter(body["nModal"], "initialCoordinates", press_fit(p, mesh, body["basis"]).tolist())
    k, w = p.drive_stiffness, p.rotation_speed
    oDrive = AddYawDrive(mbs, body["nRigid"], "EP", lambda yaw, t: (k * (w * t - yaw), -k))
    if p.axial_load != 0.0:
        mbs.AddLoad(LoadForceVector(markerNumber=mbs.AddMarker(MarkerNodePosition(nodeNumber=body["nRigid"])),
                                    loadVector=[0.0, 0.0, p.axial_load]))
    contact = mbs.CreateAnisotropicContact(name="threadContact", bodyNumber=body["oBody"],
                                           localPoints=mesh.node_sets["thread"], contactLaw=fe_screw_contact_law(p),
                                           jacobian=jacobian, implementation=implementation, show=show,
                                           storeHistory=True)
    sensors = {}
    for node, key in ((body["nRigid"], "Rigid"), (body["nModal"], "Modal")):
        for ovt in ("Coordinates", "Coordinates_t"):
            sensors[f"s{key}{ovt}"] = mbs.AddSensor(SensorNode(nodeNumber=node, storeInternal=True,
                                                               outputVariableType=getattr(exu.OutputVariableType, ovt)))
    mbs.Assemble()
    ss, st = SimulationSettingsFor(p, newtonTolerance=newtonTolerance, newton=newton)
    ss.timeIntegration.newton.modifiedNewtonContractivity = NEWTON_CONTRACTIVITY
    return dict(SC=SC, mbs=mbs, simulationSettings=ss, solverType=st, params=p, mesh=mesh, body=body,
                contact=contact, sensors=sensors, oDrive=oDrive,
                compliance=contact_compliance(p, mesh, body["basis"], warn=False))


def FeScrewTrajectory(model):
    """Trajectory dict (scenes.fe_screw.COLUMNS without the ledger, and twist_rings (n, rings)), the
    thread nodes' X, V (n, K, 3) and the history H (n, K, 9), from the stored sensors of a solved
    model."""
    mbs, S, mesh, p, body = model["mbs"], model["sensors"], model["mesh"], model["params"], model["body"]
    R, Rt = mbs.GetSensorStoredData(S["sRigidCoordinates"]), mbs.GetSensorStoredData(S["sRigidCoordinates_t"])
    E, Et = mbs.GetSensorStoredData(S["sModalCoordinates"]), mbs.GetSensorStoredData(S["sModalCoordinates_t"])
    t = R[:, 0]
    q = np.asarray(mbs.GetNodeParameter(body["nRigid"], "referenceCoordinates"), dtype=float) + R[:, 1:]
    Psi, eta, eta_t = body["basis"], E[:, 1:], Et[:, 1:]
    m = FloatingFrameMotion(mesh, Psi, q, Rt[:, 1:], eta, eta_t)
    angle = Unwrap(np.arctan2(m.rotation[:, 1, 0], m.rotation[:, 0, 0]))
    twist = ring_twist(p, mesh, m.U)
    diss, _, H = HistoryOutputs(mbs, model["contact"])
    traj = dict(t=t, angle=angle, z=q[:, 2], omega=m.omega[:, 2], vz=Rt[:, 3],
                torque=p.drive_stiffness * (p.rotation_speed * t - angle), axial_force=np.full(len(t), p.axial_load),
                twist_tip=twist[:, 0], twist_rings=twist, strain_energy=m.strain, dissipated_energy=diss,
                kinetic_energy=m.kinetic,
                rayleigh_dissipated_energy=energy.work_trapezoid(p.stiffness_damping * eta_t @ m.modal_stiffness, eta))
    fe_screw_columns(traj, H)
    thread = mesh.node_sets["thread"]
    return traj, m.X[:, thread], m.V[:, thread], H


def ReadFeScrew(model, complete):
    """What ``ModelScript.run`` reads from a solved BuildFeScrew model: the trajectory, the summary's
    inputs (the basis's compliance: a completed run's warns below its floor) and, for a completed run,
    the ledger's (the thread nodes' X, V and history H)."""
    traj, X, V, H = FeScrewTrajectory(model)
    if not complete:
        return traj, dict(compliance=model["compliance"]), None
    compliance = contact_compliance(model["params"], model["mesh"], model["body"]["basis"])
    return traj, dict(compliance=compliance), dict(X=X, V=V, H=H)


MODEL = ModelScript(SCENE, BuildFeScrew, ReadFeScrew)

RunFeScrew = MODEL.run
"""Build (``BuildFeScrew(p, **options)``) and solve the fe_screw scene: ``ModelScript.run``, which returns
an ``exu_aniso.engines.result.Result`` with ``scenes.fe_screw.COLUMNS``, the summary
(``scenes.fe_screw.fe_screw_summary``) with the basis's contact_compliance_share and basis_warning (a
BasisWarning when it is not None), and the energy ledger."""


if __name__ == "__main__":
    MODEL.show()
