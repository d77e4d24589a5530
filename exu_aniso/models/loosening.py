"""The loosening scene as an Exudyn model.

The scene (the ring, the plate, the drag, the closed forms) is ``exu_aniso.scenes.loosening``, its joint
``exu_aniso.scenes.bolted_joint`` (read their module docstrings). Here:

* case bearing: the bearing ring is a ``NodeRigidBody2D`` with an ``ObjectRigidBody2D`` (x, y, angle
  in the plate's plane), its points at the held height that carries the preload; the drag along x and
  the hold along y are C++ spring drives (``runner.AddSpringDrive``: a spring and a dashpot to a driver
  at slip_speed, and to the origin); the torque a ``LoadCoordinate`` on the angle; the plate one
  ``mbs.CreateAnisotropicContact`` with the scene's plane;
* case joint, model rings: the same planar nut with two contacts, its bearing ring and its thread
  ring, each at its held height; the shaker a spring drive to a driver whose travel is a Python
  function of time; the lead's torque a ``LoadCoordinate`` on the angle;
* case joint, model full: the nut ``mbs.CreateRigidBody`` (6 DOF, Euler parameters) on the bolt's
  helicoid (fixed to ground) and on the plate, a rigid body held by a ``GenericJoint`` to move along
  the axis only, where a C++ spring and dashpot (the joint's) and a ``LoadCoordinate`` (the force that
  settles at the preload, rising: ``bolted_joint.spring_load_at``) act; the shaker as above, on the
  nut's x, and a C++ spring drive holding its y; a pre-step function ends the run at the end of the
  cycle in which the joint came loose (``bolted_joint.LOOSE_SHARE``); a flexible shank: the bolt's end
  a rigid body that moves across only (the thread contact's master), on a C++ Cartesian spring
  (``guided_beam``) or carrying the guided end of the shank's beam elements, one ``ObjectGenericODE2``
  of constant mass, damping and stiffness matrices over their inner coordinates and the bolt's end's
  node (``fe_beam``), and the shaker on the plate.

``RunLoosening`` returns the same ``Result`` as ``exu_aniso.scenes.loosening.simulate_loosening``. Run
``python -m exu_aniso.models.loosening`` for a plot of the default scene.
"""
from __future__ import annotations

import exudyn as exu
from exudyn import graphics
from exudyn.itemInterface import (LoadCoordinate, MarkerNodeCoordinate, NodeGenericODE2,
                                  NodePointGround, NodeRigidBody2D, ObjectConnectorCoordinateSpringDamper,
                                  ObjectGenericODE2, ObjectRigidBody2D, SensorNode,
                                  VNodePointGround, VObjectConnectorCoordinateSpringDamper, VObjectGenericODE2,
                                  VObjectRigidBody2D)
from exudyn.rigidBodyUtilities import RigidBodyInertia
import numpy as np

import exu_aniso  # noqa: F401  (binds mbs.CreateAnisotropicContact)
from exu_aniso.engines.exudyn_adapter.runner import (NODE_TYPES, AddSpringDrive, HistoryOutputs, ModelScript,
                                                     SceneView, SensorMotion, SimulationSettingsFor, Unwrap)
from exu_aniso.engines import energy
from exu_aniso.scenes import bolted_joint as bj
from exu_aniso.scenes.loosening import (SCENE, LooseningParams, drag_force, finish_trajectory, held_gap, torque_at,
                                        transverse_force)
from exu_aniso.util.validation import check_instance


def NutGraphics(p):
    """The nut over its bearing ring: a hexagonal prism across the corners 2.4 bearing_radius."""
    r = 1.2 * p.bearing_radius
    return [graphics.Cylinder(pAxis=[0.0, 0.0, 0.0], vAxis=[0.0, 0.0, r], radius=r, nTiles=6,
                              color=graphics.color.steelblue, alternatingColor=graphics.color.lightgrey)]


NEWTON_TOLERANCE = dict(bearing=1e-10, joint=1e-8)
"""The build's Newton tolerance by case. Where the joint's two rings reach their friction limits
together, Newton (full or modified) stalls above 1e-10 and the step falls to its floor: with 1e-10 the
rings model fails within two cycles at dt 1e-4 and at 2e-5 alike, and runs at 1e-8."""


