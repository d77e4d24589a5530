"""The speed targets: each scene users run, at the package's settings, against one
yardstick with no Python in it: a rigid cube on as many Exudyn C++ spring-dampers as the scene has
contact points, at Exudyn's default solver settings (``studies/benchmarks.py`` section "Targets";
``python studies/baseline.py --targets`` prints them alone).

The yardstick (``BuildCube``): a free rigid body (cube, ``NodeRigidBodyEP``, the block's mass and
size) on K ``ObjectConnectorCartesianSpringDamper`` to ground at K points of its bottom face, under
gravity and a constant C++ force in the plane, with a fresh ``exu.SimulationSettings()`` (Exudyn's
modified Newton, tolerances, ``SolveDynamic``'s default integrator) and the scene's step and end
time. It is linear and needs one or two Newton iterations per step: what a C++ connector costs.

The scenes (``TARGETS``), as built by the package with its default Newton (``models.block``):
* the full block on its 4 corners (polar adhesion, radial map, the C++ displacement drive: it slides);
* the reduced screw (default 3 x 8 layout, one evaluated point by symmetry, rotation drive);
* the full block on an 8 x 8 grid (64 points, sliding);
* the moving master: the full block on a free plate (1e9 kg, the contact is a moving-master set
  over both bodies), against the same block on a fixed plane (ratio to that, not to the cube).

Every figure is the median over interleaved repeats of the whole solve (rejected steps
included) divided by the nominal number of steps t_end / dt: process CPU time (robust on a shared
machine) and wall time beside it."""
from __future__ import annotations

import math
import time

import exudyn as exu
import numpy as np
from exudyn.itemInterface import SensorNode
from exudyn.utilities import InertiaCuboid

from exu_aniso.models.block import BuildBlock, SolveTimed
from exu_aniso.models.screw import BuildScrew
from exu_aniso.scenes import BlockParams, ScrewParams

from .baseline import _cartesian_springs
from .studylib import median_call_time


def cube_points(K, size):
    """K points of the cube's bottom face: the first K of an n x n grid, n = ceil(sqrt(K))."""
    n = max(2, math.ceil(math.sqrt(K)))
    s = np.linspace(-0.5 * size, 0.5 * size, n)
    X, Y = np.meshgrid(s, s, indexing="xy")
    xy = np.stack([X.ravel(), Y.ravel()], axis=-1)[:K]
    return np.column_stack([xy, np.full(K, -0.5 * size)])


def BuildCube(K, t_end, dt, p=None):
    """The yardstick (module doc): returns dict(mbs, simulationSettings, solverType, SC)."""
    p = p or BlockParams(model="full")
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    a = p.size
    gap = -p.normal_load / p.eps_n
    oCube = mbs.CreateRigidBody(inertia=InertiaCuboid(density=p.mass / a ** 3, sideLengths=[a, a, a]),
                                referencePosition=[p.x0, p.y0, 0.5 * a + gap], gravity=[0.0, 0.0, -9.81],
                                nodeType=exu.NodeType.RotationEulerParameters)
    mbs.CreateForce(itemNumber=oCube, loadVector=[p.force, 0.5 * p.force, -p.normal_load])
    local = cube_points(K, a)
    anchors = np.column_stack([local[:, 0] + p.x0, local[:, 1] + p.y0, np.zeros(K)])
    _cartesian_springs(mbs, oCube, local, anchors, [[p.eps_1 / K, p.eps_1 / K, p.eps_n / K]] * K)
    mbs.AddSensor(SensorNode(nodeNumber=mbs.GetObject(oCube)["nodeNumber"], storeInternal=True,
                             outputVariableType=exu.OutputVariableType.Position))
    mbs.Assemble()
    return dict(SC=SC, mbs=mbs, simulationSettings=exudyn_defaults(t_end, dt),
                solverType=exu.DynamicSolverType.GeneralizedAlpha)


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


