"""Rigid slaves: one rigid node (planar, screw joint, rotation vector, Euler parameters), keyed by
Exudyn's node type in NODE_KINDS, and a group of rigid bodies of one node type carrying the same
points (RigidGroup)."""
from __future__ import annotations

import math

import numpy as np

from exu_aniso.engines.exudyn_adapter.slaves.base import Slave
from exu_aniso.util.rotations import rotation_matrix


def ep_matrix(e):
    e0, e1, e2, e3 = e
    A = np.array([[e0 * e0 + e1 * e1 - e2 * e2 - e3 * e3, 2 * (e1 * e2 - e0 * e3), 2 * (e1 * e3 + e0 * e2)],
                  [2 * (e1 * e2 + e0 * e3), e0 * e0 - e1 * e1 + e2 * e2 - e3 * e3, 2 * (e2 * e3 - e0 * e1)],
                  [2 * (e1 * e3 - e0 * e2), 2 * (e2 * e3 + e0 * e1), e0 * e0 - e1 * e1 - e2 * e2 + e3 * e3]])
    G = 2.0 * np.array([[-e1, e0, e3, -e2], [-e2, -e3, e0, e1], [-e3, e2, -e1, e0]])  # omega_local = G de/dt
    return A, G


def ep_derivatives(e):
    """dA/de_m (4, 3, 3) and dG/de_m (4, 3, 4) of ep_matrix: A is quadratic and G linear in the
    Euler parameters e (not normalised: the force is a smooth function of e in R^4)."""
    e0, e1, e2, e3 = e
    dA = 2.0 * np.array([[[e0, -e3, e2], [e3, e0, -e1], [-e2, e1, e0]],
                         [[e1, e2, e3], [e2, -e1, -e0], [e3, e0, -e1]],
                         [[-e2, e1, e0], [e1, e2, e3], [-e0, e3, -e2]],
                         [[-e3, -e0, e1], [e0, -e3, e2], [e1, e2, e3]]])
    dG = np.stack([ep_matrix(np.eye(4)[m])[1] for m in range(4)])
    return dA, dG


def rotate_z(angle, b):
    """In-plane arms (ax, ay) of local points b rotated by angle about z."""
    c, s = math.cos(angle), math.sin(angle)
    return c * b[:, 0] - s * b[:, 1], s * b[:, 0] + c * b[:, 1]


def contracted(dJ, q_t, F):
    """What the Jacobian needs of the point derivatives dJ = dJp/dq (K, 3, n, n) (point_derivatives):
    the geometric term sum_k F_k . dJp_k/dq (n, n) at point forces F (K, 3), and dv/dq = dJp/dq q_t
    (K, 3, n)."""
    return np.einsum("kiac,ki->ac", dJ, F), np.einsum("kiac,a->kic", dJ, np.asarray(q_t, dtype=float))


