"""Feeder scene: parts conveyed on a vibrating track, the way linear vibratory feeders convey and
orient parts.

The track (the master surface, the plane z = 0 of a heavy plate) vibrates harmonically along the
throw direction d = (cos(beta), 0, sin(beta)), beta = ``throw_angle`` from the track plane:
u(t) = amplitude sin(2 pi frequency t) d. ``parts`` identical cubes (edge ``part_size``, mass
``part_mass``, under gravity) stand on it in a row across the track (y = (i - (parts - 1)/2)
``spacing``), each on its 4 bottom corners, starting at rest. They do not touch each other (no
part-to-part contact is modelled: ``spacing`` must exceed ``part_size``).

The track's surface carries a net: ``net`` isotropic (mu_1, eps_1 in every direction) or
orthotropic, direction 1 at ``net_angle`` from the track's x axis (the conveying direction), with
friction mu_1 along it and mu_2 across, adhesion eps_1 / eps_2 likewise. Stiffnesses and the
normal dashpot are a part's totals, split over its 4 corners (docs/guide/conventions.md, "Per point or per set"). An
oblique net steers the parts sideways.

Engines: Exudyn (``exu_aniso/models/feeder.py``: the plate is a free rigid body of ``plate_mass`` on C++
spring-dampers tuned so that the integrator's discrete frequency is ``frequency``, rotations locked;
each part one contact set with the plate as moving master) and the reference engine
(``scenes.feeder.simulate_feeder``: the plate's motion prescribed exactly, every part integrated on
its own).

Measured (every engine; ``feeder_summary``): over the whole periods in the second half of the run,
every part's mean transport velocity (vx, vy), their mean, its direction and the spread between
parts (largest minus smallest x velocity); every part's yaw at the end (its orientation). Theory:
the one-dimensional stick-slip analysis of vibratory conveying, ``conveying_velocity``
(the part on the track, the net isotropic or aligned with the track, so no force across it).
"""
from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq

from exu_aniso.engines import energy
from exu_aniso.engines.reference import RUN_OPTIONS, RigidBody6, run
from exu_aniso.engines.result import Result
from exu_aniso.engines.timing import time_grid
from exu_aniso.kernel.contact_law import ContactLaw
from exu_aniso.fields.tensor_fields import Adhesion, Friction
from exu_aniso.geometry import Plane
from exu_aniso.law.return_maps import DEFAULT_RETURN_MAP, RETURN_MAPS
from exu_aniso.util.validation import check_keywords
from exu_aniso.scenes.base import (LEDGER_COLUMNS, HEADING_V_ABS, SOLVERS, energy_ledger, SceneParams,
                                   scene_parameters, solver_advice)
from exu_aniso.scenes.scene import Scene

FEEDER_PARAMS = {
    "parts": (3, "-", "number of parts, in a row across the track", "int >= 1"),
    "spacing": (0.05, "m", "distance between neighbouring parts across the track (> part_size)", "> 0"),
    "part_size": (0.02, "m", "edge of a cubic part", "> 0"),
    "part_mass": (0.02, "kg", "mass of a part", "> 0"),
    "amplitude": (2e-4, "m", "track vibration amplitude along the throw direction", "> 0"),
    "frequency": (50.0, "Hz", "track vibration frequency", "> 0"),
    "throw_angle": (20.0, "deg", "angle of the vibration from the track plane, in [0, 90)", "(-90, 90)"),
    "net": ("orthotropic", "-", "net of the track surface (friction and adhesion)", ("isotropic", "orthotropic")),
    "net_angle": (0.0, "deg", "direction 1 of the net from the track's x axis (conveying direction)", "real"),
    "mu_1": (0.3, "-", "friction coefficient along net direction 1 (isotropic: every direction)", "> 0"),
    "mu_2": (0.6, "-", "friction coefficient across (net direction 2)", "> 0"),
    "eps_n": (4e5, "N/m", "normal penalty stiffness of a part (total of its 4 corners)", "> 0"),
    "eps_1": (8e5, "N/m", "sticking stiffness of a part along net direction 1 (total; isotropic: every "
              "direction)", "> 0"),
    "eps_2": (8e5, "N/m", "sticking stiffness of a part across (total)", "> 0"),
    "normal_damping_ratio": (0.5, "-", "damping ratio of a part's normal contact vibration (dashpot "
                             "2 ratio sqrt(eps_n part_mass), total)", ">= 0"),
    "gravity": (9.81, "m/s^2", "gravity (along -z)", "> 0"),
    "plate_mass": (1e4, "kg", "mass of the vibrating plate (the parts' reaction moves it by part/plate mass)",
                   "> 0"),
    "return_map": (DEFAULT_RETURN_MAP, "-", "sliding return map", RETURN_MAPS),
    "t_end": (0.6, "s", "simulated time", "> 0"),
    "dt": (2.5e-5, "s", "time step", "> 0"),
    "solver": ("trapezoidal", "-", "time integrator", SOLVERS),
}


