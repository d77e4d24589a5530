"""Parts on a vibrating track (a linear vibratory feeder) as an Exudyn model (the feeder
scene: read ``exu_aniso.scenes.feeder``'s module docstring).

The track is a plate (``mbs.CreateRigidBody``, Euler parameters) on a C++ Cartesian spring-damper
to ground, its rotations locked by a C++ generic joint: a resonant spring-mass system, as real
vibratory feeders are. Its spring is tuned so that the integrator's discrete frequency is the
scene's: the trapezoidal rule turns a spring-mass of frequency w into one of (2 / h) atan(w h / 2),
so the spring gets w = (2 / h) tan(pi f h) (generalized-alpha: w = 2 pi f), and the plate starts at
u = 0 with velocity w A along the throw direction (the trapezoidal rule keeps v^2 + w^2 u^2, so the
amplitude is A). No Python drives it. Each part is a rigid cube under gravity with one
``mbs.CreateAnisotropicContact`` on the plate as its moving master (4 corners). ``RunFeeder``
returns the same ``Result`` as ``exu_aniso.scenes.feeder.simulate_feeder``.

Run ``python -m exu_aniso.models.feeder`` for a plot of the default scene.
"""
from __future__ import annotations

import math

import exudyn as exu
import numpy as np
from exudyn import graphics
from exudyn.itemInterface import SensorNode
from exudyn.utilities import InertiaCuboid

import exu_aniso  # noqa: F401  (binds mbs.CreateAnisotropicContact)
from exu_aniso.engines import energy
from exu_aniso.engines.exudyn_adapter.runner import ModelScript, SimulationSettingsFor, SceneView
from exu_aniso.scenes.feeder import (SCENE, FeederParams, feeder_contact_law, finish_trajectory, part_inertia,
                                    part_points, part_positions, throw_direction)
from exu_aniso.engines.timing import time_step
from exu_aniso.util.validation import check_instance

PLATE_SIZE = (0.4, 0.4, 0.02)          # drawn plate [m]; its mass is the scene's plate_mass


def plate_frequency(p):
    """Angular frequency [rad/s] of the plate's spring: the integrator's discrete frequency, at the step it
    takes (scenes.time_step), is 2 pi f."""
    if p.solver == "trapezoidal":
        h = time_step(p)
        return 2.0 / h * math.tan(math.pi * p.frequency * h)
    return 2.0 * math.pi * p.frequency


def BuildFeeder(p: FeederParams, jacobian="analytic", implementation="auto", newton="modified", show=True):
    """Build the feeder scene; returns dict with SC, mbs, simulationSettings, solverType, params,
    oPlate, parts (object numbers), contacts (dicts of CreateAnisotropicContact) and sensors
    (dict of lists per part: sPosition, sVelocity, sAcceleration, sRotation, sOmega; plate:
    sPlatePosition, sPlateVelocity). Options as BuildBlock; show: draw the nets and points."""
    check_instance("p", p, FeederParams)
    law = feeder_contact_law(p)
    SC = SceneView(exu.SystemContainer())
    mbs = SC.AddSystem()
    w = plate_frequency(p)
    Lx, Ly, Lz = PLATE_SIZE
    oPlate = mbs.CreateRigidBody(inertia=InertiaCuboid(density=p.plate_mass / (Lx * Ly * Lz), sideLengths=PLATE_SIZE),
                                 referencePosition=[0.0, 0.0, 0.0], initialVelocity=(w * p.amplitude
                                                                                     * throw_direction(p)).tolist(),
                                 nodeType=exu.NodeType.RotationEulerParameters, gravity=[0.0, 0.0, 0.0],
                                 graphicsDataList=[graphics.Brick(centerPoint=[0.0, 0.0, -0.5 * Lz], size=PLATE_SIZE,
                                                                  color=graphics.color.lightgrey)])
    oGround = mbs.CreateGround()
    k = p.plate_mass * w * w
    mbs.CreateCartesianSpringDamper(itemNumbers=[oGround, oPlate], stiffness=[k, k, k], damping=[0.0] * 3, show=False)
    mbs.CreateGenericJoint(itemNumbers=[oGround, oPlate], position=[0.0, 0.0, 0.0], constrainedAxes=[0, 0, 0, 1, 1, 1],
                           show=False)
    mass, J = part_inertia(p)
    a = p.part_size
    parts, contacts = [], []
    names = (("sPosition", "Position"), ("sVelocity", "Velocity"), ("sAcceleration", "Acceleration"),
             ("sRotation", "RotationMatrix"), ("sOmega", "AngularVelocity"))
    sensors = {name: [] for name, _ in names}
    for i, x0 in enumerate(part_positions(p)):
        o = mbs.CreateRigidBody(inertia=InertiaCuboid(density=mass / a ** 3, sideLengths=[a, a, a]),
                                referencePosition=x0.tolist(), gravity=[0.0, 0.0, -p.gravity],
                                nodeType=exu.NodeType.RotationEulerParameters,
                                graphicsDataList=[graphics.Brick(size=[a, a, a], color=graphics.color.steelblue,
                                                                 addEdges=True)])
        parts.append(o)
        contacts.append(mbs.CreateAnisotropicContact(name=f"part{i}Contact", bodyNumber=o, localPoints=part_points(p),
                                                     contactLaw=law, masterBodyNumber=oPlate, jacobian=jacobian,
                                                     implementation=implementation, show=show and i == 0,
                                                     storeHistory=True))   # the ledger reads it
        node = mbs.GetObject(o)["nodeNumber"]
        for name, ovt in names:
            sensors[name].append(mbs.AddSensor(SensorNode(nodeNumber=node, storeInternal=True,
                                                          outputVariableType=getattr(exu.OutputVariableType, ovt))))
    nPlate = mbs.GetObject(oPlate)["nodeNumber"]
    for name, ovt in (("sPlatePosition", "Position"), ("sPlateVelocity", "Velocity")):
        sensors[name] = mbs.AddSensor(SensorNode(nodeNumber=nPlate, storeInternal=True,
                                                 outputVariableType=getattr(exu.OutputVariableType, ovt)))
    mbs.Assemble()
    ss, st = SimulationSettingsFor(p, newton=newton)
    return dict(SC=SC, mbs=mbs, simulationSettings=ss, solverType=st, params=p, oPlate=oPlate, parts=parts,
                contacts=contacts, sensors=sensors)


