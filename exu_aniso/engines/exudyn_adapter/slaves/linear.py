"""Linear slaves: points linear in the node coordinates, x = c + S q with a constant point Jacobian S:
mass points, ANCF cables (Exudyn's Hermite shape functions) and the nodes of a full linear
finite-element body (MeshNodes)."""
from __future__ import annotations

import numpy as np

from exu_aniso.engines.exudyn_adapter.slaves.base import Slave
from exu_aniso.fe.mesh import node_index
from exu_aniso.util.validation import check_points


def hermite_shape_functions(x, L):
    """Exudyn's cubic Hermite shape functions of an ANCF cable element of length L at the local
    position x in [0, L]: r(x) = S1 r0 + S2 r0' + S3 r1 + S4 r1' (node 0 at x = 0, node 1 at x = L;
    r' the slope coordinates; tests/test_cable.py checks them against Exudyn's output)."""
    xi = x / L
    return np.array([1.0 - 3.0 * xi ** 2 + 2.0 * xi ** 3, L * (xi - 2.0 * xi ** 2 + xi ** 3),
                     3.0 * xi ** 2 - 2.0 * xi ** 3, L * (-xi ** 2 + xi ** 3)])


CABLES = {"ANCFCable2D": ("Point2DSlope1", 2), "ANCFCable": ("PointSlope1", 3)}   # object: (node type, dim)
MASS_POINTS = {"MassPoint": ("Point", 3), "MassPoint2D": ("Point2D", 2)}


class LinearSlave(Slave):
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
        if self.kind in MASS_POINTS:
            node_type, self.dim = MASS_POINTS[self.kind]
            self.elements = [[int(mbs.GetObject(objects[0])["nodeNumber"])]]
            self.lengths = [0.0]
            self.kind = node_type                       # the node type, as the rigid kinds
        else:
            node_type, self.dim = CABLES[self.kind]
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

    def check_points(self, points):
        """As Slave.check_points; on cables also: [x, 0, 0] with 0 <= x <= the length of every listed
        element."""
        super().check_points(points)
        if self.kind not in CABLES:
            return
        Lmin = min(self.lengths)
        for k, b in enumerate(points):
            if b[1] != 0.0 or b[2] != 0.0:
                raise ValueError(f"CreateAnisotropicContact: localPoints of ANCF cable elements are [x, 0, 0] (a point "
                                 f"on the cable's axis); got localPoints[{k}] = {b.tolist()}")
            if not 0.0 <= b[0] <= Lmin:
                raise ValueError(f"CreateAnisotropicContact: localPoints x of an ANCF cable element must lie in [0, L] "
                                 f"with L = {Lmin:g} m (the shortest element listed in bodyNumber); got "
                                 f"localPoints[{k}] = {b.tolist()}")

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


class MeshNodes(LinearSlave):
    """The surface nodes of a full linear finite-element body (an ObjectGenericODE2 of NodePoint
    nodes, e.g. ``exu_aniso.engines.exudyn_adapter.fem.AddLinearFEBody`` or Exudyn's
    ``FEMinterface.CreateLinearFEMObjectGenericODE2``) as contact points: point k is mesh node j_k,
    x_k = q_total of that node (S = I, c = 0), a linear slave like a mass point. The set's
    coordinates are those of the listed nodes only (the contact object connects to them alone).

    localPoints: mesh node indices (positions in the object's nodeNumbers, as the mesh numbers them)
    or (K, 3) reference positions of mesh nodes [m] (each must be a node's, to 1e-9 of the body's
    size)."""

    points_are_nodes = True

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
        return resolve_points(R, localPoints, "their reference positions")


    def number_of_points(self, b):
        return len(self.nodes)

    def linear_map(self, b):
        """idx (K, 3) = the node's three set coordinates, S = I, c = 0 (b: (K, 3) zeros)."""
        K = len(self.nodes)
        idx = 3 * np.arange(K, dtype=np.int64)[:, None] + np.arange(3, dtype=np.int64)
        return idx, np.broadcast_to(np.eye(3), (K, 3, 3)).copy(), np.zeros((K, 3))



def is_mesh_body(mbs, obj):
    """An ObjectGenericODE2 of NodePoint nodes only (a linear FE body), not the 2-coordinate screw joint."""
    if obj["objectType"] != "GenericODE2":
        return False
    return all(mbs.GetNode(nd)["nodeType"] == "Point" for nd in obj["nodeNumbers"])



def resolve_points(R, localPoints, positions):
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
        ids = []
        for k, x in enumerate(X):
            try:
                ids.append(node_index(R, x))
            except ValueError as e:
                raise ValueError(f"CreateAnisotropicContact: localPoints[{k}] = {x.tolist()} is not a node of the "
                                 f"finite-element body ({e}): give mesh node indices or {positions}") from None
    if len(set(ids)) < len(ids):
        raise ValueError(f"CreateAnisotropicContact: localPoints lists a mesh node more than once; got {ids}")
    return ids
