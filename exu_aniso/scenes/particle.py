"""Particle scene: a mass point on any surface of the protocol, under gravity, from an initial state
(the textbook oracles of a point on curved surfaces).

Frame and geometry (the surface's frame; every length in m, angles of the parameter set in DEGREES)
------------------------------------------------------------------------------------------------
* ``plane``: the plane z = 0 (Cartesian chart), slave above it on side "outside" (Plane side
  "front"), below it on "inside" ("back");
* ``cylinder``: radius ``radius`` about the x axis; "outside" a shaft, "inside" a hole;
* ``cone``: r(x) = radius + x tan(half_angle) about the x axis (half_angle 0 is the cylinder);
* ``sphere``: radius ``radius`` about the origin, the chart's pole on the x axis, so paths in the
  y-z plane (the oracles') run along the chart's equator, away from its singular poles;
* ``torus``: major radius ``radius``, tube radius ``minor_radius`` about the z axis;
* ``revolution``: the sphere of ``sphere``, written as a SurfaceOfRevolution about the x axis with
  the profile r(z) = sqrt(radius^2 - z^2) (chart (phi, z) instead of (phi, theta));
* ``parametric``: the same sphere as a ParametricSurface x(phi, theta) (the Sphere's chart, written
  by hand; projection by Newton from a grid search instead of the closed form).
  ``revolution`` and ``parametric`` make the covariance check one command: the same sphere, another
  chart or another route to the projection, the same path.

Gravity acts along (sin(tilt), 0, -cos(tilt)) in this frame: ``tilt`` tilts the surface by that
angle about the y axis so that +x runs downhill. ``eps_n``, ``eps_1``, ``eps_2`` and the dashpots
are per point (one point). Orthotropic fields: direction 1 at ``net_angle`` from the xi1 coordinate
line at every point (``nets.OrthotropicNet``), the same ``net_angle`` for adhesion and friction.

Cases (``case``)
----------------
* ``free``: the initial state is (x0, y0, z0), (vx0, vy0, vz0) as given; no oracle.
* ``departure``: a point slides from the top of a rough sphere (sphere, revolution or parametric,
  side outside, tilt 0): it starts at (0, 0, radius - m (g - speed^2 / radius) / eps_n) (the
  penetration that carries its normal force) with velocity (0, speed, 0). Measured: the polar angle
  from the top, theta = atan2(y, z), where the normal force |N| reaches 0: a quadratic fitted to
  |N| against theta over the samples of its last descent from 0.25 |N(0)| to the last sample in
  contact, and its zero next to that sample. (The gap's own crossing of 0 is a kink, linear before
  and quadratic after, that linear interpolation misses by a share of a step, and the penalty's
  normal vibration rides on it; the fit averages both out.) The point must have left for good: the
  gap stays >= 0 after that sample and exceeds 1e-4 radius at the end. Theory:
  ``point_on_surface.departure_angle`` with mu along the path (mu_1: the path runs along the xi1 lines).
* ``cavity``: a point coasts inside a spherical cavity (side inside) without gravity (gravity 0):
  it starts at (0, radius + m speed^2 / (radius eps_n), 0) with velocity (0, 0, speed), along a
  great circle of the y-z plane. Measured: the speed ratio v_end / speed and the largest relative
  deviation of |v| from speed exp(-mu psi) over the run, psi = the unwrapped angle atan2(z, y)
  turned; theory: exp(-mu psi_end) (``point_on_surface.coasting_speed``).
* ``incline``: a point slides down the top line of the cylinder (side outside) whose axis is
  inclined by ``tilt``: it starts at (0, 0, radius - m g cos(tilt) / eps_n) with velocity
  (speed, 0, 0) down the slope. Measured: the slope of a straight-line fit of vx against t over the
  samples with t >= 0.2 t_end while the point still slides (status SLIP and vx > 0); theory:
  g (sin(tilt) - mu cos(tilt)) with mu along the axis (mu_2 for an orthotropic field: the axis is
  the xi2 line). Undefined when fewer than 3 such samples remain (the point stopped).
In the oracle cases x0 ... vz0 must keep their defaults (the case sets the initial state from
``speed``); in the free case ``speed`` must. Each theory is reported only inside its domain
(``theory_domain``: one mu along the path, no tangential dashpot; the incline's point presses and
slides toward +x; ``point_on_surface.departure_angle``: friction does not stop the point), else it is None
with the reason under ``undefined``.

Summary (every engine): end state, ``speed_end``, ``contact_fraction`` (share of samples in
contact), ``slip_distance``, ``dissipated_energy``, cost figures, the case's measured value and its
theory (``departure_angle_deg`` / ``departure_angle_deg_theory``; ``cavity_speed_ratio`` /
``cavity_speed_ratio_theory`` and ``cavity_speed_error``; ``incline_acceleration`` /
``incline_acceleration_theory``), the same pair as ``oracle`` / ``oracle_theory`` (the
plot title's keys), and the energy ledger (``particle_energy``). Values that cannot be measured are
None with their reason under ``undefined``.
"""
from __future__ import annotations

