"""C++ baseline: the block and screw scenes with Exudyn's built-in linear spring-dampers in place of
the anisotropic contact, same bodies, drives, sensors, solver and step (issue 5, part 3).

    python studies/baseline.py [--quick] [--repeats 5] [--implementation numpy]   # ours/baseline table

What replaces the contact (per contact point, stiffness = our per-point values eps / K, so the
baseline is *our law in pure stick with isotropic adhesion*, which is a linear spring):

* block, planar model (``NodeRigidBody2D``): one ``ObjectConnectorCartesianSpringDamper`` per point
  between a ``MarkerBodyPosition`` at the body-local point and a ground ``MarkerBodyPosition``
  (on an ``ObjectGround``) at the point's initial world position; stiffness (eps_1/K, eps_1/K, 0).
  The 2D body's markers carry x, y and the rotation, so the in-plane force and the z torque come
  out exactly as from our law (local z is the held height, as in ``BuildBlock``).
* block, full model (3D rigid body, EP or RotVecLG node): the same connector with stiffness
  (eps_1/K, eps_1/K, eps_n/K), the ground marker at the projection (X_k, Y_k, 0) of the initial point
  onto the plane, so the spring starts with the static penetration and carries normal_load exactly
  as our normal penalty does.
* screw, reduced model (``NodeGenericODE2`` with psi, z): there are no position markers on a
  generic node, so the only C++ items acting on it are coordinate items: per evaluated contact
  point two ``ObjectConnectorCoordinateSpringDamper`` (psi with k = eps_1/K * R * (R + interference),
  z with k = eps_1/K) between a ``MarkerNodeCoordinate`` of the screw node and one of a ground node.
  This is exactly our law in stick with isotropic adhesion (torque -eps R rho psi, force -eps z per
  point). ``symmetry`` mirrors ``BuildScrew``: True (its default) -> ours evaluates ONE
  representative point carrying the totals, so the fair baseline is ONE pair with the total
  stiffnesses; False -> one pair per point of the layout (cost grows with K on both sides).
* screw, full model (3D rigid body): one ``ObjectConnectorCartesianSpringDamper`` per point, ground
  marker at the point's projection onto the hole (radius R); stiffness = the diagonal, in global
  components, of the point's local tensor diag(eps_n, eps_1, eps_1) in (e_r, e_phi, e_z)
  (exact for points on the x and y axes, off-diagonal coupling dropped elsewhere: the cheapest C++
  spring per point; it starts with the interference preload like our normal penalty).

Drives and loads are built as in ``exu_aniso.models`` (C++ loads for "force"/"torque", the same
Python ``AddNodeDrive`` for the spring drives), so with "force"/"torque" drives the contact is the
only Python user function in our model and the ratio isolates its cost.
"""
from __future__ import annotations

import math
import os
import sys
import time

import exudyn as exu
import numpy as np
from exu_aniso.models.block import NODE_TYPES, AddNodeDrive, SimulationSettingsFor, SolveTimed
from exudyn.itemInterface import (
    LoadCoordinate,
    MarkerBodyPosition,
    MarkerNodeCoordinate,
    NodeGenericODE2,
    NodePointGround,
    NodeRigidBody2D,
    ObjectConnectorCartesianSpringDamper,
    ObjectConnectorCoordinateSpringDamper,
    ObjectGenericODE2,
    ObjectGround,
    ObjectRigidBody2D,
    SensorNode,
)
from exudyn.rigidBodyUtilities import RigidBodyInertia
from exudyn.utilities import InertiaCuboid

from exu_aniso.scenes import BlockParams, ScrewParams, block_points, screw_points


def _ground(mbs):
    return mbs.AddObject(ObjectGround())


