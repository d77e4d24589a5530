"""Fastening scene: a bolt tightened into a nut, as fastening engineers see it.

A rigid bolt (6 DOF, axis z from its head towards its tip) is turned about +z by a rotation drive
through a torsional spring (``drive_stiffness``, driver at ``rotation_speed``) slowly enough to be
quasi-static. Its thread has ``turns`` x ``points_per_turn`` contact points at the pitch radius
r2 = d2/2; its head's underside has ``head_points`` points on the mean bearing radius
``head_radius``. A right-hand thread: turning by +angle advances the bolt by P angle / (2 pi).

* Thread, ``thread=flank``: the nut's load flank is a ``geometry.Helicoid`` fixed to ground (pitch P,
  thread angle beta = ``flank_angle``), the bolt's points lie on it. The bolt's tooth bears on the
  nut's flank on its +z side (the bolt is pulled into the nut), so the slave side is "forward".
  ``thread=net``: today's reduced model, a hole (Cylinder of radius r2) with a spiral friction net at
  the lead angle; the points sit at r2 + interference (``net_normal_force``, total, split over them).
* Head: the underside ring lands on the top face of the clamped part (a Plane of a moving master,
  side "back": the head is on the part's -z side), after ``rundown_angle`` of free turning. The
  part only moves along z, on a spring of ``joint_stiffness`` (the joint's compliance: the part's and
  the bolt's elasticity lumped) with a dashpot of ``joint_damping_ratio``.
* A small ``axial_load`` pulls the bolt back (-z) so that its flank stays on the nut's during run-down
  (the other flank, with its play, is not modelled).

Fields: isotropic on the flank (``mu_thread``), isotropic or orthotropic on the head bearing (a
machined lay: ``mu_head`` along the lay at ``head_net_angle`` from the part's x axis, ``mu_head_2``
across). Stiffnesses are totals, split over the points of a contact (docs/guide/conventions.md, "Per point or per set").

Measured (``fastening_summary``): the torque-angle curve (drive torque = the torsional spring's),
the thread and head torques (the contact forces' moments about the axis, as the drive must supply
them) and the clamp force (the head's axial contact force). In the tightening phase (clamp force
above TIGHTENING_FROM of its end value) least squares give T/F, T_thread/F, T_head/F and dF/dangle,
and the seating (snug) angle where that line of clamp force over angle reaches zero force; the theory
is ISO 16047 / VDI 2230's (``exu_aniso.scenes.threads``; the seating angle: ``seating_angle_rad``), reported
only inside its assumptions (else None with a reason under "undefined"), and the ISO 16047 evaluation
backs friction values out of the simulated torques. Untightening: from ``reverse_time`` the driver
turns back, and the summary adds the break-loose torque against the loosening closed forms
(``fastening_phases.break_loose``). The tool: ``tool="nutrunner"`` shuts off at ``shutoff_torque`` or ``shutoff_angle``
and holds that torque while its inertia runs on; the summary adds the overshoot against omega sqrt(J
k_T) and the joint's ISO 5393 class (``fastening_phases.shutoff``). solver=trapezoidal and spectral_radius above
MAX_SPECTRAL_RADIUS are refused (the unresolved contact vibrations must be damped numerically).
"""
from __future__ import annotations

import functools
import math

import numpy as np

from exu_aniso.engines import energy
from exu_aniso.scenes import threads
from exu_aniso.scenes.fastening_phases import break_loose, shutoff
from exu_aniso.kernel.contact_law import ContactLaw
from exu_aniso.fields.tensor_fields import Adhesion, Friction
from exu_aniso.geometry import Cylinder, Helicoid, Plane
from exu_aniso.geometry.helicoid import lead_angle
from exu_aniso.law.return_maps import DEFAULT_RETURN_MAP, RETURN_MAPS
from exu_aniso.scenes.base import LEDGER_COLUMNS, SOLVERS, energy_ledger, SceneParams, scene_parameters
from exu_aniso.scenes.scene import Scene
from exu_aniso.util.validation import ParameterError

