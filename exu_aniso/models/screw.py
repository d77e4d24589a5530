"""Screw in a threaded hole (spiral orthotropy) as an Exudyn model (paper 001, Fig. 2).

A rigid cylindrical screw carrying ``rings`` x ``points_per_ring`` contact points on the radius
``radius + interference``, inside the hole (cylinder of radius ``radius``, axis z) whose adhesion
and friction follow a spiral (thread) net; the interference fit is the normal pressure. Models,
drives and trajectory keys are those of ``exu_aniso.engines.reference`` (read its module docstring):

* ``model="reduced"``: a ``NodeGenericODE2`` with 2 coordinates (psi about z [rad], z [m]) and an
  ``ObjectGenericODE2`` with mass matrix diag(J_axial, m), J_axial = m r^2 / 2 (the contact set
  treats this node as a screw joint on the hole axis);
* ``model="full"``: ``mbs.CreateRigidBody`` (6 DOF, Lie-group rotation vector by default, Euler
  parameters allowed) with J = diag(J_t, J_t, J_axial), J_t = m (3 r^2 + L^2) / 12, centred on the
  hole axis, no gravity;
* drives: "torque" -> constant torque tau about +z (Exudyn load); "rotation" -> torsional spring
  tau = k (omega_d t - psi) to a rotating driver; "axial" -> spring F = k (v_d t - z) along +z.
  The springs on a coordinate (the reduced model's psi and z, the full model's z) are Exudyn C++
  items (``AddSpringDrive``: a coordinate spring to a driver coordinate held at constant
  velocity), so no Python runs in them (under an explicit solver, which cannot solve constraints,
  they are Python springs); the full model's rotation drive acts on the yaw and is an
  ``ObjectGenericODE2`` with its exact Jacobian in Python (``AddNodeDrive``). axial_load
  is a constant Exudyn load along +z in every drive. In the full model psi is the unwrapped yaw
  atan2(A_10, A_00), as in the reference.

Run ``python -m exu_aniso.models.screw`` (or this file) for plots of the default scene.
"""
from __future__ import annotations

import exudyn as exu
import numpy as np
from exudyn import graphics
from exudyn.itemInterface import LoadCoordinate, MarkerNodeCoordinate, SensorNode
from exudyn.rigidBodyUtilities import RigidBodyInertia

import exu_aniso  # noqa: F401  (binds mbs.CreateAnisotropicContact)
from exu_aniso.engines.exudyn_adapter.runner import (SceneView, IMPLICIT_SOLVERS, NODE_TYPES, AddSpringDrive,
                                                     AddScrewJointBody, AddYawDrive, HistoryOutputs,
                                                     ModelScript, SensorMotion, SimulationSettingsFor,
                                                     SolveTimed, Unwrap)
from exu_aniso.scenes.screw import SCENE, ScrewParams, reduced_motion, screw_contact_law, screw_points
from exu_aniso.util.validation import check_bool, check_instance


def _drive_torque(p, psi, t):
    """Drive torque about +z [N m] and its derivative by psi."""
    if p.drive == "torque":
        return p.torque, 0.0
    if p.drive == "rotation":
        return p.drive_stiffness * (p.rotation_speed * t - psi), -p.drive_stiffness
    return 0.0, 0.0


def _axial_force(p, z, t):
    """Axial force along +z [N] (axial_load plus the axial drive spring)."""
    return p.axial_load + (p.drive_stiffness * (p.axial_speed * t - z) if p.drive == "axial" else 0.0)


def ScrewGraphics(p):
    """Body graphics of the screw: a cylinder of the hole's radius over the contact length, centred on
    the body's origin along its z axis, in two alternating colours so that its rotation shows."""
    L = p.length
    return [graphics.Cylinder(pAxis=[0.0, 0.0, -0.5 * L], vAxis=[0.0, 0.0, L], radius=p.radius, nTiles=32,
                              color=graphics.color.steelblue, alternatingColor=graphics.color.lightgrey)]