@scene_parameters(FEEDER_PARAMS)
class FeederParams(SceneParams):
    """Parts on a vibrating track; see FEEDER_PARAMS for units and meaning."""

    def contact_points(self):
        return 4 * self.parts                  # the corners of each part's bottom face

    def _layout_text(self):
        return f"4 corners x parts={self.parts}"

    def _check_scene(self):
        if not self.throw_angle >= 0.0:
            raise ValueError(f"throw_angle must lie in [0, 90) deg; got {self.throw_angle!r}")
        if self.parts > 1 and not self.spacing > self.part_size:
            raise ValueError(f"spacing must be > part_size (parts must not touch: no part-to-part contact is "
                             f"modelled); got spacing={self.spacing!r} <= part_size={self.part_size!r}")
        gamma = throw_number(self)
        if not gamma < 1.0:
            raise ValueError(f"the parts would leave the track: throw number amplitude (2 pi frequency)^2 "
                             f"sin(throw_angle) / gravity = {gamma:.4g} must be < 1 (amplitude={self.amplitude!r}, "
                             f"frequency={self.frequency!r}, throw_angle={self.throw_angle!r})")
        if not self.dt <= 0.02 / self.frequency:
            raise ValueError(f"dt must be <= 1/(50 frequency) = {0.02 / self.frequency:.3g} s (50 steps per "
                             f"vibration period at least); got dt={self.dt!r}")
        if not self.t_end >= 4.0 / self.frequency:
            raise ValueError(f"t_end must be >= 4 / frequency = {4.0 / self.frequency:.3g} s (the velocity is "
                             f"measured over whole periods in the second half); got t_end={self.t_end!r}")


COLUMNS = {"t": "s", "plate_u": "m", "plate_x": "m", "plate_y": "m", "plate_z": "m",
           "x": "m", "y": "m", "z": "m", "vx": "m/s", "vy": "m/s", "yaw": "rad",
           "mean_x": "m", "mean_y": "m", "mean_z": "m", "spread_x": "m",
           "force_x": "N", "force_y": "N", "force_z": "N", "sum_v2": "m^2/s^2", "sum_omega2": "1/s^2",
           "dissipated_energy": "J", **LEDGER_COLUMNS}
"""trajectory.csv: the plate's displacement along the throw direction (plate_u) and in the world
(plate_x, _y, _z), part 0's position, velocity and yaw, the parts' mean position and the spread of
their x (largest minus smallest), the track's total contact force on the parts (force_x, _y, _z),
the sums over the parts of |v|^2 and |omega|^2, the history dissipation (friction) and the energy
ledger of the parts. With the parameters these recompute the ledger's work in (the total force over
the plate's displacement, trapezoid: the work is linear in the force), kinetic energy (m sum_v2 / 2
+ J sum_omega2 / 2, J = m part_size^2 / 6 of the cube) and potential energy (parts m g (mean_z -
mean_z(0))); the contact's penalty energy and normal-dashpot dissipation need every corner's
state and are not in the file. Written by ``feeder_energy`` (a failed run's partial file has no
ledger and none of these)."""
TITLE_KEYS = ("transport_velocity", "transport_velocity_theory")


# ----------------------------------------------------------------------------------------------
# geometry, law, motion of the track, initial state

def throw_number(p):
    """A w^2 sin(beta) / g: the part leaves the track when it reaches 1."""
    w = 2.0 * math.pi * p.frequency
    return p.amplitude * w * w * math.sin(math.radians(p.throw_angle)) / p.gravity


def throw_direction(p):
    b = math.radians(p.throw_angle)
    return np.array([math.cos(b), 0.0, math.sin(b)])


def plate_motion(p, t):
    """Displacement and velocity (n, 3) of the track at times t (the exact harmonic motion)."""
    t = np.atleast_1d(np.asarray(t, dtype=float))
    w = 2.0 * math.pi * p.frequency
    d = throw_direction(p)
    return (p.amplitude * np.sin(w * t))[:, None] * d, (p.amplitude * w * np.cos(w * t))[:, None] * d


def feeder_contact_law(p):
    a = math.radians(p.net_angle)
    k = 1.0 / POINTS                                   # the parameters are a part's totals (docs/guide/conventions.md)
    if p.net == "isotropic":
        B, F = Adhesion.isotropic(k * p.eps_1), Friction.isotropic(p.mu_1)
    else:
        B, F = Adhesion.orthotropic(k * p.eps_1, k * p.eps_2, angle=a), Friction.orthotropic(p.mu_1, p.mu_2, angle=a)
    return ContactLaw(Plane(), B, F, normal_stiffness=k * p.eps_n, return_map=p.return_map,
                      normal_damping=k * normal_damping(p))