def FeederTrajectory(model):
    """(traj, P, yaw, motions, forces, H, plate) from the stored sensors of a solved BuildFeeder model:
    P (n, parts, 3) centres, yaw (n, parts) unwrapped, motions (energy.RigidMotion per part),
    forces (n, parts, 3) resultant contact force m (a - g) on each part, H (n, parts, 4, 9) and
    plate = (displacement, velocity) (n, 3) each."""
    mbs, S, p = model["mbs"], model["sensors"], model["params"]
    get = lambda s: mbs.GetSensorStoredData(s)      # noqa: E731
    t = get(S["sPlatePosition"])[:, 0]
    P = np.stack([get(s)[:, 1:] for s in S["sPosition"]], axis=1)
    V = np.stack([get(s)[:, 1:] for s in S["sVelocity"]], axis=1)
    Acc = np.stack([get(s)[:, 1:] for s in S["sAcceleration"]], axis=1)
    R = np.stack([get(s)[:, 1:].reshape(-1, 3, 3) for s in S["sRotation"]], axis=1)
    W = np.stack([get(s)[:, 1:] for s in S["sOmega"]], axis=1)
    yaw = np.unwrap(np.arctan2(R[:, :, 1, 0], R[:, :, 0, 0]), axis=0)
    H = np.stack([get(c["sHistory"])[:, 1:].reshape(len(t), -1, 9) for c in model["contacts"]], axis=1)
    plate = (get(S["sPlatePosition"])[:, 1:], get(S["sPlateVelocity"])[:, 1:])
    mass = part_inertia(p)[0]
    forces = mass * (Acc - np.array([0.0, 0.0, -p.gravity]))
    motions = [energy.RigidMotion(P[:, i], R[:, i], V[:, i], W[:, i]) for i in range(P.shape[1])]
    traj = dict(t=t, plate_u=plate[0] @ throw_direction(p))
    finish_trajectory(traj, P, V, yaw, H[:, :, :, 5].sum(axis=(1, 2)))
    return traj, P, yaw, motions, forces, H, plate


def ReadFeeder(model, complete):
    """What ``ModelScript.run`` reads from a solved BuildFeeder model: the trajectory, the summary's
    inputs (the parts' positions and yaws; a completed run's nominal steps, beyond which Exudyn's
    accepted steps are extra, as the reference engine counts them) and, for a completed run, the
    ledger's (``scenes.feeder.feeder_energy``)."""
    traj, P, yaw, motions, forces, H, plate = FeederTrajectory(model)
    if not complete:
        return traj, dict(P=P, yaw=yaw, extra_steps=None), None
    nominal = int(model["simulationSettings"].timeIntegration.numberOfSteps)
    return (traj, dict(P=P, yaw=yaw, nominal_steps=nominal),
            dict(motions=motions, forces=forces, law=model["contacts"][0]["law"], H=H, plate=plate))


MODEL = ModelScript(SCENE, BuildFeeder, ReadFeeder, contacts=lambda model: model["contacts"])

RunFeeder = MODEL.run
"""Build (``BuildFeeder(p, **options)``) and solve the feeder scene: ``ModelScript.run``, which returns
an ``exu_aniso.engines.result.Result`` with ``scenes.feeder.COLUMNS``, the summary
(``scenes.feeder.feeder_summary``) and the energy ledger of the parts."""


if __name__ == "__main__":
    MODEL.show()
