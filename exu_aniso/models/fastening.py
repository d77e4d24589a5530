"""A bolt tightened into a nut as an Exudyn model (the fastening scene: read
``exu_aniso.scenes.fastening``'s module docstring).

The bolt is ``mbs.CreateRigidBody`` (6 DOF, Lie-group rotation vector) with two contact sets: its
thread points on the nut's thread (a Helicoid flank or a spiral net on a Cylinder, fixed to ground)
and its head's bearing ring on the clamped part's top face (``masterBodyNumber``: the part). The
clamped part is a rigid body on a C++ Cartesian spring-damper (``joint_stiffness`` along z only),
its other five motions locked by a C++ generic joint. The drive is a torsional spring about the world
z axis to a driver turning at ``rotation_speed`` (``AddYawDrive``, Python with its exact Jacobian);
``axial_load`` is a constant Exudyn load along -z on the bolt.

Run ``python -m exu_aniso.models.fastening`` for the torque-angle plot of the default scene.
"""
from __future__ import annotations

import math

import exudyn as exu
import numpy as np
from exudyn import graphics
from exudyn.itemInterface import SensorNode
from exudyn.rigidBodyUtilities import RigidBodyInertia, RotationMatrixX
from exudyn.utilities import InertiaCuboid

import exu_aniso  # noqa: F401  (binds mbs.CreateAnisotropicContact)
from exu_aniso.engines import energy
from exu_aniso.law.history import H_DISSIPATED
from exu_aniso.scenes import threads
from exu_aniso.engines.exudyn_adapter.runner import (SceneView, NODE_TYPES, SNAPSHOT_ROTATION, AddYawDrive, ModelScript,
                                                     SimulationSettingsFor, Unwrap)
from exu_aniso.scenes.fastening import (SCENE, FasteningParams, bolt_inertia, contact_torques, driver_angle,
                                       head_contact_law, head_points, head_z, joint_damping, lead, part_top_z,
                                       thread_contact_law, thread_points)
from exu_aniso.util.validation import check_instance

# Newton's relative and absolute tolerance. The residual of this scene stalls at ~4e-7 (1.6e-8 of the first
# step's initial residual; stick and slip of the thread points alternating between iterates), so the scenes'
# 1e-10 collapses the step to 1e-8 s, and 1e-8 still makes Exudyn reduce steps often (default run 1934 steps
# and 9112 iterations instead of 1500; a 30 deg flank 11886 steps). At 1e-6 no step is reduced and the
# results are the same to 1e-7 (T/F, end clamp force, ledger; an ad-hoc script over default, orthotropic head,
# 30 deg flank, 4x2 points, pitch 3 mm, orthotropic flank, net, 2026-11-26): the default solves 3-4x faster
NEWTON_TOLERANCE = 1e-6
PART_SIZE = (0.03, 0.03, 0.01)
# the scene's z axis points from the head to the tip: the snapshot turns it over, head up
SNAPSHOT_VIEW = (SNAPSHOT_ROTATION @ RotationMatrixX(math.pi)).tolist()          # drawn clamped part [m]; its mass is the scene's part_mass


class ToolState:
    """A nutrunner's state, latched between the steps: ``off_time`` [s] (None while it runs), the
    torque it holds from then on [N m], and the drive's last evaluation (time, bolt angle, torque): at a
    step's start, that of the last accepted step's converged state."""

    def __init__(self):
        self.off_time, self.hold, self.last = None, 0.0, (0.0, 0.0, 0.0)


def DriveTorque(p, angle, t, tool=None):
    """Torque of the drive [N m] and its derivative by the bolt's angle: the torsional spring to the
    driver, or after a nutrunner's shut-off (``tool``, a ToolState) the torque it holds. angle, t:
    numbers, or arrays (the trajectory's column)."""
    spring = p.drive_stiffness * (driver_angle(p, t) - angle)
    if tool is None or tool.off_time is None:
        if tool is not None and np.ndim(t) == 0:
            tool.last = (t, angle, spring)
        return spring, -p.drive_stiffness
    if np.ndim(t) == 0:
        return (tool.hold, 0.0) if t > tool.off_time else (spring, -p.drive_stiffness)
    return np.where(np.asarray(t) > tool.off_time, tool.hold, spring), None


def AddShutoff(mbs, p, nBolt, tool):
    """The nutrunner's shut-off, checked before every step on the drive's last evaluation (the last
    accepted step's converged state) once the bolt has turned rundown_angle (the head bears: the torque
    of the run-down's start is no tightening): the drive torque at or above shutoff_torque (when > 0),
    or the bolt's angle at or above shutoff_angle (when > 0), latches ``tool`` off with that torque."""

    def PreStep(mbs, t):
        t_last, yaw, torque = tool.last
        if tool.off_time is None and yaw >= math.radians(p.rundown_angle) and (
                (p.shutoff_torque > 0.0 and torque >= p.shutoff_torque)
                or (p.shutoff_angle > 0.0 and yaw >= math.radians(p.shutoff_angle))):
            tool.off_time, tool.hold = t_last, torque
        return True
    mbs.SetPreStepUserFunction(PreStep)


