"""Compile management of the kernels: a kernel compiled for its argument types (or loaded from numba's
cache, ``exu_aniso.util.numba_cache``), a first compilation announced with what it is for and how long
it takes here (COMPILE_SECONDS) and timed (``compiled_here``), and the compiled function's entry point
or machine address for callers that skip numba's dispatch."""
from __future__ import annotations

import sys
import time
import warnings

from exu_aniso.kernel.stored import machine_address


# What a first compilation costs on this 2-core machine [s] (kernel_kind): a law's, a set kernel's on a
# fixed master and on a moving one: the ranges over the scenes' kernels in
# docs/results/compile_times/compile_times.json (python studies/compile_times.py), rounded outward;
# tests/test_compile_cache.py holds them to that file
COMPILE_SECONDS = {"law": (6, 10), "fixed": (0, 9), "moving": (22, 30)}


def kernels_cached(entry, sig=None):
    """True if numba's on-disk cache (exu_aniso.util.numba_cache) holds compiled code of the kernel
    ``entry`` (a numba dispatcher, e.g. kernel.law_call.law_entry, the laws) for the argument types ``sig`` (a
    tuple of numba types; None: for any types), so that no compilation is needed; False if the
    first call will compile. Reads numba's cache index, a private API: when that fails, it answers
    True (say nothing rather than something wrong)."""
    try:
        cache = entry._cache
        index = cache._cache_file._load_index()
        if sig is None:
            return bool(index)
        from numba.core.registry import cpu_target
        return cache._index_key(sig, cpu_target.target_context.codegen()) in index
    except Exception:   # noqa: BLE001 - numba internals changed: no announcement
        return True


KERNELS = {}
"""The kernels this package compiles, by their numba dispatcher: (kind, namer), kind as COMPILE_SECONDS
names it ("law", "fixed", "moving"), namer(args, entry) -> what the kernel is for, in words
(register_kernel; a kernel not listed is "fixed" and named by its function)."""


def register_kernel(entry, which, namer):
    """List the numba dispatcher entry in KERNELS as a kernel of the kind which (a COMPILE_SECONDS key)."""
    if which not in COMPILE_SECONDS:
        raise ValueError(f"which must be one of {sorted(COMPILE_SECONDS)}; got {which!r}")
    KERNELS[entry] = (which, namer)


def kernel_name(args, entry):
    """What the kernel entry's arguments specialise it for, in words (its namer in KERNELS)."""
    namer = KERNELS.get(entry, ("fixed", None))[1]
    return namer(args, entry) if namer is not None else f"the kernel {getattr(entry, '__name__', entry)}"


def kernel_kind(entry):
    """What the kernel ``entry`` is, as COMPILE_SECONDS names it (KERNELS; "fixed" when not listed)."""
    return KERNELS.get(entry, ("fixed", None))[0]


def announce_compile(stream=None, entry=None, sig=None, args=None):
    """Say, before it happens, that a kernel is being compiled (once per kernel and process), what for
    and how long it takes here (COMPILE_SECONDS); nothing when the cache holds it (kernels_cached).
    True when it announced (the compilation follows)."""
    key = (entry, sig)
    if key in compiled_here or kernels_cached(entry, sig):
        return False
    compiled_here[key] = [kernel_name(args, entry) if args is not None else "a contact kernel", None]
    where = getattr(getattr(entry, "_cache", None), "_cache_path", "numba's cache directory")
    low, high = COMPILE_SECONDS[kernel_kind(entry)]
    print(f"exu_aniso: compiling {compiled_here[key][0]} with numba (about {low}-{high} s on a 2-core machine; "
          f"once per machine: later runs load it from the cache in {where})", file=stream or sys.stderr, flush=True)
    return True


# the set kernels compiled (and announced) in this process: (entry, signature) -> [what for (kernel_name),
# the compilation's wall time [s]]
compiled_here = {}


def compile_kernel(fn, sig, args):
    """Compile the numba dispatcher fn for the argument types sig, or load it from the cache: announced
    (announce_compile) and timed (compiled_here) when it compiles."""
    from numba.core.errors import NumbaIRAssumptionWarning
    announced = sig not in fn.overloads and announce_compile(entry=fn, sig=sig, args=args)
    start = time.perf_counter()
    with warnings.catch_warnings():
        # numba's internal SSA check complains about variables of branches it pruned in the force
        # loop's inlined law (tangent a constant False there); the code is right, the notice is noise
        warnings.simplefilter("ignore", NumbaIRAssumptionWarning)
        fn.compile(sig)
    if announced:
        compiled_here[(fn, sig)][1] = time.perf_counter() - start


def compiled_address(fn, sig, args):
    """The machine address of fn compiled for sig (compile_kernel; args: values of those types, to name it)."""
    compile_kernel(fn, sig, args)
    return machine_address(fn, sig)[0]


def entry_point(fn, args):
    """The compiled function of the numba dispatcher fn for the types of args, called directly.

    numba's type dispatch of every call costs more than the compiled call's entry itself; the types
    of a set's arguments never change (the caller passes C-contiguous float64 arrays, floats and
    ints), so the dispatch is done once. Falls back to the dispatcher if numba's API for it is not
    there."""
    from numba import typeof
    try:
        sig = tuple(typeof(a) for a in args)
        compile_kernel(fn, sig, args)
        return fn.overloads[sig].entry_point
    except Exception:               # noqa: BLE001 - numba internals changed: dispatch per call
        return fn
