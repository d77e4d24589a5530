"""The speed targets: the scenes users run, at the package's settings, each against a yardstick with
no Python in it, measured in one run (``python studies/baseline.py --targets``; section "Speed
targets" of ``python studies/benchmarks.py``).

The yardstick (``BuildCube``): a free rigid cube (``NodeRigidBodyEP``, the block's mass and size) on
K ``ObjectConnectorCartesianSpringDamper``s to ground at K points of its bottom face, as many springs
as the scene has contact points, under gravity and a constant C++ force in the plane, at Exudyn's
default settings (a fresh ``exu.SimulationSettings()``: Exudyn's modified Newton and tolerances,
generalized-alpha) with the scene's step and end time. It is linear: what a C++ connector costs.
For the 64 cubes the yardstick is 64 such cubes, each on its own 4 springs
(``scale.BuildCubes(64, "springs")``, Exudyn's sparse solver).

The targets (``TARGETS``: label, ours, yardstick, target; the ratio is ours / yardstick):
* the full block on its 4 corners (``BuildBlock``: polar adhesion, radial map, C++ displacement
  drive; it slides) against a cube on 4 springs: 3x or less;
* the full block on an 8 x 8 grid against a cube on 64 springs: 0.6x or less;
* 64 cubes on the plane, one contact set each, and the same 64 cubes as one group (one
  ``CreateAnisotropicContact`` with the list of bodies; ``scale.BuildCubes``: 4 corners each, exact
  map, sliding under different forces, normal damping 10% of critical) against 64 C++ cubes with
  the same damping: 3x or less; beside them, the group without the damping against undamped C++
  cubes (its corners chatter: ``scale``'s module doc); and the cost per body flat
  in the number of bodies: per-body cost at 64 cubes over that at 8 cubes (the same contact
  variant), 1.2x or less;
* the reduced screw (default ``ScrewParams``: 3 x 8 points, one evaluated by symmetry, rotation
  drive) against a cube on 24 springs: 1.2x or less;
* the moving master: the full block on its 4 corners on a free plate (``plate_builder``: a
  moving-master set over the block's and the plate's coordinates) against the same block on the
  fixed plane: 1.2x or less; beside it, without a target, the plate alone (the block on the fixed
  plane with the same free plate beside it, in contact with nothing: what Exudyn's dynamics of a
  second body cost before the contact touches it), and with the target the like-for-like
  comparison: the moving master against those same two bodies with the contact on the fixed plane;
* a user's body on a curved surface, built as a user builds it (``BuildUserBody``:
  ``mbs.CreateRigidBody`` + ``mbs.CreateAnisotropicContact(surface=Sphere(...) / Cone(...), ...)``
  with the function's defaults, solved at ``exu_aniso.RecommendedSimulationSettings``): a 1 kg box
  on its 4 bottom corners sliding under gravity inside a spherical bowl and down a conical trough,
  against a cube on 4 springs: 4x or less;
* the compiled call on the plane: one force evaluation of the full block's contact set (the
  ``CompiledSet`` entry with mode 0: unboxing its packed arguments and the kernel, no Exudyn) on
  K = 1, 4, 16, 64, 256 points, fitted as fixed + per-point cost: 0.5 us and 0.05 us or less. Each
  layout's call is timed over a batch of CALLS calls (CALLS_QUICK with --quick) in every repeat and
  the line fitted per repeat (median [min-max] of the repeats' fits).

The floor of a scene (column "floor"): the scene's yardstick model (the same cube(s) on C++
springs at Exudyn's defaults) plus the scene's contact items (one ``ObjectGenericODE2`` per
contact set on the same nodes, the history and dissipation data nodes with the same sensors, the
post-Newton function) whose user functions do nothing (zero force, zero Jacobian, accept the step).
So floor - cube is Exudyn's price of calling Python on the same motion, and ours - floor is what
the contact adds on top: the law, the extra Newton iterations of a sliding contact at the
package's tolerance and, for the scenes of the package, their own items (the block's C++ drive,
its sensors). Where the cube's C++ springs cost more than our contact (64 springs against the 8 x 8
grid's one compiled call), ours - floor is negative.

How it is timed: every model (ours, yardsticks, floors) is built afresh, solved once for 5 steps
untimed (kernels compiled or loaded), then in every repeat all of them are built and solved one
after the other, and the compiled calls timed, in the same order (interleaved repeats). A figure
is the process CPU time of the whole solve (rejected steps included; model building excluded) per
nominal step t_end / dt, per body where the row says so; medians over the repeats with min and
max beside them. A ratio is formed repeat by repeat (ours_i / yardstick_i, measured within
seconds of each other) and reported as the median with min and max of those ratios; a target is
met when the median ratio is at most the target. Process CPU time does not grow when other
processes share the core (wall time is kept beside it in ``targets.csv``)."""
from __future__ import annotations

import math
import time
from collections import namedtuple
from dataclasses import dataclass
from typing import Callable, Optional

