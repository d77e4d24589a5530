"""Loosening scene: how transverse slip takes a bolted joint's friction away from its turning.

A preloaded joint loosens when its nut, or the clamped plate, is shaken across the bolt's axis: while a
contact ring slides sideways, its friction resists turning only in proportion to the spin rate, so the
pitch's torque turns the nut back. Today the scene has one case, the mechanism on the bearing face:

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
against the cycles) is the next case. Its closed forms (the pitch's torque F P / (2 pi) balanced by the
thread's and the bearing's rings in complete slip; the preload lost per radian, the joint stiffness
times P / (2 pi)) assume uniform rings that slide throughout, and a nut shaken sideways opens part of
its thread ring: its shift wedges the flank (through the lead angle alone on a square thread) by more
than the penetration that carries the preload.
"""
from __future__ import annotations

import math

import numpy as np

from exu_aniso.engines import energy
from exu_aniso.engines.reference import RUN_OPTIONS, PlanarBody, run
from exu_aniso.engines.result import Result
from exu_aniso.engines.timing import smooth_rise
from exu_aniso.fields.tensor_fields import Adhesion, Friction
from exu_aniso.geometry import Plane
from exu_aniso.kernel.contact_law import ContactLaw
from exu_aniso.law.history import HISTORY_FIELDS, SLIP
from exu_aniso.law.return_maps import DEFAULT_RETURN_MAP, RETURN_MAPS
from exu_aniso.scenes import threads
from exu_aniso.scenes.base import LEDGER_COLUMNS, SOLVERS, SceneParams, energy_ledger, scene_parameters
from exu_aniso.scenes.plotting import drawn, labelled
from exu_aniso.scenes.scene import Scene
from exu_aniso.util.validation import check_instance, check_keywords

LOOSENING_PARAMS = {
    "case": ("bearing", "-", "bearing: the nut's bearing ring dragged across the plate while a torque turns it",
             ("bearing",)),
    "preload": (1e4, "N", "the joint's preload pressing the bearing ring onto the plate", "> 0"),
    "bearing_radius": (6.6e-3, "m", "mean radius r_K of the nut's bearing ring (M10: (d_w + d_h) / 4)", "> 0"),
    "points": (24, "-", "contact points on the bearing ring (>= 3)", "int >= 1"),
    "mu_bearing": (0.12, "-", "bearing friction mu_K (isotropic)", "> 0"),
    "bearing_stiffness": (1e10, "N/m", "normal penalty stiffness of the bearing contact (total)", "> 0"),
    "sticking_stiffness": (2e8, "N/m", "sticking stiffness of the bearing contact (total; 6 um of elastic stick at the "
                           "default friction limit)", "> 0"),
    "drag": ("speed", "-", "how the ring is moved across the plate along x: speed (a stiff spring to a driver at "
             "slip_speed), ramp (a force rising at force_rate: the slip onset) or shake (a force shake_amplitude "
             "sin(2 pi shake_frequency t))", ("speed", "ramp", "shake")),
    "slip_speed": (0.02, "m/s", "drag=speed: speed at which the ring is dragged across the plate", "> 0"),
    "force_rate": (4e3, "N/s", "drag=ramp: the transverse force's rise", "> 0"),
    "shake_amplitude": (500.0, "N", "drag=shake: the transverse force's amplitude", ">= 0"),
    "shake_frequency": (12.5, "Hz", "drag=shake: its frequency (a Junker test's 12.5 Hz)", "> 0"),
    "torque": (2.0, "N m", "torque turning the ring about its axis (below mu_bearing preload bearing_radius)",
               ">= 0"),
    "load_time": (0.005, "s", "the torque rises smoothly from 0 over this time ((1 - cos(pi t / load_time)) / 2), "
                  "and a ramped or shaking force starts after it (applied at once, a torque overshoots its "
                  "static twist and can turn a ring its friction holds)", ">= 0"),
    "nut_mass": (0.011, "kg", "mass of the nut", "> 0"),
    "nut_inertia": (5e-7, "kg m^2", "the nut's moment of inertia about its axis", "> 0"),
    "drag_stiffness": (1e8, "N/m", "the spring that drags the ring along x and holds it at y = 0", "> 0"),
    "drag_damping": (1e3, "N s/m", "the dashpot beside it", ">= 0"),
    "return_map": (DEFAULT_RETURN_MAP, "-", "sliding return map", RETURN_MAPS),
    "t_end": (0.05, "s", "simulated time", "> 0"),
    "dt": (1e-4, "s", "time step", "> 0"),
    "solver": ("trapezoidal", "-", "time integrator", SOLVERS),
}


@scene_parameters(LOOSENING_PARAMS)
class LooseningParams(SceneParams):
    """A bolted joint's loosening mechanisms; see LOOSENING_PARAMS for units and meaning."""

    def contact_points(self):
        return self.points

    def _layout_text(self):
        return f"points={self.points}"

    def _check_scene(self):
        if self.points < 3:
            raise ValueError(f"points must be >= 3 (a ring); got {self.points!r}")


COLUMNS = {"t": "s", "x": "m", "y": "m", "angle": "rad", "vx": "m/s", "vy": "m/s", "omega": "rad/s",
           "drag_force": "N", "slip_fraction": "-", "slip_distance": "m", "dissipated_energy": "J", **LEDGER_COLUMNS}
"""trajectory.csv: the ring's centre, its angle and their rates, the transverse force on it along x
(the drag spring's, or the applied force), the share of its points that slide, the slip distance and
the dissipated energy, and the ledger (work in: the driver's or the force's work along x and the
torque's over the angle; kinetic: nut_mass (vx^2 + vy^2) / 2 + nut_inertia omega^2 / 2)."""
TITLE_KEYS = ("spin_rate", "spin_rate_theory")
STEADY_SHARE = 0.5      # the steady state: the last half of the run
ONSET_SPEED = 1e-2      # m/s: gross slip, the ring runs away (below the limit the partial slip creeps at under 1 mm/s
                        # at the defaults; over the limit the ring's speed grows without bound)