POINTS = 4                                             # a part's contact points (its bottom corners)


def normal_damping(p):
    """A part's normal dashpot [N s/m] (total): the damping ratio normal_damping_ratio of its mass
    on eps_n, 2 ratio sqrt(eps_n m). (No tangential dashpot: one parallel to friction would drag the
    part along with the track whatever the friction.)"""
    return 2.0 * p.normal_damping_ratio * math.sqrt(p.eps_n * p.part_mass)


def part_points(p):
    """Body-local contact points (4, 3): the bottom corners of the cube (centre of mass at the origin)."""
    a = 0.5 * p.part_size
    return np.array([[sx * a, sy * a, -a] for sy in (-1.0, 1.0) for sx in (-1.0, 1.0)])


def part_inertia(p):
    """Mass and principal inertia (3,) of a cubic part about its centre."""
    return p.part_mass, np.full(3, p.part_mass * p.part_size ** 2 / 6.0)


def part_positions(p):
    """Initial centres (parts, 3): in a row across the track, resting on it at the static penetration."""
    y = (np.arange(p.parts) - 0.5 * (p.parts - 1)) * p.spacing
    z = 0.5 * p.part_size - p.part_mass * p.gravity / p.eps_n
    return np.column_stack([np.zeros(p.parts), y, np.full(p.parts, z)])


def theory_mu(p):
    """(mu along the track, None), or (None, reason) when the one-dimensional theory does not apply."""
    if p.net == "isotropic":
        return p.mu_1, None
    if p.net_angle % 180.0 == 0.0:
        return p.mu_1, None
    if p.net_angle % 180.0 == 90.0:
        return p.mu_2, None
    return None, (f"net_angle: an orthotropic net at {p.net_angle!r} deg (not along or across the track) pushes "
                  "the parts across the track, the one-dimensional theory does not apply")


# the domain of the 1D conveying theory (feeder_theory), relative error of the part's transport
# velocity; tests/test_feeder.py holds its edges, docs/guide/scenes.md quotes the figures
THEORY_RTOL = 0.2
"""How far the scene may lie from the rigid-stick theory inside its domain: the elastic stick's bias
(the part lags the track while it sticks), about -2.5 f / f_stick at mu 0.3, smaller at larger mu."""
STICK_FREQUENCY_MIN = 15.0
"""Least f_stick / frequency, f_stick = sqrt(eps_1 / part_mass) / (2 pi) (eps_2 across, for a net turned
by 90 deg): the bias 2.5 f / f_stick stays within THEORY_RTOL."""
MASS_RATIO_MAX = 1e-3
"""Largest parts part_mass / plate_mass: the parts' reaction moves the plate by that ratio (the Exudyn
engine's plate is free on springs; the reference engine prescribes it); see feeder_theory."""
TRANSIENT_RTOL = 5e-2
"""Largest relative difference between the 1D model's own mean velocity over the measuring window
(from rest at t = 0) and its periodic state (a quarter of THEORY_RTOL): beyond it the window still sees
the start transient (tests/test_feeder.py::test_theory_domain_plate_mass_and_transient)."""
TRANSPORT_V_REL = 1e-4
"""A transport velocity at or below this fraction of the run's largest speed of a part (or at or
below scenes.HEADING_V_ABS) is noise: no direction (throw_angle 0, where the theory is 0:
tests/test_feeder.py::test_transport_direction_undefined_at_noise_level)."""


def stick_frequency(p):
    """f_stick [Hz] of a sticking part on its tangential stiffness along the track."""
    eps = p.eps_2 if (p.net == "orthotropic" and p.net_angle % 180.0 == 90.0) else p.eps_1
    return math.sqrt(eps / p.part_mass) / (2.0 * math.pi)


