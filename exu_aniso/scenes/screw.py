"""The screw scene: a rigid cylindrical screw in a hole (cylinder of radius ``radius``, axis z, contact
on its inside) with a spiral (thread-like) net, pressed by an interference fit (conventions: the
module docstring of ``exu_aniso.scenes.base``).

Its parameters (``SCREW_PARAMS``, ``ScrewParams``), contact law, points, inertia, pitch, summary and
energy ledger; its body models for the reference engine (``exu_aniso.engines.reference``) with its
run there (``simulate_screw``): the reduced model (psi, z) on the hole's axis or a 6-DOF rigid
cylinder in the hole; and its closed-form steady sliding (``steady_sliding``, what
``exu_aniso.calibration`` fits to). The Exudyn model script is ``exu_aniso.models.screw``.

Body models of the reference engine (state = configuration + velocity; generalized coordinates in
brackets):

* "reduced" (psi, z): rotation psi about the hole axis z and axial position z of the COM; the
  screw axis stays on the hole axis. Inertia J_axial = m r^2 / 2, m.
* "full": the 6-DOF rigid cylinder (``RigidBody6``; J_axial = m r^2/2, J_transverse =
  m (3 r^2 + L^2)/12) in the hole (axis z), no gravity; axial_load along +z.

Drives: "torque": constant tau about +z; "rotation": tau = k (omega_d t - psi); "axial":
F = k (v_d t - z); axial_load along +z always. In the full screw psi is the unwrapped yaw
atan2(R_10, R_00) (exact for rotations about z, the motion of interest; a small tilt perturbs it at
second order).

Steady sliding in closed form (``steady_sliding``)
--------------------------------------------------
In the reduced model the screw stays on the hole axis, so every point carries the same normal force;
the total is ``N = eps_n * interference``. In steady sliding (rotation speed and axial speed
constant, inertia forces zero) the total tangential traction the hole exerts on the screw is
``T = -(tau e_phi + axial_load e_z)``: ``tau`` balances the drive torque (torque = R * tau with
the hole radius R: the traction acts where the slip is measured, see exu_aniso.kernel.point, step 5) and the axial
part balances the axial load. Write
``S = -T = tau e_phi + axial_load e_z`` in the helix frame (e1 = cos a e_phi + sin a e_z,
e2 = -sin a e_phi + cos a e_z). Sliding puts it on the friction ellipse

    (S.e1)^2 / mu_1^2 + (S.e2)^2 / mu_2^2 = N^2          ->  tau (quadratic, positive root),

which gives the sliding torque. It is also the threshold of sustained sliding under the torque drive
(below it the screw sticks). The direction of the slip rate depends on the return map:

* ``radial``: slip along ``C^-1 S`` (components S_i / eps_i): the ADHESION ratio r = eps_1/eps_2 sets
  the kinematics and the friction coefficients do not;
* ``exact``: slip along ``F S`` (components S_i / mu_i^2): the kinematics follow from mu_1/mu_2
  only, B does not matter in steady sliding;
* ``seed``: no closed form. Its steady state follows the dominant eigenvector of C F and depends
  on the step size (see studies/screw_driving.py), so it is not calibrated here.

The advance per revolution is ``2 pi R v_z / v_phi`` (R the hole radius, where the slip is measured).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from exu_aniso.engines import energy
from exu_aniso.engines.reference import RUN_OPTIONS, RigidBody6, ScrewJoint, run
from exu_aniso.engines.result import Result
from exu_aniso.kernel.contact_law import ContactLaw
from exu_aniso.scenes.plotting import CLOSED_FORM_GID, axes_of, drawn, finite_rows, labelled, note
from exu_aniso.util.validation import check_instance, check_keywords
from exu_aniso.fields.tensor_fields import Adhesion, Friction
from exu_aniso.geometry import Cone, Cylinder
from exu_aniso.law.return_maps import RETURN_MAPS
from exu_aniso.scenes.base import LEDGER_COLUMNS, SOLVERS, energy_ledger, SceneParams, scene_parameters, solver_advice
from exu_aniso.scenes.scene import Scene


TURN_ANGLE_MIN = 1e-6    # rad: a net rotation over the last half at or below this is no turning


# Default normal damping of the screw [N s/m, total]. The full screw's lateral contact mode (k_lat
# = eps_n / 2 = 5e6 N/m for a ring of points, m = 0.01 kg, 3.6 kHz; critical 2 sqrt(k_lat m) = 447
# N s/m, the dashpots act laterally with d / 2) flutters under friction. Resolved in time (dt <=
# 1e-4) it grows at 95 1/s with 100 N s/m and not at all with 200; at the default dt = 1e-3 the
# trapezoidal rule under-resolves it and growth is slower but still ruins a 2 s run without
# damping (studies/hard_cases.py, stability table). 300 N s/m is 34 % of critical. The reduced
# screw's points move along the hole wall (n . v = 0), so the damping does not act there, and the
# centred full screw then equals the reduced one.
SCREW_NORMAL_DAMPING = 300.0


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
    "return_map": ("radial", "-", "sliding return map; radial here, the package's default is exact: the papers' "
                   "screw slides where the spiral adhesion steers it", RETURN_MAPS),
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
                       "equally over the K points; the default damps the full screw's lateral mode "
                       "(docs/guide/command_line.md)", ">= 0"),
    "tangential_damping": (0.0, "N s/m", "total tangential dashpot parallel to friction while loaded, split equally "
                           "over the K points", ">= 0"),
    "surface": ("cylinder", "-", "thread surface: cylinder (the papers' hole) or cone (a tapered thread: the hole "
                "r(z) = radius + z tan(half_angle), the screw's points on the parallel cone)", ("cylinder", "cone")),
    "half_angle": (0.0, "deg", "half angle of the cone (surface = cone); 0 is the cylinder exactly; a 1:16 taper "
                   "on the diameter is 1.79 deg", "(-45, 45)"),
}


@scene_parameters(SCREW_PARAMS)
class ScrewParams(SceneParams):
    """Screw in a threaded hole with a spiral net; see SCREW_PARAMS for units and meaning."""

    def contact_points(self):
        return self.rings * self.points_per_ring

    def _layout_text(self):
        return f"rings={self.rings} x points_per_ring={self.points_per_ring}"

    def _check_scene(self):
        if self.model == "full" and self.points_per_ring < 3:
            raise ValueError(f"points_per_ring must be >= 3 for model='full' (radial centring); "
                             f"got {self.points_per_ring}")


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


def screw_inertia(p):
    """Mass [kg] and body-frame inertia tensor (3, 3) [kg m^2] of the screw: a solid cylinder of
    radius ``radius`` and length ``length`` about its COM, axis z."""
    m, r, L = p.mass, p.radius, p.length
    Jt = m * (3.0 * r * r + L * L) / 12.0
    return m, np.diag([Jt, Jt, 0.5 * m * r * r])


def pitch(p):
    """Thread pitch 2 pi R tan(alpha) of the spiral net [m per revolution]."""
    return 2.0 * math.pi * p.radius * math.tan(math.radians(p.helix_angle))


SCREW_SUMMARY_KEYS = ("angle_end", "z_end", "advance_per_rev", "advance_per_rev_theory", "torque_mean",
                      "torque_mean_theory", "axial_force_mean", "dissipated_energy", "wall_s", "steps",
                      "newton_iterations", "undefined")


def reduced_motion(traj):
    """energy.RigidMotion of the reduced screw (a turn about and a travel along z) from its
    trajectory's coordinates."""
    return energy.motion_about_z(0.0, 0.0, traj["z"], traj["angle"], 0.0, 0.0, traj["vz"], traj["omega"])


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
    stored, diss = energy.rigid_contact_energy(law, motion, points, H)
    work = energy.work_trapezoid(traj["torque"], traj["angle"]) + energy.work_trapezoid(traj["axial_force"], traj["z"])
    return energy_ledger(dict(work_in=work, kinetic=energy.rigid_kinetic(motion, mass, J),
                        potential=np.zeros(len(traj["t"])), stored=stored, dissipated=diss), traj, "screw run",
                   solver_advice(p))


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