class RigidNode(Slave):
    """Positions, velocities and point Jacobians of body-fixed points for one Exudyn node, in numpy
    (the numpy route; the compiled route's node kinds are exu_aniso.kernel.nodes, and
    tests/test_jacobian_nodes.py holds the two equal kind by kind). One subclass per node kind,
    keyed by Exudyn's node type name in NODE_KINDS; ``node_kinematics`` picks it."""

    kind = None                      # Exudyn's node type name
    n = None                         # coordinates
    velocity_parameter = "initialVelocities"

    def __init__(self, mbs, node_number):
        self.node = node_number
        self.nodes = [node_number]
        self.ref = np.asarray(mbs.GetNodeParameter(node_number, "referenceCoordinates"), dtype=float)
        if self.ref.shape != (self.n,):   # only a NodeGenericODE2 can have another size
            raise ValueError(f"CreateAnisotropicContact: NodeGenericODE2 {node_number} must have exactly 2 coordinates "
                             f"(rotation about z [rad], translation along z [m]); got {self.ref.shape[0]}")
        q0 = mbs.GetNodeParameter(node_number, "initialCoordinates")
        self.q0 = np.asarray(q0, dtype=float) if len(q0) else np.zeros(self.n)
        v0 = mbs.GetNodeParameter(node_number, self.velocity_parameter)
        self.v0 = np.asarray(v0, dtype=float) if len(v0) else np.zeros(self.n)

    def number_of_points(self, b):
        return b.shape[0]

    def coordinates(self, mbs, variable, configuration):
        """The node's coordinates (variable: exu.OutputVariableType.Coordinates or Coordinates_t)."""
        return np.asarray(mbs.GetNodeOutput(self.node, variable, configuration=configuration), dtype=float)

    def points(self, q, q_t, b):
        """Global positions (K, 3), velocities (K, 3), Jacobians Jp (K, 3, n) of local points b, and
        the rotation matrix of a 3D node (None for the planar and screw-joint nodes)."""
        return self._points(self.ref + np.asarray(q, dtype=float), np.asarray(q_t, dtype=float), b)

    def point_derivatives(self, q, b):
        """dJp/dq (K, 3, n, n) of local points b: dJp[k, :, :, c] is the derivative of Jp[k] by
        coordinate c at fixed q_t. Since v = Jp q_t for every node type, dv/dq = dJp q_t."""
        return self._point_derivatives(self.ref + np.asarray(q, dtype=float), b)

    def position_jacobian(self, q, b, Jp):
        """dx/dq (K, 3, n) of local points b, given their virtual-work Jacobian Jp: Jp itself but
        for Euler parameters (see PointTangent)."""
        return Jp

    def tangent_terms(self, q, q_t, b, F):
        """The geometric term (n, n) at point forces F (K, 3) and dv/dq (K, 3, n) (contracted)."""
        return contracted(self.point_derivatives(q, b), q_t, F)


class AboutZ(RigidNode):
    """A node turning about the z axis by its coordinate r (planar rigid body, screw joint):
    d(-a_y, a_x, 0)/dr = (-a_x, -a_y, 0) for the in-plane arm a."""

    r = None                         # the rotation coordinate

    def _point_derivatives(self, q, b):
        dJ = np.zeros((b.shape[0], 3, self.n, self.n))
        ax, ay = rotate_z(q[self.r], b)
        dJ[:, 0, self.r, self.r] = -ax
        dJ[:, 1, self.r, self.r] = -ay
        return dJ


class Planar(AboutZ):
    """NodeRigidBody2D: q = (x, y, theta); the points keep their local z."""

    kind, n, r = "RigidBody2D", 3, 2

    def _points(self, q, q_t, b):
        K = b.shape[0]
        ax, ay = rotate_z(q[2], b)
        x = np.stack([q[0] + ax, q[1] + ay, b[:, 2]], axis=-1)
        v = np.stack([q_t[0] - q_t[2] * ay, q_t[1] + q_t[2] * ax, np.zeros(K)], axis=-1)
        J = np.zeros((K, 3, 3))
        J[:, 0, 0] = J[:, 1, 1] = 1.0
        J[:, 0, 2] = -ay
        J[:, 1, 2] = ax
        return x, v, J, None


class ScrewJoint(AboutZ):
    """A 2-coordinate NodeGenericODE2: q = (psi, z), rotation about and translation along z."""

    kind, n, r = "GenericODE2", 2, 0
    velocity_parameter = "initialCoordinates_t"

    def _points(self, q, q_t, b):
        K = b.shape[0]
        ax, ay = rotate_z(q[0], b)
        x = np.stack([ax, ay, b[:, 2] + q[1]], axis=-1)
        v = np.stack([-q_t[0] * ay, q_t[0] * ax, np.full(K, q_t[1])], axis=-1)
        J = np.zeros((K, 3, 2))
        J[:, 0, 0] = -ay
        J[:, 1, 0] = ax
        J[:, 2, 1] = 1.0
        return x, v, J, None