FASTENING_PARAMS = {
    "thread": ("flank", "-", "thread model: the nut's flank (helicoid) or a spiral net on a cylinder (reduced)",
               ("flank", "net")),
    "d2": (9.026e-3, "m", "pitch diameter (M10: 9.026 mm)", "> 0"),
    "pitch": (1.5e-3, "m", "thread pitch P (M10: 1.5 mm)", "> 0"),
    "flank_angle": (60.0, "deg", "thread angle beta, full (metric: 60), in [0, 180)", ">= 0"),
    "mu_thread": (0.12, "-", "thread friction mu_G (flank; orthotropic: along the helix; net: see net_mu_along)",
                  "> 0"),
    "thread_net": ("isotropic", "-", "friction field on the flank: isotropic or orthotropic (direction 1 along the "
                   "helix, the phi coordinate line)", ("isotropic", "orthotropic")),
    "mu_thread_2": (0.3, "-", "flank friction across the helix (thread_net orthotropic)", "> 0"),
    "mu_head": (0.12, "-", "head bearing friction mu_K (orthotropic: along the lay)", "> 0"),
    "head_net": ("isotropic", "-", "head bearing field: isotropic or orthotropic (a machined lay)",
                 ("isotropic", "orthotropic")),
    "mu_head_2": (0.2, "-", "head bearing friction across the lay (head_net orthotropic)", "> 0"),
    "head_net_angle": (0.0, "deg", "direction 1 of head_net (the lay) from the clamped part's x axis", "real"),
    "head_radius": (6.6e-3, "m", "mean bearing radius r_K of the head (M10: (d_w + d_h)/4)", "> 0"),
    "joint_stiffness": (1e8, "N/m", "clamped part's spring: the joint's compliance (part and bolt)", "> 0"),
    "joint_damping_ratio": (1.0, "-", "damping ratio of the clamped part on its spring", ">= 0"),
    "thread_stiffness": (1e10, "N/m", "normal penalty stiffness of the thread contact (total)", "> 0"),
    "head_stiffness": (1e10, "N/m", "normal penalty stiffness of the head contact (total)", "> 0"),
    "sticking_stiffness": (2e9, "N/m", "sticking stiffness of thread and head contacts (each total)", "> 0"),
    "net_mu_along": (0.0, "-", "thread=net: friction along the helix (0: calibrated to the flank's thread "
                     "torque, exu_aniso.calibration)", ">= 0"),
    "net_mu_across": (3.0, "-", "thread=net: friction across the helix (carries the clamp force)", "> 0"),
    "net_normal_force": (2e4, "N", "thread=net: normal force of the interference fit (total)", "> 0"),
    "points_per_turn": (8, "-", "thread points per turn (>= 3)", "int >= 1"),
    "turns": (3, "-", "engaged thread turns carrying points", "int >= 1"),
    "head_points": (8, "-", "points on the head's bearing ring (>= 3)", "int >= 1"),
    "rundown_angle": (30.0, "deg", "free turning before the head touches the part", ">= 0"),
    "axial_load": (500.0, "N", "force pulling the bolt back (-z) on its flank during run-down", ">= 0"),
    "bolt_mass": (0.04, "kg", "mass of the bolt (a cylinder of diameter d2 and length bolt_length)", "> 0"),
    "bolt_length": (0.05, "m", "length of the bolt", "> 0"),
    "part_mass": (0.2, "kg", "mass of the clamped part", "> 0"),
    "rotation_speed": (1.0, "rad/s", "speed of the rotation drive", "> 0"),
    "tool": ("spring", "-", "the drive: a torsional spring to a driver turning at rotation_speed (spring), or a "
             "nutrunner: the same until it shuts off, then holding its shut-off torque while its rotating inertia "
             "(tool_inertia) runs on into the joint", ("spring", "nutrunner")),
    "tool_inertia": (1e-3, "kg m^2", "nutrunner: rotating inertia of motor, gears and spindle, turning with the bolt",
                     ">= 0"),
    "shutoff_torque": (0.0, "N m", "nutrunner: drive torque at which it shuts off (0: not by torque)", ">= 0"),
    "shutoff_angle": (0.0, "deg", "nutrunner: bolt angle at which it shuts off (0: not by angle; the first of the two "
                      "reached)", ">= 0"),
    "reverse_time": (0.0, "s", "the driver turns back at rotation_speed from this time on (untightening: the "
                     "break-loose torque); 0: it never does", ">= 0"),
    "drive_stiffness": (2e3, "N m/rad", "torsional spring between driver and bolt", "> 0"),
    "return_map": (DEFAULT_RETURN_MAP, "-", "sliding return map", RETURN_MAPS),
    "t_end": (1.5, "s", "simulated time", "> 0"),
    "dt": (1e-3, "s", "time step", "> 0"),
    "solver": ("generalized_alpha", "-", "time integrator (numerical damping of the stiff contact modes; "
               "trapezoidal is refused: it leaves them undamped and runs away)", SOLVERS),
    "spectral_radius": (0.0, "-", "generalized-alpha's rho_inf, at most 0.6 here: 0 removes the unresolved contact "
                        "and drive vibrations in one step (quasi-static tightening)", ">= 0"),
}


MAX_SPECTRAL_RADIUS = 0.6
"""Largest generalized-alpha rho_inf the scene accepts. Its contact and drive vibrations (thread and head
penalty modes ~4e5 rad/s, the drive spring's ~7e4 rad/s at the defaults) are far from resolved at any
practical dt and must be damped numerically: left undamped they grow through the contact nonlinearity
(stick and slip do not matter: a nearly frictionless thread does the same). At the defaults up to 0.6
runs at dt; above it the step shrinks, then the run stops at the step's floor, and the undamped rule
(1, or the trapezoidal rule) tilts the bolt and clamps it far beyond the joint within the run-down."""
TRAPEZOIDAL_REFUSED = (
    "solver='trapezoidal' is not available for the fastening scene: the rule is that its stiff contact and drive "
    "vibrations (not resolved at any practical dt) must be damped numerically, and the trapezoidal rule does not "
    "damp them, so they grow until the step collapses (default scene: the bolt tilts 1.4 deg within 50 ms of "
    f"run-down); use solver='generalized_alpha' with spectral_radius <= {MAX_SPECTRAL_RADIUS:g} (default 0)")
ENERGY_ADVICE = ("reduce dt (spectral_radius 0, the default, removes the unresolved contact and drive vibrations in "
                 "one step; solver='trapezoidal' is not available for this scene)")
"""The energy warning's advice for this scene (energy.warn_if_open): not the generic 'try trapezoidal'."""


