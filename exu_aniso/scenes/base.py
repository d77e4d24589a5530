"""Scene parameter sets shared by every engine (numpy reference, Exudyn glue, CLI).

Two scenes of the papers:

* ``BlockParams``: a rigid cube on the plane z = 0 with (polar) orthotropic adhesion and friction
  about the origin, pressed down by ``normal_load`` and driven in the xy-plane;
* ``ScrewParams``: a rigid cylindrical screw in a hole (cylinder of radius ``radius``, axis z,
  contact on its inside) with a spiral (thread-like) net, pressed by an interference fit.

Conventions (they hold for every engine that uses these parameters)
-------------------------------------------------------------------
* Units SI; angles in these parameter sets are in DEGREES (``drive_angle``, ``adhesion_angle``,
  ``friction_angle``, ``helix_angle``); rates in rad/s.
* ``eps_n``, ``eps_1``, ``eps_2`` are TOTAL stiffnesses of the contact set [N/m]: they are split
  equally over the K contact points (``eps / K`` per point), so refining the point layout keeps the
  overall stiffness of the contact. ``normal_damping`` and ``tangential_damping`` [N s/m] are
  TOTAL dashpot constants split the same way. Friction coefficients are not split.
* Field indices: polar -> 1 = radial (e_r), 2 = circumferential (e_phi); cartesian -> 1 along the
  field angle (``adhesion_angle`` / ``friction_angle`` from e_x towards e_y), 2 across;
  spiral -> 1 along the helix (e1 = cos(alpha) e_phi + sin(alpha) e_z), 2 across it;
  isotropic -> only ``eps_1`` / ``mu_1`` are used.
* Polar fields are regularised inside ``core_radius`` (see ``exu_aniso.fields.tensor_fields``): relative
  deviation ~ (core_radius / r)^2, finite at the origin.
* Block normal load: ``normal_load`` [N] is the whole downward load. In the planar model the
  contact points are held at the penetration that carries it equally
  (gap = -normal_load / eps_n); in the full 6-DOF model it is a constant vertical force at the
  centre of mass and gravity is NOT applied separately (set normal_load = mass * g for a block
  resting under its weight; that is the default).
* Screw: the hole has radius ``radius``; the contact points sit on a cylinder of radius
  ``radius + interference`` in the screw, so the interference is the normal penetration and
  ``eps_n * interference`` is the total normal force. Positive rotation is about +z; with
  helix_angle > 0 a rotation about +z advances along +z (pitch 2 pi R tan(alpha)).
  ``axial_load`` acts along +z in every drive; gravity is off.
* ``drive_stiffness`` is N/m for translational drives (block "displacement", screw "axial") and
  N m/rad for the screw "rotation" drive.

Each field has a default, a unit, a one-line description and a rule (``BLOCK_PARAMS``,
``SCREW_PARAMS``: name -> (default, unit, description, allowed)). ``from_strings`` parses
strings (numbers, or simple expressions with ``pi``, e.g. ``"2*pi"``) and ``with_overrides``
returns a validated copy; both raise ValueError naming the parameter, the rule and the value.
"""
from __future__ import annotations

import ast
import dataclasses
import math
import operator
import os
import re
from dataclasses import dataclass

import numpy as np

from exu_aniso.engines import energy
from exu_aniso.engines.timing import step_count, time_grid, time_step  # noqa: F401  (every scene's grid)
from exu_aniso.kernel.contact_law import ContactLaw
from exu_aniso.fields.tensor_fields import Adhesion, Friction
from exu_aniso.law.return_maps import RETURN_MAPS
from exu_aniso.geometry import Cone, Cylinder, Plane

SOLVERS = ("trapezoidal", "generalized_alpha")

# Default normal damping of the screw [N s/m, total]. The full screw's lateral contact mode (k_lat
# = eps_n / 2 = 5e6 N/m for a ring of points, m = 0.01 kg, 3.6 kHz; critical 2 sqrt(k_lat m) = 447
# N s/m, the dashpots act laterally with d / 2) flutters under friction. Resolved in time (dt <=
# 1e-4) it grows at 95 1/s with 100 N s/m and not at all with 200; at the default dt = 1e-3 the
# trapezoidal rule under-resolves it and growth is slower but still ruins a 2 s run without
# damping (studies/hard_cases.py, stability table). 300 N s/m is 34 % of critical. The reduced
# screw's points move along the hole wall (n . v = 0), so the damping does not act there, and the
# centred full screw then equals the reduced one.
SCREW_NORMAL_DAMPING = 300.0
POSITION_LIMIT = 1e6     # block: |x0|, |y0| <= POSITION_LIMIT * size

# rules: "real", "> 0", ">= 0", "int >= 1", "(-90, 90)", "(-45, 45)", "points" or a tuple of choices
_POINTS_RULE = "'center' | 'corners' | 'grid:N' (N >= 2)"