import exudyn as exu
import numpy as np
from exudyn.itemInterface import SensorNode
from exudyn.rigidBodyUtilities import RotationMatrixY
from exudyn.utilities import InertiaCuboid

from exu_aniso.models.block import BuildBlock
from exu_aniso.engines.exudyn_adapter.runner import SolveTimed
from exu_aniso.models.screw import BuildScrew
from exu_aniso.scenes.block import BlockParams
from exu_aniso.scenes.screw import ScrewParams

from .baseline import _cartesian_springs, empty_contact, exudyn_defaults
from .studylib import markdown_table

T_END, T_END_QUICK, DT = 0.5, 0.05, 1e-3
WARM_STEPS = 5


# ----------------------------------------------------------------------------------------------
# the yardstick

def cube_points(K, size):
    """K points of the cube's bottom face: the first K of an n x n grid, n = ceil(sqrt(K))."""
    n = max(2, math.ceil(math.sqrt(K)))
    s = np.linspace(-0.5 * size, 0.5 * size, n)
    X, Y = np.meshgrid(s, s, indexing="xy")
    xy = np.stack([X.ravel(), Y.ravel()], axis=-1)[:K]
    return np.column_stack([xy, np.full(K, -0.5 * size)])


def BuildCube(K, t_end, dt, p=None, extra=None):
    """The yardstick (module doc): returns dict(mbs, simulationSettings, solverType, SC, oCube).
    extra(mbs, oCube): adds items before Assemble (the floors)."""
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
    if extra is not None:
        extra(mbs, oCube)
    mbs.Assemble()
    return dict(SC=SC, mbs=mbs, simulationSettings=exudyn_defaults(t_end, dt), oCube=oCube,
                solverType=exu.DynamicSolverType.GeneralizedAlpha)


def _node(mbs, o):
    return mbs.GetObject(o)["nodeNumber"]


# ----------------------------------------------------------------------------------------------
# the scenes

def plate_builder(p, speed=0.0, nodeType=exu.NodeType.RotationEulerParameters, implementation="auto",
                  jacobian="analytic", touching=True):
    """contactBuilder of BuildBlock: the block's contact on a free plate (a rigid body of 1e9 kg
    without load, moving uniformly at (speed, -speed/2, 0)) instead of the fixed plane: a
    moving-master set over the block's and the plate's coordinates. touching False: the block's
    contact stays on the fixed plane and the plate is beside it, in contact with nothing (what the
    plate's own dynamics cost in Exudyn)."""
    def build(mbs, oBlock, localPoints):
        from exu_aniso.scenes.block import block_contact_law
        oPlate = _plate(mbs, speed, nodeType)
        return mbs.CreateAnisotropicContact(name="blockContact", bodyNumber=oBlock, localPoints=localPoints,
                                            contactLaw=block_contact_law(p),
                                            masterBodyNumber=oPlate if touching else None,
                                            jacobian=jacobian, initializeHistory=True,
                                            implementation=implementation, show=False,
                                            storeHistory=True)   # as the scene's own contact
    return build


def _plate(mbs, speed=0.0, nodeType=exu.NodeType.RotationEulerParameters):
    return mbs.CreateRigidBody(inertia=InertiaCuboid(1e9 / 0.02, [1.0, 1.0, 0.02]),
                               referencePosition=[0.0, 0.0, 0.0], initialVelocity=[speed, -0.5 * speed, 0.0],
                               nodeType=nodeType, gravity=[0.0, 0.0, 0.0])


def _block(points, moving=False, spectator=False):
    """The full block on ``points``: on the fixed plane, on the free plate (moving), or on the fixed
    plane with the same free plate beside it in contact with nothing (spectator: what the plate's
    own dynamics cost in Exudyn)."""
    def build(t_end, dt):
        p = BlockParams(model="full", points=points, t_end=t_end, dt=dt)
        if moving or spectator:
            return BuildBlock(p, contactBuilder=plate_builder(p, touching=moving))
        return BuildBlock(p)
    return build


def _screw(t_end, dt):
    return BuildScrew(ScrewParams(t_end=t_end, dt=dt))


def _cubes(M, contact, damped=True):
    def build(t_end, dt):
        from .scale import BuildCubes
        return BuildCubes(M, contact, t_end, dt, damped=damped)
    return build


# the user's body: a box on its 4 bottom corners, values of the README's example (1 kg, 0.1 m)
USER_MASS, USER_SIZE, USER_NORMAL_STIFFNESS = 1.0, 0.1, 2.5e5          # kg, m, N/m per point
USER_ADHESION = (2.5e4, 2.5e3)                                         # N/m per point, along xi1 and xi2
BOWL_RADIUS, BOWL_START = 1.0, math.radians(30.0)                      # m; start 30 deg up the wall
BOWL_FRICTION = (0.3, 0.2)                                             # tan 30 deg = 0.58 > 0.3: it slides
TROUGH_RADIUS, TROUGH_HALF_ANGLE = 0.3, math.radians(20.0)             # m at the start; rad
TROUGH_FRICTION = (0.3, 0.15)                                          # along the trough 0.15 < tan 20 deg