@scene_parameters(FASTENING_PARAMS)
class FasteningParams(SceneParams):
    """A bolt tightened into a nut; see FASTENING_PARAMS for units and meaning."""

    RENAMED = {"head_lay_angle": "head_net_angle"}

    def contact_points(self):
        return self.turns * self.points_per_turn + self.head_points

    def _layout_text(self):
        return f"turns={self.turns} x points_per_turn={self.points_per_turn} + head_points={self.head_points}"

    def _check_scene(self):
        if not self.spectral_radius <= 1.0:
            raise ValueError(f"spectral_radius must lie in [0, 1]; got {self.spectral_radius!r}")
        if not self.flank_angle < 180.0:
            raise ValueError(f"flank_angle must lie in [0, 180) deg; got {self.flank_angle!r}")
        if self.points_per_turn < 3 or self.head_points < 3:
            raise ValueError(f"points_per_turn and head_points must be >= 3 (the bolt is centred by points all "
                             f"round); got points_per_turn={self.points_per_turn!r}, head_points={self.head_points!r}")
        if not self.head_radius > 0.5 * self.d2:
            raise ValueError(f"head_radius must be > d2/2 (the bearing ring lies outside the thread); got "
                             f"head_radius={self.head_radius!r}, d2={self.d2!r}")
        if not self.turns * self.pitch < 0.5 * self.bolt_length:
            raise ValueError(f"turns * pitch must be < bolt_length / 2 (the engaged thread fits on the shank); got "
                             f"{self.turns} * {self.pitch!r} >= {self.bolt_length!r} / 2")
        if self.solver == "trapezoidal":
            raise ValueError(TRAPEZOIDAL_REFUSED)
        if self.tool == "nutrunner" and not (self.shutoff_torque > 0.0 or self.shutoff_angle > 0.0):
            raise ValueError("tool='nutrunner' needs shutoff_torque > 0 or shutoff_angle > 0 (when it shuts off); got "
                             "both 0")
        if self.tool == "nutrunner" and self.reverse_time > 0.0:
            raise ValueError("reverse_time must be 0 with tool='nutrunner' (a nutrunner shuts off and holds; "
                             f"untightening turns the spring drive back); got reverse_time={self.reverse_time!r}")
        if not (self.reverse_time == 0.0 or self.reverse_time < self.t_end):
            raise ValueError(f"reverse_time must be 0 (no untightening) or < t_end (the driver turns back within "
                             f"the run); got reverse_time={self.reverse_time!r} >= t_end={self.t_end!r}")
        if not self.spectral_radius <= MAX_SPECTRAL_RADIUS:
            raise ValueError(f"spectral_radius must be <= {MAX_SPECTRAL_RADIUS:g} for the fastening scene (its "
                             "unresolved contact and drive vibrations must be damped numerically; at the defaults "
                             "0.8 and above stop within 25 ms, 0.7 cuts the step to dt/4); got "
                             f"{self.spectral_radius!r}. Use the default 0 (quasi-static tightening)")
        # the thread must slide (not lock) under the tightening torque
        threads.thread_torque_per_force(self.d2, self.pitch, math.radians(self.flank_angle), self.mu_thread)
        if self.thread == "net" and not self.net_mu_along:
            calibrate_net(self)        # ParameterError now (17 ms, closed form) rather than after the model is built


COLUMNS = {"t": "s", "angle": "rad", "z": "m", "torque": "N m", "thread_torque": "N m", "head_torque": "N m",
           "clamp_force": "N", "part_displacement": "m", "tilt": "rad", "lateral": "m",
           "vx": "m/s", "vy": "m/s", "vz": "m/s", "omega_x": "rad/s", "omega_y": "rad/s", "omega_z": "rad/s",
           "omega_axial": "rad/s", "part_velocity": "m/s", "drive_on": "-", "dissipated_energy": "J",
           **LEDGER_COLUMNS}
"""trajectory.csv: the bolt's angle (unwrapped yaw) and axial advance, the drive torque, the thread and
head torques about the axis (what the drive supplies to each), the clamp force, the clamped part's
displacement, the bolt's tilt and lateral offset of its axis (wobble), the bolt's velocity and angular
velocity (world frame) and its angular velocity about its own axis, the part's velocity, whether the
drive runs (1) or a nutrunner has shut off and holds its torque (0), the dissipated
energy and the energy ledger. The ledger's terms follow from these columns and the parameters alone
(as ``fastening_energy`` books them): work in = trapezoid of torque over angle - axial_load (z - z0);
kinetic = bolt_mass |v|^2 / 2 + J_t |omega|^2 / 2 + (J_z - J_t) omega_axial^2 / 2 (``bolt_inertia``) +
part_mass part_velocity^2 / 2; potential = joint_stiffness part_displacement^2 / 2; residual = work in -
kinetic - potential - energy_stored - energy_dissipated."""
TITLE_KEYS = ("torque_per_clamp_force", "torque_per_clamp_force_theory")

TIGHTENING_FROM = 0.2       # the tightening phase: clamp force above this share of its end value
MIN_TIGHTENING_SAMPLES = 10  # samples of the tightening phase below which no slope, intercept or theory is reported


# ----------------------------------------------------------------------------------------------
# geometry and laws

def lead(p):
    """Axial advance per radian, h = P / (2 pi) [m/rad]."""
    return p.pitch / (2.0 * math.pi)


def driver_angle(p, t):
    """The drive's driver angle [rad] at time t: rotation_speed t, and from reverse_time on (when it
    is > 0) turning back at the same speed; t a number or an array."""
    if p.reverse_time == 0.0:
        return p.rotation_speed * t
    back = p.rotation_speed * (2.0 * p.reverse_time - t)
    return float(back if t > p.reverse_time else p.rotation_speed * t) if np.ndim(t) == 0 else np.where(
        t > p.reverse_time, back, p.rotation_speed * t)