BLOCK_PARAMS = {
    "mass": (1.0, "kg", "mass of the block", "> 0"),
    "size": (0.1, "m", "edge length of the cube", "> 0"),
    "x0": (0.5, "m", "initial x of the centre (polar origin at x = y = 0); |x0| <= 1e6 size", "real"),
    "y0": (0.0, "m", "initial y of the centre; |y0| <= 1e6 size", "real"),
    "points": ("corners", "-", "contact points on the bottom face: one centre point, 4 corners or an "
               "N x N grid including the edges", _POINTS_RULE),
    "normal_load": (9.81, "N", "total downward load (planar: carried by the held penetration; full: "
                    "vertical force at the COM, no separate gravity)", ">= 0"),
    "eps_n": (1e6, "N/m", "total normal penalty stiffness, split equally over the K points", "> 0"),
    "adhesion": ("polar", "-", "adhesion (sticking stiffness) field B", ("isotropic", "cartesian", "polar")),
    "eps_1": (1e5, "N/m", "total tangential stiffness along e1 (polar: radial; isotropic: both)", "> 0"),
    "eps_2": (1e3, "N/m", "total tangential stiffness along e2 (polar: circumferential)", "> 0"),
    "adhesion_angle": (0.0, "deg", "angle of e1 from e_x for cartesian adhesion", "real"),
    "friction": ("polar", "-", "friction field F", ("isotropic", "cartesian", "polar")),
    "mu_1": (0.3, "-", "friction coefficient along e1 (polar: radial; isotropic: both)", "> 0"),
    "mu_2": (0.3, "-", "friction coefficient along e2 (polar: circumferential)", "> 0"),
    "friction_angle": (0.0, "deg", "angle of e1 from e_x for cartesian friction", "real"),
    "return_map": ("radial", "-", "sliding return map", RETURN_MAPS),
    "drive": ("displacement", "-", "constant force at the COM, or a spring along the drive direction "
              "from a driver moving at drive_speed", ("force", "displacement")),
    "drive_angle": (90.0, "deg", "drive direction in the xy-plane, from e_x", "real"),
    "force": (5.0, "N", "magnitude of the constant drive force (drive = 'force')", ">= 0"),
    "drive_speed": (0.1, "m/s", "speed of the driver point (drive = 'displacement')", "real"),
    "drive_stiffness": (1e3, "N/m", "stiffness of the drive spring, acting along the drive direction only",
                        "> 0"),
    "t_end": (2.0, "s", "simulated time", "> 0"),
    "dt": (1e-3, "s", "time step", "> 0"),
    "model": ("planar", "-", "planar (x, y, theta; held normal load) or full 6-DOF rigid body",
              ("planar", "full")),
    "solver": ("trapezoidal", "-", "time integrator", SOLVERS),
    "core_radius": (1e-3, "m", "regularisation radius of polar fields at the origin", ">= 0"),
    "normal_damping": (0.0, "N s/m", "total normal contact damping (dashpot on the gap rate), split equally over "
                       "the K points", ">= 0"),
    "tangential_damping": (0.0, "N s/m", "total tangential dashpot parallel to friction while loaded, split equally "
                           "over the K points", ">= 0"),
}

SCREW_PARAMS = {
    "radius": (0.005, "m", "radius of the hole (the screw is radius + interference)", "> 0"),
    "length": (0.02, "m", "length of the contact zone of the screw", "> 0"),
    "mass": (0.01, "kg", "mass of the screw (solid cylinder inertia)", "> 0"),
    "interference": (1e-5, "m", "interference fit: screw radius minus hole radius (normal penetration)",
                     ">= 0"),
    "helix_angle": (10.0, "deg", "helix angle alpha of the spiral net (pitch 2 pi R tan(alpha))",
                    "(-90, 90)"),
    "eps_n": (1e7, "N/m", "total normal penalty stiffness, split equally over the K points", "> 0"),
    "adhesion": ("spiral", "-", "adhesion (sticking stiffness) field B", ("isotropic", "spiral")),
    "eps_1": (1e4, "N/m", "total tangential stiffness along the helix (isotropic: both)", "> 0"),
    "eps_2": (1e6, "N/m", "total tangential stiffness across the helix", "> 0"),
    "friction": ("spiral", "-", "friction field F", ("isotropic", "spiral")),
    "mu_1": (0.2, "-", "friction coefficient along the helix (isotropic: both)", "> 0"),
    "mu_2": (0.6, "-", "friction coefficient across the helix", "> 0"),
    "return_map": ("radial", "-", "sliding return map", RETURN_MAPS),
    "drive": ("rotation", "-", "constant torque, torsional spring to a rotating driver, or axial spring "
              "to a translating driver", ("torque", "rotation", "axial")),
    "torque": (0.05, "N m", "constant drive torque about +z (drive = 'torque')", "real"),
    "rotation_speed": (2.0 * math.pi, "rad/s", "angular speed of the driver (drive = 'rotation')", "real"),
    "axial_speed": (0.01, "m/s", "speed of the axial driver (drive = 'axial')", "real"),
    "drive_stiffness": (1.0, "N m/rad | N/m", "drive spring stiffness (rotation: N m/rad; axial: N/m)", "> 0"),
    "axial_load": (0.0, "N", "constant axial force along +z (all drives)", "real"),
    "rings": (3, "-", "rings of contact points along the length (the reduced model on the cylinder evaluates "
              "one point carrying the totals: by symmetry every layout gives the same result)", "int >= 1"),
    "points_per_ring": (8, "-", "contact points per ring, equally spaced in angle (reduced model: one per ring, "
                        "exact by symmetry)", "int >= 1"),
    "t_end": (1.0, "s", "simulated time", "> 0"),
    "dt": (1e-3, "s", "time step", "> 0"),
    "model": ("reduced", "-", "reduced (rotation angle, axial position) or full 6-DOF rigid body",
              ("reduced", "full")),
    "solver": ("trapezoidal", "-", "time integrator", SOLVERS),
    "normal_damping": (SCREW_NORMAL_DAMPING, "N s/m", "total normal contact damping (dashpot on the gap rate), split "
                       "equally over the K points; the default damps the full screw's lateral mode (README)", ">= 0"),
    "tangential_damping": (0.0, "N s/m", "total tangential dashpot parallel to friction while loaded, split equally "
                           "over the K points", ">= 0"),
    "surface": ("cylinder", "-", "thread surface: cylinder (the papers' hole) or cone (a tapered thread: the hole "
                "r(z) = radius + z tan(half_angle), the screw's points on the parallel cone)", ("cylinder", "cone")),
    "half_angle": (0.0, "deg", "half angle of the cone (surface = cone); 0 is the cylinder exactly; a 1:16 taper "
                   "on the diameter is 1.79 deg", "(-45, 45)"),
}