def user_body_pose(surface):
    """(position, rotation matrix, local points, the surface) of the user's box resting on its 4
    bottom corners at the static penetration m g / (4 eps_N):
    "sphere": inside a spherical bowl (Sphere, side "inside", centre 1 m above the origin, its pole
    axis along y so the chart's poles are off the path) at 30 deg from the bottom in the xz-plane;
    "cone": at the bottom of a conical trough (Cone, side "inside", axis along x at 0.3 m height,
    half angle 20 deg: its bottom line descends along +x), face parallel to the bottom line and
    tilted about y so that the four corners press equally (the trough's sagitta differs front to
    back)."""
    from exu_aniso import Cone, Sphere
    h = c = 0.5 * USER_SIZE
    pen = USER_MASS * 9.81 / (4 * USER_NORMAL_STIFFNESS)
    local = np.array([[sx * h, sy * h, -c] for sx in (-1, 1) for sy in (-1, 1)])
    if surface == "sphere":
        R, al = BOWL_RADIUS, BOWL_START
        C = np.array([0.0, 0.0, R])
        n = np.array([math.sin(al), 0.0, -math.cos(al)])             # outward at the start
        d = math.sqrt((R + pen) ** 2 - 2 * h * h)                     # face centre from the centre
        return (C + (d - c) * n, RotationMatrixY(-al), local,
                Sphere(radius=R, center=C.tolist(), axis_direction=[0.0, 1.0, 0.0], side="inside"))
    if surface != "cone":
        raise ValueError(f"surface must be 'sphere' or 'cone'; got {surface!r}")
    R0, ha = TROUGH_RADIUS, TROUGH_HALF_ANGLE
    A0 = np.array([0.0, 0.0, R0])

    def pose(v):
        off, tilt = v
        A = np.asarray(RotationMatrixY(ha + tilt))
        return A @ np.array([0.0, 0.0, 1.0]) * off, A           # face centre at the origin (bottom line)

    def pens(v):
        x0, A = pose(v)
        X = x0 + local @ A.T
        rho = np.hypot(X[:, 1] - A0[1], X[:, 2] - A0[2])
        return (rho - (R0 + (X[:, 0] - A0[0]) * math.tan(ha))) * math.cos(ha)

    def res(v):
        P = pens(v)
        return np.array([np.mean(P) - pen, P[2] - P[0]])

    v = np.array([c, 0.0])
    for _ in range(10):                                              # Newton with a difference Jacobian
        r = res(v)
        J = np.column_stack([(res(v + e) - r) / 1e-8 for e in np.eye(2) * 1e-8])
        v = v - np.linalg.solve(J, r)
    x0, A = pose(v)
    return (x0, A, local, Cone(half_angle=ha, radius=R0, axis_point=A0.tolist(),
                               axis_direction=[1.0, 0.0, 0.0], side="inside"))


def BuildUserBody(surface, t_end, dt):
    """A user's model (module doc): mbs.CreateRigidBody, mbs.CreateAnisotropicContact on the Sphere
    or Cone with orthotropic adhesion and friction and otherwise the function's defaults, solved at
    RecommendedSimulationSettings. Returns dict(mbs, simulationSettings, solverType, contact, SC,
    oBody, sPosition)."""
    import exu_aniso
    from exu_aniso import Adhesion, Friction
    x0, A, local, surf = user_body_pose(surface)
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    a = USER_SIZE
    oBody = mbs.CreateRigidBody(inertia=InertiaCuboid(USER_MASS / a ** 3, [a] * 3),
                                referencePosition=list(x0), referenceRotationMatrix=np.asarray(A),
                                gravity=[0.0, 0.0, -9.81],
                                nodeType=exu.NodeType.RotationEulerParameters)
    mu = BOWL_FRICTION if surface == "sphere" else TROUGH_FRICTION
    contact = mbs.CreateAnisotropicContact(name=f"userBodyOn{type(surf).__name__}", bodyNumber=oBody,
                                           localPoints=local.tolist(), surface=surf,
                                           adhesion=Adhesion.orthotropic(*USER_ADHESION),
                                           friction=Friction.orthotropic(*mu),
                                           normalStiffness=USER_NORMAL_STIFFNESS)
    sPosition = mbs.AddSensor(SensorNode(nodeNumber=_node(mbs, oBody), storeInternal=True,
                                         outputVariableType=exu.OutputVariableType.Position))
    mbs.Assemble()
    ss, solverType = exu_aniso.RecommendedSimulationSettings(t_end, dt)
    return dict(SC=SC, mbs=mbs, simulationSettings=ss, solverType=solverType, contact=contact, oBody=oBody,
                sPosition=sPosition)


def _user(surface):
    return lambda t_end, dt: BuildUserBody(surface, t_end, dt)