def plate_builder(p, speed=0.0, nodeType=exu.NodeType.RotationEulerParameters, implementation="auto",
                  jacobian="analytic"):
    """contactBuilder of BuildBlock: the block's contact on a free plate (a rigid body of 1e9 kg
    without load, moving uniformly at (speed, -speed/2, 0)) instead of the fixed plane: a
    moving-master set over the block's and the plate's coordinates."""
    def build(mbs, oBlock, localPoints):
        from exu_aniso.models.block import block_contact_law
        oPlate = mbs.CreateRigidBody(inertia=InertiaCuboid(1e9 / 0.02, [1.0, 1.0, 0.02]),
                                     referencePosition=[0.0, 0.0, 0.0], initialVelocity=[speed, -0.5 * speed, 0.0],
                                     nodeType=nodeType, gravity=[0.0, 0.0, 0.0])
        return mbs.CreateAnisotropicContact(name="blockContact", bodyNumber=oBlock, localPoints=localPoints,
                                            contactLaw=block_contact_law(p), masterBodyNumber=oPlate,
                                            jacobian=jacobian, initializeHistory=True, implementation=implementation,
                                            show=False, storeHistory=True)   # as the scene's own contact
    return build


def _block(overrides, moving=False):
    def build(t_end, dt):
        p = BlockParams(model="full", t_end=t_end, dt=dt, **overrides)
        return BuildBlock(p, contactBuilder=plate_builder(p) if moving else None)
    return build


def _screw(t_end, dt):
    return BuildScrew(ScrewParams(t_end=t_end, dt=dt))


# (label, build(t_end, dt) of ours, points of the yardstick cube or the label of the row it is
# compared with, target ratio)
TARGETS = [
    ("full block, 4 corners", _block(dict(points="corners")), 4, 4.0),
    ("reduced screw, 3 x 8 points", _screw, 24, 2.0),
    ("full block, 8 x 8 grid", _block(dict(points="grid:8")), 64, 1.0),
    ("moving master (full block, 4 corners, on a free plate)", _block(dict(points="corners"), moving=True),
     "full block, 4 corners", 1.5),
]


def _solve(model):
    c0, w0 = time.process_time(), time.perf_counter()
    _, steps, iters, _ = SolveTimed(model["mbs"], model["simulationSettings"], model["solverType"])
    return time.process_time() - c0, time.perf_counter() - w0, steps, iters


def target_rows(quick=False, repeats=5):
    """Measure TARGETS (module doc); returns one dict per row."""
    t_end, dt = (0.05, 1e-3) if quick else (0.5, 1e-3)
    nominal = int(round(t_end / dt))
    cubes = sorted({K for _, _, K, _ in TARGETS if isinstance(K, int)})
    runs = {label: build for label, build, _, _ in TARGETS}
    runs.update({f"cube, {K} C++ springs": (lambda t, d, K=K: BuildCube(K, t, d)) for K in cubes})
    for build in runs.values():                       # warm-up: kernels compiled or loaded, untimed
        _solve(build(5 * dt, dt))
    times = {label: [] for label in runs}
    for _ in range(repeats):                          # interleaved
        for label, build in runs.items():
            times[label].append(_solve(build(t_end, dt)))
    med = {}
    for label, ts in times.items():
        T = np.array(ts, dtype=float)
        med[label] = dict(cpu_step=float(np.median(T[:, 0])) / nominal, wall_step=float(np.median(T[:, 1])) / nominal,
                          steps=float(np.median(T[:, 2])), newton_per_step=float(np.median(T[:, 3] / T[:, 2])))
    rows = []
    for label, _, ref, target in TARGETS:
        yard = f"cube, {ref} C++ springs" if isinstance(ref, int) else ref
        o, y = med[label], med[yard]
        ratio = o["cpu_step"] / y["cpu_step"]
        rows.append(dict(scene=label, yardstick=yard, ours_us=o["cpu_step"] * 1e6, ours_wall_us=o["wall_step"] * 1e6,
                         yardstick_us=y["cpu_step"] * 1e6, yardstick_wall_us=y["wall_step"] * 1e6,
                         ours_newton=o["newton_per_step"], yardstick_newton=y["newton_per_step"],
                         ours_steps=o["steps"], nominal_steps=nominal, t_end=t_end, ratio=ratio,
                         ratio_wall=o["wall_step"] / y["wall_step"], target=target, met=ratio <= target))
    return rows


TARGET_COLUMNS = ["scene [-]", "yardstick [-]", "ours_per_step [us]", "ours_wall_per_step [us]",
                  "yardstick_per_step [us]", "yardstick_wall_per_step [us]", "ours_newton_per_step [-]",
                  "yardstick_newton_per_step [-]", "ours_steps [-]", "nominal_steps [-]", "ratio [-]",
                  "ratio_wall [-]", "target [-]", "met [-]"]