SEE_THROUGH = [0.27, 0.51, 0.71, 0.35]     # steel blue: the thread's flank and points show inside


def JointNutGraphics(p):
    """The full joint's nut in its own frame: a see-through hexagonal tube (across the corners 2.4
    bearing_radius, the bore d2 / 2) of nut_height from its bearing face up."""
    zb = bj.bearing_points(p)[0, 2]
    return [graphics.Cylinder(pAxis=[0.0, 0.0, zb], vAxis=[0.0, 0.0, p.nut_height], radius=1.2 * p.bearing_radius,
                              innerRadius=0.5 * p.d2, nTiles=6, color=SEE_THROUGH)]


def BuildLoosening(p: LooseningParams, jacobian="analytic", implementation="auto", newton="modified",
                   newtonTolerance=None, rhoInf=None, show=True):
    """Build the loosening scene; returns dict with SC, mbs, simulationSettings, solverType, params, oNut,
    nNut, contacts (dict name -> dict of CreateAnisotropicContact: bearing, and case joint thread) and
    sensors (and case joint model full nPlate). Options as BuildBlock, but newtonTolerance None: the
    case's, NEWTON_TOLERANCE, and rhoInf None: p.spectral_radius; show: draw the nets and the points."""
    check_instance("p", p, LooseningParams)
    SC = SceneView(exu.SystemContainer())
    mbs = SC.AddSystem()
    options = dict(jacobian=jacobian, initializeHistory=True, implementation=implementation, show=show,
                   storeHistory=True)
    model = _BUILD[(p.case, p.model if p.case == "joint" else None)](mbs, p, options)
    mbs.Assemble()
    ss, st = LooseningSettings(p, newtonTolerance, rhoInf, newton)
    return dict(SC=SC, mbs=mbs, simulationSettings=ss, solverType=st, params=p, **model)


def LooseningSettings(p, newtonTolerance=None, rhoInf=None, newton="modified"):
    """The scene's SimulationSettings and DynamicSolverType for p (``SimulationSettingsFor``):
    newtonTolerance None, the case's (NEWTON_TOLERANCE); rhoInf None, p.spectral_radius."""
    tolerance = NEWTON_TOLERANCE[p.case] if newtonTolerance is None else newtonTolerance
    return SimulationSettingsFor(p, rhoInf=p.spectral_radius if rhoInf is None else rhoInf,
                                 newtonTolerance=tolerance, newton=newton)


def _NodeSensors(mbs, nNut, names):
    return {name: mbs.AddSensor(SensorNode(nodeNumber=nNut, storeInternal=True,
                                           outputVariableType=getattr(exu.OutputVariableType, ovt)))
            for name, ovt in names}


def _PlanarNut(mbs, p):
    nNut = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=[0.0, 0.0, 0.0]))
    oNut = mbs.AddObject(ObjectRigidBody2D(nodeNumber=nNut, mass=p.nut_mass, inertia=p.nut_inertia,
                                           visualization=VObjectRigidBody2D(graphicsData=NutGraphics(p))))
    AddSpringDrive(mbs, nNut, [0.0, 1.0, 0.0], p.drag_stiffness, 0.0, damping=p.drag_damping)
    sensors = _NodeSensors(mbs, nNut, (("sCoordinates", "Coordinates"), ("sVelocities", "Coordinates_t")))
    return oNut, nNut, sensors


def _AngleLoad(mbs, nNut, value, load):
    """A LoadCoordinate on the planar nut's angle: value [N m] at the start of its rise, load(t) its user
    function."""
    mbs.AddLoad(LoadCoordinate(markerNumber=mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=nNut, coordinate=2)),
                               load=value, loadUserFunction=lambda mbs, t, _: float(load(t))))


def _BuildBearing(mbs, p, options):
    oNut, nNut, sensors = _PlanarNut(mbs, p)
    if p.drag == "speed":
        AddSpringDrive(mbs, nNut, [1.0, 0.0, 0.0], p.drag_stiffness, p.slip_speed, damping=p.drag_damping)
    else:
        mX = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=nNut, coordinate=0))
        mbs.AddLoad(LoadCoordinate(markerNumber=mX, load=0.0,
                                   loadUserFunction=lambda mbs, t, load: float(transverse_force(p, t))))
    _AngleLoad(mbs, nNut, p.torque, lambda t: torque_at(p, t))
    points = bj.bearing_ring(p)
    points[:, 2] = held_gap(p)                  # the plane's points at the height that carries the preload
    contact = mbs.CreateAnisotropicContact(name="bearingContact", bodyNumber=oNut, localPoints=points,
                                           contactLaw=bj.bearing_law(p), graphicsSize=3.0 * p.bearing_radius,
                                           **options)
    return dict(oNut=oNut, nNut=nNut, contacts=dict(bearing=contact), sensors=sensors)