import functools
import math

import numpy as np

from exu_aniso.engines import energy
from exu_aniso.engines.reference import RUN_OPTIONS, BodyModel, run
from exu_aniso.engines.result import Result
from exu_aniso.scenes import point_on_surface
from exu_aniso.law.history import HISTORY_FIELDS, SLIP
from exu_aniso.kernel.contact_law import ContactLaw
from exu_aniso.fields.tensor_fields import Adhesion, Friction
from exu_aniso.geometry import Cone, Cylinder, ParametricSurface, Plane, Sphere, SurfaceOfRevolution, Torus
from exu_aniso.law.return_maps import DEFAULT_RETURN_MAP, RETURN_MAPS
from exu_aniso.util.validation import check_instance, check_keywords
from exu_aniso.scenes.base import (LEDGER_COLUMNS, SOLVERS, energy_ledger, SceneParams, scene_parameters,
                                   solver_advice)
from exu_aniso.scenes.scene import Scene

SURFACES = ("plane", "cylinder", "cone", "sphere", "torus", "revolution", "parametric")
SPHERES = ("sphere", "revolution", "parametric")
CASES = ("free", "departure", "cavity", "incline")
LEAVE_GAP = 1e-4          # departure: the point has left for good once its gap exceeds this * radius
DEPARTURE_FIT = 0.25      # departure: |N| is fitted over its last descent below this share of |N(0)|

PARTICLE_PARAMS = {
    "case": ("departure", "-", "textbook oracle measured (free: none; the others set the initial state)", CASES),
    "surface": ("sphere", "-", "master surface (revolution / parametric: the sphere in another chart)", SURFACES),
    "side": ("outside", "-", "side of the surface the point is on (plane: outside = above z = 0)",
             ("outside", "inside")),
    "radius": (0.5, "m", "sphere / cylinder radius, cone radius at x = 0, torus major radius", "> 0"),
    "half_angle": (0.0, "deg", "cone half angle (0: the cylinder)", "(-90, 90)"),
    "minor_radius": (0.2, "m", "torus tube radius (< radius)", "> 0"),
    "x0": (0.0, "m", "initial x (case free)", "real"),
    "y0": (0.0, "m", "initial y (case free)", "real"),
    "z0": (0.5, "m", "initial z (case free)", "real"),
    "vx0": (0.0, "m/s", "initial x velocity (case free)", "real"),
    "vy0": (0.5, "m/s", "initial y velocity (case free)", "real"),
    "vz0": (0.0, "m/s", "initial z velocity (case free)", "real"),
    "speed": (0.5, "m/s", "initial speed of the oracle cases (departure, cavity, incline)", ">= 0"),
    "gravity": (9.81, "m/s^2", "magnitude of gravity", ">= 0"),
    "tilt": (0.0, "deg", "tilt of the surface about y: gravity along (sin tilt, 0, -cos tilt)", "(-90, 90)"),
    "mass": (0.1, "kg", "mass of the point", "> 0"),
    "eps_n": (1e6, "N/m", "normal penalty stiffness", "> 0"),
    "adhesion": ("isotropic", "-", "adhesion (sticking stiffness) field B", ("isotropic", "orthotropic")),
    "eps_1": (1e5, "N/m", "tangential stiffness along direction 1 (isotropic: both)", "> 0"),
    "eps_2": (1e5, "N/m", "tangential stiffness along direction 2", "> 0"),
    "friction": ("isotropic", "-", "friction field F", ("isotropic", "orthotropic")),
    "mu_1": (0.15, "-", "friction coefficient along direction 1 (isotropic: both)", "> 0"),
    "mu_2": (0.15, "-", "friction coefficient along direction 2", "> 0"),
    "net_angle": (0.0, "deg", "direction 1 of the orthotropic fields' net from the xi1 coordinate line (the same "
                  "for adhesion and friction)", "real"),
    "return_map": (DEFAULT_RETURN_MAP, "-", "sliding return map", RETURN_MAPS),
    "t_end": (1.0, "s", "simulated time", "> 0"),
    "dt": (2e-4, "s", "time step", "> 0"),
    "solver": ("trapezoidal", "-", "time integrator", SOLVERS),
    "normal_damping": (0.0, "N s/m", "normal contact dashpot", ">= 0"),
    "tangential_damping": (0.0, "N s/m", "tangential dashpot parallel to friction while loaded", ">= 0"),
}