# ----------------------------------------------------------------------------------------------
# what is timed, declared

@dataclass(frozen=True)
class Run:
    """A model timed in every repeat: name, build(t_end, dt) -> dict(mbs, simulationSettings,
    solverType), bodies (for per-body figures); for ours: floor (the floor's Run) and cube (the C++
    model the floor is built on)."""
    name: str
    build: Callable
    bodies: int = 1
    floor: Optional["Run"] = None
    cube: Optional["Run"] = None


@dataclass(frozen=True)
class PerBody:
    """Yardstick: another Run, compared per body and step (ours per body over its per body)."""
    run: Run


@dataclass(frozen=True)
class CallFit:
    """Ours of an absolute target: a part of the compiled call's fit ("fixed" [us], "per_point"
    [us per point])."""
    part: str


def cube_run(K):
    return Run(f"cube, {K} C++ springs", lambda t_end, dt: BuildCube(K, t_end, dt))


def cubes_run(M, damped=True):
    return Run(f"{M} cubes, 4 C++ springs each" + ("" if damped else ", undamped"), _cubes(M, "springs", damped),
               bodies=M)


def floor_run(K, storeHistory, points, plate=False):
    """The floor of a single-body scene: the cube on K springs plus one empty contact set of
    ``points`` points on its node (plate: and on a free plate's node, a moving-master set)."""
    def extra(mbs, oCube):
        nodes = [_node(mbs, oCube)]
        if plate:
            nodes.append(_node(mbs, _plate(mbs)))
        empty_contact(mbs, nodes, points, storeHistory)
    what = (f"{points} points" + (", history sensor" if storeHistory else "")
            + (", on a free plate" if plate else ""))
    return Run(f"floor: cube, {K} C++ springs + empty contact ({what})",
               lambda t_end, dt: BuildCube(K, t_end, dt, extra=extra))


def cubes_floor_run(M, contact):
    """The floor of M cubes: the C++ cubes plus one empty set per cube ("sets") or one empty group."""
    def build(t_end, dt):
        from .scale import BuildCubes
        return BuildCubes(M, "springs", t_end, dt, floor=contact)
    return Run(f"floor: {M} cubes, 4 C++ springs each + empty contact ({contact})", build, bodies=M)


CUBE4, CUBE24, CUBE64, CUBES64 = cube_run(4), cube_run(24), cube_run(64), cubes_run(64)
BLOCK4 = Run("full block, 4 corners", _block("corners"), floor=floor_run(4, True, 4), cube=CUBE4)
GRID8 = Run("full block, 8 x 8 grid", _block("grid:8"), floor=floor_run(64, True, 64), cube=CUBE64)
SETS = {M: Run(f"{M} cubes, one contact set each", _cubes(M, "sets"), bodies=M,
               floor=cubes_floor_run(M, "sets") if M == 64 else None, cube=CUBES64 if M == 64 else None)
        for M in (8, 64)}
GROUP = {M: Run(f"{M} cubes, one group", _cubes(M, "group"), bodies=M,
                floor=cubes_floor_run(M, "group") if M == 64 else None, cube=CUBES64 if M == 64 else None)
         for M in (8, 64)}
GROUP64_UNDAMPED = Run("64 cubes, one group, undamped", _cubes(64, "group", damped=False), bodies=64)
CUBES64_UNDAMPED = cubes_run(64, damped=False)
SCREW = Run("reduced screw (default ScrewParams)", _screw, floor=floor_run(24, True, 1), cube=CUBE24)
MOVING = Run("moving master (full block, 4 corners, on a free plate)", _block("corners", moving=True),
             floor=floor_run(4, True, 4, plate=True), cube=CUBE4)
BESIDE_PLATE = Run("full block, 4 corners, the free plate beside it (in contact with nothing)",
                   _block("corners", spectator=True))
USER_FLOOR = floor_run(4, False, 4)
SPHERE = Run("user's 4-point body in a spherical bowl (Sphere)", _user("sphere"), floor=USER_FLOOR,
             cube=CUBE4)
CONE = Run("user's 4-point body down a conical trough (Cone)", _user("cone"), floor=USER_FLOOR, cube=CUBE4)

