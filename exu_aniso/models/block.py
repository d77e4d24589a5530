"""Block on a (polar-)orthotropic plane as an Exudyn model (paper 000, Fig. 1).

A rigid cube on the plane z = 0, pressed by ``normal_load`` and driven in the xy-plane, with the
anisotropic contact of ``exu_aniso`` added by one ``mbs.CreateAnisotropicContact`` call. The models,
drives, initial state and trajectory keys are those of ``exu_aniso.engines.reference`` (read its module
docstring); ``RunBlock`` returns the same ``Result`` so the two engines compare field by field:

* ``model="planar"``: ``NodeRigidBody2D`` + ``ObjectRigidBody2D`` (x, y, theta; inertia m size^2/6);
  the contact points sit at the body-local height gap = -normal_load / eps_n, which holds the
  normal load exactly as the reference does;
* ``model="full"``: ``mbs.CreateRigidBody`` (6 DOF; Euler parameters by default, exact for the tiny
  first rotations of a block at rest; ``nodeType="RotVecLG"`` for the Lie-group rotation vector,
  which the explicit solvers need), normal_load as a constant
  downward force at the centre of mass, no gravity, started at the static penetration;
* drives: "force" -> constant load at the centre of mass; "displacement" -> a spring and a dashpot
  along the drive direction d only, F = (k (s - d.(r - r0)) + c (s' - d.v)) d, from Exudyn C++ items
  (``AddSpringDrive``: a driver at constant velocity, a slider held at d.(r - r0), a coordinate
  spring; with drive_ramp > 0 the spring's force is a Python function of the driver's travel s(t);
  under an explicit solver, which cannot solve constraints, a Python ``ObjectGenericODE2`` with
  its exact Jacobian).

Run ``python -m exu_aniso.models.block`` (or this file) for a plot of the default scene.
"""
from __future__ import annotations

import math

import exudyn as exu
import exudyn.solver
import numpy as np
from exudyn import graphics
from exudyn.itemInterface import (LoadCoordinate, MarkerNodeCoordinate, NodeRigidBody2D, ObjectRigidBody2D,
                                  SensorNode, VObjectRigidBody2D)
from exudyn.utilities import InertiaCuboid

import exu_aniso  # noqa: F401  (binds mbs.CreateAnisotropicContact)
from exu_aniso.scenes.block import SCENE, BlockParams, block_contact_law, block_points, planar_motion
from exu_aniso.engines.timing import driver_travel
from exu_aniso.engines.exudyn_adapter.runner import (SceneView, IMPLICIT_SOLVERS, NODE_TYPES, AddSpringDrive,
                                                     HistoryOutputs, ModelScript, SensorMotion,
                                                     SimulationSettingsFor, SolveTimed, Unwrap)
from exu_aniso.util.validation import check_instance


# ----------------------------------------------------------------------------------------------
# pictures: body graphics, raytraced snapshot, solution viewer


def BlockGraphics(p, center=(0.0, 0.0, 0.0)):
    """Body graphics of the block: a cube of edge p.size centred at the body-local ``center``."""
    a = p.size
    return [graphics.Brick(centerPoint=list(center), size=[a, a, a], color=graphics.color.steelblue,
                           addEdges=True, edgeColor=graphics.color.black)]


# ----------------------------------------------------------------------------------------------
# the block scene