# ----------------------------------------------------------------------------------------------
# parsing and validation

_BINOPS = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul, ast.Div: operator.truediv,
           ast.Pow: operator.pow}


def _eval_expr(text):
    """Evaluate a tiny arithmetic expression (numbers, pi, + - * / **, parentheses)."""
    def ev(node):
        if isinstance(node, ast.Expression):
            return ev(node.body)
        if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) and not isinstance(node.value, bool):
            return float(node.value)
        if isinstance(node, ast.Name) and node.id == "pi":
            return math.pi
        if isinstance(node, ast.BinOp) and type(node.op) in _BINOPS:
            return _BINOPS[type(node.op)](ev(node.left), ev(node.right))
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
            v = ev(node.operand)
            return -v if isinstance(node.op, ast.USub) else v
        raise ValueError
    return ev(ast.parse(text.strip(), mode="eval"))


def _parse_number(name, value, integer=False):
    if isinstance(value, str):
        s = value.strip()
        try:
            v = float(s)
        except ValueError:
            try:
                v = _eval_expr(s)
            except (ValueError, SyntaxError, ZeroDivisionError, TypeError, OverflowError):
                raise ValueError(f"{name}: expected a number (or an expression with pi); got {value!r}") from None
    elif isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise ValueError(f"{name}: expected a number; got {value!r} ({type(value).__name__})")
    else:
        v = float(value)
    if not math.isfinite(v):
        raise ValueError(f"{name} must be finite; got {value!r}")
    if integer:
        if v != int(v):
            raise ValueError(f"{name} must be an integer; got {value!r}")
        return int(v)
    return v


# Physical range of a scene parameter by its unit: (smallest value a "> 0" parameter may take or None,
# largest magnitude). Wide enough for any machine part a multibody contact model describes (lengths of
# a nanometre to ten kilometres, stiffnesses up to 1e14 N/m, friction coefficients up to 1e3); outside it
# a double loses the contact's resolution or overflows (mu 1e300, a size of 1e300 m), and the value is
# refused here with its name rather than failing deep inside.
MAGNITUDE_LIMITS = {
    "m": (1e-9, 1e4), "kg": (1e-9, 1e6), "kg/m": (1e-9, 1e6), "s": (1e-12, 1e5),
    "-": (None, 1e3), "deg": (None, 3600.0), "N": (None, 1e9), "N m": (None, 1e7),
    "N/m": (None, 1e14), "N/m^2": (None, 1e14), "N m/rad": (None, 1e12), "N m/rad | N/m": (None, 1e14),
    "N m^2": (None, 1e9), "N s/m": (None, 1e12), "N s/m^2": (None, 1e12), "m/s": (None, 1e4),
    "m/s^2": (None, 1e4), "rad/s": (None, 1e5), "Hz": (None, 1e6), "1/s": (None, 1e6),
}
MAX_COUNT = 1_000_000        # largest value of any integer count parameter (before the cost checks below)

# What a run may cost, checked from the parameters before anything is built (``_ParamsMixin.check_cost``):
MAX_STEPS = 1_000_000        # time steps N = round(t_end / dt)
MAX_CONTACT_POINTS = 10_000  # contact points of the whole scene
MAX_POINT_STEPS = 1e9        # contact points x steps (~25 min at the block's 1.4 us per point and step)
MEMORY_SHARE = 0.8           # of the machine's available memory a run's estimate may take


def _check_magnitude(name, value, unit):
    lo, hi = MAGNITUDE_LIMITS.get(unit, (None, None))
    u = "" if unit in (None, "-") else " " + unit
    if hi is not None and not abs(value) <= hi:
        raise ValueError(f"{name} must satisfy |{name}| <= {hi:g}{u} (the physical range of this unit in "
                         f"exu_aniso's scenes); got {value!r}")
    if lo is not None and 0.0 < value < lo:
        raise ValueError(f"{name} must be 0 or >= {lo:g}{u} (the physical range of this unit in exu_aniso's "
                         f"scenes); got {value!r}")
    return value


def available_memory_bytes():
    """Memory the system can still give a process [bytes] (Linux MemAvailable), or None if unknown."""
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return None


def estimated_memory_bytes(steps, points):
    """A coarse upper estimate of a run's peak memory for its results [bytes]: per step, some 200
    numbers of trajectory, sensors and CSV text, and 40 per contact point (the stored history, 9
    numbers, and the ledger's per-point arrays, in several copies), at 8 bytes each."""
    return 8.0 * (200.0 + 40.0 * points) * (steps + 1)