# The targets, in table order: (label, ours: a Run or a CallFit, yardstick: a Run, PerBody(Run) or
# None for an absolute target in us, target: ratio, us for an absolute target, or None for a row
# that explains another (no target: "met" is "-"))
Target = namedtuple("Target", "label build yardstick target")
TARGETS = [
    Target("full block, 4 corners", BLOCK4, CUBE4, 3.0),
    Target("full block, 8 x 8 grid", GRID8, CUBE64, 0.6),
    Target("64 cubes, one contact set each", SETS[64], CUBES64, 3.0),
    Target("64 cubes, one group", GROUP[64], CUBES64, 3.0),
    Target("64 cubes, one group, undamped (the corners chatter)", GROUP64_UNDAMPED, CUBES64_UNDAMPED, 3.0),
    Target("one contact set each: per body, 64 / 8 cubes", SETS[64], PerBody(SETS[8]), 1.2),
    Target("one group: per body, 64 / 8 cubes", GROUP[64], PerBody(GROUP[8]), 1.2),
    Target("reduced screw (default ScrewParams)", SCREW, CUBE24, 1.2),
    Target("moving master (full block, 4 corners, on a free plate)", MOVING, BLOCK4, 1.2),
    Target("the moving master's plate alone: the fixed-plane block with the free plate beside it", BESIDE_PLATE,
           BLOCK4, None),
    Target("moving master against the same two bodies with the contact on the fixed plane", MOVING, BESIDE_PLATE,
           1.2),
    Target("user's 4-point body in a spherical bowl (Sphere)", SPHERE, CUBE4, 4.0),
    Target("user's 4-point body down a conical trough (Cone)", CONE, CUBE4, 4.0),
    Target("compiled call on the plane, as Exudyn makes it: fixed part [us]", CallFit("fixed"), None, 0.5),
    Target("compiled call on the plane, as Exudyn makes it: per point [us]", CallFit("per_point"), None, 0.05),
]

# the compiled call: the full block's contact set on K points
CALL_LAYOUTS = ("center", "corners", "grid:4", "grid:8", "grid:16")      # K = 1, 4, 16, 64, 256
CALLS, CALLS_QUICK = 2000, 200                                           # calls per timed batch


def runs_of(targets):
    """Every Run the targets need (ours, yardsticks, floors and their cubes), each once, in order."""
    out = {}
    for t in targets:
        if isinstance(t.build, CallFit):
            continue
        y = t.yardstick.run if isinstance(t.yardstick, PerBody) else t.yardstick
        for r in (t.build, y, t.build.floor, t.build.cube):
            if r is not None:
                out.setdefault(r.name, r)
    return list(out.values())


# ----------------------------------------------------------------------------------------------
# measuring

def _solve(model):
    c0, w0 = time.process_time(), time.perf_counter()
    _, steps, iters, _ = SolveTimed(model["mbs"], model["simulationSettings"], model["solverType"])
    return time.process_time() - c0, time.perf_counter() - w0, steps, iters


class CallBench:
    """The compiled call of the full block's contact set on each layout of CALL_LAYOUTS, after 20
    steps of sliding: ``time()`` gives, per layout, the CPU time of one force callback as Exudyn calls
    it in Python (q, q_t as lists), of the compiled entry alone with the force's packed arguments
    (mode 0), and of the native force callback (the package's default: Exudyn calls a C++ function
    that calls the compiled kernel, ``_native.call_force`` calling it as Exudyn does), each over a
    batch of ``calls`` calls; NaN for the native call where the extension is not built."""

    def __init__(self, calls, layouts=CALL_LAYOUTS):
        from exu_aniso.engines.exudyn_adapter import commit, contact_set
        self.calls, self.items = calls, []
        for points in layouts:
            model = BuildBlock(BlockParams(model="full", points=points, t_end=0.02))
            _solve(model)
            mbs = model["mbs"]
            cs = mbs.variables[commit.SETS_KEY][0]
            if not isinstance(cs, contact_set.CompiledSet) or getattr(cs, "_force_args", None) is None:
                raise RuntimeError(f"CallBench: the block's contact set on {points!r} is not a compiled set "
                                   "with packed force arguments (contact_set.CompiledSet._force_args)")
            # the state of the last residual: the solve's end (Exudyn's Current coordinates); the native
            # callbacks leave the set's Python clock (cs._t) at the solve's first call
            ti = model["simulationSettings"].timeIntegration
            q, q_t, t = list(cs._q), list(cs._q_t), float(ti.endTime)

            def callback(cs=cs, mbs=mbs, t=t, q=q, q_t=q_t):
                cs.force_in_place(mbs, t, 0, q, q_t)                # the function Exudyn calls

            def entry(cs=cs):
                cs._entry(*cs._force_args)                          # mode 0: the force, unboxing + kernel

            def native_call(calls, cs=cs, mbs=mbs, t=t, q=q, q_t=q_t):
                from exu_aniso.engines.exudyn_adapter import _native
                clock = cs._native.clock                            # armed in the step of the last residual
                saved = clock.copy()
                clock[:2] = (t - cs._dt, 1.0)
                _native.call_force(mbs, cs.oContact, t, q, q_t, calls)
                clock[:] = saved

            native = native_call if cs._native is not None else None
            callback()                                              # loads the history of the step at t
            entry()
            assert cs._force_args[0] == 0 and cs._t == t
            if native is not None:
                before = cs.native_calls()
                native(1)
                if cs.native_calls()[0] != before[0] + 1:
                    raise RuntimeError(f"CallBench: the native force call on {points!r} went to Python")
            self.items.append(dict(points=points, K=cs.K, in_contact=int(np.sum(cs.pk.Hn[:, 7] > 0)),
                                   callback=callback, entry=entry, native=native, model=model))

    def time(self):
        """One repeat: {points: (callback_s, entry_s, native_s)} per call, CPU time."""
        out = {}
        for it in self.items:
            res = []
            for fn in (it["callback"], it["entry"]):
                c0 = time.process_time()
                for _ in range(self.calls):
                    fn()
                res.append((time.process_time() - c0) / self.calls)
            if it["native"] is None:
                res.append(float("nan"))
            else:
                c0 = time.process_time()
                it["native"](self.calls)
                res.append((time.process_time() - c0) / self.calls)
            out[it["points"]] = tuple(res)
        return out