def _BuildRings(mbs, p, options):
    oNut, nNut, sensors = _PlanarNut(mbs, p)
    AddSpringDrive(mbs, nNut, [1.0, 0.0, 0.0], p.drag_stiffness, 0.0, damping=p.drag_damping,
                   travel=lambda t: bj.shake_travel(p, t))
    _AngleLoad(mbs, nNut, 0.0, lambda t: bj.lead_torque(p, t))
    gaps, contacts = bj.held_gaps(p), {}
    for name, points, law in (("bearing", bj.bearing_points(p), bj.bearing_law(p)),
                              ("thread", bj.thread_points(p), bj.thread_law(p))):
        points[:, 2] = gaps[name]               # each ring at the height that carries its load
        contacts[name] = mbs.CreateAnisotropicContact(name=name + "Contact", bodyNumber=oNut, localPoints=points,
                                                      contactLaw=law, graphicsSize=3.0 * p.bearing_radius, **options)
    return dict(oNut=oNut, nNut=nNut, contacts=contacts, sensors=sensors)


def _BuildFullJoint(mbs, p, options):
    zc = bj.centre_height(p)
    core = 0.5 * p.d2 - 0.6 * p.pitch          # the bolt's core inside the flank, so the flank drawn shows round it
    ground = mbs.CreateGround(graphicsDataList=[graphics.Cylinder(
        pAxis=[0.0, 0.0, bj.plate_height(p) - 1.5 * p.bearing_radius], vAxis=[0.0, 0.0, 2.0 * zc + 2.0 * p.nut_height],
        radius=core, nTiles=24, color=graphics.color.grey)])
    inertia = RigidBodyInertia(mass=p.nut_mass, inertiaTensor=np.diag(bj.nut_inertia_tensor(p)))
    oNut = mbs.CreateRigidBody(inertia=inertia,
                               referencePosition=[0.0, 0.0, zc], nodeType=NODE_TYPES["EP"],
                               graphicsDataList=JointNutGraphics(p))
    nNut = mbs.GetObject(oNut)["nodeNumber"]
    zp = bj.plate_height(p)
    side = 3.0 * p.bearing_radius
    plate_inertia = RigidBodyInertia(mass=p.plate_mass, inertiaTensor=np.eye(3) * p.plate_mass * side ** 2 / 6.0)
    oPlate = mbs.CreateRigidBody(inertia=plate_inertia,
                                 referencePosition=[0.0, 0.0, zp], nodeType=NODE_TYPES["EP"],
                                 graphicsDataList=[graphics.Brick(centerPoint=[0.0, 0.0, -0.25 * side],
                                                                  size=[2 * side, 2 * side, 0.5 * side],
                                                                  color=graphics.color.lightgrey)])
    nPlate = mbs.GetObject(oPlate)["nodeNumber"]
    beam = p.shank in bj.SHANKS                 # the plate shaken along x, the bolt's end on its shank
    mbs.CreateGenericJoint(itemNumbers=[ground, oPlate], position=[0.0, 0.0, zp],
                           constrainedAxes=[0 if beam else 1, 1, 0, 1, 1, 1], show=False)
    mZ = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=nPlate, coordinate=2))
    mGround = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=mbs.AddNode(NodePointGround(
        visualization=VNodePointGround(show=False))), coordinate=0))
    mbs.AddObject(ObjectConnectorCoordinateSpringDamper(
        markerNumbers=[mGround, mZ], stiffness=p.joint_stiffness, damping=p.joint_damping,
        visualization=VObjectConnectorCoordinateSpringDamper(show=False)))
    factor = bj.spring_load_factor(p)           # once: the load's user function runs every Newton iteration
    mbs.AddLoad(LoadCoordinate(markerNumber=mZ, load=0.0,
                               loadUserFunction=lambda mbs, t, _: factor * float(bj.preload_at(p, t))))
    e = np.eye(7)
    AddSpringDrive(mbs, nPlate if beam else nNut, e[0], p.drag_stiffness, 0.0, damping=p.drag_damping,
                   travel=lambda t: bj.shake_travel(p, t))
    bolt = {}
    if beam:                                    # the bolt's end: a body moving across only, on its shank
        oBolt = mbs.CreateRigidBody(inertia=RigidBodyInertia(mass=p.bolt_mass, inertiaTensor=np.eye(3) * 1e-6),
                                    referencePosition=[0.0, 0.0, 0.0], nodeType=NODE_TYPES["EP"])
        mbs.CreateGenericJoint(itemNumbers=[ground, oBolt], position=[0.0, 0.0, 0.0],
                               constrainedAxes=[0, 0, 1, 1, 1, 1],
                               show=False)
        shank = _SHANKS[p.shank](mbs, p, ground, oBolt)
        bolt = dict(masterBodyNumber=oBolt)
    else:
        AddSpringDrive(mbs, nNut, e[1], p.drag_stiffness, 0.0, damping=p.drag_damping)
    contacts = dict(
        bearing=mbs.CreateAnisotropicContact(name="bearingContact", bodyNumber=oNut, localPoints=bj.bearing_points(p),
                                             contactLaw=bj.bearing_law(p), masterBodyNumber=oPlate,
                                             graphicsSize=side, **options),
        thread=mbs.CreateAnisotropicContact(name="threadContact", bodyNumber=oNut, localPoints=bj.thread_points(p),
                                            contactLaw=bj.thread_law(p), graphicsSize=p.d2, **bolt, **options))
    coordinates = exu.OutputVariableType.Coordinates
    check = dict(next=p.load_time + 1.0 / p.shake_frequency)

    def go_on(mbs, t):
        """The pre-step function: at each cycle's end, end the run if the joint is loose
        (bolted_joint.LOOSE_SHARE; reading the plate allocates, so not in every step)."""
        if t < check["next"]:
            return True
        check["next"] += 1.0 / p.shake_frequency
        plate_z = mbs.GetNodeOutput(nPlate, coordinates)[2]
        return not bj.loose(p, t, factor * float(bj.preload_at(p, t)) - p.joint_stiffness * plate_z)
    mbs.SetPreStepUserFunction(go_on)
    sensors = _NodeSensors(mbs, nNut, (("sPosition", "Position"), ("sVelocity", "Velocity"),
                                       ("sRotation", "RotationMatrix"), ("sOmega", "AngularVelocity")))
    sensors.update(_NodeSensors(mbs, nPlate, (("sPlate", "Coordinates"), ("sPlateVelocity", "Coordinates_t"))))
    if beam:
        sensors.update(_NodeSensors(mbs, mbs.GetObject(bolt["masterBodyNumber"])["nodeNumber"],
                                    (("sBolt", "Coordinates"), ("sBoltVelocity", "Coordinates_t"))))
        if shank["node"] is not None:
            sensors.update(_NodeSensors(mbs, shank["node"], (("sShank", "Coordinates"),
                                                             ("sShankVelocity", "Coordinates_t"))))
    return dict(oNut=oNut, nNut=nNut, oPlate=oPlate, nPlate=nPlate, contacts=contacts, sensors=sensors,
                shank=shank if beam else None)


