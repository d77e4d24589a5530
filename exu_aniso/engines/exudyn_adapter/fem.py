"""Linear finite-element bodies in an Exudyn model: an ``exu_aniso.fe.ElasticMesh`` handed to Exudyn's
``exudyn.FEM.FEMinterface`` and added as one ``ObjectGenericODE2`` of ``NodePoint`` nodes (the full
linear FE body: M u'' + D u' + K u = f, small deformations).

``FEMinterfaceOf(mesh)`` fills the interface (nodes, Hex8 elements in Exudyn's node order, the
matrices, the boundary triangles for drawing), so Exudyn's own tools (eigenmodes, Craig-Bampton
modes, node searches, ``ObjectFFRFreducedOrder``) work on it. ``AddLinearFEBody`` adds the full body
and gives it a Jacobian function: without one Exudyn differentiates the object numerically, one
force evaluation per coordinate; with one that adds nothing, Exudyn assembles the object's K and D
into the system Jacobian itself (its ObjectGenericODE2 adds mass, damping and stiffness matrices to
the user function's part). Measured on the fe_block scene's defaults over 0.3 s (192 coordinates,
300 steps, 61 Jacobians; the jacobianUserFunction set back to 0 for the comparison): 0.41 s of
CPU against 1.19 s, the same steps and Newton iterations.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
import exudyn as exu
from exudyn.FEM import FEMinterface
from exudyn.itemInterface import NodePoint, ObjectGenericODE2, VObjectGenericODE2
from exudyn.rigidBodyUtilities import EulerParameters2GLocal, EulerParameters2RotationMatrix

from exu_aniso.util.validation import check_nonnegative, check_vector

# scikit-fem's hexahedron (corners (000), (010), (100), (001), (110), (011), (101), (111) in the
# element's unit cube) -> Exudyn's Hex8 / Abaqus C3D8: bottom face (000), (100), (110), (010), then
# the top face in the same order
_HEX8_FROM_SKFEM = (0, 2, 4, 1, 3, 6, 7, 5)


def FEMinterfaceOf(mesh):
    """An exudyn.FEM.FEMinterface of an ElasticMesh (module docstring); its node sets as nodeSets."""
    fem = FEMinterface()
    fem.nodes = {"Position": np.asarray(mesh.nodes, dtype=float)}
    fem.elements = [{"Name": "body", "Hex8": np.asarray(mesh.hexahedra)[:, _HEX8_FROM_SKFEM]}]
    fem.massMatrix = mesh.mass
    fem.stiffnessMatrix = mesh.stiffness
    fem.surface = [{"Name": "boundary", "Trigs": np.asarray(mesh.triangles)}]
    fem.nodeSets = [{"Name": name, "NodeNumbers": np.asarray(ids), "NodeWeights": np.full(len(ids), 1.0 / len(ids))}
                    for name, ids in mesh.node_sets.items()]
    fem.metaData = {"source": "exu_aniso.fe (scikit-fem)"}
    return fem


def _no_user_jacobian(mbs, t, itemNumber, q, q_t, fODE2, fODE2_t):
    """The object's Jacobian beyond its own matrices: none (Exudyn adds fODE2 K + fODE2_t D)."""
    return _EMPTY


_EMPTY = exu.MatrixContainer()
_EMPTY.SetWithSparseMatrix(np.zeros((0, 3)), 0, 0, useDenseMatrix=False)


def AddLinearFEBody(mbs, mesh, position=(0.0, 0.0, 0.0), stiffnessDamping=0.0, color=(0.55, 0.65, 0.8, 1.0)):
    """Add the full linear FE body of ``mesh`` to mbs: one NodePoint per mesh node (at the mesh's
    reference position + position [m]), one ObjectGenericODE2 with the mass matrix, the stiffness
    matrix and the damping matrix stiffnessDamping * K (stiffness-proportional Rayleigh damping
    [s], >= 0), drawn as the boundary triangles. Returns dict oBody, nodes (the node numbers in mesh
    order), fem (the FEMinterface)."""
    position = np.asarray(check_vector("position", position, 3), dtype=float)
    beta = check_nonnegative("stiffnessDamping", stiffnessDamping)
    fem = FEMinterfaceOf(mesh)
    nodes = [mbs.AddNode(NodePoint(referenceCoordinates=(x + position).tolist())) for x in mesh.nodes]
    n = mesh.number_of_coordinates

    def container(matrix):
        c = exu.MatrixContainer()
        c.SetWithSparseMatrix(matrix.tocsr(), n, n, useDenseMatrix=False)
        return c

    kw = dict(dampingMatrix=container(beta * mesh.stiffness)) if beta > 0.0 else {}
    oBody = mbs.AddObject(ObjectGenericODE2(nodeNumbers=nodes, massMatrix=container(mesh.mass),
                                            stiffnessMatrix=container(mesh.stiffness),
                                            jacobianUserFunction=_no_user_jacobian,
                                            visualization=VObjectGenericODE2(triangleMesh=mesh.triangles.tolist(),
                                                                             color=list(color)), **kw))
    return dict(oBody=oBody, nodes=nodes, fem=fem)


class FrameMotion(NamedTuple):
    """FloatingFrameMotion's samples: every mesh node's global position X and velocity V (n, N, 3),
    its displacement in the body frame U = Psi eta (n, N, 3) [m], the frame's rotation matrices
    (n, 3, 3) and global angular velocity omega (n, 3) [rad/s], the body's kinetic energy 0.5 v.M v
    and strain energy 0.5 eta.K_r eta (n,) [J], and the modal stiffness K_r = Psi^T K Psi (m, m)."""
    X: np.ndarray
    V: np.ndarray
    U: np.ndarray
    rotation: np.ndarray
    omega: np.ndarray
    kinetic: np.ndarray
    strain: np.ndarray
    modal_stiffness: np.ndarray


def FloatingFrameMotion(mesh, basis, rigid, rigid_t, modal, modal_t):
    """The motion of an ObjectFFRFreducedOrder (Euler-parameter frame) over n samples, as a
    FrameMotion. rigid, rigid_t (n, 7): the frame node's coordinates with their reference values and
    its velocities; modal, modal_t (n, m); basis Psi (3N, m): x_k = p + A (r_k + Psi_k eta),
    v_k = p' + A (omega_local x (r_k + Psi_k eta) + Psi_k eta')."""
    n = len(rigid)
    X, V = np.empty((n, mesh.number_of_nodes, 3)), np.empty((n, mesh.number_of_nodes, 3))
    U = (modal @ basis.T).reshape(n, -1, 3)
    A, omega = np.empty((n, 3, 3)), np.empty((n, 3))
    for i in range(n):
        e = rigid[i, 3:7]
        A[i] = EulerParameters2RotationMatrix(e)
        w_local = np.asarray(EulerParameters2GLocal(e)) @ rigid_t[i, 3:7]
        omega[i] = A[i] @ w_local
        b = mesh.nodes + U[i]
        X[i] = rigid[i, 0:3] + b @ A[i].T
        V[i] = rigid_t[i, 0:3] + (np.cross(w_local, b) + (basis @ modal_t[i]).reshape(-1, 3)) @ A[i].T
    Kr = basis.T @ (mesh.stiffness @ basis)
    return FrameMotion(X, V, U, A, omega, mesh.kinetic_energy(V.reshape(n, -1)),
                       0.5 * np.einsum("ni,ij,nj->n", modal, Kr, modal), Kr)