def _stats(x):
    x = np.asarray(x, dtype=float)
    return float(np.median(x)), float(np.min(x)), float(np.max(x))


Results = namedtuple("Results", "rows calls t_end repeats")


def measure(quick=False, repeats=5, targets=None, t_end=None, calls=None, layouts=CALL_LAYOUTS):
    """Measure the targets (module doc); returns Results(rows: one dict per target, calls: one dict
    per call layout, t_end, repeats). t_end, calls and layouts override the defaults (tests)."""
    targets = TARGETS if targets is None else targets
    t_end = t_end if t_end is not None else (T_END_QUICK if quick else T_END)
    dt = DT
    nominal = int(round(t_end / dt))
    runs = runs_of(targets)
    want_calls = any(isinstance(t.build, CallFit) for t in targets)
    for r in runs:                                     # warm-up: kernels compiled or loaded, untimed
        _solve(r.build(WARM_STEPS * dt, dt))
    bench = CallBench(calls or (CALLS_QUICK if quick else CALLS), layouts) if want_calls else None
    times = {r.name: [] for r in runs}
    call_times = []
    for _ in range(repeats):                           # interleaved: every model once per repeat
        for r in runs:
            model = r.build(t_end, dt)
            times[r.name].append(_solve(model))
            del model
        if bench is not None:
            call_times.append(bench.time())
    # (repeats, 4): cpu, wall, steps, Newton iterations
    T = {name: np.array(ts, dtype=float) for name, ts in times.items()}
    calls_rows, fits = _call_rows(bench, call_times) if bench is not None else ([], None)
    rows = [_row(t, T, nominal, t_end, repeats, fits) for t in targets]
    return Results(rows, calls_rows, t_end, repeats)


def _call_rows(bench, call_times):
    """Per layout: callback, entry and native medians [min, max] [us]; per repeat a least-squares fit
    of the entry's and of the native call's time over K: fixed + per-point cost. The targets take the
    native call's fit (the call Exudyn makes at the package's default), the entry's without the
    extension."""
    K = np.array([it["K"] for it in bench.items], dtype=float)

    def fit(col):
        out = []
        for rep in call_times:
            y = np.array([rep[it["points"]][col] for it in bench.items]) * 1e6
            b, a = np.polyfit(K, y, 1) if len(K) > 1 and np.all(np.isfinite(y)) else (float("nan"), y[0])
            out.append((a, b))
        return np.array(out, dtype=float)

    fits = {"entry": fit(1), "native": fit(2)}
    rows = []
    for it in bench.items:
        r = dict(points=it["points"], K=it["K"], in_contact=it["in_contact"])
        for col, name in enumerate(("callback", "entry", "native")):
            m, lo, hi = _stats([rep[it["points"]][col] * 1e6 for rep in call_times])
            r.update({f"{name}_us": m, f"{name}_min_us": lo, f"{name}_max_us": hi})
        rows.append(r)
    for name, f in fits.items():
        fixed, per_point = _stats(f[:, 0]), _stats(f[:, 1])
        for r in rows:
            r.update({f"{name}_fixed_us": fixed[0], f"{name}_fixed_min_us": fixed[1],
                      f"{name}_fixed_max_us": fixed[2], f"{name}_per_point_us": per_point[0],
                      f"{name}_per_point_min_us": per_point[1], f"{name}_per_point_max_us": per_point[2]})
    use = fits["native"] if np.all(np.isfinite(fits["native"])) else fits["entry"]
    return rows, dict(fixed=use[:, 0], per_point=use[:, 1])


def _met(value, target):
    """value <= target; None for a row without a target."""
    return None if math.isnan(target) else bool(value <= target)


