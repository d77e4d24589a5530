"""The loosening scene's preloaded joint (``case="joint"``): a nut clamping a plate onto a fixed bolt,
shaken across the bolt's axis.

The joint: a rigid M10 nut (``d2``, ``pitch``, ``flank_angle``) whose thread bears on the bolt's lower
flank and whose bearing face (the ring of ``bearing_radius``) bears on the clamped plate; the
``preload`` F presses them together. The nut is shaken across the axis: a stiff spring
(``drag_stiffness``, a dashpot ``drag_damping`` beside it) pulls its centre along x to a driver at
D sin(2 pi f (t - load_time)) (``shake_displacement`` D, ``shake_frequency`` f: the Junker test
prescribes the displacement) and holds it at y = 0. Two models:

* ``model="rings"``: the closed form's idealisation. The nut is a planar rigid body (x, y, angle);
  its bearing ring (``points`` points) and its thread ring (``turns * points_per_turn`` points at
  d2 / 2) are held at the penetrations that carry F on the plate and F W / r on the flank
  (``threads.flank_load_per_axial_force``), each ring against a plane, so both stay uniform and
  closed whatever the nut does; the lead's torque F P / (2 pi) turns the nut loose. The preload does
  not fall (the rings hold their loads): its loss per radian is the full model's to show.
* ``model="full"``: a 6-DOF nut on the bolt's helicoid flank (``turns`` turns of
  ``points_per_turn`` points at the pitch radius), its bearing ring on the plate; the plate moves
  along the axis only, on the joint's spring (``joint_stiffness``, a dashpot ``joint_damping``)
  that is compressed by F: when the nut backs off, the plate follows and the preload falls. With a
  flexible shank (``SHANKS``) the bolt's threaded end moves across on its shank, a beam of
  ``clamp_length`` clamped at the head and guided at the nut (its end shifts without turning), and
  the shaker drives the plate instead, as a Junker test does: ``shank="guided_beam"`` lumps it at its
  end on 12 E I / L^3, ``shank="fe_beam"`` is ``shank_elements`` Timoshenko beam elements
  (``exu_aniso.fe.beam``) with their shear and mass.

Closed forms (``scenes.threads``): with both rings uniform, closed and sliding, the nut turns loose by
``joint_rotation_per_path`` radians per metre of its sideways slip path, against a sideways force of
F ``joint_slide_force_per_preload`` (the hysteresis loop's plateau), and each radian backs it off by
P / (2 pi), which loses the preload ``threads.clamp_force_per_angle`` (the joint's spring and the two
contacts' normal compliances in series). With a flexible shank the bearing ring slides as a whole once
the plate's shift reaches mu_bearing F (1 / k_shank + 1 / sticking_stiffness), the critical amplitude
(``joint_closed_forms``), with k_shank the guided beam's lateral stiffness (``shank_stiffness``:
``threads.guided_beam_stiffness``, or with shear ``threads.guided_shear_beam_stiffness``).

A nut shaken sideways on a helicoid wedges its flank: the shift moves each thread point along the
helix by the shift's component along e_phi over r, so the flank's height under it changes by h / r
times that, about 10 um at a 0.2 mm shift on M10 against the 1 um penetration that carries the
preload. The full model's nut tilts to follow and opens part of its thread ring; the summary says by
how much (``thread_open_share``, ``flank_load_spread``) and what it costs against the uniform rings.
"""
from __future__ import annotations

import math
from typing import Callable, NamedTuple

import numpy as np

from exu_aniso.engines import energy
from exu_aniso.engines.timing import smooth_rise
from exu_aniso.fe.beam import ShankMatrices, guided_shank, round_section
from exu_aniso.fields.tensor_fields import Adhesion, Friction
from exu_aniso.geometry import Helicoid, Plane
from exu_aniso.kernel.contact_law import ContactLaw
from exu_aniso.law.history import HISTORY_FIELDS, SLIP, STICK
from exu_aniso.scenes import threads

_STATUS, _NORMAL = HISTORY_FIELDS.index("status"), HISTORY_FIELDS.index("normal")
BEARING_GAP = 0.3           # the bearing face's height below the nut's lowest thread point [pitches]
LOOSE_SHARE = 0.1
"""The joint is loose once its preload falls under this share of ``preload`` after the shaking began.
Model full ends its run there (``loose``): past it the loosening has nothing more to show, and the
model's flank has no crest or root to keep a nut that no preload holds on the bolt."""