def _check(name, value, rule, unit=None):
    """Parse/validate one value against its rule (and the physical range of its unit); returns the
    clean value."""
    if isinstance(rule, tuple):
        if not isinstance(value, str) or value.strip() not in rule:
            raise ValueError(f"{name} must be one of {rule}; got {value!r}")
        return value.strip()
    if rule == _POINTS_RULE:
        if isinstance(value, str):
            s = value.strip()
            if s in ("center", "corners"):
                return s
            m = re.fullmatch(r"grid:(\d+)", s)
            if m and int(m.group(1)) >= 2:
                return f"grid:{int(m.group(1))}"
        raise ValueError(f"{name} must be {_POINTS_RULE}; got {value!r}")
    if rule == "int >= 1":
        v = _parse_number(name, value, integer=True)
        if not 1 <= v <= MAX_COUNT:
            raise ValueError(f"{name} must be an integer >= 1 and <= {MAX_COUNT} (a bound on a run's cost); "
                             f"got {value!r}")
        return v
    v = _check_magnitude(name, _parse_number(name, value), unit)
    if rule == "> 0" and not v > 0.0:
        raise ValueError(f"{name} must be > 0; got {value!r}")
    if rule == ">= 0" and not v >= 0.0:
        raise ValueError(f"{name} must be >= 0; got {value!r}")
    if rule == "(-90, 90)" and not -90.0 < v < 90.0:
        raise ValueError(f"{name} must lie in (-90, 90) deg; got {value!r}")
    if rule == "(-45, 45)" and not -45.0 < v < 45.0:
        raise ValueError(f"{name} must lie in (-45, 45) deg; got {value!r}")
    return v


class _ParamsMixin:
    """Shared parsing, validation and description for the scene parameter dataclasses."""

    TABLE: dict = {}

    def __post_init__(self):
        for name, (_, unit, _, rule) in self.TABLE.items():
            object.__setattr__(self, name, _check(name, getattr(self, name), rule, unit))
        if not self.dt <= self.t_end:
            raise ValueError(f"dt must be <= t_end; got dt={self.dt!r} > t_end={self.t_end!r}")
        self.check_cost()
        self._check_scene()
        if getattr(self, "model", None) == "full" and getattr(self, "points_per_ring", 3) < 3:
            raise ValueError(f"points_per_ring must be >= 3 for model='full' (radial centring); "
                             f"got {self.points_per_ring}")

    def _check_scene(self):
        """Rules that tie several parameters together (scene-specific)."""

    def contact_points(self):
        """Number of contact points of the whole scene as laid out by the parameters (scene-specific)."""
        return 1

    def check_cost(self):
        """Refuse a run whose cost is out of bounds before anything is built: steps <= MAX_STEPS, contact
        points <= MAX_CONTACT_POINTS, their product <= MAX_POINT_STEPS, and estimated_memory_bytes within
        MEMORY_SHARE of the machine's available memory. Messages name the parameters."""
        steps, K = step_count(self), self.contact_points()
        if steps > MAX_STEPS:
            raise ValueError(f"t_end / dt must be <= {MAX_STEPS:,} steps (a bound on a run's cost); got "
                             f"t_end={self.t_end!r} / dt={self.dt!r} = {steps:,} steps: raise dt or shorten t_end")
        if K > MAX_CONTACT_POINTS:
            raise ValueError(f"the scene's contact points must be <= {MAX_CONTACT_POINTS:,} (a bound on a run's "
                             f"cost); the parameters lay out {K:,} ({self._layout_text()})")
        if K * steps > MAX_POINT_STEPS:
            raise ValueError(f"contact points x steps must be <= {MAX_POINT_STEPS:.0e} (a bound on a run's cost); "
                             f"got {K:,} points ({self._layout_text()}) x {steps:,} steps (t_end / dt)")
        need, have = estimated_memory_bytes(steps, K), available_memory_bytes()
        if have is not None and need > MEMORY_SHARE * have:
            raise ValueError(f"the run needs an estimated {need / 2**30:.3g} GiB for {steps:,} steps (t_end / dt) x "
                             f"{K:,} contact points ({self._layout_text()}), more than {MEMORY_SHARE:.0%} of the "
                             f"{have / 2**30:.3g} GiB this machine has available: raise dt, shorten t_end or use "
                             "fewer points")

    def _layout_text(self):
        """The parameters that set contact_points(), as 'name=value' text (scene-specific)."""
        return "the scene's layout"

    @classmethod
    def _unknown(cls, names):
        bad = sorted(set(names) - set(cls.TABLE))
        if bad:
            raise ValueError(f"{cls.__name__}: unknown parameter(s) {bad}; valid names: {list(cls.TABLE)}")

    @classmethod
    def from_strings(cls, values):
        """Build from a mapping name -> string (or value), e.g. parsed 'name=value' CLI pairs;
        missing names take their defaults. Raises ValueError on unknown names or bad values."""
        try:
            values = dict(values)
        except (TypeError, ValueError):
            raise TypeError(f"{cls.__name__}.from_strings: values must be a mapping name -> value (e.g. "
                            f"{{'mass': '2'}}); got {values!r} ({type(values).__name__})") from None
        cls._unknown(values)
        return cls(**values)

    def with_overrides(self, **kw):
        """A validated copy with some fields replaced (strings are parsed)."""
        self._unknown(kw)
        return dataclasses.replace(self, **kw)

    def as_dict(self):
        return dataclasses.asdict(self)

    @classmethod
    def describe(cls):
        """A text table: name, default, unit, allowed values, description."""
        rows = []
        for name, (default, unit, desc, rule) in cls.TABLE.items():
            allowed = " | ".join(rule) if isinstance(rule, tuple) else rule
            lo, hi = MAGNITUDE_LIMITS.get(unit, (None, None)) if rule in ("real", "> 0", ">= 0") else (None, None)
            if rule == "int >= 1":
                allowed = f"int in [1, {MAX_COUNT:.0e}]"
            elif hi is not None:       # the physical range of the unit (MAGNITUDE_LIMITS)
                allowed = {"real": f"[-{hi:g}, {hi:g}]",
                           "> 0": f"(0, {hi:g}]" if lo is None else f"[{lo:g}, {hi:g}]",
                           ">= 0": f"[0, {hi:g}]" if lo is None else f"0 or [{lo:g}, {hi:g}]"}[rule]
            rows.append(f"{name:16s} {default!s:14s} {unit:14s} {allowed:34s} {desc}")
        return "\n".join(rows)


