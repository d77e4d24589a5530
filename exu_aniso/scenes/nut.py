"""Nut scene: a free nut on a fixed vertical bolt, under its own weight (does it hold, or run down?).

The bolt's thread is fixed: its upper flank is a ``geometry.Helicoid`` about the z axis (pitch P,
thread angle beta = ``flank_angle``, pitch diameter d2, right hand, ``flank_of="bolt"``), and the nut
rests on it from above (side "forward"). The nut is rigid, of mass ``nut_mass`` and axial moment of
inertia ``nut_inertia``; its thread carries ``turns`` x ``points_per_turn`` contact points on the flank
at the pitch radius r2 = d2 / 2. Gravity ``gravity`` pulls it down (-z); nothing else acts: no head,
no drive. It starts at rest touching the flank, and its weight rises smoothly over ``load_time`` (the
nut is set down: a weight applied at once would overshoot the tangential springs' static load and
slip a nut that holds at rest).

Models: ``model="reduced"``, the nut on a screw joint along the bolt's axis (q = (angle, z): every
point of the layout has the same state there, so one representative point carries the totals);
``model="full"``, a 6-DOF rigid nut, centred by the flank's radial normal components all round.

Friction on the flank: ``mu_thread`` along the helix, isotropic or an orthotropic net whose direction 1
is the helix (the chart's phi line; ``mu_thread_2`` across it). The nut slides along the helix, a
principal direction, so the sliding law is mu_thread N there with every return map.

Closed forms (``scenes.threads``): the nut holds when mu_thread >= tan(phi) cos(beta_n)
(``self_locking_friction``; phi the lead angle, beta_n the flank's half angle in the helix's normal
section); below it runs down at the constant axial acceleration of ``nut_descent``, set by the mass,
the inertia, the lead, the flank angle and mu. Stiffnesses are totals (docs/guide/conventions.md).

Summary (every engine; ``nut_summary``): the end state, ``held`` (the thread slides less than a
millionth of the pitch over the last tenth of the run), ``descent_acceleration`` (the slope of vz
over the second half while the nut slides) beside ``descent_acceleration_theory``,
``self_locking_mu_theory``, and the energy ledger (``nut_energy``: the weight's work in).
"""
from __future__ import annotations

import math

import numpy as np

from exu_aniso.engines import energy
from exu_aniso.engines.reference import RUN_OPTIONS, RigidBody6, ScrewJoint, run
from exu_aniso.engines.result import Result
from exu_aniso.engines.timing import smooth_rise
from exu_aniso.fields.tensor_fields import Adhesion, Friction
from exu_aniso.geometry import Helicoid
from exu_aniso.kernel.contact_law import ContactLaw
from exu_aniso.law.history import HISTORY_FIELDS, SLIP, STICK
from exu_aniso.law.return_maps import DEFAULT_RETURN_MAP, RETURN_MAPS
from exu_aniso.scenes import threads
from exu_aniso.scenes.base import LEDGER_COLUMNS, SOLVERS, SceneParams, energy_ledger, scene_parameters
from exu_aniso.scenes.plotting import drawn, labelled
from exu_aniso.scenes.scene import Scene
from exu_aniso.util.validation import check_instance, check_keywords