_PD = {k: v[0] for k, v in PARTICLE_PARAMS.items()}
_STATE = ("x0", "y0", "z0", "vx0", "vy0", "vz0")


@scene_parameters(PARTICLE_PARAMS)
class ParticleParams(SceneParams):
    """Mass point on a surface of the protocol; see PARTICLE_PARAMS for units and meaning."""

    RENAMED = {"angle": "net_angle"}

    def _check_scene(self):
        if self.surface == "torus" and not self.minor_radius < self.radius:
            raise ValueError(f"minor_radius must be < radius for surface=torus (a ring torus); got "
                             f"minor_radius={self.minor_radius!r} >= radius={self.radius!r}")
        if self.case == "free":
            if self.speed != _PD["speed"]:
                raise ValueError(f"speed applies to the oracle cases only (case=free takes x0 ... vz0); "
                                 f"got speed={self.speed!r} with case=free")
            return
        for name in _STATE:
            if getattr(self, name) != _PD[name]:
                raise ValueError(f"{name} applies to case=free only (case={self.case} sets the initial state "
                                 f"from speed); got {name}={getattr(self, name)!r}")
        need = {"departure": (SPHERES, "outside"), "cavity": (SPHERES, "inside"),
                "incline": (("cylinder",), "outside")}[self.case]
        if self.surface not in need[0]:
            raise ValueError(f"surface must be one of {need[0]} for case={self.case}; got {self.surface!r}")
        if self.side != need[1]:
            raise ValueError(f"side must be {need[1]!r} for case={self.case}; got {self.side!r}")
        if self.case == "departure":
            if self.tilt != 0.0:
                raise ValueError(f"tilt must be 0 for case=departure (the start is the top); got {self.tilt!r}")
            if not self.speed ** 2 < self.gravity * self.radius:
                raise ValueError(f"speed must satisfy speed^2 < gravity * radius for case=departure (else the "
                                 f"point leaves at the top); got speed={self.speed!r}, gravity={self.gravity!r}, "
                                 f"radius={self.radius!r}")
        if self.case == "cavity":
            if self.gravity != 0.0:
                raise ValueError(f"gravity must be 0 for case=cavity (coasting without gravity); "
                                 f"got gravity={self.gravity!r}")
            if not self.speed > 0.0:
                raise ValueError(f"speed must be > 0 for case=cavity; got speed={self.speed!r}")


# trajectory columns (csv) -> SI unit
COLUMNS = {"t": "s", "x": "m", "y": "m", "z": "m", "vx": "m/s", "vy": "m/s", "vz": "m/s", "gap": "m",
           "normal_force": "N", "status": "-", "slip_distance": "m", "dissipated_energy": "J",
           **LEDGER_COLUMNS}
TITLE_KEYS = ("oracle", "oracle_theory")
ORACLE_KEYS = {"departure": ("departure_angle_deg", "departure_angle_deg_theory"),
               "cavity": ("cavity_speed_ratio", "cavity_speed_ratio_theory"),
               "incline": ("incline_acceleration", "incline_acceleration_theory")}


# ----------------------------------------------------------------------------------------------
# geometry, law, initial state

def _sphere_profile(R):
    def profile(z):
        r = math.sqrt(R * R - z * z)
        return r, -z / r, -R * R / (r * r * r)
    return profile


def _sphere_point(R):
    """x(phi, theta) of the Sphere(R, axis_direction=(1, 0, 0)) chart: pole on x, phi from y to z."""
    def point(phi, theta):
        cp, sp, ct, st = math.cos(phi), math.sin(phi), math.cos(theta), math.sin(theta)
        x = np.array([R * ct, R * st * cp, R * st * sp])
        dx = np.array([[0.0, -R * st * sp, R * st * cp], [-R * st, R * ct * cp, R * ct * sp]])
        ddx = np.array([[[0.0, -R * st * cp, -R * st * sp], [0.0, -R * ct * sp, R * ct * cp]],
                        [[0.0, -R * ct * sp, R * ct * cp], [-R * ct, -R * st * cp, -R * st * sp]]])
        return x, dx, ddx
    return point


