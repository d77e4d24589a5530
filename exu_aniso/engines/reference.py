"""Standalone numpy/scipy reference engine: rigid-body dynamics and an implicit integrator.

No Exudyn here: this module is the oracle the Exudyn engine is compared with.

Body models: any ``BodyModel`` (a configuration, a velocity and the generalized forces of its
contact points); each scene's module defines its own and says what it models (e.g. the block's
planar and 6-DOF models in ``exu_aniso.scenes.block``, the screw's in ``exu_aniso.scenes.screw``, a
mass point in ``exu_aniso.scenes.particle``). They share three: ``PlanarBody`` (x, y, theta, its
points held at a height), ``ScrewJoint`` (a turn about and a travel along z) and ``RigidBody6``, the
6-DOF rigid body: position r of the COM (world), rotation matrix R (body -> world), velocity v
(world), angular velocity Omega (BODY frame).

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

import numpy as np

from exu_aniso.law.history import UNRESOLVED
from exu_aniso.engines import energy
from exu_aniso.engines.timing import time_grid, time_step
from exu_aniso.util.rotations import rotation_matrix, skew, wrap_angle
from exu_aniso.util.validation import check_bool, check_in_range, check_instance, check_integer, check_positive

# ----------------------------------------------------------------------------------------------
# SO(3) helpers


def _skew_batch(a):
    S = np.zeros(a.shape[:-1] + (3, 3))
    S[..., 0, 1], S[..., 0, 2] = -a[..., 2], a[..., 1]
    S[..., 1, 0], S[..., 1, 2] = a[..., 2], -a[..., 0]
    S[..., 2, 0], S[..., 2, 1] = -a[..., 1], a[..., 0]
    return S


def _right_jacobian(th):
    """J_r(th): exp([th + d]x) = exp([th]x) exp([J_r d]x) + O(d^2)."""
    phi = math.sqrt(th @ th)
    W = skew(th)
    if phi < 1e-6:
        return np.eye(3) - 0.5 * W + W @ W / 6.0
    return np.eye(3) - (1.0 - math.cos(phi)) / phi ** 2 * W + (phi - math.sin(phi)) / phi ** 3 * W @ W


# ----------------------------------------------------------------------------------------------
# models: g(q, v, t) and its derivatives with respect to the increment and the velocity


class BodyModel:
    """A body model of the reference engine (a scene's module defines its own; see
    docs/adding_a_scene.md). What ``run`` uses:

    * ``n`` coordinates, ``K`` contact points, ``law`` (its ContactLaw);
    * ``mass`` (n,): the diagonal mass matrix; ``row_scale`` (n,): the residual rows' scale for the
      convergence test (a moment row: a length); ``dof_scale`` (n,): the coordinates' size for the
      numerical Jacobian;
    * ``q0``, ``v0``: the initial state;
    * ``points0(q, v)``: the contact points' positions and velocities (K, 3) for the initial history;
    * ``evaluate(q, v, t, H, tangent=True, dt=None)`` -> (g, dg/dq, dg/dv, ContactState): the
      generalized force and, with tangent, its derivatives (None without);
    * ``motion(q, v)`` -> (position, rotation matrix, velocity, angular velocity) for the energy ledger;
    * ``record(q, v, t, st)`` -> dict of the trajectory's row;
    * ``retract(q, d)`` -> (q + d, its tangent or None): the update (a Lie group's for rotations;
      this class: vector addition) and ``force_level(st)`` (the convergence test's force scale)
      have defaults here."""

    def retract(self, q, d):
        return q + d, None

    def force_level(self, state):
        return float(np.sum(np.linalg.norm(state.force, axis=1)))


class RigidBody6(BodyModel):
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

    def points0(self, q, v):
        r, R, _ = q
        return r + self.s @ R.T, np.zeros_like(self.s)

    def retract(self, q, d):
        r, R, yaw = q
        R1 = R @ rotation_matrix(d[3:])
        yaw1 = yaw + wrap_angle(math.atan2(R1[1, 0], R1[0, 0]) - yaw)
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
            Gq[3:, 3:] += skew(R.T @ Me) + np.outer(R.T @ dMe, R[2, :])
            Gq[:3, :3] += dFe
            dV = np.zeros((self.K, 3, 6))                             # d(R (Om x s))/dphi = -R [Om x s]x
            dV[:, :, 3:] = -np.einsum("ij,kjl->kil", R, _skew_batch(np.cross(Om, self.s)))
            Gq += np.einsum("kia,kab,kbj->ij", B, st.damping, dV)
            Gv = np.einsum("kia,kab,kbj->ij", B, st.damping, A)
            Gv[3:, 3:] -= skew(Om) @ np.diag(self.J) - skew(JOm)
        return g, Gq, Gv, st

    def world_omega(self, q, v):
        return q[1] @ v[3:]

    def motion(self, q, v):
        return q[0], q[1], v[:3], self.world_omega(q, v)


class PlanarBody(BodyModel):
    """A rigid body moving in the plane z = const: q = (x, y, theta) [m, m, rad], v their rates; mass
    diag(mass, mass, inertia); contact points s_k (body frame, (K, 2)) held at the height
    ``point_height`` [m] (a normal load carried by a held penetration), the centre of mass at
    ``com_height`` [m]; ``size`` [m] scales the torque row. Subclasses give ``drive(q, v, t)`` -> (force
    (2,), its d/dq[:2] and d/dv[:2] (2, 2)) and may give ``torque(q, v, t)`` -> (torque about z [N m],
    its d/dtheta, its d/domega); both act at the centre of mass."""

    n = 3

    def __init__(self, law, s, mass, inertia, size, q0, point_height, com_height):
        self.law, self.s = law, np.asarray(s, float)
        self.K = len(self.s)
        self.gap, self.com_height = point_height, com_height
        self.mass = np.array([mass, mass, inertia])
        self.row_scale = np.array([1.0, 1.0, size])
        self.dof_scale = np.array([size, size, 1.0])
        self.q0 = np.array(q0, dtype=float)
        self.v0 = np.zeros(3)

    def drive(self, q, v, t):
        raise NotImplementedError

    def torque(self, q, v, t):
        return None

    def points(self, q, v):
        c, s = math.cos(q[2]), math.sin(q[2])
        P = self.s @ np.array([[c, s], [-s, c]])                      # R(theta) s_k, rows
        X = np.column_stack([q[0] + P[:, 0], q[1] + P[:, 1], np.full(self.K, self.gap)])
        V = np.column_stack([v[0] - v[2] * P[:, 1], v[1] + v[2] * P[:, 0], np.zeros(self.K)])
        return X, V, P

    def points0(self, q, v):
        X, V, _ = self.points(q, v)
        return X, V

    def evaluate(self, q, v, t, H, tangent=True, dt=None):
        X, V, P = self.points(q, v)
        st = self.law.evaluate(X, V, H, tangent, dt)
        f = st.force
        Fd, dFd, dFd_v = self.drive(q, v, t)
        applied = self.torque(q, v, t)
        g = np.array([f[:, 0].sum() + Fd[0], f[:, 1].sum() + Fd[1],
                      np.sum(P[:, 0] * f[:, 1] - P[:, 1] * f[:, 0])])
        if applied is not None:
            g[2] += applied[0]
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
            Gv[:2, :2] += dFd_v
            if applied is not None:
                Gq[2, 2] += applied[1]
                Gv[2, 2] += applied[2]
        return g, Gq, Gv, st

    def motion(self, q, v):
        """(COM position, rotation matrix, velocity, angular velocity) in the world frame."""
        c, s = math.cos(q[2]), math.sin(q[2])
        return (np.array([q[0], q[1], self.com_height]), np.array([[c, -s, 0.0], [s, c, 0.0], [0, 0, 1.0]]),
                np.array([v[0], v[1], 0.0]), np.array([0.0, 0.0, v[2]]))


class ScrewJoint(BodyModel):
    """A body on a screw joint along the z axis: q = (psi [rad], z [m]), v = (omega, vz), the rotation
    about and the travel along z free and independent (a thread's lead comes from the contact, not the
    joint); mass diag(inertia, mass); contact points s_k (body frame, the axis through the origin)
    against a ground master. ``size``: the body's radius [m] (the torque row's scale). Subclasses give
    ``external(q, t)`` -> (torque about z, its d/dpsi, force along z, its d/dz)."""

    n = 2

    def __init__(self, law, s, mass, inertia, size, q0=(0.0, 0.0)):
        self.law, self.s = law, np.asarray(s, float)
        self.K = len(self.s)
        self.mass = np.array([inertia, mass])
        self.row_scale = np.array([size, 1.0])
        self.dof_scale = np.array([1.0, size])
        self.q0 = np.array(q0, dtype=float)
        self.v0 = np.zeros(2)

    def external(self, q, t):
        raise NotImplementedError

    def turned_points(self, psi):
        """The body's points turned by psi about z (K, 3)."""
        c, s = math.cos(psi), math.sin(psi)
        return self.s @ np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])

    def points0(self, q, v):
        P = self.turned_points(q[0])
        return P + np.array([0.0, 0.0, q[1]]), np.zeros_like(P)

    def evaluate(self, q, v, t, H, tangent=True, dt=None):
        P = self.turned_points(q[0])
        X = P + np.array([0.0, 0.0, q[1]])
        ez_x_P = np.column_stack([-P[:, 1], P[:, 0], np.zeros(self.K)])
        V = v[0] * ez_x_P
        V[:, 2] += v[1]
        st = self.law.evaluate(X, V, H, tangent, dt)
        f = st.force
        tau, dtau, Fz, dFz = self.external(q, t)
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

    def contact_torque_and_force(self, q, st):
        """The contact's torque about z [N m] and force along z [N] at q."""
        P, f = self.turned_points(q[0]), st.force
        return float(np.sum(P[:, 0] * f[:, 1] - P[:, 1] * f[:, 0])), float(f[:, 2].sum())


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
        return self.m.points0(q, v)

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