def head_z(p):
    """Body-local z of the head's underside [m] (the bolt's origin is its centre of mass)."""
    return -0.5 * p.bolt_length


def nut_z(p):
    """z of the nut flank's reference (phi = 0 at r2) [m]: the engaged turns end a pitch short of the tip."""
    return 0.5 * p.bolt_length - (p.turns + 1) * p.pitch


def thread_surface(p):
    """The nut's thread in the world frame: Helicoid (flank) or Cylinder with a spiral net (net)."""
    if p.thread == "net":
        return Cylinder(0.5 * p.d2, side="inside")
    return Helicoid(p.pitch, math.radians(p.flank_angle), p.d2, axis_point=(0.0, 0.0, nut_z(p)),
                    hand="right", flank_of="nut", side="forward")


def thread_points(p):
    """Body-local thread points (turns * points_per_turn, 3): on the flank at the pitch radius, at
    phi = 2 pi j / points_per_turn over the engaged turns (net: the same heights and angles at the
    radius r2 + interference)."""
    n = p.turns * p.points_per_turn
    phi = 2.0 * math.pi * np.arange(n) / p.points_per_turn
    r = 0.5 * p.d2 + (net_interference(p) if p.thread == "net" else 0.0)
    return np.column_stack([r * np.cos(phi), r * np.sin(phi), nut_z(p) + lead(p) * phi])


def head_points(p):
    """Body-local points of the head's bearing ring (head_points, 3) at the radius head_radius."""
    a = 2.0 * math.pi * np.arange(p.head_points) / p.head_points
    return np.column_stack([p.head_radius * np.cos(a), p.head_radius * np.sin(a), np.full(p.head_points, head_z(p))])


def part_top_z(p):
    """World z of the clamped part's top face at the start [m]: the head closes the gap after rundown_angle."""
    return head_z(p) + lead(p) * math.radians(p.rundown_angle)


def net_interference(p):
    """thread=net: radial interference of the points [m], net_normal_force / thread_stiffness."""
    return p.net_normal_force / p.thread_stiffness


def calibration_force(p):
    """Axial force on the thread [N] at which thread=net is calibrated: the flank's at the end of the run,
    the theory's clamp force (dF/dangle over the turning after seating) plus axial_load."""
    flank = p.with_overrides(thread="flank")
    turned = p.rotation_speed * (p.reverse_time or p.t_end) - math.radians(p.rundown_angle)
    return max(theory(flank)[0]["clamp_force_per_angle_theory"] * turned, 0.0) + p.axial_load


@functools.lru_cache(maxsize=64)
def calibrate_net(p):
    """thread=net's friction along the helix [-]: the net's steady sliding under the axial force
    ``calibration_force(p)`` (exu_aniso.scenes.screw.steady_sliding: the screw scene's closed form with the
    hole of radius d2/2, the spiral at the lead angle, the normal force net_normal_force, the exact map)
    needs the flank theory's thread torque there. net_mu_across stays as given: it carries the clamp force.

    Raises ParameterError when no friction along the helix in (0, net_mu_across] does it: the net's
    friction ellipse (net_mu_along, net_mu_across) x net_normal_force must hold the axial force and the
    thread torque's circumferential force at once, and the axial force grows with the turning after
    seating (rotation_speed * t_end - rundown_angle). Cached per parameter set (FasteningParams checks
    it when it is made, the contact law uses it)."""
    from scipy.optimize import brentq

    from exu_aniso.scenes.screw import steady_sliding
    from exu_aniso.scenes.screw import ScrewParams
    Fa = calibration_force(p)
    target = threads.thread_torque_per_force(p.d2, p.pitch, math.radians(p.flank_angle), p.mu_thread) * Fa
    base = ScrewParams(radius=0.5 * p.d2, helix_angle=math.degrees(lead_angle(p.pitch, 0.5 * p.d2)),
                       interference=net_interference(p), eps_n=p.thread_stiffness, adhesion="isotropic",
                       eps_1=p.sticking_stiffness, friction="spiral", mu_2=p.net_mu_across, return_map="exact",
                       axial_load=-Fa)

    def excess(mu1):
        return steady_sliding(base.with_overrides(mu_1=mu1)).torque - target

    lo, hi = 1e-6, p.net_mu_across
    try:
        ok = excess(lo) <= 0.0 <= excess(hi)
        why = "its largest torque (net_mu_along = net_mu_across) stays below it" if not ok else ""
    except ValueError:          # steady_sliding: the axial force exceeds the net's axial friction capacity
        ok, why = False, (f"the axial force exceeds what the net holds across the helix (about net_mu_across * "
                          f"net_normal_force = {p.net_mu_across * p.net_normal_force:.4g} N)")
    if not ok:
        raise ParameterError(
            f"thread=net with net_mu_along=0 cannot be calibrated: the rule is that the net's steady sliding under "
            f"the flank's predicted end force F = dF/dangle * (rotation_speed * t_end - rundown_angle) + axial_load "
            f"= {Fa:.4g} N (rotation_speed={p.rotation_speed!r}, t_end={p.t_end!r}, rundown_angle="
            f"{p.rundown_angle!r}, joint_stiffness={p.joint_stiffness!r}, axial_load={p.axial_load!r}) gives the "
            f"flank's thread torque {target:.4g} N m for some friction along the helix in (0, net_mu_across="
            f"{p.net_mu_across!r}], with net_normal_force={p.net_normal_force!r} N; here {why}. Turn less "
            f"(rotation_speed, t_end), raise net_normal_force or net_mu_across, or set net_mu_along > 0")
    return brentq(excess, lo, hi, xtol=1e-12, rtol=1e-12)


