"""The native callbacks' extension (``_native.cpp``, built at install) as the adapter sees it:
``extension`` (None on an install without a C++ compiler: Python callbacks then) and what its C++
calls back in Python, held weakly (the C++ registry must not keep a system alive)."""
from __future__ import annotations

import weakref

from exu_aniso.kernel.native import stage_kernel

try:        # the native callbacks (C++, built at install; see _native.cpp); absent: Python callbacks
    from exu_aniso.engines.exudyn_adapter import _native as extension
    extension.set_stage_kernel(stage_kernel.address)
except ImportError:                             # pragma: no cover - an install without a C++ compiler
    extension = None


def alive(ref, what):
    """The object a weak reference holds, or an error naming what was deleted."""
    obj = ref()
    if obj is None:
        raise RuntimeError(f"exu_aniso: {what} was deleted while Exudyn still calls its user functions; keep a "
                           "reference to mbs while solving")
    return obj


class Delegate:
    """What the native callback calls in Python: the set's native_delegate, by weak references (the
    C++ registry must not keep a system alive)."""

    def __init__(self, cs, mbs):
        self.cs, self.mbs = weakref.ref(cs), weakref.ref(mbs)

    def __call__(self, t, q, q_t):
        alive(self.cs, "a contact set").native_delegate(alive(self.mbs, "the exudyn.MainSystem of a contact set"), t)

    def jacobian(self, t, q, q_t, fODE2, fODE2_t):
        return alive(self.cs, "a contact set").jacobian_in_place(
            alive(self.mbs, "the exudyn.MainSystem of a contact set"), t, None, q, q_t, fODE2, fODE2_t)