@functools.lru_cache(maxsize=32)
def _surface(kind, side, radius, half_angle, minor_radius):
    x_axis = (1.0, 0.0, 0.0)
    if kind == "plane":
        return Plane(side="front" if side == "outside" else "back")
    if kind == "cylinder":
        return Cylinder(radius, axis_direction=x_axis, side=side)
    if kind == "cone":
        return Cone(math.radians(half_angle), radius, axis_direction=x_axis, side=side)
    if kind == "sphere":
        return Sphere(radius, axis_direction=x_axis, side=side)
    if kind == "torus":
        return Torus(radius, minor_radius, side=side)
    if kind == "revolution":
        return SurfaceOfRevolution(_sphere_profile(radius), axis_direction=x_axis, side=side)
    # the Sphere's chart is inward (rho_1 x rho_2 = -R^2 sin(theta) e_r): "outside" is its back
    eps = 1e-3
    return ParametricSurface(_sphere_point(radius), side="back" if side == "outside" else "front",
                             periods=(2.0 * math.pi, 0.0), bounds=((-math.pi, math.pi), (eps, math.pi - eps)))


def particle_surface(p):
    """The master surface of the scene (in the scene's frame; see the module docstring). Built once
    per distinct geometry in a process (user surfaces compile their function)."""
    return _surface(p.surface, p.side, p.radius, p.half_angle, p.minor_radius)


def particle_contact_law(p, surface=None):
    """ContactLaw of the scene (one point: the stiffnesses as given); surface: another surface of
    the protocol instead of the scene's (tests: a ParametricSurface of one's own)."""
    a = math.radians(p.net_angle)
    B = (Adhesion.isotropic(p.eps_1) if p.adhesion == "isotropic"
         else Adhesion.orthotropic(p.eps_1, p.eps_2, angle=a))
    F = Friction.isotropic(p.mu_1) if p.friction == "isotropic" else Friction.orthotropic(p.mu_1, p.mu_2, angle=a)
    return ContactLaw(particle_surface(p) if surface is None else surface, B, F, normal_stiffness=p.eps_n,
                      return_map=p.return_map, normal_damping=p.normal_damping,
                      tangential_damping=p.tangential_damping)


def gravity_vector(p):
    """Gravity [m/s^2] in the surface's frame: g (sin(tilt), 0, -cos(tilt))."""
    t = math.radians(p.tilt)
    return p.gravity * np.array([math.sin(t), 0.0, -math.cos(t)])


def initial_state(p):
    """Initial position and velocity (3,), (3,) of the point [m, m/s] (see the module docstring)."""
    R, m, v0 = p.radius, p.mass, p.speed
    if p.case == "free":
        return np.array([p.x0, p.y0, p.z0]), np.array([p.vx0, p.vy0, p.vz0])
    if p.case == "departure":
        return np.array([0.0, 0.0, R - m * (p.gravity - v0 * v0 / R) / p.eps_n]), np.array([0.0, v0, 0.0])
    if p.case == "cavity":
        return np.array([0.0, R + m * v0 * v0 / (R * p.eps_n), 0.0]), np.array([0.0, 0.0, v0])
    t = math.radians(p.tilt)
    return np.array([0.0, 0.0, R - m * p.gravity * math.cos(t) / p.eps_n]), np.array([v0, 0.0, 0.0])


def path_mu(p):
    """(mu along the oracle's path, None) or (None, reason): the path runs along the xi1 lines
    (departure, cavity) or the xi2 line (incline: the cylinder's axis); on these orthogonal charts an
    orthotropic F has a principal direction along the path when ``net_angle`` is a multiple of 90 deg
    (direction 1 along xi1 at 0 and 180 deg, along xi2 at 90 and 270 deg)."""
    name, mu = _path_mu_name(p)
    if name is None:
        return None, (f"net_angle={p.net_angle:g} deg with friction=orthotropic: the path does not run along a principal "
                      "direction of F (net_angle a multiple of 90 deg), so no single mu applies to the textbook oracle")
    return mu, None


def _path_mu_name(p):
    """(name of the parameter that is mu along the path, its value), or (None, None) off the axes."""
    if p.friction == "isotropic":
        return "mu_1", p.mu_1
    if p.net_angle % 90.0 != 0.0:
        return None, None
    name = "mu_1" if (p.net_angle % 180.0 == 0.0) == (p.case != "incline") else "mu_2"
    return name, getattr(p, name)