def _not_steady_sliding(t, ang, torque, diss):
    """Reason why the samples of the last half (t, angle, drive torque, dissipated energy) are not
    steady sliding, or None. Steady sliding: in every output step the screw turns forward (d angle
    > 0) and its contact slides, i.e. dissipates at least half the drive's work of that step
    (d dissipated >= torque d angle / 2; in steady sliding they are equal). A screw that sticks
    (it turns only by the elastic wind-up of its contact) or that stops and turns back in a
    stick-slip cycle fails it."""
    if len(t) < 2:
        return f"fewer than two samples in the last half of the run ({len(t)})"
    dang, ddiss = np.diff(ang), np.diff(diss)
    back = dang <= 0.0
    if back.any():
        return (f"no steady sliding over the last half: the screw stops or turns backwards in "
                f"{100.0 * back.mean():.3g} % of the output steps (stick-slip; the closed form is steady sliding, "
                f"see sliding_growth_rate)")
    stuck = ddiss < 0.5 * 0.5 * (torque[1:] + torque[:-1]) * dang
    if stuck.any():
        return (f"no steady sliding over the last half: the contact sticks (dissipates less than half the drive's "
                f"work) in {100.0 * stuck.mean():.3g} % of the output steps (the closed form is steady sliding)")
    return None


