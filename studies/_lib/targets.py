"""The speed targets: the scenes users run, at the package's settings, each against a yardstick with
no Python in it (``yardstick``), measured in one run (``python studies/baseline.py --targets``;
section "Speed targets" of ``python studies/benchmarks.py``).

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

What is declared here is timed by ``target_timing`` (how: its module doc) and tabled by
``target_tables``."""
from __future__ import annotations

from collections import namedtuple
from dataclasses import dataclass
from typing import Callable, Optional

from exu_aniso.models.block import BuildBlock
from exu_aniso.models.screw import BuildScrew
from exu_aniso.scenes.block import BlockParams
from exu_aniso.scenes.screw import ScrewParams

from .baseline import empty_contact
from .target_models import BuildUserBody, free_plate, node_of, plate_builder
from .yardstick import BuildCube


# ----------------------------------------------------------------------------------------------
# the models timed, as build(t_end, dt)

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
        nodes = [node_of(mbs, oCube)]
        if plate:
            nodes.append(node_of(mbs, free_plate(mbs)))
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
