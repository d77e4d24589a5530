"""What every scene shares: the parameter sets' parsing, rules and validation (``SceneParams``), the
summaries' conventions and the energy ledger's columns (numpy reference, Exudyn adapter, CLI).

The two scenes of the papers are ``exu_aniso.scenes.block`` (``BlockParams``: a rigid cube on the
plane with (polar) orthotropic adhesion and friction) and ``exu_aniso.scenes.screw``
(``ScrewParams``: a rigid screw in a hole with a spiral net); the conventions below hold for them
and, where they say so, for the other scenes.

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
import functools
from dataclasses import dataclass
import math
import operator
import os
import re
import warnings

import numpy as np

from exu_aniso.engines import energy
from exu_aniso.fe.compliance import BasisWarning, compliance_share, missing_compliance
from exu_aniso.engines.timing import step_count

SOLVERS = ("trapezoidal", "generalized_alpha")
# rules: "real", "> 0", ">= 0", "int >= 1", "int >= 0", "(-90, 90)", "(-45, 45)", "points" or a tuple of choices
_POINTS_RULE = "'center' | 'corners' | 'grid:N' (N >= 2)"


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


EXPRESSION_LENGTH_MAX = 200
"""The longest text a number or an expression may be (deeper nesting only hides a typo)."""

_PLAIN_NUMBER = re.compile(r"[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?")
_NOT_PLAIN = re.compile(r"[_xXoObB]|[+-]\s*[+-]")     # digit separators, hex/octal/binary, doubled signs


def _parse_number(name, value, integer=False):
    """A parameter's number from its text or value: a plain decimal number, or an expression of
    numbers and pi with + - * / ** and parentheses (no digit separators, no hex, no doubled signs,
    at most EXPRESSION_LENGTH_MAX characters); the error names the parameter and the rule."""
    rule = "expected a decimal number (or an expression of numbers and pi with + - * / ** and parentheses)"
    if isinstance(value, str):
        s = value.strip()
        if len(s) > EXPRESSION_LENGTH_MAX:
            raise ValueError(f"{name}: {rule} of at most {EXPRESSION_LENGTH_MAX} characters; got {len(s)} characters")
        if _PLAIN_NUMBER.fullmatch(s):
            v = float(s)
        elif s.lower() in ("nan", "inf", "+inf", "-inf", "infinity", "+infinity", "-infinity"):
            v = float(s)
        else:
            if _NOT_PLAIN.search(s):
                raise ValueError(f"{name}: {rule}, without digit separators, hex/octal/binary or doubled signs; got "
                                 f"{value!r}")
            try:
                v = _eval_expr(s)
            except (ValueError, SyntaxError, ZeroDivisionError, TypeError, OverflowError, RecursionError,
                    MemoryError):
                raise ValueError(f"{name}: {rule}; got {value!r}") from None
            if isinstance(v, complex):
                raise ValueError(f"{name}: must be a real number; the expression {value!r} gives a complex one")
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


# Physical range of a scene parameter by its unit: (smallest magnitude of a value other than 0, largest
# magnitude). Wide enough for any machine part a multibody contact model describes (lengths of
# a nanometre to ten kilometres, stiffnesses up to 1e14 N/m, friction coefficients up to 1e3); outside it
# a double loses the contact's resolution or overflows (mu 1e300, a size of 1e300 m), and the value is
# refused here with its name rather than failing deep inside.
MAGNITUDE_LIMITS = {
    "m": (1e-9, 1e4), "kg": (1e-9, 1e6), "kg/m": (1e-9, 1e6), "s": (1e-12, 1e5),
    "-": (1e-9, 1e3), "deg": (1e-9, 3600.0), "N": (1e-9, 1e9), "N m": (1e-12, 1e7),
    "N/m": (1e-6, 1e14), "N/m^2": (1e-6, 1e14), "N m/rad": (1e-9, 1e12), "N m/rad | N/m": (1e-9, 1e14),
    "N m^2": (1e-12, 1e9), "N s/m": (1e-9, 1e12), "N s/m^2": (1e-9, 1e12), "m/s": (1e-12, 1e4),
    "m/s^2": (1e-12, 1e4), "rad/s": (1e-12, 1e5), "Hz": (1e-9, 1e6), "1/s": (1e-12, 1e6),
    "Pa": (1e-3, 1e13), "kg/m^3": (1e-3, 1e5),
}
"""The physical range of a real parameter by its unit: (lo, hi), |value| <= hi and a value that is
not 0 at least lo in magnitude (no denormal or vanishing value that passes as positive and then
divides: a friction coefficient of 5e-324 gave a ZeroDivisionError deep in the law)."""
MAX_COUNT = 1_000_000        # largest value of any integer count parameter (before the cost checks below)

# What a run may cost, checked from the parameters before anything is built (``SceneParams.check_cost``):
MAX_STEPS = 1_000_000        # time steps N = round(t_end / dt)
MAX_CONTACT_POINTS = 10_000  # contact points of the whole scene
MAX_POINT_STEPS = 1e9        # contact points x steps (~25 min at the block's 1.4 us per point and step)
MEMORY_SHARE = 0.8           # of the machine's available memory a run's estimate may take


def _check_magnitude(name, value, unit, positive=False):
    lo, hi = MAGNITUDE_LIMITS.get(unit, (None, None))
    u = "" if unit in (None, "-") else " " + unit
    if hi is not None and not abs(value) <= hi:
        raise ValueError(f"{name} must satisfy |{name}| <= {hi:g}{u} (the physical range of this unit in "
                         f"exu_aniso's scenes); got {value!r}")
    if lo is not None and 0.0 < abs(value) < lo:
        least = f"at least {lo:g}{u}" if positive else f"0 or at least {lo:g}{u} in magnitude"
        raise ValueError(f"{name} must be {least} (the physical range of this unit in exu_aniso's scenes); got "
                         f"{value!r}")
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
    if rule in ("int >= 1", "int >= 0"):
        v = _parse_number(name, value, integer=True)
        least = 1 if rule == "int >= 1" else 0
        if not least <= v <= MAX_COUNT:
            raise ValueError(f"{name} must be an integer >= {least} and <= {MAX_COUNT} (a bound on a run's cost); "
                             f"got {value!r}")
        return v
    v = _check_magnitude(name, _parse_number(name, value), unit, positive=rule == "> 0")
    if rule == "> 0" and not v > 0.0:
        raise ValueError(f"{name} must be > 0; got {value!r}")
    if rule == ">= 0" and not v >= 0.0:
        raise ValueError(f"{name} must be >= 0; got {value!r}")
    if rule == "(-90, 90)" and not -90.0 < v < 90.0:
        raise ValueError(f"{name} must lie in (-90, 90) deg; got {value!r}")
    if rule == "(-45, 45)" and not -45.0 < v < 45.0:
        raise ValueError(f"{name} must lie in (-45, 45) deg; got {value!r}")
    return v


class SceneParams:
    """The base of every scene's parameter set (made with ``scene_parameters``): parsing
    (``from_strings``), validated copies (``with_overrides``), ``as_dict``, ``describe`` (what
    ``exu-aniso params`` prints) and the checks of every value against its rule and its unit's range,
    ``dt <= t_end`` and the run's cost. A scene adds the rules that tie parameters together in
    ``_check_scene`` and its number of contact points in ``contact_points``."""

    TABLE: dict = {}
    RENAMED: dict = {}
    """Old parameter names still accepted: old name -> new name (a FutureWarning says so)."""
    RENAMED_VALUES: dict = {}
    """Old choices still accepted: (parameter, old value) -> new value (a FutureWarning says so)."""

    @classmethod
    def _current_names(cls, values):
        """values (a dict name -> value) with every old name and old choice (RENAMED, RENAMED_VALUES)
        replaced by the current one, each with a FutureWarning naming both; an old name given beside
        its new one is an error."""
        out = {}
        for name, value in values.items():
            if name in cls.RENAMED:
                new = cls.RENAMED[name]
                if new in values:
                    raise ValueError(f"{cls.__name__}: {name} is the old name of {new}; give {new} only")
                warnings.warn(f"{cls.__name__}: the parameter {name} is now called {new}; the old name will be "
                              "removed", FutureWarning, stacklevel=energy.outside_the_package())
                name = new
            old = value.strip() if isinstance(value, str) else value
            if isinstance(old, str) and (name, old) in cls.RENAMED_VALUES:
                value = cls.RENAMED_VALUES[name, old]
                warnings.warn(f"{cls.__name__}: {name}={old} is now called {name}={value}; the old value will be "
                              "removed", FutureWarning, stacklevel=energy.outside_the_package())
            out[name] = value
        return out

    def __post_init__(self):
        for name, (_, unit, _, rule) in self.TABLE.items():
            object.__setattr__(self, name, _check(name, getattr(self, name), rule, unit))
        if not self.dt <= self.t_end:
            raise ValueError(f"dt must be <= t_end; got dt={self.dt!r} > t_end={self.t_end!r}")
        self.check_cost()
        self._check_scene()

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

    @classmethod
    def cost_rules(cls):
        """The bounds check_cost applies, as lines of text (``exu-aniso params``); a scene with more
        bounds adds its own."""
        return [f"t_end / dt <= {MAX_STEPS:,} steps; contact points <= {MAX_CONTACT_POINTS:,}; contact points x "
                f"steps <= {MAX_POINT_STEPS:.0e}; the results' estimated memory <= {MEMORY_SHARE:.0%} of the "
                "memory available"]

    def _layout_text(self):
        """The parameters that set contact_points(), as 'name=value' text (scene-specific)."""
        return "the scene's layout"

    @classmethod
    def _unknown(cls, names):
        bad = sorted(set(names) - set(cls.TABLE) - set(cls.RENAMED))
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
        return dataclasses.replace(self, **self._current_names(kw))

    def as_dict(self):
        return dataclasses.asdict(self)

    @classmethod
    def describe(cls, width=None):
        """A text table with a header: name, default, unit, allowed values, description. The
        columns are as wide as their longest entry; the description wraps at ``width`` characters
        (default: the terminal's, 130 in a pipe; at least 100) under its own column."""
        import shutil
        import textwrap
        rows = []
        for name, (default, unit, desc, rule) in cls.TABLE.items():
            allowed = " | ".join(rule) if isinstance(rule, tuple) else rule
            lo, hi = MAGNITUDE_LIMITS.get(unit, (None, None)) if rule in ("real", "> 0", ">= 0") else (None, None)
            if rule in ("int >= 1", "int >= 0"):
                allowed = f"int in [{rule[-1]}, {MAX_COUNT:.0e}]"
            elif hi is not None:       # the physical range of the unit (MAGNITUDE_LIMITS)
                allowed = {"real": f"[-{hi:g}, {hi:g}]" if lo is None else f"0 or {lo:g} <= |x| <= {hi:g}",
                           "> 0": f"(0, {hi:g}]" if lo is None else f"[{lo:g}, {hi:g}]",
                           ">= 0": f"[0, {hi:g}]" if lo is None else f"0 or [{lo:g}, {hi:g}]"}[rule]
            rows.append((name, str(default), unit, allowed, desc))
        head = ("name", "default", "unit", "allowed", "description")
        w = [max(len(r[i]) for r in rows + [head]) for i in range(4)]
        indent = sum(w) + 4 * 2
        width = max(width or shutil.get_terminal_size((130, 24)).columns, 100)
        lines = []
        for r in [head] + rows:
            first = "  ".join(f"{c:{w[i]}s}" for i, c in enumerate(r[:4])) + "  "
            wrapped = textwrap.wrap(r[4], max(width - indent, 40)) or [""]
            lines.append(first + wrapped[0])
            lines += [" " * indent + more for more in wrapped[1:]]
        renamed = [f"{old} -> {new}" for old, new in cls.RENAMED.items()]
        renamed += [f"{name}={old} -> {name}={new}" for (name, old), new in cls.RENAMED_VALUES.items()]
        if renamed:
            lines += ["", "Old names still accepted (with a warning): " + "; ".join(renamed)]
        lines += ["", "Bounds on a run's cost, checked before anything is built:"]
        for rule in cls.cost_rules():
            lines += textwrap.wrap(rule, max(width, 40), initial_indent="  ", subsequent_indent="    ")
        return "\n".join(lines)


def scene_parameters(table):
    """Class decorator: a scene's parameter set as a frozen dataclass with one field per row of its
    table (name -> (default, unit, description, rule)), in the table's order, the row's default as
    the field's default, and ``TABLE = table``. The table is the one definition of every parameter:
    the dataclass, ``exu-aniso params``, the parsing and the validation (``SceneParams``) read it."""
    def make(cls):
        cls.__annotations__ = {name: type(row[0]).__name__ for name, row in table.items()}
        for name, row in table.items():
            setattr(cls, name, row[0])
        cls.TABLE = table
        made = dataclass(frozen=True)(cls)
        init = made.__init__

        @functools.wraps(init)
        def __init__(self, **values):      # old names and choices (RENAMED, RENAMED_VALUES) still accepted
            init(self, **made._current_names(values))
        made.__init__ = __init__
        return made
    return make


# ----------------------------------------------------------------------------------------------
# summaries shared by every engine (keys are a public interface: CLI summary.json)


# thresholds below which a summary value is undefined (null in summary.json, reason under "undefined")
HEADING_V_ABS = 1e-9     # m/s: |v_end| at or below this has no direction (round-off of a block at rest)


def summary_float(summary, key):
    """summary[key] as a float for tables and fits: NaN where the value is undefined (None)."""
    v = summary[key]
    return float("nan") if v is None else float(v)


ENERGY_COLUMNS = tuple("energy_" + k for k in energy.LEDGER_KEYS)
LEDGER_COLUMNS = {k: "J" for k in ENERGY_COLUMNS}
LEDGER_TERM_COLUMNS = ("kinetic_energy", "contact_stored_energy", "contact_dissipated_energy")
"""trajectory.csv columns [J] of a ledger's terms that the file's state alone cannot recompute (a
flexible body's kinetic energy needs every coordinate, the contact's every point): the kinetic energy
of the bodies, the contact's stored energy (penalty and adhesion) and its dissipated energy (friction
and dashpots, cumulative). A scene that writes them writes every other term too (its COLUMNS)."""


def solver_advice(p):
    """What to try when the ledger of a run with parameters p does not close (energy.warn_if_open)."""
    if p.solver == "generalized_alpha":
        return ("reduce dt (generalized_alpha damps vibrations numerically, rho_inf 0.8: the energy it removes "
                "shows as a residual that falls with dt)")
    return "reduce dt"


def energy_ledger(terms, traj, what, advice=energy.DEFAULT_ADVICE):
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


COMPLIANCE_SHARE_FLOOR = 0.9
"""Below this share of a flexible body's contact nodes' static compliance
(``exu_aniso.fe.compliance_share``) its basis misses the contact's give: the run warns."""


def basis_compliance(p, mesh, basis, contact_set, fixed_set, words, warn=True):
    """The summary's entries on a flexible body's basis (3N, m) of the ElasticMesh mesh, clamped at the
    node set fixed_set: contact_compliance_share, the share of the node set contact_set's static
    compliance the basis keeps against the full mesh (``exu_aniso.fe.compliance_share``; 1 for
    p.model == "full"), and basis_warning: None, or below COMPLIANCE_SHARE_FLOOR the warning naming
    the basis and the fix (``exu_aniso.fe.compliance.missing_compliance``; words: the basis, the
    contact nodes and the body in words), which warn=True also issues as a BasisWarning."""
    share = 1.0 if p.model == "full" else compliance_share(mesh, basis, mesh.node_sets[contact_set],
                                                           mesh.node_sets[fixed_set])
    text = missing_compliance(share, COMPLIANCE_SHARE_FLOOR, *words)
    if text is not None and warn:
        warnings.warn(text, BasisWarning, stacklevel=energy.outside_the_package())
    return dict(contact_compliance_share=float(share), basis_warning=text)

