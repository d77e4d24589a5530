"""Standalone numpy/scipy reference of the two scenes: rigid-body dynamics and an implicit integrator.

No Exudyn here: this module is the oracle the Exudyn engine is compared with.

Models (state = configuration + velocity; generalized coordinates in brackets)
----------------------------------------------------------------------------
* block "planar"  (x, y, theta): the slave points are held at the penetration that carries the
  normal load equally, gap = -normal_load / eps_n (eps_n total); only the in-plane contact force
  and the z-torque act. Inertia m, m, m size^2 / 6.
* block "full"    6-DOF rigid cube: position r of the COM (world), rotation matrix R (body ->
  world), velocity v (world), angular velocity Omega (BODY frame). normal_load acts downward at
  the COM (no separate gravity); the contact points carry it through the normal penalty.
  The block starts at the static penetration (no initial bounce).
* screw "reduced" (psi, z): rotation psi about the hole axis z and axial position z of the COM;
  the screw axis stays on the hole axis. Inertia J_axial = m r^2 / 2, m.
* screw "full"    6-DOF rigid cylinder (J_axial = m r^2/2, J_transverse = m (3 r^2 + L^2)/12) in the
  hole (axis z), no gravity; axial_load along +z.
* particle        mass point (x, y, z) on any surface of the protocol (exu_aniso.scene_particle),
  gravity m g as a constant force, the initial state of the scene (the history of t = 0 is
  evaluated with the initial velocity, as the Exudyn glue does).

Drives: block "force" P (cos a, sin a, 0) at the COM; block "displacement": spring along the drive
direction d only, F = k (s t - d.(r - r0)) d. Screw "torque": constant tau about +z; "rotation":
tau = k (omega_d t - psi); "axial": F = k (v_d t - z); axial_load along +z always. In the full
screw psi is the unwrapped yaw atan2(R_10, R_00) (exact for rotations about z, which is the
motion of interest; a small tilt perturbs it at second order).

Contact: ``ContactLaw.evaluate`` at the end-of-step configuration with the last CONVERGED history
(backward Euler of the rate law); the history candidate is committed only when the step is
accepted. The initial history is the one of the initial configuration (all points in contact,
anchors at their initial contact points, zero traction), so the first step already carries
tangential traction.

Integrator
----------
Generalized-alpha on a Lie group (Arnold & Brüls 2007; Brüls, Cardona & Arnold 2012) in the
"increment" form; with alpha_m = alpha_f = 0, beta = 1/4, gamma = 1/2 (``solver="trapezoidal"``,
the default) it is the trapezoidal rule / Newmark average acceleration:

    q_{n+1} = q_n o exp(Delta),   Delta = h v_n + h^2 (1/2 - beta) a_n + h^2 beta a_{n+1}
    v_{n+1} = v_n + h (1 - gamma) a_n + h gamma a_{n+1}
    (1 - alpha_m) a_{n+1} + alpha_m a_n = (1 - alpha_f) vdot_{n+1} + alpha_f vdot_n
    M vdot_{n+1} = g(q_{n+1}, v_{n+1}, t_{n+1})         (g includes -Omega x J Omega)

For vector coordinates ``o exp`` is addition. For the 6-DOF models Delta = (dr, theta):
r_{n+1} = r_n + dr, R_{n+1} = R_n exp([theta]x) with the body-frame rotation vector increment
theta = h/2 (Omega_n + Omega_{n+1}) (trapezoidal) -- a second-order Lie-group scheme (the
dexp^-1 correction is O(h^3) locally). ``solver="generalized_alpha"`` uses Chung & Hulbert's
parameters from rho_inf (keyword ``rho_inf``, default 0.8): numerical damping of the unresolved
penalty modes, still second order.

Newton on Delta. Analytic Jacobian: M c_a - dg/dq . T(Delta) - dg/dv c_v with
c_a = (1 - alpha_m) / ((1 - alpha_f) beta h^2), c_v = gamma / (beta h); dg/dq comes from the
contact stiffness/damping mapped through the point Jacobians plus the geometric terms of the
moments and the drive springs; T is the tangent of the retraction (identity or the right Jacobian
J_r(theta) of SO(3)). ``jacobian="numerical"`` uses forward differences of the residual instead.
Line search (``line_search=True``, default): the full Newton step is kept whenever it decreases
|r / row_scale|_2 (or meets the convergence test), so monotonically converging solves keep their
iterates; otherwise the step is halved (Armijo, up to 2^-10) -- this breaks the two-cycles of plain
Newton at the kinks of the return maps (torque drive, axial load; counted in ``info["backtracks"]``).
Convergence: every scaled residual row below ``newton_tol`` (rows scaled by a force level of the
step, moment rows also by the body size). If Newton fails (``max_newton`` iterations, non-finite
values) the step is rejected -- the history stays untouched -- and done as two half steps,
recursively; at the last level (``max_halvings``) the smallest-residual iterate is accepted
and counted (``nonsmooth_accept``; only the seed map, discontinuous at stick/slip, needs it).
``reject_steps`` forces this for the given nominal step indices (the full step is
solved to convergence and then thrown away), ``split_steps`` halves them directly; the two must
agree to round-off, which tests that a rejected step leaves no trace.

Outputs: ``Result.trajectory`` (one entry per accepted step, plus t = 0), ``Result.summary``.
The slip distance is the accumulated slip per contact point averaged over the points [m]; the
dissipated energy is the sum over the points [J] (history columns 6 and 5).
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from .contact import UNRESOLVED, ContactLaw
from . import energy
from .scenes import (BlockParams, ScrewParams, block_contact_law, block_energy, block_inertia, block_points,
                     block_summary, screw_contact_law, screw_energy, screw_inertia, screw_points, screw_summary,
                     time_grid, time_step)
from .validation import check_bool, check_in_range, check_instance, check_integer, check_keywords, check_positive

# ----------------------------------------------------------------------------------------------
# SO(3) helpers


def _skew(a):
    return np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])


def _skew_batch(a):
    S = np.zeros(a.shape[:-1] + (3, 3))
    S[..., 0, 1], S[..., 0, 2] = -a[..., 2], a[..., 1]
    S[..., 1, 0], S[..., 1, 2] = a[..., 2], -a[..., 0]
    S[..., 2, 0], S[..., 2, 1] = -a[..., 1], a[..., 0]
    return S


def _exp_so3(th):
    """Rodrigues: exp([th]x)."""
    phi = math.sqrt(th @ th)
    W = _skew(th)
    if phi < 1e-8:
        return np.eye(3) + W + 0.5 * W @ W
    return np.eye(3) + math.sin(phi) / phi * W + (1.0 - math.cos(phi)) / phi ** 2 * W @ W


def _right_jacobian(th):
    """J_r(th): exp([th + d]x) = exp([th]x) exp([J_r d]x) + O(d^2)."""
    phi = math.sqrt(th @ th)
    W = _skew(th)
    if phi < 1e-6:
        return np.eye(3) - 0.5 * W + W @ W / 6.0
    return np.eye(3) - (1.0 - math.cos(phi)) / phi ** 2 * W + (phi - math.sin(phi)) / phi ** 3 * W @ W


def _wrap(a):
    return math.pi - (math.pi - a) % (2.0 * math.pi)


# ----------------------------------------------------------------------------------------------
# models: g(q, v, t) and its derivatives with respect to the increment and the velocity


class _Model:
    """Interface: n, mass (n,), row_scale (n,), q0/v0, retract, evaluate, record, force_level."""

    def retract(self, q, d):
        return q + d, None

    def force_level(self, state):
        return float(np.sum(np.linalg.norm(state.force, axis=1)))


class _BlockPlanar(_Model):
    n = 3

    def __init__(self, p, law):
        self.p, self.law = p, law
        self.s = block_points(p)[:, :2]
        self.K = len(self.s)
        self.gap = -p.normal_load / p.eps_n
        m, J = block_inertia(p)
        self.mass = np.array([m, m, J[2, 2]])
        self.row_scale = np.array([1.0, 1.0, p.size])
        self.dof_scale = np.array([p.size, p.size, 1.0])
        self.q0 = np.array([p.x0, p.y0, 0.0])
        self.v0 = np.zeros(3)
        self.d = np.array([math.cos(math.radians(p.drive_angle)), math.sin(math.radians(p.drive_angle))])

    def drive(self, q, t):
        p = self.p
        if p.drive == "force":
            return p.force * self.d, np.zeros((2, 2))
        stretch = p.drive_speed * t - self.d @ (q[:2] - self.q0[:2])
        return p.drive_stiffness * stretch * self.d, -p.drive_stiffness * np.outer(self.d, self.d)

    def points(self, q, v):
        c, s = math.cos(q[2]), math.sin(q[2])
        P = self.s @ np.array([[c, s], [-s, c]])                      # R(theta) s_k, rows
        X = np.column_stack([q[0] + P[:, 0], q[1] + P[:, 1], np.full(self.K, self.gap)])
        V = np.column_stack([v[0] - v[2] * P[:, 1], v[1] + v[2] * P[:, 0], np.zeros(self.K)])
        return X, V, P

    def evaluate(self, q, v, t, H, tangent=True, dt=None):
        X, V, P = self.points(q, v)
        st = self.law.evaluate(X, V, H, tangent, dt)
        f = st.force
        Fd, dFd = self.drive(q, t)
        g = np.array([f[:, 0].sum() + Fd[0], f[:, 1].sum() + Fd[1],
                      np.sum(P[:, 0] * f[:, 1] - P[:, 1] * f[:, 0])])
        Gq = Gv = None
        if tangent:
            J = np.zeros((self.K, 3, 3))
            J[:, 0, 0] = J[:, 1, 1] = 1.0
            J[:, 0, 2], J[:, 1, 2] = -P[:, 1], P[:, 0]
            Gq = np.einsum("kai,kab,kbj->ij", J, st.stiffness, J)
            Gq[2, 2] -= np.sum(P[:, 0] * f[:, 0] + P[:, 1] * f[:, 1])
            Gq[:2, :2] += dFd
            dV = np.zeros((self.K, 3, 3))                             # dV/dq at fixed v: arms turn
            dV[:, 0, 2], dV[:, 1, 2] = -v[2] * P[:, 0], -v[2] * P[:, 1]
            Gq += np.einsum("kai,kab,kbj->ij", J, st.damping, dV)
            Gv = np.einsum("kai,kab,kbj->ij", J, st.damping, J)
        return g, Gq, Gv, st

    def motion(self, q, v):
        """(COM position, rotation matrix, velocity, angular velocity) in the world frame."""
        c, s = math.cos(q[2]), math.sin(q[2])
        return (np.array([q[0], q[1], self.p.size / 2 + self.gap]), np.array([[c, -s, 0.0], [s, c, 0.0], [0, 0, 1.0]]),
                np.array([v[0], v[1], 0.0]), np.array([0.0, 0.0, v[2]]))

    def record(self, q, v, t, st):
        Fd, _ = self.drive(q, t)
        return dict(x=q[0], y=q[1], theta=q[2], vx=v[0], vy=v[1], omega=v[2], z=self.p.size / 2 + self.gap,
                    drive_force=float(Fd @ self.d))


class _Rigid6(_Model):
    """6-DOF rigid body with contact points s_k (body frame, from the COM) against a ground master.

    q = (r, R, yaw); v = (v_world, Omega_body); increment Delta = (dr, theta_body)."""

    n = 6

    def __init__(self, law, s, mass, inertia, r0, L):
        self.law, self.s, self.K = law, np.asarray(s, float), len(s)
        self.J = np.asarray(inertia, float)
        self.mass = np.array([mass] * 3 + list(self.J))
        self.row_scale = np.array([1.0, 1.0, 1.0, L, L, L])
        self.dof_scale = np.array([L, L, L, 1.0, 1.0, 1.0])
        self.q0 = (np.asarray(r0, float), np.eye(3), 0.0)
        self.v0 = np.zeros(6)
        self.S = _skew_batch(self.s)                              # [s_k]x  (K, 3, 3)

    def retract(self, q, d):
        r, R, yaw = q
        R1 = R @ _exp_so3(d[3:])
        yaw1 = yaw + _wrap(math.atan2(R1[1, 0], R1[0, 0]) - yaw)
        T = np.eye(6)
        T[3:, 3:] = _right_jacobian(d[3:])
        return (r + d[:3], R1, yaw1), T

    def external(self, q, t):
        """F_world (3), M_world (3), dF/dr (3,3), dM_world/dyaw (3)."""
        raise NotImplementedError

    def master(self, t):
        """Displacement and velocity (3,), (3,) of a master that only translates (prescribed), or
        None (ground): the law sees the points relative to it; forces and tangents are unchanged."""
        return None

    def evaluate(self, q, v, t, H, tangent=True, dt=None):
        r, R, yaw = q
        Om = v[3:]
        RS = self.s @ R.T                                         # R s_k, rows
        X = r + RS
        V = v[:3] + np.cross(Om, self.s) @ R.T
        moving = self.master(t)
        if moving is not None:
            X, V = X - moving[0], V - moving[1]
        st = self.law.evaluate(X, V, H, tangent, dt)
        f = st.force
        fb = f @ R                                                # R^T f_k, rows
        Fe, Me, dFe, dMe = self.external(q, t)
        JOm = self.J * Om
        g = np.concatenate([f.sum(axis=0) + Fe,
                            np.cross(self.s, fb).sum(axis=0) + R.T @ Me - np.cross(Om, JOm)])
        Gq = Gv = None
        if tangent:
            A = np.zeros((self.K, 3, 6))                          # d x_k / d(dr, dphi)
            A[:, :, :3] = np.eye(3)
            A[:, :, 3:] = -np.einsum("ij,kjl->kil", R, self.S)
            B = np.concatenate([np.broadcast_to(np.eye(3), (self.K, 3, 3)),
                                np.einsum("kij,lj->kil", self.S, R)], axis=1)   # rows of g per force
            Gq = np.einsum("kia,kab,kbj->ij", B, st.stiffness, A)
            Gq[3:, 3:] += np.einsum("kij,kjl->il", self.S, _skew_batch(fb))
            Gq[3:, 3:] += _skew(R.T @ Me) + np.outer(R.T @ dMe, R[2, :])
            Gq[:3, :3] += dFe
            dV = np.zeros((self.K, 3, 6))                             # d(R (Om x s))/dphi = -R [Om x s]x
            dV[:, :, 3:] = -np.einsum("ij,kjl->kil", R, _skew_batch(np.cross(Om, self.s)))
            Gq += np.einsum("kia,kab,kbj->ij", B, st.damping, dV)
            Gv = np.einsum("kia,kab,kbj->ij", B, st.damping, A)
            Gv[3:, 3:] -= _skew(Om) @ np.diag(self.J) - _skew(JOm)
        return g, Gq, Gv, st

    def world_omega(self, q, v):
        return q[1] @ v[3:]

    def motion(self, q, v):
        return q[0], q[1], v[:3], self.world_omega(q, v)


class _BlockFull(_Rigid6):
    def __init__(self, p, law):
        self.p = p
        gap = -p.normal_load / p.eps_n
        super().__init__(law, block_points(p), p.mass, np.diag(block_inertia(p)[1]),
                         [p.x0, p.y0, 0.5 * p.size + gap], p.size)
        a = math.radians(p.drive_angle)
        self.d = np.array([math.cos(a), math.sin(a), 0.0])

    def external(self, q, t):
        p = self.p
        F = np.array([0.0, 0.0, -p.normal_load])
        dF = np.zeros((3, 3))
        if p.drive == "force":
            F += p.force * self.d
        else:
            F += p.drive_stiffness * (p.drive_speed * t - self.d @ (q[0] - self.q0[0])) * self.d
            dF = -p.drive_stiffness * np.outer(self.d, self.d)
        return F, np.zeros(3), dF, np.zeros(3)

    def record(self, q, v, t, st):
        r, R, yaw = q
        w = self.world_omega(q, v)
        F, _, _, _ = self.external(q, t)
        return dict(x=r[0], y=r[1], theta=yaw, vx=v[0], vy=v[1], omega=w[2], z=r[2], vz=v[2],
                    tilt=math.acos(max(-1.0, min(1.0, R[2, 2]))), drive_force=float(F @ self.d))


class _FeederPart(_Rigid6):
    """One part of the feeder scene (exu_aniso.scene_feeder) on the track, whose harmonic motion is
    prescribed exactly (scene_feeder.plate_motion): weight as the external force, the law at the
    points relative to the track."""

    def __init__(self, p, law, x0):
        from .scene_feeder import part_inertia, part_points
        mass, J = part_inertia(p)
        super().__init__(law, part_points(p), mass, J, x0, p.part_size)
        self.p = p
        self.weight = np.array([0.0, 0.0, -mass * p.gravity])

    def master(self, t):
        from .scene_feeder import plate_motion
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


class _MassPoint(_Model):
    """Mass point: q = x (3,) in the master frame, v = dx/dt; one contact point at x."""

    n = 3
    K = 1

    def __init__(self, p, law):
        from .scene_particle import gravity_vector, initial_state
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


class _ScrewReduced(_Model):
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


class _ScrewFull(_Rigid6):
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


# ----------------------------------------------------------------------------------------------
# integrator


def _coefficients(solver, rho_inf):
    if solver == "trapezoidal":
        return 0.0, 0.0, 0.25, 0.5
    if solver == "generalized_alpha":
        r = check_in_range("rho_inf", rho_inf, 0.0, 1.0)
        am, af = (2 * r - 1) / (r + 1), r / (r + 1)
        gamma = 0.5 + af - am
        return am, af, 0.25 * (gamma + 0.5) ** 2, gamma
    raise ValueError(f"solver must be 'trapezoidal' or 'generalized_alpha'; got {solver!r}")


@dataclass
class Result:
    """trajectory: dict of arrays (one entry per accepted step and t = 0); summary: dict of
    scalars; params: the scene parameters; info: solver settings and counters."""

    trajectory: dict
    summary: dict
    params: object
    info: dict = field(default_factory=dict)


class _Stepper:
    LS_HALVINGS = 10          # backtracking halvings of the Newton step (lam down to 2^-10)

    def __init__(self, model, solver, rho_inf, jacobian, newton_tol, max_newton, max_halvings, floor):
        if jacobian not in ("analytic", "numerical"):
            raise ValueError(f"jacobian must be 'analytic' or 'numerical'; got {jacobian!r}")
        self.m = model
        self.am, self.af, self.beta, self.gamma = _coefficients(solver, rho_inf)
        self.jacobian = jacobian
        self.tol = check_positive("newton_tol", newton_tol)
        self.max_newton = check_integer("max_newton", max_newton, 1)
        self.max_halvings = check_integer("max_halvings", max_halvings, 0)
        self.floor = float(floor)
        self.n_iter = 0
        self.n_rejected = 0
        self.n_unresolved = 0     # converged steps rejected because a contact point's motion was unresolved
        self.forced = []          # (t, scaled residual) of steps accepted without convergence
        self.line_search = True
        self.n_backtracks = 0     # residual evaluations of the line search beyond the full Newton step

    def initial(self, t0):
        m = self.m
        q, v = m.q0, m.v0.copy()
        H = m.law.evaluate(*self._points0(q, v), None, tangent=False).history
        g, _, _, st = m.evaluate(q, v, t0, H, tangent=False)
        vdot = g / m.mass
        return dict(q=q, v=v, a=vdot.copy(), vdot=vdot, H=H, st=st,
                    fref=max(m.force_level(st), self.floor))

    def _points0(self, q, v):
        m = self.m
        if hasattr(m, "points0"):
            return m.points0(q, v)
        if isinstance(m, _BlockPlanar):
            X, V, _ = m.points(q, v)
            return X, V
        if isinstance(m, _ScrewReduced):
            c, s = math.cos(q[0]), math.sin(q[0])
            P = m.s @ np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])
            return P + np.array([0.0, 0.0, q[1]]), np.zeros_like(P)
        r, R, _ = q
        return r + m.s @ R.T, np.zeros_like(m.s)

    def _residual(self, S, d, h, t1, tangent):
        m = self.m
        a1 = (d - h * S["v"] - h * h * (0.5 - self.beta) * S["a"]) / (h * h * self.beta)
        v1 = S["v"] + h * (1.0 - self.gamma) * S["a"] + h * self.gamma * a1
        vdot1 = ((1.0 - self.am) * a1 + self.am * S["a"] - self.af * S["vdot"]) / (1.0 - self.af)
        q1, T = m.retract(S["q"], d)
        g, Gq, Gv, st = m.evaluate(q1, v1, t1, S["H"], tangent, h)
        r = m.mass * vdot1 - g
        return r, (q1, v1, a1, vdot1, st), (T, Gq, Gv)

    def step(self, S, t, h, accept_best=False):
        """One Newton solve; returns the new state or None (not converged). With accept_best the
        iterate with the smallest residual is returned instead of None (flag "forced")."""
        m = self.m
        ca = (1.0 - self.am) / ((1.0 - self.af) * self.beta * h * h)
        cv = self.gamma / (self.beta * h)
        d = h * S["v"] + h * h * 0.5 * S["a"]
        fref = S["fref"]
        scale = m.row_scale
        analytic = self.jacobian == "analytic"
        best = None

        def pack(sol, it, forced=False):
            q1, v1, a1, vdot1, st = sol
            return dict(q=q1, v=v1, a=a1, vdot=vdot1, H=st.history, st=st, iters=it, forced=forced,
                        fref=max(m.force_level(st), self.floor))

        r, sol, (T, Gq, Gv) = self._residual(S, d, h, t + h, analytic)
        for it in range(self.max_newton + 1):
            if not np.all(np.isfinite(r)):
                break
            fref = max(fref, m.force_level(sol[4]))
            err = np.max(np.abs(r) / scale) / fref
            if err <= self.tol:
                if np.any(sol[4].status == UNRESOLVED):   # a point turned more than the step resolves
                    self.n_unresolved += 1
                    return None
                return pack(sol, it)
            if best is None or err < best[0]:
                best = (err, sol, it)
            if it == self.max_newton:
                break
            if analytic:
                Tm = np.eye(m.n) if T is None else T
                Jac = np.diag(m.mass * ca) - Gq @ Tm - Gv * cv
            else:
                Jac = self._numerical_jacobian(S, d, h, t + h, r)
            try:
                delta = np.linalg.solve(Jac, r)
            except np.linalg.LinAlgError:
                break
            self.n_iter += 1
            d, r, sol, (T, Gq, Gv) = self._line_search(S, d, delta, r, h, t + h, analytic, fref)
        if accept_best and best is not None:
            self.forced.append((t + h, best[0]))
            return pack(best[1], best[2], forced=True)
        return None

    def _line_search(self, S, d, delta, r, h, t1, tangent, fref):
        """Next Newton iterate d - lam delta. The full step (lam = 1) is taken whenever it decreases
        the merit |r / row_scale|_2 or already meets the convergence test -- so a Newton solve that converges monotonically keeps exactly
        its iterates (and its parity with Exudyn's plain Newton). Otherwise (two-cycles at the
        kinks of the return maps, overshoot of the first step from the predictor) lam is halved
        until the Armijo condition |r(lam)| <= (1 - 1e-4 lam) |r| holds, at most ``LS_HALVINGS``
        times; if none holds the trial with the smallest merit is taken (and the outer loop goes
        on, or the step is cut as before). Counted in ``n_backtracks`` (residual evaluations)."""
        scale = self.m.row_scale
        phi0 = np.linalg.norm(r / scale)
        lam, best = 1.0, None
        for k in range(self.LS_HALVINGS + 1 if self.line_search else 1):
            dk = d - lam * delta
            rk, sol, tang = self._residual(S, dk, h, t1, tangent)
            phi = np.linalg.norm(rk / scale) if np.all(np.isfinite(rk)) else math.inf
            if k > 0:
                self.n_backtracks += 1
            elif not self.line_search or phi < phi0 or (math.isfinite(phi) and np.max(np.abs(rk) / scale)
                                                         <= self.tol * max(fref, self.m.force_level(sol[4]))):
                return dk, rk, sol, tang
            if phi <= (1.0 - 1e-4 * lam) * phi0:
                return dk, rk, sol, tang
            if best is None or phi < best[0]:
                best = (phi, dk, rk, sol, tang)
            lam *= 0.5
        return best[1:]

    def _numerical_jacobian(self, S, d, h, t1, r0):
        n = self.m.n
        Jac = np.empty((n, n))
        # perturbation: sqrt(machine eps) times the increment or 1e-2 of the DOF's natural scale
        # (body size for translations, 1 rad for rotations)
        ref = 1e-2 * self.m.dof_scale
        for j in range(n):
            e = 1.5e-8 * max(abs(d[j]), ref[j])
            dj = d.copy()
            dj[j] += e
            rj, _, _ = self._residual(S, dj, h, t1, False)
            Jac[:, j] = (rj - r0) / e
        return Jac


def _model_for(p, law=None):
    """Model of the scene; ``law`` replaces the scene's ContactLaw (e.g. another chart of its surface)."""
    if law is not None:
        check_instance("law", law, ContactLaw)
    if isinstance(p, BlockParams):
        law = block_contact_law(p) if law is None else law
        return (_BlockPlanar(p, law) if p.model == "planar" else _BlockFull(p, law)), 1e-6 * p.eps_n * p.size
    law = screw_contact_law(p) if law is None else law
    return (_ScrewReduced(p, law) if p.model == "reduced" else _ScrewFull(p, law)), 1e-6 * p.eps_n * p.radius


