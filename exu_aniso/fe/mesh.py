"""A linear elastic body meshed with trilinear hexahedra, its matrices assembled by scikit-fem.

``ElasticMesh`` holds what a multibody engine needs of a linear finite-element body: the nodes'
reference positions, the elements, the consistent mass matrix M and the small-strain stiffness
matrix K of isotropic linear elasticity (Young's modulus E, Poisson's ratio nu, density rho), both
sparse in node-by-node coordinate order (u = [u0x, u0y, u0z, u1x, ...]: Exudyn's), named node sets
(faces), the boundary's triangles for drawing, and the energies 0.5 u.K u, 0.5 v.M v.

scikit-fem (pure Python, ``pip install ".[fem]"``) assembles the matrices: ``ElementVector
(ElementHex1())`` with a third-order Gauss rule, the bilinear forms of linear elasticity
(``skfem.models.elasticity``) and of the mass rho u.v. The mesh is a tensor-product grid, so its
elements are exact parallelepipeds and the rule integrates M exactly.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from exu_aniso.util.validation import check_integer, check_positive, check_real

FEM_EXTRA = 'pip install ".[fem]" (scikit-fem, a pure-Python finite-element assembler)'


def _skfem():
    try:
        import skfem
    except ImportError as e:        # an optional dependency: say how to get it
        raise ImportError(f"exu_aniso's finite-element bodies need scikit-fem: {FEM_EXTRA}") from e
    return skfem


@dataclass(frozen=True, eq=False)
class ElasticMesh:
    """A linear elastic finite-element body (module docstring). nodes (N, 3) reference positions [m];
    hexahedra (E, 8) node indices (scikit-fem's order); mass, stiffness: scipy CSR (3N, 3N) [kg],
    [N/m] in node-by-node order; node_sets: name -> node indices (sorted); triangles (T, 3): the
    boundary's faces split in two, counter-clockwise seen from outside; E [Pa], nu [-], rho
    [kg/m^3]."""
    nodes: np.ndarray
    hexahedra: np.ndarray
    mass: object
    stiffness: object
    node_sets: dict
    triangles: np.ndarray
    E: float
    nu: float
    rho: float
    meta: dict = field(default_factory=dict)

    @property
    def number_of_nodes(self):
        return int(self.nodes.shape[0])

    @property
    def number_of_coordinates(self):
        return 3 * self.number_of_nodes

    @property
    def total_mass(self):
        """The body's mass [kg] (the mass matrix's sum over one direction)."""
        return float(self.mass[0::3, 0::3].sum())

    def strain_energy(self, u):
        """0.5 u.K u [J] of nodal displacements u (3N,) or samples (n, 3N)."""
        u = np.asarray(u, dtype=float)
        return 0.5 * np.einsum("...i,...i->...", u, (self.stiffness @ u.T).T)

    def kinetic_energy(self, v):
        """0.5 v.M v [J] of nodal velocities v (3N,) or samples (n, 3N)."""
        v = np.asarray(v, dtype=float)
        return 0.5 * np.einsum("...i,...i->...", v, (self.mass @ v.T).T)

    def rigid_body_modes(self):
        """(3N, 6): the translations along x, y, z and the infinitesimal rotations about the axes
        through the origin of the body frame, as nodal displacements."""
        X = self.nodes
        out = []
        for i in range(3):
            t = np.zeros_like(X)
            t[:, i] = 1.0
            w = np.zeros(3)
            w[i] = 1.0
            out += [t.ravel(), np.cross(w, X).ravel()]
        return np.array(out).T

    def without_rigid_motion(self, basis, tolerance=1e-9):
        """A mode basis (3N, m) for a floating frame of reference: its rigid-body motion removed in
        the mass metric (Psi^T M R = 0, so the frame carries all of it), the columns that become
        dependent dropped (relative mass below tolerance) and the rest mass-orthonormal
        (Psi^T M Psi = I). It spans what basis spans beyond rigid motion: Craig-Bampton's static
        modes of every boundary coordinate contain the rigid-body modes themselves, which beside the
        frame's coordinates would make the system singular."""
        P = np.asarray(basis, dtype=float)
        R = self.rigid_body_modes()
        MR = self.mass @ R
        P = P - R @ np.linalg.solve(R.T @ MR, MR.T @ P)
        Mr = P.T @ (self.mass @ P)
        Mr = 0.5 * (Mr + Mr.T)
        lam, V = np.linalg.eigh(Mr)
        keep = lam > tolerance * lam.max()
        return P @ (V[:, keep] / np.sqrt(lam[keep]))

    def node_at(self, point, tolerance=None):
        """Index of the node at the reference position point (3,) [m], within tolerance (default
        1e-9 of the mesh's size); a ValueError naming the point and the closest node otherwise."""
        p = np.asarray(point, dtype=float)
        d = np.linalg.norm(self.nodes - p, axis=1)
        k = int(np.argmin(d))
        tol = 1e-9 * float(np.ptp(self.nodes, axis=0).max()) if tolerance is None else tolerance
        if d[k] > tol:
            raise ValueError(f"no mesh node at {p.tolist()} (the closest, node {k} at {self.nodes[k].tolist()}, is "
                             f"{d[k]:.3g} m away; tolerance {tol:.3g} m)")
        return k


