"""The block scene's body models for the reference engine (``exu_aniso.engines.reference``) and its run
there: a planar rigid body (x, y, theta) held at the penetration that carries the normal load, or a
6-DOF rigid cube on the plane (see the reference engine's docstring for the models' equations). The
scene's parameters, law, points, summary and ledger are in ``exu_aniso.scenes.base``.
"""
from __future__ import annotations

import math

import numpy as np

from exu_aniso.engines import energy
from exu_aniso.engines.reference import RUN_OPTIONS, BodyModel, RigidBody6, run
from exu_aniso.engines.result import Result
from exu_aniso.kernel.contact_law import ContactLaw
from exu_aniso.util.validation import check_instance, check_keywords
from exu_aniso.scenes.base import BlockParams, block_contact_law, block_energy, block_inertia, block_points, block_summary


class _BlockPlanar(BodyModel):
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

    def points0(self, q, v):
        X, V, _ = self.points(q, v)
        return X, V

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


class _BlockFull(RigidBody6):
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


def reference_model(p, law=None):
    """The block's body model for the reference engine and its force floor; ``law`` replaces the
    scene's ContactLaw (e.g. another chart of its surface)."""
    if law is not None:
        check_instance("law", law, ContactLaw)
    law = block_contact_law(p) if law is None else law
    return (_BlockPlanar(p, law) if p.model == "planar" else _BlockFull(p, law)), 1e-6 * p.eps_n * p.size


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
    check_keywords("simulate_block", options, RUN_OPTIONS + ("law",))
    model, floor = reference_model(p, options.pop("law", None))
    traj, wall, iters, steps, info, motion, H = run(model, p, floor=floor, **options)
    summary = block_summary(traj, wall, steps, iters)
    summary.update(block_energy(p, traj, motion, model.law, H))
    return Result(traj, summary, p, info)