class Rigid3D(RigidNode):
    """A 3D rigid node: q = (position, rotation parameters), omega_local = G dq_rot/dt."""

    def _points(self, q, q_t, b):
        K = b.shape[0]
        A, G = self.rotation(q)
        arm = b @ A.T
        omega_local = G @ q_t[3:]
        x = q[0:3] + arm
        v = q_t[0:3] + np.cross(omega_local, b) @ A.T
        skew = np.zeros((K, 3, 3))
        skew[:, 0, 1], skew[:, 0, 2], skew[:, 1, 2] = -b[:, 2], b[:, 1], -b[:, 0]
        skew[:, 1, 0], skew[:, 2, 0], skew[:, 2, 1] = b[:, 2], -b[:, 1], b[:, 0]
        J = np.zeros((K, 3, self.n))
        J[:, :, 0:3] = np.eye(3)
        J[:, :, 3:] = -(A @ skew) @ G           # -A [b]x G (matmul: a three-operand einsum costs ten times more)
        return x, v, J, A

    def frame(self, q, q_t):
        """Position, rotation matrix, global angular velocity and velocity of the node."""
        q = self.ref + np.asarray(q, dtype=float)
        q_t = np.asarray(q_t, dtype=float)
        A, G = self.rotation(q)
        return q[0:3], A, A @ (G @ q_t[3:]), q_t[0:3]


class RotationVector(Rigid3D):
    """NodeRigidBodyRotVecLG, differentiated by the local rotation increment dtheta (A -> A (I +
    [dtheta]x), what Exudyn's Lie-group solver linearises in): Jp_rot e_a = -A (b x e_a), so
    d(Jp_rot e_a)/dtheta_c = -A (e_c x (b x e_a)) = -A (b delta_ac - e_a b_c)."""

    kind, n = "RigidBodyRotVecLG", 6

    @staticmethod
    def rotation(q_total):
        """Rotation matrix A and G = I (omega_local = the rotation vector's rate, linearised)."""
        return rotation_matrix(q_total[3:6]), np.eye(3)

    def _point_derivatives(self, q, b):
        dJ = np.zeros((b.shape[0], 3, self.n, self.n))
        A, _ = self.rotation(q)
        Ab = b @ A.T                                              # (K, 3): A b
        for a in range(3):
            dJ[:, :, 3 + a, 3 + a] -= Ab
            dJ[:, :, 3 + a, 3:6] += np.einsum("i,kc->kic", A[:, a], b)
        return dJ


class EulerParameters(Rigid3D):
    """NodeRigidBodyEP, differentiated by the four Euler parameters e themselves (Exudyn's EP
    constraint is a separate object): Jp_rot = -A(e) [b]x G(e), d/de_m = -(dA/de_m [b]x G +
    A [b]x dG/de_m); the position's dx/de_m = dA/de_m b differs from Jp_rot (position_jacobian)."""

    kind, n = "RigidBodyEP", 7

    @staticmethod
    def rotation(q_total):
        """Rotation matrix A and G (omega_local = G de/dt) of the Euler parameters q_total[3:7]."""
        return ep_matrix(q_total[3:7])

    def _point_derivatives(self, q, b):
        dJ = np.zeros((b.shape[0], 3, self.n, self.n))
        A, G = self.rotation(q)
        dA, dG = ep_derivatives(q[3:7])
        bxG = np.cross(b[:, None, :], G.T[None, :, :])                    # (K, a, 3): b x G e_a
        bxdG = np.cross(b[:, None, None, :], dG.transpose(0, 2, 1)[None])  # (K, m, a, 3): b x dG_m e_a
        dJ[:, :, 3:, 3:] = -(np.einsum("mij,kaj->kiam", dA, bxG) + np.einsum("ij,kmaj->kiam", A, bxdG))
        return dJ

    def position_jacobian(self, q, b, Jp):
        dA, _ = ep_derivatives(self.ref[3:7] + np.asarray(q, dtype=float)[3:7])
        Jx = Jp.copy()
        Jx[:, :, 3:7] = np.einsum("mij,kj->kim", dA, b)
        return Jx


NODE_KINDS = {c.kind: c for c in (Planar, ScrewJoint, RotationVector, EulerParameters)}


def node_kinematics(mbs, node_number):
    """The RigidNode of an Exudyn node, by its node type."""
    kind = mbs.GetNode(node_number)["nodeType"]
    if kind not in NODE_KINDS:
        raise ValueError(f"CreateAnisotropicContact: body node {node_number} has type {kind!r}; supported "
                         f"are NodeRigidBody2D, NodeRigidBodyRotVecLG (RotationRotationVector), NodeRigidBodyEP, "
                         f"NodePoint and NodePoint2D (mass points), NodePoint2DSlope1 and NodePointSlope1 (ANCF "
                         f"cables) and a 2-coordinate NodeGenericODE2 (screw joint: rotation about z, translation "
                         f"along z)")
    return NODE_KINDS[kind](mbs, node_number)