def _LumpedShank(mbs, p, ground, oBolt):
    """Shank guided_beam: a C++ Cartesian spring and dashpot from ground to the bolt's end (the K and D
    of ``bolted_joint.shank_matrices``, whose coordinates are the end's x and y)."""
    _, D, K, tip = bj.shank_matrices(p)
    mbs.CreateCartesianSpringDamper(itemNumbers=[ground, oBolt], stiffness=[K[0, 0], K[1, 1], 0.0],
                                    damping=[D[0, 0], D[1, 1], 0.0], show=False)
    return dict(node=None, inner=[], tip=tip)


def _BeamShank(mbs, p, ground, oBolt):
    """Shank fe_beam: the shank's matrices (``bolted_joint.shank_matrices``) as one ObjectGenericODE2 over
    a NodeGenericODE2 of its inner coordinates (none for one element) and the bolt's end's node, whose x
    and y are the guided end's: M, D, K mapped onto those coordinates, so that no constraint ties them
    (beside Euler-parameter nodes Exudyn allocates two matrices per Newton iteration for a coordinate
    constraint)."""
    M, D, K, tip = bj.shank_matrices(p)
    inner = [i for i in range(M.shape[0]) if i not in tip]
    nBolt = mbs.GetObject(oBolt)["nodeNumber"]
    nodes, nShank = [], None
    if inner:
        zero = [0.0] * len(inner)
        nShank = mbs.AddNode(NodeGenericODE2(numberOfODE2Coordinates=len(inner), referenceCoordinates=zero,
                                             initialCoordinates=zero, initialCoordinates_t=zero))
        nodes.append(nShank)
    bolt = len(mbs.GetNodeParameter(nBolt, "referenceCoordinates"))
    P = np.zeros((M.shape[0], len(inner) + bolt))        # the shank's coordinates from the object's
    P[inner, np.arange(len(inner))] = 1.0
    P[tip[0], len(inner)], P[tip[1], len(inner) + 1] = 1.0, 1.0    # the bolt's end's x and y
    mbs.AddObject(ObjectGenericODE2(nodeNumbers=nodes + [nBolt], massMatrix=P.T @ M @ P, dampingMatrix=P.T @ D @ P,
                                    stiffnessMatrix=P.T @ K @ P, visualization=VObjectGenericODE2(show=False)))
    return dict(node=nShank, inner=inner, tip=tip)