# ----------------------------------------------------------------------------------------------
# geometry, laws, loads

def lead(p):
    """Axial advance per radian, h = P / (2 pi) [m/rad]."""
    return p.pitch / (2.0 * math.pi)


def flank_angle_rad(p):
    return math.radians(p.flank_angle)


def thread_point_count(p):
    return p.turns * p.points_per_turn


def bolt_flank(p):
    """The bolt's lower flank, fixed to ground (world frame): the helicoid through z = h phi at d2 / 2,
    facing down onto the nut's thread."""
    return Helicoid(p.pitch, flank_angle_rad(p), p.d2, hand="right", flank_of="bolt", side="backward")


def centre_height(p):
    """Height [m] of the full nut's centre over the flank's z = 0 at phi = 0: the middle of its thread
    points' span."""
    return lead(p) * math.pi * (thread_point_count(p) - 1) / p.points_per_turn


def thread_points(p):
    """Body-local thread points (K, 3): model full, on the flank at the pitch radius from the nut's
    centre (phi_k = 2 pi k / points_per_turn, z = h phi_k - centre_height); model rings, the ring at
    d2 / 2 in the plane z = 0 (each ring's held height is its model's)."""
    K = thread_point_count(p)
    phi = 2.0 * math.pi * np.arange(K) / p.points_per_turn
    z = lead(p) * phi - centre_height(p) if p.model == "full" else np.zeros(K)
    return np.column_stack([0.5 * p.d2 * np.cos(phi), 0.5 * p.d2 * np.sin(phi), z])


def bearing_ring(p):
    """The bearing ring (points, 3): ``points`` points on bearing_radius in the plane z = 0 (the bearing
    case's ring, and the rings model's)."""
    a = 2.0 * math.pi * np.arange(p.points) / p.points
    return np.column_stack([p.bearing_radius * np.cos(a), p.bearing_radius * np.sin(a), np.zeros(p.points)])


def bearing_points(p):
    """Body-local bearing points (points, 3): the bearing ring, model full BEARING_GAP pitches below the
    lowest thread point."""
    ring = bearing_ring(p)
    if p.model == "full":
        ring[:, 2] = -centre_height(p) - BEARING_GAP * p.pitch
    return ring


def plate_height(p):
    """The plate's top face (world z [m]) under the full nut's bearing face at the start."""
    return -BEARING_GAP * p.pitch


def thread_law(p):
    """ContactLaw of the nut's thread: model full, on the bolt's flank; model rings, on a plane (the
    flank held uniform). Isotropic mu_thread; stiffnesses split over the points."""
    K = thread_point_count(p)
    surface = bolt_flank(p) if p.model == "full" else Plane()
    return ContactLaw(surface, Adhesion.isotropic(p.sticking_stiffness / K), Friction.isotropic(p.mu_thread),
                      normal_stiffness=p.thread_stiffness / K, return_map=p.return_map)


def bearing_law(p):
    """ContactLaw of the bearing face on the plate (the plane z = 0 of the plate's frame, isotropic
    mu_bearing), stiffnesses split over the points: both cases' bearing ring."""
    K = p.points
    return ContactLaw(Plane(), Adhesion.isotropic(p.sticking_stiffness / K), Friction.isotropic(p.mu_bearing),
                      normal_stiffness=p.bearing_stiffness / K, return_map=p.return_map)


def shank_section(p):
    """The bolt's shank's section (``fe.beam.RoundSection``)."""
    return round_section(p.youngs_modulus, p.poissons_ratio, p.shank_diameter, p.shank_density)


class Shank(NamedTuple):
    """A flexible shank: the closed form of its guided end's lateral stiffness [N/m] and its matrices
    (``fe.beam.ShankMatrices``), each a function of the scene's parameters."""
    stiffness: Callable
    matrices: Callable


def _lumped_matrices(p):
    """Shank guided_beam: the bolt's end's (x, y) on the spring 12 E I / L^3 and the dashpot
    drag_damping; no mass (the end's own is bolt_mass)."""
    k = SHANKS["guided_beam"].stiffness(p)
    return ShankMatrices(np.zeros((2, 2)), p.drag_damping * np.eye(2), k * np.eye(2), (0, 1))


def _beam_matrices(p):
    """Shank fe_beam: shank_elements Timoshenko elements over the clamp length (``fe.beam.guided_shank``),
    damped by D = beta K with beta = drag_damping / k_shank: the lumped shank's dashpot at the end."""
    return guided_shank(shank_section(p), p.clamp_length, p.shank_elements,
                        p.drag_damping / SHANKS["fe_beam"].stiffness(p))