# ----------------------------------------------------------------------------------------------
# geometry, law, the drag

def ring_points(p):
    """Body-local points of the bearing ring (points, 3) on bearing_radius, z = 0."""
    a = 2.0 * math.pi * np.arange(p.points) / p.points
    return np.column_stack([p.bearing_radius * np.cos(a), p.bearing_radius * np.sin(a), np.zeros(p.points)])


def bearing_contact_law(p):
    """ContactLaw of the bearing face on the plate (the plane z = 0, isotropic), stiffnesses split over the
    points."""
    K = p.points
    return ContactLaw(Plane(), Adhesion.isotropic(p.sticking_stiffness / K), Friction.isotropic(p.mu_bearing),
                      normal_stiffness=p.bearing_stiffness / K, return_map=p.return_map)


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
    """The cost and, by the drag: speed, the ring's spin rate (its mean over the last STEADY_SHARE of the
    run) and the drag force there beside their closed forms; ramp, the slip onset (``onset_force``: the
    transverse force at the first sample where the ring's speed reaches ONSET_SPEED, gross slip) beside
    ``onset_force_theory``;
    shake, the ring's largest turn (``rotation_max`` [rad]), its turn per cycle between the first and the
    last whole cycle's ends (``rotation_per_cycle`` [rad]: a ratchet) and whether it ever slid as a whole,
    over ``cycles`` whole cycles of the shaking."""
    t = np.asarray(traj["t"], float)
    theory = loosening_closed_forms(p)
    s = dict(torque_ratio=theory["torque_ratio"], slip_distance=float(traj["slip_distance"][-1]),
             dissipated_energy=float(traj["dissipated_energy"][-1]), wall_s=float(wall_s), steps=int(steps),
             newton_iterations=int(newton_iterations), undefined={})
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
        ends = p.load_time + np.arange(1, int((t[-1] - p.load_time) * p.shake_frequency + 1e-9) + 1) / p.shake_frequency
        at = np.interp(ends, t, angle)
        s.update(rotation_max=float(np.max(np.abs(angle - angle[0]))), slid_as_a_whole=bool(len(whole)),
                 cycles=float(len(ends)), rotation_per_cycle=None)
        if len(ends) >= 2:      # the angle at the same phase of the first and the last whole cycle
            s["rotation_per_cycle"] = float((at[-1] - at[0]) / (len(ends) - 1))
        else:
            s["undefined"]["rotation_per_cycle"] = "fewer than 2 whole cycles of the shaking: run longer"
    return s


def loosening_energy(p, traj, motion, law, H):
    """Energy ledger of a run (any engine): work in, the drag springs' forces over the ring's travel and
    the torque over its angle; kinetic; the drag springs' own energy and the contact's stored energy;
    the contact's and the drag dashpots' dissipation."""
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
    stored, diss = energy.rigid_contact_energy(law, motion, ring_points(p) + np.array([0.0, 0.0, held_gap(p)]), H)
    kinetic = 0.5 * p.nut_mass * (vx ** 2 + vy ** 2) + 0.5 * p.nut_inertia * np.asarray(traj["omega"], float) ** 2
    return energy_ledger(dict(work_in=work, kinetic=kinetic, potential=springs, stored=stored,
                              dissipated=diss + dashpots), traj, "loosening run")


# ----------------------------------------------------------------------------------------------
# the plot of trajectory.png

def PlotLoosening(traj, params, fig):
    """trajectory.png: the ring's spin rate over time with its closed form."""
    t, w = drawn(np.asarray(traj["t"]), np.asarray(traj["omega"]))
    ax = fig.add_subplot(1, 1, 1)
    ax.plot(t, w, label="spin rate")
    theory = loosening_closed_forms(params)["spin_rate_theory"]
    if theory is not None:
        ax.axhline(theory, color="k", ls="--", lw=0.8, label=f"ring integral: {theory:.5g} rad/s")
    labelled(ax, "t [s]", "omega [rad/s]")


# ----------------------------------------------------------------------------------------------
# the reference engine's body model and run

class _BearingRing(PlanarBody):
    def __init__(self, p, law):
        self.p = p
        super().__init__(law, ring_points(p)[:, :2], p.nut_mass, p.nut_inertia, p.bearing_radius,
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
    model = _BearingRing(p, bearing_contact_law(p))
    traj, wall, iters, steps, info, motion, H = run(model, p, floor=1e-6 * p.preload, **options)
    finish_trajectory(traj, H)
    summary = loosening_summary(traj, p, wall, steps, iters)
    summary.update(loosening_energy(p, traj, motion, model.law, H))
    return Result(traj, summary, p, info)


# ----------------------------------------------------------------------------------------------
# the scene, as every engine and the command line see it

class LooseningScene(Scene):
    """The loosening scene (the module docstring); the summary takes no inputs, the ledger
    ``loosening_energy``'s (motion, law, H)."""

    name = "loosening"
    Params = LooseningParams
    columns = COLUMNS
    title_keys = TITLE_KEYS
    figsize = (6.0, 4.5)
    law = staticmethod(bearing_contact_law)
    points = staticmethod(ring_points)
    closed_forms = staticmethod(loosening_closed_forms)
    summary = staticmethod(loosening_summary)
    ledger = staticmethod(loosening_energy)
    plot = staticmethod(PlotLoosening)
    reference = staticmethod(simulate_loosening)


SCENE = LooseningScene()