def _row(t, T, nominal, t_end, repeats, fits):
    nan = float("nan")
    target = nan if t.target is None else float(t.target)
    row = dict(scene=t.label, target=target, t_end=t_end, nominal_steps=nominal, repeats=repeats)
    if isinstance(t.build, CallFit):
        v = fits[t.build.part]
        m, lo, hi = _stats(v)
        row.update(kind="absolute", unit="us/call" if t.build.part == "fixed" else "us/point",
                   yardstick="none", ours_us=m, ours_min_us=lo, ours_max_us=hi, met=_met(m, target))
        for k in ("yardstick_us", "yardstick_min_us", "yardstick_max_us", "ratio", "ratio_min", "ratio_max",
                  "ours_newton", "yardstick_newton", "floor_us", "floor_min_us", "floor_max_us",
                  "floor_newton", "cube_us", "ours_minus_floor_us", "floor_minus_cube_us", "ours_wall_us",
                  "yardstick_wall_us", "ratio_wall", "ours_steps"):
            row[k] = nan
        row.update(floor="", cube="")
        return row
    per_body = isinstance(t.yardstick, PerBody)
    y = t.yardstick.run if per_body else t.yardstick
    o = t.build

    def per(run, col=0):                     # per nominal step (and body), per repeat [us]
        return T[run.name][:, col] / nominal / (run.bodies if per_body else 1) * 1e6

    def newton(run):
        return float(np.median(T[run.name][:, 3] / T[run.name][:, 2]))

    ours, yard = per(o), per(y)
    ratio = ours / yard
    (om, o0, o1), (ym, y0, y1), (rm, r0, r1) = _stats(ours), _stats(yard), _stats(ratio)
    row.update(kind="ratio", unit="us/body/step" if per_body else "us/step", yardstick=y.name,
               ours_us=om, ours_min_us=o0, ours_max_us=o1, yardstick_us=ym, yardstick_min_us=y0,
               yardstick_max_us=y1, ratio=rm, ratio_min=r0, ratio_max=r1, met=_met(rm, target),
               ours_newton=newton(o), yardstick_newton=newton(y),
               ours_wall_us=float(np.median(per(o, 1))), yardstick_wall_us=float(np.median(per(y, 1))),
               ratio_wall=float(np.median(per(o, 1) / per(y, 1))),
               ours_steps=float(np.median(T[o.name][:, 2])))
    if o.floor is not None:
        f, c = per(o.floor), per(o.cube)
        fm, f0, f1 = _stats(f)
        row.update(floor=o.floor.name, cube=o.cube.name, floor_us=fm, floor_min_us=f0, floor_max_us=f1,
                   floor_newton=newton(o.floor), cube_us=float(np.median(c)),
                   ours_minus_floor_us=float(np.median(ours - f)),
                   floor_minus_cube_us=float(np.median(f - c)))
    else:
        row.update(floor="", cube="", floor_us=nan, floor_min_us=nan, floor_max_us=nan, floor_newton=nan,
                   cube_us=nan, ours_minus_floor_us=nan, floor_minus_cube_us=nan)
    return row


# ----------------------------------------------------------------------------------------------
# tables

TARGET_COLUMNS = [
    "scene [-]", "kind [-]", "unit [-]", "yardstick [-]", "ours [us]", "ours_min [us]", "ours_max [us]",
    "yardstick_per_step [us]", "yardstick_min [us]", "yardstick_max [us]", "ratio [-]", "ratio_min [-]",
    "ratio_max [-]", "target [-]", "met [-]", "ours_newton_per_step [-]", "yardstick_newton_per_step [-]",
    "floor [us]", "floor_min [us]", "floor_max [us]", "floor_newton_per_step [-]", "cube [us]",
    "ours_minus_floor [us]", "floor_minus_cube [us]", "ours_wall [us]", "yardstick_wall [us]",
    "ratio_wall [-]", "ours_steps [-]", "nominal_steps [-]", "t_end [s]", "repeats [-]", "floor_model [-]",
    "cube_model [-]"]

_KEYS = ["scene", "kind", "unit", "yardstick", "ours_us", "ours_min_us", "ours_max_us", "yardstick_us",
         "yardstick_min_us", "yardstick_max_us", "ratio", "ratio_min", "ratio_max", "target", "met",
         "ours_newton", "yardstick_newton", "floor_us", "floor_min_us", "floor_max_us", "floor_newton",
         "cube_us", "ours_minus_floor_us", "floor_minus_cube_us", "ours_wall_us", "yardstick_wall_us",
         "ratio_wall", "ours_steps", "nominal_steps", "t_end", "repeats", "floor", "cube"]


def target_table_rows(rows):
    return [[r[k] for k in _KEYS] for r in rows]


def _spread(m, lo, hi, fmt="{:.1f}"):
    if not np.isfinite(m):
        return "-"
    return f"{fmt.format(m)} [{fmt.format(lo)}-{fmt.format(hi)}]"


HEAD = ["scene", "ours us median [min-max]", "yardstick", "yardstick us median [min-max]",
        "ratio median [min-max]", "target", "met", "Newton/step ours, yardstick", "floor us median [min-max]",
        "ours - floor us", "floor - cube us"]


