"""Loosening scene: how transverse slip takes a bolted joint's friction away from its turning.

A preloaded joint loosens when its nut, or the clamped plate, is shaken across the bolt's axis: while a
contact ring slides sideways, its friction resists turning only in proportion to the spin rate, so the
pitch's torque turns the nut back. The scene has two cases, the mechanism on one ring and the joint:

* ``case="bearing"``: the nut's bearing ring (``points`` points on the radius ``bearing_radius``),
  pressed onto the clamped plate (the plane z = 0, its friction ``mu_bearing`` isotropic) by the
  ``preload``, dragged across it along x at ``slip_speed`` while a ``torque`` turns it about its axis.
  The ring is a planar rigid body (x, y, angle) whose points are held at the penetration that carries
  the preload (as the block scene's planar model); a stiff spring (``drag_stiffness``, with a dashpot
  ``drag_damping``) to a driver at slip_speed drags it along x, another to the origin holds y.

Closed forms (``scenes.threads``): dragged at v (``drag="speed"``), the ring turns in the steady state
at omega = s v / r, where G(s) = T / (mu N r) and G, the ring integral of Coulomb friction against
every point's slip velocity v e_x + omega r e_phi, grows as s / 2 for s << 1 (``ring_torque_factor``,
``ring_spin_ratio``): the summary's ``spin_rate`` against ``spin_rate_theory``. Pushed by a rising
force (``drag="ramp"``), it slides as a whole at the ring's friction limit under a force and a torque,
mu N D(s) at that s (``ring_drag_factor``, ``onset_force``). Shaken below it (``drag="shake"``), it
does not turn.

The preloaded joint (``case="joint"``: bolt, nut and plate, the nut shaken across the axis, the preload
against the cycles) is ``exu_aniso.scenes.bolted_joint`` (read its module docstring): the same scene's
second case, with its two models (``rings``, the closed form's uniform rings; ``full``, the nut on the
bolt's helicoid and the plate on the joint's spring) and their closed forms.
"""
from __future__ import annotations

import math
from typing import Callable, NamedTuple

import numpy as np

from exu_aniso.engines import energy
from exu_aniso.engines.reference import RUN_OPTIONS, PlanarBody, run
from exu_aniso.engines.result import Result
from exu_aniso.engines.timing import smooth_rise
from exu_aniso.law.history import HISTORY_FIELDS, SLIP
from exu_aniso.law.return_maps import DEFAULT_RETURN_MAP, RETURN_MAPS
from exu_aniso.scenes import bolted_joint, threads
from exu_aniso.scenes.bolted_joint import bearing_law, bearing_ring
from exu_aniso.scenes.base import LEDGER_COLUMNS, SOLVERS, SceneParams, energy_ledger, scene_parameters
from exu_aniso.scenes.plotting import drawn, labelled
from exu_aniso.scenes.scene import Scene
from exu_aniso.util.validation import check_instance, check_keywords