def thread_contact_law(p):
    """ContactLaw of the thread: isotropic friction mu_thread on the flank; on the net a spiral net at
    the lead angle (net_mu_along along the helix, calibrate_net when it is 0; net_mu_across across)."""
    K = p.turns * p.points_per_turn
    eps_t = p.sticking_stiffness / K
    if p.thread == "net":
        mu1 = p.net_mu_along or calibrate_net(p)
        a = lead_angle(p.pitch, 0.5 * p.d2)
        return ContactLaw(thread_surface(p), Adhesion.isotropic(eps_t), Friction.spiral(mu1, p.net_mu_across, a),
                          normal_stiffness=p.thread_stiffness / K, return_map=p.return_map)
    F = (Friction.orthotropic(p.mu_thread, p.mu_thread_2, angle=0.0) if p.thread_net == "orthotropic"
         else Friction.isotropic(p.mu_thread))
    return ContactLaw(thread_surface(p), Adhesion.isotropic(eps_t), F, normal_stiffness=p.thread_stiffness / K,
                      return_map=p.return_map)


def head_contact_law(p):
    """ContactLaw of the head bearing on the part's top face (the part's frame: Plane z = 0, side back)."""
    K = p.head_points
    eps_t = p.sticking_stiffness / K
    if p.head_net == "orthotropic":
        a = math.radians(p.head_net_angle)
        F = Friction.orthotropic(p.mu_head, p.mu_head_2, angle=a)
    else:
        F = Friction.isotropic(p.mu_head)
    return ContactLaw(Plane(side="back"), Adhesion.isotropic(eps_t), F, normal_stiffness=p.head_stiffness / K,
                      return_map=p.return_map)


def bolt_inertia(p):
    """Mass and body-frame inertia (3, 3) of the bolt: a solid cylinder of diameter d2 and length
    bolt_length, and a nutrunner's tool_inertia about its axis (the tool turns with it; half of it
    across the axis, a disc's)."""
    m, r, L = p.bolt_mass, 0.5 * p.d2, p.bolt_length
    Jt = m * (3.0 * r * r + L * L) / 12.0
    if p.tool == "nutrunner":
        Jt += 0.5 * p.tool_inertia
        return m, np.diag([Jt, Jt, 0.5 * m * r * r + p.tool_inertia])
    return m, np.diag([Jt, Jt, 0.5 * m * r * r])


def joint_damping(p):
    """Dashpot of the clamped part [N s/m]: 2 ratio sqrt(k m)."""
    return 2.0 * p.joint_damping_ratio * math.sqrt(p.joint_stiffness * p.part_mass)


# ----------------------------------------------------------------------------------------------
# theory

def theory(p):
    """The closed forms of the scene (oracles) from the parameters alone: T/F, thread and head terms,
    VDI 2230's linearization, dF/dangle with the contact compliances in series, the seating angle.
    Values None with a reason where they do not apply (under 'undefined'). fastening_summary reports
    them only where the run is in their domain too (the head clamped over enough samples).

    thread=net: the formulas are a flank's (the flank's normal force grows with the load); the net's
    normal force is the interference fit's, so its thread torque hardly grows with the clamp force and
    only matches the formula at calibration_force (the calibration's target). The thread, total and
    VDI 2230 T/F, dF/dangle and the seating angle have no closed form for it: None; the head term holds."""
    beta = math.radians(p.flank_angle)
    out, undefined = {}, {}
    net = ("thread=net: the formula is a flank's (normal force from the load); the net's normal force is the "
           "interference fit's, so it matches only at calibration_force, not as a slope")
    # an orthotropic flank slides along its direction 1 (the helix), where the associated law's friction is mu_thread
    thread = threads.thread_torque_per_force(p.d2, p.pitch, beta, p.mu_thread)
    if p.thread == "net":
        thread = None
        undefined["thread_torque_per_clamp_force_theory"] = net
    elif p.thread_net == "orthotropic" and p.return_map != "exact":
        thread = None
        undefined["thread_torque_per_clamp_force_theory"] = (f"orthotropic flank under the {p.return_map!r} map: "
                                                             "the formula is checked for the exact map")
    k_thread = (threads.thread_axial_stiffness(p.thread_stiffness, p.d2, p.pitch, beta, p.mu_thread)
                if p.thread == "flank" else None)
    if p.head_net == "isotropic":
        head = p.mu_head * p.head_radius
    elif p.return_map == "exact":      # at the start orientation; fastening_summary follows the ring as it turns
        head = p.head_radius * threads.orthotropic_ring_torque_factor(p.mu_head, p.mu_head_2,
                                                                      math.radians(p.head_net_angle), p.head_points)
    else:
        head = None
        undefined["head_torque_per_clamp_force_theory"] = (f"orthotropic head under the {p.return_map!r} map: the "
                                                           "ring formula holds for the associated (exact) map")
    out["thread_torque_per_clamp_force_theory"] = thread
    out["head_torque_per_clamp_force_theory"] = head
    out["torque_per_clamp_force_theory"] = None if thread is None or head is None else thread + head
    if out["torque_per_clamp_force_theory"] is None:
        undefined["torque_per_clamp_force_theory"] = "a term has no theory (see its entry)"
    out["torque_per_clamp_force_vdi2230"] = (threads.torque_per_clamp_force_vdi2230(p.d2, p.pitch, p.mu_thread,
                                                                                   p.mu_head, p.head_radius)
                                             if p.head_net == "isotropic" and thread is not None else None)
    if out["torque_per_clamp_force_vdi2230"] is None:
        undefined["torque_per_clamp_force_vdi2230"] = ("VDI 2230's formula is for an isotropic head bearing and "
                                                       "flank" + (f" ({net})" if p.thread == "net" else ""))
    comp = [1.0 / p.head_stiffness] + ([1.0 / k_thread] if k_thread else [])
    S = threads.clamp_force_per_angle(p.joint_stiffness, p.pitch, comp) if k_thread else None
    out["clamp_force_per_angle_theory"] = S
    out["seating_angle_theory"] = None if S is None else math.degrees(seating_angle_rad(p, k_thread, S,
                                                                                       out["torque_per_clamp_force_theory"]))
    if k_thread is None:
        undefined["clamp_force_per_angle_theory"] = ("thread=net: the net's advance per turn is not the pitch under "
                                                     "load (it slips across the helix), no closed form here")
        undefined["seating_angle_theory"] = ("thread=net: its tightening curve is not straight (the net slips across "
                                             "the helix under load), so the line's zero-force intercept has no "
                                             "closed form")
    return out, undefined