def BuildBlock(p: BlockParams, jacobian="analytic", nodeType="EP", solverType=None, rhoInf=0.8,
               newtonTolerance=1e-10, implementation="auto", contactBuilder=None, newton="modified"):
    """Build the block scene; returns dict with SC, mbs, simulationSettings, solverType, params,
    nBlock, oBlock, contact (dict of CreateAnisotropicContact), sensors (dict) and oDrive (or None).

    jacobian: "analytic" | "numerical" (contact Jacobian); nodeType: "EP" (default: exact for small
    rotations) | "RotVecLG" (needed by explicit solvers; Exudyn 1.13.6 loses rotation increments
    below ~1.5e-8 rad in its composition, see tests/test_exudyn_scenes.py) for the full model;
    implementation: contact kernel "auto" | "compiled" | "numpy" (CreateAnisotropicContact);
    solverType: an exu.DynamicSolverType overriding p.solver; rhoInf: spectral radius of
    generalized-alpha; newtonTolerance: Newton relative and absolute tolerance; newton: "modified"
    | "full" (SimulationSettingsFor);
    contactBuilder: None (the anisotropic contact) or a function (mbs, bodyNumber, localPoints) ->
    dict that puts another contact model at the same points (studies/baseline.py: C++ springs);
    everything else of the scene (body, loads, drive, sensors, settings) stays the same."""
    if nodeType not in NODE_TYPES:
        raise ValueError(f"nodeType must be one of {tuple(NODE_TYPES)}; got {nodeType!r}")
    check_instance("p", p, BlockParams)
    SC = SceneView(exu.SystemContainer())
    mbs = SC.AddSystem()

    m, a = p.mass, p.size                       # mass [kg], edge length [m]
    gap = -p.normal_load / p.eps_n              # static penetration carrying normal_load [m]
    ang = math.radians(p.drive_angle)
    d = np.array([math.cos(ang), math.sin(ang)])  # drive direction in the plane
    sensors = {}
    if p.model == "planar":
        nBlock = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=[p.x0, p.y0, 0.0]))
        # drawn as the cube standing on the plane: the node lies in z = 0, the bottom face at the held gap
        look = VObjectRigidBody2D(graphicsData=BlockGraphics(p, [0.0, 0.0, 0.5 * a + gap]))
        oBlock = mbs.AddObject(ObjectRigidBody2D(nodeNumber=nBlock, mass=m, inertia=m * a * a / 6.0,
                                                 visualization=look))
        nq, pos = 3, slice(0, 2)
        localPoints = block_points(p)
        localPoints[:, 2] = gap                 # planar: local z = held height over the plane
        if p.drive == "force":
            for i in range(2):
                mC = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=nBlock, coordinate=i))
                mbs.AddLoad(LoadCoordinate(markerNumber=mC, load=p.force * d[i]))
        sensors["sCoordinates"] = mbs.AddSensor(SensorNode(nodeNumber=nBlock, storeInternal=True,
                                                           outputVariableType=exu.OutputVariableType.Coordinates))
        sensors["sVelocities"] = mbs.AddSensor(SensorNode(nodeNumber=nBlock, storeInternal=True,
                                                          outputVariableType=exu.OutputVariableType.Coordinates_t))
    else:
        oBlock = mbs.CreateRigidBody(inertia=InertiaCuboid(density=m / a ** 3, sideLengths=[a, a, a]),
                                     referencePosition=[p.x0, p.y0, 0.5 * a + gap],
                                     nodeType=NODE_TYPES[nodeType], graphicsDataList=BlockGraphics(p))
        nBlock = mbs.GetObject(oBlock)["nodeNumber"]
        nq, pos = (6 if nodeType == "RotVecLG" else 7), slice(0, 3)
        localPoints = block_points(p)
        load = np.array([0.0, 0.0, -p.normal_load])
        if p.drive == "force":
            load[:2] += p.force * d
        mbs.CreateForce(itemNumber=oBlock, loadVector=load.tolist())
        for name, ovt in (("sPosition", "Position"), ("sVelocity", "Velocity"),
                          ("sRotation", "RotationMatrix"), ("sOmega", "AngularVelocity")):
            sensors[name] = mbs.AddSensor(SensorNode(nodeNumber=nBlock, storeInternal=True,
                                                     outputVariableType=getattr(exu.OutputVariableType, ovt)))

    oDrive = None
    if p.drive == "displacement":               # spring along d only, driver point moving at drive_speed
        along = np.zeros(nq)
        along[:2] = d
        oDrive = AddSpringDrive(mbs, nBlock, along, p.drive_stiffness, p.drive_speed, damping=p.drive_damping,
                                ramp=p.drive_ramp,
                                python=solverType is not None and solverType not in IMPLICIT_SOLVERS)

    if contactBuilder is None:
        contact = mbs.CreateAnisotropicContact(name="blockContact", bodyNumber=oBlock, localPoints=localPoints,
                                               contactLaw=block_contact_law(p), jacobian=jacobian,
                                               initializeHistory=True, implementation=implementation,
                                               storeHistory=True,   # the ledger and the summary read it
                                               graphicsSize=drawn_plane_size(p))
    else:
        contact = contactBuilder(mbs, oBlock, localPoints)
    mbs.Assemble()
    ss, st = SimulationSettingsFor(p, rhoInf=rhoInf, newtonTolerance=newtonTolerance, solverType=solverType,
                                   newton=newton)
    return dict(SC=SC, mbs=mbs, simulationSettings=ss, solverType=st, params=p, nBlock=nBlock, oBlock=oBlock,
                contact=contact, sensors=sensors, oDrive=oDrive, driveDirection=d, nodeType=nodeType,
                position=pos)


