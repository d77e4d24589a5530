"""C++ baseline: the block and screw scenes with Exudyn's built-in linear spring-dampers in place of
the anisotropic contact, same bodies, drives, sensors, solver and step.

Used by ``studies/benchmarks.py`` (its ``baseline.csv``) and ``studies/baseline.py`` (the ratio
table alone: ``python studies/baseline.py [--quick] [--repeats 5] [--implementation numpy]``).

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
  point two ``ObjectConnectorCoordinateSpringDamper`` (psi with k = eps_1/K * R**2: slip and force at the contact point C on the hole surface,
  z with k = eps_1/K) between a ``MarkerNodeCoordinate`` of the screw node and one of a ground node.
  This is exactly our law in stick with isotropic adhesion (torque -eps R^2 psi, force -eps z per
  point). ``symmetry`` mirrors ``BuildScrew``: True (its default) -> ours evaluates ONE
  representative point carrying the totals, so the fair baseline is ONE pair with the total
  stiffnesses; False -> one pair per point of the layout (cost grows with K on both sides).
* screw, full model (3D rigid body): one ``ObjectConnectorCartesianSpringDamper`` per point, ground
  marker at the point's projection onto the hole (radius R); stiffness = the diagonal, in global
  components, of the point's local tensor diag(eps_n, eps_1, eps_1) in (e_r, e_phi, e_z)
  (exact for points on the x and y axes, off-diagonal coupling dropped elsewhere: the cheapest C++
  spring per point; it starts with the interference preload like our normal penalty).

The floor: the same C++ springs plus the Exudyn items of one contact set with user functions that
do nothing (``empty_contact``, the speed targets' floor too): an ``ObjectGenericODE2`` on the
body's node, without mass matrix, whose force and Jacobian user functions return zeros, the history
data nodes with their two C++ sensors and a post-Newton function that accepts the step. It costs what the callbacks cost without any
contact computation, so ours - floor is the contact itself and floor - C++ is Exudyn's price of
calling Python.

Settings: every row is measured at the package's solver settings ("package": Exudyn's modified
Newton with a fresh Jacobian when an iteration contracts by less than 0.01, relative and absolute
tolerance 1e-10, ``SimulationSettingsFor``) and at Exudyn's defaults
("exudyn": the Newton settings of a fresh ``exu.SimulationSettings()``: modified Newton, relative
tolerance 1e-8, absolute 1e-10) and at Exudyn's defaults with a fresh Jacobian at every step
("jacobian_per_step": ``newton.modifiedNewtonJacUpdatePerStep = True``), the same step and
integrator for ours, the floor and the C++ model.

The scenes themselves are built by ``BuildBlock`` / ``BuildScrew`` (their ``contactBuilder`` hook
puts the springs where the anisotropic contact would go), so bodies, loads, drives, sensors and
settings are the same items: C++ loads for "force"/"torque", the same C++ spring drives
(``AddSpringDrive``, ``AddCoordinateDrive``). With these drives the contact is the only Python user
function in our model and the ratio isolates its cost.
"""
from __future__ import annotations

import sys
import time

import numpy as np
from exu_aniso.engines.exudyn_adapter.runner import SolveTimed
import exudyn as exu
from exudyn.itemInterface import (
    MarkerBodyPosition,
    NodeGenericData,
    ObjectGenericODE2,
    SensorNode,
    MarkerNodeCoordinate,
    NodePointGround,
    ObjectConnectorCartesianSpringDamper,
    ObjectConnectorCoordinateSpringDamper,
    ObjectGround,
)

from exu_aniso.scenes.block import BlockParams
from exu_aniso.scenes.screw import ScrewParams