def jacobian_check(params, steps=50, rho_inf=0.8):
    """Compare the analytic Newton Jacobian with central differences after ``steps`` steps of the
    scene (at the converged end-of-step increment of the next step). Returns (analytic,
    numerical, relative error max|A - N| / max|N - M c_a|), i.e. relative to the force part."""
    model, floor = _model_for(params)
    st = _Stepper(model, params.solver, rho_inf, "analytic", 1e-10, 25, 12, floor)
    S = st.initial(0.0)
    h, t = time_step(params), 0.0

    def advance(S, t, h, depth=0):
        new = st.step(S, t, h)
        if new is not None or depth > 12:
            return new
        return advance(advance(S, t, 0.5 * h, depth + 1), t + 0.5 * h, 0.5 * h, depth + 1)

    for _ in range(steps):
        S = advance(S, t, h)
        t += h
    new = st.step(S, t, h)
    # recover the increment: vector models d = q1 - q; 6-DOF: (dr, log(R^T R1)) via the predictor
    d = h * S["v"] + h * h * (0.5 - st.beta) * S["a"] + h * h * st.beta * new["a"]
    ca = (1.0 - st.am) / ((1.0 - st.af) * st.beta * h * h)
    cv = st.gamma / (st.beta * h)
    r0, _, (T, Gq, Gv) = st._residual(S, d, h, t + h, True)
    A = np.diag(model.mass * ca) - Gq @ (np.eye(model.n) if T is None else T) - Gv * cv
    Nm = np.empty_like(A)
    for j in range(model.n):
        e = 1e-6 * max(abs(d[j]), 1e-2 * model.dof_scale[j])
        dp, dm = d.copy(), d.copy()
        dp[j] += e
        dm[j] -= e
        Nm[:, j] = (st._residual(S, dp, h, t + h, False)[0] - st._residual(S, dm, h, t + h, False)[0]) / (2 * e)
    Mi = np.diag(model.mass * ca)       # inertia part is common to both: compare the rest
    return A, Nm, float(np.max(np.abs(A - Nm)) / np.max(np.abs(Nm - Mi)))


