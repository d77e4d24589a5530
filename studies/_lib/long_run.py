"""A long run in the benchmark: the loosening scene's joint shaken for 1000 cycles (its default rings
model: a planar nut on two rings of 24 points, dt 1e-4 s, 800050 steps), against a yardstick with no
Python in it and the floor of the same calls with empty callbacks.

* ours: ``BuildLoosening(LooseningParams(case="joint", t_end=...))`` at the scene's settings, its
  history sensors on (the scene's run keeps them), solved as built;
* the yardstick (``BuildShakenNut``): the same planar nut (``ObjectRigidBody2D``, the nut's mass and
  inertia) on as many C++ springs (``ObjectConnectorCartesianSpringDamper`` to ground at the rings'
  points, the rings' sticking stiffness shared among them), shaken along x by the same C++ spring and
  dashpot to a driver and held along y by another, the lead's torque a constant ``LoadCoordinate``,
  the nut's coordinates and velocities in sensors. The driver swings D sin(2 pi f t) as an undamped
  oscillator of C++ items (a ``NodeGenericODE2`` of ``DRIVER_MASS`` on a coordinate spring of
  ``DRIVER_MASS`` (2 pi f)^2, started at the speed 2 pi f D): ours drives the same spring by a Python
  function of time, the one piece of ours that the yardstick cannot copy without Python. It is timed
  at Exudyn's default settings and at the scene's;
* the floor: the yardstick at the scene's settings with the two contact sets' items whose user
  functions do nothing (``baseline.empty_contact``, history sensors on): ours - floor is what the
  contact law adds, floor - yardstick what Exudyn's calls into Python cost.

Timed as the speed targets are (``target_timing``): each model built afresh in every repeat, the
repeats interleaved (ours, the yardstick at both settings, the floor, then again), the process CPU
time and the wall time of the solve alone (building and reading excluded); medians with min and max,
and the ratios to ours repeat by repeat."""
from __future__ import annotations

import gc
import math

import exudyn as exu
import numpy as np
from exudyn.itemInterface import (LoadCoordinate, MarkerBodyPosition, MarkerNodeCoordinate, NodeGenericODE2,
                                  NodePointGround, NodeRigidBody2D, ObjectConnectorCartesianSpringDamper,
                                  ObjectConnectorCoordinateSpringDamper, ObjectGenericODE2, ObjectGround,
                                  ObjectRigidBody2D, SensorNode)

from exu_aniso.models.loosening import BuildLoosening, LooseningSettings
from exu_aniso.scenes import bolted_joint as bj
from exu_aniso.scenes.loosening import LooseningParams

from .baseline import empty_contact, exudyn_defaults
from .target_timing import timed_solve

CYCLES, CYCLES_QUICK, REPEATS = 1000, 4, 3
DRIVER_MASS = 1e6          # kg: the yardstick's driver, heavy enough that the shaker's spring barely detunes it
LONG_COLUMNS = ["model [-]", "settings [-]", "cycles [-]", "steps [-]", "cpu [s]", "cpu_min [s]", "cpu_max [s]",
                "wall [s]", "wall_min [s]", "wall_max [s]", "ours_over_this [-]", "ratio_min [-]", "ratio_max [-]",
                "repeats [-]"]


def joint_params(cycles):
    """The loosening scene's default joint shaken for ``cycles`` cycles after its load time."""
    p = LooseningParams(case="joint")
    return LooseningParams(case="joint", t_end=p.load_time + cycles / p.shake_frequency)