def theory_domain(p):
    """None when the case's textbook oracle applies to p, else the one-sentence reason naming the
    parameter that breaks its assumptions. Rules (each held by tests/test_particle_scene.py; the
    departures from the oracles outside them: docs/guide/surfaces_and_fields.md):

    * friction: one mu along the path (isotropic, or orthotropic at a multiple of 90 deg: ``path_mu``);
      the return map does not matter there (seed, exact, radial: the same angle to 2e-9 deg), unless
      the adhesion B is orthotropic off the axes (eps_1 != eps_2, net_angle not a multiple of 90 deg): the
      non-associated maps (seed, radial) then slide with T along B v, not v, which bends the path; the
      exact map stays on the oracle, so only seed and radial are refused there;
    * tangential_damping must be 0: the dashpot acts with friction while the point slides (all three
      oracles slide), so the sliding law is no longer Coulomb's;
    * normal_damping is allowed at any value: along the oracles' paths n.v follows only the penalty's
      own penetration rate, so the dashpot takes a share of N but not its value (the oracles' errors
      stay within their budget);
    * incline: gravity > 0 (else N = 0: no contact, nothing slides), and a point that starts at rest
      (speed 0) must slide toward +x: tan(tilt) > mu (with tan|tilt| <= mu it sticks, with tilt < 0 it
      slides toward -x, outside the formula's sense);
    * departure: ``point_on_surface.departure_angle`` refuses a point that friction stops (OutsideDomain),
      e.g. speed 0, or mu above about 0.231 at the default speed 0.5 m/s, radius 0.5 m.
    The cavity's other assumptions (gravity 0, side inside, speed > 0) are parameter rules of the case."""
    if p.case == "free":
        return "case=free has no textbook oracle"
    mu, why = path_mu(p)
    if why:
        return why
    if (p.return_map != "exact" and p.adhesion == "orthotropic" and p.eps_1 != p.eps_2
            and p.net_angle % 90.0 != 0.0):
        return (f"return_map={p.return_map} with adhesion=orthotropic at net_angle={p.net_angle:g} deg (eps_1 != eps_2): "
                "this non-associated map turns the friction force toward B v, off the sliding direction, the "
                "textbook oracle assumes friction against the sliding (return_map=exact keeps it)")
    if p.tangential_damping > 0.0:
        return (f"tangential_damping={p.tangential_damping:g} N s/m > 0: the dashpot acts with friction while the "
                "point slides, the textbook oracle assumes Coulomb friction alone (tangential_damping 0)")
    if p.case == "incline":
        t = math.radians(p.tilt)
        if not p.gravity > 0.0:
            return "gravity=0: the point does not press on the cylinder (N = m g cos(tilt) = 0), nothing slides"
        if p.speed == 0.0 and abs(math.tan(t)) <= mu:
            return (f"speed=0 and tan|tilt| = {abs(math.tan(t)):.6g} <= mu = {mu:g}: friction holds the point at "
                    "rest (sticking rule), it never slides")
        if p.speed == 0.0 and p.tilt < 0.0:
            return (f"speed=0 with tilt={p.tilt:g} deg < 0: the point slides toward -x, the oracle's formula is "
                    "for sliding toward +x")
    return None


def particle_theory(p, psi=None):
    """(theory, None) or (None, reason) of the case's oracle (see theory_domain): departure: the angle
    [deg] of ``point_on_surface.departure_angle``; cavity: v / v0 = exp(-mu psi) [-] at the turned angles psi
    [rad] (an array); incline: the acceleration [m/s^2]."""
    why = theory_domain(p)
    if why:
        return None, why
    name, mu = _path_mu_name(p)
    if p.case == "departure":
        try:
            return math.degrees(point_on_surface.departure_angle(mu, p.radius, p.gravity, p.speed)), None
        except point_on_surface.OutsideDomain as e:       # the message names mu, speed and the sticking rule
            return None, f"{str(e).split(': ', 1)[1]} ({name} is mu along the path)"
    if p.case == "cavity":
        return point_on_surface.coasting_speed(p.speed, mu, psi) / p.speed, None
    return point_on_surface.incline_acceleration(mu, math.radians(p.tilt), p.gravity), None


def particle_closed_forms(p):
    """The particle's closed form for p, under the case's theory key (``ORACLE_KEYS``): departure:
    ``departure_angle_deg_theory`` [deg]; incline: ``incline_acceleration_theory`` [m/s^2]; cavity:
    ``cavity_speed_decay_per_rad`` [1/rad], mu along the path, of v / v0 = exp(-mu psi) (its ratio
    at the run's end is the summary's ``cavity_speed_ratio_theory``). None, with the reason under
    ``undefined``, outside the theory's domain (``theory_domain``); the free case has none."""
    if p.case == "free":
        return dict(undefined={})
    key = "cavity_speed_decay_per_rad" if p.case == "cavity" else ORACLE_KEYS[p.case][1]
    if p.case == "cavity":
        why = theory_domain(p)
        value = None if why else _path_mu_name(p)[1]
    else:
        value, why = particle_theory(p)
    return {key: value, "undefined": {key: why} if why else {}}


# ----------------------------------------------------------------------------------------------
# trajectory, summary, energy (every engine)

_NORMAL = HISTORY_FIELDS.index("normal")
_STATUS = HISTORY_FIELDS.index("status")