def _defaults(table):
    return {k: v[0] for k, v in table.items()}


_BD = _defaults(BLOCK_PARAMS)
_SD = _defaults(SCREW_PARAMS)


@dataclass(frozen=True)
class BlockParams(_ParamsMixin):
    """Block on a (polar-)orthotropic plane; see BLOCK_PARAMS for units and meaning."""

    TABLE = BLOCK_PARAMS

    mass: float = _BD["mass"]
    size: float = _BD["size"]
    x0: float = _BD["x0"]
    y0: float = _BD["y0"]
    points: str = _BD["points"]
    normal_load: float = _BD["normal_load"]
    eps_n: float = _BD["eps_n"]
    adhesion: str = _BD["adhesion"]
    eps_1: float = _BD["eps_1"]
    eps_2: float = _BD["eps_2"]
    adhesion_angle: float = _BD["adhesion_angle"]
    friction: str = _BD["friction"]
    mu_1: float = _BD["mu_1"]
    mu_2: float = _BD["mu_2"]
    friction_angle: float = _BD["friction_angle"]
    return_map: str = _BD["return_map"]
    drive: str = _BD["drive"]
    drive_angle: float = _BD["drive_angle"]
    force: float = _BD["force"]
    drive_speed: float = _BD["drive_speed"]
    drive_stiffness: float = _BD["drive_stiffness"]
    t_end: float = _BD["t_end"]
    dt: float = _BD["dt"]
    model: str = _BD["model"]
    solver: str = _BD["solver"]
    core_radius: float = _BD["core_radius"]
    normal_damping: float = _BD["normal_damping"]
    tangential_damping: float = _BD["tangential_damping"]

    def contact_points(self):
        return _n_block_points(self)

    def _layout_text(self):
        return f"points={self.points}"

    def _check_scene(self):
        # positions far beyond the block: a double at |x0| resolves only |x0| * 2.2e-16, and at
        # 1e6 size that is 2.2e-10 size -- the limit where contact slips (~1e-5 m) still resolve;
        # beyond ~1e154 m the polar field's x^2 + y^2 overflows. One clear rule instead.
        for name in ("x0", "y0"):
            v = getattr(self, name)
            if not abs(v) <= POSITION_LIMIT * self.size:
                raise ValueError(f"{name} must satisfy |{name}| <= {POSITION_LIMIT:g} * size = "
                                 f"{POSITION_LIMIT * self.size:g} m (double precision must resolve the contact "
                                 f"slip at that distance from the origin); got {name}={v!r}")


@dataclass(frozen=True)
class ScrewParams(_ParamsMixin):
    """Screw in a threaded hole with a spiral net; see SCREW_PARAMS for units and meaning."""

    TABLE = SCREW_PARAMS

    radius: float = _SD["radius"]
    length: float = _SD["length"]
    mass: float = _SD["mass"]
    interference: float = _SD["interference"]
    helix_angle: float = _SD["helix_angle"]
    eps_n: float = _SD["eps_n"]
    adhesion: str = _SD["adhesion"]
    eps_1: float = _SD["eps_1"]
    eps_2: float = _SD["eps_2"]
    friction: str = _SD["friction"]
    mu_1: float = _SD["mu_1"]
    mu_2: float = _SD["mu_2"]
    return_map: str = _SD["return_map"]
    drive: str = _SD["drive"]
    torque: float = _SD["torque"]
    rotation_speed: float = _SD["rotation_speed"]
    axial_speed: float = _SD["axial_speed"]
    drive_stiffness: float = _SD["drive_stiffness"]
    axial_load: float = _SD["axial_load"]
    rings: int = _SD["rings"]
    points_per_ring: int = _SD["points_per_ring"]
    t_end: float = _SD["t_end"]
    dt: float = _SD["dt"]
    model: str = _SD["model"]
    solver: str = _SD["solver"]
    normal_damping: float = _SD["normal_damping"]
    tangential_damping: float = _SD["tangential_damping"]
    surface: str = _SD["surface"]
    half_angle: float = _SD["half_angle"]

    def contact_points(self):
        return self.rings * self.points_per_ring

    def _layout_text(self):
        return f"rings={self.rings} x points_per_ring={self.points_per_ring}"


