"""exu_aniso: anisotropic frictional contact (Konyukhov & Schweizerhof) for Exudyn.

The kernels (geometry, nets, fields, law, kernel, contact, reference) never import exudyn; the
adapter ``exu_aniso.engines.exudyn_adapter`` talks to Exudyn: ``create_contact`` (the constructor of
a contact set), ``mainsystem`` (the method ``mbs.CreateAnisotropicContact``, bound to
``exudyn.MainSystem`` when this package is imported), ``graphics`` and the scenes' ``runner``. Without Exudyn installed the
package still imports, and the reference engine runs.
"""
from exu_aniso.util.numba_cache import CACHE_DIR as NUMBA_CACHE_DIR   # first: before any compiled kernel is defined
from exu_aniso.law.history import HISTORY_FIELDS, OPEN, SLIP, STICK
from exu_aniso.kernel.contact_law import ContactLaw, ContactState
from exu_aniso.fields.tensor_fields import Adhesion, Friction, TensorField
from exu_aniso.law.return_maps import RETURN_MAPS, return_map_batch, return_map_point
from exu_aniso.geometry import Cone, Cylinder, Helicoid, ParametricSurface, Plane, Sphere, SurfaceOfRevolution, Torus

try:   # Exudyn is a dependency, but the kernels and the reference engine also run without it
    import exudyn as _exudyn
except ImportError:
    _exudyn = None
if _exudyn is not None:
    from exu_aniso.engines.exudyn_adapter import mainsystem as _mainsystem   # binds mbs.CreateAnisotropicContact (extension registry)
    from exu_aniso.engines.exudyn_adapter.solver_settings import RecommendedSimulationSettings
    from exu_aniso.engines.exudyn_adapter.runner import Snapshot

__version__ = "0.1.0"
__all__ = ["Adhesion", "Friction", "TensorField", "Plane", "Cylinder", "Cone", "Sphere", "Torus", "Helicoid",
           "SurfaceOfRevolution", "ParametricSurface", "ContactLaw", "ContactState",
           "HISTORY_FIELDS", "OPEN", "STICK", "SLIP", "RETURN_MAPS", "return_map_point", "return_map_batch"]
if _exudyn is not None:
    __all__ += ["RecommendedSimulationSettings", "Snapshot"]