SHANKS = {
    "guided_beam": Shank(lambda p: threads.guided_beam_stiffness(p.youngs_modulus, p.shank_diameter, p.clamp_length),
                         _lumped_matrices),
    "fe_beam": Shank(lambda p: threads.guided_shear_beam_stiffness(shank_section(p), p.clamp_length),
                     _beam_matrices),
}
"""The flexible shanks by name (``shank``; ``rigid`` has none): a beam clamped at the head and guided at
the nut, lumped at its end on 12 E I / L^3, or of finite elements with its shear and its mass."""


def shank_stiffness(p):
    """A flexible shank's closed-form lateral stiffness at the nut [N/m] (``SHANKS``)."""
    return SHANKS[p.shank].stiffness(p)


def shank_matrices(p):
    """A flexible shank's ``fe.beam.ShankMatrices`` (``SHANKS``)."""
    return SHANKS[p.shank].matrices(p)


def held_gaps(p):
    """Model rings: the heights [m] of the bearing and thread rings over their planes that carry the
    preload on the plate and F W / r on the flank (negative: penetrations)."""
    flank_load = p.preload * threads.flank_load_per_axial_force(p.d2, p.pitch, flank_angle_rad(p))
    return dict(bearing=-p.preload / p.bearing_stiffness, thread=-flank_load / p.thread_stiffness)


def preload_at(p, t):
    """The preload's share at time t [s]: F rising as (1 - cos(pi t / load_time)) / 2 [N]."""
    return p.preload * smooth_rise(t, p.load_time)


def contact_compliance(p):
    """The bearing's and the flank's axial compliances in series [m/N]: 1 / bearing_stiffness + 1 / the
    flank's axial stiffness (``threads.thread_axial_stiffness`` at mu 0)."""
    k_axial = threads.thread_axial_stiffness(p.thread_stiffness, p.d2, p.pitch, flank_angle_rad(p), 0.0)
    return 1.0 / p.bearing_stiffness + 1.0 / k_axial


def loose(p, t, preload):
    """Whether the joint is loose at time t [s] under the preload [N] (``LOOSE_SHARE``)."""
    return t > p.load_time and preload < LOOSE_SHARE * p.preload


def spring_load_factor(p):
    """Model full: the force on the plate that, against the joint's spring, settles at a preload F once
    the contacts have taken their compression, over F [-]: the plate rises by F times
    ``contact_compliance`` and the spring takes back joint_stiffness times that."""
    return 1.0 + p.joint_stiffness * contact_compliance(p)


def spring_load_at(p, t):
    """Model full: that force at time t [s] (a number or an array) [N], ``preload_at`` times
    ``spring_load_factor`` (a user function that runs every Newton iteration takes the factor once)."""
    return preload_at(p, t) * spring_load_factor(p)


def lead_torque(p, t):
    """Model rings: the lead's torque F(t) P / (2 pi) [N m] turning the nut loose (positive angle)."""
    return preload_at(p, t) * lead(p)


def shake_travel(p, t):
    """The shaker's driver: its travel D sin(2 pi f tau) [m] and rate [m/s], tau = t - load_time, at rest
    before; t a number (the spring's user function, every Newton iteration: no arrays) or an array."""
    w = 2.0 * math.pi * p.shake_frequency
    if np.ndim(t) == 0:
        tau = t - p.load_time
        if tau <= 0.0:
            return 0.0, 0.0
        return p.shake_displacement * math.sin(w * tau), p.shake_displacement * w * math.cos(w * tau)
    tau = np.maximum(np.asarray(t, float) - p.load_time, 0.0)
    return p.shake_displacement * np.sin(w * tau), np.where(tau > 0.0, p.shake_displacement * w * np.cos(w * tau), 0.0)


def shake_force(p, x, vx, t):
    """The shaker's spring and dashpot force along x [N] (arrays) on the body it drives (the nut, or the
    plate with the guided-beam shank) at x, vx."""
    s, s_t = shake_travel(p, t)
    return p.drag_stiffness * (s - x) + p.drag_damping * (s_t - vx)


# ----------------------------------------------------------------------------------------------
# the rings' states