def BuildBlockBaseline(p: BlockParams, nodeType="EP", solverType=None, rhoInf=0.8, newtonTolerance=1e-10):
    """The block scene with C++ Cartesian spring-dampers at the contact points (see module doc).
    Returns dict(SC, mbs, simulationSettings, solverType, params, nBlock, oBlock, springs, sensors)."""
    if nodeType not in NODE_TYPES:
        raise ValueError(f"nodeType must be one of {tuple(NODE_TYPES)}; got {nodeType!r}")
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    m, a = p.mass, p.size
    K = len(block_points(p))
    gap = -p.normal_load / p.eps_n
    ang = math.radians(p.drive_angle)
    d = np.array([math.cos(ang), math.sin(ang)])
    kt, kn = p.eps_1 / K, p.eps_n / K
    sensors = {}
    local = block_points(p)
    if p.model == "planar":
        nBlock = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=[p.x0, p.y0, 0.0]))
        oBlock = mbs.AddObject(ObjectRigidBody2D(nodeNumber=nBlock, mass=m, inertia=m * a * a / 6.0))
        nq = 3
        local[:, 2] = gap
        anchors = np.column_stack([local[:, 0] + p.x0, local[:, 1] + p.y0, local[:, 2]])
        stiffness = [kt, kt, 0.0]
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
                                     referencePosition=[p.x0, p.y0, 0.5 * a + gap], nodeType=NODE_TYPES[nodeType])
        nBlock = mbs.GetObject(oBlock)["nodeNumber"]
        nq = 6 if nodeType == "RotVecLG" else 7
        anchors = np.column_stack([local[:, 0] + p.x0, local[:, 1] + p.y0, np.zeros(K)])
        stiffness = [kt, kt, kn]
        load = np.array([0.0, 0.0, -p.normal_load])
        if p.drive == "force":
            load[:2] += p.force * d
        mbs.CreateForce(itemNumber=oBlock, loadVector=load.tolist())
        for name, ovt in (("sPosition", "Position"), ("sVelocity", "Velocity"),
                          ("sRotation", "RotationMatrix"), ("sOmega", "AngularVelocity")):
            sensors[name] = mbs.AddSensor(SensorNode(nodeNumber=nBlock, storeInternal=True,
                                                     outputVariableType=getattr(exu.OutputVariableType, ovt)))
    if p.drive == "displacement":
        k, s = p.drive_stiffness, p.drive_speed
        dd = np.zeros(nq)
        dd[0:2] = d
        Kdrive = k * np.outer(dd, dd)
        AddNodeDrive(mbs, nBlock, nq, lambda t, q: k * (s * t - d @ q[0:2]) * dd, lambda t, q: Kdrive)
    oGround = _ground(mbs)
    springs = []
    for b, g in zip(local, anchors):
        mBody = mbs.AddMarker(MarkerBodyPosition(bodyNumber=oBlock, localPosition=b.tolist()))
        mGround = mbs.AddMarker(MarkerBodyPosition(bodyNumber=oGround, localPosition=g.tolist()))
        springs.append(mbs.AddObject(ObjectConnectorCartesianSpringDamper(markerNumbers=[mGround, mBody],
                                                                          stiffness=stiffness, damping=[0.0] * 3)))
    mbs.Assemble()
    ss, st = SimulationSettingsFor(p, rhoInf=rhoInf, newtonTolerance=newtonTolerance, solverType=solverType)
    return dict(SC=SC, mbs=mbs, simulationSettings=ss, solverType=st, params=p, nBlock=nBlock, oBlock=oBlock,
                springs=springs, sensors=sensors, nodeType=nodeType)


