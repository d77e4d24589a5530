"""exu_aniso: anisotropic frictional contact (Konyukhov & Schweizerhof) for Exudyn.

The numpy kernels (surfaces, fields, law, contact, reference) never import exudyn; the glue
module ``exu_aniso.exudyn_glue`` is the one place that talks to Exudyn.
"""
from .contact import HISTORY_FIELDS, OPEN, SLIP, STICK, ContactLaw, ContactState
from .fields import Adhesion, Friction, TensorField
from .law import RETURN_MAPS, return_map_batch, return_map_point
from .surfaces import Cylinder, Plane

__version__ = "0.1.0"
__all__ = ["Adhesion", "Friction", "TensorField", "Plane", "Cylinder", "ContactLaw", "ContactState",
           "HISTORY_FIELDS", "OPEN", "STICK", "SLIP", "RETURN_MAPS", "return_map_point", "return_map_batch"]