def ring_states(H, prefix):
    """The shares of a ring's points that slide, stick and are open and its normal forces' total [N]
    from its history H (n, K, 9), named ``prefix``_..., and their spread ((max - min) / mean over its
    points, 0 where none is loaded)."""
    status, N = H[:, :, _STATUS], -H[:, :, _NORMAL]
    total = N.sum(axis=1)
    mean = total / N.shape[1]
    spread = np.where(mean > 0.0, (N.max(axis=1) - N.min(axis=1)) / np.where(mean > 0.0, mean, 1.0), 0.0)
    return {f"{prefix}_slip_fraction": (status == SLIP).mean(axis=1),
            f"{prefix}_stick_fraction": (status == STICK).mean(axis=1),
            f"{prefix}_open_fraction": ((status != SLIP) & (status != STICK)).mean(axis=1),
            f"{prefix}_load": total}, spread


def finish_joint_trajectory(traj, H_bearing, H_thread):
    """Add the rings' states (``ring_states``), the flank's load spread and the preload (the bearing's
    normal force) to traj."""
    bearing, _ = ring_states(H_bearing, "bearing")
    thread, traj["flank_load_spread"] = ring_states(H_thread, "thread")
    traj.update(bearing, **thread)
    traj["slip_fraction"] = traj["bearing_slip_fraction"]
    traj["preload"] = traj["bearing_load"]
    return traj


# ----------------------------------------------------------------------------------------------
# closed forms

def joint_closed_forms(p):
    """``rotation_per_path_theory`` [rad/m] (``threads.joint_rotation_per_path``),
    ``slide_force_per_preload_theory`` [-] (``threads.joint_slide_force_per_preload``) and
    ``preload_loss_per_radian_theory`` [N/rad] (``threads.clamp_force_per_angle`` with the bearing's and
    the flank's axial compliances, ``threads.thread_axial_stiffness`` at mu 0, in series with the
    joint's spring) and, with a flexible shank, ``critical_amplitude_theory`` [m]: the plate's
    shift at which the bearing ring slides as a whole, mu_bearing F (1 / k_shank + 1 /
    sticking_stiffness): while it sticks the nut and the bolt's end follow the plate, and the shank's
    bending force (``shank_stiffness``) and the bearing's elastic stick take the shift until that force
    reaches the bearing's friction (the thread, whose 60 degree flank wedges against a sideways slide,
    holds on); None with the reason where undefined."""
    args = (p.d2, p.pitch, flank_angle_rad(p), p.mu_thread, p.mu_bearing, p.bearing_radius)
    out = dict(undefined={})
    try:
        out["rotation_per_path_theory"] = threads.joint_rotation_per_path(*args)
        out["slide_force_per_preload_theory"] = threads.joint_slide_force_per_preload(*args)
    except ValueError as e:
        out.update(rotation_per_path_theory=None, slide_force_per_preload_theory=None)
        out["undefined"].update(rotation_per_path_theory=str(e), slide_force_per_preload_theory=str(e))
    out["preload_loss_per_radian_theory"] = threads.clamp_force_per_angle(p.joint_stiffness, p.pitch,
                                                                          (contact_compliance(p),))
    if p.model == "full" and p.shank in SHANKS:
        out["critical_amplitude_theory"] = p.mu_bearing * p.preload * (1.0 / shank_stiffness(p)
                                                                       + 1.0 / p.sticking_stiffness)
    else:
        out["critical_amplitude_theory"] = None
        out["undefined"]["critical_amplitude_theory"] = ("the critical amplitude is a flexible shank's "
                                                         f"(model full, shank {' or '.join(SHANKS)})")
    return out


# ----------------------------------------------------------------------------------------------
# summary, energy

def cycle_ends(p, t_end):
    """The times [s] at which whole cycles of the shaking end."""
    n = int((t_end - p.load_time) * p.shake_frequency + 1e-9)
    return p.load_time + np.arange(1, n + 1) / p.shake_frequency


FEW_CYCLES = "fewer than 2 whole cycles of the shaking: run longer"
"""Why a figure per cycle is undefined."""


def rotation_per_cycle(p, t, angle):
    """The angle [rad] turned per cycle between the first and the last whole cycle's end (the same
    phase of the shaking), or None with fewer than 2 whole cycles (``FEW_CYCLES``); with those ends
    [s] and the angles there: (per cycle, ends, angles)."""
    ends = cycle_ends(p, t[-1])
    at = np.interp(ends, t, angle)
    return (float((at[-1] - at[0]) / (len(ends) - 1)) if len(ends) >= 2 else None), ends, at


def sliding_intervals(traj):
    """The sample intervals over which no point of either ring sticks (both ends): the nut slides."""
    free = (np.asarray(traj["bearing_stick_fraction"]) == 0.0) & (np.asarray(traj["thread_stick_fraction"]) == 0.0)
    return free[1:] & free[:-1]


