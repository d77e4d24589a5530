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

from exu_aniso.util.validation import check_integer, check_positive, check_real, check_vector

FEM_EXTRA = 'pip install ".[fem]" (scikit-fem, a pure-Python finite-element assembler)'

MAX_MESH_NODES = 100_000
"""The most nodes a mesh helper builds (checked before the assembly: 300,000 coordinates and their
sparse matrices fit this machine's memory many times; 400^3 cells did not)."""

MIN_ASPECT = 1e-6
"""The smallest ratio of a mesh's extents (and of a tube's wall to its radius): flatter, the node
sets (found within 1e-9 of the mesh's size) and the stiffness lose their meaning in doubles."""


def _check_nodes(count, what):
    if count > MAX_MESH_NODES:
        raise ValueError(f"cells must give at most {MAX_MESH_NODES} nodes (a bound on the assembly's memory); "
                         f"{what} gives {count}")


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

    def clamped_modes(self, fixed_nodes, count=None):
        """A mode basis (3N, m) that vanishes at fixed_nodes (every coordinate of those nodes held):
        with count None, every other coordinate as its own column (the identity: the full body
        relative to the fixed nodes); else the count lowest eigenmodes of the body clamped there
        (K phi = omega^2 M phi on the other coordinates). In a floating frame of reference this
        basis makes the frame the fixed nodes' rigid motion. Each eigenmode is scaled to a largest
        nodal displacement of 1 (Exudyn's scaling of its modes): a modal coordinate is then a
        displacement [m], not a mass-weighted one, of the scale of the other coordinates in Newton's
        increments (mass-orthonormal modes took the fe_screw scene far more steps)."""
        fixed = np.zeros(self.number_of_nodes, dtype=bool)
        fixed[np.asarray(fixed_nodes, dtype=np.int64)] = True
        free = np.flatnonzero(np.repeat(~fixed, 3))
        if not fixed.any() or free.size == 0:
            raise ValueError(f"fixed_nodes must hold some but not all of the {self.number_of_nodes} nodes")
        P = np.zeros((self.number_of_coordinates, free.size if count is None else 0))
        if count is None:
            P[free, np.arange(free.size)] = 1.0
            return P
        count = check_integer("count", count, 1)
        if count > free.size:
            raise ValueError(f"count must be <= {free.size} (the free coordinates); got {count}")
        import scipy.linalg
        Kf = self.stiffness[free][:, free].toarray()
        Mf = self.mass[free][:, free].toarray()
        _, V = scipy.linalg.eigh(Kf, Mf, subset_by_index=[0, count - 1])
        P = np.zeros((self.number_of_coordinates, count))
        P[free] = V / np.abs(V).max(axis=0)
        return P

    def craig_bampton_modes(self, fixed_nodes, boundary_nodes, count=0):
        """A Craig-Bampton basis (3N, b + count) of the body clamped at fixed_nodes: the static
        (constraint) modes of every coordinate of boundary_nodes (those not among fixed_nodes) --
        a unit displacement of one boundary coordinate, the other boundary coordinates held, the
        interior in equilibrium, K_ii u_i = -K_ib e -- then count eigenmodes of the body clamped at
        the fixed and the boundary nodes (fixed-interface modes), each scaled to a largest nodal
        displacement of 1 as clamped_modes does. It vanishes at fixed_nodes; its static modes span
        the static response to any load on the boundary nodes (K^-1 P), so the body under loads
        there is the full mesh's in statics (compliance_share 1)."""
        import scipy.sparse.linalg
        fixed = np.zeros(self.number_of_nodes, dtype=bool)
        fixed[np.asarray(fixed_nodes, dtype=np.int64)] = True
        if not fixed.any():
            raise ValueError("fixed_nodes must hold some of the nodes (a clamped body)")
        boundary = np.zeros(self.number_of_nodes, dtype=bool)
        boundary[np.asarray(boundary_nodes, dtype=np.int64)] = True
        boundary &= ~fixed
        b = np.flatnonzero(np.repeat(boundary, 3))
        i = np.flatnonzero(np.repeat(~fixed & ~boundary, 3))
        if b.size == 0:
            raise ValueError("boundary_nodes must hold some nodes that are not fixed")
        count = check_integer("count", count, 0)
        if count > i.size:
            raise ValueError(f"count must be <= {i.size} (the interior coordinates, off the fixed and boundary "
                             f"nodes); got {count}")
        K = self.stiffness.tocsr()
        P = np.zeros((self.number_of_coordinates, b.size + count))
        P[b, np.arange(b.size)] = 1.0
        if i.size:
            Kii = K[i][:, i].tocsc()
            P[i, :b.size] = -scipy.sparse.linalg.splu(Kii).solve(K[i][:, b].toarray())
        if count:
            import scipy.linalg
            _, V = scipy.linalg.eigh(Kii.toarray(), self.mass[i][:, i].toarray(), subset_by_index=[0, count - 1])
            P[i, b.size:] = V / np.abs(V).max(axis=0)
        return P

    def node_at(self, point, tolerance=None):
        """Index of the node at the reference position point (3,) [m] (``node_index``)."""
        return node_index(self.nodes, point, tolerance)