def _cartesian_springs(mbs, bodyNumber, localPoints, anchors, stiffness, damping=None):
    """One C++ Cartesian spring-damper per point between the body point and its ground anchor;
    stiffness [N/m] and damping [N s/m] (default none): per point, along x, y, z."""
    damping = [[0.0] * 3] * len(stiffness) if damping is None else damping
    oGround = mbs.AddObject(ObjectGround())
    springs = []
    for b, g, k, d in zip(localPoints, anchors, stiffness, damping):
        mBody = mbs.AddMarker(MarkerBodyPosition(bodyNumber=bodyNumber, localPosition=list(map(float, b))))
        mGround = mbs.AddMarker(MarkerBodyPosition(bodyNumber=oGround, localPosition=list(map(float, g))))
        springs.append(mbs.AddObject(ObjectConnectorCartesianSpringDamper(markerNumbers=[mGround, mBody],
                                                                          stiffness=list(k), damping=list(d))))
    return dict(springs=springs, points=np.asarray(localPoints))


def empty_contact(mbs, nodes, K, storeHistory, sparse=False):
    """The Exudyn items of one contact set of K points over ``nodes`` (what CreateAnisotropicContact
    adds: an ObjectGenericODE2 without mass matrix, the history and dissipation data nodes, the
    dissipation sensor and with storeHistory the history sensor, the post-Newton function) with user
    functions that return zeros and accept every step. sparse: the Jacobian as a sparse matrix (a
    group's)."""
    from exu_aniso.law.history import N_HISTORY
    n = sum(len(mbs.GetNodeParameter(nd, "referenceCoordinates")) for nd in nodes)
    zq = np.zeros(n)
    if sparse:
        import scipy.sparse as sp
        zJ = sp.csr_matrix((n, n))
    else:
        zJ = np.zeros((n, n))

    def force(mbs, t, itemNumber, q, q_t):
        return zq

    def jacobian(mbs, t, itemNumber, q, q_t, fODE2, fODE2_t):
        return zJ

    mbs.AddObject(ObjectGenericODE2(nodeNumbers=list(nodes), forceUserFunction=force,
                                    jacobianUserFunction=jacobian))
    nHistory = mbs.AddNode(NodeGenericData(initialCoordinates=[0.0] * (K * N_HISTORY),
                                           numberOfDataCoordinates=K * N_HISTORY))
    nDissipation = mbs.AddNode(NodeGenericData(initialCoordinates=[0.0], numberOfDataCoordinates=1))
    for nd, store in ((nDissipation, True), (nHistory, storeHistory)):
        if store:
            mbs.AddSensor(SensorNode(nodeNumber=nd, outputVariableType=exu.OutputVariableType.Coordinates,
                                     storeInternal=True))
    mbs.SetPostNewtonUserFunction(lambda mbs, t: [0.0, -1.0])


def exudyn_defaults(t_end, dt):
    """A fresh exu.SimulationSettings() (Exudyn's defaults) for t_end at step dt, silent, no file,
    sensors every step."""
    ss = exu.SimulationSettings()
    ss.timeIntegration.numberOfSteps = int(round(t_end / dt))
    ss.timeIntegration.endTime = t_end
    ss.timeIntegration.verboseMode = 0
    ss.solution.file.write = False
    ss.solution.sensors.writePeriod = 0
    return ss


def apply_settings(model, settings):
    """Newton settings of a built model (module doc): "package" (as built), "exudyn" (a fresh
    exu.SimulationSettings()'s Newton settings), "jacobian_per_step" (Exudyn's, with the modified
    Newton's Jacobian computed afresh at every step: modifiedNewtonJacUpdatePerStep), "package_1e-8"
    (the package's contractivity 0.01 at Exudyn's tolerances), "full_newton_1e-8" (full Newton at Exudyn's tolerances) or "full_newton_1e-10" (full Newton at
    the package's tolerance: the package's setting before the Newton-settings study)."""
    if settings == "package":
        return model
    if settings not in NEWTON_SETTINGS:
        raise ValueError(f"settings must be 'package' or one of {tuple(NEWTON_SETTINGS)}; got {settings!r}")
    d, n = exu.SimulationSettings().timeIntegration.newton, model["simulationSettings"].timeIntegration.newton
    for name in ("useModifiedNewton", "relativeTolerance", "absoluteTolerance", "maxIterations",
                 "modifiedNewtonContractivity"):
        setattr(n, name, getattr(d, name))
    for name, value in NEWTON_SETTINGS[settings].items():
        setattr(n, name, value)
    return model


