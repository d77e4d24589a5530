"""Linear finite-element bodies: meshes and their mass and stiffness matrices, assembled by
scikit-fem (an optional dependency: ``pip install ".[fem]"``), in Exudyn's coordinate order (node
by node: x0, y0, z0, x1, ...). No Exudyn here; ``exu_aniso.engines.exudyn_adapter.fem`` hands a mesh
to Exudyn's FEMinterface."""
from exu_aniso.fe.compliance import BasisWarning, compliance_share
from exu_aniso.fe.mesh import ElasticMesh, block_mesh, shank_mesh

__all__ = ["BasisWarning", "ElasticMesh", "block_mesh", "compliance_share", "shank_mesh"]