def BuildScrew(p: ScrewParams, jacobian="analytic", nodeType="RotVecLG", solverType=None, rhoInf=0.8,
               newtonTolerance=1e-10, implementation="auto", symmetry=True, contactBuilder=None, newton="modified",
               contactOutputs=True):
    """Build the screw scene; returns dict with SC, mbs, simulationSettings, solverType, params,
    nScrew, oScrew, contact (dict of CreateAnisotropicContact), sensors (dict), oDrive (or None).
    Options as for exu_aniso.models.block.BuildBlock (contactBuilder gets the evaluated points), and
    symmetry (reduced model only): True -> one representative contact point carrying the totals
    eps_n, eps_1, eps_2. Under the screw joint (rotation about and translation along the hole
    axis) every point of the layout sits at the same radius in the same rotation- and
    translation-invariant spiral field with the same history, so all points have the same state.
    Their summed generalized force equals that of one point with the total stiffnesses, because
    the return maps are positively homogeneous in (B, N). The two give the same trajectory to
    round-off (tests/test_fastpath.py). False -> every point of the rings x points_per_ring
    layout is evaluated. contactOutputs: a completed run's trajectory also holds the contact's torque
    and axial force (``ScrewTrajectory``)."""
    if nodeType not in NODE_TYPES:
        raise ValueError(f"nodeType must be one of {tuple(NODE_TYPES)}; got {nodeType!r}")
    check_instance("p", p, ScrewParams)
    check_bool("contactOutputs", contactOutputs)
    if p.model == "full" and p.points_per_ring < 3:
        raise ValueError(f"points_per_ring must be >= 3 for model='full' (radial centring); got {p.points_per_ring}")
    SC = SceneView(exu.SystemContainer())
    mbs = SC.AddSystem()

    m, r, L = p.mass, p.radius, p.length        # mass [kg], hole radius [m], contact length [m]
    Ja = 0.5 * m * r * r                        # axial moment of inertia [kg m^2]
    Jt = m * (3.0 * r * r + L * L) / 12.0       # transverse moment of inertia [kg m^2]
    sensors = {}
    oDrive = None
    explicit = solverType is not None and solverType not in IMPLICIT_SOLVERS   # drives without constraints
    if p.model == "reduced":
        oScrew, nScrew = AddScrewJointBody(mbs, m, Ja, ScrewGraphics(p))
        mPsi = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=nScrew, coordinate=0))
        mZ = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=nScrew, coordinate=1))
        if p.drive == "torque":
            mbs.AddLoad(LoadCoordinate(markerNumber=mPsi, load=p.torque))
        mbs.AddLoad(LoadCoordinate(markerNumber=mZ, load=p.axial_load))
        if p.drive in ("rotation", "axial"):
            along, rate = ([1.0, 0.0], p.rotation_speed) if p.drive == "rotation" else ([0.0, 1.0], p.axial_speed)
            oDrive = AddSpringDrive(mbs, nScrew, along, p.drive_stiffness, rate, python=explicit)
        sensors["sCoordinates"] = mbs.AddSensor(SensorNode(nodeNumber=nScrew, storeInternal=True,
                                                           outputVariableType=exu.OutputVariableType.Coordinates))
        sensors["sVelocities"] = mbs.AddSensor(SensorNode(nodeNumber=nScrew, storeInternal=True,
                                                          outputVariableType=exu.OutputVariableType.Coordinates_t))
    else:
        oScrew = mbs.CreateRigidBody(inertia=RigidBodyInertia(mass=m, inertiaTensor=np.diag([Jt, Jt, Ja])),
                                     referencePosition=[0.0, 0.0, 0.0], nodeType=NODE_TYPES[nodeType],
                                     graphicsDataList=ScrewGraphics(p))
        nScrew = mbs.GetObject(oScrew)["nodeNumber"]
        if p.drive == "torque":
            mbs.CreateTorque(itemNumber=oScrew, loadVector=[0.0, 0.0, p.torque])
        mbs.CreateForce(itemNumber=oScrew, loadVector=[0.0, 0.0, p.axial_load])
        if p.drive == "axial":                    # z is coordinate 2 of both rigid node types
            nq = 7 if nodeType == "EP" else 6
            oDrive = AddSpringDrive(mbs, nScrew, np.eye(nq)[2], p.drive_stiffness, p.axial_speed, python=explicit)
        elif p.drive == "rotation":
            oDrive = AddYawDrive(mbs, nScrew, nodeType, lambda yaw, t: _drive_torque(p, yaw, t))
        for name, ovt in (("sPosition", "Position"), ("sVelocity", "Velocity"),
                          ("sRotation", "RotationMatrix"), ("sOmega", "AngularVelocity")):
            sensors[name] = mbs.AddSensor(SensorNode(nodeNumber=nScrew, storeInternal=True,
                                                     outputVariableType=getattr(exu.OutputVariableType, ovt)))

    # under the screw joint every point of a ring has the same state; on a cylinder every ring too
    pc = p
    if symmetry and p.model == "reduced":
        pc = p.with_overrides(rings=1, points_per_ring=1) if (p.surface == "cylinder" or p.half_angle == 0.0) \
            else p.with_overrides(points_per_ring=1)
    if contactBuilder is None:
        contact = mbs.CreateAnisotropicContact(name="threadContact", bodyNumber=oScrew, localPoints=screw_points(pc),
                                               contactLaw=screw_contact_law(pc), jacobian=jacobian,
                                               initializeHistory=True, implementation=implementation,
                                               storeHistory=True)   # the ledger and the summary read it
    else:
        contact = contactBuilder(mbs, oScrew, screw_points(pc))
    mbs.Assemble()
    ss, st = SimulationSettingsFor(p, rhoInf=rhoInf, newtonTolerance=newtonTolerance, solverType=solverType,
                                   newton=newton)
    return dict(SC=SC, mbs=mbs, simulationSettings=ss, solverType=st, params=p, nScrew=nScrew, oScrew=oScrew,
                contact=contact, sensors=sensors, oDrive=oDrive, nodeType=nodeType, contactOutputs=contactOutputs)


