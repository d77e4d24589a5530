"""A free nut on a fixed vertical bolt as an Exudyn model (the nut scene).

The scene (thread, nut, gravity, closed forms) is ``exu_aniso.scenes.nut`` (read its module
docstring). Here:

* ``model="reduced"``: the nut on a screw joint (``runner.AddScrewJointBody``: a NodeGenericODE2 with
  the angle about and the height along the bolt's axis, mass diag(nut_inertia, nut_mass)), its weight
  a ``LoadCoordinate`` on the height (a user function while it rises), one representative contact
  point carrying the totals (every point of the layout has the same state on the joint);
* ``model="full"``: ``mbs.CreateRigidBody`` (6 DOF, Euler parameters), its weight a force at the centre
  (a user function while it rises), every point of the layout;
* the bolt's flank: one ``mbs.CreateAnisotropicContact`` with the scene's Helicoid fixed to ground.

``RunNut`` returns the same ``Result`` as ``exu_aniso.scenes.nut.simulate_nut``. Run ``python -m
exu_aniso.models.nut`` for a plot of the default scene (a greased M10 nut running down).
"""
from __future__ import annotations

import exudyn as exu
import numpy as np
from exudyn import graphics
from exudyn.itemInterface import LoadCoordinate, MarkerNodeCoordinate, SensorNode
from exudyn.rigidBodyUtilities import RigidBodyInertia

import exu_aniso  # noqa: F401  (binds mbs.CreateAnisotropicContact)
from exu_aniso.engines.exudyn_adapter.runner import (NODE_TYPES, AddScrewJointBody, HistoryOutputs, ModelScript,
                                                     SceneView, SensorMotion, SimulationSettingsFor, Unwrap)
from exu_aniso.scenes.nut import (SCENE, NutParams, finish_trajectory, nut_contact_law, nut_inertia,
                                  nut_points, reduced_motion, centre_height, weight_force)
from exu_aniso.util.validation import check_instance


NUT_COLOR = [0.27, 0.51, 0.71, 0.35]     # steel blue, see-through: the thread's flank and points show inside


def NutGraphics(p):
    """The nut in its own frame: a hexagonal tube about the axis (across the corners 1.6 d2, the bore
    d2 / 2) of nut_height, see-through."""
    return [graphics.Cylinder(pAxis=[0.0, 0.0, -0.5 * p.nut_height], vAxis=[0.0, 0.0, p.nut_height],
                              radius=0.8 * p.d2, innerRadius=0.5 * p.d2, nTiles=6, color=NUT_COLOR)]


def BoltGraphics(p, z_low, z_high):
    """The fixed bolt's core from z_low to z_high [m], inside the flank (radius d2 / 2 - 0.6 pitch), so
    that the flank drawn by the contact shows round it."""
    return graphics.Cylinder(pAxis=[0.0, 0.0, z_low], vAxis=[0.0, 0.0, z_high - z_low],
                             radius=0.5 * p.d2 - 0.6 * p.pitch, nTiles=24, color=graphics.color.grey)


