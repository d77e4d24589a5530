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

Closed form (``scenes.threads``): in the steady state the ring turns at omega = s v / r, where
G(s) = T / (mu N r) and G, the ring integral of Coulomb friction against every point's slip velocity
v e_x + omega r e_phi, grows as s / 2 for s << 1 (``ring_torque_factor``, ``ring_spin_ratio``): the
summary's ``spin_rate`` against ``spin_rate_theory``.

The preloaded joint (``case="joint"``: bolt, nut and plate, the nut shaken across the axis, the preload
against the cycles) is the next case; its closed forms (the pitch's torque F P / (2 pi) balanced by
the thread's and the bearing's rings; the preload lost per radian, the joint stiffness times P / (2
pi)) need the thread's transverse slip, which the rigid nut on a helicoid does not give.
"""
from __future__ import annotations

import math

import numpy as np

from exu_aniso.engines import energy
from exu_aniso.engines.reference import RUN_OPTIONS, PlanarBody, run
from exu_aniso.engines.result import Result
from exu_aniso.fields.tensor_fields import Adhesion, Friction
from exu_aniso.geometry import Plane
from exu_aniso.kernel.contact_law import ContactLaw
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
    "slip_speed": (0.02, "m/s", "speed at which the ring is dragged across the plate (along x)", "> 0"),
    "torque": (2.0, "N m", "torque turning the ring about its axis (below mu_bearing preload bearing_radius)",
               ">= 0"),
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
           "drag_force": "N", "slip_distance": "m", "dissipated_energy": "J", **LEDGER_COLUMNS}
"""trajectory.csv: the ring's centre, its angle and their rates, the drag spring's force along x, the
slip distance and the dissipated energy, and the ledger (work in: the drag force over x, the torque
over the angle and the y spring's force over y; kinetic: nut_mass (vx^2 + vy^2) / 2 + nut_inertia
omega^2 / 2)."""
TITLE_KEYS = ("spin_rate", "spin_rate_theory")
STEADY_SHARE = 0.5      # the steady state: the last half of the run


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


def drag_force(p, x, y, vx, vy, t):
    """The drag springs' force (2,) on the ring: along x to the driver at slip_speed t, along y to 0,
    with their dashpots."""
    return np.array([p.drag_stiffness * (p.slip_speed * t - x) + p.drag_damping * (p.slip_speed - vx),
                     -p.drag_stiffness * y - p.drag_damping * vy])


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


# ----------------------------------------------------------------------------------------------
# summary, energy

def loosening_summary(traj, p, wall_s, steps, newton_iterations):
    """The ring's spin rate, its mean over the last STEADY_SHARE of the run, beside its closed form, the
    drag force there, and the cost."""
    t = np.asarray(traj["t"], float)
    late = t >= t[-1] - STEADY_SHARE * (t[-1] - t[0])
    theory = loosening_closed_forms(p)
    return dict(spin_rate=float(np.mean(np.asarray(traj["omega"], float)[late])),
                spin_rate_theory=theory["spin_rate_theory"], torque_ratio=theory["torque_ratio"],
                drag_force_mean=float(np.mean(np.asarray(traj["drag_force"], float)[late])),
                drag_force_theory=theory["drag_force_theory"],
                slip_distance=float(traj["slip_distance"][-1]), dissipated_energy=float(traj["dissipated_energy"][-1]),
                wall_s=float(wall_s), steps=int(steps), newton_iterations=int(newton_iterations),
                undefined=dict(theory["undefined"]))


def loosening_energy(p, traj, motion, law, H):
    """Energy ledger of a run (any engine): work in, the drag springs' forces over the ring's travel and
    the torque over its angle; kinetic; the drag springs' own energy and the contact's stored energy;
    the contact's and the drag dashpots' dissipation."""
    x, y = np.asarray(traj["x"], float), np.asarray(traj["y"], float)
    vx, vy = np.asarray(traj["vx"], float), np.asarray(traj["vy"], float)
    t = np.asarray(traj["t"], float)
    travel = p.slip_speed * t
    stretch_x = travel - x
    # the driver's work: the spring-and-dashpot force along x over the driver's travel, and the torque's
    work = (energy.work_trapezoid(traj["drag_force"], travel) + energy.work_trapezoid(np.full(len(t), p.torque),
                                                                                      traj["angle"]))
    springs = 0.5 * p.drag_stiffness * (stretch_x ** 2 + y ** 2)
    dashpots = (energy.work_trapezoid(p.drag_damping * (p.slip_speed - vx), stretch_x)
                + energy.work_trapezoid(p.drag_damping * vy, y))
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
        return drag_force(p, q[0], q[1], v[0], v[1], t), -k * np.eye(2), -c * np.eye(2)

    def torque(self, q, v, t):
        return self.p.torque, 0.0, 0.0

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