# the Newton settings besides the package's: changes to a fresh exu.SimulationSettings()'s Newton settings
NEWTON_SETTINGS = {"exudyn": {}, "jacobian_per_step": {"modifiedNewtonJacUpdatePerStep": True},
                   "package_1e-8": {"modifiedNewtonContractivity": 0.01},
                   "full_newton_1e-8": {"useModifiedNewton": False},
                   "full_newton_1e-10": {"useModifiedNewton": False, "relativeTolerance": 1e-10,
                                         "absoluteTolerance": 1e-10}}


def BuildBlockBaseline(p: BlockParams, nodeType="EP", solverType=None, rhoInf=0.8, newtonTolerance=1e-10,
                       emptyCallbacks=False):
    """The block scene of ``BuildBlock`` (same body, loads, drive, sensors, settings) with C++
    Cartesian spring-dampers at the contact points (see module doc); emptyCallbacks: plus the
    floor's do-nothing contact items. Returns BuildBlock's dict plus 'springs'."""
    from exu_aniso.models.block import BuildBlock

    def springs(mbs, oBlock, local):
        K = len(local)
        kt, kn = p.eps_1 / K, p.eps_n / K
        if p.model == "planar":   # local z is the held height: anchor at the initial point, no normal spring
            anchors = np.column_stack([local[:, 0] + p.x0, local[:, 1] + p.y0, local[:, 2]])
            k = [kt, kt, 0.0]
        else:                     # anchor on the plane: the normal spring starts with the static penetration
            anchors = np.column_stack([local[:, 0] + p.x0, local[:, 1] + p.y0, np.zeros(K)])
            k = [kt, kt, kn]
        if emptyCallbacks:
            empty_contact(mbs, [mbs.GetObject(oBlock)["nodeNumber"]], K, storeHistory=True)
        return _cartesian_springs(mbs, oBlock, local, anchors, [k] * K)

    model = BuildBlock(p, nodeType=nodeType, solverType=solverType, rhoInf=rhoInf, newtonTolerance=newtonTolerance,
                       contactBuilder=springs)
    model["springs"] = model["contact"]["springs"]
    return model


def BuildScrewBaseline(p: ScrewParams, nodeType="RotVecLG", solverType=None, rhoInf=0.8, newtonTolerance=1e-10,
                       symmetry=True, emptyCallbacks=False):
    """The screw scene of ``BuildScrew`` with C++ spring-dampers per evaluated contact point (see
    module doc; symmetry as in BuildScrew, reduced model only). Returns BuildScrew's dict plus
    'springs'."""
    from exu_aniso.models.screw import BuildScrew
    if p.model == "full" and p.drive == "rotation":
        raise ValueError("BuildScrewBaseline: drive 'rotation' of the full model has no spring equivalent (the "
                         "screw slides all around the hole while ground-anchored springs wind up); use drive='torque' "
                         "or 'axial'")

    def springs(mbs, oScrew, local):
        K = len(local)
        kt, kn = p.eps_1 / K, p.eps_n / K
        if emptyCallbacks:
            obj = mbs.GetObject(oScrew)
            empty_contact(mbs, [obj["nodeNumber"] if "nodeNumber" in obj else obj["nodeNumbers"][0]], K,
                          storeHistory=True)
        if p.model == "reduced":  # coordinate springs on (psi, z), one pair per evaluated point
            node = mbs.GetObject(oScrew)["nodeNumbers"][0]
            mPsi, mZ = (mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=node, coordinate=i)) for i in (0, 1))
            mGround = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=mbs.AddNode(NodePointGround()), coordinate=0))
            out = []
            for _ in range(K):
                for mC, kc in ((mPsi, kt * p.radius ** 2), (mZ, kt)):
                    out.append(mbs.AddObject(ObjectConnectorCoordinateSpringDamper(markerNumbers=[mGround, mC],
                                                                                  stiffness=kc, damping=0.0)))
            return dict(springs=out, points=np.asarray(local))
        phi = np.arctan2(local[:, 1], local[:, 0])   # diagonal of diag(kn, kt, kt) in (e_r, e_phi, e_z), global
        c2, s2 = np.cos(phi) ** 2, np.sin(phi) ** 2
        anchors = np.column_stack([p.radius * np.cos(phi), p.radius * np.sin(phi), local[:, 2]])
        return _cartesian_springs(mbs, oScrew, local, anchors,
                                  np.column_stack([kn * c2 + kt * s2, kn * s2 + kt * c2, np.full(K, kt)]))

    model = BuildScrew(p, nodeType=nodeType, solverType=solverType, rhoInf=rhoInf, newtonTolerance=newtonTolerance,
                       symmetry=symmetry, contactBuilder=springs)
    model["springs"] = model["contact"]["springs"]
    return model