def screw_summary(traj, p, wall_s, steps, newton_iterations):
    """Summary of a screw trajectory (t, angle, z, torque, axial_force, dissipated_energy):
    advance per revolution = 2 pi dz/dangle fitted over the last half of the run (signed; None
    when the screw does not turn there, see ``_undefined_advance``), mean drive torque and axial
    force over the last half; ``undefined`` maps every None value to its reason.

    p (ScrewParams): also the closed-form steady sliding beside them, advance_per_rev_theory
    and torque_mean_theory (``screw_theory``), where it applies to the parameters and the run
    slides steadily over the last half (``_not_steady_sliding``); else None with the reason. (p
    None: the summary without the closed form.)"""
    t = np.asarray(traj["t"], float)
    late = t >= 0.5 * t[-1]
    ang, z = np.asarray(traj["angle"], float)[late], np.asarray(traj["z"], float)[late]
    undefined = {}
    why = _undefined_advance(t[late], ang)
    if why is None:
        adv = float(np.polyfit(ang, z, 1)[0] * 2.0 * math.pi)
    else:
        adv, undefined["advance_per_rev"] = None, why
    out = dict(angle_end=float(traj["angle"][-1]), z_end=float(traj["z"][-1]), advance_per_rev=adv,
               torque_mean=float(traj["torque"][late].mean()),
               axial_force_mean=float(traj["axial_force"][late].mean()),
               dissipated_energy=float(traj["dissipated_energy"][-1]),
               wall_s=float(wall_s), steps=int(steps), newton_iterations=int(newton_iterations),
               undefined=undefined)
    if p is not None:
        theory, why = screw_theory(p)
        if why is None:
            why = _not_steady_sliding(t[late], ang, np.asarray(traj["torque"], float)[late],
                                      np.asarray(traj["dissipated_energy"], float)[late])
        out["advance_per_rev_theory"] = theory.advance_per_rev if why is None else None
        out["torque_mean_theory"] = theory.torque if why is None else None
        if why is not None:
            undefined["advance_per_rev_theory"] = undefined["torque_mean_theory"] = why
    return out


def reference_model(p, law=None):
    """The screw's body model for the reference engine and its force floor; ``law`` replaces the
    scene's ContactLaw."""
    if law is not None:
        check_instance("law", law, ContactLaw)
    law = screw_contact_law(p) if law is None else law
    return (_ScrewReduced(p, law) if p.model == "reduced" else _ScrewFull(p, law)), 1e-6 * p.eps_n * p.radius


def _screw_drive(p, psi, z, t):
    """Drive torque about +z, its d/dpsi; axial force along +z, its d/dz."""
    tau, dtau, Fz, dFz = 0.0, 0.0, p.axial_load, 0.0
    if p.drive == "torque":
        tau = p.torque
    elif p.drive == "rotation":
        tau, dtau = p.drive_stiffness * (p.rotation_speed * t - psi), -p.drive_stiffness
    else:
        Fz, dFz = Fz + p.drive_stiffness * (p.axial_speed * t - z), -p.drive_stiffness
    return tau, dtau, Fz, dFz