_SHANKS = {"guided_beam": _LumpedShank, "fe_beam": _BeamShank}
"""The flexible shanks' builds by name (``bolted_joint.SHANKS``): f(mbs, p, ground, oBolt) -> dict node (a
NodeGenericODE2 of the shank's inner coordinates, or None), inner (their indices among the shank's
coordinates) and tip (the indices of the guided end's x and y, the bolt's end's)."""


_BUILD = {("bearing", None): _BuildBearing, ("joint", "rings"): _BuildRings, ("joint", "full"): _BuildFullJoint}


def ReadLoosening(model, complete):
    """What ``ModelScript.run`` reads from a solved BuildLoosening model: the trajectory, the summary's
    inputs (none) and the ledger's (the case's: ``scenes.loosening.loosening_energy``)."""
    mbs, p, S = model["mbs"], model["params"], model["sensors"]
    histories = {name: HistoryOutputs(mbs, c) for name, c in model["contacts"].items()}
    diss, slip, H = histories["bearing"]
    full = p.case == "joint" and p.model == "full"
    if full:
        P, V, W = (mbs.GetSensorStoredData(S[k]) for k in ("sPosition", "sVelocity", "sOmega"))
        A = mbs.GetSensorStoredData(S["sRotation"])[:, 1:].reshape(-1, 3, 3)
        t = P[:, 0]
        traj = dict(t=t, x=P[:, 1], y=P[:, 2], angle=Unwrap(np.arctan2(A[:, 1, 0], A[:, 0, 0])), vx=V[:, 1],
                    vy=V[:, 2], omega=W[:, 3], tilt=np.arccos(np.clip(A[:, 2, 2], -1.0, 1.0)))
    else:
        Q = mbs.GetSensorStoredData(S["sCoordinates"])
        V = mbs.GetSensorStoredData(S["sVelocities"])
        t = Q[:, 0]
        traj = dict(t=t, x=Q[:, 1], y=Q[:, 2], angle=Q[:, 3], vx=V[:, 1], vy=V[:, 2], omega=V[:, 3])
    if p.case == "bearing":
        traj.update(drag_force=drag_force(p, traj["x"], traj["y"], traj["vx"], traj["vy"], t)[0],
                    dissipated_energy=diss, slip_distance=slip)
        finish_trajectory(traj, H)
        if not complete:
            return traj, {}, None
        return traj, {}, dict(motion=_PlanarMotion(traj, held_gap(p)), law=model["contacts"]["bearing"]["law"], H=H)
    zero = np.zeros_like(t)
    plate = bolt = shank = None
    shaken = {k: traj[k] for k in ("x", "y", "vx", "vy")}
    if full:
        C, C_t = mbs.GetSensorStoredData(S["sPlate"]), mbs.GetSensorStoredData(S["sPlateVelocity"])
        plate = dict(x=C[:, 1], vx=C_t[:, 1], z=C[:, 3], vz=C_t[:, 3])
        if "sBolt" in S:
            B, B_t = mbs.GetSensorStoredData(S["sBolt"]), mbs.GetSensorStoredData(S["sBoltVelocity"])
            bolt = dict(x=B[:, 1], y=B[:, 2], vx=B_t[:, 1], vy=B_t[:, 2])
            shank = _ShankCoordinates(model["shank"], bolt, lambda k: mbs.GetSensorStoredData(S[k])[:, 1:])
            shaken = dict(x=plate["x"], y=zero, vx=plate["vx"], vy=zero)
            traj.update(plate_x=plate["x"], bolt_x=bolt["x"], bolt_y=bolt["y"])
    traj.update(drag_force=bj.shake_force(p, shaken["x"], shaken["vx"], t),
                dissipated_energy=diss + histories["thread"][0], slip_distance=slip)
    bj.finish_joint_trajectory(traj, H, histories["thread"][2])
    traj.setdefault("tilt", zero)
    if not complete:
        return traj, {}, None
    laws = {name: c["law"] for name, c in model["contacts"].items()}
    if full:
        nut = SensorMotion(model)
        on_plate = _Relative(nut, plate["x"], zero, plate["z"] + bj.plate_height(p), plate["vx"], zero, plate["vz"])
        on_bolt = nut if bolt is None else _Relative(nut, bolt["x"], bolt["y"], zero, bolt["vx"], bolt["vy"], zero)
        contacts = [(laws["bearing"], on_plate, bj.bearing_points(p), H),
                    (laws["thread"], on_bolt, bj.thread_points(p), histories["thread"][2])]
        return traj, {}, dict(contacts=contacts, shaken=shaken, plate=plate, nut_motion=nut, bolt=bolt, shank=shank)
    gaps = bj.held_gaps(p)
    contacts = [(laws[name], _PlanarMotion(traj, gaps[name]), points, histories[name][2])
                for name, points in (("bearing", bj.bearing_points(p)), ("thread", bj.thread_points(p)))]
    return traj, {}, dict(contacts=contacts, shaken=shaken)