def BuildScrewBaseline(p: ScrewParams, nodeType="RotVecLG", solverType=None, rhoInf=0.8, newtonTolerance=1e-10,
                       symmetry=True):
    """The screw scene with C++ spring-dampers per contact point (see module doc; symmetry as in
    BuildScrew, reduced model only). Returns dict(SC, mbs, simulationSettings, solverType, params,
    nScrew, oScrew, springs, sensors)."""
    if nodeType not in NODE_TYPES:
        raise ValueError(f"nodeType must be one of {tuple(NODE_TYPES)}; got {nodeType!r}")
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    m, r, L = p.mass, p.radius, p.length
    Ja, Jt = 0.5 * m * r * r, m * (3.0 * r * r + L * L) / 12.0
    local = screw_points(p)
    K = len(local)
    kt, kn = p.eps_1 / K, p.eps_n / K
    rho = p.radius + p.interference
    sensors, springs = {}, []
    if p.model == "reduced":
        nScrew = mbs.AddNode(NodeGenericODE2(referenceCoordinates=[0.0, 0.0], initialCoordinates=[0.0, 0.0],
                                             initialCoordinates_t=[0.0, 0.0], numberOfODE2Coordinates=2))
        oScrew = mbs.AddObject(ObjectGenericODE2(nodeNumbers=[nScrew], massMatrix=np.diag([Ja, m])))
        mPsi = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=nScrew, coordinate=0))
        mZ = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=nScrew, coordinate=1))
        if p.drive == "torque":
            mbs.AddLoad(LoadCoordinate(markerNumber=mPsi, load=p.torque))
        mbs.AddLoad(LoadCoordinate(markerNumber=mZ, load=p.axial_load))
        if p.drive in ("rotation", "axial"):
            i, rate = (0, p.rotation_speed) if p.drive == "rotation" else (1, p.axial_speed)
            k = p.drive_stiffness
            Kdrive = np.zeros((2, 2))
            Kdrive[i, i] = k

            def DriveForce(t, q):
                Q = np.zeros(2)
                Q[i] = k * (rate * t - q[i])
                return Q

            AddNodeDrive(mbs, nScrew, 2, DriveForce, lambda t, q: Kdrive)
        nGround = mbs.AddNode(NodePointGround())
        mGround = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=nGround, coordinate=0))
        pairs = 1 if symmetry else K
        for _ in range(pairs):
            for mC, kc in ((mPsi, p.eps_1 / pairs * p.radius * rho), (mZ, p.eps_1 / pairs)):
                springs.append(mbs.AddObject(ObjectConnectorCoordinateSpringDamper(markerNumbers=[mGround, mC],
                                                                                   stiffness=kc, damping=0.0)))
        sensors["sCoordinates"] = mbs.AddSensor(SensorNode(nodeNumber=nScrew, storeInternal=True,
                                                           outputVariableType=exu.OutputVariableType.Coordinates))
        sensors["sVelocities"] = mbs.AddSensor(SensorNode(nodeNumber=nScrew, storeInternal=True,
                                                          outputVariableType=exu.OutputVariableType.Coordinates_t))
    else:
        if p.drive == "rotation":
            raise ValueError("BuildScrewBaseline: drive 'rotation' of the full model is not built here; "
                             "use drive='torque' or 'axial'")
        oScrew = mbs.CreateRigidBody(inertia=RigidBodyInertia(mass=m, inertiaTensor=np.diag([Jt, Jt, Ja])),
                                     referencePosition=[0.0, 0.0, 0.0], nodeType=NODE_TYPES[nodeType])
        nScrew = mbs.GetObject(oScrew)["nodeNumber"]
        if p.drive == "torque":
            mbs.CreateTorque(itemNumber=oScrew, loadVector=[0.0, 0.0, p.torque])
        mbs.CreateForce(itemNumber=oScrew, loadVector=[0.0, 0.0, p.axial_load])
        if p.drive == "axial":
            nq = 7 if nodeType == "EP" else 6
            k = p.drive_stiffness
            Kdrive = np.zeros((nq, nq))
            Kdrive[2, 2] = k

            def DriveForce(t, q):
                Q = np.zeros(nq)
                Q[2] = k * (p.axial_speed * t - q[2])
                return Q

            AddNodeDrive(mbs, nScrew, nq, DriveForce, lambda t, q: Kdrive)
        oGround = _ground(mbs)
        for b in local:
            phi = math.atan2(b[1], b[0])
            c2, s2 = math.cos(phi) ** 2, math.sin(phi) ** 2
            stiffness = [kn * c2 + kt * s2, kn * s2 + kt * c2, kt]
            g = [p.radius * math.cos(phi), p.radius * math.sin(phi), b[2]]
            mBody = mbs.AddMarker(MarkerBodyPosition(bodyNumber=oScrew, localPosition=b.tolist()))
            mG = mbs.AddMarker(MarkerBodyPosition(bodyNumber=oGround, localPosition=g))
            springs.append(mbs.AddObject(ObjectConnectorCartesianSpringDamper(markerNumbers=[mG, mBody],
                                                                              stiffness=stiffness, damping=[0.0] * 3)))
        for name, ovt in (("sPosition", "Position"), ("sVelocity", "Velocity"),
                          ("sRotation", "RotationMatrix"), ("sOmega", "AngularVelocity")):
            sensors[name] = mbs.AddSensor(SensorNode(nodeNumber=nScrew, storeInternal=True,
                                                     outputVariableType=getattr(exu.OutputVariableType, ovt)))
    mbs.Assemble()
    ss, st = SimulationSettingsFor(p, rhoInf=rhoInf, newtonTolerance=newtonTolerance, solverType=solverType)
    return dict(SC=SC, mbs=mbs, simulationSettings=ss, solverType=st, params=p, nScrew=nScrew, oScrew=oScrew,
                springs=springs, sensors=sensors, nodeType=nodeType)