def conveying_velocity(amplitude, frequency, throw_angle, mu, gravity=9.81, periods=2000, samples=2000,
                       tolerance=1e-7, period_means=False):
    """Mean transport velocity [m/s] of a part on a linear vibratory conveyor, by the one-dimensional
    stick-slip analysis of Coulomb friction (the classic model of vibratory conveying).

    The track moves harmonically along the throw direction, ``amplitude`` A [m] at ``frequency`` f
    [Hz] and ``throw_angle`` beta [rad] from the track plane: u(t) = A sin(w t) (cos beta, sin beta)
    (tangential, normal), w = 2 pi f. The part stays on the track (throw number
    Gamma = A w^2 sin(beta) / g < 1), so its normal force per mass is n(t) = g - A w^2 sin(beta)
    sin(w t) > 0; along the track (friction coefficient ``mu`` in that direction, the track's
    direction of a principal axis of an orthotropic net, so no force across it) it
    * sticks, v = A w cos(beta) cos(w t), while the track's tangential acceleration can be carried:
      A w^2 cos(beta) |sin(w t)| <= mu n(t);
    * slides otherwise: dv/dt = -mu n(t) sign(v - w_t(t)), in closed form between events,
      v(t) = v0 - s mu (g (t - t0) + A w sin(beta) (cos(w t) - cos(w t0))), s = sign(v - w_t).
    Events (the relative velocity's zero; the stick limit) are located by scanning ``samples`` points
    per period and refining with brentq. The part starts at rest at t = 0 (the track at u = 0,
    moving); the result is the mean velocity over the first period after which two successive
    periods' means differ by less than ``tolerance`` times the track's velocity amplitude (at most
    ``periods`` periods; ValueError if not settled). With ``period_means`` it returns (that velocity,
    the list of every period's mean velocity from the start): the transient from rest, which a
    measurement over a finite window sees.

    Assumptions (the domain a simulation must lie in to be compared with it): a point mass (no
    rocking: the friction force's moment about the centre of mass must not lift an edge), rigid
    contact (stick means moving with the track exactly; no normal or tangential compliance or
    dashpot), one dimension (friction along the track only), the track's motion prescribed
    (unaffected by the part), Gamma < 1 (no flight phase), the periodic state reached."""
    for name, v in (("amplitude", amplitude), ("frequency", frequency), ("mu", mu), ("gravity", gravity)):
        if not (isinstance(v, (int, float, np.floating)) and math.isfinite(v) and v > 0):
            raise ValueError(f"conveying_velocity: {name} must be a finite number > 0; got {v!r}")
    if not (math.isfinite(throw_angle) and 0.0 <= throw_angle < 0.5 * math.pi):
        raise ValueError(f"conveying_velocity: throw_angle must lie in [0, pi/2) rad; got {throw_angle!r}")
    w = 2.0 * math.pi * frequency
    a_t, a_n = amplitude * w * w * math.cos(throw_angle), amplitude * w * w * math.sin(throw_angle)
    if a_n >= gravity:
        raise ValueError(f"conveying_velocity: the part leaves the track (throw number A w^2 sin(beta) / g = "
                         f"{a_n / gravity:.4g} >= 1); the analysis needs it on the track")
    V = amplitude * w * math.cos(throw_angle)          # track's tangential velocity amplitude
    T = 1.0 / frequency
    dt = T / samples

    def track_v(t):
        return V * math.cos(w * t)

    def carried(t):                                     # > 0 while sticking is possible
        return mu * (gravity - a_n * math.sin(w * t)) - a_t * abs(math.sin(w * t))

    def slide_v(t, t0, v0, s):
        return v0 - s * mu * (gravity * (t - t0) + a_n / w * (math.cos(w * t) - math.cos(w * t0)))

    def first_root(f, t0, t_max):
        """First t in (t0 + 1e-9 T, t_max] where f changes sign (an event right at t0 is the one that
        started the phase: skipped, so every phase advances the time)."""
        ta = min(t0 + 1e-9 * T, t_max)
        fa = f(ta)
        while ta < t_max:
            tb = min(ta + dt, t_max)
            fb = f(tb)
            if fa == 0.0:
                return ta
            if fa * fb <= 0.0:
                return brentq(f, ta, tb, xtol=1e-15 * T, rtol=1e-15)
            ta, fa = tb, fb
        return None

    # piecewise motion: phases (kind, t0, v0, s); the mean velocity per period integrates v exactly
    t, v = 0.0, 0.0
    mode = "slip"
    s = 1.0 if v - track_v(0.0) > 0 else -1.0
    means, horizon = [], periods * T
    x_period, period_end = 0.0, T

    def slide_x(t1, t0, v0, s):   # integral of slide_v from t0 to t1
        return (v0 * (t1 - t0) - s * mu * (0.5 * gravity * (t1 - t0) ** 2
                + a_n / w * (math.sin(w * t1) / w - math.sin(w * t0) / w - math.cos(w * t0) * (t1 - t0))))

    def stick_x(t1, t0):
        return amplitude * math.cos(throw_angle) * (math.sin(w * t1) - math.sin(w * t0))

    phases = 0
    while t < horizon:
        phases += 1
        if phases > 100 * periods:
            raise RuntimeError(f"conveying_velocity: more than {100 * periods} stick/slip phases in {periods} periods "
                               f"(t = {t:.6g} s): the event search does not advance")
        if mode == "slip":
            t0, v0 = t, v
            t_end = first_root(lambda tt: slide_v(tt, t0, v0, s) - track_v(tt), t0, period_end)
        else:
            t0 = t
            t_end = first_root(carried, t0, period_end)
        t_next = period_end if t_end is None else t_end
        x_period += slide_x(t_next, t0, v0, s) if mode == "slip" else stick_x(t_next, t0)
        v = slide_v(t_next, t0, v0, s) if mode == "slip" else track_v(t_next)
        t = t_next
        if t_end is not None:                            # an event: decide the next phase
            eps = 1e-9 * T
            if mode == "slip" and carried(t + eps) > 0.0:
                mode, v = "stick", track_v(t)
            else:                                        # (re)start sliding: the direction of the relative motion
                mode = "slip"
                acc_track = -a_t * math.sin(w * t)
                s = -1.0 if acc_track > 0.0 else 1.0     # the track runs away from the part: v - w_t turns negative
        if t >= period_end - 1e-12 * T:
            means.append(x_period / T)
            x_period, period_end = 0.0, period_end + T
            if len(means) >= 3 and abs(means[-1] - means[-2]) < tolerance * V:
                return (means[-1], list(means)) if period_means else means[-1]
    raise ValueError(f"conveying_velocity: no periodic state within {periods} periods (last means "
                     f"{means[-3:]}); raise periods")