LOOSENING_PARAMS = {
    "case": ("bearing", "-", "bearing: the nut's bearing ring dragged across the plate while a torque turns it; "
             "joint: the preloaded joint, its nut shaken across the bolt's axis (scenes.bolted_joint)",
             ("bearing", "joint")),
    "model": ("rings", "-", "case joint: rings (a planar nut on its thread and bearing rings, held uniform: the "
              "closed form's idealisation) or full (a 6-DOF nut on the bolt's helicoid, the plate on the joint's "
              "spring)", ("rings", "full")),
    "preload": (1e4, "N", "the joint's preload pressing the bearing ring onto the plate", "> 0"),
    "bearing_radius": (6.6e-3, "m", "mean radius r_K of the nut's bearing ring (M10: (d_w + d_h) / 4)", "> 0"),
    "points": (24, "-", "contact points on the bearing ring (>= 3)", "int >= 1"),
    "mu_bearing": (0.12, "-", "bearing friction mu_K (isotropic)", "> 0"),
    "d2": (9.026e-3, "m", "case joint: pitch diameter (M10: 9.026 mm)", "> 0"),
    "pitch": (1.5e-3, "m", "case joint: thread pitch P (M10: 1.5 mm)", "> 0"),
    "flank_angle": (60.0, "deg", "case joint: thread angle beta, full (metric: 60), in [0, 180)", ">= 0"),
    "mu_thread": (0.12, "-", "case joint: flank friction (isotropic)", "> 0"),
    "thread_stiffness": (1e10, "N/m", "case joint: normal penalty stiffness of the thread contact (total)", "> 0"),
    "turns": (3, "-", "case joint: engaged thread turns carrying points", "int >= 1"),
    "points_per_turn": (8, "-", "case joint: thread points per turn (>= 3)", "int >= 1"),
    "joint_stiffness": (1e8, "N/m", "case joint, model full: the clamped parts' and the bolt's stiffness in series, "
                        "the plate's spring along the axis", "> 0"),
    "joint_damping": (9e3, "N s/m", "case joint, model full: the dashpot beside it (about critical with plate_mass)",
                      ">= 0"),
    "plate_mass": (0.2, "kg", "case joint, model full: the clamped plate's mass", "> 0"),
    "shank": ("rigid", "-", "case joint, model full: rigid (the bolt fixed, the nut shaken), or the bolt's threaded "
              "end on its shank, a beam clamped at the head and guided at the nut, the plate shaken as in a Junker "
              "test: guided_beam (lumped at the end: 12 E I / clamp_length^3) or fe_beam (shank_elements Timoshenko "
              "beam elements: its shear and its mass; damped by drag_damping / k_shank times its stiffness)",
              ("rigid", "guided_beam", "fe_beam")),
    "clamp_length": (0.03, "m", "flexible shank: the shank's bending length between head and nut", "> 0"),
    "shank_diameter": (8.6e-3, "m", "flexible shank: the shank's diameter (M10's stress diameter: 8.6 mm)", "> 0"),
    "youngs_modulus": (2.1e11, "Pa", "flexible shank: the bolt's Young's modulus (steel)", "> 0"),
    "poissons_ratio": (0.3, "-", "shank fe_beam: the bolt's Poisson's ratio (its shear modulus), in [0, 0.5)", ">= 0"),
    "shank_density": (7850.0, "kg/m^3", "shank fe_beam: the bolt's density (steel)", "> 0"),
    "shank_elements": (1, "-", "shank fe_beam: beam elements over the clamp length (one is exact under the end's "
                       "load alone; studies/junker.py sets more against it)", "int >= 1"),
    "bolt_mass": (0.02, "kg", "flexible shank: the mass of the bolt's end moving with the nut", "> 0"),
    "nut_height": (8e-3, "m", "case joint, model full: height of the nut (its inertia across the axis: "
                   "nut_inertia / 2 + nut_mass nut_height^2 / 12)", "> 0"),
    "shake_displacement": (2e-4, "m", "case joint: the shaker's amplitude D (the nut's centre pulled to "
                           "D sin(2 pi shake_frequency (t - load_time)) along x; the model's flank has no crest or "
                           "root, a real thread's radial play bounds the slip at the thread)", ">= 0"),
    "bearing_stiffness": (1e10, "N/m", "normal penalty stiffness of the bearing contact (total)", "> 0"),
    "sticking_stiffness": (2e8, "N/m", "sticking stiffness of the bearing contact, and of the thread's (total "
                           "each; 6 um of elastic stick at the default friction limit)", "> 0"),
    "drag": ("speed", "-", "how the ring is moved across the plate along x: speed (a stiff spring to a driver at "
             "slip_speed), ramp (a force rising at force_rate: the slip onset) or shake (a force shake_amplitude "
             "sin(2 pi shake_frequency t))", ("speed", "ramp", "shake")),
    "slip_speed": (0.02, "m/s", "drag=speed: speed at which the ring is dragged across the plate", "> 0"),
    "force_rate": (4e3, "N/s", "drag=ramp: the transverse force's rise", "> 0"),
    "shake_amplitude": (500.0, "N", "drag=shake: the transverse force's amplitude", ">= 0"),
    "shake_frequency": (12.5, "Hz", "drag=shake, and case joint: its frequency (a Junker test's 12.5 Hz)", "> 0"),
    "torque": (2.0, "N m", "torque turning the ring about its axis (below mu_bearing preload bearing_radius)",
               ">= 0"),
    "load_time": (0.005, "s", "the torque rises smoothly from 0 over this time ((1 - cos(pi t / load_time)) / 2), "
                  "and a ramped or shaking force starts after it (applied at once, a torque overshoots its "
                  "static twist and can turn a ring its friction holds)", ">= 0"),
    "nut_mass": (0.011, "kg", "mass of the nut", "> 0"),
    "nut_inertia": (5e-7, "kg m^2", "the nut's moment of inertia about its axis", "> 0"),
    "drag_stiffness": (1e8, "N/m", "the spring that drags the ring (case joint: shakes the nut) along x and holds it "
                       "at y = 0", "> 0"),
    "drag_damping": (1e3, "N s/m", "the dashpot beside it", ">= 0"),
    "return_map": (DEFAULT_RETURN_MAP, "-", "sliding return map", RETURN_MAPS),
    "t_end": (0.05, "s", "simulated time", "> 0"),
    "dt": (1e-4, "s", "time step", "> 0"),
    "solver": ("generalized_alpha", "-", "time integrator (the trapezoidal rule leaves the contacts' stick-slip "
               "chatter undamped: the joint's rings at dt 1e-3 and its full nut's long runs at dt 1e-4 fail under it, "
               "docs/guide/scenes.md)", SOLVERS),
    "spectral_radius": (0.0, "-", "solver generalized_alpha: its rho_inf in [0, 1] (0 damps the unresolved chatter "
                        "in one step)", ">= 0"),
}


