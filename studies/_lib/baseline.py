"""C++ baseline: the block and screw scenes with Exudyn's built-in linear spring-dampers in place of
the anisotropic contact, same bodies, drives, sensors, solver and step (issue 5, part 3).

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

The scenes themselves are built by ``BuildBlock`` / ``BuildScrew`` (their ``contactBuilder`` hook
puts the springs where the anisotropic contact would go), so bodies, loads, drives, sensors and
settings are the same items: C++ loads for "force"/"torque", the same Python ``AddNodeDrive`` for
the spring drives. With "force"/"torque" drives the contact is the only Python user function in
our model and the ratio isolates its cost.
"""
from __future__ import annotations

import sys
import time

import numpy as np
from exu_aniso.models.block import SolveTimed
from exudyn.itemInterface import (
    MarkerBodyPosition,
    MarkerNodeCoordinate,
    NodePointGround,
    ObjectConnectorCartesianSpringDamper,
    ObjectConnectorCoordinateSpringDamper,
    ObjectGround,
)

from exu_aniso.scenes import BlockParams, ScrewParams


def _cartesian_springs(mbs, bodyNumber, localPoints, anchors, stiffness):
    """One C++ Cartesian spring-damper per point between the body point and its ground anchor."""
    oGround = mbs.AddObject(ObjectGround())
    springs = []
    for b, g, k in zip(localPoints, anchors, stiffness):
        mBody = mbs.AddMarker(MarkerBodyPosition(bodyNumber=bodyNumber, localPosition=list(map(float, b))))
        mGround = mbs.AddMarker(MarkerBodyPosition(bodyNumber=oGround, localPosition=list(map(float, g))))
        springs.append(mbs.AddObject(ObjectConnectorCartesianSpringDamper(markerNumbers=[mGround, mBody],
                                                                          stiffness=list(k), damping=[0.0] * 3)))
    return dict(springs=springs, points=np.asarray(localPoints))


def BuildBlockBaseline(p: BlockParams, nodeType="EP", solverType=None, rhoInf=0.8, newtonTolerance=1e-10):
    """The block scene of ``BuildBlock`` (same body, loads, drive, sensors, settings) with C++
    Cartesian spring-dampers at the contact points (see module doc). Returns BuildBlock's dict
    plus 'springs'."""
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
        return _cartesian_springs(mbs, oBlock, local, anchors, [k] * K)

    model = BuildBlock(p, nodeType=nodeType, solverType=solverType, rhoInf=rhoInf, newtonTolerance=newtonTolerance,
                       contactBuilder=springs)
    model["springs"] = model["contact"]["springs"]
    return model


def BuildScrewBaseline(p: ScrewParams, nodeType="RotVecLG", solverType=None, rhoInf=0.8, newtonTolerance=1e-10,
                       symmetry=True):
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


# columns of baseline.csv (benchmarks.py and baseline.py)
BASE_COLUMNS = ["scene [-]", "model [-]", "drive [-]", "contact_impl [-]", "K [-]", "ours_per_step [s]", "baseline_per_step [s]",
                "ours_over_baseline [-]", "ours_newton_per_step [-]", "baseline_newton_per_step [-]",
                "ours_over_baseline_per_newton [-]"]


def table_rows(rows):
    """Rows of baseline.csv (BASE_COLUMNS) from ratio_case results."""
    return [[r["scene"], r["model"], r["drive"], r["contact"], r["K"], r["ours_step_s"], r["base_step_s"], r["ratio_step"],
             r["ours_newton_per_step"], r["base_newton_per_step"], r["ratio_per_newton"]] for r in rows]


def print_ratio_table(rows, file=None):
    file = sys.stdout if file is None else file
    print(f"{'scene':6s} {'model':8s} {'drive':24s} {'contact':8s} {'K':>3s} {'ours CPU/step [ms]':>18s} {'C++ CPU/step [ms]':>17s} "
          f"{'ours/C++':>9s} {'Newton/step ours':>17s} {'C++':>5s} {'ratio per Newton it.':>21s}", file=file)
    for r in rows:
        print(f"{r['scene']:6s} {r['model']:8s} {r['drive']:24s} {r['contact']:8s} {r['K']:3d} {r['ours_step_s'] * 1e3:18.3f} {r['base_step_s'] * 1e3:17.3f} "
              f"{r['ratio_step']:9.2f} {r['ours_newton_per_step']:17.2f} {r['base_newton_per_step']:5.2f} "
              f"{r['ratio_per_newton']:21.2f}", file=file)