def feeder_theory(p, t0=None, t1=None):
    """(transport velocity of the 1D theory, None) where it applies to the scene, else (None, reason
    naming the parameter that breaks it). ``conveying_velocity`` assumes, and the scene meets:

    * one dimension: the net isotropic or with a principal axis along the track (net_angle 0 or 90
      mod 180; ``theory_mu``);
    * a point mass: a part does not rock. The friction force at the bottom, mu N, tips a cube about
      its edge when mu (part_size / 2) >= N (part_size / 2), so mu along the track < 1 (else the
      reason names mu_1 or mu_2; tests/test_feeder.py::test_theory_domain_edge_rocking);
    * rigid stick: stick_frequency / frequency >= STICK_FREQUENCY_MIN (else eps_1, eps_2); the scene's
      bias stays within THEORY_RTOL;
    * rigid normal contact without dashpots: the normal penalty and dashpot change the result by less
      than the stick's bias, and the limit eps_1 -> oo meets the theory
      (tests/test_feeder.py::test_scene_converges_to_the_rigid_stick_theory); no tangential dashpot
      (the scene has none);
    * the track's motion prescribed: parts part_mass / plate_mass <= MASS_RATIO_MAX (plate_mass);
    * throw number < 1 (no flight): FeederParams refuses larger ones;
    * the periodic state: when the measuring window (t0, t1) is given, the 1D model's own mean over
      it, from rest at t = 0, within TRANSIENT_RTOL of its periodic state (else t_end)."""
    mu, why = theory_mu(p)
    if mu is None:
        return None, why
    name = "mu_2" if (p.net == "orthotropic" and p.net_angle % 180.0 == 90.0) else "mu_1"
    if not mu < 1.0:
        return None, (f"{name}: friction {mu:g} >= 1 along the track lets the friction force tip a cubic part about its "
                      "edge (mu part_size/2 >= part_size/2): the part rocks, the point-mass theory does not apply")
    ratio = stick_frequency(p) / p.frequency
    if ratio < STICK_FREQUENCY_MIN:
        eps = "eps_2" if name == "mu_2" else "eps_1"
        return None, (f"{eps}: sticking frequency sqrt({eps} / part_mass) / (2 pi) = {ratio:.3g} x frequency < "
                      f"{STICK_FREQUENCY_MIN:g}: the elastic stick lags the track (bias ~ {2.5 / ratio:.0%}), the "
                      "rigid-stick theory does not apply")
    m = p.parts * p.part_mass / p.plate_mass
    if m > MASS_RATIO_MAX:
        return None, (f"plate_mass: parts part_mass / plate_mass = {m:.3g} > {MASS_RATIO_MAX:g}: the parts move the "
                      "track, whose motion the theory prescribes")
    v, means = conveying_velocity(p.amplitude, p.frequency, math.radians(p.throw_angle), mu, p.gravity,
                                          period_means=True)
    if t0 is not None and t1 is not None:
        k0, k1 = int(round(t0 * p.frequency)), int(round(t1 * p.frequency))
        seen = [means[k] if k < len(means) else v for k in range(k0, max(k1, k0 + 1))]
        window = float(np.mean(seen))
        scale = max(abs(v), 1e-12 * p.amplitude * 2.0 * math.pi * p.frequency)
        if abs(window - v) > TRANSIENT_RTOL * scale:
            return None, (f"t_end: the 1D model's mean over the measuring window ({window:.4g} m/s, from rest at t = 0) "
                          f"differs from its periodic state ({v:.4g} m/s) by more than {TRANSIENT_RTOL:g}: the "
                          "window still sees the start transient")
    return v, None


# ----------------------------------------------------------------------------------------------
# trajectory, summary, energy (every engine)