@scene_parameters(LOOSENING_PARAMS)
class LooseningParams(SceneParams):
    """A bolted joint's loosening mechanisms; see LOOSENING_PARAMS for units and meaning."""

    def contact_points(self):
        return self.points + (self.turns * self.points_per_turn if self.case == "joint" else 0)

    def _layout_text(self):
        thread = f", thread {self.turns} x {self.points_per_turn}" if self.case == "joint" else ""
        return f"points={self.points}{thread}"

    def _check_scene(self):
        if self.points < 3:
            raise ValueError(f"points must be >= 3 (a ring); got {self.points!r}")
        if self.points_per_turn < 3:
            raise ValueError(f"points_per_turn must be >= 3 (a ring); got {self.points_per_turn!r}")
        if not 0.0 <= self.spectral_radius <= 1.0:
            raise ValueError(f"spectral_radius must lie in [0, 1]; got {self.spectral_radius!r}")
        if self.shank != "rigid" and (self.case, self.model) != ("joint", "full"):
            raise ValueError(f"shank: a flexible shank ({self.shank!r}) is the full joint's (case='joint', "
                             f"model='full'); got case={self.case!r}, model={self.model!r}")
        if not 0.0 <= self.poissons_ratio < 0.5:
            raise ValueError(f"poissons_ratio must lie in [0, 0.5); got {self.poissons_ratio!r}")
        if not 0.0 <= self.flank_angle < 180.0:
            raise ValueError(f"flank_angle must lie in [0, 180) deg; got {self.flank_angle!r}")


COLUMNS = {"t": "s", "x": "m", "y": "m", "angle": "rad", "vx": "m/s", "vy": "m/s", "omega": "rad/s",
           "drag_force": "N", "slip_fraction": "-", "slip_distance": "m", "dissipated_energy": "J",
           "preload": "N", "thread_load": "N", "bearing_load": "N", "thread_slip_fraction": "-",
           "thread_stick_fraction": "-", "thread_open_fraction": "-", "bearing_slip_fraction": "-",
           "bearing_stick_fraction": "-", "bearing_open_fraction": "-", "flank_load_spread": "-", "tilt": "rad",
           "plate_x": "m", "bolt_x": "m", "bolt_y": "m",
           **LEDGER_COLUMNS}