class _ScrewReduced(ScrewJoint):
    def __init__(self, p, law):
        self.p = p
        m, J = screw_inertia(p)
        super().__init__(law, screw_points(p), m, J[2, 2], p.radius)

    def external(self, q, t):
        return _screw_drive(self.p, q[0], q[1], t)

    def record(self, q, v, t, st):
        tau, _, Fz, _ = _screw_drive(self.p, q[0], q[1], t)
        torque, axial = self.contact_torque_and_force(q, st)
        return dict(angle=q[0], z=q[1], omega=v[0], vz=v[1], torque=tau, axial_force=Fz,
                    contact_torque=torque, contact_axial_force=axial)


class _ScrewFull(RigidBody6):
    def __init__(self, p, law):
        self.p = p
        m, J = screw_inertia(p)
        super().__init__(law, screw_points(p), m, np.diag(J), [0.0, 0.0, 0.0], p.radius)

    def external(self, q, t):
        r, R, yaw = q
        tau, dtau, Fz, dFz = _screw_drive(self.p, yaw, r[2], t)
        dF = np.zeros((3, 3))
        dF[2, 2] = dFz
        return np.array([0.0, 0.0, Fz]), np.array([0.0, 0.0, tau]), dF, np.array([0.0, 0.0, dtau])

    def record(self, q, v, t, st):
        r, R, yaw = q
        w = self.world_omega(q, v)
        tau, _, Fz, _ = _screw_drive(self.p, yaw, r[2], t)
        f = st.force
        arm = self.s @ R.T
        return dict(angle=yaw, z=r[2], omega=w[2], vz=v[2], torque=tau, axial_force=Fz,
                    contact_torque=float(np.sum(arm[:, 0] * f[:, 1] - arm[:, 1] * f[:, 0])),
                    contact_axial_force=float(f[:, 2].sum()),
                    x=r[0], y=r[1], tilt=math.acos(max(-1.0, min(1.0, R[2, 2]))))


def simulate_screw(params=None, **options):
    """Screw scene with the reference integrator; params: ScrewParams (defaults if None).
    Options as for simulate_block. Returns Result."""
    p = ScrewParams() if params is None else params
    if not isinstance(p, ScrewParams):
        raise TypeError(f"params must be ScrewParams; got {type(p).__name__}")
    check_keywords("simulate_screw", options, RUN_OPTIONS)
    model, floor = reference_model(p)
    traj, wall, iters, steps, info, motion, H = run(model, p, floor=floor, **options)
    summary = screw_summary(traj, p, wall, steps, iters)
    summary.update(screw_energy(p, traj, motion, model.s, model.law, H))
    return Result(traj, summary, p, info)


# ----------------------------------------------------------------------------------------------
# steady sliding in closed form (module docstring)

# the return maps with a closed form (the seed map's steady state depends on the step size)
CALIBRATED_MAPS = ("radial", "exact")


@dataclass(frozen=True)
class SteadySliding:
    """Closed-form steady sliding state of the screw scene (SI units).

    advance_per_rev [m], advance_ratio = advance_per_rev / pitch [-], torque = drive torque while
    sliding (= sticking threshold of the torque drive) [N m], circumferential_traction = tau [N]
    (total), normal_force = N [N] (total), slip_direction = unit slip-rate direction (e_phi, e_z)."""

    advance_per_rev: float
    advance_ratio: float
    torque: float
    circumferential_traction: float
    normal_force: float
    slip_direction: tuple


def helix_components(p):
    a = math.radians(p.helix_angle)
    return math.cos(a), math.sin(a)


def friction_coefficients(p):
    return (p.mu_1, p.mu_1) if p.friction == "isotropic" else (p.mu_1, p.mu_2)


def adhesion_stiffnesses(p):
    return (p.eps_1, p.eps_1) if p.adhesion == "isotropic" else (p.eps_1, p.eps_2)