def drawn_plane_size(p):
    """The radius [m] of the plane drawn under the block (polar disk, square half-width): its start's
    distance from the origin, plus the way the block can go in t_end (the driver's travel; under a
    constant force, the free acceleration's F t^2 / 2m, at most 100 m), plus its size."""
    way = (abs(p.drive_speed) * p.t_end if p.drive == "displacement"
           else min(0.5 * p.force / p.mass * p.t_end ** 2, 100.0))
    return math.hypot(p.x0, p.y0) + way + p.size


def BlockTrajectory(model, history=None):
    """Trajectory dict (reference keys) from the stored sensors of a solved BuildBlock model;
    history: the contact's HistoryOutputs when the caller has them already."""
    mbs, p, S, d = model["mbs"], model["params"], model["sensors"], model["driveDirection"]
    diss, slip, _ = HistoryOutputs(mbs, model["contact"]) if history is None else history
    gap = -p.normal_load / p.eps_n
    if p.model == "planar":
        Q = mbs.GetSensorStoredData(S["sCoordinates"])
        V = mbs.GetSensorStoredData(S["sVelocities"])
        traj = dict(t=Q[:, 0], x=Q[:, 1] + p.x0, y=Q[:, 2] + p.y0, theta=Q[:, 3], vx=V[:, 1], vy=V[:, 2],
                    omega=V[:, 3], z=np.full(len(Q), 0.5 * p.size + gap))
    else:
        P = mbs.GetSensorStoredData(S["sPosition"])
        V = mbs.GetSensorStoredData(S["sVelocity"])
        A = mbs.GetSensorStoredData(S["sRotation"])[:, 1:].reshape(-1, 3, 3)
        W = mbs.GetSensorStoredData(S["sOmega"])
        traj = dict(t=P[:, 0], x=P[:, 1], y=P[:, 2], theta=Unwrap(np.arctan2(A[:, 1, 0], A[:, 0, 0])),
                    vx=V[:, 1], vy=V[:, 2], omega=W[:, 3], z=P[:, 3], vz=V[:, 3],
                    tilt=np.arccos(np.clip(A[:, 2, 2], -1.0, 1.0)))
    if p.drive == "force":
        traj["drive_force"] = np.full(len(traj["t"]), p.force)
    else:
        disp = d[0] * (traj["x"] - p.x0) + d[1] * (traj["y"] - p.y0)
        s, s_t = driver_travel(traj["t"], p.drive_speed, 0.0, p.drive_ramp)
        traj["drive_force"] = (p.drive_stiffness * (s - disp)
                               + p.drive_damping * (s_t - d[0] * traj["vx"] - d[1] * traj["vy"]))
    traj["dissipated_energy"] = diss
    traj["slip_distance"] = slip
    return traj


def BlockMotion(model, traj):
    """energy.RigidMotion of the block: the full model's from its sensors, the planar one's from the
    trajectory."""
    return SensorMotion(model) if model["params"].model == "full" else planar_motion(traj)


def ReadBlock(model, complete):
    """What ``ModelScript.run`` reads from a solved BuildBlock model: the trajectory, the summary's
    inputs (none) and, for a completed run, the ledger's (the block's motion, the contact law and
    its history)."""
    history = HistoryOutputs(model["mbs"], model["contact"])
    traj = BlockTrajectory(model, history)
    if not complete:
        return traj, {}, None
    return traj, {}, dict(motion=BlockMotion(model, traj), law=model["contact"]["law"], H=history[2])


def BlockInfo(model):
    """The block's entries of a run's info: the model and its node type."""
    p = model["params"]
    return dict(model=p.model, nodeType=model["nodeType"] if p.model == "full" else "RigidBody2D")


MODEL = ModelScript(SCENE, BuildBlock, ReadBlock, info=BlockInfo)

RunBlock = MODEL.run
"""Build (``BuildBlock(p, **options)``) and solve the block scene: ``ModelScript.run``, which returns
an ``exu_aniso.engines.result.Result`` with the reference's trajectory keys, the summary
(``scenes.block.block_summary``) and the energy ledger."""


if __name__ == "__main__":
    p = BlockParams()                           # defaults: polar orthotropy, radial map, driven along +y
    model = BuildBlock(p)
    mbs = model["mbs"]
    SolveTimed(mbs, model["simulationSettings"], model["solverType"])
    mbs.PlotSensor(model["sensors"]["sCoordinates"], components=[1], componentsX=[0],
                   labels=["block path (displacement from x0, y0)"], closeAll=True)
    mbs.PlotSensor(model["contact"]["sDissipation"], components=0, labels=["dissipated energy [J]"])