assert [f.name for f in dataclasses.fields(BlockParams)] == list(BLOCK_PARAMS)
assert [f.name for f in dataclasses.fields(ScrewParams)] == list(SCREW_PARAMS)


# ----------------------------------------------------------------------------------------------
# geometry and contact laws of the scenes

def block_points(p):
    """Body-local contact points (K, 3) on the bottom face z = -size/2 of the cube [m].

    "center": the face centre; "corners": the four corners; "grid:N": N x N points including the
    edges (row-major in x, then y)."""
    a = 0.5 * p.size
    if p.points == "center":
        xy = np.zeros((1, 2))
    elif p.points == "corners":
        xy = np.array([[-a, -a], [a, -a], [a, a], [-a, a]])
    else:
        n = int(p.points.split(":")[1])
        s = np.linspace(-a, a, n)
        X, Y = np.meshgrid(s, s, indexing="xy")
        xy = np.stack([X.ravel(), Y.ravel()], axis=-1)
    return np.column_stack([xy, np.full(len(xy), -a)])


def screw_points(p):
    """Body-local contact points (K, 3) on the cylinder of radius radius + interference [m] (on a
    cone: at radius + interference / cos(half_angle) + z tan(half_angle), the cone parallel to the
    hole at the normal distance interference).

    ``rings`` rings equally spaced over the length, centred on the COM (z from -length/2 to
    +length/2 including the ends; one ring sits at z = 0); ``points_per_ring`` points per ring at
    angles 2 pi j / points_per_ring. Ring-major order."""
    z = np.zeros(1) if p.rings == 1 else np.linspace(-0.5 * p.length, 0.5 * p.length, p.rings)
    phi = 2.0 * np.pi * np.arange(p.points_per_ring) / p.points_per_ring
    Z, PHI = np.meshgrid(z, phi, indexing="ij")
    if p.surface == "cone":
        beta = math.radians(p.half_angle)
        rho = p.radius + p.interference / math.cos(beta) + Z.ravel() * math.tan(beta)
    else:
        rho = p.radius + p.interference
    return np.column_stack([rho * np.cos(PHI.ravel()), rho * np.sin(PHI.ravel()), Z.ravel()])


def _n_block_points(p):
    return {"center": 1, "corners": 4}.get(p.points) or int(p.points.split(":")[1]) ** 2


def block_contact_law(p):
    """ContactLaw of the block scene: plane z = 0 (polar chart when a field is polar), per-point
    stiffnesses = total / K, friction coefficients as given."""
    K = _n_block_points(p)
    rad = math.radians
    if p.adhesion == "isotropic":
        B = Adhesion.isotropic(p.eps_1 / K)
    elif p.adhesion == "cartesian":
        B = Adhesion.orthotropic(p.eps_1 / K, p.eps_2 / K, angle=rad(p.adhesion_angle))
    else:
        B = Adhesion.polar(p.eps_1 / K, p.eps_2 / K, core_radius=p.core_radius)
    if p.friction == "isotropic":
        Fr = Friction.isotropic(p.mu_1)
    elif p.friction == "cartesian":
        Fr = Friction.orthotropic(p.mu_1, p.mu_2, angle=rad(p.friction_angle))
    else:
        Fr = Friction.polar(p.mu_1, p.mu_2, core_radius=p.core_radius)
    # the Cartesian chart for every field: its coordinate basis is parallel, so the transport of the
    # sticking traction is exact; a polar net is defined on it (nets.PolarNet)
    return ContactLaw(Plane(), B, Fr, normal_stiffness=p.eps_n / K, return_map=p.return_map,
                      normal_damping=p.normal_damping / K, tangential_damping=p.tangential_damping / K)


def screw_contact_law(p):
    """ContactLaw of the screw scene: hole = Cylinder(radius, side="inside") about the z axis (or
    the Cone of half_angle through it at z = 0), per-point stiffnesses = total / K, spiral fields
    with the helix angle (on the cone: the same lead, the pitch 2 pi radius tan(helix_angle))."""
    K = p.rings * p.points_per_ring
    alpha = math.radians(p.helix_angle)
    if p.adhesion == "isotropic":
        B = Adhesion.isotropic(p.eps_1 / K)
    else:
        B = Adhesion.spiral(p.eps_1 / K, p.eps_2 / K, alpha)
    if p.friction == "isotropic":
        Fr = Friction.isotropic(p.mu_1)
    else:
        Fr = Friction.spiral(p.mu_1, p.mu_2, alpha)
    if p.surface == "cone":
        hole = Cone(math.radians(p.half_angle), p.radius, side="inside")
    else:
        hole = Cylinder(p.radius, side="inside")
    return ContactLaw(hole, B, Fr, normal_stiffness=p.eps_n / K, return_map=p.return_map,
                      normal_damping=p.normal_damping / K, tangential_damping=p.tangential_damping / K)


def block_inertia(p):
    """Mass [kg] and body-frame inertia tensor (3, 3) [kg m^2] of the cube (about its COM)."""
    return p.mass, np.eye(3) * (p.mass * p.size ** 2 / 6.0)