NUT_PARAMS = {
    "model": ("reduced", "-", "reduced: the nut on a screw joint (one representative point); full: a 6-DOF rigid "
              "nut", ("reduced", "full")),
    "d2": (9.026e-3, "m", "pitch diameter (M10: 9.026 mm)", "> 0"),
    "pitch": (1.5e-3, "m", "thread pitch P (M10: 1.5 mm)", "> 0"),
    "flank_angle": (60.0, "deg", "thread angle beta, full (metric: 60), in [0, 180)", ">= 0"),
    "mu_thread": (0.02, "-", "flank friction along the helix (a greased thread; the nut holds from "
                  "tan(phi) cos(beta_n), 0.0458 for M10)", "> 0"),
    "thread_net": ("isotropic", "-", "friction field on the flank: isotropic or orthotropic (direction 1 along the "
                   "helix)", ("isotropic", "orthotropic")),
    "mu_thread_2": (0.3, "-", "flank friction across the helix (thread_net orthotropic)", "> 0"),
    "nut_mass": (0.011, "kg", "mass of the nut (an M10 nut: 11 g)", "> 0"),
    "nut_inertia": (5e-7, "kg m^2", "the nut's moment of inertia about the bolt's axis", "> 0"),
    "nut_height": (8e-3, "m", "height of the nut (its inertia across the axis: nut_inertia / 2 + nut_mass "
                   "nut_height^2 / 12)", "> 0"),
    "turns": (3, "-", "engaged thread turns carrying points", "int >= 1"),
    "points_per_turn": (8, "-", "thread points per turn (>= 3)", "int >= 1"),
    "thread_stiffness": (1e8, "N/m", "normal penalty stiffness of the thread contact (total)", "> 0"),
    "sticking_stiffness": (1e7, "N/m", "sticking stiffness of the thread contact (total)", "> 0"),
    "gravity": (9.81, "m/s^2", "gravity along -z", "> 0"),
    "load_time": (0.02, "s", "the weight rises smoothly from 0 over this time ((1 - cos(pi t / load_time)) / 2): the "
                  "nut is set down, not dropped", ">= 0"),
    "return_map": (DEFAULT_RETURN_MAP, "-", "sliding return map", RETURN_MAPS),
    "t_end": (0.5, "s", "simulated time", "> 0"),
    "dt": (4e-4, "s", "time step (the reduced model's; the full nut needs 1e-4 or less under the trapezoidal rule: "
           "python studies/nut.py)", "> 0"),
    "solver": ("trapezoidal", "-", "time integrator", SOLVERS),
}


@scene_parameters(NUT_PARAMS)
class NutParams(SceneParams):
    """A free nut on a vertical bolt; see NUT_PARAMS for units and meaning."""

    def contact_points(self):
        return self.turns * self.points_per_turn

    def _layout_text(self):
        return f"turns={self.turns} x points_per_turn={self.points_per_turn}"

    def _check_scene(self):
        if not self.flank_angle < 180.0:
            raise ValueError(f"flank_angle must lie in [0, 180) deg; got {self.flank_angle!r}")
        if self.points_per_turn < 3:
            raise ValueError(f"points_per_turn must be >= 3 (the nut is centred by points all round); got "
                             f"{self.points_per_turn!r}")
        if not self.turns * self.pitch <= self.nut_height:
            raise ValueError(f"turns * pitch must be <= nut_height (the engaged turns lie in the nut); got "
                             f"{self.turns} * {self.pitch!r} > {self.nut_height!r}")


COLUMNS = {"t": "s", "angle": "rad", "z": "m", "omega": "rad/s", "vz": "m/s", "weight": "N",
           "normal_force": "N", "stick_fraction": "-", "slip_fraction": "-", "slip_distance": "m",
           "dissipated_energy": "J",
           # the full model's other motions (the reduced model has none)
           "x": "m", "y": "m", "vx": "m/s", "vy": "m/s", "tilt": "rad", "omega_x": "rad/s", "omega_y": "rad/s",
           **LEDGER_COLUMNS}
"""trajectory.csv: the nut's angle (unwrapped yaw) and height (its centre of mass), their rates, its
weight as it rises (the force along -z, ``weight_force``), the thread's total normal force (the sum
of |N| over the points: one point of the reduced model carries the total), the shares of the points
that stick and that slide, the slip distance, the dissipated energy and the ledger; the full model
adds the centre's lateral position and velocity, the tilt of the nut's axis and the angular velocity
across the axis (world frame). Kinetic energy: nut_mass |v|^2 / 2 + nut_inertia
omega^2 / 2 (+ the transverse inertia's share of omega_x, omega_y); work in: the weight over the
descent (a trapezoid of weight over z0 - z)."""
TITLE_KEYS = ("descent_acceleration", "descent_acceleration_theory")