class RigidGroup(Slave):
    """Several rigid bodies of one node type carrying the same body-local points (a group: one
    contact set, one Exudyn object and one compiled call for all). The set's coordinates
    are the nodes' one after the other, its points body by body (K = bodies x points). Composed of
    one node_kinematics per body: every point depends on its own body's coordinates only."""

    compiled_route = "group"
    moving_master = False

    def __init__(self, mbs, objects):
        self.bodies = [node_kinematics(mbs, body_node(mbs, o)) for o in objects]
        kinds = sorted({bd.kind for bd in self.bodies})
        if len(kinds) > 1:
            raise ValueError(f"CreateAnisotropicContact: the rigid bodies of a list in bodyNumber must have nodes of "
                             f"one type; got {kinds}")
        self.kind = self.bodies[0].kind
        self.nodes = [bd.node for bd in self.bodies]
        self.node = self.nodes[0]
        self.nq = self.bodies[0].n
        self.n = self.nq * len(self.bodies)
        self.ref, self.q0, self.v0 = (np.concatenate([getattr(bd, name) for bd in self.bodies])
                                      for name in ("ref", "q0", "v0"))

    def number_of_points(self, b):
        return b.shape[0] * len(self.bodies)

    def coordinates(self, mbs, variable, configuration):
        return np.concatenate([bd.coordinates(mbs, variable, configuration) for bd in self.bodies])

    def _each(self, q):
        q = np.asarray(q, dtype=float)
        return ((j * self.nq, bd, q[j * self.nq:(j + 1) * self.nq]) for j, bd in enumerate(self.bodies))

    def points(self, q, q_t, b):
        """As node_kinematics.points over all bodies (Jp (K, 3, n): each point's body's columns); no
        rotation matrix (None)."""
        q_t = np.asarray(q_t, dtype=float)
        K = b.shape[0]
        x, v, J = [], [], np.zeros((K * len(self.bodies), 3, self.n))
        for j, (c, bd, qj) in enumerate(self._each(q)):
            xj, vj, Jj, _ = bd.points(qj, q_t[c:c + self.nq], b)
            x.append(xj)
            v.append(vj)
            J[j * K:(j + 1) * K, :, c:c + self.nq] = Jj
        return np.concatenate(x), np.concatenate(v), J, None

    def point_derivatives(self, q, b):
        K = b.shape[0]
        dJ = np.zeros((K * len(self.bodies), 3, self.n, self.n))
        for j, (c, bd, qj) in enumerate(self._each(q)):
            dJ[j * K:(j + 1) * K, :, c:c + self.nq, c:c + self.nq] = bd.point_derivatives(qj, b)
        return dJ

    def tangent_terms(self, q, q_t, b, F):
        return contracted(self.point_derivatives(q, b), q_t, F)

    def position_jacobian(self, q, b, Jp):
        K = b.shape[0]
        Jx = Jp.copy()
        for j, (c, bd, qj) in enumerate(self._each(q)):
            rows = slice(j * K, (j + 1) * K)
            Jx[rows, :, c:c + self.nq] = bd.position_jacobian(qj, b, Jp[rows, :, c:c + self.nq])
        return Jx



def body_node(mbs, bodyNumber):
    """Node of a body object: 'nodeNumber' of a rigid body, the single node of an ObjectGenericODE2."""
    obj = mbs.GetObject(bodyNumber)
    if "nodeNumber" in obj:
        return obj["nodeNumber"]
    nodes = list(obj.get("nodeNumbers", []))
    if len(nodes) != 1:
        raise ValueError(f"CreateAnisotropicContact: body {bodyNumber} ({obj.get('objectType')}) must have exactly one "
                         f"node; got nodeNumbers={nodes}")
    return nodes[0]



def rigid_body(mbs, body, localPoints=None):
    """The slave of a body object with one rigid node (a rigid body; a 2-coordinate ObjectGenericODE2,
    the screw joint)."""
    return node_kinematics(mbs, body_node(mbs, body))
