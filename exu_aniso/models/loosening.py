"""The loosening scene as an Exudyn model (its case ``bearing``).

The scene (the ring, the plate, the drag, the closed forms) is ``exu_aniso.scenes.loosening`` (read its
module docstring). Here the bearing ring is a ``NodeRigidBody2D`` with an ``ObjectRigidBody2D`` (x, y,
angle in the plate's plane), its points at the held height that carries the preload; the drag along x
and the hold along y are C++ spring drives (``runner.AddSpringDrive``: a spring and a dashpot to a
driver at slip_speed, and to the origin); the torque a ``LoadCoordinate`` on the angle; the plate one
``mbs.CreateAnisotropicContact`` with the scene's plane.

``RunLoosening`` returns the same ``Result`` as ``exu_aniso.scenes.loosening.simulate_loosening``. Run
``python -m exu_aniso.models.loosening`` for a plot of the default scene.
"""
from __future__ import annotations

import exudyn as exu
from exudyn import graphics
from exudyn.itemInterface import (LoadCoordinate, MarkerNodeCoordinate, NodeRigidBody2D, ObjectRigidBody2D,
                                  SensorNode, VObjectRigidBody2D)

import exu_aniso  # noqa: F401  (binds mbs.CreateAnisotropicContact)
from exu_aniso.engines.exudyn_adapter.runner import (AddSpringDrive, HistoryOutputs, ModelScript, SceneView,
                                                     SimulationSettingsFor)
from exu_aniso.engines import energy
from exu_aniso.scenes.loosening import (SCENE, LooseningParams, bearing_contact_law, drag_force, finish_trajectory,
                                        held_gap, ring_points, torque_at, transverse_force)
from exu_aniso.util.validation import check_instance


def NutGraphics(p):
    """The nut over its bearing ring: a hexagonal prism across the corners 2.4 bearing_radius."""
    r = 1.2 * p.bearing_radius
    return [graphics.Cylinder(pAxis=[0.0, 0.0, 0.0], vAxis=[0.0, 0.0, r], radius=r, nTiles=6,
                              color=graphics.color.steelblue, alternatingColor=graphics.color.lightgrey)]


def BuildLoosening(p: LooseningParams, jacobian="analytic", implementation="auto", newton="modified",
                   newtonTolerance=1e-10, rhoInf=0.8, show=True):
    """Build the loosening scene; returns dict with SC, mbs, simulationSettings, solverType, params, oNut,
    nNut, contact (dict of CreateAnisotropicContact) and sensors. Options as BuildBlock; show: draw the
    plate's net and the points."""
    check_instance("p", p, LooseningParams)
    SC = SceneView(exu.SystemContainer())
    mbs = SC.AddSystem()
    nNut = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=[0.0, 0.0, 0.0]))
    oNut = mbs.AddObject(ObjectRigidBody2D(nodeNumber=nNut, mass=p.nut_mass, inertia=p.nut_inertia,
                                           visualization=VObjectRigidBody2D(graphicsData=NutGraphics(p))))
    if p.drag == "speed":
        AddSpringDrive(mbs, nNut, [1.0, 0.0, 0.0], p.drag_stiffness, p.slip_speed, damping=p.drag_damping)
    else:
        mX = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=nNut, coordinate=0))
        mbs.AddLoad(LoadCoordinate(markerNumber=mX, load=0.0,
                                   loadUserFunction=lambda mbs, t, load: float(transverse_force(p, t))))
    AddSpringDrive(mbs, nNut, [0.0, 1.0, 0.0], p.drag_stiffness, 0.0, damping=p.drag_damping)
    mbs.AddLoad(LoadCoordinate(markerNumber=mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=nNut, coordinate=2)),
                               load=p.torque, loadUserFunction=lambda mbs, t, load: float(torque_at(p, t))))
    points = ring_points(p)
    points[:, 2] = held_gap(p)                  # the plane's points at the height that carries the preload
    contact = mbs.CreateAnisotropicContact(name="bearingContact", bodyNumber=oNut, localPoints=points,
                                           contactLaw=bearing_contact_law(p), jacobian=jacobian,
                                           initializeHistory=True, implementation=implementation, show=show,
                                           storeHistory=True, graphicsSize=3.0 * p.bearing_radius)
    sensors = {name: mbs.AddSensor(SensorNode(nodeNumber=nNut, storeInternal=True,
                                              outputVariableType=getattr(exu.OutputVariableType, ovt)))
               for name, ovt in (("sCoordinates", "Coordinates"), ("sVelocities", "Coordinates_t"))}
    mbs.Assemble()
    ss, st = SimulationSettingsFor(p, rhoInf=rhoInf, newtonTolerance=newtonTolerance, newton=newton)
    return dict(SC=SC, mbs=mbs, simulationSettings=ss, solverType=st, params=p, oNut=oNut, nNut=nNut,
                contact=contact, sensors=sensors)


def ReadLoosening(model, complete):
    """What ``ModelScript.run`` reads from a solved BuildLoosening model: the trajectory, the summary's
    inputs (none) and the ledger's (the ring's motion, the contact law and its history)."""
    mbs, p, S = model["mbs"], model["params"], model["sensors"]
    Q = mbs.GetSensorStoredData(S["sCoordinates"])
    V = mbs.GetSensorStoredData(S["sVelocities"])
    diss, slip, H = HistoryOutputs(mbs, model["contact"])
    t = Q[:, 0]
    traj = dict(t=t, x=Q[:, 1], y=Q[:, 2], angle=Q[:, 3], vx=V[:, 1], vy=V[:, 2], omega=V[:, 3],
                drag_force=drag_force(p, Q[:, 1], Q[:, 2], V[:, 1], V[:, 2], t)[0],
                dissipated_energy=diss, slip_distance=slip)
    finish_trajectory(traj, H)
    if not complete:
        return traj, {}, None
    motion = energy.motion_about_z(traj["x"], traj["y"], held_gap(p), traj["angle"], traj["vx"], traj["vy"], 0.0,
                                   traj["omega"])
    return traj, {}, dict(motion=motion, law=model["contact"]["law"], H=H)


MODEL = ModelScript(SCENE, BuildLoosening, ReadLoosening)

RunLoosening = MODEL.run
"""Build (``BuildLoosening(p, **options)``) and solve the loosening scene: ``ModelScript.run``, which
returns an ``exu_aniso.engines.result.Result`` with ``scenes.loosening.COLUMNS``, the summary
(``scenes.loosening.loosening_summary``) and the energy ledger."""


if __name__ == "__main__":
    MODEL.show()
