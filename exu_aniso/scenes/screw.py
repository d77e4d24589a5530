"""The screw scene's body models for the reference engine (``exu_aniso.engines.reference``) and its run
there: the reduced model (psi, z) on the hole's axis or a 6-DOF rigid cylinder in the hole. The
scene's parameters, law, points, summary and ledger are in ``exu_aniso.scenes.base``; its closed-form
steady sliding (``steady_sliding``, what ``exu_aniso.calibration`` fits to) is here.

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
from exu_aniso.engines.reference import RUN_OPTIONS, BodyModel, RigidBody6, run
from exu_aniso.engines.result import Result
from exu_aniso.kernel.contact_law import ContactLaw
from exu_aniso.util.validation import check_instance, check_keywords
from exu_aniso.scenes.base import ScrewParams, pitch, screw_contact_law, screw_energy, screw_inertia, screw_points, screw_summary


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


class _ScrewReduced(BodyModel):
    n = 2

    def __init__(self, p, law):
        self.p, self.law = p, law
        self.s = screw_points(p)
        self.K = len(self.s)
        m, J = screw_inertia(p)
        self.mass = np.array([J[2, 2], m])
        self.row_scale = np.array([p.radius, 1.0])
        self.dof_scale = np.array([1.0, p.radius])
        self.q0 = np.zeros(2)
        self.v0 = np.zeros(2)

    def points0(self, q, v):
        c, s = math.cos(q[0]), math.sin(q[0])
        P = self.s @ np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])
        return P + np.array([0.0, 0.0, q[1]]), np.zeros_like(P)

    def evaluate(self, q, v, t, H, tangent=True, dt=None):
        c, s = math.cos(q[0]), math.sin(q[0])
        P = self.s @ np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])
        X = P + np.array([0.0, 0.0, q[1]])
        ez_x_P = np.column_stack([-P[:, 1], P[:, 0], np.zeros(self.K)])
        V = v[0] * ez_x_P
        V[:, 2] += v[1]
        st = self.law.evaluate(X, V, H, tangent, dt)
        f = st.force
        tau, dtau, Fz, dFz = _screw_drive(self.p, q[0], q[1], t)
        g = np.array([np.sum(ez_x_P * f) + tau, f[:, 2].sum() + Fz])
        Gq = Gv = None
        if tangent:
            J = np.zeros((self.K, 3, 2))
            J[:, :, 0] = ez_x_P
            J[:, 2, 1] = 1.0
            Gq = np.einsum("kai,kab,kbj->ij", J, st.stiffness, J)
            Gq[0, 0] += dtau - np.sum(P[:, 0] * f[:, 0] + P[:, 1] * f[:, 1])
            Gq[1, 1] += dFz
            dV = np.zeros((self.K, 3, 2))                             # d(v0 ez x P)/dpsi = -v0 P_xy
            dV[:, 0, 0], dV[:, 1, 0] = -v[0] * P[:, 0], -v[0] * P[:, 1]
            Gq += np.einsum("kai,kab,kbj->ij", J, st.damping, dV)
            Gv = np.einsum("kai,kab,kbj->ij", J, st.damping, J)
        return g, Gq, Gv, st

    def motion(self, q, v):
        c, s = math.cos(q[0]), math.sin(q[0])
        return (np.array([0.0, 0.0, q[1]]), np.array([[c, -s, 0.0], [s, c, 0.0], [0, 0, 1.0]]),
                np.array([0.0, 0.0, v[1]]), np.array([0.0, 0.0, v[0]]))

    def record(self, q, v, t, st):
        tau, _, Fz, _ = _screw_drive(self.p, q[0], q[1], t)
        c, s = math.cos(q[0]), math.sin(q[0])
        P = self.s @ np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])
        f = st.force
        return dict(angle=q[0], z=q[1], omega=v[0], vz=v[1], torque=tau, axial_force=Fz,
                    contact_torque=float(np.sum(P[:, 0] * f[:, 1] - P[:, 1] * f[:, 0])),
                    contact_axial_force=float(f[:, 2].sum()))


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
    if p.model == "full" and p.points_per_ring < 3:
        raise ValueError(f"points_per_ring must be >= 3 for model='full' (radial centring); got {p.points_per_ring}")
    check_keywords("simulate_screw", options, RUN_OPTIONS)
    model, floor = reference_model(p)
    traj, wall, iters, steps, info, motion, H = run(model, p, floor=floor, **options)
    summary = screw_summary(traj, wall, steps, iters)
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


def _helix_components(p):
    a = math.radians(p.helix_angle)
    return math.cos(a), math.sin(a)


def _friction_coefficients(p):
    return (p.mu_1, p.mu_1) if p.friction == "isotropic" else (p.mu_1, p.mu_2)


def _adhesion_stiffnesses(p):
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
    c, s = _helix_components(p)
    mu1, mu2 = _friction_coefficients(p)
    eps1, eps2 = _adhesion_stiffnesses(p)
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
    c, s = _helix_components(p)
    eps1, eps2 = _adhesion_stiffnesses(p)
    st = steady_sliding(p)
    k_phi = 1.0 / (c * c / eps1 + s * s / eps2)
    return st.circumferential_traction / k_phi / p.radius + st.torque / p.drive_stiffness