def _ShankCoordinates(shank, bolt, stored):
    """The shank's coordinates q and rates q_t (n, m) of a solved model: its inner ones from their node's
    sensors (stored(name) -> (n, len(inner))), its guided end's x and y the bolt's end's (bolt: dict x, y,
    vx, vy)."""
    m = len(shank["inner"]) + 2
    q, q_t = np.zeros((len(bolt["x"]), m)), np.zeros((len(bolt["x"]), m))
    if shank["inner"]:
        q[:, shank["inner"]], q_t[:, shank["inner"]] = stored("sShank"), stored("sShankVelocity")
    for i, (x, v) in zip(shank["tip"], (("x", "vx"), ("y", "vy"))):
        q[:, i], q_t[:, i] = bolt[x], bolt[v]
    return dict(q=q, q_t=q_t)


def _Relative(motion, x, y, z, vx, vy, vz):
    """energy.RigidMotion of a body relative to a master that translates by (x, y, z) at (vx, vy, vz)."""
    return energy.RigidMotion(motion.position - np.column_stack([x, y, z]), motion.rotation,
                              motion.velocity - np.column_stack([vx, vy, vz]), motion.omega)


def _PlanarMotion(traj, height):
    """energy.RigidMotion of the planar nut at the points' held height [m]."""
    return energy.motion_about_z(traj["x"], traj["y"], height, traj["angle"], traj["vx"], traj["vy"], 0.0,
                                 traj["omega"])


MODEL = ModelScript(SCENE, BuildLoosening, ReadLoosening, contacts=lambda model: list(model["contacts"].values()),
                    info=lambda model: dict(case=model["params"].case))

RunLoosening = MODEL.run
"""Build (``BuildLoosening(p, **options)``) and solve the loosening scene: ``ModelScript.run``, which
returns an ``exu_aniso.engines.result.Result`` with ``scenes.loosening.COLUMNS``, the summary
(``scenes.loosening.loosening_summary``) and the energy ledger."""


if __name__ == "__main__":
    MODEL.show()