def finish_trajectory(traj, law, H):
    """Add the contact columns from the positions and the converged history H (n, 1, 9): gap (the
    signed normal distance from the surface, projected afresh), normal_force (|N| >= 0) and the
    status (0 open, 1 stick, 2 slip)."""
    H = np.asarray(H, dtype=float).reshape(len(traj["t"]), -1, len(HISTORY_FIELDS))
    X = np.column_stack([traj["x"], traj["y"], traj["z"]])
    traj["gap"] = law.gap_and_normal(X)[0]
    traj["normal_force"] = -H[:, 0, _NORMAL]
    traj["status"] = H[:, 0, _STATUS].astype(float)
    return traj


def particle_motion(traj):
    """energy.RigidMotion of the point (no rotation)."""
    n = len(traj["t"])
    return energy.RigidMotion(np.column_stack([traj["x"], traj["y"], traj["z"]]),
                              np.broadcast_to(np.eye(3), (n, 3, 3)),
                              np.column_stack([traj["vx"], traj["vy"], traj["vz"]]), np.zeros((n, 3)))


def particle_energy(p, traj, law, H):
    """Energy ledger of a particle run (any engine), as scenes.block_energy: adds the ENERGY_COLUMNS
    to traj and returns the summary entries (energy, energy_ok, energy_tolerance). No work in (no
    drive); kinetic m |v|^2 / 2; potential -m g . (x - x0); stored and dissipated of the contact law
    (normal penalty, adhesion, friction, dashpots)."""
    motion = particle_motion(traj)
    stored, diss = energy.rigid_contact_energy(law, motion, np.zeros((1, 3)),
                                               np.asarray(H, dtype=float).reshape(len(traj["t"]), 1, -1))
    potential = -p.mass * (motion.position - motion.position[0]) @ gravity_vector(p)
    return energy_ledger(dict(work_in=np.zeros(len(traj["t"])),
                        kinetic=0.5 * p.mass * np.sum(motion.velocity ** 2, axis=1),
                        potential=potential, stored=stored, dissipated=diss), traj, "particle run",
                   solver_advice(p))


def _departure(p, traj):
    """(angle [deg], None) or (None, reason): see the module docstring."""
    gap = np.asarray(traj["gap"], float)
    N = np.asarray(traj["normal_force"], float)
    theta = np.arctan2(np.asarray(traj["y"], float), np.asarray(traj["z"], float))
    pressed = np.nonzero(gap < 0.0)[0]
    if not pressed.size or pressed[-1] + 1 >= len(gap) or not gap[-1] > LEAVE_GAP * p.radius:
        if pressed.size and gap[-1] < 0.0:
            v_end = math.sqrt(sum(float(traj[k][-1]) ** 2 for k in ("vx", "vy", "vz")))
            return None, (f"the point is still on the sphere at t_end (speed_end = {v_end:.3g} m/s: stopped by "
                          "friction if ~0, else raise t_end)")
        return None, "the point did not leave the sphere within t_end (or never pressed on it)"
    k = pressed[-1]                                  # the last sample in contact before leaving for good
    above = np.nonzero(N[:k + 1] >= DEPARTURE_FIT * N[0])[0]
    sel = np.arange(above[-1] + 1 if above.size else 0, k + 1)      # the last descent below the share
    sel = sel[N[sel] > 0.0]
    if sel.size < 5:
        return None, (f"fewer than 5 samples with 0 < |N| < {DEPARTURE_FIT:g} |N(0)| before the point left "
                      f"({sel.size}): refine dt")
    c = np.polyfit(theta[sel], N[sel], 2)
    roots = np.roots(c)
    roots = roots[np.isreal(roots)].real
    if not roots.size:
        return None, "the fit of |N| against the angle has no zero"
    return math.degrees(roots[np.argmin(np.abs(roots - theta[k]))]), None


def _cavity(p, traj):
    y, z = np.asarray(traj["y"], float), np.asarray(traj["z"], float)
    psi = np.unwrap(np.arctan2(z, y))
    psi = psi - psi[0]
    v = np.sqrt(np.asarray(traj["vx"], float) ** 2 + np.asarray(traj["vy"], float) ** 2
                + np.asarray(traj["vz"], float) ** 2)
    return v, psi