def ScrewTrajectory(model, contactOutputs=True, history=None):
    """Trajectory dict (reference keys) from the stored sensors of a solved BuildScrew model.

    contactOutputs: also contact_torque [N m] and contact_axial_force [N], re-evaluated from the
    stored states and the history of the previous step (what the solver saw at convergence);
    history: the contact's HistoryOutputs when the caller has them already."""
    mbs, p, S = model["mbs"], model["params"], model["sensors"]
    diss, slip, H = HistoryOutputs(mbs, model["contact"]) if history is None else history
    s = np.asarray(model["contact"]["points"])   # the evaluated points (one under symmetry)
    if p.model == "reduced":
        Q = mbs.GetSensorStoredData(S["sCoordinates"])
        V = mbs.GetSensorStoredData(S["sVelocities"])
        t, psi, z = Q[:, 0], Q[:, 1], Q[:, 2]
        traj = dict(t=t, angle=psi, z=z, omega=V[:, 1], vz=V[:, 2])
        c, sn = np.cos(psi), np.sin(psi)
        A = np.zeros((len(t), 3, 3))
        A[:, 0, 0], A[:, 0, 1], A[:, 1, 0], A[:, 1, 1], A[:, 2, 2] = c, -sn, sn, c, 1.0
        pos = np.column_stack([np.zeros_like(t), np.zeros_like(t), z])
        vel = np.column_stack([np.zeros_like(t), np.zeros_like(t), V[:, 2]])
        w = np.column_stack([np.zeros_like(t), np.zeros_like(t), V[:, 1]])
    else:
        P = mbs.GetSensorStoredData(S["sPosition"])
        V = mbs.GetSensorStoredData(S["sVelocity"])
        A = mbs.GetSensorStoredData(S["sRotation"])[:, 1:].reshape(-1, 3, 3)
        W = mbs.GetSensorStoredData(S["sOmega"])
        t = P[:, 0]
        psi = Unwrap(np.arctan2(A[:, 1, 0], A[:, 0, 0]))
        traj = dict(t=t, angle=psi, z=P[:, 3], omega=W[:, 3], vz=V[:, 3], x=P[:, 1], y=P[:, 2],
                    tilt=np.arccos(np.clip(A[:, 2, 2], -1.0, 1.0)))
        pos, vel, w = P[:, 1:], V[:, 1:], W[:, 1:]
    traj["torque"] = np.array([_drive_torque(p, a, ti)[0] for a, ti in zip(psi, t)])
    traj["axial_force"] = np.array([_axial_force(p, zi, ti) for zi, ti in zip(traj["z"], t)])
    if contactOutputs and p.model == "reduced":
        # the contact object's generalized force on (psi, z) is the torque about the axis and the axial
        # force, from the set's own kernel (no second compiled law to build for post-processing)
        previous = np.concatenate([H[:1], H[:-1]])        # the history each sample's step started from
        G = model["contact"]["generalizedForce"](np.column_stack([psi, z]), np.column_stack([traj["omega"], traj["vz"]]),
                                                 previous)
        traj["contact_torque"], traj["contact_axial_force"] = G[:, 0], G[:, 1]
    elif contactOutputs:
        law = model["contact"]["law"]
        ct, cf = np.zeros(len(t)), np.zeros(len(t))
        for n in range(len(t)):
            arm = s @ A[n].T
            x = pos[n] + arm
            v = vel[n] + np.cross(w[n], arm)
            f = law.evaluate(x, v, H[max(n - 1, 0)], tangent=False).force
            ct[n] = np.sum(arm[:, 0] * f[:, 1] - arm[:, 1] * f[:, 0])
            cf[n] = f[:, 2].sum()
        traj["contact_torque"], traj["contact_axial_force"] = ct, cf
    traj["dissipated_energy"] = diss
    traj["slip_distance"] = slip
    return traj