def RunBaseline(scene, p, settings="package", **options):
    """Build and solve a baseline model (options: Build*Baseline's, e.g. emptyCallbacks=True for the
    floor; settings: apply_settings); returns (model, cpu_s, steps, newton_iterations) with the
    process CPU time of SolveDynamic (model building excluded)."""
    build = {"block": BuildBlockBaseline, "screw": BuildScrewBaseline}[scene]
    model = apply_settings(build(p, **options), settings)
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

# scenes of the ratio table: (scene, model, overrides, drive label, Build* options). With C++ loads and the
# default spring drives (Exudyn C++ items too: exu_aniso.engines.exudyn_adapter.runner.AddSpringDrive) the contact is the only Python
# user function in ours. The screw's torque is 0.02 N m: it sticks (the step load overshoots to 0.04 N m
# against a sliding torque of 0.101 N m), where our law is the linear spring of the baseline. At the
# scene's default torque, 0.05 N m, the overshoot grazes the sliding torque and the run is not converged in
# the step (studies/newton_settings.py); a per-step ratio against springs that never slip would mislead.
# The full screw's default rotation drive (yaw tracking in Python) has no baseline builder: torque only.
STICKING_TORQUE = 0.02
RATIO_SCENES = [
    ("block", "planar", dict(points="corners", drive="force"), "C++ load", {}),
    ("block", "full", dict(points="corners", drive="force"), "C++ load", {}),
    ("screw", "reduced", dict(drive="torque", torque=STICKING_TORQUE), "C++ load", {}),
    ("screw", "reduced", dict(drive="torque", torque=STICKING_TORQUE), "C++ load, no symmetry", dict(symmetry=False)),
    ("screw", "full", dict(drive="torque", torque=STICKING_TORQUE), "C++ load", {}),
    ("block", "planar", dict(points="corners"), "spring drive (default)", {}),
    ("block", "full", dict(points="corners"), "spring drive (default)", {}),
    ("screw", "reduced", dict(), "spring drive (default)", {}),
]


def ratio_case(case):
    """One ratio-table row: median CPU time per step of ours, of the floor and of the C++ baseline
    at case["settings"] (process CPU time of SolveDynamic; the three interleaved in every repeat)."""
    from exu_aniso.models.block import BuildBlock
    from exu_aniso.models.screw import BuildScrew

    P = BlockParams if case["scene"] == "block" else ScrewParams
    p = P(**case["params"])
    build = BuildBlock if case["scene"] == "block" else BuildScrew
    settings = case.get("settings", "package")
    base_opts = {k: v for k, v in case.get("options", {}).items() if k == "symmetry"}
    warm = p.with_overrides(t_end=5 * p.dt)           # first-call costs (imports, numba cache) untimed
    SolveTimed(*[build(warm, **case.get("options", {}))[k] for k in ("mbs", "simulationSettings", "solverType")])
    RunBaseline(case["scene"], warm, **base_opts)
    ours, base, floor = [], [], []
    for _ in range(case["repeats"]):
        model = apply_settings(build(p, **case.get("options", {})), settings)
        c0 = time.process_time()
        _, s, it, _ = SolveTimed(model["mbs"], model["simulationSettings"], model["solverType"])
        ours.append((time.process_time() - c0, s, it))
        impl = model["contact"].get("implementation", "numpy")
        K_eval = len(model["contact"]["points"])          # points ours evaluates (1 under screw symmetry)
        _, c, s, it = RunBaseline(case["scene"], p, settings, **base_opts)
        base.append((c, s, it))
        _, c, s, it = RunBaseline(case["scene"], p, settings, emptyCallbacks=True, **base_opts)
        floor.append((c, s, it))
    o, b, f = (np.array(x, dtype=float) for x in (ours, base, floor))
    o_step, b_step, f_step = (float(np.median(x[:, 0] / x[:, 1])) for x in (o, b, f))
    # per simulated second: the whole solve (rejected steps included) over t_end
    o_sim, b_sim, f_sim = (float(np.median(x[:, 0])) / p.t_end for x in (o, b, f))
    o_it, b_it, f_it = (float(np.median(x[:, 0] / x[:, 2])) for x in (o, b, f))
    return dict(scene=case["scene"], model=p.model, drive=case["drive"], settings=settings, contact=impl, K=K_eval,
                ours_step_s=o_step, base_step_s=b_step, floor_step_s=f_step, ratio_step=o_step / b_step,
                ours_sim_s=o_sim, base_sim_s=b_sim, floor_sim_s=f_sim,
                floor_ratio_step=f_step / b_step,
                ours_newton_per_step=float(np.median(o[:, 2] / o[:, 1])),
                base_newton_per_step=float(np.median(b[:, 2] / b[:, 1])),
                ratio_per_newton=o_it / b_it, floor_ratio_per_newton=f_it / b_it)