def target_table_rows(rows):
    return [[r["scene"], r["yardstick"], r["ours_us"], r["ours_wall_us"], r["yardstick_us"], r["yardstick_wall_us"],
             r["ours_newton"], r["yardstick_newton"], r["ours_steps"], r["nominal_steps"], r["ratio"],
             r["ratio_wall"], r["target"], bool(r["met"])] for r in rows]


def print_targets(rows, file=None):
    print(f"{'scene':56s} {'ours us/step':>12s} {'yardstick':>10s} {'ratio':>6s} {'target':>6s}  met  "
          f"(Newton/step ours, yardstick; yardstick)", file=file)
    for r in rows:
        print(f"{r['scene']:56s} {r['ours_us']:12.1f} {r['yardstick_us']:10.1f} {r['ratio']:6.2f} {r['target']:6.1f}  "
              f"{'yes' if r['met'] else 'no ':3s}  ({r['ours_newton']:.2f}, {r['yardstick_newton']:.2f}; "
              f"{r['yardstick']})", file=file)


def markdown(rows, repeats):
    """The targets as a report section (markdown)."""
    from .studylib import markdown_table
    t_end = rows[0]["t_end"]
    return (f"Process CPU time of the whole solve (rejected steps included) per nominal step, median of {repeats} "
            f"interleaved repeats, t_end = {t_end:g} s, dt = 1 ms; ours at the package's settings, the yardstick (a "
            "rigid cube on as many C++ `CartesianSpringDamper`s as the scene has contact points) at Exudyn's "
            "defaults. File: `targets.csv`.\n\n"
            + markdown_table(["scene", "ours us/step", "yardstick us/step", "ratio", "target", "met",
                              "Newton/step ours", "Newton/step yardstick", "yardstick"],
                             [[r["scene"], r["ours_us"], r["yardstick_us"], r["ratio"], r["target"],
                               "yes" if r["met"] else "no", r["ours_newton"], r["yardstick_newton"], r["yardstick"]]
                              for r in rows]))


# ----------------------------------------------------------------------------------------------
# the cost of one force call of a contact set, against the number of points (the kernel's target)

FORCE_CALL_LAYOUTS = ("center", "corners", "grid:4", "grid:8")


def force_call_rows(quick=False, repeats=5):
    """The full block's contact set on 1, 4, 16 and 64 points after 20 steps of sliding: median wall
    time of one force callback as Exudyn calls it (q, q_t as lists) and of the compiled call
    alone (the set's entry point with its packed arguments: unboxing and kernel), over repeats of
    `calls` calls each."""
    from exu_aniso import exudyn_glue
    calls = 200 if quick else 2000
    rows = []
    for points in FORCE_CALL_LAYOUTS:
        model = BuildBlock(BlockParams(model="full", points=points, t_end=0.02))
        _solve(model)
        mbs = model["mbs"]
        cs = mbs.variables[exudyn_glue._SETS_KEY][0]
        q, q_t = list(cs._q), list(cs._q_t)          # the state of the last residual
        t = cs._t

        def callback():
            cs.force_in_place(mbs, t, 0, q, q_t)     # the function Exudyn calls

        def entry():
            cs._entry(*cs._force_args)

        med = {}
        for name, fn in (("callback", callback), ("entry", entry)):
            fn()
            med[name] = median_call_time(fn, repeats, calls)
        K = cs.K
        rows.append(dict(points=points, K=K, in_contact=int(np.sum(cs.pk.Hn[:, 7] > 0)), callback_us=med["callback"] * 1e6,
                         entry_us=med["entry"] * 1e6))
    K = np.array([r["K"] for r in rows], dtype=float)
    b, a = np.polyfit(K, [r["entry_us"] for r in rows], 1)
    for r in rows:
        r.update(entry_fixed_us=float(a), entry_per_point_us=float(b))
    return rows


FORCE_CALL_COLUMNS = ["points [-]", "K [-]", "in_contact [-]", "callback [us]", "entry [us]", "entry_fixed [us]",
                      "entry_per_point [us]"]


def force_call_table_rows(rows):
    return [[r["points"], r["K"], r["in_contact"], r["callback_us"], r["entry_us"], r["entry_fixed_us"],
             r["entry_per_point_us"]] for r in rows]