def screw_inertia(p):
    """Mass [kg] and body-frame inertia tensor (3, 3) [kg m^2] of the screw: a solid cylinder of
    radius ``radius`` and length ``length`` about its COM, axis z."""
    m, r, L = p.mass, p.radius, p.length
    Jt = m * (3.0 * r * r + L * L) / 12.0
    return m, np.diag([Jt, Jt, 0.5 * m * r * r])


def pitch(p):
    """Thread pitch 2 pi R tan(alpha) of the spiral net [m per revolution]."""
    return 2.0 * math.pi * p.radius * math.tan(math.radians(p.helix_angle))


# ----------------------------------------------------------------------------------------------
# summaries shared by every engine (keys are a public interface: CLI summary.json)

BLOCK_SUMMARY_KEYS = ("x_end", "y_end", "theta_end", "vx_end", "vy_end", "heading_deg", "r_min", "r_max", "r_mean",
                      "slip_distance", "dissipated_energy", "wall_s", "steps", "newton_iterations", "undefined")
SCREW_SUMMARY_KEYS = ("angle_end", "z_end", "advance_per_rev", "torque_mean", "axial_force_mean",
                      "dissipated_energy", "wall_s", "steps", "newton_iterations", "undefined")


# thresholds below which a summary value is undefined (null in summary.json, reason under "undefined")
HEADING_V_ABS = 1e-9     # m/s: |v_end| at or below this has no direction (round-off of a block at rest)
HEADING_V_REL = 1e-6     # ... nor below this fraction of the largest speed of the run (a block come to rest)
TURN_ANGLE_MIN = 1e-6    # rad: a net rotation over the last half at or below this is no turning


def summary_float(summary, key):
    """summary[key] as a float for tables and fits: NaN where the value is undefined (None)."""
    v = summary[key]
    return float("nan") if v is None else float(v)


def _undefined_heading(vx, vy):
    """Reason why the heading of the final velocity is undefined, or None. Undefined when
    |v_end| <= max(HEADING_V_ABS, HEADING_V_REL * max_t |v|): the direction of a velocity at round-off
    level is noise (atan2 of 1e-14 values)."""
    speed = np.hypot(vx, vy)
    limit = max(HEADING_V_ABS, HEADING_V_REL * float(speed.max()))
    if speed[-1] <= limit:
        return (f"block at rest at the end: |v_end| = {speed[-1]:.3g} m/s <= {limit:.3g} m/s "
                f"(max({HEADING_V_ABS:g} m/s, {HEADING_V_REL:g} x the largest speed of the run, "
                f"{speed.max():.3g} m/s)); its direction is round-off")
    return None


ENERGY_COLUMNS = tuple("energy_" + k for k in energy.LEDGER_KEYS)


def solver_advice(p):
    """What to try when the ledger of a run with parameters p does not close (energy.warn_if_open)."""
    if p.solver == "generalized_alpha":
        return ("reduce dt (generalized_alpha damps vibrations numerically, rho_inf 0.8: the energy it removes "
                "shows as a residual that falls with dt)")
    return "reduce dt"


def _energy(terms, traj, what, advice=energy.DEFAULT_ADVICE):
    """Energy ledger of a run: adds the ENERGY_COLUMNS to traj and returns the summary entries.

    The trajectory's own columns (the state) are checked too: a non-finite value there makes
    ``energy_ok`` False and is named under ``state_nonfinite`` = dict(column, index, t) (the command
    line then exits 1); a non-finite ledger term under ``energy_nonfinite`` (energy.ledger)."""
    state = energy.first_nonfinite({k: v for k, v in traj.items() if not k.startswith("energy_")}, traj["t"])
    cols, summary = energy.ledger(**terms, t=traj["t"])
    traj.update({"energy_" + k: v for k, v in cols.items()})
    if state is not None:
        summary.update(energy_ok=False, state_nonfinite=state)
        summary["energy"]["residual"] = float("nan")
    energy.warn_if_open(summary, what, advice)
    return summary


def block_energy(p, traj, motion, law, H, extra_work=None):
    """Energy ledger of a block run (any engine): adds the ENERGY_COLUMNS to traj and returns the
    summary entries (energy, energy_ok, energy_tolerance; see exu_aniso.engines.energy.ledger).

    motion: energy.RigidMotion of the cube's COM (world = master frame); law: the contact law as
    evaluated at block_points(p); H (n, K, 9): converged history per sample. Work in: the drive
    force along the drive direction; potential: normal_load (z - z0) (the load stands in for the
    weight; constant in the planar model); extra_work: cumulative work [J] of loads the scene does
    not know (e.g. a lift pulse of a study), added to the work in. The full model's trajectory gains
    omega_x, omega_y (world), so its kinetic energy can be recomputed from trajectory.csv."""
    if p.model == "full":        # what the kinetic energy needs, in the file too (J of the cube is isotropic)
        traj.update(omega_x=motion.omega[:, 0], omega_y=motion.omega[:, 1])
    d = np.array([math.cos(math.radians(p.drive_angle)), math.sin(math.radians(p.drive_angle))])
    s = d[0] * traj["x"] + d[1] * traj["y"]
    mass, J = block_inertia(p)
    X, V = energy.point_motion(motion, block_points(p))
    stored, diss = energy.contact_energy(law, X, V, H)
    work = energy.work_trapezoid(traj["drive_force"], s)
    return _energy(dict(work_in=work if extra_work is None else work + extra_work,
                        kinetic=energy.rigid_kinetic(motion, mass, J),
                        potential=p.normal_load * (traj["z"] - traj["z"][0]), stored=stored, dissipated=diss),
                   traj, "block run", solver_advice(p))