def particle_summary(traj, params, wall_s, steps, newton_iterations):
    """Summary of a particle trajectory (see the module docstring); the energy ledger is added by
    the engines (particle_energy)."""
    p = params
    t = np.asarray(traj["t"], float)
    vx, vy, vz = (np.asarray(traj[k], float) for k in ("vx", "vy", "vz"))
    speed = np.sqrt(vx * vx + vy * vy + vz * vz)
    status = np.asarray(traj["status"], float)
    undefined = {}
    s = dict(case=p.case, x_end=float(traj["x"][-1]), y_end=float(traj["y"][-1]), z_end=float(traj["z"][-1]),
             vx_end=float(vx[-1]), vy_end=float(vy[-1]), vz_end=float(vz[-1]), speed_end=float(speed[-1]),
             contact_fraction=float(np.mean(status > 0.5)), slip_fraction=float(np.mean(status == SLIP)),
             slip_distance=float(traj["slip_distance"][-1]), dissipated_energy=float(traj["dissipated_energy"][-1]),
             wall_s=float(wall_s), steps=int(steps), newton_iterations=int(newton_iterations))
    measured = theory = None
    if p.case == "departure":
        measured, why = _departure(p, traj)
        if why:
            undefined["departure_angle_deg"] = why
        theory, why_t = particle_theory(p)
        s["departure_angle_deg"], s["departure_angle_deg_theory"] = measured, theory
    elif p.case == "cavity":
        v, psi = _cavity(p, traj)
        s["cavity_psi_end_deg"] = float(math.degrees(psi[-1]))
        measured = float(v[-1] / p.speed)
        ratio, why_t = particle_theory(p, psi)
        s["cavity_speed_error"] = None
        if ratio is not None:
            theory = float(ratio[-1])
            s["cavity_speed_error"] = float(np.max(np.abs(v / p.speed - ratio) / ratio))
        else:
            undefined["cavity_speed_error"] = why_t
        s["cavity_speed_ratio"], s["cavity_speed_ratio_theory"] = measured, theory
    elif p.case == "incline":
        sel = (t >= 0.2 * t[-1]) & (status == SLIP) & (vx > 0.0)
        if np.count_nonzero(sel) >= 3:
            measured = float(np.polyfit(t[sel], vx[sel], 1)[0])
        else:
            undefined["incline_acceleration"] = (f"fewer than 3 samples at t >= 0.2 t_end with the point sliding "
                                                 f"toward +x ({int(np.count_nonzero(sel))}): it stopped or never "
                                                 "slid that way")
        theory, why_t = particle_theory(p)
        s["incline_acceleration"], s["incline_acceleration_theory"] = measured, theory
    if p.case != "free":
        keys = ORACLE_KEYS[p.case]
        if theory is None:
            undefined[keys[1]] = why_t
        if measured is None:
            undefined["oracle"] = undefined.get(keys[0], "not measured")
        if theory is None:
            undefined["oracle_theory"] = why_t
    else:
        undefined["oracle"] = undefined["oracle_theory"] = "case=free has no textbook oracle"
    s["oracle"], s["oracle_theory"] = measured, theory
    s["undefined"] = undefined
    return s


# ----------------------------------------------------------------------------------------------
# plot

def PlotParticle(traj, params, fig):
    """Two panels on the matplotlib Figure ``fig``: the path (the y-z plane for the sphere cases and
    the torus, the x-z plane otherwise) over the surface's section, and the case's oracle against
    theory (departure: the normal force against the polar angle from the top, the theory's angle
    marked; cavity: the speed against the angle turned with v0 exp(-mu psi); incline: vx against t
    with the theory's slope; free: speed and normal force against t). Returns the two Axes."""
    p = params
    a1, a2 = fig.subplots(1, 2)
    x, y, z = (np.asarray(traj[k], float) for k in ("x", "y", "z"))
    t = np.asarray(traj["t"], float)
    R = p.radius
    yz = p.surface in SPHERES or p.surface == "torus"
    h, v = (y, z) if yz else (x, z)
    a1.plot(h, v, "C0-", lw=1.2, label="path")
    a1.plot(h[:1], v[:1], "ko", ms=4, label="start")
    s = np.linspace(0.0, 2.0 * math.pi, 361)
    if p.surface in SPHERES:
        a1.plot(R * np.cos(s), R * np.sin(s), color="0.6", lw=0.8, label="surface")
    elif p.surface == "torus":
        for c in (-R, R):
            a1.plot(c + p.minor_radius * np.cos(s), p.minor_radius * np.sin(s), color="0.6", lw=0.8)
    elif p.surface == "plane":
        a1.axhline(0.0, color="0.6", lw=0.8)
    else:
        xs = np.linspace(min(x.min(), -R), max(x.max(), R), 50)
        r = R + (xs * math.tan(math.radians(p.half_angle)) if p.surface == "cone" else 0.0)
        a1.plot(xs, r + 0 * xs, color="0.6", lw=0.8, label="surface (top line)")
    a1.set(xlabel=("y" if yz else "x") + " [m]", ylabel="z [m]", title="path")
    a1.set_aspect("equal", adjustable="datalim")
    a1.legend(fontsize=7)
    theory = particle_theory(p)[0] if p.case in ("departure", "incline") else None
    if p.case == "departure":
        th = np.degrees(np.arctan2(y, z))
        a2.plot(th, traj["normal_force"], "C0-", label="|N| (simulation)")
        if theory is not None:
            a2.axvline(theory, color="C3", ls="--",
                       label="departure angle (theory)")
        a2.set(xlabel="angle from the top [deg]", ylabel="normal force [N]")
    elif p.case == "cavity":
        vel, psi = _cavity(p, traj)
        a2.plot(np.degrees(psi), vel, "C0-", label="|v| (simulation)")
        ratio = particle_theory(p, psi)[0]
        if ratio is not None:
            a2.plot(np.degrees(psi), p.speed * ratio, "C3--", label="v0 exp(-mu psi)")
        a2.set(xlabel="angle turned psi [deg]", ylabel="speed [m/s]")
    elif p.case == "incline":
        a2.plot(t, traj["vx"], "C0-", label="vx (simulation)")
        if theory is not None:
            a2.plot(t, p.speed + theory * t, "C3--", label="speed + g (sin a - mu cos a) t")
        a2.set(xlabel="t [s]", ylabel="velocity down the slope [m/s]")
    else:
        vel = np.sqrt(sum(np.asarray(traj[k], float) ** 2 for k in ("vx", "vy", "vz")))
        a2.plot(t, vel, "C0-", label="speed [m/s]")
        a2.plot(t, traj["normal_force"], "C1-", label="|N| [N]")
        a2.set(xlabel="t [s]")
    a2.grid(True, alpha=0.3)
    a2.legend(fontsize=7)
    return a1, a2


