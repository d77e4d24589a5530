"""How much of a contact's static compliance a mode basis can feel.

A reduced elastic body u = Psi eta answers a load f on its contact nodes with the Rayleigh-Ritz
displacement Psi (Psi^T K Psi)^-1 Psi^T f: the body stiffened to its basis. The static compliance of
the contact nodes' coordinates is then

    C_basis = P^T Psi (Psi^T K Psi)^-1 Psi^T P    against    C_full = P^T K^-1 P

(P: the unit loads on those coordinates, one column each). Rayleigh-Ritz makes C_basis <= C_full
(the difference is positive semi-definite: a basis only removes compliance), equal where the basis
spans K^-1 P (the static modes of those coordinates). ``compliance_share`` returns
trace(C_basis) / trace(C_full) in [0, 1]: the share of the contact nodes' flexibility, summed over
every coordinate under the contact, that the basis keeps. The trace is the sum of the compliances
under a unit load at each coordinate alone (no load pattern chosen: a contact can push on any of
them), a basis-independent number (both traces are invariant under Psi -> Psi A, A invertible), and
monotone in the basis (adding columns never lowers it). A penalty contact of stiffness eps per node
in series with the body feels the body's give through that compliance: a share well below 1 means
a body much stiffer under the contact than the mesh, and forces off by that much (the missing give
is the radial give of the fe_screw scene's shank, the local indentation of the fe_block scene's
block).

A body clamped at ``fixed_nodes``: K is the stiffness of the other coordinates, the basis must
vanish at the fixed nodes, contact coordinates at fixed nodes have no compliance and are left out.
A free body (``fixed_nodes`` None, a floating frame carrying the rigid motion): a load moves it as a
whole, so each unit load counts in its self-equilibrated part, balanced on the contact nodes
themselves (the unit loads projected off the rigid-body modes restricted to the contact
coordinates, least squares: P -> P (I - R_c R_c^+)); such a load does no work on rigid motion, the
compliance does not depend on the rigid part of a displacement, and the basis's own rigid-body
content is removed (in the mass metric, ``ElasticMesh.without_rigid_motion``'s choice) before it
is counted. C_full solves the saddle-point system [K, M R; R^T M, 0] (the displacements free of
rigid motion in the mass metric), one sparse factorization. The static modes of the contact nodes
with the rigid motion removed, as the fe_block scene's reduced body holds them, keep all of it.
"""
from __future__ import annotations

import numpy as np

class BasisWarning(UserWarning):
    """A reduced body's basis keeps too small a share of its contact's compliance (compliance_share)."""


RANK_TOLERANCE = 1e-10
"""Columns of a basis (each scaled to unit length) whose singular values fall below this share of
the largest are dependent: their span is counted once."""


def _coordinates(nodes):
    nodes = np.asarray(nodes, dtype=np.int64).ravel()
    return (3 * nodes[:, None] + np.arange(3)).ravel()


def _orthonormal(B, before=None):
    """An orthonormal basis (Euclidean) of the span of the columns of B, dependent columns dropped,
    and those that a projection left at round-off of their length ``before`` it."""
    norms = np.linalg.norm(B, axis=0)
    keep = norms > (0.0 if before is None else RANK_TOLERANCE * np.linalg.norm(before, axis=0))
    B = B[:, keep] / norms[keep]
    if B.shape[1] == 0:
        return B
    U, s, _ = np.linalg.svd(B, full_matrices=False)
    return U[:, s > RANK_TOLERANCE * s[0]]