"""trajectory.csv: the ring's (the nut's) centre, its angle (case joint: turned loose, positive) and
their rates, the transverse force on it along x (the drag or shaker spring's, or the applied force), the
share of its bearing points that slide, the slip distance and the dissipated energy, and the ledger
(work in: the driver's or the force's work along x and the torque's over the angle, or the preload's;
kinetic: the nut's and the plate's). Case joint only (``bolted_joint.finish_joint_trajectory``): the
preload (the bearing's normal force), the rings' normal forces and shares of sliding, sticking and open
points, the flank's load spread ((max - min) / mean over the thread's points) and the nut's tilt; with
the guided-beam shank, the plate's shift and the bolt's end (x, y)."""
STEADY_SHARE = 0.5      # the steady state: the last half of the run
ONSET_SPEED = 1e-2      # m/s: gross slip, the ring runs away (below the limit the partial slip creeps at under 1 mm/s
                        # at the defaults; over the limit the ring's speed grows without bound)


# ----------------------------------------------------------------------------------------------
# geometry, law, the drag

# the bearing ring's points and contact law are the joint's (``bolted_joint.bearing_ring``,
# ``bolted_joint.bearing_law``): one ring, one law, in both cases

def held_gap(p):
    """The points' height over the plate that carries the preload [m] (negative: a penetration)."""
    return -p.preload / p.bearing_stiffness


def torque_at(p, t):
    """The torque on the ring at time t [N m] (a number or an array): rising as (1 - cos(pi t /
    load_time)) / 2 to ``torque`` at load_time."""
    return p.torque * smooth_rise(t, p.load_time)


def transverse_force(p, t):
    """drag=ramp or shake: the applied force along x [N] at time t (a number or an array), from
    load_time on."""
    scalar = np.ndim(t) == 0         # the Exudyn load's user function: every Newton iteration, no arrays
    tau = max(t - p.load_time, 0.0) if scalar else np.maximum(np.asarray(t, dtype=float) - p.load_time, 0.0)
    if p.drag == "ramp":
        return p.force_rate * tau
    return p.shake_amplitude * (math.sin if scalar else np.sin)(2.0 * math.pi * p.shake_frequency * tau)


def drag_force(p, x, y, vx, vy, t):
    """The force (2,) on the ring: along x the drag spring and dashpot to the driver at slip_speed t
    (drag=speed) or the applied transverse force; along y a spring and a dashpot to 0."""
    fx = (p.drag_stiffness * (p.slip_speed * t - x) + p.drag_damping * (p.slip_speed - vx) if p.drag == "speed"
          else transverse_force(p, t))
    return np.array([fx, -p.drag_stiffness * y - p.drag_damping * vy])


_SLIP = HISTORY_FIELDS.index("status")


def finish_trajectory(traj, H):
    """Add the share of sliding points from the contact history H (n, K, 9)."""
    traj["slip_fraction"] = (H[:, :, _SLIP] == SLIP).mean(axis=1)
    return traj


# ----------------------------------------------------------------------------------------------
# closed forms

def loosening_closed_forms(p):
    """The scene's closed forms for its case (``CASES``): ``bearing_closed_forms`` or
    ``bolted_joint.joint_closed_forms``."""
    return CASES[p.case].closed_forms(p)


def bearing_closed_forms(p):
    """``spin_rate_theory`` [rad/s]: omega = s v / r with G(s) = torque / (mu_bearing preload
    bearing_radius) (``threads.ring_spin_ratio``), that torque ratio, ``torque_ratio`` [-], and the
    friction force against the slide then, ``drag_force_theory`` [N] = mu N D(s)
    (``threads.ring_drag_factor``). None, with the reason, at or above 1 (the ring spins up without
    bound)."""
    g = p.torque / (p.mu_bearing * p.preload * p.bearing_radius)
    out = dict(torque_ratio=g, undefined={})
    try:
        s = threads.ring_spin_ratio(g)
    except ValueError as e:
        why = f"torque, mu_bearing, preload, bearing_radius: {e}"
        out.update(spin_rate_theory=None, drag_force_theory=None)
        out["undefined"].update(spin_rate_theory=why, drag_force_theory=why)
        return out
    out["spin_rate_theory"] = s * p.slip_speed / p.bearing_radius
    out["drag_force_theory"] = p.mu_bearing * p.preload * threads.ring_drag_factor(s)
    return out


