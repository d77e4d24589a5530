"""The implementations the timing studies compare (``studies/benchmarks.py``, ``studies/work_precision.py``).

An implementation is a name -> (engine, keyword options for BuildBlock/BuildScrew (engine
"exudyn") or simulate_block/simulate_screw (engine "reference")). "exudyn" runs BuildBlock /
BuildScrew with their defaults (CreateAnisotropicContact's default implementation; the one used
is recorded in the benchmark's column contact_impl); "exudyn-numpy" the adapter's numpy route
(``implementation="numpy"``).
"""
from __future__ import annotations

import inspect

from exu_aniso.models.block import BuildBlock

IMPLEMENTATIONS = {
    "exudyn": ("exudyn", {}),
    "reference": ("reference", {}),
}
# the numpy route of the adapter (CreateAnisotropicContact(..., implementation="numpy")), as soon as
# BuildBlock/BuildScrew pass `implementation` on
if "implementation" in inspect.signature(BuildBlock).parameters:
    IMPLEMENTATIONS["exudyn-numpy"] = ("exudyn", {"implementation": "numpy"})