HELD_SHARE = 0.1        # held: the nut slides less than HELD_SLIP pitch over this last share of the run
HELD_SLIP = 1e-6        # (a held nut's points still reach the friction limit now and then by round-off)
_NORMAL = HISTORY_FIELDS.index("normal")
_STATUS = HISTORY_FIELDS.index("status")


# ----------------------------------------------------------------------------------------------
# geometry, law, inertia, initial state

def lead(p):
    """Axial advance per radian, h = P / (2 pi) [m/rad]."""
    return p.pitch / (2.0 * math.pi)


def thread_surface(p):
    """The bolt's upper flank, fixed to ground: the Helicoid through z = h phi at r2 (world frame)."""
    return Helicoid(p.pitch, math.radians(p.flank_angle), p.d2, hand="right", flank_of="bolt", side="forward")


def centre_height(p):
    """Height of the nut's centre above the flank's reference z = 0 at phi = 0 [m]: the middle of the
    points' span."""
    return lead(p) * 2.0 * math.pi * (p.contact_points() - 1) / (2.0 * p.points_per_turn)


def nut_points(p, representative=False):
    """Body-local thread points (K, 3) from the nut's centre: on the flank at the pitch radius, at phi =
    2 pi j / points_per_turn over the engaged turns; representative: the one point at phi = 0."""
    n = 1 if representative else p.contact_points()
    phi = 2.0 * math.pi * np.arange(n) / p.points_per_turn
    r = 0.5 * p.d2
    return np.column_stack([r * np.cos(phi), r * np.sin(phi), lead(p) * phi - centre_height(p)])


def nut_contact_law(p, representative=False):
    """ContactLaw of the flank, stiffnesses split over the points (representative: one point carries the
    totals)."""
    K = 1 if representative else p.contact_points()
    F = (Friction.orthotropic(p.mu_thread, p.mu_thread_2, angle=0.0) if p.thread_net == "orthotropic"
         else Friction.isotropic(p.mu_thread))
    return ContactLaw(thread_surface(p), Adhesion.isotropic(p.sticking_stiffness / K), F,
                      normal_stiffness=p.thread_stiffness / K, return_map=p.return_map)


def nut_inertia(p):
    """Mass [kg] and body-frame inertia (3, 3) [kg m^2]: nut_inertia about the axis, nut_inertia / 2 +
    nut_mass nut_height^2 / 12 across it (a short tube's)."""
    Jt = 0.5 * p.nut_inertia + p.nut_mass * p.nut_height ** 2 / 12.0
    return p.nut_mass, np.diag([Jt, Jt, p.nut_inertia])


def weight_force(p, t):
    """The nut's weight at time t [s] (scalar or array) [N], rising as (1 - cos(pi t / load_time)) / 2
    to nut_mass gravity at load_time."""
    return p.nut_mass * p.gravity * smooth_rise(t, p.load_time)


# ----------------------------------------------------------------------------------------------
# closed forms

def nut_closed_forms(p):
    """``self_locking_mu_theory`` [-] and ``descent_acceleration_theory`` [m/s^2] (negative: down; None,
    with the reason, when the nut holds), ``scenes.threads``."""
    beta = math.radians(p.flank_angle)
    out = dict(self_locking_mu_theory=threads.self_locking_friction(p.d2, p.pitch, beta), undefined={})
    try:
        out["descent_acceleration_theory"] = threads.nut_descent(p.d2, p.pitch, beta, p.mu_thread, p.nut_mass,
                                                                 p.nut_inertia, p.gravity)[0]
    except ValueError as e:
        out["descent_acceleration_theory"] = None
        out["undefined"]["descent_acceleration_theory"] = str(e).replace("mu:", "mu_thread:", 1)
    return out


# ----------------------------------------------------------------------------------------------
# trajectory, summary, energy (every engine)