def seating_angle_rad(p, k_thread, S, T_per_F=None):
    """The seating (snug) angle of the flank thread [rad], as fastening_summary measures it: where the
    tightening line F = S (angle - angle_s) reaches zero force. Quasi-static, with the head's penetration
    lead (angle - rundown) - (F + axial_load) / k_thread - u: the thread yields (F + axial_load) / k_thread
    (axial_load already in run-down, from the start's offset), the part's spring k_joint u = F - c du/dt
    with the dashpot c at the part's velocity du/dt = S omega / k_joint, omega the bolt's speed (the
    driver's less the drive spring's wind-up rate, (T/F) S / drive_stiffness of it). So angle_s =
    rundown + (axial_load / k_thread - c du/dt / k_joint) / lead: 30.0112 deg at the defaults (0.016 deg
    from the thread's give under axial_load, -0.005 deg from the dashpot)."""
    h = lead(p)
    omega = p.rotation_speed / (1.0 + (T_per_F or 0.0) * S / p.drive_stiffness)
    u_dot = S * omega / p.joint_stiffness
    return math.radians(p.rundown_angle) + (p.axial_load / k_thread - joint_damping(p) * u_dot / p.joint_stiffness) / h


# ----------------------------------------------------------------------------------------------
# trajectory, summary, energy (every engine)

def contact_torques(law_thread, law_head, p, pos, vel, w, A, part_u, part_v, H_thread, H_head):
    """Per sample: thread torque, head torque (what the drive supplies to each: minus the moments of
    the contact forces on the bolt about its axis through the bolt's centre) and the clamp force
    (minus the head's axial contact force on the bolt). pos, vel, w (n, 3), A (n, 3, 3) of the bolt;
    part_u, part_v (n, 3) the part's displacement and velocity; H_*: converged histories (n, K, 9),
    each sample evaluated with the history of the sample before (what the solver saw). The points
    are independent given their history: every sample goes into one call of the law."""
    prev = np.maximum(np.arange(len(pos)) - 1, 0)

    def forces(law, b, shift, vshift, H):
        arm = np.einsum("nij,kj->nki", A, b)                      # (n, K, 3) world arms
        x = pos[:, None, :] + arm - shift[:, None, :]
        v = vel[:, None, :] + np.cross(w[:, None, :], arm) - vshift[:, None, :]
        n, K = arm.shape[:2]
        f = law.evaluate(x.reshape(-1, 3), v.reshape(-1, 3), H[prev].reshape(-1, 9), tangent=False).force
        f = f.reshape(n, K, 3)
        return -np.sum(arm[:, :, 0] * f[:, :, 1] - arm[:, :, 1] * f[:, :, 0], axis=1), f

    Tt, _ = forces(law_thread, thread_points(p), np.zeros_like(pos), np.zeros_like(vel), H_thread)
    top = part_u + np.array([0.0, 0.0, part_top_z(p)])
    Th, f = forces(law_head, head_points(p), top, part_v, H_head)
    return Tt, Th, -np.sum(f[:, :, 2], axis=1)


def tightening(clamp_force):
    """Mask of the tightening phase: clamp force above TIGHTENING_FROM of its end value."""
    F = np.asarray(clamp_force, float)
    return F >= TIGHTENING_FROM * F[-1]


def head_ring_factor(p, angle):
    """The orthotropic head ring's torque factor (threads.orthotropic_ring_torque_factor) at the bolt
    angles ``angle`` [rad]: the ring turns with the bolt while the lay stays with the part, so the lay
    lies at head_net_angle - angle from the ring's points."""
    lay = math.radians(p.head_net_angle)
    return np.array([threads.orthotropic_ring_torque_factor(p.mu_head, p.mu_head_2, lay - a, p.head_points)
                     for a in np.atleast_1d(angle)])


def _slope(x, y):
    return float(np.polyfit(x, y, 1)[0])


def seating_angle(angle, clamp_force):
    """The seating (snug) angle [rad]: where the tightening line, the least-squares line of the clamp
    force over the angle in the tightening phase (``tightening``), reaches zero force. The first touch
    is no seating angle: a tilted head grazes the part with a few newtons long before its ring bears
    (4 thread points on 1 turn: 4.6 N at 19.6 deg, the line's intercept at 30.01 deg). None when the
    line does not rise."""
    ang, F = np.asarray(angle, float), np.asarray(clamp_force, float)
    tight = tightening(F)
    k, b = np.polyfit(ang[tight], F[tight], 1)
    return float(-b / k) if k > 0.0 else None