def node_index(positions, point, tolerance=None):
    """Index of the node at point (3,) [m] among the nodes at positions (N, 3) [m], within tolerance
    (default 1e-9 of the nodes' extent); a ValueError naming the point and the closest node otherwise."""
    p = check_vector("point", point, 3)
    positions = np.asarray(positions, dtype=float)
    d = np.linalg.norm(positions - p, axis=1)
    k = int(np.argmin(d))
    tol = 1e-9 * float(np.ptp(positions, axis=0).max()) if tolerance is None else tolerance
    if d[k] > tol:
        raise ValueError(f"no mesh node at {p.tolist()} (the closest, node {k} at {positions[k].tolist()}, is "
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
    if min(size) < MIN_ASPECT * max(size):
        raise ValueError(f"size must have its smallest entry at least {MIN_ASPECT:g} of its largest (a block, not a "
                         f"sheet the doubles cannot resolve); got size={size!r}")
    _check_nodes(int(np.prod([c + 1 for c in cells])), f"cells={cells!r}")
    lx, ly, lz = size
    mesh = sk.MeshHex.init_tensor(np.linspace(-lx / 2, lx / 2, cells[0] + 1), np.linspace(-ly / 2, ly / 2, cells[1] + 1),
                                  np.linspace(0.0, lz, cells[2] + 1))
    nodes = mesh.p.T
    tol = 1e-9 * max(size)
    sets = {"bottom": np.abs(nodes[:, 2]) < tol, "top": np.abs(nodes[:, 2] - lz) < tol}
    return _elastic_mesh(mesh, E, nu, rho, sets, dict(size=size, cells=cells))


def shank_mesh(radius=0.005, bore=0.0025, length=0.02, cells=(1, 8, 4), E=2e9, nu=0.3, rho=1200.0):
    """ElasticMesh of a hollow cylindrical shank (a tube: outer radius ``radius``, inner radius
    ``bore``, length ``length`` [m]) in cells (n_r, n_theta, n_z) trilinear hexahedra of a polar grid
    (rings of nodes at equal radii, angles 2 pi j / n_theta, equal z steps); body frame: axis z, the
    shank in -length/2 <= z <= length/2 (its centre at the origin). Node sets "thread" (the outer
    surface r = radius, ordered ring by ring from the tip, angle within a ring), "head"
    (z = +length/2), "tip" (z = -length/2). The cross-section is the annulus between two regular
    n_theta-gons (straight element edges), of area n_theta sin(2 pi / n_theta) (radius^2 -
    bore^2) / 2. A solid shank would need an O-grid at the axis; the bore keeps every element a
    regular polar cell (cannulated screws have one)."""
    sk = _skfem()
    radius, length = check_positive("radius", radius), check_positive("length", length)
    if not 0.0 < check_real("bore", bore) < radius:
        raise ValueError(f"bore (inner radius [m]) must lie in (0, radius); got bore={bore!r}, radius={radius!r}")
    if len(cells) != 3:
        raise ValueError(f"cells must have three entries (n_r, n_theta, n_z); got {cells!r}")
    n_r, n_theta, n_z = (check_integer(f"cells[{i}]", c, m) for i, (c, m) in enumerate(zip(cells, (1, 6, 1))))
    if radius - bore < MIN_ASPECT * radius:
        raise ValueError(f"bore must leave a wall of at least {MIN_ASPECT:g} of the radius (the thread's nodes are "
                         f"found within 1e-9 of the size); got bore={bore!r}, radius={radius!r}")
    _check_nodes((n_r + 1) * n_theta * (n_z + 1), f"cells={cells!r}")
    grid = sk.MeshHex.init_tensor(np.linspace(bore, radius, n_r + 1), np.arange(n_theta + 1, dtype=float),
                                  np.linspace(-length / 2, length / 2, n_z + 1))
    r, j, z = grid.p
    j = np.rint(j).astype(np.int64) % n_theta                     # the seam: angle index n_theta is 0
    ir = np.rint((r - bore) / (radius - bore) * n_r).astype(np.int64)
    iz = np.rint((z + length / 2) / length * n_z).astype(np.int64)
    key = (iz * n_theta + j) * (n_r + 1) + ir                    # ring by ring from the tip, angle, radius
    unique, index = np.unique(key, return_inverse=True)
    angle = 2.0 * np.pi * j / n_theta
    nodes = np.zeros((len(unique), 3))
    nodes[index] = np.column_stack([r * np.cos(angle), r * np.sin(angle), z])
    mesh = sk.MeshHex(nodes.T, index[grid.t])                     # (r, theta, z) -> (x, y, z): right-handed
    tol = 1e-9 * max(radius, length)
    rho_n = np.hypot(nodes[:, 0], nodes[:, 1])
    sets = {"thread": np.abs(rho_n - radius) < tol, "head": np.abs(nodes[:, 2] - length / 2) < tol,
            "tip": np.abs(nodes[:, 2] + length / 2) < tol}
    return _elastic_mesh(mesh, E, nu, rho, sets, dict(radius=radius, bore=bore, length=length, cells=(n_r, n_theta, n_z)))


def _elastic_mesh(mesh, E, nu, rho, sets, meta):
    """The ElasticMesh of a scikit-fem hexahedral mesh; sets: name -> boolean mask over the nodes."""
    M, K = assemble(mesh, E, nu, rho)
    sets = {name: np.flatnonzero(mask) for name, mask in sets.items()}
    return ElasticMesh(mesh.p.T.copy(), mesh.t.T.copy(), M, K, sets, boundary_triangles(mesh), float(E), float(nu),
                       float(rho), meta)


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
