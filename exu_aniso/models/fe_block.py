"""The elastic block on the polar-orthotropic plane as an Exudyn model (the fe_block scene).

The scene (mesh, basis, contact law, the drive, columns, ledger, its rigid limit) is
``exu_aniso.scenes.fe_block`` (read its module docstring). Here: the block is Exudyn's
ObjectFFRFreducedOrder (``exudyn.FEM.ObjectFFRFreducedOrderInterface``: an Euler-parameter frame and
the modal coordinates) of the mesh with the scene's basis, which vanishes at the top face, so that
the frame is the top face's rigid motion: the press plate bonded to it. The frame's height follows
the press (``ObjectConnectorCoordinate`` with an offset function), its tilt is held by two
coordinate constraints on its Euler parameters e1 = e2 = 0 (a rotation about the vertical only),
and the drive is the block scene's spring and dashpot along d (``runner.AddSpringDrive``, its driver
at rest until t_press). The contact is one ``mbs.CreateAnisotropicContact`` on the bottom face's
mesh nodes.

Run ``python -m exu_aniso.models.fe_block`` for a plot of the default scene.
"""
from __future__ import annotations

import numpy as np
import exudyn as exu
from exudyn.FEM import ObjectFFRFreducedOrderInterface
from exudyn.itemInterface import MarkerNodeCoordinate, NodePointGround, ObjectConnectorCoordinate, SensorNode, SensorObject

import exu_aniso  # noqa: F401  (binds mbs.CreateAnisotropicContact)
from exu_aniso.engines import energy
from exu_aniso.engines.exudyn_adapter.fem import FEMinterfaceOf, FloatingFrameMotion
from exu_aniso.engines.exudyn_adapter.runner import (AddSpringDrive, HistoryOutputs, ModelScript, SceneView,
                                                     SimulationSettingsFor)
from exu_aniso.engines.timing import driver_travel
from exu_aniso.scenes.fe_block import (SCENE, FeBlockParams, contact_columns, contact_compliance, drive_direction,
                                      drive_speed, drive_stretch, fe_block_basis, fe_block_contact_law, fe_block_mesh,
                                      press_depth)
from exu_aniso.util.validation import check_instance


def BuildFeBlock(p: FeBlockParams, jacobian="analytic", implementation="auto", newton="modified",
                 newtonTolerance=1e-10, show=True):
    """Build the fe_block scene; returns dict with SC, mbs, simulationSettings, solverType, params,
    mesh, body (oBody, nRigid, nModal, basis), contact, sensors, oDrive, constraints (press, tilt_x,
    tilt_y). Options as BuildBlock; show: draw the plane's net and the contact points (Exudyn draws
    the deformed block itself)."""
    check_instance("p", p, FeBlockParams)
    SC = SceneView(exu.SystemContainer())
    mbs = SC.AddSystem()
    mesh = fe_block_mesh(p)
    fem = FEMinterfaceOf(mesh)
    fem.modeBasis = {"matrix": fe_block_basis(p, mesh), "type": "NormalModes"}
    ffrf = ObjectFFRFreducedOrderInterface(fem).AddObjectFFRFreducedOrder(
        mbs, positionRef=[p.x0, p.y0, 0.0], stiffnessProportionalDamping=p.stiffness_damping,
        color=[0.55, 0.65, 0.8, 1.0])
    body = dict(oBody=ffrf["oFFRFreducedOrder"], nRigid=ffrf["nRigidBody"], nModal=ffrf["nGenericODE2"],
                basis=np.asarray(fem.modeBasis["matrix"]))
    nFrame = body["nRigid"]
    mGround = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=mbs.AddNode(NodePointGround()), coordinate=0))
    last = {}

    def descent(t):
        """The frame's prescribed height offset and its rate at t, evaluated once per time (Exudyn
        calls the offset functions at every Newton iteration; the index-2 solvers hold the rate)."""
        if last.get("t") != t:
            w, w_t = press_depth(p, t)
            last.update(t=t, value=(-float(w[0]), -float(w_t[0])))
        return last["value"]
    constraints = {}
    for i, name in ((2, "press"), (4, "tilt_x"), (5, "tilt_y")):      # z; Euler parameters e1, e2
        m = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=nFrame, coordinate=i))
        held = (dict(offsetUserFunction=lambda mbs, t, item, offset: descent(t)[0],
                     offsetUserFunction_t=lambda mbs, t, item, offset: descent(t)[1])
                if name == "press" else dict(offset=0.0))
        constraints[name] = mbs.AddObject(ObjectConnectorCoordinate(markerNumbers=[mGround, m], **held))
    d = drive_direction(p)
    oDrive = AddSpringDrive(mbs, nFrame, [d[0], d[1], 0.0, 0.0, 0.0, 0.0, 0.0], p.drive_stiffness, drive_speed(p),
                            start=p.t_press, ramp=p.drive_ramp, damping=p.drive_damping)
    contact = mbs.CreateAnisotropicContact(name="bottomContact", bodyNumber=body["oBody"],
                                           localPoints=mesh.node_sets["bottom"], contactLaw=fe_block_contact_law(p),
                                           jacobian=jacobian, implementation=implementation, show=show,
                                           storeHistory=True,
                                           graphicsSize=max(abs(p.x0), abs(p.y0)) + p.travel + p.size)
    sensors = {}
    for node, key in ((nFrame, "Rigid"), (body["nModal"], "Modal")):
        for ovt in ("Coordinates", "Coordinates_t"):
            sensors[f"s{key}{ovt}"] = mbs.AddSensor(SensorNode(nodeNumber=node, storeInternal=True,
                                                               outputVariableType=getattr(exu.OutputVariableType, ovt)))
    sensors["sPress"] = mbs.AddSensor(SensorObject(objectNumber=constraints["press"], storeInternal=True,
                                                   outputVariableType=exu.OutputVariableType.Force))
    mbs.Assemble()
    ss, st = SimulationSettingsFor(p, newtonTolerance=newtonTolerance, newton=newton)
    return dict(SC=SC, mbs=mbs, simulationSettings=ss, solverType=st, params=p, mesh=mesh, body=body,
                contact=contact, sensors=sensors, oDrive=oDrive, constraints=constraints)