def finish_trajectory(traj, H):
    """Add the thread's total normal force and the shares of sticking and sliding points from the history
    H (n, K, 9)."""
    traj["normal_force"] = -H[:, :, _NORMAL].sum(axis=1)
    traj["stick_fraction"] = (H[:, :, _STATUS] == STICK).mean(axis=1)
    traj["slip_fraction"] = (H[:, :, _STATUS] == SLIP).mean(axis=1)
    return traj


def nut_summary(traj, p, wall_s, steps, newton_iterations):
    """End state, ``held`` (the slip distance over the last HELD_SHARE of the run is at most HELD_SLIP
    pitch: a held nut's points reach the friction limit now and then by round-off, slipping 1e-17 m),
    the descent's
    acceleration (a straight line through vz over the second half, where every point slides; None with
    the reason when fewer than 3 samples slide) beside its closed form, and the cost."""
    t, vz = np.asarray(traj["t"], float), np.asarray(traj["vz"], float)
    slide = np.asarray(traj["slip_fraction"], float) == 1.0
    theory = nut_closed_forms(p)
    undefined = dict(theory["undefined"])
    late = (t >= 0.5 * t[-1]) & slide
    if late.sum() >= 3:
        acceleration = float(np.polyfit(t[late], vz[late], 1)[0])
    else:
        acceleration = None
        undefined["descent_acceleration"] = (f"{int(late.sum())} samples of the second half slide: fewer than 3 "
                                             "to fit (the nut holds)")
    slip = np.asarray(traj["slip_distance"], float)
    tail_slip = slip[-1] - np.interp(t[-1] - HELD_SHARE * (t[-1] - t[0]), t, slip)
    return dict(angle_end=float(traj["angle"][-1]), z_end=float(traj["z"][-1]),
                descent=float(traj["z"][0] - traj["z"][-1]), omega_end=float(traj["omega"][-1]),
                vz_end=float(vz[-1]), held=bool(tail_slip <= HELD_SLIP * p.pitch),
                descent_acceleration=acceleration,
                descent_acceleration_theory=theory["descent_acceleration_theory"],
                self_locking_mu_theory=theory["self_locking_mu_theory"],
                slip_distance=float(traj["slip_distance"][-1]),
                dissipated_energy=float(traj["dissipated_energy"][-1]),
                wall_s=float(wall_s), steps=int(steps), newton_iterations=int(newton_iterations),
                undefined=undefined)


def reduced_motion(traj):
    """energy.RigidMotion of the nut on its screw joint from its trajectory's coordinates."""
    return energy.motion_about_z(0.0, 0.0, traj["z"], traj["angle"], 0.0, 0.0, traj["vz"], traj["omega"])


def nut_energy(p, traj, motion, points, law, H):
    """Energy ledger of a nut run (any engine): work in, the weight over the descent; kinetic; the
    contact's stored and dissipated energy at the evaluated points (one representative point of the
    reduced model carries the totals). The full model's trajectory gains vx, vy, omega_x and
    omega_y (world), so the kinetic energy can be recomputed from trajectory.csv."""
    if p.model == "full":
        traj.update(vx=motion.velocity[:, 0], vy=motion.velocity[:, 1], omega_x=motion.omega[:, 0],
                    omega_y=motion.omega[:, 1])
    mass, J = nut_inertia(p)
    stored, diss = energy.rigid_contact_energy(law, motion, points, H)
    z = np.asarray(traj["z"], float)
    traj["weight"] = weight_force(p, traj["t"])
    return energy_ledger(dict(work_in=-energy.work_trapezoid(traj["weight"], z),
                              kinetic=energy.rigid_kinetic(motion, mass, J), potential=np.zeros(len(z)),
                              stored=stored, dissipated=diss), traj, "nut run")


# ----------------------------------------------------------------------------------------------
# the plot of trajectory.png