def fastening_summary(traj, p, wall_s, steps, newton_iterations):
    """Summary of a fastening run (any engine): seating angle, end values, the least-squares slopes
    in the tightening phase against their theory (``theory``), the ISO 16047 friction values, wobble.

    seating_angle [deg] is the snug point of the torque-angle method: the angle where the tightening
    line (clamp force over angle, least squares over the tightening phase: clamp force above
    TIGHTENING_FROM of its end value) reaches zero force (``seating_angle``); seating_angle_theory is
    the same intercept in closed form (``seating_angle_rad``). Every value needs a tightening phase of
    MIN_TIGHTENING_SAMPLES samples at least; the theories are reported only then (and where ``theory``
    defines them), otherwise None with a reason under "undefined"."""
    t = np.asarray(traj["t"], float)
    ang = np.asarray(traj["angle"], float)
    F = np.asarray(traj["clamp_force"], float)
    T, Tt, Th = (np.asarray(traj[k], float) for k in ("torque", "thread_torque", "head_torque"))
    s = dict(t_end=float(t[-1]), wall_s=float(wall_s), steps=int(steps), newton_iterations=int(newton_iterations),
             angle_end_deg=float(math.degrees(ang[-1])), torque_end=float(T[-1]), clamp_force_end=float(F[-1]),
             thread_torque_end=float(Tt[-1]), head_torque_end=float(Th[-1]),
             tilt_max_deg=float(math.degrees(np.max(traj["tilt"]))), lateral_max=float(np.max(traj["lateral"])))
    th, undefined = theory(p)
    s.update(th)
    s.update(break_loose(p, t, ang, F, T, undefined))
    s.update(shutoff(p, t, np.asarray(traj["omega_axial"], float), T, Tt + Th, traj["drive_on"], th, undefined,
                     bolt_inertia(p)[1][2, 2]))
    if p.reverse_time > 0.0 or p.tool == "nutrunner":   # the tightening: before the driver turned back or shut off
        rows = (t <= p.reverse_time) if p.reverse_time > 0.0 else (np.asarray(traj["drive_on"]) > 0.5)
        ang, F, T, Tt, Th = (a[rows] for a in (ang, F, T, Tt, Th))
    keys = ("seating_angle", "torque_per_clamp_force", "thread_torque_per_clamp_force", "head_torque_per_clamp_force",
            "clamp_force_per_angle", "mu_thread_iso16047", "mu_head_iso16047", "mu_total_iso16047")
    n_tight = int(np.count_nonzero(tightening(F))) if F[-1] > 0.0 else 0
    seat = seating_angle(ang, F) if n_tight >= MIN_TIGHTENING_SAMPLES else None
    if seat is None:
        why = (f"the head did not clamp enough: clamp force at the end {F[-1]:.3g} N, {n_tight} samples above "
               f"{TIGHTENING_FROM:g} of it (at least {MIN_TIGHTENING_SAMPLES} needed for the tightening line); turn "
               "further (t_end, rotation_speed)")
        for k in keys + tuple(th):
            s[k] = None
            undefined[k] = why
        s["undefined"] = undefined
        return s
    tight = tightening(F)
    s["seating_angle"] = math.degrees(seat)
    s["torque_per_clamp_force"] = _slope(F[tight], T[tight])
    s["thread_torque_per_clamp_force"] = _slope(F[tight], Tt[tight])
    s["head_torque_per_clamp_force"] = _slope(F[tight], Th[tight])
    s["clamp_force_per_angle"] = _slope(ang[tight], F[tight])
    if s["head_torque_per_clamp_force_theory"] is not None and p.head_net == "orthotropic":
        # the ring turns with the bolt over the lay: the formula at the ring's orientation in every sample
        g = head_ring_factor(p, ang[tight])
        s["head_torque_per_clamp_force_theory"] = _slope(F[tight], p.head_radius * g * F[tight])
        if s["thread_torque_per_clamp_force_theory"] is not None:
            s["torque_per_clamp_force_theory"] = (s["thread_torque_per_clamp_force_theory"]
                                                  + s["head_torque_per_clamp_force_theory"])
    beta = math.radians(p.flank_angle)
    s["mu_thread_iso16047"] = threads.mu_thread_iso16047(s["thread_torque_per_clamp_force"], p.d2, p.pitch, beta)
    s["mu_head_iso16047"] = threads.mu_head_iso16047(s["head_torque_per_clamp_force"], p.head_radius)
    s["mu_total_iso16047"] = ((s["torque_per_clamp_force"] - p.pitch / (2.0 * math.pi))
                              / (0.5 * p.d2 / math.cos(0.5 * beta) + p.head_radius))
    s["undefined"] = undefined
    return s