def jacobian_check(model, floor, params, steps=50, rho_inf=0.8):
    """Compare the analytic Newton Jacobian of a body model (floor: its force level's floor, as for run)
    with central differences after ``steps`` steps of the scene params (solver, dt) (at the converged
    end-of-step increment of the next step). Returns (analytic, numerical, relative error
    max|A - N| / max|N - M c_a|), i.e. relative to the force part."""
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


RUN_OPTIONS = ("jacobian", "rho_inf", "newton_tol", "max_newton", "max_halvings", "nonsmooth_accept", "line_search",
                "reject_steps", "split_steps")


def run(model, p, *, jacobian="analytic", rho_inf=0.8, newton_tol=1e-10, max_newton=25, max_halvings=6,
         nonsmooth_accept=True, line_search=True, reject_steps=(), split_steps=(), floor):
    """Integrate a body model (``BodyModel``) over the time grid of the parameter set p (``t_end``,
    ``dt``, ``solver``: "trapezoidal" or "generalized_alpha"); floor [N]: the smallest force scale of
    the convergence test (a scene takes 1e-6 x its normal stiffness x its size). Options as listed in
    the module docstring (``RUN_OPTIONS``). Returns (trajectory dict of arrays, wall time [s], Newton
    iterations, accepted steps, info dict, energy.RigidMotion of the model's motion, contact history
    (steps + 1, K, N_HISTORY)); a scene turns them into its Result (e.g. scenes.block.simulate_block)."""
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