def StaticPenetration(p):
    """Axial offset [m] of the bolt into the nut's flank under axial_load at the start (net: none), so
    that every thread point starts in contact."""
    if p.thread == "net" or not p.axial_load:
        return 0.0
    k = threads.thread_axial_stiffness(p.thread_stiffness, p.d2, p.pitch, math.radians(p.flank_angle), 0.0)
    return p.axial_load / k


def BoltGraphics(p):
    """The bolt: a shank of diameter d2 and a head (a disc of 2 head_radius) above the bearing ring."""
    L, zh = p.bolt_length, head_z(p)
    return [graphics.Cylinder(pAxis=[0.0, 0.0, zh], vAxis=[0.0, 0.0, L], radius=0.5 * p.d2, nTiles=24,
                              color=graphics.color.steelblue, alternatingColor=graphics.color.lightgrey),
            graphics.Cylinder(pAxis=[0.0, 0.0, zh - 0.6 * p.d2], vAxis=[0.0, 0.0, 0.6 * p.d2],
                              radius=1.3 * p.head_radius, nTiles=6, color=graphics.color.steelblue)]


def BuildFastening(p: FasteningParams, jacobian="analytic", implementation="auto", newton="modified",
                   show=True, nodeType="RotVecLG", newtonTolerance=NEWTON_TOLERANCE):
    """Build the fastening scene; returns dict with SC, mbs, simulationSettings, solverType, params,
    oBolt, oPart, contacts (dict thread, head of CreateAnisotropicContact), sensors, oDrive. Options as
    BuildBlock; show: draw the nets and points (the nut's flank a quarter of d2 about the pitch radius,
    the bearing face's net 1.6 head radii wide); newtonTolerance: see NEWTON_TOLERANCE."""
    check_instance("p", p, FasteningParams)
    if nodeType not in NODE_TYPES:
        raise ValueError(f"nodeType must be one of {tuple(NODE_TYPES)}; got {nodeType!r}")
    SC = SceneView(exu.SystemContainer(), SNAPSHOT_VIEW)
    mbs = SC.AddSystem()
    m, J = bolt_inertia(p)
    # started in the thread's screw motion at the driver's speed: no start-up kick on the stiff contacts
    oBolt = mbs.CreateRigidBody(inertia=RigidBodyInertia(mass=m, inertiaTensor=J),
                                referencePosition=[0.0, 0.0, -StaticPenetration(p)],
                                initialVelocity=[0.0, 0.0, lead(p) * p.rotation_speed],
                                initialAngularVelocity=[0.0, 0.0, p.rotation_speed],
                                nodeType=NODE_TYPES[nodeType], gravity=[0.0, 0.0, 0.0],
                                graphicsDataList=BoltGraphics(p))
    nBolt = mbs.GetObject(oBolt)["nodeNumber"]
    if p.axial_load:
        load = mbs.CreateForce(itemNumber=oBolt, loadVector=[0.0, 0.0, -p.axial_load])
        mbs.SetLoadParameter(load, "Vshow", False)       # CreateForce(show=False) draws it all the same
    tool = ToolState() if p.tool == "nutrunner" else None
    oDrive = AddYawDrive(mbs, nBolt, nodeType, lambda angle, t: DriveTorque(p, angle, t, tool))
    if tool is not None:
        AddShutoff(mbs, p, nBolt, tool)

    z0 = part_top_z(p)
    Lx, Ly, Lz = PART_SIZE
    oPart = mbs.CreateRigidBody(inertia=InertiaCuboid(density=p.part_mass / (Lx * Ly * Lz), sideLengths=PART_SIZE),
                                referencePosition=[0.0, 0.0, z0], nodeType=exu.NodeType.RotationEulerParameters,
                                gravity=[0.0, 0.0, 0.0],
                                graphicsDataList=[graphics.Brick(centerPoint=[0.0, 0.0, 0.5 * Lz], size=PART_SIZE,
                                                                 color=graphics.color.lightgrey)])
    oGround = mbs.CreateGround()
    mbs.CreateCartesianSpringDamper(itemNumbers=[oGround, oPart], localPosition0=[0.0, 0.0, z0],
                                    stiffness=[0.0, 0.0, p.joint_stiffness], damping=[0.0, 0.0, joint_damping(p)],
                                    show=False)
    mbs.CreateGenericJoint(itemNumbers=[oGround, oPart], position=[0.0, 0.0, z0], constrainedAxes=[1, 1, 0, 1, 1, 1],
                           show=False)
    contacts = dict(
        thread=mbs.CreateAnisotropicContact(name="threadContact", bodyNumber=oBolt, localPoints=thread_points(p),
                                            contactLaw=thread_contact_law(p), jacobian=jacobian,
                                            implementation=implementation, show=show, storeHistory=True,
                                            graphicsSize=0.25 * p.d2),
        head=mbs.CreateAnisotropicContact(name="headContact", bodyNumber=oBolt, localPoints=head_points(p),
                                          contactLaw=head_contact_law(p), masterBodyNumber=oPart, jacobian=jacobian,
                                          implementation=implementation, show=show, storeHistory=True,
                                          graphicsSize=1.6 * p.head_radius))
    sensors = {}
    nPart = mbs.GetObject(oPart)["nodeNumber"]
    for prefix, node in (("s", nBolt), ("sPart", nPart)):
        for name, ovt in (("Position", "Position"), ("Velocity", "Velocity"), ("Rotation", "RotationMatrix"),
                          ("Omega", "AngularVelocity")):
            if prefix == "sPart" and name in ("Rotation", "Omega"):
                continue
            sensors[prefix + name] = mbs.AddSensor(SensorNode(nodeNumber=node, storeInternal=True,
                                                              outputVariableType=getattr(exu.OutputVariableType, ovt)))
    mbs.Assemble()
    ss, st = SimulationSettingsFor(p, rhoInf=p.spectral_radius, newtonTolerance=newtonTolerance, newton=newton)
    return dict(SC=SC, mbs=mbs, simulationSettings=ss, solverType=st, params=p, oBolt=oBolt, oPart=oPart,
                contacts=contacts, sensors=sensors, oDrive=oDrive, tool=tool)