def steady_sliding(p: ScrewParams) -> SteadySliding:
    """Steady sliding of the screw scene in closed form (see the module docstring).

    Valid for return_map 'radial' and 'exact', the reduced model (the full model agrees while the
    screw stays centred) and positive rotation. Raises ValueError for the seed map, or when the axial
    load exceeds the axial friction capacity (then no steady sliding rotation exists)."""
    if not isinstance(p, ScrewParams):
        raise TypeError(f"p must be ScrewParams; got {type(p).__name__}")
    if p.return_map not in CALIBRATED_MAPS:
        raise ValueError(f"return_map must be one of {CALIBRATED_MAPS} for the closed form (the seed map's steady "
                         f"state depends on the step size); got {p.return_map!r}")
    c, s = helix_components(p)
    mu1, mu2 = friction_coefficients(p)
    eps1, eps2 = adhesion_stiffnesses(p)
    N = p.eps_n * p.interference
    Fa = p.axial_load
    f1, f2 = 1.0 / mu1 ** 2, 1.0 / mu2 ** 2
    # S = tau e_phi + Fa e_z; S1 = tau c + Fa s, S2 = -tau s + Fa c; f1 S1^2 + f2 S2^2 = N^2
    A = f1 * c * c + f2 * s * s
    B = Fa * c * s * (f1 - f2)
    C = Fa * Fa * (f1 * s * s + f2 * c * c) - N * N
    disc = B * B - A * C
    if N <= 0.0 or disc < 0.0 or (-B + math.sqrt(disc)) <= 0.0:
        raise ValueError(f"axial_load: |axial_load| = {abs(Fa)!r} N must stay below the axial friction capacity "
                         f"(normal force eps_n * interference = {N!r} N) for a steady sliding rotation")
    tau = (-B + math.sqrt(disc)) / A
    S1, S2 = tau * c + Fa * s, -tau * s + Fa * c
    w1, w2 = (S1 / eps1, S2 / eps2) if p.return_map == "radial" else (S1 * f1, S2 * f2)
    v_phi, v_z = c * w1 - s * w2, s * w1 + c * w2
    if not v_phi > 0.0:
        raise ValueError("the closed form needs a slip with positive rotation; this parameter set slides backwards")
    adv = 2.0 * math.pi * p.radius * v_z / v_phi
    pt = pitch(p)
    norm = math.hypot(v_phi, v_z)
    return SteadySliding(advance_per_rev=adv, advance_ratio=adv / pt if pt != 0.0 else float("nan"),
                         torque=p.radius * tau, circumferential_traction=tau, normal_force=N,
                         slip_direction=(v_phi / norm, v_z / norm))


def sliding_onset_angle(p: ScrewParams) -> float:
    """Driver rotation [rad] until the screw starts to slide under the rotation drive (estimate):
    elastic circumferential travel of the contact (axial direction free, stiffness
    1 / (cos^2 a / eps_1 + sin^2 a / eps_2)) plus the wind-up of the drive spring."""
    c, s = helix_components(p)
    eps1, eps2 = adhesion_stiffnesses(p)
    st = steady_sliding(p)
    k_phi = 1.0 / (c * c / eps1 + s * s / eps2)
    return st.circumferential_traction / k_phi / p.radius + st.torque / p.drive_stiffness


def screw_theory(p):
    """(SteadySliding, None) where the closed form applies to the parameters, else (None, reason):
    the rotation drive at a positive speed (the constant torque accelerates the screw or lets it
    stick, the axial drive sets an axial force the closed form does not know), the radial or exact
    map, the cylinder, and an axial load the friction can hold. Whether a run reaches the steady
    sliding is the summary's check (``screw_summary``)."""
    check_instance("p", p, ScrewParams)
    if p.drive != "rotation":
        return None, (f"drive = {p.drive!r}: the closed form is the steady sliding under the rotation drive (a "
                      f"constant torque accelerates the screw or lets it stick; the axial drive sets the axial force)")
    if not p.rotation_speed > 0.0:
        return None, f"rotation_speed = {p.rotation_speed!r} rad/s: the closed form is for a positive rotation"
    if p.surface == "cone" and p.half_angle != 0.0:
        return None, f"surface = 'cone' (half_angle = {p.half_angle!r} deg): the closed form is the cylinder's"
    try:
        return steady_sliding(p), None
    except ValueError as e:
        return None, str(e)