def onset_force(p):
    """The transverse force [N] at which the ring, held turned by the torque, slides as a whole: the
    friction limit of a ring under a force Q and a torque T is the curve (Q, T) = mu N (D(s), G(s)) over
    the spin ratio s (every point then slides, the velocity field a rigid motion's), so Q = mu N
    D(G^-1(T / (mu N r))); mu N with no torque."""
    s = threads.ring_spin_ratio(p.torque / (p.mu_bearing * p.preload * p.bearing_radius))
    return p.mu_bearing * p.preload * threads.ring_drag_factor(s)


# ----------------------------------------------------------------------------------------------
# summary, energy

def loosening_summary(traj, p, wall_s, steps, newton_iterations):
    """The cost, the slip distance and the dissipated energy, and the case's own (``CASES``):
    ``bearing_summary`` or ``bolted_joint.joint_summary``."""
    s = dict(slip_distance=float(traj["slip_distance"][-1]), dissipated_energy=float(traj["dissipated_energy"][-1]),
             wall_s=float(wall_s), steps=int(steps), newton_iterations=int(newton_iterations))
    return {**s, **CASES[p.case].summary(traj, p)}


def bearing_summary(traj, p):
    """By the drag: speed, the ring's spin rate (its mean over the last STEADY_SHARE of the
    run) and the drag force there beside their closed forms; ramp, the slip onset (``onset_force``: the
    transverse force at the first sample where the ring's speed reaches ONSET_SPEED, gross slip) beside
    ``onset_force_theory``;
    shake, the ring's largest turn (``rotation_max`` [rad]), its turn per cycle between the first and the
    last whole cycle's ends (``rotation_per_cycle`` [rad]: a ratchet) and whether it ever slid as a whole,
    over ``cycles`` whole cycles of the shaking."""
    t = np.asarray(traj["t"], float)
    theory = bearing_closed_forms(p)
    s = dict(torque_ratio=theory["torque_ratio"], undefined={})
    if p.drag == "speed":
        late = t >= t[-1] - STEADY_SHARE * (t[-1] - t[0])
        s.update(spin_rate=float(np.mean(np.asarray(traj["omega"], float)[late])),
                 spin_rate_theory=theory["spin_rate_theory"],
                 drag_force_mean=float(np.mean(np.asarray(traj["drag_force"], float)[late])),
                 drag_force_theory=theory["drag_force_theory"])
        s["undefined"].update(theory["undefined"])
    elif p.drag == "ramp":
        speed = np.hypot(np.asarray(traj["vx"], float), np.asarray(traj["vy"], float))
        gross = np.flatnonzero(speed >= ONSET_SPEED)
        s["onset_force"] = float(traj["drag_force"][gross[0]]) if len(gross) else None
        if not len(gross):
            s["undefined"]["onset_force"] = "the ring did not slide as a whole by the end of the run: run longer"
        try:
            s["onset_force_theory"] = onset_force(p)
        except ValueError as e:
            s["onset_force_theory"] = None
            s["undefined"]["onset_force_theory"] = f"torque, mu_bearing, preload, bearing_radius: {e}"
    else:
        angle = np.asarray(traj["angle"], float)
        whole = np.flatnonzero(np.asarray(traj["slip_fraction"], float) == 1.0)
        per_cycle, ends, _ = bolted_joint.rotation_per_cycle(p, t, angle)
        s.update(rotation_max=float(np.max(np.abs(angle - angle[0]))), slid_as_a_whole=bool(len(whole)),
                 cycles=float(len(ends)), rotation_per_cycle=per_cycle)
        if per_cycle is None:
            s["undefined"]["rotation_per_cycle"] = bolted_joint.FEW_CYCLES
    return s


def loosening_energy(p, traj, **inputs):
    """Energy ledger of a run (any engine), the case's terms (``CASES``): ``bearing_energy_terms``
    (inputs motion, law, H) or ``bolted_joint.joint_energy_terms`` (inputs contacts, shaken, and model
    full plate, nut_motion and a flexible shank's bolt and shank)."""
    return energy_ledger(CASES[p.case].energy_terms(p, traj, **inputs), traj, "loosening run")