def block_mesh(size=(0.1, 0.1, 0.1), cells=(4, 4, 4), E=1e7, nu=0.3, rho=1000.0):
    """ElasticMesh of a rectangular block of size (lx, ly, lz) [m] in cells (nx, ny, nz) trilinear
    hexahedra; body frame: the bottom face's centre at the origin, the block in 0 <= z <= lz. Node
    sets "bottom" (z = 0), "top" (z = lz)."""
    sk = _skfem()
    if len(size) != 3 or len(cells) != 3:
        raise ValueError(f"size and cells must have three entries (x, y, z); got size={size!r}, cells={cells!r}")
    size = tuple(check_positive(f"size[{i}]", s) for i, s in enumerate(size))
    cells = tuple(check_integer(f"cells[{i}]", c, 1) for i, c in enumerate(cells))
    lx, ly, lz = size
    mesh = sk.MeshHex.init_tensor(np.linspace(-lx / 2, lx / 2, cells[0] + 1), np.linspace(-ly / 2, ly / 2, cells[1] + 1),
                                  np.linspace(0.0, lz, cells[2] + 1))
    nodes = mesh.p.T.copy()
    M, K = assemble(mesh, E, nu, rho)
    tol = 1e-9 * max(size)
    sets = {"bottom": np.flatnonzero(np.abs(nodes[:, 2]) < tol), "top": np.flatnonzero(np.abs(nodes[:, 2] - lz) < tol)}
    return ElasticMesh(nodes, mesh.t.T.copy(), M, K, sets, boundary_triangles(mesh), float(E), float(nu), float(rho),
                       dict(size=size, cells=cells))


def assemble(mesh, E, nu, rho):
    """(M, K): consistent mass and linear-elastic stiffness of a scikit-fem mesh, CSR in node-by-node
    order (module docstring). E [Pa] > 0, -1 < nu < 0.5, rho [kg/m^3] > 0."""
    check_positive("E (Young's modulus [Pa])", E)
    if not -1.0 < check_real("nu", nu) < 0.5:
        raise ValueError(f"nu (Poisson's ratio) must lie in (-1, 0.5) for a positive definite elasticity; got {nu!r}")
    check_positive("rho (density [kg/m^3])", rho)
    sk = _skfem()
    from skfem.helpers import dot
    from skfem.models.elasticity import lame_parameters, linear_elasticity
    basis = sk.Basis(mesh, sk.ElementVector(sk.ElementHex1()), intorder=3)

    @sk.BilinearForm
    def mass(u, v, w):
        return rho * dot(u, v)

    order = basis.nodal_dofs.T.reshape(-1)          # node by node: x, y, z of node 0, then node 1, ...
    K = sk.asm(linear_elasticity(*lame_parameters(E, nu)), basis)[order][:, order].tocsr()
    M = sk.asm(mass, basis)[order][:, order].tocsr()
    return M, K


def boundary_triangles(mesh):
    """The boundary quadrilaterals of a hexahedral scikit-fem mesh as triangles (T, 3), each
    counter-clockwise seen from outside (its normal points away from its element's centre)."""
    facets = mesh.boundary_facets()
    quads = mesh.facets[:, facets].T                # (F, 4) in scikit-fem's facet order (a cycle)
    owner = mesh.f2t[0, facets]
    centre = mesh.p[:, mesh.t[:, owner]].mean(axis=1).T
    tris = []
    for q, c in zip(quads, centre):
        P = mesh.p[:, q].T
        for a, b, d in ((0, 1, 2), (0, 2, 3)):
            n = np.cross(P[b] - P[a], P[d] - P[a])
            outward = np.dot(n, P[[a, b, d]].mean(axis=0) - c) > 0.0
            tris.append((q[a], q[b], q[d]) if outward else (q[a], q[d], q[b]))
    return np.array(tris, dtype=np.int64)