def BuildNut(p: NutParams, jacobian="analytic", implementation="auto", newton="modified", newtonTolerance=1e-10,
             rhoInf=0.8, show=True):
    """Build the nut scene; returns dict with SC, mbs, simulationSettings, solverType, params, oNut, nNut,
    contact (dict of CreateAnisotropicContact) and sensors. jacobian, implementation, newton,
    newtonTolerance, rhoInf: as BuildBlock; show: draw the flank's net and the contact points."""
    check_instance("p", p, NutParams)
    SC = SceneView(exu.SystemContainer())
    mbs = SC.AddSystem()
    z0 = centre_height(p)
    mbs.CreateGround(graphicsDataList=[BoltGraphics(p, z0 - 1.5 * p.nut_height, z0 + p.nut_height)])
    mass, J = nut_inertia(p)
    sensors = {}
    reduced = p.model == "reduced"
    if reduced:
        oNut, nNut = AddScrewJointBody(mbs, mass, J[2, 2], NutGraphics(p), initialCoordinates=(0.0, z0))
        mZ = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=nNut, coordinate=1))
        mbs.AddLoad(LoadCoordinate(markerNumber=mZ, load=-mass * p.gravity,
                                   loadUserFunction=lambda mbs, t, load: -float(weight_force(p, t))))
        for name, ovt in (("sCoordinates", "Coordinates"), ("sVelocities", "Coordinates_t")):
            sensors[name] = mbs.AddSensor(SensorNode(nodeNumber=nNut, storeInternal=True,
                                                     outputVariableType=getattr(exu.OutputVariableType, ovt)))
    else:
        oNut = mbs.CreateRigidBody(inertia=RigidBodyInertia(mass=mass, inertiaTensor=J),
                                   referencePosition=[0.0, 0.0, z0], nodeType=NODE_TYPES["EP"],
                                   graphicsDataList=NutGraphics(p))
        mbs.CreateForce(itemNumber=oNut, loadVector=[0.0, 0.0, -mass * p.gravity],
                        loadVectorUserFunction=lambda mbs, t, load: [0.0, 0.0, -float(weight_force(p, t))])
        nNut = mbs.GetObject(oNut)["nodeNumber"]
        for name, ovt in (("sPosition", "Position"), ("sVelocity", "Velocity"),
                          ("sRotation", "RotationMatrix"), ("sOmega", "AngularVelocity")):
            sensors[name] = mbs.AddSensor(SensorNode(nodeNumber=nNut, storeInternal=True,
                                                     outputVariableType=getattr(exu.OutputVariableType, ovt)))
    contact = mbs.CreateAnisotropicContact(name="threadContact", bodyNumber=oNut,
                                           localPoints=nut_points(p, representative=reduced),
                                           contactLaw=nut_contact_law(p, representative=reduced), jacobian=jacobian,
                                           initializeHistory=True, implementation=implementation, show=show,
                                           storeHistory=True, graphicsSize=p.d2)
    mbs.Assemble()
    ss, st = SimulationSettingsFor(p, rhoInf=rhoInf, newtonTolerance=newtonTolerance, newton=newton)
    return dict(SC=SC, mbs=mbs, simulationSettings=ss, solverType=st, params=p, oNut=oNut, nNut=nNut,
                contact=contact, sensors=sensors)


def NutTrajectory(model):
    """Trajectory dict (the reference's keys) from the stored sensors of a solved BuildNut model, and the
    contact's history H."""
    mbs, p, S = model["mbs"], model["params"], model["sensors"]
    diss, slip, H = HistoryOutputs(mbs, model["contact"])
    if p.model == "reduced":
        Q = mbs.GetSensorStoredData(S["sCoordinates"])
        V = mbs.GetSensorStoredData(S["sVelocities"])
        traj = dict(t=Q[:, 0], angle=Q[:, 1], z=Q[:, 2], omega=V[:, 1], vz=V[:, 2])
    else:
        P = mbs.GetSensorStoredData(S["sPosition"])
        V = mbs.GetSensorStoredData(S["sVelocity"])
        A = mbs.GetSensorStoredData(S["sRotation"])[:, 1:].reshape(-1, 3, 3)
        W = mbs.GetSensorStoredData(S["sOmega"])
        traj = dict(t=P[:, 0], angle=Unwrap(np.arctan2(A[:, 1, 0], A[:, 0, 0])), z=P[:, 3], omega=W[:, 3],
                    vz=V[:, 3], x=P[:, 1], y=P[:, 2], tilt=np.arccos(np.clip(A[:, 2, 2], -1.0, 1.0)))
    traj.update(dissipated_energy=diss, slip_distance=slip)
    return finish_trajectory(traj, H), H


def ReadNut(model, complete):
    """What ``ModelScript.run`` reads from a solved BuildNut model: the trajectory, the summary's inputs
    (none) and the ledger's (the nut's motion, the evaluated points, the contact law and its history)."""
    traj, H = NutTrajectory(model)
    if not complete:
        return traj, {}, None
    motion = SensorMotion(model) if model["params"].model == "full" else reduced_motion(traj)
    return traj, {}, dict(motion=motion, points=np.asarray(model["contact"]["points"]),
                          law=model["contact"]["law"], H=H)


MODEL = ModelScript(SCENE, BuildNut, ReadNut, info=lambda model: dict(model=model["params"].model))

RunNut = MODEL.run
"""Build (``BuildNut(p, **options)``) and solve the nut scene: ``ModelScript.run``, which returns an
``exu_aniso.engines.result.Result`` with ``scenes.nut.COLUMNS``, the summary (``scenes.nut.nut_summary``)
and the energy ledger."""


if __name__ == "__main__":
    MODEL.show()
