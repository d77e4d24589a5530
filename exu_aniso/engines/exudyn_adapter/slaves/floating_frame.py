"""The nodes of a reduced-order flexible body in a floating frame of reference (Exudyn's
ObjectFFRFreducedOrder) as a slave."""
from __future__ import annotations

import numpy as np

from exu_aniso.engines.exudyn_adapter.slaves.base import Slave
from exu_aniso.engines.exudyn_adapter.slaves.linear import resolve_points
from exu_aniso.engines.exudyn_adapter.slaves.rigid import node_kinematics


class FloatingFrame(Slave):
    """The mesh nodes of a reduced-order flexible body (Exudyn's ObjectFFRFreducedOrder: a floating
    frame of reference, a 3D rigid node (position p, rotation A), and modal coordinates eta of a
    NodeGenericODE2) as contact points: mesh node k at

        x_k = p + A (r_k + Psi_k eta)

    with its reference position r_k in the body frame (the object's referencePositions) and its
    three rows Psi_k (3, m) of the object's modeBasis. The set's coordinates are the rigid node's
    (6 or 7) and then the m modal ones. Jp = [I, -A [r_k + Psi_k eta]x G, A Psi_k]: the rigid node's
    point Jacobian at the deformed body-frame point, and the modes turned with the frame; v = Jp q_t.
    Its derivatives (point_derivatives): the rigid node's at the deformed point, and the coupling of
    the rotation and the modes, dJp_rot/deta_j = the rotation columns of Jp at the point Psi_k e_j
    (linear in the point), dJp_modal_j/dq_rot = dx/dq_rot at that point; dJp_modal/deta = 0.

    localPoints: mesh node indices or (K, 3) body-frame reference positions of mesh nodes [m]. The
    kinematics are numpy's (the compiled kernel has no node kind with modes); the law at the points
    runs compiled where the law compiles (CompiledPointLaw). tangent_terms gives the Jacobian what
    it needs of point_derivatives without forming it."""

    points_are_nodes = True
    compiled_route = None

    def __init__(self, mbs, body, localPoints):
        obj = mbs.GetObject(body)
        node_rigid, node_modal = (int(nd) for nd in obj["nodeNumbers"])
        self.frame_node = node_kinematics(mbs, node_rigid)
        if self.frame_node.kind not in ("RigidBodyEP", "RigidBodyRotVecLG"):
            raise ValueError(f"CreateAnisotropicContact: the floating frame of ObjectFFRFreducedOrder {body} must be a "
                             f"3D rigid node (EP or RotVecLG); got {self.frame_node.kind}")
        self.kind = "FFRFreducedOrder"
        self.objects = [body]
        self.node = node_rigid
        self.nodes = [node_rigid, node_modal]
        R = np.asarray(obj["referencePositions"], dtype=float).reshape(-1, 3)
        Psi = np.asarray(obj["modeBasis"], dtype=float)
        self.mesh_indices = resolve_points(R, localPoints, "its referencePositions (body frame)")
        rows = (3 * np.asarray(self.mesh_indices)[:, None] + np.arange(3)).ravel()
        self.r = R[self.mesh_indices]
        self.Psi = Psi[rows].reshape(len(self.mesh_indices), 3, Psi.shape[1])
        self.nr, self.m = self.frame_node.n, Psi.shape[1]
        self.n = self.nr + self.m
        modal = mbs.GetNodeParameter(node_modal, "referenceCoordinates")
        q0m = mbs.GetNodeParameter(node_modal, "initialCoordinates")
        v0m = mbs.GetNodeParameter(node_modal, "initialCoordinates_t")
        zeros = np.zeros(self.m)
        self.ref = np.concatenate([self.frame_node.ref, np.asarray(modal, dtype=float) if len(modal) else zeros])
        self.q0 = np.concatenate([self.frame_node.q0, np.asarray(q0m, dtype=float) if len(q0m) else zeros])
        self.v0 = np.concatenate([self.frame_node.v0, np.asarray(v0m, dtype=float) if len(v0m) else zeros])

    def number_of_points(self, b):
        return len(self.mesh_indices)

    def coordinates(self, mbs, variable, configuration):
        return np.concatenate([np.asarray(mbs.GetNodeOutput(nd, variable, configuration=configuration), dtype=float)
                               for nd in self.nodes])

    def _deformed(self, q):
        """Body-frame positions r_k + Psi_k eta (K, 3) at the set's coordinates q (reference excluded)."""
        eta = self.ref[self.nr:] + np.asarray(q, dtype=float)[self.nr:]
        return self.r + self.Psi @ eta

    def points(self, q, q_t, b):
        """Global positions (K, 3), velocities (K, 3), Jacobians Jp (K, 3, n) and the frame's A."""
        q, q_t = np.asarray(q, dtype=float), np.asarray(q_t, dtype=float)
        x, v, J, A = self.frame_node.points(q[:self.nr], q_t[:self.nr], self._deformed(q))
        turned = A @ self.Psi                                               # A Psi_k (K, 3, m)
        return x, v + turned @ q_t[self.nr:], np.concatenate([J, turned], axis=2), A

    def point_derivatives(self, q, b):
        q = np.asarray(q, dtype=float)
        K, nr, m = len(self.r), self.nr, self.m
        dJ = np.zeros((K, 3, self.n, self.n))
        dJ[:, :, :nr, :nr] = self.frame_node.point_derivatives(q[:nr], self._deformed(q))
        e = self.Psi.transpose(0, 2, 1).reshape(K * m, 3)                   # the points Psi_k e_j, all at once
        Je = self.frame_node.points(q[:nr], np.zeros(nr), e)[2]
        Jx = self.frame_node.position_jacobian(q[:nr], e, Je)
        dJ[:, :, 3:nr, nr:] = Je[:, :, 3:].reshape(K, m, 3, nr - 3).transpose(0, 2, 3, 1)   # d(rotation columns)/d eta_j
        dJ[:, :, nr:, 3:nr] = Jx[:, :, 3:].reshape(K, m, 3, nr - 3).transpose(0, 2, 1, 3)   # d(A Psi e_j)/dq_rot
        return dJ

    def position_jacobian(self, q, b, Jp):
        Jx = Jp.copy()
        Jx[:, :, :self.nr] = self.frame_node.position_jacobian(q[:self.nr], self._deformed(q), Jp[:, :, :self.nr])
        return Jx

    def tangent_terms(self, q, q_t, b, F):
        """What the Jacobian needs of point_derivatives without forming its (K, 3, n, n) array (its
        blocks: the rigid node's at the deformed point, and the two couplings of rotation and modes):
        the geometric term sum_k F_k . dJp_k/dq (n, n) at the point forces F (K, 3), and dv/dq
        (K, 3, n) = dJp/dq q_t. Equal to the contractions of point_derivatives (tests/
        test_jacobian_nodes.py)."""
        q, q_t, F = np.asarray(q, dtype=float), np.asarray(q_t, dtype=float), np.asarray(F, dtype=float)
        K, nr, m = len(self.r), self.nr, self.m
        D = self.frame_node.point_derivatives(q[:nr], self._deformed(q))          # (K, 3, nr, nr)
        e = self.Psi.transpose(0, 2, 1).reshape(K * m, 3)                          # the points Psi_k e_j
        Jpe = self.frame_node.points(q[:nr], np.zeros(nr), e)[2]                  # the rigid node's Jp there
        Je = Jpe[:, :, 3:].reshape(K, m, 3, nr - 3)
        Jx = self.frame_node.position_jacobian(q[:nr], e, Jpe)[:, :, 3:].reshape(K, m, 3, nr - 3)
        geo = np.zeros((self.n, self.n))
        geo[:nr, :nr] = np.einsum("kiac,ki->ac", D, F)
        geo[3:nr, nr:] = np.einsum("kjir,ki->rj", Je, F)                           # d(rotation columns)/d eta_j
        geo[nr:, 3:nr] = np.einsum("kjir,ki->jr", Jx, F)                           # d(A Psi e_j)/dq_rot
        dv = np.zeros((K, 3, self.n))
        dv[:, :, :nr] = np.einsum("kiac,a->kic", D, q_t[:nr])
        dv[:, :, nr:] = np.einsum("kjir,r->kij", Je, q_t[3:nr])
        dv[:, :, 3:nr] += np.einsum("kjir,j->kir", Jx, q_t[nr:])
        return geo, dv