def ratio_cases(quick, repeats, extra_options=None):
    t_end, dt = (0.05, 1e-3) if quick else (0.2, 1e-3)
    return [dict(scene=s, params=dict(model=m, t_end=t_end, dt=dt, **ov), options={**(extra_options or {}), **opts},
                 repeats=repeats, drive=drv, settings=st)
            for st in SETTINGS for s, m, ov, drv, opts in RATIO_SCENES]


SETTINGS = ("package", "exudyn", "jacobian_per_step")

# columns of baseline.csv (benchmarks.py and baseline.py)
BASE_COLUMNS = ["scene [-]", "model [-]", "drive [-]", "settings [-]", "contact_impl [-]", "K [-]",
                "ours_per_step [s]", "floor_per_step [s]", "baseline_per_step [s]", "ours_over_baseline [-]",
                "floor_over_baseline [-]", "ours_newton_per_step [-]", "baseline_newton_per_step [-]",
                "ours_over_baseline_per_newton [-]", "floor_over_baseline_per_newton [-]",
                "ours_per_simulated_second [s/s]", "floor_per_simulated_second [s/s]",
                "baseline_per_simulated_second [s/s]"]


def table_rows(rows):
    """Rows of baseline.csv (BASE_COLUMNS) from ratio_case results."""
    return [[r["scene"], r["model"], r["drive"], r["settings"], r["contact"], r["K"], r["ours_step_s"], r["floor_step_s"],
             r["base_step_s"], r["ratio_step"], r["floor_ratio_step"], r["ours_newton_per_step"],
             r["base_newton_per_step"], r["ratio_per_newton"], r["floor_ratio_per_newton"], r["ours_sim_s"],
             r["floor_sim_s"], r["base_sim_s"]] for r in rows]


def print_ratio_table(rows, file=None):
    file = sys.stdout if file is None else file
    print(f"{'scene':6s} {'model':8s} {'drive':24s} {'settings':8s} {'K':>3s} {'ours us/step':>12s} "
          f"{'floor':>8s} {'C++':>8s} {'ours/C++':>9s} {'floor/C++':>10s} {'Newton/step ours':>17s} {'C++':>5s} "
          f"{'ours s/sim s':>12s}", file=file)
    for r in rows:
        print(f"{r['scene']:6s} {r['model']:8s} {r['drive']:24s} {r['settings']:8s} {r['K']:3d} "
              f"{r['ours_step_s'] * 1e6:12.1f} {r['floor_step_s'] * 1e6:8.1f} {r['base_step_s'] * 1e6:8.1f} "
              f"{r['ratio_step']:9.2f} {r['floor_ratio_step']:10.2f} {r['ours_newton_per_step']:17.2f} "
              f"{r['base_newton_per_step']:5.2f} {r['ours_sim_s']:12.4f}", file=file)
