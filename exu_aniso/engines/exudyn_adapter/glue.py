"""The one place that talks to Exudyn: ``CreateAnisotropicContact`` adds a contact set to an mbs.

Mechanism (verified against Exudyn 1.13; see docs/guide/contact_api.md, "How it works inside Exudyn"):

* one ``ObjectGenericODE2`` per contact set acting on the slave body node (and the master body
  node when the surface moves), with a ``forceUserFunction`` returning the generalized contact
  forces ``Q = sum_k Jp_k^T f_k`` and a ``jacobianUserFunction`` with the consistent tangent of
  ``exu_aniso.kernel.contact_law`` mapped through the point Jacobians ``Jp_k``, completed by the terms of
  ``Jp_k`` depending on the node coordinates (lever arms and point velocities turning with the
  body; ``_ContactSet._add_geometric``) for every node type; with a moving master the compiled
  route (``kernel.sets.evaluate_pair``) gives it over the slave's and the master's coordinates, the
  numpy route leaves the Jacobian to Exudyn (numerical);
* the history lives in a ``NodeGenericData`` (9 numbers per point, ``HISTORY_FIELDS``). During
  Newton the law is evaluated from the last *converged* history (``ConfigurationType.StartOfStep``);
  one post-Newton function per mbs (native when every set is: ``_native.post_newton``, else
  ``_post_newton``) evaluates every set at the converged state and writes the
  candidate to ``ConfigurationType.Current``. Exudyn copies Current to StartOfStep only when a step
  is accepted and restores Current from StartOfStep when it rejects a step, so rejected or reduced
  steps leave no trace. The compiled sets do this in place, on Exudyn's own vectors
  (``_SystemViews``: numpy views of the Current and StartOfStep coordinates): the history is read
  from the StartOfStep data, the candidate written into the Current data, the state read from the
  Current ODE2 coordinates, with no Get/Set of whole vectors per step;
* a group (bodyNumber a list of rigid bodies): one such object over all their nodes, the same points on
  each body (_RigidGroup; compiled: kernel.sets.evaluate_group, the Jacobian a scipy CSR matrix of the
  bodies' diagonal blocks, so Exudyn's sparse solver gets no coupling that is not there);
* node types: ``NodeRigidBody2D`` (planar: in-plane force and z torque; the local z of a point is
  its fixed height over the plane), ``NodeRigidBodyRotVecLG`` (``NodeType.RotationRotationVector``)
  and ``NodeRigidBodyEP``. Explicit solvers work with the 2D and rotation-vector nodes (Exudyn
  refuses EP nodes there).

The law itself is never changed here: every force comes from ``ContactLaw.evaluate``.
"""
from __future__ import annotations

import math
import weakref
from typing import NamedTuple

import exudyn as exu
import numpy as np
from exudyn.itemInterface import NodeGenericData, ObjectGenericODE2, SensorNode

from exu_aniso.kernel.sets import gather_coordinates, stage_candidate
from exu_aniso.kernel.point import _entry_point
from exu_aniso.kernel.native import NativeBlock, stage_kernel

try:        # the native callbacks (C++, built at install; see _native.cpp); absent: Python callbacks
    from exu_aniso.engines.exudyn_adapter import _native
    _native.set_stage_kernel(stage_kernel.address)
except ImportError:                             # pragma: no cover - an install without a C++ compiler
    _native = None
from exu_aniso.law.history import HISTORY_FIELDS, N_HISTORY, UNRESOLVED
from exu_aniso.law.return_maps import DEFAULT_RETURN_MAP
from exu_aniso.kernel.contact_law import ContactLaw
from exu_aniso.util.rotations import rotation_matrix
from exu_aniso.util.validation import check_bool, check_index, check_instance, check_points

_SETS_KEY = "exu_aniso_contact_sets"
_UNRESOLVED_KEY = "exu_aniso_unresolved_time"   # time of the last step rejected as unresolved
_SOS = exu.ConfigurationType.StartOfStep
_STATUS = HISTORY_FIELDS.index("status")
_DISSIPATED = HISTORY_FIELDS.index("dissipated_energy")
_CUR = exu.ConfigurationType.Current


def _ep_matrix(e):
    e0, e1, e2, e3 = e
    A = np.array([[e0 * e0 + e1 * e1 - e2 * e2 - e3 * e3, 2 * (e1 * e2 - e0 * e3), 2 * (e1 * e3 + e0 * e2)],
                  [2 * (e1 * e2 + e0 * e3), e0 * e0 - e1 * e1 + e2 * e2 - e3 * e3, 2 * (e2 * e3 - e0 * e1)],
                  [2 * (e1 * e3 - e0 * e2), 2 * (e2 * e3 + e0 * e1), e0 * e0 - e1 * e1 - e2 * e2 + e3 * e3]])
    G = 2.0 * np.array([[-e1, e0, e3, -e2], [-e2, -e3, e0, e1], [-e3, e2, -e1, e0]])  # omega_local = G de/dt
    return A, G


def _ep_derivatives(e):
    """dA/de_m (4, 3, 3) and dG/de_m (4, 3, 4) of _ep_matrix: A is quadratic and G linear in the
    Euler parameters e (not normalised: the force is a smooth function of e in R^4)."""
    e0, e1, e2, e3 = e
    dA = 2.0 * np.array([[[e0, -e3, e2], [e3, e0, -e1], [-e2, e1, e0]],
                         [[e1, e2, e3], [e2, -e1, -e0], [e3, e0, -e1]],
                         [[-e2, e1, e0], [e1, e2, e3], [-e0, e3, -e2]],
                         [[-e3, -e0, e1], [e0, -e3, e2], [e1, e2, e3]]])
    dG = np.stack([_ep_matrix(np.eye(4)[m])[1] for m in range(4)])
    return dA, dG


def _rotate_z(angle, b):
    """In-plane arms (ax, ay) of local points b rotated by angle about z."""
    c, s = math.cos(angle), math.sin(angle)
    return c * b[:, 0] - s * b[:, 1], s * b[:, 0] + c * b[:, 1]


def _contracted(dJ, q_t, F):
    """What the Jacobian needs of the point derivatives dJ = dJp/dq (K, 3, n, n) (point_derivatives):
    the geometric term sum_k F_k . dJp_k/dq (n, n) at point forces F (K, 3), and dv/dq = dJp/dq q_t
    (K, 3, n)."""
    return np.einsum("kiac,ki->ac", dJ, F), np.einsum("kiac,a->kic", dJ, np.asarray(q_t, dtype=float))