def finish_trajectory(traj, P, V, yaw, H_total):
    """traj (dict with t, plate_u) completed from every part's centre P (n, parts, 3), velocity V
    (n, parts, 3), yaw (n, parts) and the total dissipated energy H_total (n,)."""
    traj.update(x=P[:, 0, 0], y=P[:, 0, 1], z=P[:, 0, 2], vx=V[:, 0, 0], vy=V[:, 0, 1], yaw=yaw[:, 0],
                mean_x=P[:, :, 0].mean(axis=1), mean_y=P[:, :, 1].mean(axis=1),
                spread_x=P[:, :, 0].max(axis=1) - P[:, :, 0].min(axis=1), dissipated_energy=H_total)
    return traj


def measure_window(p, t):
    """(t0, t1): the whole vibration periods in the second half of the run, ending at the last sample."""
    T = 1.0 / p.frequency
    t1 = float(t[-1])
    n = max(1, int(math.floor(0.5 * t1 / T + 1e-9)))
    return t1 - n * T, t1


def _at(t, y, tq):
    return np.array([np.interp(tq, t, y[:, i]) for i in range(y.shape[1])])


def feeder_summary(traj, p, wall_s, steps, newton_iterations, P, yaw, extra_steps=0, nominal_steps=None):
    """Summary of a feeder run (any engine): per part mean velocity over measure_window, their mean,
    direction and spread, yaws at the end, the theory (``feeder_theory``: None outside its domain) and
    cost. ``steps``: the nominal time steps of the run (the whole system's, the same on both engines);
    ``extra_steps``: accepted steps beyond them (step reductions, halvings); ``newton_iterations``:
    of the whole system (the reference engine, which integrates every part on its own, counts per
    step the most any part took). transport_direction_deg is None when the transport is noise:
    |v| <= max(scenes.HEADING_V_ABS, TRANSPORT_V_REL x the largest speed of part 0 in the run).
    P, yaw (n, parts, 3) and (n, parts): the parts' positions [m] and yaws [rad] per sample;
    nominal_steps: when given, ``steps`` counts every accepted step (Exudyn's count), and those
    beyond the nominal ones are the extra steps."""
    if nominal_steps is not None:
        extra_steps = max(0, steps - nominal_steps)
        steps -= extra_steps
    t = np.asarray(traj["t"], dtype=float)
    t0, t1 = measure_window(p, t)
    vx = (_at(t, P[:, :, 0], t1) - _at(t, P[:, :, 0], t0)) / (t1 - t0)
    vy = (_at(t, P[:, :, 1], t1) - _at(t, P[:, :, 1], t0)) / (t1 - t0)
    speed = float(math.hypot(vx.mean(), vy.mean()))
    s = dict(t_end=float(t[-1]), wall_s=float(wall_s), steps=int(steps), extra_steps=extra_steps,
             newton_iterations=int(newton_iterations), measured_from=t0, throw_number=throw_number(p),
             part_velocity_x=vx.tolist(), part_velocity_y=vy.tolist(),
             transport_velocity_x=float(vx.mean()), transport_velocity_y=float(vy.mean()),
             transport_velocity=speed, transport_direction_deg=None,
             velocity_spread=float(vx.max() - vx.min()),
             part_yaw_end_deg=np.degrees(yaw[-1]).tolist(), yaw_spread_deg=float(np.degrees(np.ptp(yaw[-1]))))
    undefined = {}
    if extra_steps is None:
        undefined["extra_steps"] = "the run did not complete"
    largest = float(np.hypot(np.asarray(traj["vx"], float), np.asarray(traj["vy"], float)).max())
    limit = max(HEADING_V_ABS, TRANSPORT_V_REL * largest)
    if speed > limit:
        s["transport_direction_deg"] = float(math.degrees(math.atan2(vy.mean(), vx.mean())))
    else:
        undefined["transport_direction_deg"] = (
            f"no transport: |v| = {speed:.3g} m/s <= {limit:.3g} m/s (max({HEADING_V_ABS:g} m/s, {TRANSPORT_V_REL:g} x "
            f"the largest speed of a part, {largest:.3g} m/s)); its direction is noise")
    s["transport_velocity_theory"], why = feeder_theory(p, t0, t1)
    if why is not None:
        undefined["transport_velocity_theory"] = why
    s["undefined"] = undefined
    return s