def BuildShakenNut(p, settings, floor=False):
    """The yardstick (module doc) of the joint p at ``settings`` ("exudyn": Exudyn's defaults; "ours":
    the scene's); floor: with the contact sets' empty items. Returns dict(mbs, simulationSettings,
    solverType, SC)."""
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    nNut = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=[0.0, 0.0, 0.0]))
    oNut = mbs.AddObject(ObjectRigidBody2D(nodeNumber=nNut, mass=p.nut_mass, inertia=p.nut_inertia))
    ground = mbs.AddObject(ObjectGround())
    rings = [bj.bearing_points(p), bj.thread_points(p)]
    k = p.sticking_stiffness / p.points
    for points in rings:
        for x, y, _ in points:
            mbs.AddObject(ObjectConnectorCartesianSpringDamper(
                markerNumbers=[mbs.AddMarker(MarkerBodyPosition(bodyNumber=ground, localPosition=[x, y, 0.0])),
                               mbs.AddMarker(MarkerBodyPosition(bodyNumber=oNut, localPosition=[x, y, 0.0]))],
                stiffness=[k, k, 0.0]))
    omega = 2.0 * math.pi * p.shake_frequency
    nDriver = mbs.AddNode(NodeGenericODE2(numberOfODE2Coordinates=1, referenceCoordinates=[0.0],
                                          initialCoordinates=[0.0],
                                          initialCoordinates_t=[omega * p.shake_displacement]))
    mbs.AddObject(ObjectGenericODE2(nodeNumbers=[nDriver], massMatrix=[[DRIVER_MASS]]))
    mGround = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=mbs.AddNode(NodePointGround()), coordinate=0))
    mDriver = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=nDriver, coordinate=0))
    mX, mY, mAngle = (mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=nNut, coordinate=i)) for i in range(3))
    for markers, stiffness, damping in (([mGround, mDriver], DRIVER_MASS * omega ** 2, 0.0),
                                        ([mDriver, mX], p.drag_stiffness, p.drag_damping),
                                        ([mGround, mY], p.drag_stiffness, p.drag_damping)):
        mbs.AddObject(ObjectConnectorCoordinateSpringDamper(markerNumbers=markers, stiffness=stiffness,
                                                            damping=damping))
    mbs.AddLoad(LoadCoordinate(markerNumber=mAngle, load=bj.lead_torque(p, p.t_end)))
    for ovt in (exu.OutputVariableType.Coordinates, exu.OutputVariableType.Coordinates_t):
        mbs.AddSensor(SensorNode(nodeNumber=nNut, outputVariableType=ovt, storeInternal=True))
    if floor:
        for points in rings:
            empty_contact(mbs, [nNut], len(points), storeHistory=True)
    mbs.Assemble()
    if settings == "exudyn":
        ss, st = exudyn_defaults(p.t_end, p.dt), exu.DynamicSolverType.GeneralizedAlpha
    else:
        ss, st = LooseningSettings(p)
    return dict(SC=SC, mbs=mbs, simulationSettings=ss, solverType=st)


MODELS = [
    # label, settings, build(p)
    ("ours", "ours", lambda p: BuildLoosening(p, show=False)),
    ("C++ springs", "exudyn", lambda p: BuildShakenNut(p, "exudyn")),
    ("C++ springs", "ours", lambda p: BuildShakenNut(p, "ours")),
    ("floor", "ours", lambda p: BuildShakenNut(p, "ours", floor=True)),
]


def measure(quick, repeats=REPEATS):
    """The rows of LONG_COLUMNS: every model of MODELS solved once untimed on a short run (kernels
    compiled or loaded), then ``repeats`` interleaved timed rounds of the long run (module doc)."""
    cycles = CYCLES_QUICK if quick else CYCLES
    p = joint_params(cycles)
    warm = joint_params(1)
    for _, _, build in MODELS:
        timed_solve(build(warm))
    timings = [[] for _ in MODELS]
    for _ in range(repeats):
        for i, (_, _, build) in enumerate(MODELS):
            model = build(p)
            timings[i].append(timed_solve(model)[:3])
            del model
            gc.collect()                  # ours keeps its history (GBs over 1000 cycles): free it before the next
    ours = np.array([c for c, _, _ in timings[0]])
    rows = []
    for (label, settings, _), t in zip(MODELS, timings):
        cpu, wall = np.array([c for c, _, _ in t]), np.array([w for _, w, _ in t])
        ratio = ours / cpu
        rows.append([label, settings, cycles, t[0][2], float(np.median(cpu)), float(cpu.min()), float(cpu.max()),
                     float(np.median(wall)), float(wall.min()), float(wall.max()), float(np.median(ratio)),
                     float(ratio.min()), float(ratio.max()), repeats])
    return rows