_RUN_OPTIONS = ("jacobian", "rho_inf", "newton_tol", "max_newton", "max_halvings", "nonsmooth_accept", "line_search",
                "reject_steps", "split_steps")


def _run(model, p, *, jacobian="analytic", rho_inf=0.8, newton_tol=1e-10, max_newton=25, max_halvings=6,
         nonsmooth_accept=True, line_search=True, reject_steps=(), split_steps=(), floor):
    stepper = _Stepper(model, p.solver, rho_inf, jacobian, newton_tol, max_newton, max_halvings, floor)
    stepper.line_search = check_bool("line_search", line_search)
    nonsmooth_accept = check_bool("nonsmooth_accept", nonsmooth_accept)
    reject_steps = {check_integer("reject_steps entry", i, 0) for i in check_instance(
        "reject_steps", reject_steps, (list, tuple, set, range, np.ndarray), "sequence of step indices")}
    split_steps = {check_integer("split_steps entry", i, 0) for i in check_instance(
        "split_steps", split_steps, (list, tuple, set, range, np.ndarray), "sequence of step indices")}
    wall0 = time.perf_counter()
    S = stepper.initial(0.0)
    rows, states = [], []

    def rec(t, S, iters, h):
        states.append((model.motion(S["q"], S["v"]), S["H"].copy()))
        row = model.record(S["q"], S["v"], t, S["st"])
        row.update(t=t, h=h, newton_iterations=iters, dissipated_energy=float(S["H"][:, 5].sum()),
                   slip_distance=float(S["H"][:, 6].mean()))
        rows.append(row)

    rec(0.0, S, 0, 0.0)
    grid = time_grid(p)
    n_steps = len(grid) - 1

    def advance(S, t, h, depth, forced_reject, forced_split):
        if not forced_split:
            last = depth >= stepper.max_halvings and nonsmooth_accept
            new = stepper.step(S, t, h, accept_best=last)
            if new is not None and not forced_reject:
                rec(t + h, new, new["iters"], h)
                return new
            stepper.n_rejected += 1
        if depth >= stepper.max_halvings:
            if stepper.n_unresolved:
                raise RuntimeError(f"contact point motion unresolved at t = {t:.6g} s even with step {h:.3g} s "
                                   f"({depth} halvings): a point turns too far about the cylinder axis per step "
                                   f"for its angle increment to be known; use a smaller dt")
            raise RuntimeError(f"Newton did not converge at t = {t:.6g} s even with step {h:.3g} s "
                               f"({depth} halvings); try a smaller dt or the numerical Jacobian")
        S = advance(S, t, 0.5 * h, depth + 1, False, False)
        return advance(S, t + 0.5 * h, 0.5 * h, depth + 1, False, False)

    for i in range(n_steps):
        S = advance(S, grid[i], grid[i + 1] - grid[i], 0, i in reject_steps, i in split_steps)
    wall = time.perf_counter() - wall0
    traj = {k: np.array([row[k] for row in rows]) for k in rows[0]}
    motion = energy.RigidMotion(*(np.array([m[i] for m, _ in states]) for i in range(4)))
    info = dict(solver=p.solver, jacobian=jacobian, rho_inf=rho_inf if p.solver == "generalized_alpha" else None,
                rejected_steps=stepper.n_rejected, unresolved_steps=stepper.n_unresolved, newton_tol=newton_tol,
                K=model.K,
                forced_accepts=len(stepper.forced), line_search=stepper.line_search, backtracks=stepper.n_backtracks,
                max_forced_residual=max((e for _, e in stepper.forced), default=0.0))
    return traj, wall, stepper.n_iter, len(rows) - 1, info, motion, np.array([H for _, H in states])