def bearing_energy_terms(p, traj, motion, law, H):
    """The bearing case's energy terms (energy.ledger's arguments): work in, the drag springs' forces
    over the ring's travel and the torque over its angle; kinetic; the drag springs' own energy and the
    contact's stored energy; the contact's and the drag dashpots' dissipation."""
    x, y = np.asarray(traj["x"], float), np.asarray(traj["y"], float)
    vx, vy = np.asarray(traj["vx"], float), np.asarray(traj["vy"], float)
    t = np.asarray(traj["t"], float)
    work = energy.work_trapezoid(torque_at(p, t), traj["angle"])
    springs = 0.5 * p.drag_stiffness * y ** 2
    dashpots = energy.work_trapezoid(p.drag_damping * vy, y)
    if p.drag == "speed":       # the driver's work: the spring-and-dashpot force over the driver's travel
        travel = p.slip_speed * t
        stretch_x = travel - x
        work = work + energy.work_trapezoid(traj["drag_force"], travel)
        springs = springs + 0.5 * p.drag_stiffness * stretch_x ** 2
        dashpots = dashpots + energy.work_trapezoid(p.drag_damping * (p.slip_speed - vx), stretch_x)
    else:                       # the applied force's work along x
        work = work + energy.work_trapezoid(traj["drag_force"], x)
    stored, diss = energy.rigid_contact_energy(law, motion, bearing_ring(p), H)     # motion: at the held height
    kinetic = 0.5 * p.nut_mass * (vx ** 2 + vy ** 2) + 0.5 * p.nut_inertia * np.asarray(traj["omega"], float) ** 2
    return dict(work_in=work, kinetic=kinetic, potential=springs, stored=stored, dissipated=diss + dashpots)


# ----------------------------------------------------------------------------------------------
# the plot of trajectory.png

def PlotLoosening(traj, params, fig):
    """trajectory.png: the case's plot (``CASES``), ``PlotBearing`` or ``PlotJoint``."""
    return CASES[params.case].plot(traj, params, fig)


def PlotBearing(traj, params, fig):
    """Case bearing: the ring's spin rate over time with its closed form."""
    t, w = drawn(np.asarray(traj["t"]), np.asarray(traj["omega"]))
    ax = fig.add_subplot(1, 1, 1)
    ax.plot(t, w, label="spin rate")
    theory = bearing_closed_forms(params)["spin_rate_theory"]
    if theory is not None:
        ax.axhline(theory, color="k", ls="--", lw=0.8, label=f"ring integral: {theory:.5g} rad/s")
    labelled(ax, "t [s]", "omega [rad/s]")


def PlotJoint(traj, p, fig):
    """Case joint: the angle turned loose and the preload against the shaking's cycles (top), and the
    transverse force against the nut's displacement, the hysteresis loop, with the uniform rings'
    sliding force (bottom)."""
    t = np.asarray(traj["t"], float)
    cycles = (t - p.load_time) * p.shake_frequency
    ax = fig.add_subplot(2, 1, 1)
    ax.plot(*drawn(cycles, np.asarray(traj["angle"], float)), label="angle turned loose")
    labelled(ax, "cycles", "angle [rad]")
    ax2 = ax.twinx()
    ax2.plot(*drawn(cycles, 1e-3 * np.asarray(traj["preload"], float)), color="C1", label="preload")
    ax2.set_ylabel("preload [kN]", color="C1")
    ax = fig.add_subplot(2, 1, 2)
    shaking = t > p.load_time
    ax.plot(*drawn(1e3 * np.asarray(traj["x"], float)[shaking], np.asarray(traj["drag_force"], float)[shaking]),
            lw=0.8, label="transverse force")
    ratio = bolted_joint.joint_closed_forms(p)["slide_force_per_preload_theory"]
    if ratio is not None:
        for sign in (1.0, -1.0):
            ax.axhline(sign * ratio * p.preload, color="k", ls="--", lw=0.8,
                       label="uniform rings sliding" if sign > 0 else None)
    labelled(ax, "x [mm]", "force [N]")


# ----------------------------------------------------------------------------------------------
# the reference engine's body model and run