def RunBaseline(scene, p, **options):
    """Build and solve a baseline model; returns (model, cpu_s, steps, newton_iterations) with the
    process CPU time of SolveDynamic (model building excluded)."""
    build = {"block": BuildBlockBaseline, "screw": BuildScrewBaseline}[scene]
    model = build(p, **options)
    c0 = time.process_time()
    _, steps, iters, _ = SolveTimed(model["mbs"], model["simulationSettings"], model["solverType"])
    return model, time.process_time() - c0, steps, iters


def BaselineTrajectory(model):
    """Body coordinates from the stored sensors: block planar (t, x, y, theta), block full
    (t, x, y, z), screw reduced (t, psi, z), screw full (t, x, y, z)."""
    S, mbs = model["sensors"], model["mbs"]
    if "sCoordinates" in S:
        Q = mbs.GetSensorStoredData(S["sCoordinates"])
        return Q
    return mbs.GetSensorStoredData(S["sPosition"])


# ----------------------------------------------------------------------------------------------
# the ratio table (ours / baseline, measured in the same run)

# scenes of the ratio table: (scene, model, overrides, drive label, Build* options). "C++ load" drives leave the
# contact as the only Python user function in ours; the default spring drives are Python
# (AddNodeDrive) in both models, as in the scenes' defaults. The full screw's default rotation
# drive (yaw tracking in Python) has no baseline builder: torque only.
RATIO_SCENES = [
    ("block", "planar", dict(points="corners", drive="force"), "C++ load", {}),
    ("block", "full", dict(points="corners", drive="force"), "C++ load", {}),
    ("screw", "reduced", dict(drive="torque"), "C++ load", {}),
    ("screw", "reduced", dict(drive="torque"), "C++ load, no symmetry", dict(symmetry=False)),
    ("screw", "full", dict(drive="torque"), "C++ load", {}),
    ("block", "planar", dict(points="corners"), "Python spring (default)", {}),
    ("block", "full", dict(points="corners"), "Python spring (default)", {}),
    ("screw", "reduced", dict(), "Python spring (default)", {}),
]