def joint_summary(traj, p):
    """The joint's loosening: over the shaking (from load_time), ``cycles`` whole cycles,
    ``rotation`` [rad] (the angle turned loose since load_time), ``rotation_per_cycle`` and
    ``rotation_per_path_all`` [rad/m] (the angle over the nut's whole path |dx|, sticking or not),
    between the first and the last whole cycle's ends; over the intervals in which the nut slides
    (``sliding_intervals``; ``sliding_share`` of the shaking's time), ``rotation_per_path`` [rad/m] (the
    angle over the nut's path |dx|) and ``slide_force_per_preload`` [-] (the mean of |shake force| /
    preload) beside their closed forms; the preload at the shaking's start and end [N] and, model full,
    ``preload_loss_per_radian`` [N/rad] (the line through the cycle ends' preload against angle);
    ``cycles_to_loose``, the cycles until the preload fell under LOOSE_SHARE of ``preload`` (model full
    ends its run at that cycle's end); with the guided-beam shank ``plate_amplitude`` [m], the plate's
    largest shift, and ``bearing_slid``, whether the bearing ring ever slid as a whole; the rings'
    shares of sliding and open point-samples over the shaking and the flank's mean load spread."""
    t = np.asarray(traj["t"], float)
    angle = np.asarray(traj["angle"], float)
    theory = joint_closed_forms(p)
    shaking = t > p.load_time
    per_cycle, ends, at = rotation_per_cycle(p, t, angle)
    s = dict(cycles=float(len(ends)), undefined=dict(theory["undefined"]),
             rotation=float(angle[-1] - np.interp(p.load_time, t, angle)),
             rotation_per_cycle=per_cycle, rotation_per_path=None, slide_force_per_preload=None,
             preload_loss_per_radian=None)
    for k in ("rotation_per_path_theory", "slide_force_per_preload_theory", "preload_loss_per_radian_theory",
              "critical_amplitude_theory"):
        s[k] = theory[k]
    x = np.asarray(traj["x"], float)
    s["rotation_per_path_all"] = None
    if per_cycle is not None:
        whole = (t[1:] > ends[0]) & (t[:-1] < ends[-1])
        s["rotation_per_path_all"] = float((at[-1] - at[0]) / np.abs(np.diff(x))[whole].sum())
    else:
        s["undefined"].update(rotation_per_cycle=FEW_CYCLES, rotation_per_path_all=FEW_CYCLES)
    slide = sliding_intervals(traj) & shaking[1:]
    path = np.abs(np.diff(x))[slide].sum()
    s["sliding_share"] = float(np.sum(np.diff(t)[slide]) / max(t[-1] - p.load_time, 1e-300))
    if path > 0.0:
        s["rotation_per_path"] = float(np.diff(angle)[slide].sum() / path)
        mid = np.flatnonzero(slide) + 1
        s["slide_force_per_preload"] = float(np.mean(np.abs(np.asarray(traj["drag_force"], float)[mid])
                                                     / np.asarray(traj["preload"], float)[mid]))
    else:
        why = "the nut never slid with both rings free of sticking points: shake wider or longer"
        s["undefined"].update(rotation_per_path=why, slide_force_per_preload=why)
    preload = np.asarray(traj["preload"], float)
    s["preload_start"] = float(np.interp(p.load_time, t, preload))
    s["preload_end"] = float(preload[-1])
    if "plate_x" in traj:         # the guided-beam shank: the plate's shift, and whether the bearing ever slid whole
        s["plate_amplitude"] = float(np.max(np.abs(np.asarray(traj["plate_x"], float)[shaking])))
        s["bearing_slid"] = bool(np.any(np.asarray(traj["bearing_slip_fraction"])[shaking] == 1.0))
    came = np.flatnonzero((t > p.load_time) & (preload < LOOSE_SHARE * p.preload))
    s["cycles_to_loose"] = float((t[came[0]] - p.load_time) * p.shake_frequency) if len(came) else None
    if not len(came):
        s["undefined"]["cycles_to_loose"] = f"the preload held above {LOOSE_SHARE:g} of its value to the end"
    if p.model == "full" and len(ends) >= 2 and np.ptp(at) > 0.0:
        s["preload_loss_per_radian"] = float(-np.polyfit(at, np.interp(ends, t, preload), 1)[0])
    elif p.model == "full":
        s["undefined"]["preload_loss_per_radian"] = "fewer than 2 whole cycles, or the nut did not turn"
    else:
        s["undefined"]["preload_loss_per_radian"] = ("model rings holds the rings' loads (the closed form's "
                                                     "assumption): model full lets the preload fall")
    for ring in ("thread", "bearing"):
        for state in ("slip", "open"):
            s[f"{ring}_{state}_share"] = float(np.mean(np.asarray(traj[f"{ring}_{state}_fraction"])[shaking]))
    s["flank_load_spread"] = float(np.mean(np.interp(ends, t, traj["flank_load_spread"]))) if len(ends) else None
    if s["flank_load_spread"] is None:
        s["undefined"]["flank_load_spread"] = "no whole cycle of the shaking: run longer"
    return s