def ScrewMotion(model, traj):
    """energy.RigidMotion of the screw: the full model's from its sensors, the reduced one's from the
    trajectory."""
    return SensorMotion(model) if model["params"].model == "full" else reduced_motion(traj)


def ReadScrew(model, complete):
    """What ``ModelScript.run`` reads from a solved BuildScrew model: the trajectory (with the
    contact's outputs when the model was built with contactOutputs and the run completed), the
    summary's inputs (none) and, for a completed run, the ledger's (the screw's motion, the evaluated
    points, the contact law and its history)."""
    if not complete:
        return ScrewTrajectory(model, contactOutputs=False), {}, None
    history = HistoryOutputs(model["mbs"], model["contact"])
    traj = ScrewTrajectory(model, model["contactOutputs"], history)
    return traj, {}, dict(motion=ScrewMotion(model, traj), points=np.asarray(model["contact"]["points"]),
                          law=model["contact"]["law"], H=history[2])


def ScrewInfo(model):
    """The screw's entries of a run's info: the model and its node type."""
    p = model["params"]
    return dict(model=p.model, nodeType=model["nodeType"] if p.model == "full" else "GenericODE2")


MODEL = ModelScript(SCENE, BuildScrew, ReadScrew, info=ScrewInfo)

RunScrew = MODEL.run
"""Build (``BuildScrew(p, **options)``) and solve the screw scene: ``ModelScript.run``, which returns
an ``exu_aniso.engines.result.Result`` with the reference's trajectory keys, the summary
(``scenes.screw.screw_summary``) and the energy ledger."""


if __name__ == "__main__":
    p = ScrewParams()                           # defaults: spiral net, radial map, rotating driver
    model = BuildScrew(p)
    mbs = model["mbs"]
    SolveTimed(mbs, model["simulationSettings"], model["solverType"])
    mbs.PlotSensor(model["sensors"]["sCoordinates"], components=[1], componentsX=[0],
                   labels=["axial advance z [m] vs rotation psi [rad]"], closeAll=True)
    mbs.PlotSensor(model["contact"]["sDissipation"], components=0, labels=["dissipated energy [J]"])