class _BearingRing(PlanarBody):
    def __init__(self, p, law):
        self.p = p
        super().__init__(law, bearing_ring(p)[:, :2], p.nut_mass, p.nut_inertia, p.bearing_radius,
                         [0.0, 0.0, 0.0], held_gap(p), held_gap(p))

    def drive(self, q, v, t):
        p = self.p
        k, c = p.drag_stiffness, p.drag_damping
        along = 1.0 if p.drag == "speed" else 0.0         # the applied force does not depend on the motion
        return (drag_force(p, q[0], q[1], v[0], v[1], t), -k * np.diag([along, 1.0]), -c * np.diag([along, 1.0]))

    def torque(self, q, v, t):
        return float(torque_at(self.p, t)), 0.0, 0.0

    def record(self, q, v, t, st):
        return dict(x=q[0], y=q[1], angle=q[2], vx=v[0], vy=v[1], omega=v[2],
                    drag_force=float(drag_force(self.p, q[0], q[1], v[0], v[1], t)[0]))


def simulate_loosening(params=None, **options):
    """The loosening scene with the reference integrator; params: LooseningParams (defaults if None).
    Options as for simulate_block. Returns Result."""
    p = LooseningParams() if params is None else params
    check_instance("params", p, LooseningParams)
    check_keywords("simulate_loosening", options, RUN_OPTIONS)
    if p.case != "bearing":
        raise ValueError(f"case: the reference engine runs the loosening's case bearing; case {p.case!r} runs on "
                         "Exudyn (exu_aniso.models.loosening)")
    options.setdefault("rho_inf", p.spectral_radius)
    model = _BearingRing(p, bearing_law(p))
    traj, wall, iters, steps, info, motion, H = run(model, p, floor=1e-6 * p.preload, **options)
    finish_trajectory(traj, H)
    summary = loosening_summary(traj, p, wall, steps, iters)
    summary.update(loosening_energy(p, traj, motion=motion, law=model.law, H=H))
    return Result(traj, summary, p, info)


# ----------------------------------------------------------------------------------------------
# the cases, and the scene as every engine and the command line see it

class Case(NamedTuple):
    """What the scene does by its ``case``: each a function of the parameters p (and the run's data)."""
    closed_forms: Callable      # p -> dict of closed forms with "undefined"
    summary: Callable           # (traj, p) -> the case's summary
    energy_terms: Callable      # (p, traj, **ledger inputs) -> energy.ledger's terms
    plot: Callable              # (traj, p, fig) -> trajectory.png
    law: Callable               # p -> ContactLaw, or dict name -> ContactLaw
    points: Callable            # p -> body-local points (K, 3), or dict name -> points
    title_keys: tuple           # the summary keys in trajectory.png's title


CASES = {
    "bearing": Case(bearing_closed_forms, bearing_summary, bearing_energy_terms, PlotBearing, bearing_law,
                    bearing_ring, ("spin_rate", "spin_rate_theory")),
    "joint": Case(bolted_joint.joint_closed_forms, bolted_joint.joint_summary, bolted_joint.joint_energy_terms,
                  PlotJoint,
                  lambda p: dict(bearing=bolted_joint.bearing_law(p), thread=bolted_joint.thread_law(p)),
                  lambda p: dict(bearing=bolted_joint.bearing_points(p), thread=bolted_joint.thread_points(p)),
                  ("rotation_per_path", "rotation_per_path_theory")),
}
"""The scene's cases by name (``case``): the bearing ring dragged across the plate, or the joint
(``scenes.bolted_joint``)."""

class LooseningScene(Scene):
    """The loosening scene (the module docstring): the bearing case's law and points, or the joint's two
    contacts (bearing, thread) by name; the summary takes no inputs, the ledger ``loosening_energy``'s
    (the case's)."""

    name = "loosening"
    Params = LooseningParams
    columns = COLUMNS
    title_keys = CASES["bearing"].title_keys        # the defaults'; title_keys_for(p) by the case
    figsize = (6.0, 6.0)
    closed_forms = staticmethod(loosening_closed_forms)
    summary = staticmethod(loosening_summary)
    ledger = staticmethod(loosening_energy)
    plot = staticmethod(PlotLoosening)
    reference = staticmethod(simulate_loosening)

    def title_keys_for(self, p):
        return CASES[p.case].title_keys

    def law(self, p):
        return CASES[p.case].law(p)

    def points(self, p):
        return CASES[p.case].points(p)


SCENE = LooseningScene()