def joint_energy_terms(p, traj, contacts, shaken, plate=None, nut_motion=None, bolt=None, shank=None):
    """The joint's energy terms (energy.ledger's arguments): work in, the shaker's spring over its
    driver's travel, plus (model rings) the lead's torque over the angle or (model full) the preload's
    rising force over the plate's travel; kinetic, the bodies'; potential, the springs' (the shaker's, the
    joint's, the shank's); stored and dissipated, the contacts' (``contacts``: (law, motion relative to
    the master, body-local points, history) each) and the dashpots'. shaken: dict x, y, vx, vy (n,) of the
    body the shaker drives along x and its spring holds at y = 0 (the nut, or with the guided-beam shank
    the plate, whose y its joint holds at 0); model full: plate, dict x, vx, z, vz (n,) of the plate, and
    nut_motion, the nut's RigidMotion; a flexible shank: bolt, dict vx, vy (n,) of the bolt's end, and
    shank, dict q, q_t (n, m) of the shank's coordinates (``shank_matrices``)."""
    t = np.asarray(traj["t"], float)
    x, y, vx, vy = (np.asarray(shaken[k], float) for k in ("x", "y", "vx", "vy"))
    s, s_t = shake_travel(p, t)
    work = energy.work_trapezoid(traj["drag_force"], s)
    springs = 0.5 * p.drag_stiffness * ((s - x) ** 2 + y ** 2)
    dashpots = (energy.work_trapezoid(p.drag_damping * (s_t - vx), s - x)
                + energy.work_trapezoid(p.drag_damping * vy, y))
    if p.model == "full":
        z, vz = plate["z"], plate["vz"]
        work = work + energy.work_trapezoid(spring_load_at(p, t), z)
        springs = springs + 0.5 * p.joint_stiffness * z ** 2
        dashpots = dashpots + energy.work_trapezoid(p.joint_damping * vz, z)
        kinetic = (energy.rigid_kinetic(nut_motion, p.nut_mass, np.diag(nut_inertia_tensor(p)))
                   + 0.5 * p.plate_mass * (plate["vx"] ** 2 + vz ** 2))
    else:
        work = work + energy.work_trapezoid(lead_torque(p, t), traj["angle"])
        kinetic = 0.5 * p.nut_mass * (vx ** 2 + vy ** 2) + 0.5 * p.nut_inertia * np.asarray(traj["omega"], float) ** 2
    if bolt is not None:
        M, D, K, _ = shank_matrices(p)
        q, q_t = np.asarray(shank["q"], float), np.asarray(shank["q_t"], float)
        springs = springs + 0.5 * np.einsum("ni,ij,nj->n", q, K, q)
        dashpots = dashpots + energy.work_trapezoid(q_t @ D, q)
        kinetic = kinetic + 0.5 * np.einsum("ni,ij,nj->n", q_t, M, q_t) + 0.5 * p.bolt_mass * (
            np.asarray(bolt["vx"], float) ** 2 + np.asarray(bolt["vy"], float) ** 2)
    stored = np.zeros_like(t)
    diss = dashpots
    for law, motion, points, H in contacts:
        st, di = energy.rigid_contact_energy(law, motion, points, H)
        stored, diss = stored + st, diss + di
    return dict(work_in=work, kinetic=kinetic, potential=springs, stored=stored, dissipated=diss)


def nut_inertia_tensor(p):
    """The full nut's principal moments [kg m^2]: nut_inertia about the axis, nut_inertia / 2 +
    nut_mass nut_height^2 / 12 across it (a ring's)."""
    across = 0.5 * p.nut_inertia + p.nut_mass * p.nut_height ** 2 / 12.0
    return np.array([across, across, p.nut_inertia])