def simulate_block(params=None, **options):
    """Block scene with the reference integrator; params: BlockParams (defaults if None).

    options: jacobian ("analytic" | "numerical"), rho_inf (generalized_alpha, default 0.8),
    newton_tol (1e-10, scaled residual), max_newton (25), max_halvings (6), nonsmooth_accept
    (True: at the last halving level accept the smallest-residual iterate instead of failing;
    needed by the seed map, whose discontinuity at stick/slip can leave the step without a root;
    counted in ``info["forced_accepts"]``), reject_steps / split_steps (nominal step indices to
    reject after convergence / to halve directly), law (a ContactLaw replacing the scene's, e.g.
    the plane in polar coordinates). Returns Result."""
    p = BlockParams() if params is None else params
    if not isinstance(p, BlockParams):
        raise TypeError(f"params must be BlockParams; got {type(p).__name__}")
    check_keywords("simulate_block", options, _RUN_OPTIONS + ("law",))
    model, floor = _model_for(p, options.pop("law", None))
    traj, wall, iters, steps, info, motion, H = _run(model, p, floor=floor, **options)
    summary = block_summary(traj, wall, steps, iters)
    summary.update(block_energy(p, traj, motion, model.law, H))
    return Result(traj, summary, p, info)


def simulate_screw(params=None, **options):
    """Screw scene with the reference integrator; params: ScrewParams (defaults if None).
    Options as for simulate_block. Returns Result."""
    p = ScrewParams() if params is None else params
    if not isinstance(p, ScrewParams):
        raise TypeError(f"params must be ScrewParams; got {type(p).__name__}")
    if p.model == "full" and p.points_per_ring < 3:
        raise ValueError(f"points_per_ring must be >= 3 for model='full' (radial centring); got {p.points_per_ring}")
    check_keywords("simulate_screw", options, _RUN_OPTIONS)
    model, floor = _model_for(p)
    traj, wall, iters, steps, info, motion, H = _run(model, p, floor=floor, **options)
    summary = screw_summary(traj, wall, steps, iters)
    summary.update(screw_energy(p, traj, motion, model.s, model.law, H))
    return Result(traj, summary, p, info)