def feeder_energy(p, traj, motions, forces, law, H, plate):
    """Energy ledger of the parts (any engine), as scenes.block_energy: adds ENERGY_COLUMNS to traj.

    motions: per part an energy.RigidMotion (world frame); forces (n, parts, 3): the resultant
    contact force on each part (the track only translates, so the power it delivers is that force
    times its velocity); H (n, parts, 4, 9); plate: the track's displacement and velocity (n, 3)
    each, as the engine moved it. Work in: the track's work on the parts (trapezoid over its
    displacement); kinetic and potential (gravity) of the parts; stored and dissipated of the
    contact in the track's frame (positions relative to the track)."""
    u, ud = plate
    mass, J = part_inertia(p)
    traj.update(plate_x=u[:, 0], plate_y=u[:, 1], plate_z=u[:, 2],
                force_x=forces[:, :, 0].sum(axis=1), force_y=forces[:, :, 1].sum(axis=1),
                force_z=forces[:, :, 2].sum(axis=1), mean_z=np.mean([m.position[:, 2] for m in motions], axis=0),
                sum_v2=sum(np.sum(m.velocity ** 2, axis=1) for m in motions),
                sum_omega2=sum(np.sum(m.omega ** 2, axis=1) for m in motions))
    work = kinetic = potential = stored = diss = 0.0
    for i, m in enumerate(motions):
        work = work + energy.work_trapezoid(forces[:, i], u)
        kinetic = kinetic + energy.rigid_kinetic(m, mass, np.diag(J))
        potential = potential + mass * p.gravity * (m.position[:, 2] - m.position[0, 2])
        X, V = energy.point_motion(m, part_points(p))
        s_i, d_i = energy.contact_energy(law, X - u[:, None, :], V - ud[:, None, :], H[:, i])
        stored, diss = stored + s_i, diss + d_i
    return energy_ledger(dict(work_in=work, kinetic=kinetic, potential=potential, stored=stored, dissipated=diss),
                   traj, "feeder run", solver_advice(p))


# ----------------------------------------------------------------------------------------------
# plot

def PlotFeeder(traj, params, fig):
    """Two panels: part 0's and the mean x against t with the theory's transport line (when it
    applies: the 1D rigid-contact limit, which the penalty scene approaches as its stiffnesses
    grow), and the paths in the track plane from each one's start, in mm (the parts start metres
    apart, their paths are millimetres long)."""
    p = params
    a1, a2 = fig.subplots(2, 1)
    t = np.asarray(traj["t"], float)
    a1.plot(t, traj["x"], "C0-", lw=0.8, label="part 0: x")
    a1.plot(t, traj["mean_x"], "C1-", lw=1.2, label="mean x of the parts")
    t0, t1 = measure_window(p, t)
    v, _ = feeder_theory(p, t0, t1)
    if v is not None:
        x0 = float(np.interp(t0, t, traj["mean_x"]))
        a1.plot(t, x0 + v * (t - t0), "C3--", lw=1.0,
                label=f"1D theory, rigid contact: {v * 1e3:.2f} mm/s (approached as the stiffnesses grow)")
    a1.set(xlabel="t [s]", ylabel="x [m]", title="conveying")
    a1.grid(True, alpha=0.3)
    a1.legend(fontsize=7)
    for x, y, style, label in ((traj["mean_x"], traj["mean_y"], "C1-", "mean path of the parts"),
                               (traj["x"], traj["y"], "C0-", "part 0")):
        x, y = np.asarray(x, float), np.asarray(y, float)
        a2.plot(1e3 * (x - x[0]), 1e3 * (y - y[0]), style, lw=1.2 if style == "C1-" else 0.8, label=label)
    a2.set(xlabel="x from the start [mm]", ylabel="y from the start [mm]",
           title=f"paths, net {p.net}, net_angle {p.net_angle:g} deg")
    a2.set_aspect("equal", adjustable="datalim")        # a round-off drift across is not blown up to the axis
    a2.grid(True, alpha=0.3)
    a2.legend(fontsize=7)
    return a1, a2


# ----------------------------------------------------------------------------------------------
# the body model of the reference engine and the run there

class _FeederPart(RigidBody6):
    """One part of the feeder scene (exu_aniso.scenes.feeder) on the track, whose harmonic motion is
    prescribed exactly (scenes.feeder.plate_motion): weight as the external force, the law at the
    points relative to the track."""

    def __init__(self, p, law, x0):
        mass, J = part_inertia(p)
        super().__init__(law, part_points(p), mass, J, x0, p.part_size)
        self.p = p
        self.weight = np.array([0.0, 0.0, -mass * p.gravity])

    def master(self, t):
        u, ud = plate_motion(self.p, t)
        return u[0], ud[0]

    def points0(self, q, v):
        r, R, _ = q
        u, ud = self.master(0.0)
        return r + self.s @ R.T - u, np.zeros_like(self.s) - ud

    def external(self, q, t):
        return self.weight, np.zeros(3), np.zeros((3, 3)), np.zeros(3)

    def record(self, q, v, t, st):
        r, R, yaw = q
        return dict(x=r[0], y=r[1], z=r[2], vx=v[0], vy=v[1], vz=v[2], yaw=yaw, contact_force=st.force.sum(axis=0))