def compliance_share(mesh, basis, contact_nodes, fixed_nodes=None):
    """trace(C_basis) / trace(C_full) of the contact nodes' coordinates (module docstring): the share
    of their static compliance that the mode basis (3N, m) keeps against the full mesh (an
    ElasticMesh), in [0, 1] (1: the basis holds every static response to loads on the contact nodes;
    for 1 x 8 x 4 cells of the fe_screw shank, its 12 lowest clamped eigenmodes keep a small part of
    it: docs/guide/scenes.md). contact_nodes: mesh node indices; fixed_nodes: the nodes where the body
    is clamped (the basis must vanish there), or None for a free body with the rigid-body motion
    removed in the mass metric. One sparse factorization of the full stiffness; numpy and scipy."""
    import scipy.sparse
    import scipy.sparse.linalg
    Psi = np.asarray(basis, dtype=float)
    n = mesh.number_of_coordinates
    if Psi.ndim != 2 or Psi.shape[0] != n:
        raise ValueError(f"basis must be a ({n}, m) array of nodal displacements (the mesh's {n} coordinates); "
                         f"got shape {Psi.shape}")
    contact = np.unique(np.asarray(contact_nodes, dtype=np.int64).ravel())
    if contact.size == 0 or contact.min() < 0 or contact.max() >= mesh.number_of_nodes:
        raise ValueError(f"contact_nodes must be some of the mesh's node indices 0 .. {mesh.number_of_nodes - 1}; "
                         f"got {np.asarray(contact_nodes).tolist()[:8]}")
    K = mesh.stiffness.tocsr()
    if fixed_nodes is not None:
        fixed = np.zeros(mesh.number_of_nodes, dtype=bool)
        fixed[np.asarray(fixed_nodes, dtype=np.int64)] = True
        if not fixed.any() or fixed.all():
            raise ValueError(f"fixed_nodes must hold some but not all of the {mesh.number_of_nodes} nodes "
                             "(None: a free body)")
        held = _coordinates(np.flatnonzero(fixed))
        if np.abs(Psi[held]).max(initial=0.0) > 1e-12 * np.abs(Psi).max(initial=0.0):
            raise ValueError("basis must vanish at fixed_nodes (a clamped body's modes hold those nodes)")
        free = _coordinates(np.flatnonzero(~fixed))
        contact = contact[~fixed[contact]]
        if contact.size == 0:
            raise ValueError("contact_nodes are all fixed: they have no compliance to share")
        Kf = K[free][:, free].tocsc()
        rows = np.searchsorted(free, _coordinates(contact))          # the contact coordinates among the free
        P = scipy.sparse.csc_matrix((np.ones(rows.size), (rows, np.arange(rows.size))), shape=(free.size, rows.size))
        X = scipy.sparse.linalg.splu(Kf).solve(P.toarray())
        full = float(np.trace(X[rows]))
        Q = _orthonormal(Psi[free])
        KQ = Kf @ Q
        PQ = Q[rows]
    else:
        R = mesh.rigid_body_modes()
        MR = mesh.mass @ R
        before, Psi = Psi, Psi - R @ np.linalg.solve(R.T @ MR, MR.T @ Psi)     # its rigid motion to the frame
        rows = _coordinates(contact)
        Rc = R[rows]
        E = np.eye(rows.size) - Rc @ np.linalg.pinv(Rc)              # unit loads balanced on the contact nodes
        A = scipy.sparse.bmat([[K, scipy.sparse.csr_matrix(MR)], [scipy.sparse.csr_matrix(MR.T), None]]).tocsc()
        F = np.zeros((n + 6, rows.size))
        F[rows] = E
        X = scipy.sparse.linalg.splu(A).solve(F)[:n]
        full = float(np.trace(E @ X[rows]))
        Q = _orthonormal(Psi, before)
        KQ = K @ Q
        PQ = E @ Q[rows]
    if Q.shape[1] == 0:
        return 0.0
    Kr = Q.T @ KQ
    L = np.linalg.cholesky(0.5 * (Kr + Kr.T))
    Y = np.linalg.solve(L, PQ.T)                    # trace(P^T Q Kr^-1 Q^T P) = |L^-1 Q^T P|^2
    return float(np.sum(Y * Y) / full)


def missing_compliance(share, floor, basis, contact, body):
    """The warning's text for a basis that keeps share < floor of the contact nodes' static compliance
    (``compliance_share``), else None. basis, contact, body: words for the basis, the contact nodes
    and the body (e.g. "12 clamped eigenmodes", "thread nodes", "shank")."""
    if share >= floor:
        return None
    return (f"the {body}'s basis ({basis}) keeps {share:.3g} of the {contact}' static compliance (< {floor}): the "
            f"{body} is stiffer under the contact than its mesh, and the contact's forces and the body's deformation "
            f"are off by that; use basis=craig_bampton or more modes")