def simulate_particle(params=None, **options):
    """Particle scene (exu_aniso.scene_particle) with the reference integrator; params:
    ParticleParams (defaults if None). Options as for simulate_block, law: a ContactLaw replacing
    the scene's (e.g. on a surface of one's own). Returns Result with the trajectory keys of
    scene_particle.COLUMNS (plus h, newton_iterations) and particle_summary with the energy ledger."""
    from .scene_particle import ParticleParams, finish_trajectory, particle_contact_law, particle_energy, \
        particle_summary
    p = ParticleParams() if params is None else params
    if not isinstance(p, ParticleParams):
        raise TypeError(f"params must be ParticleParams; got {type(p).__name__}")
    check_keywords("simulate_particle", options, _RUN_OPTIONS + ("law",))
    law = options.pop("law", None)
    if law is not None:
        check_instance("law", law, ContactLaw)
    model = _MassPoint(p, particle_contact_law(p) if law is None else law)
    floor = 1e-6 * p.eps_n * p.radius
    traj, wall, iters, steps, info, motion, H = _run(model, p, floor=floor, **options)
    finish_trajectory(traj, model.law, H)
    summary = particle_summary(traj, p, wall, steps, iters)
    summary.update(particle_energy(p, traj, model.law, H))
    info.update(engine="reference")
    return Result(traj, summary, p, info)