def screw_closed_forms(p):
    """The screw's closed forms for p: the steady sliding's ``advance_per_rev_theory`` [m] and
    ``torque_mean_theory`` [N m] (``screw_theory``), None with the reason under ``undefined`` where
    the closed form does not apply to p (whether a run reaches the steady sliding is the summary's
    check)."""
    theory, why = screw_theory(p)
    if why is not None:
        return dict(advance_per_rev_theory=None, torque_mean_theory=None,
                    undefined=dict(advance_per_rev_theory=why, torque_mean_theory=why))
    return dict(advance_per_rev_theory=theory.advance_per_rev, torque_mean_theory=theory.torque, undefined={})


def sliding_growth_rate(p: ScrewParams) -> float:
    """Growth rate [1/s] of a small disturbance of the closed-form steady sliding (``steady_sliding``)
    under the rotation drive: the largest real part of the eigenvalues of the linearised dynamics;
    positive: the steady sliding is unstable (a flutter), the screw turns in a stick-slip cycle
    instead and the closed form does not describe the run.

    The model: the screw's point on the hole axis (reduced model, the totals of the law), its
    rotation x = R psi with the mass J_axial / R^2 on the drive spring k / R^2, its axial position
    with the mass m; the contact's elastic displacement u (e_phi, e_z) with traction T = C u on the
    friction ellipse T.A.T = N^2 (A = F^-1 of the helix frame) slides at the rate lambda n, n = C^-1 T
    (radial map) or A T (exact map), lambda from the consistency d(T.A.T)/dt = 0. State (drive
    spring's stretch, the two velocities, u); the Jacobian by central differences at the steady
    state. Its eigenvalue along the ellipse's normal is zero (the ellipse is kept exactly)."""
    st = steady_sliding(p)
    if p.drive != "rotation":
        raise ValueError(f"drive must be 'rotation' for sliding_growth_rate; got {p.drive!r}")
    m, J = screw_inertia(p)
    R = p.radius
    Mx, kx = J[2, 2] / R ** 2, p.drive_stiffness / R ** 2
    c, s = helix_components(p)
    Q = np.array([[c, -s], [s, c]])                          # columns e1, e2 in (e_phi, e_z)
    eps1, eps2 = adhesion_stiffnesses(p)
    mu1, mu2 = friction_coefficients(p)
    C = Q @ np.diag([eps1, eps2]) @ Q.T
    A = Q @ np.diag([mu1 ** -2, mu2 ** -2]) @ Q.T
    Ci = np.linalg.inv(C)

    def direction(T):
        return Ci @ T if p.return_map == "radial" else A @ T

    T0 = np.array([st.circumferential_traction, p.axial_load])
    u0 = Ci @ T0
    V = p.rotation_speed * R
    n0 = direction(T0)
    lam0 = V / n0[0]
    y0 = np.array([st.torque / p.drive_stiffness / R, V, lam0 * n0[1], *u0])

    def f(y):
        d, vx, vz, u1, u2 = y
        T = C @ np.array([u1, u2])
        n = direction(T)
        v = np.array([vx, vz])
        lam = (T @ A @ C @ v) / (T @ A @ C @ n)
        return np.array([V - vx, (kx * d - T[0]) / Mx, -(T[1] - p.axial_load) / m, *(v - lam * n)])

    h = 1e-7 * np.maximum(np.abs(y0), 1e-12)
    E = np.eye(5)
    jac = np.column_stack([(f(y0 + h[i] * E[i]) - f(y0 - h[i] * E[i])) / (2.0 * h[i]) for i in range(5)])
    ev = np.linalg.eigvals(jac)
    scale = np.abs(ev).max()
    return float(max(e.real for e in ev if abs(e) > 1e-9 * scale))


# ----------------------------------------------------------------------------------------------
# the plot of trajectory.png

def screw_closed_form(params, backwards=False):
    """(SteadySliding or None, reason text when None) for the screw parameters ``params``; backwards:
    the screw turned the other way (the closed form is for positive rotation when an axial load
    breaks the symmetry)."""
    if backwards and params.axial_load != 0.0:
        return None, "no closed form: it is for positive rotation (axial load breaks the symmetry)"
    if params.return_map == "seed":
        return None, "seed map: no closed form (its steady state depends on dt)"
    if params.drive == "axial":
        return None, "axial drive: no closed form (steady sliding is for the rotation and torque drives)"
    try:
        return steady_sliding(params), ""
    except ValueError as e:
        return None, f"no closed form: {e}"