def simulate_feeder(params=None, **options):
    """Feeder scene (exu_aniso.scenes.feeder) with the reference integrator: the track's motion
    prescribed exactly, every part integrated on its own (parts do not touch). params: FeederParams
    (defaults if None); options as for simulate_block. The trajectory and the summary are those of
    exu_aniso/models/feeder.py (scenes.feeder.COLUMNS, feeder_summary with the parts' energy ledger), sampled
    at the nominal steps.

    Counts as the Exudyn engine's, for the whole system: summary ``steps`` = the nominal steps of the
    run (not their sum over the parts); ``extra_steps`` = accepted steps beyond them (halvings; a
    time at which any part took one counts once, as a joint integration would take it);
    ``newton_iterations`` = per nominal step the most iterations any part took (a joint Newton solve
    of independent parts converges when the slowest does). Per-part counts are in info:
    part_steps, part_newton_iterations (every iteration, rejected attempts included),
    part_rejected_steps."""
    p = FeederParams() if params is None else params
    if not isinstance(p, FeederParams):
        raise TypeError(f"params must be FeederParams; got {type(p).__name__}")
    check_keywords("simulate_feeder", options, RUN_OPTIONS)
    law = feeder_contact_law(p)
    grid = time_grid(p)
    runs, wall, info = [], 0.0, {}
    per_step, times, part_steps, part_iters, part_rejected = [], [], [], [], []
    for x0 in part_positions(p):
        model = _FeederPart(p, law, x0)
        traj, w, it, st, info, motion, H = run(model, p, floor=1e-6 * p.eps_n * p.part_size, **dict(options))
        on_grid = np.searchsorted(traj["t"], grid - 1e-12 * p.dt)     # rows at the nominal steps (halvings between)
        runs.append((traj, motion, H, on_grid))
        wall += w
        per_step.append(np.diff(np.cumsum(traj["newton_iterations"])[on_grid]))   # iterations per nominal step
        times.append(np.asarray(traj["t"]))
        part_steps.append(st)
        part_iters.append(it)
        part_rejected.append(info.get("rejected_steps", 0))
    steps = len(grid) - 1
    iters = int(np.max(per_step, axis=0).sum())
    instants = np.unique(np.round(np.concatenate(times) / (1e-9 * p.dt)))
    extra = int(len(instants) - len(grid))
    pick = lambda a, rows: np.asarray(a)[rows]                       # noqa: E731
    P = np.stack([np.column_stack([pick(tr[k], g) for k in ("x", "y", "z")]) for tr, _, _, g in runs], axis=1)
    V = np.stack([np.column_stack([pick(tr[k], g) for k in ("vx", "vy", "vz")]) for tr, _, _, g in runs], axis=1)
    yaw = np.stack([pick(tr["yaw"], g) for tr, _, _, g in runs], axis=1)
    forces = np.stack([pick(tr["contact_force"], g) for tr, _, _, g in runs], axis=1)
    H = np.stack([pick(h, g) for _, _, h, g in runs], axis=1)
    motions = [energy.RigidMotion(*(pick(a, g) for a in m)) for _, m, _, g in runs]
    u, ud = plate_motion(p, grid)
    out = dict(t=grid, plate_u=u @ throw_direction(p))
    finish_trajectory(out, P, V, yaw, H[:, :, :, 5].sum(axis=(1, 2)))
    summary = feeder_summary(out, p, wall, steps, iters, P, yaw, extra_steps=extra)
    summary.update(feeder_energy(p, out, motions, forces, law, H, (u, ud)))
    info.update(engine="reference", K=4 * p.parts, part_steps=part_steps, part_newton_iterations=part_iters,
                part_rejected_steps=part_rejected)
    return Result(out, summary, p, info)


# ----------------------------------------------------------------------------------------------
# the scene, as every engine and the command line see it

class FeederScene(Scene):
    """The feeder scene (the module docstring); the summary's inputs: the parts' positions P and
    yaws (and the step counts, ``feeder_summary``), the ledger's ``feeder_energy``'s (motions, forces,
    law, H, plate)."""

    name = "feeder"
    Params = FeederParams
    columns = COLUMNS
    title_keys = TITLE_KEYS
    figsize = (7.5, 6.5)
    law = staticmethod(feeder_contact_law)
    points = staticmethod(part_points)
    summary = staticmethod(feeder_summary)
    ledger = staticmethod(feeder_energy)
    plot = staticmethod(PlotFeeder)
    reference = staticmethod(simulate_feeder)

    def closed_forms(self, p):
        """The conveying theory's ``transport_velocity_theory`` [m/s] over the default measuring window
        (``feeder_theory``), None with the reason under ``undefined`` outside its assumptions."""
        value, why = feeder_theory(p)
        return dict(transport_velocity_theory=value, undefined={"transport_velocity_theory": why} if why else {})


SCENE = FeederScene()