def simulate_feeder(params=None, **options):
    """Feeder scene (exu_aniso.scene_feeder) with the reference integrator: the track's motion
    prescribed exactly, every part integrated on its own (parts do not touch). params: FeederParams
    (defaults if None); options as for simulate_block. The trajectory and the summary are those of
    models/feeder.py (scene_feeder.COLUMNS, feeder_summary with the parts' energy ledger), sampled
    at the nominal steps.

    Counts as the Exudyn engine's, for the whole system: summary ``steps`` = the nominal steps of the
    run (not their sum over the parts); ``extra_steps`` = accepted steps beyond them (halvings; a
    time at which any part took one counts once, as a joint integration would take it);
    ``newton_iterations`` = per nominal step the most iterations any part took (a joint Newton solve
    of independent parts converges when the slowest does). Per-part counts are in info:
    part_steps, part_newton_iterations (every iteration, rejected attempts included),
    part_rejected_steps."""
    from .scene_feeder import (FeederParams, feeder_contact_law, feeder_energy, feeder_summary, finish_trajectory,
                               part_positions, plate_motion, throw_direction)
    p = FeederParams() if params is None else params
    if not isinstance(p, FeederParams):
        raise TypeError(f"params must be FeederParams; got {type(p).__name__}")
    check_keywords("simulate_feeder", options, _RUN_OPTIONS)
    law = feeder_contact_law(p)
    grid = time_grid(p)
    runs, wall, info = [], 0.0, {}
    per_step, times, part_steps, part_iters, part_rejected = [], [], [], [], []
    for x0 in part_positions(p):
        model = _FeederPart(p, law, x0)
        traj, w, it, st, info, motion, H = _run(model, p, floor=1e-6 * p.eps_n * p.part_size, **dict(options))
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
    summary = feeder_summary(out, P, yaw, p, wall, steps, iters, extra_steps=extra)
    summary.update(feeder_energy(p, out, motions, forces, law, H, (u, ud)))
    info.update(engine="reference", K=4 * p.parts, part_steps=part_steps, part_newton_iterations=part_iters,
                part_rejected_steps=part_rejected)
    return Result(out, summary, p, info)