def ratio_case(case):
    """One ratio-table row: median CPU time per step of ours and of the baseline (process CPU
    time of SolveDynamic; interleaved repeats)."""
    from exu_aniso.models.block import BuildBlock
    from exu_aniso.models.screw import BuildScrew

    P = BlockParams if case["scene"] == "block" else ScrewParams
    p = P(**case["params"])
    build = BuildBlock if case["scene"] == "block" else BuildScrew
    base_opts = {k: v for k, v in case.get("options", {}).items() if k == "symmetry"}
    warm = p.with_overrides(t_end=5 * p.dt)           # first-call costs (imports, numba cache) untimed
    SolveTimed(*[build(warm, **case.get("options", {}))[k] for k in ("mbs", "simulationSettings", "solverType")])
    RunBaseline(case["scene"], warm, **base_opts)
    ours, base = [], []
    for _ in range(case["repeats"]):
        model = build(p, **case.get("options", {}))
        c0 = time.process_time()
        _, s, it, _ = SolveTimed(model["mbs"], model["simulationSettings"], model["solverType"])
        ours.append((time.process_time() - c0, s, it))
        impl = model["contact"].get("implementation", "numpy")
        K_eval = len(model["contact"]["points"])          # points ours evaluates (1 under screw symmetry)
        _, c, s, it = RunBaseline(case["scene"], p, **base_opts)
        base.append((c, s, it))
    o, b = np.array(ours, dtype=float), np.array(base, dtype=float)
    o_step, b_step = np.median(o[:, 0] / o[:, 1]), np.median(b[:, 0] / b[:, 1])
    o_it, b_it = np.median(o[:, 0] / o[:, 2]), np.median(b[:, 0] / b[:, 2])
    return dict(scene=case["scene"], model=p.model, drive=case["drive"], contact=impl, K=K_eval,
                ours_step_s=float(o_step), base_step_s=float(b_step), ratio_step=float(o_step / b_step),
                ours_newton_per_step=float(np.median(o[:, 2] / o[:, 1])),
                base_newton_per_step=float(np.median(b[:, 2] / b[:, 1])),
                ratio_per_newton=float(o_it / b_it))


def ratio_cases(quick, repeats, extra_options=None):
    t_end, dt = (0.05, 1e-3) if quick else (0.2, 1e-3)
    return [dict(scene=s, params=dict(model=m, t_end=t_end, dt=dt, **ov), options={**(extra_options or {}), **opts},
                 repeats=repeats, drive=drv) for s, m, ov, drv, opts in RATIO_SCENES]


def print_ratio_table(rows, file=sys.stdout):
    print(f"{'scene':6s} {'model':8s} {'drive':24s} {'contact':8s} {'K':>3s} {'ours CPU/step [ms]':>18s} {'C++ CPU/step [ms]':>17s} "
          f"{'ours/C++':>9s} {'Newton/step ours':>17s} {'C++':>5s} {'ratio per Newton it.':>21s}", file=file)
    for r in rows:
        print(f"{r['scene']:6s} {r['model']:8s} {r['drive']:24s} {r['contact']:8s} {r['K']:3d} {r['ours_step_s'] * 1e3:18.3f} {r['base_step_s'] * 1e3:17.3f} "
              f"{r['ratio_step']:9.2f} {r['ours_newton_per_step']:17.2f} {r['base_newton_per_step']:5.2f} "
              f"{r['ratio_per_newton']:21.2f}", file=file)


def main(argv=None):
    import argparse
    ap = argparse.ArgumentParser(description="ours/C++-baseline step cost per scene and model (serial timing)")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--repeats", type=int, default=None)
    ap.add_argument("--implementation", default=None, help="contact kernel passed to BuildBlock/BuildScrew "
                    "(auto | compiled | numpy; default: their default)")
    a = ap.parse_args(argv)
    reps = a.repeats or (3 if a.quick else 5)
    opts = {} if a.implementation is None else {"implementation": a.implementation}
    rows = [ratio_case(c) for c in ratio_cases(a.quick, reps, opts)]
    print_ratio_table(rows)
    return 0


if __name__ == "__main__":
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    sys.exit(main())