def _cells(r):
    """Display cells of one row (HEAD)."""
    met = "-" if r["met"] is None else "yes" if r["met"] else "**no**"
    if r["kind"] == "absolute":
        return [r["scene"], _spread(r["ours_us"], r["ours_min_us"], r["ours_max_us"], "{:.3f}"),
                "none (absolute)", "-", "-", f"{r['target']:g} us", met, "-", "-", "-", "-"]
    floor = np.isfinite(r["floor_us"])
    return [r["scene"], _spread(r["ours_us"], r["ours_min_us"], r["ours_max_us"]), r["yardstick"],
            _spread(r["yardstick_us"], r["yardstick_min_us"], r["yardstick_max_us"]),
            _spread(r["ratio"], r["ratio_min"], r["ratio_max"], "{:.2f}"),
            "-" if math.isnan(r["target"]) else f"{r['target']:g}x", met,
            f"{r['ours_newton']:.2f}, {r['yardstick_newton']:.2f}",
            _spread(r["floor_us"], r["floor_min_us"], r["floor_max_us"]) if floor else "-",
            f"{r['ours_minus_floor_us']:.1f}" if floor else "-",
            f"{r['floor_minus_cube_us']:.1f}" if floor else "-"]


def print_targets(rows, file=None):
    """The table (HEAD) as aligned text."""
    cells = [[c.replace("**", "") for c in _cells(r)] for r in rows]
    width = [max(len(h), *(len(c[j]) for c in cells)) for j, h in enumerate(HEAD)]
    for line in [HEAD] + cells:
        print("  ".join(c.ljust(w) for c, w in zip(line, width)).rstrip(), file=file)


def markdown(res):
    """The targets as a report section (markdown)."""
    rows, calls = res.rows, res.calls
    text = (f"Process CPU time of the whole solve (rejected steps included) per nominal step (per body "
            f"and step where the row says so): median [min-max] of {res.repeats} interleaved repeats, "
            f"t_end = {res.t_end:g} s, dt = 1 ms. Ours at the package's settings; the yardstick (a rigid "
            "cube on as many C++ `CartesianSpringDamper`s as the scene has contact points; 64 such cubes "
            "for the 64 cubes; for the moving master the block on the fixed plane, or with its plate beside it where "
            "the row says so; for the per-body rows the "
            "same contact at 8 cubes) at Exudyn's defaults; ratio = ours / yardstick formed repeat by "
            "repeat, median [min-max]; met: median ratio <= target. Floor: the yardstick's C++ model plus "
            "the scene's contact items with user functions that do nothing (ours - floor: what the contact "
            "adds; floor - cube: Exudyn's price of calling Python). Files: `targets.csv`, "
            "`force_call.csv`.\n\n"
            + markdown_table(HEAD, [_cells(r) for r in rows]))
    if calls:
        c = calls[0]
        fixed = _spread(c["entry_fixed_us"], c["entry_fixed_min_us"], c["entry_fixed_max_us"], "{:.3f}")
        slope = _spread(c["entry_per_point_us"], c["entry_per_point_min_us"], c["entry_per_point_max_us"],
                        "{:.4f}")
        nfixed = _spread(c["native_fixed_us"], c["native_fixed_min_us"], c["native_fixed_max_us"], "{:.3f}")
        nslope = _spread(c["native_per_point_us"], c["native_per_point_min_us"], c["native_per_point_max_us"],
                         "{:.4f}")
        text += ("\nThe compiled call on the plane (the full block's contact set after 20 steps of sliding): "
                 "CPU time of one force callback as Exudyn calls it in Python (q, q_t as lists), of the "
                 "compiled entry called from Python (mode 0: unboxing its packed arguments and the kernel), "
                 "and of the native force callback as Exudyn calls it (the package's default: a C++ function "
                 "that calls the compiled kernel on its stored arguments; the targets' rows), median "
                 "[min-max] over the repeats, each a batch of calls; least-squares fit per repeat: native = "
                 f"{nfixed} us + {nslope} us per point; entry from Python = {fixed} us + {slope} us per "
                 "point.\n\n"
                 + markdown_table(["points", "K", "in contact", "Python callback us", "entry from Python us",
                                   "native call us"],
                                  [[r["points"], r["K"], r["in_contact"]]
                                   + [_spread(r[f"{n}_us"], r[f"{n}_min_us"], r[f"{n}_max_us"], "{:.3f}")
                                      for n in ("callback", "entry", "native")]
                                   for r in calls]))
    return text


_CALL_FIELDS = ["callback", "callback_min", "callback_max", "entry", "entry_min", "entry_max", "entry_fixed",
                "entry_fixed_min", "entry_fixed_max", "entry_per_point", "entry_per_point_min",
                "entry_per_point_max", "native", "native_min", "native_max", "native_fixed", "native_fixed_min",
                "native_fixed_max", "native_per_point", "native_per_point_min", "native_per_point_max"]
FORCE_CALL_COLUMNS = ["points [-]", "K [-]", "in_contact [-]"] + [f"{f} [us]" for f in _CALL_FIELDS]


def force_call_table_rows(rows):
    return [[r["points"], r["K"], r["in_contact"]] + [r[f + "_us"] for f in _CALL_FIELDS] for r in rows]