def screw_energy(p, traj, motion, points, law, H):
    """Energy ledger of a screw run (any engine), as block_energy; points: the body-local points
    the engine evaluates with law (one representative point carrying the totals under symmetry).
    Work in: drive torque over the angle plus axial force (drive and axial_load) over z. The full
    model's trajectory gains vx, vy, omega_x, omega_y and the axis (axis_x, axis_y, axis_z: the body's
    z axis in the world), so its kinetic energy can be recomputed from trajectory.csv."""
    if p.model == "full":        # what the kinetic energy needs, in the file too: lateral velocity, spin, axis
        traj.update(vx=motion.velocity[:, 0], vy=motion.velocity[:, 1], omega_x=motion.omega[:, 0],
                    omega_y=motion.omega[:, 1], axis_x=motion.rotation[:, 0, 2], axis_y=motion.rotation[:, 1, 2],
                    axis_z=motion.rotation[:, 2, 2])
    mass, J = screw_inertia(p)
    X, V = energy.point_motion(motion, points)
    stored, diss = energy.contact_energy(law, X, V, H)
    work = energy.work_trapezoid(traj["torque"], traj["angle"]) + energy.work_trapezoid(traj["axial_force"], traj["z"])
    return _energy(dict(work_in=work, kinetic=energy.rigid_kinetic(motion, mass, J),
                        potential=np.zeros(len(traj["t"])), stored=stored, dissipated=diss), traj, "screw run",
                   solver_advice(p))


def block_summary(traj, wall_s, steps, newton_iterations):
    """Summary of a block trajectory (dict of arrays with t, x, y, theta, vx, vy, slip_distance,
    dissipated_energy): end state, heading of the final velocity [deg], distance of the centre
    from the origin along the path (min, max, mean) [m], cost figures. ``heading_deg`` is None
    when the block is at rest at the end (see ``_undefined_heading``); ``undefined`` maps every
    None value to its reason."""
    x, y = traj["x"], traj["y"]
    r = np.hypot(x, y)
    vx, vy = np.asarray(traj["vx"], float), np.asarray(traj["vy"], float)
    undefined = {}
    why = _undefined_heading(vx, vy)
    if why is None:
        heading = float(math.degrees(math.atan2(vy[-1], vx[-1])))
    else:
        heading, undefined["heading_deg"] = None, why
    return dict(x_end=float(x[-1]), y_end=float(y[-1]), theta_end=float(traj["theta"][-1]),
                vx_end=float(vx[-1]), vy_end=float(vy[-1]), heading_deg=heading,
                r_min=float(r.min()), r_max=float(r.max()), r_mean=float(r.mean()),
                slip_distance=float(traj["slip_distance"][-1]),
                dissipated_energy=float(traj["dissipated_energy"][-1]),
                wall_s=float(wall_s), steps=int(steps), newton_iterations=int(newton_iterations),
                undefined=undefined)


def _undefined_advance(t, ang):
    """Reason why the advance per revolution over the samples (t, ang) of the last half is
    undefined, or None. The screw turns there when its net rotation exceeds TURN_ANGLE_MIN and
    the peak-to-peak oscillation of the angle about its mean rate (a linear fit in t): a stuck
    screw that only vibrates elastically has a z(angle) slope from the elastic coupling of the
    net, which is no advance."""
    if len(t) < 2:
        return f"fewer than two samples in the last half of the run ({len(t)})"
    net = abs(float(ang[-1] - ang[0]))
    if net <= TURN_ANGLE_MIN:
        return (f"screw did not turn over the last half of the run (|d angle| = {net:.3g} rad "
                f"<= {TURN_ANGLE_MIN:g} rad)")
    wobble = float(np.ptp(ang - np.polyval(np.polyfit(t, ang, 1), t)))
    if net <= wobble:
        return (f"screw sticks and only oscillates over the last half of the run: net rotation "
                f"{net:.3g} rad <= its oscillation {wobble:.3g} rad (peak to peak about the mean rate)")
    return None


def screw_summary(traj, wall_s, steps, newton_iterations):
    """Summary of a screw trajectory (t, angle, z, torque, axial_force, dissipated_energy):
    advance per revolution = 2 pi dz/dangle fitted over the last half of the run (signed; None
    when the screw does not turn there, see ``_undefined_advance``), mean drive torque and axial
    force over the last half; ``undefined`` maps every None value to its reason."""
    t = np.asarray(traj["t"], float)
    late = t >= 0.5 * t[-1]
    ang, z = np.asarray(traj["angle"], float)[late], np.asarray(traj["z"], float)[late]
    undefined = {}
    why = _undefined_advance(t[late], ang)
    if why is None:
        adv = float(np.polyfit(ang, z, 1)[0] * 2.0 * math.pi)
    else:
        adv, undefined["advance_per_rev"] = None, why
    return dict(angle_end=float(traj["angle"][-1]), z_end=float(traj["z"][-1]), advance_per_rev=adv,
                torque_mean=float(traj["torque"][late].mean()),
                axial_force_mean=float(traj["axial_force"][late].mean()),
                dissipated_energy=float(traj["dissipated_energy"][-1]),
                wall_s=float(wall_s), steps=int(steps), newton_iterations=int(newton_iterations),
                undefined=undefined)