# ----------------------------------------------------------------------------------------------
# the body model of the reference engine and the run there

class _MassPoint(BodyModel):
    """Mass point: q = x (3,) in the master frame, v = dx/dt; one contact point at x."""

    n = 3
    K = 1

    def __init__(self, p, law):
        self.p, self.law = p, law
        self.mass = np.full(3, p.mass)
        self.row_scale = np.ones(3)
        self.dof_scale = np.full(3, p.radius)
        self.q0, self.v0 = initial_state(p)
        self.weight = p.mass * gravity_vector(p)

    def points0(self, q, v):
        return q[None, :], v[None, :]

    def evaluate(self, q, v, t, H, tangent=True, dt=None):
        st = self.law.evaluate(q[None, :], v[None, :], H, tangent, dt)
        g = st.force[0] + self.weight
        if not tangent:
            return g, None, None, st
        return g, st.stiffness[0].copy(), st.damping[0].copy(), st

    def motion(self, q, v):
        return q.copy(), np.eye(3), v.copy(), np.zeros(3)

    def record(self, q, v, t, st):
        return dict(x=q[0], y=q[1], z=q[2], vx=v[0], vy=v[1], vz=v[2])


def simulate_particle(params=None, **options):
    """Particle scene (exu_aniso.scenes.particle) with the reference integrator; params:
    ParticleParams (defaults if None). Options as for simulate_block, law: a ContactLaw replacing
    the scene's (e.g. on a surface of one's own). Returns Result with the trajectory keys of
    scenes.particle.COLUMNS (plus h, newton_iterations) and particle_summary with the energy ledger."""
    p = ParticleParams() if params is None else params
    if not isinstance(p, ParticleParams):
        raise TypeError(f"params must be ParticleParams; got {type(p).__name__}")
    check_keywords("simulate_particle", options, RUN_OPTIONS + ("law",))
    law = options.pop("law", None)
    if law is not None:
        check_instance("law", law, ContactLaw)
    model = _MassPoint(p, particle_contact_law(p) if law is None else law)
    floor = 1e-6 * p.eps_n * p.radius
    traj, wall, iters, steps, info, motion, H = run(model, p, floor=floor, **options)
    finish_trajectory(traj, model.law, H)
    summary = particle_summary(traj, p, wall, steps, iters)
    summary.update(particle_energy(p, traj, model.law, H))
    info.update(engine="reference")
    return Result(traj, summary, p, info)


# ----------------------------------------------------------------------------------------------
# the scene, as every engine and the command line see it

class ParticleScene(Scene):
    """The particle scene (the module docstring); the summary takes no inputs, the ledger
    ``particle_energy``'s (law, H)."""

    name = "particle"
    Params = ParticleParams
    columns = COLUMNS
    title_keys = TITLE_KEYS
    figsize = (6.0, 6.5)
    law = staticmethod(particle_contact_law)
    closed_forms = staticmethod(particle_closed_forms)
    summary = staticmethod(particle_summary)
    ledger = staticmethod(particle_energy)
    plot = staticmethod(PlotParticle)
    reference = staticmethod(simulate_particle)

    def points(self, p):
        """The one contact point: the mass point itself."""
        return np.zeros((1, 3))


SCENE = ParticleScene()