def PlotScrewAdvance(traj, params, ax=None):
    """Axial position z [mm] against rotation [rev], with the closed form's advance per revolution
    (radial/exact map) as a straight line through the last point, and the thread pitch dotted.
    Returns the Axes."""
    ax = axes_of(ax, figsize=(6.0, 4.0))
    rev, z = finite_rows(np.asarray(traj["angle"], dtype=float) / (2.0 * math.pi),
                     np.asarray(traj["z"], dtype=float) * 1e3)
    ax.plot(*drawn(rev, z), "-", color="C0", lw=1.6, label=f"screw ({params.return_map} map)")
    st, why = screw_closed_form(params, backwards=bool(rev.size) and rev[-1] < 0.0)
    if rev.size:
        xr = np.array([min(rev.min(), 0.0), max(rev.max(), 0.0)])
        if xr[1] - xr[0] <= 0.0:
            xr = np.array([rev[-1] - 0.5, rev[-1] + 0.5])
        p_mm = pitch(params) * 1e3
        ax.plot(xr, z[-1] + p_mm * (xr - rev[-1]), ls=":", color="0.5", lw=1.0, gid="pitch",
                label=f"thread pitch {p_mm:.4g} mm/rev")
        if st is not None:
            k = st.advance_per_rev * 1e3
            ax.plot(xr, z[-1] + k * (xr - rev[-1]), "--", color="C3", lw=1.2, gid=CLOSED_FORM_GID,
                    label=f"closed form, steady sliding: {k:.4g} mm/rev")
    if st is None:
        note(ax, why)
    return labelled(ax, "rotation [rev]", "axial position z [mm]")


def PlotScrewTorque(traj, params, ax=None):
    """Drive torque [N m] against time [s] with the closed form's sliding torque (radial/exact map)
    as a horizontal line. Returns the Axes."""
    ax = axes_of(ax, figsize=(6.0, 4.0))
    t, tau = finite_rows(traj["t"], traj["torque"])
    ax.plot(*drawn(t, tau), "-", color="C0", lw=1.2, label=f"drive torque ({params.drive} drive)")
    sign = -1.0 if t.size and np.mean(tau) < 0.0 else 1.0     # a screw driven backwards
    st, why = screw_closed_form(params, backwards=sign < 0.0)
    if st is not None and t.size:
        ax.plot([float(t[0]), float(t[-1])], [sign * st.torque] * 2, "--", color="C3", lw=1.2,
                gid=CLOSED_FORM_GID, label=f"closed-form sliding torque {sign * st.torque:.4g} N m")
    elif st is None:
        note(ax, why)
    return labelled(ax, "t [s]", "torque [N m]")


def PlotScrew(traj, params, fig):
    """trajectory.png of the screw on the matplotlib Figure fig: PlotScrewAdvance over PlotScrewTorque."""
    PlotScrewAdvance(traj, params, ax=fig.add_subplot(2, 1, 1))
    PlotScrewTorque(traj, params, ax=fig.add_subplot(2, 1, 2))


# ----------------------------------------------------------------------------------------------
# the scene, as every engine and the command line see it

class ScrewScene(Scene):
    """The screw scene (the module docstring); the summary takes no inputs, the ledger
    ``screw_energy``'s (motion, points, law, H)."""

    name = "screw"
    Params = ScrewParams
    columns = {"t": "s", "angle": "rad", "z": "m", "omega": "rad/s", "vz": "m/s", "torque": "N m",
               "axial_force": "N", "dissipated_energy": "J",
               # the full model's other motions (axis_*: the screw's axis in the world)
               "x": "m", "y": "m", "vx": "m/s", "vy": "m/s", "tilt": "rad", "omega_x": "rad/s", "omega_y": "rad/s",
               "axis_x": "-", "axis_y": "-", "axis_z": "-", **LEDGER_COLUMNS}
    title_keys = ("advance_per_rev", "torque_mean")
    figsize = (6.0, 6.5)
    law = staticmethod(screw_contact_law)
    points = staticmethod(screw_points)
    closed_forms = staticmethod(screw_closed_forms)
    summary = staticmethod(screw_summary)
    ledger = staticmethod(screw_energy)
    plot = staticmethod(PlotScrew)
    reference = staticmethod(simulate_screw)


SCENE = ScrewScene()