class _RigidNode:
    """Positions, velocities and point Jacobians of body-fixed points for one Exudyn node, in numpy
    (the numpy route; the compiled route's node kinds are exu_aniso.kernel.nodes, and
    tests/test_jacobian_nodes.py holds the two equal kind by kind). One subclass per node kind,
    keyed by Exudyn's node type name in _NODE_KINDS; ``_BodyKinematics`` picks it."""

    kind = None                      # Exudyn's node type name
    n = None                         # coordinates
    velocity_parameter = "initialVelocities"
    linear = False

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
        for Euler parameters (see _PointTangent)."""
        return Jp

    def tangent_terms(self, q, q_t, b, F):
        """The geometric term (n, n) at point forces F (K, 3) and dv/dq (K, 3, n) (_contracted)."""
        return _contracted(self.point_derivatives(q, b), q_t, F)


class _AboutZ(_RigidNode):
    """A node turning about the z axis by its coordinate r (planar rigid body, screw joint):
    d(-a_y, a_x, 0)/dr = (-a_x, -a_y, 0) for the in-plane arm a."""

    r = None                         # the rotation coordinate

    def _point_derivatives(self, q, b):
        dJ = np.zeros((b.shape[0], 3, self.n, self.n))
        ax, ay = _rotate_z(q[self.r], b)
        dJ[:, 0, self.r, self.r] = -ax
        dJ[:, 1, self.r, self.r] = -ay
        return dJ


class _Planar(_AboutZ):
    """NodeRigidBody2D: q = (x, y, theta); the points keep their local z."""

    kind, n, r = "RigidBody2D", 3, 2

    def _points(self, q, q_t, b):
        K = b.shape[0]
        ax, ay = _rotate_z(q[2], b)
        x = np.stack([q[0] + ax, q[1] + ay, b[:, 2]], axis=-1)
        v = np.stack([q_t[0] - q_t[2] * ay, q_t[1] + q_t[2] * ax, np.zeros(K)], axis=-1)
        J = np.zeros((K, 3, 3))
        J[:, 0, 0] = J[:, 1, 1] = 1.0
        J[:, 0, 2] = -ay
        J[:, 1, 2] = ax
        return x, v, J, None


class _ScrewJoint(_AboutZ):
    """A 2-coordinate NodeGenericODE2: q = (psi, z), rotation about and translation along z."""

    kind, n, r = "GenericODE2", 2, 0
    velocity_parameter = "initialCoordinates_t"

    def _points(self, q, q_t, b):
        K = b.shape[0]
        ax, ay = _rotate_z(q[0], b)
        x = np.stack([ax, ay, b[:, 2] + q[1]], axis=-1)
        v = np.stack([-q_t[0] * ay, q_t[0] * ax, np.full(K, q_t[1])], axis=-1)
        J = np.zeros((K, 3, 2))
        J[:, 0, 0] = -ay
        J[:, 1, 0] = ax
        J[:, 2, 1] = 1.0
        return x, v, J, None


class _Rigid3D(_RigidNode):
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


class _RotationVector(_Rigid3D):
    """NodeRigidBodyRotVecLG, differentiated by the local rotation increment dtheta (A -> A (I +
    [dtheta]x), what Exudyn's Lie-group solver linearises in): Jp_rot e_a = -A (b x e_a), so
    d(Jp_rot e_a)/dtheta_c = -A (e_c x (b x e_a)) = -A (b delta_ac - e_a b_c)."""

    kind, n = "RigidBodyRotVecLG", 6

    def rotation(self, q_total):
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


class _EulerParameters(_Rigid3D):
    """NodeRigidBodyEP, differentiated by the four Euler parameters e themselves (Exudyn's EP
    constraint is a separate object): Jp_rot = -A(e) [b]x G(e), d/de_m = -(dA/de_m [b]x G +
    A [b]x dG/de_m); the position's dx/de_m = dA/de_m b differs from Jp_rot (position_jacobian)."""

    kind, n = "RigidBodyEP", 7

    def rotation(self, q_total):
        return _ep_matrix(q_total[3:7])

    def _point_derivatives(self, q, b):
        dJ = np.zeros((b.shape[0], 3, self.n, self.n))
        A, G = self.rotation(q)
        dA, dG = _ep_derivatives(q[3:7])
        bxG = np.cross(b[:, None, :], G.T[None, :, :])                    # (K, a, 3): b x G e_a
        bxdG = np.cross(b[:, None, None, :], dG.transpose(0, 2, 1)[None])  # (K, m, a, 3): b x dG_m e_a
        dJ[:, :, 3:, 3:] = -(np.einsum("mij,kaj->kiam", dA, bxG) + np.einsum("ij,kmaj->kiam", A, bxdG))
        return dJ

    def position_jacobian(self, q, b, Jp):
        dA, _ = _ep_derivatives(self.ref[3:7] + np.asarray(q, dtype=float)[3:7])
        Jx = Jp.copy()
        Jx[:, :, 3:7] = np.einsum("mij,kj->kim", dA, b)
        return Jx


_NODE_KINDS = {c.kind: c for c in (_Planar, _ScrewJoint, _RotationVector, _EulerParameters)}


def _BodyKinematics(mbs, node_number):
    """The _RigidNode of an Exudyn node, by its node type."""
    kind = mbs.GetNode(node_number)["nodeType"]
    if kind not in _NODE_KINDS:
        raise ValueError(f"CreateAnisotropicContact: body node {node_number} has type {kind!r}; supported "
                         f"are NodeRigidBody2D, NodeRigidBodyRotVecLG (RotationRotationVector), NodeRigidBodyEP, "
                         f"NodePoint and NodePoint2D (mass points), NodePoint2DSlope1 and NodePointSlope1 (ANCF "
                         f"cables) and a 2-coordinate NodeGenericODE2 (screw joint: rotation about z, translation "
                         f"along z)")
    return _NODE_KINDS[kind](mbs, node_number)


class _RigidGroup:
    """Several rigid bodies of one node type carrying the same body-local points (a group: one
    contact set, one Exudyn object and one compiled call for all). The set's coordinates
    are the nodes' one after the other, its points body by body (K = bodies x points). Composed of
    one _BodyKinematics per body: every point depends on its own body's coordinates only."""

    linear = False

    def __init__(self, mbs, objects):
        self.bodies = [_BodyKinematics(mbs, _body_node(mbs, o)) for o in objects]
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
        """As _BodyKinematics.points over all bodies (Jp (K, 3, n): each point's body's columns); no
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
        return _contracted(self.point_derivatives(q, b), q_t, F)

    def position_jacobian(self, q, b, Jp):
        K = b.shape[0]
        Jx = Jp.copy()
        for j, (c, bd, qj) in enumerate(self._each(q)):
            rows = slice(j * K, (j + 1) * K)
            Jx[rows, :, c:c + self.nq] = bd.position_jacobian(qj, b, Jp[rows, :, c:c + self.nq])
        return Jx


def hermite_shape_functions(x, L):
    """Exudyn's cubic Hermite shape functions of an ANCF cable element of length L at the local
    position x in [0, L]: r(x) = S1 r0 + S2 r0' + S3 r1 + S4 r1' (node 0 at x = 0, node 1 at x = L;
    r' the slope coordinates; tests/test_cable.py checks them against Exudyn's output)."""
    xi = x / L
    return np.array([1.0 - 3.0 * xi ** 2 + 2.0 * xi ** 3, L * (xi - 2.0 * xi ** 2 + xi ** 3),
                     3.0 * xi ** 2 - 2.0 * xi ** 3, L * (-xi ** 2 + xi ** 3)])


_CABLES = {"ANCFCable2D": ("Point2DSlope1", 2), "ANCFCable": ("PointSlope1", 3)}   # object: (node type, dim)
_MASS_POINTS = {"MassPoint": ("Point", 3), "MassPoint2D": ("Point2D", 2)}
_RIGID_BODIES = ("RigidBody", "RigidBody2D")                      # objects a group may hold


class _LinearSlave:
    """A slave whose points are linear in its node coordinates: x_k = c_k + S_k q_total, with a
    constant point Jacobian Jp_k = S_k (so dJp/dq = 0 and v_k = S_k q_t).

    * mass points (ObjectMassPoint, ObjectMassPoint2D): S = I over the node's coordinates
      (2D: x, y in the plane z = 0), c = the local point b;
    * ANCF cables (ObjectANCFCable2D with NodePoint2DSlope1 (x, y, x', y') in the plane z = 0;
      ObjectANCFCable with NodePointSlope1 (x, y, z, x', y', z')): a list of elements, every local
      point [x, 0, 0] (0 <= x <= element length) on every element, S = Exudyn's Hermite shape
      functions (``hermite_shape_functions``), c = 0.

    The set's coordinates are those of the distinct nodes in order of first appearance; points are
    ordered element by element (K = number of elements x number of local points)."""

    linear = True

    def __init__(self, mbs, objects):
        types = [mbs.GetObject(o)["objectType"] for o in objects]
        self.kind = types[0]
        self.objects = list(objects)
        if self.kind in _MASS_POINTS:
            node_type, self.dim = _MASS_POINTS[self.kind]
            self.elements = [[int(mbs.GetObject(objects[0])["nodeNumber"])]]
            self.lengths = [0.0]
            self.kind = node_type                       # the node type, as the rigid kinds
        else:
            node_type, self.dim = _CABLES[self.kind]
            self.elements = [[int(nd) for nd in mbs.GetObject(o)["nodeNumbers"]] for o in objects]
            self.lengths = [float(mbs.GetObject(o)["length"]) for o in objects]
        self.nodes = []
        for el in self.elements:
            for nd in el:
                if nd not in self.nodes:
                    self.nodes.append(nd)
        self.node = self.nodes[0]
        self.nc = len(mbs.GetNodeParameter(self.nodes[0], "referenceCoordinates"))   # coordinates per node
        self.n = self.nc * len(self.nodes)
        self.ref, self.q0, self.v0 = (np.concatenate([self._node_vector(mbs, nd, name) for nd in self.nodes])
                                      for name in ("referenceCoordinates", "initialCoordinates", "initialVelocities"))

    def _node_vector(self, mbs, node, name):
        v = mbs.GetNodeParameter(node, name)
        return np.asarray(v, dtype=float) if len(v) else np.zeros(self.nc)

    def number_of_points(self, b):
        return b.shape[0] * len(self.elements)

    def coordinates(self, mbs, variable, configuration):
        return np.concatenate([np.asarray(mbs.GetNodeOutput(nd, variable, configuration=configuration), dtype=float)
                               for nd in self.nodes])

    def linear_map(self, b):
        """(idx (K, m), S (K, 3, m), c (K, 3)) of local points b: x_k = c_k + S_k q_total[idx_k]."""
        b = np.asarray(b, dtype=float)
        d = self.dim
        if self.kind in ("Point", "Point2D"):
            K = b.shape[0]
            idx = np.tile(np.arange(d), (K, 1))
            S = np.zeros((K, 3, d))
            for i in range(d):
                S[:, i, i] = 1.0
            return idx, S, b.copy()
        rows = []
        for el, L in zip(self.elements, self.lengths):
            cols = np.concatenate([self.nodes.index(nd) * self.nc + np.arange(2 * d) for nd in el])
            for x in b[:, 0]:
                h = hermite_shape_functions(x, L)          # (4,): r0, r0', r1, r1'
                S = np.zeros((3, 4 * d))
                for j in range(4):
                    S[:d, j * d:(j + 1) * d] = h[j] * np.eye(d)
                rows.append((cols, S))
        idx = np.array([r[0] for r in rows], dtype=np.int64)
        S = np.array([r[1] for r in rows])
        return idx, S, np.zeros((len(rows), 3))

    def jacobian_matrix(self, b):
        """Dense point Jacobians Jp (K, 3, n) and offsets c (K, 3) of local points b."""
        idx, S, c = self.linear_map(b)
        Jp = np.zeros((idx.shape[0], 3, self.n))
        for k in range(idx.shape[0]):
            Jp[k][:, idx[k]] += S[k]
        return Jp, c

    def points(self, q, q_t, b):
        """Global positions (K, 3), velocities (K, 3), Jacobians Jp (K, 3, n) of local points b and None."""
        Jp, c = self.jacobian_matrix(b)
        q = self.ref + np.asarray(q, dtype=float)
        return c + Jp @ q, Jp @ np.asarray(q_t, dtype=float), Jp, None

    def point_derivatives(self, q, b):
        return None                                     # dJp/dq = 0

    def position_jacobian(self, q, b, Jp):
        return Jp


class _MeshNodes(_LinearSlave):
    """The surface nodes of a full linear finite-element body (an ObjectGenericODE2 of NodePoint
    nodes, e.g. ``exu_aniso.engines.exudyn_adapter.fem.AddLinearFEBody`` or Exudyn's
    ``FEMinterface.CreateLinearFEMObjectGenericODE2``) as contact points: point k is mesh node j_k,
    x_k = q_total of that node (S = I, c = 0), a linear slave like a mass point. The set's
    coordinates are those of the listed nodes only (the contact object connects to them alone).

    localPoints: mesh node indices (positions in the object's nodeNumbers, as the mesh numbers them)
    or (K, 3) reference positions of mesh nodes [m] (each must be a node's, to 1e-9 of the body's
    size)."""

    def __init__(self, mbs, body, localPoints):
        obj = mbs.GetObject(body)
        mesh_nodes = [int(nd) for nd in obj["nodeNumbers"]]
        self.kind, self.dim = "Point", 3
        self.objects = [body]
        self.mesh_indices = self._resolve(mbs, mesh_nodes, localPoints)
        self.nodes = [mesh_nodes[j] for j in self.mesh_indices]
        self.elements = [[nd] for nd in self.nodes]
        self.lengths = [0.0] * len(self.nodes)
        self.node = self.nodes[0]
        self.nc = 3
        self.n = 3 * len(self.nodes)
        self.ref, self.q0, self.v0 = (np.concatenate([self._node_vector(mbs, nd, name) for nd in self.nodes])
                                      for name in ("referenceCoordinates", "initialCoordinates", "initialVelocities"))

    @staticmethod
    def _resolve(mbs, mesh_nodes, localPoints):
        """Mesh node indices of localPoints (class docstring)."""
        R = np.array([mbs.GetNodeParameter(nd, "referenceCoordinates") for nd in mesh_nodes], dtype=float)
        return _MeshNodes._resolve_points(R, localPoints, "their reference positions")

    @staticmethod
    def _resolve_points(R, localPoints, positions):
        """Indices into the mesh nodes at reference positions R (N, 3) of localPoints: indices
        themselves, or positions (each a node's to 1e-9 of the mesh's size)."""
        a = np.asarray(localPoints)
        if a.ndim == 1 and a.size and a.dtype != bool and (a.dtype.kind in "iu" or np.all(np.equal(np.mod(a, 1), 0))):
            ids = [int(j) for j in a]
            for k, j in enumerate(ids):
                if not 0 <= j < len(R):
                    raise ValueError(f"CreateAnisotropicContact: localPoints[{k}] = {j} is not a mesh node index of the "
                                     f"finite-element body (0 ... {len(R) - 1})")
        else:
            X = check_points("localPoints", localPoints)
            tol = 1e-9 * float(np.ptp(R, axis=0).max())
            ids = []
            for k, x in enumerate(X):
                d = np.linalg.norm(R - x, axis=1)
                j = int(np.argmin(d))
                if d[j] > tol:
                    raise ValueError(f"CreateAnisotropicContact: localPoints[{k}] = {x.tolist()} is not a node of the "
                                     f"finite-element body (the closest, mesh node {j} at {R[j].tolist()}, is "
                                     f"{d[j]:.3g} m away): give mesh node indices or {positions}")
                ids.append(j)
        if len(set(ids)) < len(ids):
            raise ValueError(f"CreateAnisotropicContact: localPoints lists a mesh node more than once; got {ids}")
        return ids

    def number_of_points(self, b):
        return len(self.nodes)

    def linear_map(self, b):
        """idx (K, 3) = the node's three set coordinates, S = I, c = 0 (b: (K, 3) zeros)."""
        K = len(self.nodes)
        idx = 3 * np.arange(K, dtype=np.int64)[:, None] + np.arange(3, dtype=np.int64)
        return idx, np.broadcast_to(np.eye(3), (K, 3, 3)).copy(), np.zeros((K, 3))


class _FloatingFrame:
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
    runs compiled where the law compiles (_CompiledPointLaw). tangent_terms gives the Jacobian what
    it needs of point_derivatives without forming it."""

    linear = False

    def __init__(self, mbs, body, localPoints):
        obj = mbs.GetObject(body)
        node_rigid, node_modal = (int(nd) for nd in obj["nodeNumbers"])
        self.frame_node = _BodyKinematics(mbs, node_rigid)
        if self.frame_node.kind not in ("RigidBodyEP", "RigidBodyRotVecLG"):
            raise ValueError(f"CreateAnisotropicContact: the floating frame of ObjectFFRFreducedOrder {body} must be a "
                             f"3D rigid node (EP or RotVecLG); got {self.frame_node.kind}")
        self.kind = "FFRFreducedOrder"
        self.objects = [body]
        self.node = node_rigid
        self.nodes = [node_rigid, node_modal]
        R = np.asarray(obj["referencePositions"], dtype=float).reshape(-1, 3)
        Psi = np.asarray(obj["modeBasis"], dtype=float)
        self.mesh_indices = _MeshNodes._resolve_points(R, localPoints, "its referencePositions (body frame)")
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


class _CompiledPointLaw:
    """The contact law at K points through the compiled kernel, for a slave whose kinematics the
    kernel has no node kind for (the floating frame): the set kernel of K free points (a linear
    slave over 3K coordinates, x_k = q[3k:3k+3], S = I), so that one compiled call gives the point
    forces (mode 0: Q = f), and df/dx, df/dv as its Jacobian's diagonal blocks (mode 1 with (fq, fv)
    = (1, 0) and (0, 1)). evaluate() answers as ContactLaw.evaluate for what the glue reads (force,
    stiffness, damping, history and its status)."""

    def __init__(self, law, K):
        from exu_aniso.kernel.point import CovariantSet
        from exu_aniso.kernel.sets import LinearMap
        idx = np.arange(3 * K, dtype=np.int64).reshape(K, 3)
        self.K = K
        self.pk = CovariantSet(law, LinearMap(idx, np.broadcast_to(np.eye(3), (K, 3, 3)), np.zeros((K, 3)), 3 * K),
                               np.zeros(3 * K), None)
        self.damped = law.d_N > 0.0 or law.d_T > 0.0
        self._blocks = (np.arange(3 * K).reshape(K, 3)[:, :, None], np.arange(3 * K).reshape(K, 3)[:, None, :])

    def evaluate(self, x, v, history, tangent=True, dt=None):
        pk, K = self.pk, self.K
        pk.H[:] = 0.0 if history is None else np.reshape(history, (K, N_HISTORY))
        q, q_t = np.ascontiguousarray(x, dtype=float).ravel(), np.ascontiguousarray(v, dtype=float).ravel()
        dt = 0.0 if dt is None else float(dt)
        pk.evaluate(0, q, q_t, 0.0, 0.0, dt)
        force, history = pk.Q.reshape(K, 3).copy(), pk.Hn.copy()
        stiffness = damping = None
        if tangent:
            pk.evaluate(1, q, q_t, 1.0, 0.0, dt)
            stiffness = -pk.J[self._blocks]
            damping = np.zeros((K, 3, 3))
            if self.damped:
                pk.evaluate(1, q, q_t, 0.0, 1.0, dt)
                damping = -pk.J[self._blocks]
        return _PointStates(force, stiffness, damping, history)


class _PointStates(NamedTuple):
    """What _CompiledPointLaw.evaluate gives: force (K, 3) [N], stiffness = df/dx and damping =
    df/dv (K, 3, 3) or None, the history candidate (K, 9)."""
    force: np.ndarray
    stiffness: np.ndarray
    damping: np.ndarray
    history: np.ndarray

    @property
    def status(self):
        """Each point's state (K,) int: OPEN, STICK, SLIP or UNRESOLVED (law.history)."""
        return self.history[:, _STATUS].astype(int)


def _is_mesh_body(mbs, obj):
    """An ObjectGenericODE2 of NodePoint nodes only (a linear FE body), not the 2-coordinate screw joint."""
    if obj["objectType"] != "GenericODE2":
        return False
    return all(mbs.GetNode(nd)["nodeType"] == "Point" for nd in obj["nodeNumbers"])


class _PointTangent(NamedTuple):
    """q-derivatives of the slave point kinematics for the Jacobian: dx (K, 3, n) = dx/dq,
    geometric (n, n) = sum_k f_k . dJp_k/dq at the point forces f and dv (K, 3, n) = dv/dq at fixed
    q_t = dJp/dq q_t (the slave's tangent_terms; both None for a linear slave, whose Jp is constant),
    and the law's damping Dv = df/dv (K, 3, 3). dx equals Jp except for Euler parameters: x = p + A(e)
    b with A quadratic in e, so along e itself dx/de e = 2 A b while the virtual-work Jacobian
    -A [b]x G(e) e = 0 (the unit norm is Exudyn's separate constraint)."""
    dx: np.ndarray
    geometric: np.ndarray
    dv: np.ndarray
    damping: np.ndarray


class _ContactSet:
    """State-free glue between one GenericODE2 object and a ContactLaw."""

    force_calls = 0             # calls of the force user function Exudyn made (each costs Exudyn 2 vectors)
    _native = None              # kernel.native.NativeBlock when Exudyn calls the native force (_CompiledSet)
    point_law = None            # _CompiledPointLaw: the law at the points through the compiled kernel (else law)

    def __init__(self, mbs, law, slave, points, master):
        self.law = law
        self.slave = slave
        self.points = points
        self.master = master
        self.K = slave.number_of_points(points)
        self.nData = None

    def _split(self, q, q_t):
        ns = self.slave.n
        return q[:ns], q_t[:ns], q[ns:], q_t[ns:]

    def initial_history(self, q, q_t):
        """The history (K * 9,) of the points at the initial coordinates q, q_t (the set's): the
        candidate from a history of zeros, so that points in contact start sticking there."""
        return self.state(None, q, q_t, None, tangent=False)[0].history.ravel()

    def state(self, mbs, q, q_t, history, tangent, dt=None):
        """Evaluate the law (dt: time since the converged history, see ContactLaw.evaluate); returns
        (ContactState, slave Jp, F_global, master Jp or None, tangent data of the slave points for
        _add_geometric: _PointTangent when tangent and the master is ground, else None)."""
        qs, vs, qm, vm = self._split(q, q_t)
        x, v, Jp, _ = self.slave.points(qs, vs, self.points)
        if self.master is None:
            st = (self.point_law or self.law).evaluate(x, v, history, tangent, dt)
            tg = None
            if tangent and self.slave.linear:          # Jp constant: dx/dq = Jp, dJp/dq = 0
                tg = _PointTangent(Jp, None, None, st.damping)
            elif tangent:
                geo, dv = self.slave.tangent_terms(qs, vs, self.points, st.force)
                tg = _PointTangent(self.slave.position_jacobian(qs, self.points, Jp), geo, dv, st.damping)
            return st, Jp, st.force, None, tg
        p, A, w, vp = self.master.frame(qm, vm)
        d = x - p
        x_rel = d @ A
        v_rel = (v - vp - np.cross(w, d)) @ A
        st = self.law.evaluate(x_rel, v_rel, history, tangent, dt)
        F = st.force @ A.T
        b_master = x_rel                       # reaction at the master's material point at S
        Jm = self.master.points(qm, vm, b_master)[2]
        return st, Jp, F, Jm, None

    def history(self, mbs, configuration):
        h = mbs.GetNodeOutput(self.nData, exu.OutputVariableType.Coordinates, configuration=configuration)
        return np.asarray(h, dtype=float).reshape(self.K, N_HISTORY)

    # --- read-only views for graphics and post-processing (never called by the solver) -----------
    def history_at(self, mbs, configuration=None):
        """History (K, 9) in an exu.ConfigurationType (e.g. Visualization: what the renderer and the
        SolutionViewer show); None: the initial history given to the node (works before Assemble)."""
        if configuration is None:
            return np.asarray(mbs.GetNodeParameter(self.nData, "initialCoordinates"), dtype=float).reshape(
                self.K, N_HISTORY)
        return self.history(mbs, configuration)

    def points_and_master_pose(self, mbs, configuration=None):
        """Slave points in the master frame (K, 3) and the master's pose: position (3,) and rotation
        matrix (3, 3) (master frame -> global; the origin and the identity for a ground master), in an
        exu.ConfigurationType; None: the nodes' initial coordinates (works before Assemble). Global
        positions are p + A x. Positions only: the law is not evaluated."""
        def coordinates(nd):
            if configuration is None:
                return nd.q0
            return nd.coordinates(mbs, exu.OutputVariableType.Coordinates, configuration)
        x = self.slave.points(coordinates(self.slave), np.zeros(self.slave.n), self.points)[0]
        if self.master is None:
            return x, np.zeros(3), np.eye(3)
        p, A, _, _ = self.master.frame(coordinates(self.master), np.zeros(self.master.n))
        return (x - p) @ A, np.array(p, dtype=float), A

    def body_position(self, mbs, configuration=None):
        """Global position (3,) of the slave body's local origin (node reference point; the joint
        origin of a screw-joint node; the start of the first element of a cable) in a configuration
        (None: initial coordinates)."""
        q = self.slave.q0 if configuration is None else self.slave.coordinates(
            mbs, exu.OutputVariableType.Coordinates, configuration)
        return self.slave.points(q, np.zeros(self.slave.n), np.zeros((1, 3)))[0][0]

    @staticmethod
    def step_time(mbs, t):
        """Time since the start of the step [s] (the age of the converged history)."""
        return t - mbs.systemData.GetTime(_SOS)

    def force(self, mbs, t, itemNumber, q, q_t):
        self.force_calls += 1
        st, Jp, F, Jm, _ = self.state(mbs, q, q_t, self.history(mbs, _SOS), tangent=False, dt=self.step_time(mbs, t))
        Q = F.reshape(-1) @ Jp.reshape(-1, Jp.shape[2])                 # sum_k Jp_k^T F_k
        if Jm is not None:
            Q = np.concatenate([Q, -np.einsum("kij,ki->j", Jm, F)])
        return Q.tolist()

    def generalized_force(self, q, q_t, history):
        """The contact object's generalized force Q over its coordinates at q, q_t (the set's
        coordinates, reference values excluded) from the converged history (K, 9), as a residual of
        the solver with no time elapsed since that history (post-processing: what the solver saw).
        Samples at once: q, q_t (n, nq) and history (n, K, 9) or (n, K*9) give Q (n, nq)."""
        q, q_t, H = np.asarray(q, dtype=float), np.asarray(q_t, dtype=float), np.asarray(history, dtype=float)
        if q.ndim == 1:
            return self._generalized_force(q, q_t, H.reshape(-1, N_HISTORY))
        if q.ndim != 2 or q_t.shape != q.shape or H.size != len(q) * self.K * N_HISTORY:
            raise ValueError(f"generalizedForce: q, q_t (n, nq) and history (n, K, {N_HISTORY}) over the same "
                             f"samples, K = {self.K}; got q {q.shape}, q_t {q_t.shape}, history {H.shape}")
        return self._sample_forces(q, q_t, H.reshape(len(q), self.K, N_HISTORY))

    def _generalized_force(self, q, q_t, H):
        _, Jp, F, Jm, _ = self.state(None, q, q_t, H, tangent=False, dt=0.0)
        Q = F.reshape(-1) @ Jp.reshape(-1, Jp.shape[2])
        return Q if Jm is None else np.concatenate([Q, -np.einsum("kij,ki->j", Jm, F)])

    def _sample_forces(self, q, q_t, H):
        return np.array([self._generalized_force(q[n], q_t[n], H[n]) for n in range(len(q))])

    def jacobian(self, mbs, t, itemNumber, q, q_t, fODE2, fODE2_t):
        """-(fODE2 dQ/dq + fODE2_t dQ/dq_t) of Q = sum_k Jp_k^T f_k(x_k, v_k) (ground master)."""
        st, Jp, _, _, tg = self.state(mbs, q, q_t, self.history(mbs, _SOS), tangent=True, dt=self.step_time(mbs, t))
        n = Jp.shape[2]
        rows = Jp.reshape(-1, n).T                                       # sum_k Jp_k^T M_k R_k as one product
        Kq = rows @ (st.stiffness @ tg.dx).reshape(-1, n)
        Dq = rows @ (st.damping @ Jp).reshape(-1, n)
        self._add_geometric(Kq, Jp, tg)
        return -(fODE2 * Kq + fODE2_t * Dq)

    @staticmethod
    def _add_geometric(Kq, Jp, tg):
        """Add the terms of dQ/dq that come from Jp depending on q (every node type; tg: the
        _PointTangent of state()). With v = Jp q_t and f = f(x, v):

            dQ/dq = sum_k Jp^T Kx Jp + sum_k f . dJp/dq + sum_k Jp^T Dv (dJp/dq q_t),

        the first (law stiffness) is in Kq already; the second is the lever arms turning at fixed
        point forces (the reference's geometric term), the third the point velocities turning
        with the body (nonzero only with normal damping: Dv = df/dv). A linear slave has none."""
        if tg.geometric is None:
            return
        Kq += tg.geometric
        if np.any(tg.damping):
            n = Jp.shape[2]
            Kq += Jp.reshape(-1, n).T @ (tg.damping @ tg.dv).reshape(-1, n)

    def candidate(self, mbs, t, q, q_t):
        """The history candidate (K, 9) at the converged state q, q_t (the set's coordinates) at time
        t, or None when a contact point's motion in the step is unresolved."""
        H = self.state(mbs, q, q_t, self.history(mbs, _SOS), tangent=False, dt=self.step_time(mbs, t))[0].history
        return None if np.any(H[:, _STATUS] == UNRESOLVED) else H

    def stage(self, mbs, t):
        """Put the history candidate at the converged state (Exudyn's Current coordinates) at time t
        into the Current data coordinates, in place; False (nothing written) when a point's step is
        unresolved. The numpy route fetches the views and its indices afresh at every commit (its
        own cost is far above theirs), so it never holds a view across a re-assembly."""
        self._indices(mbs)
        V = _SystemViews(mbs)
        self._check_indices(V)
        H = self.candidate(mbs, t, V.q[self.ltgODE2], V.q_t[self.ltgODE2])
        if H is None:
            return False
        V.data[self.ltg] = H.ravel()
        V.data[self.ltgTotal] = H[:, _DISSIPATED].sum()
        return True

    def locate(self, mbs, oContact):
        """Remember where the set's coordinates and history live in the system vectors (after
        Assemble): ODE2 indices of the contact object, data indices of the history and total."""
        self.oContact = oContact
        self.ltgODE2 = None

    def _indices(self, mbs):
        self.ltgODE2 = np.asarray(mbs.systemData.GetObjectLTGODE2(self.oContact), dtype=np.int64)
        self.ltg = np.asarray(mbs.systemData.GetNodeLTGData(self.nData), dtype=np.int64)
        self.ltgTotal = int(mbs.systemData.GetNodeLTGData(self.nTotal)[0])

    def _check_indices(self, V):
        """Assert that the set's indices lie in the system vectors of the views V: the object's
        coordinates (slave, then master), the history (one range of K * 9 data coordinates) and
        the total dissipation (one data coordinate)."""
        n = self.slave.n + (self.master.n if self.master is not None else 0)
        assert self.ltgODE2.shape == (n,) and 0 <= self.ltgODE2.min() and self.ltgODE2.max() < V.q.size, \
            (self.ltgODE2, V.sizes)
        assert np.array_equal(self.ltg, self.ltg[0] + np.arange(self.K * N_HISTORY)), self.ltg
        assert 0 <= self.ltg[0] and self.ltg[-1] < V.data.size and 0 <= self.ltgTotal < V.data.size, V.sizes


class _SystemViews:
    """numpy views of Exudyn's own system vectors (``copy=False``, Exudyn 1.13): the Current ODE2
    coordinates q [m, rad] and velocities q_t [m/s, rad/s], the Current data coordinates and the
    StartOfStep data coordinates. Writing into them writes into Exudyn's memory. They stay valid
    through solves and through re-assemblies of the same sizes; Exudyn reallocates a vector when
    it grows (Assemble of a larger system), so a holder compares ``sizes`` (ODE2, data) with the
    system's before it uses them again (_CompiledSet._load_history)."""

    def __init__(self, mbs):
        sd = mbs.systemData
        self.sizes = (sd.ODE2Size(), sd.DataSize())
        self.q = sd.GetODE2Coordinates(configuration=_CUR, copy=False)
        self.q_t = sd.GetODE2Coordinates_t(configuration=_CUR, copy=False)
        self.data = sd.GetDataCoordinates(configuration=_CUR, copy=False)
        self.data0 = sd.GetDataCoordinates(configuration=_SOS, copy=False)
        for v, size in ((self.q, self.sizes[0]), (self.q_t, self.sizes[0]), (self.data, self.sizes[1]),
                        (self.data0, self.sizes[1])):
            assert v.shape == (size,) and v.dtype == np.float64 and v.flags.c_contiguous and v.flags.writeable, \
                (v.shape, v.dtype, v.flags, self.sizes)

    def current(self, mbs):
        """True while the system's sizes (ODE2, data) are those at fetch time. With the new-solve rule
        of _CompiledSet._load_history this misses only a system re-assembled smaller and then back
        to the same sizes between two solves, the second starting at the first one's last commit."""
        sd = mbs.systemData
        return sd.ODE2Size() == self.sizes[0] and sd.DataSize() == self.sizes[1]


class _CompiledSet(_ContactSet):
    """The same contact set evaluated by the compiled kernel ``exu_aniso.kernel.sets`` (ground
    master, a surface numba compiles): one compiled call per user function on arrays packed once
    (``kernel.CovariantSet``).

    What is not recomputed or copied:
    * the converged history is not copied: the kernel reads it from the StartOfStep data
      coordinates (a view of Exudyn's vector, which changes only when a step is accepted);
    * q, q_t are read from the Current ODE2 coordinates (views: Exudyn's q, q_t lists are these
      numbers, at the object's coordinates), never from the lists: a slice of the views when the
      object's coordinates are one range of the system vector (a body, a group of consecutive
      bodies), else gathered at its indices into float64 buffers by a compiled loop
      (``gather_coordinates``; a moving master: the slave's range, then the master's);
    * every residual (mode 0) also leaves its history candidate and its state; the post-Newton commit
      takes the candidate of the last residual when that state is the converged one (it is: Newton
      stops after a residual), and evaluates afresh otherwise, and writes it into the Current data
      coordinates (a view) in place. Exudyn's accept (Current -> StartOfStep) is the commit, its
      reject (StartOfStep -> Current) the rollback.

    The views are fetched again (_views) at the first step of a solve (a start-of-step time that
    is neither the last one nor the last commit's) and whenever the system's sizes changed."""

    def __init__(self, mbs, law, slave, points, master):
        super().__init__(mbs, law, slave, points, master)
        from exu_aniso.kernel.sets import LinearMap
        # a linear slave (mass points, cables) goes to kernel.sets.evaluate_linear, a rigid one to evaluate_set
        kind = LinearMap(*slave.linear_map(points), slave.n) if slave.linear else slave.kind
        self.pk = self._pack(law, kind, slave, points, master)
        self._t = None                        # time of the Newton solve of the current arguments
        self._t0 = None                       # its start-of-step time [s]
        self._dt = 0.0
        self._committed_t = None              # time of the last commit [s]
        self.recomputed = 0                   # commits that had to evaluate afresh (diagnostics)
        # the compiled function itself (numba's dispatch done once) and its packed arguments: q, q_t
        # are the views of Exudyn's Current coordinates at the object's range (_views) or float64
        # buffers they are gathered into (_gathered; the kernel keeps no reference to them: a
        # residual copies its state into X); fODE2, fODE2_t are floats
        self._entry, self._tail = self.pk.entry(), self.pk.tail
        self._V = None                        # _SystemViews
        self._gathered = True
        self._gather, self._gather_args = None, None   # gather_coordinates and its arguments (_views)
        self._qb, self._q_tb = np.zeros(self.pk.X.shape[1]), np.zeros(self.pk.X.shape[1])   # own buffers
        self._q, self._q_t = self._qb, self._q_tb
        self._force_args = None               # the force call's arguments, made with dt by _load_history
        self._mbs_address = None              # the C++ system's address: the native registry's key

    def _generalized_force(self, q, q_t, H):
        return self._sample_forces(q[None], q_t[None], H[None])[0]

    def _sample_forces(self, q, q_t, H):
        """_ContactSet.generalized_force from the set's own compiled kernel, one call per sample
        (mode 0 on each sample's history; the residual's state is forgotten afterwards, so a later
        commit evaluates afresh)."""
        entry, tail, Q = self.pk.entry(), self.pk.tail, self.pk.Q
        q, q_t = np.ascontiguousarray(q), np.ascontiguousarray(q_t)
        H = np.ascontiguousarray(H)
        out = np.empty((len(q), len(Q)))
        for n in range(len(q)):
            entry(0, q[n], q_t[n], 0.0, 0.0, 0.0, H[n], *tail)
            out[n] = Q
        self.pk.X[:] = np.nan
        return out

    def initial_history(self, q, q_t):
        """As _ContactSet.initial_history, from the set's own compiled kernel (mode 2: the candidate
        from the zero history the packed set starts with), so no other compiled entry is needed."""
        self.pk.evaluate(2, q, q_t, 0.0, 0.0, 0.0)
        return self.pk.Hn.ravel().copy()

    @staticmethod
    def _pack(law, kind, slave, points, master):
        """The set packed for its compiled kernel (_CompiledPairSet: a moving master's)."""
        from exu_aniso.kernel.point import CovariantSet
        return CovariantSet(law, kind, slave.ref, points)

    def _views(self, mbs):
        """(Re)fetch the views of Exudyn's vectors and the set's indices, assert them, and make the
        set's slices: the history (K, 9) in the StartOfStep data and its q, q_t in the Current ODE2
        vectors (one range: slices of the views; else the buffers and the gather's arguments)."""
        self._indices(mbs)
        V = _SystemViews(mbs)
        self._check_indices(V)
        a, n = self.ltgODE2, self.ltgODE2.size
        self._gathered = not np.array_equal(a, a[0] + np.arange(n))
        if self._gathered:
            self._q, self._q_t = self._qb, self._q_tb
            self._gather_args = (V.q, V.q_t, np.ascontiguousarray(a, dtype=np.int64), self._qb, self._q_tb)
            self._gather = _entry_point(gather_coordinates, self._gather_args)
        else:
            self._q, self._q_t = V.q[a[0]:a[0] + n], V.q_t[a[0]:a[0] + n]
            self._gather, self._gather_args = None, None
        h = int(self.ltg[0])
        self._h0 = V.data0[h:h + self.K * N_HISTORY].reshape(self.K, N_HISTORY)
        self._V = V
        # the commit's compiled function (numba's dispatch done once: it cost ~1 us per step) and arguments
        self._stage_args = (self.pk.X, self._q, self._q_t, self.pk.Hn, V.data, np.ascontiguousarray(self.ltg),
                            int(self.ltgTotal))
        self._stage = _entry_point(stage_candidate, self._stage_args)
        if self._native is not None:          # the native callers read the new views from now on
            self._native.store(self._h0, self._native_stage_args(V))

    def _native_stage_args(self, V):
        """The native post-Newton commit's arguments (kernel.native.STAGE_TYPE) over the views V: the
        set's coordinates gathered at its indices into its buffers, then stage_candidate."""
        return (self.pk.X, V.q, V.q_t, np.ascontiguousarray(self.ltgODE2, dtype=np.int64), self._qb, self._q_tb,
                self.pk.Hn, V.data, np.ascontiguousarray(self.ltg, dtype=np.int64), int(self.ltgTotal))

    def _load_history(self, mbs, t):
        t0 = mbs.systemData.GetTime(_SOS)
        # the last commit: the native post-Newton's while the native callers are armed (it moves their clock)
        native = self._native is not None and self._native.clock[1] != 0.0
        committed = self._native.clock[0] if native else self._committed_t
        if self._V is None or (t0 != self._t0 and t0 != committed) or not self._V.current(mbs):
            self._views(mbs)                  # a new solve, or a re-assembled system
        self._t = t
        self._t0 = t0
        self._dt = t - t0
        self._force_args = (0, self._q, self._q_t, 0.0, 0.0, self._dt, self._h0) + self._tail
        if self._native is not None:          # views checked, start of the step known: the native callers may go on
            self._native.clock[:2] = (t0, 1.0)

    # --- the native force callback (_native.cpp): Exudyn calls the kernel without Python -----------
    def use_native(self, mbs):
        """Give Exudyn the native force callback for this set's object (after locate): its kernel
        (kernel.native: the same compiled entry over the same arguments) is registered for (mbs,
        object), unarmed; the first call of a solve goes to ``native_delegate``, which arms it."""
        f, i = np.zeros(0), np.zeros(0, dtype=np.int64)          # stage arguments until the views are known
        self._native = NativeBlock(self.pk._fn, self.pk.H, self._tail,
                                   (self.pk.X, f, f, i, self._qb, self._q_tb, self.pk.Hn, f, i, 0))
        self._mbs_address = _native.system_address(mbs)
        _native.register_set(mbs, self.oContact, self._native.kernel, self._native.args.address,
                             self._native.stage.address, self.pk.Q.ctypes.data, self.pk.X.shape[1],
                             self._native.clock.ctypes.data,
                             _Delegate(self, mbs), self.pk.J)
        return _native.force

    def native_delegate(self, mbs, t):
        """The native callback's call in Python (its first call of every solve, a call at or before
        the start of the step, a call the kernel raised in): checks the views (_load_history, which
        arms the native caller), reads the solve's end time and step (the native callers take steps up to
        twice the nominal one: a later call is a new solve, which Python checks) and evaluates the force
        into Q."""
        self.force_calls += 1
        self._load_history(mbs, t)
        ss = mbs.sys.get("simulationSettings")
        ti = ss.timeIntegration if ss is not None else None
        clock = self._native.clock
        clock[2] = float(ti.endTime) if ti is not None else math.inf
        clock[3] = (2.0 * (ti.endTime - ti.startTime) / max(int(ti.numberOfSteps), 1) if ti is not None
                    else math.inf)
        if self._gathered:
            self._gather(*self._gather_args)
        self._entry(*self._force_args)

    def disarm(self):
        """The next native call goes to Python first (native_delegate): at the end of a solve."""
        if self._native is not None:
            self._native.clock[1] = 0.0

    def step_done(self, t):
        """After an accepted step at t (every set committed): the native caller's next step starts at
        t; after the solve's last step (t within half a step of its end time) its next call goes to
        Python first."""
        clock = self._native.clock            # start of the step, armed, end of the solve
        h = t - clock[0]
        clock[0] = t
        if t + 0.5 * h >= clock[2]:
            clock[1] = 0.0

    def native_calls(self):
        """(native, delegated) force calls of this set so far."""
        if self._native is None:
            return 0, 0
        return _native.calls(self._mbs_address, self.oContact)

    def native_jacobians(self):
        """(native, delegated) Jacobian calls of this set so far."""
        if self._native is None:
            return 0, 0
        return _native.jacobian_calls(self._mbs_address, self.oContact)

    def __del__(self):
        if self._native is not None and _native is not None:
            _native.release_set(self._mbs_address, self.oContact, self._native.args.address)

    def force(self, mbs, t, itemNumber, q, q_t):
        """Generalized contact forces at the given q, q_t (the set's coordinates, any values: for
        direct calls, e.g. finite differences); Exudyn calls force_in_place."""
        if t != self._t:
            self._load_history(mbs, t)
        self._qb[:] = q
        self._q_tb[:] = q_t
        self._entry(0, self._qb, self._q_tb, 0.0, 0.0, self._dt, self._h0, *self._tail)
        return self.pk.Q

    def jacobian(self, mbs, t, itemNumber, q, q_t, fODE2, fODE2_t):
        """As force: the Jacobian at the given q, q_t; Exudyn calls jacobian_in_place."""
        if t != self._t:
            self._load_history(mbs, t)
        self._qb[:] = q
        self._q_tb[:] = q_t
        self._entry(1, self._qb, self._q_tb, fODE2, fODE2_t, self._dt, self._h0, *self._tail)
        return self.pk.J

    def force_in_place(self, mbs, t, itemNumber, q, q_t):
        """The force user function given to Exudyn: the lists q, q_t Exudyn passes are its Current
        coordinates at the object's indices, read here from the views instead (a slice, or gathered
        when the indices are not one range; tests/test_history_in_place.py checks they are equal)."""
        self.force_calls += 1
        if t != self._t:
            self._load_history(mbs, t)
        if self._gathered:
            self._gather(*self._gather_args)
        self._entry(*self._force_args)
        return self.pk.Q

    def jacobian_in_place(self, mbs, t, itemNumber, q, q_t, fODE2, fODE2_t):
        """The Jacobian user function given to Exudyn (q, q_t as in force_in_place)."""
        if t != self._t:
            self._load_history(mbs, t)
        if self._gathered:
            self._gather(*self._gather_args)
        self._entry(1, self._q, self._q_t, fODE2, fODE2_t, self._dt, self._h0, *self._tail)
        return self.pk.J

    def stage(self, mbs, t):
        if t != self._t:
            self._load_history(mbs, t)
        if self._gathered:                    # the object's coordinates are not one range
            self._gather(*self._gather_args)
        q, q_t = self._q, self._q_t
        code = self._stage(*self._stage_args)
        if code == 1:                         # the last residual was not at the converged state
            self.recomputed += 1
            self._entry(2, q, q_t, 0.0, 0.0, self._dt, self._h0, *self._tail)
            self.pk.X[0] = q                  # the candidate now belongs to this state
            self.pk.X[1] = q_t
            code = self._stage(*self._stage_args)
        if code == 0:
            self._committed_t = t
            # the next call reloads (and checks the views), even at this time: a solve that
            # continues from here may follow a re-assembly
            self._t = None
        return code == 0


def _commit(mbs, t, sets):
    """Write the history candidates of the contact sets at the converged state of time t into the
    Current data coordinates (in place, through views of Exudyn's vector). Returns False when a
    set's step is unresolved; sets staged before it have written into Current, which Exudyn
    restores from StartOfStep when it rejects the step."""
    for cs in sets:
        if not cs.stage(mbs, t):
            return False
    return True


class _CompiledPairSet(_CompiledSet):
    """A contact set with a moving master (the surface on a 3D rigid body) on the compiled kernel
    ``kernel.sets.evaluate_pair`` (``kernel.CovariantPairSet``): the slave's and the master's
    coordinates (the contact object's) in one compiled call, with the consistent Jacobian over both
    (so ``jacobian="analytic"`` applies). Its coordinates are two ranges of Exudyn's ODE2 vector,
    gathered from the views at every call (``gather_coordinates``). Everything else as _CompiledSet."""

    @staticmethod
    def _pack(law, kind, slave, points, master):
        from exu_aniso.kernel.point import CovariantPairSet
        return CovariantPairSet(law, kind, slave.ref, points, master.kind, master.ref)


class _CompiledGroupSet(_CompiledSet):
    """A group (_RigidGroup: the same points on several rigid bodies) on the compiled kernel
    ``kernel.sets.evaluate_group`` (``kernel.CovariantGroupSet``): one compiled call for all bodies;
    the Jacobian goes to Exudyn as a sparse matrix of the bodies' diagonal blocks."""

    @staticmethod
    def _pack(law, kind, slave, points, master):
        from exu_aniso.kernel.point import CovariantGroupSet
        return CovariantGroupSet(law, kind, slave.ref, points, len(slave.bodies))


def _body_node(mbs, bodyNumber):
    """Node of a body object: 'nodeNumber' of a rigid body, the single node of an ObjectGenericODE2."""
    obj = mbs.GetObject(bodyNumber)
    if "nodeNumber" in obj:
        return obj["nodeNumber"]
    nodes = list(obj.get("nodeNumbers", []))
    if len(nodes) != 1:
        raise ValueError(f"CreateAnisotropicContact: body {bodyNumber} ({obj.get('objectType')}) must have exactly one "
                         f"node; got nodeNumbers={nodes}")
    return nodes[0]


def _slave_kinematics(mbs, bodyNumber, nObjects, localPoints=None):
    """The slave kinematics of bodyNumber: one body, a list of ANCF cable elements (one set), a
    list of rigid bodies of one node type (a group, _RigidGroup) or a linear FE body (its nodes
    chosen by localPoints, _MeshNodes)."""
    many = isinstance(bodyNumber, (list, tuple, np.ndarray))
    objects = list(bodyNumber) if many else [bodyNumber]
    if many and not objects:
        raise ValueError("CreateAnisotropicContact: bodyNumber is an empty list; give a body or a list of ANCF cable "
                         "elements")
    for i, o in enumerate(objects):
        check_index(f"bodyNumber[{i}]" if many else "bodyNumber", o, nObjects, "object")
    types = [mbs.GetObject(o)["objectType"] for o in objects]
    cables = [t in _CABLES for t in types]
    rigid = [t in _RIGID_BODIES for t in types]
    if many and all(rigid):
        if len(set(int(o) for o in objects)) < len(objects):
            raise ValueError(f"CreateAnisotropicContact: bodyNumber lists a body more than once; got {objects}")
        group = _RigidGroup(mbs, objects)
        kinds = [bd.kind for bd in group.bodies]
        if len(set(kinds)) > 1:
            raise ValueError(f"CreateAnisotropicContact: the rigid bodies of a list in bodyNumber must have nodes of "
                             f"one type; got {sorted(set(kinds))}")
        return group
    if many and not all(cables):
        bad = [f"bodyNumber[{i}] = {o} is Object{t}" for i, (o, t, c) in enumerate(zip(objects, types, cables))
               if not c]
        raise ValueError("CreateAnisotropicContact: a list in bodyNumber must hold either ANCF cable elements "
                         "(ObjectANCFCable2D or ObjectANCFCable, all of one type) or rigid bodies (ObjectRigidBody, "
                         "ObjectRigidBody2D, all of one node type); " + "; ".join(bad))
    if many and len(set(types)) > 1:
        raise ValueError(f"CreateAnisotropicContact: the cable elements in bodyNumber must be all ObjectANCFCable2D or "
                         f"all ObjectANCFCable; got {sorted(set(types))}")
    if many and len(set(int(o) for o in objects)) < len(objects):
        raise ValueError(f"CreateAnisotropicContact: bodyNumber lists a cable element more than once; got {objects}")
    if cables[0] or types[0] in _MASS_POINTS:
        return _LinearSlave(mbs, objects)
    if not many and _is_mesh_body(mbs, mbs.GetObject(bodyNumber)):
        return _MeshNodes(mbs, bodyNumber, localPoints)
    if not many and types[0] == "FFRFreducedOrder":
        return _FloatingFrame(mbs, bodyNumber, localPoints)
    return _BodyKinematics(mbs, _body_node(mbs, bodyNumber))


def _check_cable_points(slave, points):
    """localPoints of a cable: [x, 0, 0] with 0 <= x <= the length of every listed element."""
    if slave.kind in ("Point", "Point2D") or not slave.linear:
        return
    Lmin = min(slave.lengths)
    for k, b in enumerate(points):
        if b[1] != 0.0 or b[2] != 0.0:
            raise ValueError(f"CreateAnisotropicContact: localPoints of ANCF cable elements are [x, 0, 0] (a point on "
                             f"the cable's axis); got localPoints[{k}] = {b.tolist()}")
        if not 0.0 <= b[0] <= Lmin:
            raise ValueError(f"CreateAnisotropicContact: localPoints x of an ANCF cable element must lie in [0, L] "
                             f"with L = {Lmin:g} m (the shortest element listed in bodyNumber); got localPoints[{k}] "
                             f"= {b.tolist()}")


# Step reduction asked for when a contact point's motion in a step is unresolved (see
# ContactLaw.evaluate): the step is repeated with this fraction of its size.
UNRESOLVED_STEP_FACTOR = 0.25


def contact_force_calls(mbs):
    """How many times Exudyn called the force user functions of this system's contact sets so far.
    Exudyn allocates 2 vectors per call of an ObjectGenericODE2 force function (its own copies of the
    returned force), which its solver's allocation check counts (exu_aniso.engines.exudyn_adapter.runner.SolveTimed)."""
    sets = mbs.variables.get(_SETS_KEY, ())
    return sum(cs.force_calls + (cs.native_calls()[0] if isinstance(cs, _CompiledSet) else 0) for cs in sets)


def _post_newton(mbs, t):
    """Commit every contact set's history candidate; if any set saw an unresolved step, reject the
    step and ask Exudyn to repeat it with a quarter of the step size (Exudyn restores Current
    from StartOfStep, so sets already written leave no trace)."""
    sets = mbs.variables[_SETS_KEY]
    if not _commit(mbs, t, sets):
        h = t - mbs.systemData.GetTime(_SOS)
        mbs.variables[_UNRESOLVED_KEY] = t
        return [1.0, UNRESOLVED_STEP_FACTOR * h]
    for cs in sets:
        if cs._native is not None:
            cs.step_done(t)
    return [0.0, -1.0]


def disarm_native(mbs):
    """Every native set of mbs calls Python first at its next call (``_CompiledSet.disarm``): before
    and after a solve whose start the sets cannot see."""
    for cs in mbs.variables.get(_SETS_KEY, ()):
        if isinstance(cs, _CompiledSet):
            cs.disarm()


def post_newton_calls(mbs):
    """(native, Python) calls of the native post-Newton function of mbs so far."""
    return _native.post_newton_calls(_native.system_address(mbs)) if _native is not None else (0, 0)


def _alive(ref, what):
    obj = ref()
    if obj is None:
        raise RuntimeError(f"exu_aniso: {what} was deleted while Exudyn still calls its user functions; keep a "
                           "reference to mbs while solving")
    return obj


class _PostNewtonFallback:
    """What the native post-Newton function calls in Python: _post_newton of the system, held weakly."""

    def __init__(self, mbs):
        self.mbs = weakref.ref(mbs)

    def __call__(self, t):
        return _post_newton(_alive(self.mbs, "the exudyn.MainSystem of a contact set"), t)


class _Delegate:
    """What the native callback calls in Python: the set's native_delegate, by weak references (the
    C++ registry must not keep a system alive)."""

    def __init__(self, cs, mbs):
        self.cs, self.mbs = weakref.ref(cs), weakref.ref(mbs)

    def __call__(self, t, q, q_t):
        _alive(self.cs, "a contact set").native_delegate(_alive(self.mbs, "the exudyn.MainSystem of a contact set"), t)

    def jacobian(self, t, q, q_t, fODE2, fODE2_t):
        return _alive(self.cs, "a contact set").jacobian_in_place(
            _alive(self.mbs, "the exudyn.MainSystem of a contact set"), t, None, q, q_t, fODE2, fODE2_t)


def CreateAnisotropicContact(mbs, bodyNumber, localPoints, surface=None, adhesion=None, friction=None,
                             normalStiffness=None, normalDamping=None, returnMap=DEFAULT_RETURN_MAP, contactLaw=None,
                             masterBodyNumber=None, jacobian="analytic", initializeHistory=True, storeSensors=True,
                             implementation="auto", tangentialDamping=None, storeHistory=False,
                             nativeCallbacks=None):
    """Add anisotropic frictional contact between body-fixed points and an analytical surface.

    bodyNumber: slave body (ObjectRigidBody, ObjectRigidBody2D for a planar model, ObjectMassPoint or
    ObjectMassPoint2D), or an ANCF cable: one ObjectANCFCable2D / ObjectANCFCable element or a list of
    them (one contact set over all their distinct nodes, e.g. a whole rope), or a list of rigid
    bodies with nodes of one type (a group: one contact set over all of them with localPoints on
    each, one ObjectGenericODE2, one compiled call per user function, the Jacobian as the bodies'
    diagonal blocks in a sparse matrix; a fixed surface only; history rows body by body), or a full
    linear finite-element body (an ObjectGenericODE2 of NodePoint nodes, _MeshNodes: its mesh nodes
    are the points, given in localPoints as mesh node indices or reference positions; the result's
    'meshNodes' lists them); localPoints: (K, 3)
    body-local contact points [m]; for cables element-local points [x, 0, 0] with 0 <= x <= element
    length, applied to every element of the list (points ordered element by element: K = elements x
    points; x = Exudyn's Hermite shape functions, linear in the node coordinates, so the analytic
    Jacobian has no geometric terms); surface: a surface of
    exu_aniso (Plane, Cylinder, Cone, Sphere, Torus, Helicoid, SurfaceOfRevolution, ParametricSurface) in the
    master frame; adhesion / friction: exu_aniso Adhesion / Friction fields; normalStiffness
    eps_N [N/m per point]; normalDamping d_N [N s/m per point, default 0]; tangentialDamping d_T
    [N s/m per point, default 0: a dashpot -d_T v_t parallel to friction while loaded];
    returnMap "seed" | "exact" | "radial"; or contactLaw: a ready ContactLaw instead of these
    seven arguments (giving both is an error).
    masterBodyNumber: None (surface fixed to ground) or a 3D rigid body (RotVecLG or EP node)
    carrying the surface (equal and opposite force on it at the material point coinciding with each
    slave point).
    jacobian: "analytic" (consistent tangent; with a moving master over the slave's and the master's
    coordinates, on the compiled route only: the numpy route then uses Exudyn's) or "numerical"
    (Exudyn's).
    storeSensors: True -> a sensor of the set's total dissipated energy (one number per step);
    storeHistory: True -> also a sensor of the whole history (9 numbers per point and step: memory
    grows with points x steps, so it is off unless asked for; the history itself is always in the
    data node 'nData', for the renderer, the solution file and 'historyAt').
    initializeHistory: True -> points already in contact at the initial configuration start
    sticking there (anchor = initial contact point, T = 0), as in the reference engine; False ->
    they start as a new contact in the first step.
    Slave node types: NodeRigidBody2D, NodeRigidBodyRotVecLG, NodeRigidBodyEP, NodePoint, NodePoint2D,
    NodePoint2DSlope1 / NodePointSlope1 (cables), or a NodeGenericODE2 with 2 coordinates (psi about
    z [rad], z [m]) for a reduced screw-joint model.
    implementation: "compiled" (the numba kernel of exu_aniso.kernel.sets: one compiled call per user
    function; a surface and fields numba compiles; ground or moving master), "numpy"
    (ContactLaw.evaluate with numpy; any configuration) or "auto" (compiled where it applies, numpy
    otherwise). Both give the same results to round-off (tests/test_fastpath.py,
    tests/test_moving_master_compiled.py).
    nativeCallbacks: None (default: where the compiled kernel is used and the native extension is
    built), True (required: an error otherwise) or False: Exudyn calls the compiled kernel through a
    C++ force function (``_native.cpp``) without entering Python, instead of through a Python user
    function; the same compiled call on the same arguments, so the same numbers bit for bit
    (tests/test_native_callbacks.py). When every set of the system is native, the post-Newton commit
    is native too (``_native.post_newton``: the compiled stage kernel; Python for an unresolved step).
    The Jacobian stays in Python.

    Returns a dict with 'oContact' (ObjectGenericODE2), 'nDissipation' (NodeGenericData with the set's
    total dissipated energy [J], written with the history), 'nData' (NodeGenericData, the history:
    9 numbers per point, see HISTORY_FIELDS), 'sHistory' (sensor of the history, with storeHistory),
    'sDissipation' (sensor of the total dissipated energy [J], with storeSensors), 'law', 'points', 'implementation' (the one used),
    'jacobian' (as given) and 'nativeCallbacks' (True when Exudyn calls the native force),
    and for graphics and post-processing: 'bodyNumber', 'masterBodyNumber' (as given), and three
    read-only functions of (mbs, configuration=None) (an exu.ConfigurationType; None: the initial
    coordinates, usable before Assemble): 'pointsAndMasterPose' -> (slave points in the master frame
    (K, 3), master position (3,), master rotation (3, 3)), 'historyAt' -> history (K, 9) and
    'bodyPosition' -> global position (3,) of the slave body's local origin (a cable: the start of
    its first element); and 'generalizedForce', a function (q, q_t, history) -> the contact object's
    generalized force over its coordinates (reference values excluded; the slave's, then the
    master's) from a converged history (K, 9), as the solver evaluates it (post-processing of
    stored states: contact torques, reaction forces); samples at once: q, q_t (n, nq) and history
    (n, K, 9) give (n, nq).
    """
    if contactLaw is None:
        if normalStiffness is None:
            raise ValueError("CreateAnisotropicContact: give normalStiffness (with surface, adhesion, friction) "
                             "or a ready contactLaw")
        try:
            contactLaw = ContactLaw(surface, adhesion, friction, normalStiffness,
                                    0.0 if normalDamping is None else normalDamping, returnMap,
                                    tangential_damping=0.0 if tangentialDamping is None else tangentialDamping)
        except (TypeError, ValueError) as e:   # name the arguments as this function spells them
            raise type(e)("CreateAnisotropicContact: " + str(e).replace("normal_stiffness", "normalStiffness").replace(
                "normal_damping", "normalDamping").replace("tangential_damping", "tangentialDamping").replace(
                "return_map", "returnMap")) from None
    elif any(a is not None for a in (surface, adhesion, friction, normalStiffness, normalDamping, tangentialDamping)):
        raise ValueError("CreateAnisotropicContact: contactLaw replaces surface/adhesion/friction/normalStiffness/"
                         "normalDamping/tangentialDamping; give one or the other")
    check_instance("mbs", mbs, exu.MainSystem, "MainSystem of Exudyn (SC.AddSystem())")
    check_instance("contactLaw", contactLaw, ContactLaw)
    nObjects = mbs.systemData.NumberOfObjects()
    slave = _slave_kinematics(mbs, bodyNumber, nObjects, localPoints)
    if masterBodyNumber is not None and check_index("masterBodyNumber", masterBodyNumber, nObjects, "object") in (
            [int(o) for o in (bodyNumber if isinstance(bodyNumber, (list, tuple, np.ndarray)) else [bodyNumber])]):
        raise ValueError(f"CreateAnisotropicContact: masterBodyNumber must differ from bodyNumber; got both "
                         f"{masterBodyNumber}")
    check_bool("initializeHistory", initializeHistory)
    check_bool("storeSensors", storeSensors)
    check_bool("storeHistory", storeHistory)
    if jacobian not in ("analytic", "numerical"):
        raise ValueError(f"CreateAnisotropicContact: jacobian must be 'analytic' or 'numerical'; got {jacobian!r}")
    if isinstance(slave, (_MeshNodes, _FloatingFrame)):      # every point is a mesh node: no offset from it
        points = np.zeros((len(slave.mesh_indices), 3))
    else:
        points = check_points("localPoints", localPoints)
        _, inverse, counts = np.unique(points, axis=0, return_inverse=True, return_counts=True)
        if (counts > 1).any():
            rows = np.flatnonzero(counts[np.ravel(inverse)] > 1)
            raise ValueError(f"CreateAnisotropicContact: localPoints lists a point more than once (rows "
                             f"{rows[:6].tolist()}: {points[rows[0]].tolist()}); each row is one contact point, so "
                             f"give each once (its stiffness is the contact law's per point)")
    _check_cable_points(slave, points)
    master = None
    if masterBodyNumber is not None:
        master = _BodyKinematics(mbs, _body_node(mbs, masterBodyNumber))
        if master.kind not in ("RigidBodyRotVecLG", "RigidBodyEP"):
            raise ValueError("CreateAnisotropicContact: masterBodyNumber must be a 3D rigid body (RotVecLG or EP node)")
    if implementation not in ("auto", "compiled", "numpy"):
        raise ValueError("CreateAnisotropicContact: implementation must be 'auto', 'compiled' or 'numpy'; "
                         f"got {implementation!r}")
    floating = isinstance(slave, _FloatingFrame)   # its kinematics in numpy, the law compiled (_CompiledPointLaw)
    compiled_ok = contactLaw.compiled and not (floating and master is not None)
    if implementation == "compiled" and not compiled_ok:
        raise ValueError("CreateAnisotropicContact: implementation='compiled' needs a surface and fields numba can "
                         "compile, and has no route for an ObjectFFRFreducedOrder slave on a moving master; use "
                         "'numpy' or 'auto'")
    use_compiled = compiled_ok and implementation != "numpy" and not floating
    if nativeCallbacks not in (None, True, False):
        raise ValueError(f"CreateAnisotropicContact: nativeCallbacks must be None, True or False; got {nativeCallbacks!r}")
    if nativeCallbacks and not use_compiled:
        raise ValueError("CreateAnisotropicContact: nativeCallbacks=True needs the compiled kernel (implementation "
                         "'auto' or 'compiled' with a surface and fields numba compiles; an ObjectFFRFreducedOrder "
                         "slave has no native callback)")
    if nativeCallbacks and _native is None:
        raise ValueError("CreateAnisotropicContact: nativeCallbacks=True, but the native extension "
                         "exu_aniso.engines.exudyn_adapter._native is not built (pip install builds it with a C++ "
                         "compiler)")
    use_native = use_compiled and _native is not None and nativeCallbacks is not False
    if isinstance(slave, _RigidGroup) and master is not None:
        raise ValueError("CreateAnisotropicContact: a list of rigid bodies in bodyNumber (a group) needs a fixed "
                         "surface (masterBodyNumber None); give each body its own contact set on a moving master")
    if use_compiled and isinstance(slave, _RigidGroup):
        cls = _CompiledGroupSet
    else:
        cls = _ContactSet if not use_compiled else (_CompiledSet if master is None else _CompiledPairSet)
    cs = cls(mbs, contactLaw, slave, points, master)
    K = cs.K
    if floating and compiled_ok and implementation != "numpy":
        cs.point_law = _CompiledPointLaw(contactLaw, K)
    h0 = np.zeros(K * N_HISTORY)
    if initializeHistory:   # points in contact at t = 0 start sticking at their initial contact point
        nodes = [slave] + ([master] if master is not None else [])
        h0 = cs.initial_history(np.concatenate([nd.q0 for nd in nodes]), np.concatenate([nd.v0 for nd in nodes]))
    cs.nData = mbs.AddNode(NodeGenericData(initialCoordinates=h0.tolist(), numberOfDataCoordinates=K * N_HISTORY))
    # the set's total dissipated energy, written with the history: a C++ sensor reads it (no Python per step)
    cs.nTotal = mbs.AddNode(NodeGenericData(initialCoordinates=[float(h0[_DISSIPATED::N_HISTORY].sum())],
                                            numberOfDataCoordinates=1))
    nodes = slave.nodes + (master.nodes if master is not None else [])
    kw = {}
    if jacobian == "analytic" and (master is None or use_compiled):   # numpy route, moving master: Exudyn's
        kw["jacobianUserFunction"] = cs.jacobian_in_place if use_compiled else cs.jacobian
    # no mass matrix (the bodies have theirs): a dense zero n x n one would put (n)^2 zeros into a group's
    # sparse system matrix
    oContact = mbs.AddObject(ObjectGenericODE2(nodeNumbers=nodes, forceUserFunction=cs.force_in_place
                                               if use_compiled else cs.force, **kw))
    cs.locate(mbs, oContact)
    if use_native:
        mbs.SetObjectParameter(oContact, "forceUserFunction", cs.use_native(mbs))
        if "jacobianUserFunction" in kw:
            mbs.SetObjectParameter(oContact, "jacobianUserFunction", _native.jacobian)
    first = _SETS_KEY not in mbs.variables
    sets = mbs.variables.setdefault(_SETS_KEY, [])
    sets.append(cs)
    current = None if first else mbs.GetPostNewtonUserFunction()
    current = current.get("function") if isinstance(current, dict) else current    # Exudyn's record of it
    if first or current is _post_newton or (_native is not None and current is _native.post_newton):
        if all(s._native is not None for s in sets):       # the commit without Python too (_native.cpp)
            _native.register_system(mbs, _PostNewtonFallback(mbs))
            mbs.SetPostNewtonUserFunction(_native.post_newton)
        else:
            mbs.SetPostNewtonUserFunction(_post_newton)
    out = {"oContact": oContact, "nData": cs.nData, "nDissipation": cs.nTotal, "law": contactLaw, "points": points,
           "implementation": "compiled" if use_compiled or cs.point_law is not None else "numpy", "nativeCallbacks": use_native,
           "jacobian": jacobian,
           # read-only views (exu_aniso.engines.exudyn_adapter.graphics); functions of (mbs, configuration=None), see _ContactSet
           "bodyNumber": bodyNumber, "masterBodyNumber": masterBodyNumber,
           "pointsAndMasterPose": cs.points_and_master_pose, "historyAt": cs.history_at,
           "bodyPosition": cs.body_position, "generalizedForce": cs.generalized_force}
    if isinstance(slave, (_MeshNodes, _FloatingFrame)):
        out["meshNodes"] = list(slave.mesh_indices)
    if storeHistory:     # 9 numbers per point and step: only when asked for
        out["sHistory"] = mbs.AddSensor(SensorNode(nodeNumber=cs.nData,
                                                   outputVariableType=exu.OutputVariableType.Coordinates,
                                                   storeInternal=True))
    if storeSensors:
        out["sDissipation"] = mbs.AddSensor(SensorNode(nodeNumber=cs.nTotal,
                                                       outputVariableType=exu.OutputVariableType.Coordinates,
                                                       storeInternal=True))
    return out


def HistoryComponent(point, field):
    """Sensor component index of `field` (a HISTORY_FIELDS name) of contact point `point` in the
    'sHistory' sensor, e.g. mbs.PlotSensor(sHistory, components=HistoryComponent(0, 'traction_1'))."""
    if field not in HISTORY_FIELDS:
        raise ValueError(f"field must be one of {HISTORY_FIELDS}; got {field!r}")
    return int(point) * N_HISTORY + HISTORY_FIELDS.index(field)