def PlotNut(traj, params, fig):
    """trajectory.png: the nut's descent z0 - z over time (top) and its axial velocity with the closed
    form's line v = a t where the nut runs down (bottom)."""
    p = params
    t, z, vz = drawn(np.asarray(traj["t"]), np.asarray(traj["z"]), np.asarray(traj["vz"]))
    ax = fig.add_subplot(2, 1, 1)
    ax.plot(t, 1e3 * (z[0] - z), label="descent")
    labelled(ax, "t [s]", "z0 - z [mm]")
    ax = fig.add_subplot(2, 1, 2)
    ax.plot(t, 1e3 * vz, label="vz")
    a = nut_closed_forms(p)["descent_acceleration_theory"]
    if a is not None:
        ax.plot(t, 1e3 * a * (t - t[0]), "k--", lw=0.8, label=f"closed form, a = {a:.4g} m/s^2 (from rest)")
    labelled(ax, "t [s]", "vz [mm/s]")


# ----------------------------------------------------------------------------------------------
# the reference engine's body models and run

class _NutReduced(ScrewJoint):
    def __init__(self, p, law):
        self.p = p
        super().__init__(law, nut_points(p, representative=True), p.nut_mass, p.nut_inertia, 0.5 * p.d2,
                         q0=(0.0, centre_height(p)))

    def external(self, q, t):
        return 0.0, 0.0, -float(weight_force(self.p, t)), 0.0

    def record(self, q, v, t, st):
        return dict(angle=q[0], z=q[1], omega=v[0], vz=v[1])


class _NutFull(RigidBody6):
    def __init__(self, p, law):
        self.p = p
        m, J = nut_inertia(p)
        super().__init__(law, nut_points(p), m, np.diag(J), [0.0, 0.0, centre_height(p)], 0.5 * p.d2)

    def external(self, q, t):
        weight = np.array([0.0, 0.0, -float(weight_force(self.p, t))])
        return weight, np.zeros(3), np.zeros((3, 3)), np.zeros(3)

    def record(self, q, v, t, st):
        r, R, yaw = q
        w = self.world_omega(q, v)
        return dict(angle=yaw, z=r[2], omega=w[2], vz=v[2], x=r[0], y=r[1],
                    tilt=math.acos(max(-1.0, min(1.0, R[2, 2]))))


def simulate_nut(params=None, **options):
    """The nut scene with the reference integrator; params: NutParams (defaults if None). Options as for
    simulate_block. Newton's force floor is the block's convention, 1e-6 of the force of a penetration
    d2 deep (thread_stiffness d2): the nut's weight is far below the penalty forces' round-off
    (thread_stiffness times a double's resolution of z). Returns Result."""
    p = NutParams() if params is None else params
    check_instance("params", p, NutParams)
    check_keywords("simulate_nut", options, RUN_OPTIONS)
    reduced = p.model == "reduced"
    model = (_NutReduced if reduced else _NutFull)(p, nut_contact_law(p, representative=reduced))
    floor = 1e-6 * p.thread_stiffness * p.d2
    traj, wall, iters, steps, info, motion, H = run(model, p, floor=floor, **options)
    finish_trajectory(traj, H)
    summary = nut_summary(traj, p, wall, steps, iters)
    summary.update(nut_energy(p, traj, motion, model.s, model.law, H))
    return Result(traj, summary, p, info)


# ----------------------------------------------------------------------------------------------
# the scene, as every engine and the command line see it

class NutScene(Scene):
    """The nut scene (the module docstring); the summary takes no inputs, the ledger ``nut_energy``'s
    (motion, points, law, H)."""

    name = "nut"
    Params = NutParams
    columns = COLUMNS
    title_keys = TITLE_KEYS
    figsize = (6.0, 6.0)
    law = staticmethod(nut_contact_law)
    points = staticmethod(nut_points)
    closed_forms = staticmethod(nut_closed_forms)
    summary = staticmethod(nut_summary)
    ledger = staticmethod(nut_energy)
    plot = staticmethod(PlotNut)
    reference = staticmethod(simulate_nut)


SCENE = NutScene()