def FeBlockTrajectory(model):
    """Trajectory dict (scenes.fe_block.COLUMNS without the ledger and the contact's energy), the bottom
    nodes' X, V (n, K, 3), the history H (n, K, 9) and the work in (n,) [J], from the stored sensors of
    a solved model."""
    mbs, S, mesh, p, body = model["mbs"], model["sensors"], model["mesh"], model["params"], model["body"]
    R, Rt = mbs.GetSensorStoredData(S["sRigidCoordinates"]), mbs.GetSensorStoredData(S["sRigidCoordinates_t"])
    E, Et = mbs.GetSensorStoredData(S["sModalCoordinates"]), mbs.GetSensorStoredData(S["sModalCoordinates_t"])
    t = R[:, 0]
    q = np.asarray(mbs.GetNodeParameter(body["nRigid"], "referenceCoordinates"), dtype=float) + R[:, 1:]
    eta, eta_t = E[:, 1:], Et[:, 1:]
    m = FloatingFrameMotion(mesh, body["basis"], q, Rt[:, 1:], eta, eta_t)
    lam = mbs.GetSensorStoredData(S["sPress"])[:, 1]
    bottom = mesh.node_sets["bottom"]
    d = drive_direction(p)
    stretch, rate = drive_stretch(p, t, q[:, 0], q[:, 1], Rt[:, 1], Rt[:, 2])
    Fd = p.drive_stiffness * stretch + p.drive_damping * rate
    diss, _, H = HistoryOutputs(mbs, model["contact"])
    stick, slip = contact_columns(H)
    Xb = m.X[:, bottom]
    # the forces applied at the frame: the drive's along d (x, y) and the press's (z; lam: Exudyn's Force
    # output of a coordinate constraint is the multiplier, the force on its second marker's negative)
    traj = dict(t=t, x_top=q[:, 0], y_top=q[:, 1], yaw_top=np.arctan2(m.rotation[:, 1, 0], m.rotation[:, 0, 0]),
                x_bottom=Xb[..., 0].mean(axis=1), y_bottom=Xb[..., 1].mean(axis=1), z_bottom=Xb[..., 2].mean(axis=1),
                drive_force=Fd, force_x=Fd * d[0], force_y=Fd * d[1],
                force_z=-lam, z_top=q[:, 2], drive_stretch=stretch, stick_fraction=stick, slip_fraction=slip,
                strain_energy=m.strain, dissipated_energy=diss, kinetic_energy=m.kinetic,
                drive_spring_energy=0.5 * p.drive_stiffness * stretch ** 2,
                rayleigh_dissipated_energy=energy.work_trapezoid(p.stiffness_damping * eta_t @ m.modal_stiffness, eta),
                drive_dashpot_dissipated_energy=energy.work_trapezoid(p.drive_damping * rate, stretch))
    # work in: the driver's (the drive's force along its travel) and the press's
    travel, _ = driver_travel(t, drive_speed(p), p.t_press, p.drive_ramp)
    work_in = energy.work_trapezoid(Fd, travel) - energy.work_trapezoid(lam, q[:, 2])
    return traj, Xb, m.V[:, bottom], H, work_in


def ReadFeBlock(model, complete):
    """What ``ModelScript.run`` reads from a solved BuildFeBlock model: the trajectory, the summary's
    inputs (a completed run's basis compliance, which warns below its floor) and, for a completed run,
    the ledger's (``FeBlockTrajectory``'s bottom nodes, history and work in)."""
    traj, Xb, Vb, H, work_in = FeBlockTrajectory(model)
    if not complete:
        return traj, {}, None
    compliance = contact_compliance(model["params"], model["mesh"], model["body"]["basis"])
    return traj, dict(compliance=compliance), dict(Xb=Xb, Vb=Vb, H=H, work_in=work_in)


MODEL = ModelScript(SCENE, BuildFeBlock, ReadFeBlock)

RunFeBlock = MODEL.run
"""Build (``BuildFeBlock(p, **options)``) and solve the fe_block scene: ``ModelScript.run``, which returns
an ``exu_aniso.engines.result.Result`` with ``scenes.fe_block.COLUMNS``, the summary
(``scenes.fe_block.fe_block_summary``) with the basis's compliance entries, and the energy ledger."""


if __name__ == "__main__":
    MODEL.show()