def fastening_energy(p, traj, bolt, part_z, part_vz, laws, X, V, H):
    """Energy ledger (any engine): adds ENERGY_COLUMNS to traj and returns the summary entries.

    bolt: energy.RigidMotion of the bolt; part_z, part_vz (n,): the part's displacement and velocity;
    laws, X, V, H: per contact (thread, head) its law, slave points and velocities in its master's frame
    and histories. Work in: the drive torque over the angle and the axial load over z; potential: the
    joint spring; dissipated: contacts and the joint's dashpot."""
    m, J = bolt_inertia(p)
    work = energy.work_trapezoid(traj["torque"], traj["angle"]) - p.axial_load * (traj["z"] - traj["z"][0])
    kinetic = energy.rigid_kinetic(bolt, m, J) + 0.5 * p.part_mass * part_vz ** 2
    potential = 0.5 * p.joint_stiffness * part_z ** 2
    stored = diss = 0.0
    for law, x, v, h in zip(laws, X, V, H):
        s_i, d_i = energy.contact_energy(law, x, v, h)
        stored, diss = stored + s_i, diss + d_i
    c = joint_damping(p)
    f = c * part_vz                                  # dashpot force on the part against its velocity
    diss = diss + energy.work_trapezoid(f, part_z)
    return energy_ledger(dict(work_in=work, kinetic=kinetic, potential=potential, stored=stored, dissipated=diss),
                   traj, "fastening run", ENERGY_ADVICE)


# ----------------------------------------------------------------------------------------------
# plot

def PlotFastening(traj, params, fig):
    """Two panels: the torque-angle curve with its phases (run-down, seating, tightening) and the thread
    and head torques; torque against clamp force with the ISO 16047 / VDI 2230 line."""
    p = params
    a1, a2 = fig.subplots(2, 1)
    deg = np.degrees(np.asarray(traj["angle"], float))
    F = np.asarray(traj["clamp_force"], float)
    a1.plot(deg, traj["torque"], "k-", lw=1.2, label="drive torque")
    a1.plot(deg, traj["thread_torque"], "C0-", lw=0.9, label="thread")
    a1.plot(deg, traj["head_torque"], "C1-", lw=0.9, label="head")
    ok = F[-1] > 0.0 and np.count_nonzero(tightening(F)) >= MIN_TIGHTENING_SAMPLES
    seat = seating_angle(traj["angle"], F) if ok else None
    if seat is not None:                 # the snug point: the tightening line's zero-force intercept
        seat = math.degrees(seat)
        a1.axvline(seat, color="C3", ls="--", lw=0.8)
        a1.axvspan(deg[0], seat, color="0.9", zorder=0)
        a1.text(0.5 * (deg[0] + seat), 0.9 * a1.get_ylim()[1], "run-down", ha="center", fontsize=7)
        a1.text(seat, 0.5 * a1.get_ylim()[1], " seating", color="C3", fontsize=7)
        a1.text(0.5 * (seat + deg[-1]), 0.9 * a1.get_ylim()[1], "tightening", ha="center", fontsize=7)
    a1.set(xlabel="angle [deg]", ylabel="torque [N m]", title=f"torque-angle, thread={p.thread}")
    a1.grid(True, alpha=0.3)
    a1.legend(fontsize=7, loc="center left")
    a2.plot(F * 1e-3, traj["torque"], "k-", lw=1.2, label="simulated")
    th, _ = theory(p if p.thread == "flank" else p.with_overrides(thread="flank"))   # net: the flank's line
    Ff = np.linspace(0.0, max(F.max(), 0.0), 2)
    # the thread also carries axial_load: T = T/F F + (thread term) axial_load
    if th["torque_per_clamp_force_theory"] is not None:
        T0 = th["thread_torque_per_clamp_force_theory"] * p.axial_load
        a2.plot(Ff * 1e-3, T0 + th["torque_per_clamp_force_theory"] * Ff, "C3--", lw=1.0,
                label=f"ISO 16047 / VDI 2230: T/F = {th['torque_per_clamp_force_theory'] * 1e3:.3f} mm")
    if th["torque_per_clamp_force_vdi2230"] is not None:
        T0 = (th["torque_per_clamp_force_vdi2230"] - p.mu_head * p.head_radius) * p.axial_load
        a2.plot(Ff * 1e-3, T0 + th["torque_per_clamp_force_vdi2230"] * Ff, "C2:", lw=1.0,
                label=f"VDI 2230 linearized: {th['torque_per_clamp_force_vdi2230'] * 1e3:.3f} mm")
    a2.set(xlabel="clamp force [kN]", ylabel="torque [N m]", title="torque-tension")
    a2.grid(True, alpha=0.3)
    a2.legend(fontsize=7)
    return a1, a2


# ----------------------------------------------------------------------------------------------
# the scene, as every engine and the command line see it

class FasteningScene(Scene):
    """The fastening scene (the module docstring); no reference-engine model (the oracles are
    ISO 16047 / VDI 2230's closed forms, ``theory``); two contacts, ``thread`` and ``head``; the summary
    takes no inputs, the ledger ``fastening_energy``'s (bolt, part_z, part_vz, laws, X, V, H)."""

    name = "fastening"
    Params = FasteningParams
    columns = COLUMNS
    title_keys = TITLE_KEYS
    figsize = (7.0, 7.0)
    summary = staticmethod(fastening_summary)
    ledger = staticmethod(fastening_energy)
    plot = staticmethod(PlotFastening)

    def closed_forms(self, p):
        """ISO 16047 / VDI 2230's closed forms for p (``theory``), None with the reason under
        ``undefined`` where they do not apply."""
        out, undefined = theory(p)
        return dict(out, undefined=undefined)

    def law(self, p):
        """The thread's and the head's contact laws, by contact name."""
        return dict(thread=thread_contact_law(p), head=head_contact_law(p))

    def points(self, p):
        """The thread's and the head's contact points in the bolt's frame [m], by contact name."""
        return dict(thread=thread_points(p), head=head_points(p))


SCENE = FasteningScene()