def FasteningTrajectory(model):
    """(traj, extras) from the stored sensors of a solved BuildFastening model; extras has the bolt's
    RigidMotion, the part's z and vz, and per contact the slave points and velocities in its master's
    frame and the histories (for the energy ledger)."""
    mbs, S, p = model["mbs"], model["sensors"], model["params"]
    get = lambda s: mbs.GetSensorStoredData(s)[:, 1:]     # noqa: E731
    t = mbs.GetSensorStoredData(S["sPosition"])[:, 0]
    pos, vel, w = get(S["sPosition"]), get(S["sVelocity"]), get(S["sOmega"])
    A = get(S["sRotation"]).reshape(-1, 3, 3)
    part_u = get(S["sPartPosition"]) - np.array([0.0, 0.0, part_top_z(p)])
    part_v = get(S["sPartVelocity"])
    H = {k: mbs.GetSensorStoredData(c["sHistory"])[:, 1:].reshape(len(t), -1, 9) for k, c in model["contacts"].items()}
    angle = Unwrap(np.arctan2(A[:, 1, 0], A[:, 0, 0]))
    Tt, Th, F = contact_torques(model["contacts"]["thread"]["law"], model["contacts"]["head"]["law"], p, pos, vel, w,
                                A, part_u, part_v, H["thread"], H["head"])
    axis = A[:, :, 2]
    tool = model["tool"]
    on = np.ones(len(t)) if tool is None or tool.off_time is None else (t <= tool.off_time).astype(float)
    traj = dict(t=t, angle=angle, z=pos[:, 2], torque=DriveTorque(p, angle, t, tool)[0], thread_torque=Tt,
                head_torque=Th,
                clamp_force=F, part_displacement=part_u[:, 2], tilt=np.arccos(np.clip(axis[:, 2], -1.0, 1.0)),
                lateral=np.hypot(pos[:, 0], pos[:, 1]), vx=vel[:, 0], vy=vel[:, 1], vz=vel[:, 2], omega_x=w[:, 0],
                omega_y=w[:, 1], omega_z=w[:, 2], omega_axial=np.einsum("ni,ni->n", w, axis),
                part_velocity=part_v[:, 2], drive_on=on,
                dissipated_energy=sum(h[:, :, H_DISSIPATED].sum(axis=1) for h in H.values()))
    bolt = energy.RigidMotion(pos, A, vel, w)
    Xt, Vt = energy.point_motion(bolt, thread_points(p))
    Xh, Vh = energy.point_motion(bolt, head_points(p))
    Xh = Xh - (part_u + np.array([0.0, 0.0, part_top_z(p)]))[:, None, :]
    Vh = Vh - part_v[:, None, :]
    extras = dict(bolt=bolt, part_z=part_u[:, 2], part_vz=part_v[:, 2],
                  laws=[model["contacts"][k]["law"] for k in ("thread", "head")],
                  X=[Xt, Xh], V=[Vt, Vh], H=[H["thread"], H["head"]])
    return traj, extras


def ReadFastening(model, complete):
    """What ``ModelScript.run`` reads from a solved BuildFastening model: the trajectory, the summary's
    inputs (none) and the ledger's (``FasteningTrajectory``'s extras)."""
    traj, extras = FasteningTrajectory(model)
    return traj, {}, extras


MODEL = ModelScript(SCENE, BuildFastening, ReadFastening, contacts=lambda model: list(model["contacts"].values()),
                    info=lambda model: dict(thread_law=repr(model["contacts"]["thread"]["law"])),
                    snapshotOptions=dict(modelRotation=SNAPSHOT_VIEW))

RunFastening = MODEL.run
"""Build (``BuildFastening(p, **options)``) and solve the fastening scene: ``ModelScript.run``, which
returns an ``exu_aniso.engines.result.Result`` with ``scenes.fastening.COLUMNS``, the summary
(``scenes.fastening.fastening_summary``) and the energy ledger."""


if __name__ == "__main__":
    MODEL.show()
