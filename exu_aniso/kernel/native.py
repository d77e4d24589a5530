"""A contact set's compiled call as a C function: what Exudyn's native force callback calls
(``exu_aniso.engines.exudyn_adapter._native``), with no Python in between.

A set's compiled entry takes ``(mode, q, q_t, fq, fv, dt, H, *tail)`` (``CovariantSet.entry``:
the history view H and the packed ``tail``: law bundle, points, scratch, outputs). Here those
arguments are stored once, as numba's own native value of the tuple ``(entry address, (H,) +
tail)``, into a block of memory (``StoredArguments``: arrays keep one reference each while stored,
given back by ``release`` and when it is collected); a cfunc made per tuple type (``set_cfunc``)
loads the tuple from that address and calls the entry's machine code at the stored address with
q, q_t given as C pointers:

    status = cfunc(address, mode, dt [s], q, q_t, n, fq, fv)

the same compiled function with the same arguments as the Python-called entry, so the two give
the same numbers bit for bit (tests/test_native_callbacks.py). The cfunc calls the entry through
its address (``_call_entry``) instead of linking it: linked, numba optimised the whole kernel a
second time for the cfunc (3.7 s of the screw's first run). The post-Newton commit likewise:
``stage_kernel(address)`` over the stored arguments of kernel.sets.stage_gathered. A kernel that
raises (an ill-posed contact state) returns ``KERNEL_ERROR``: the caller repeats the call from
Python, where the error is raised with its message. ``NativeBlock`` holds what one contact set
needs. This module needs no Exudyn.
"""
from __future__ import annotations

import hashlib
import importlib.util
import math
import os
import sys
from types import ModuleType

import numpy as np
from numba import cfunc, njit, typeof, types
from numba.core.registry import cpu_target
from numba.extending import intrinsic

from exu_aniso.kernel.sets import stage_gathered
from exu_aniso.util.numba_cache import native_dir
from exu_aniso.util.output import write_text

# the status a cfunc returns when the kernel raised (the same number in _native.cpp)
KERNEL_ERROR = -1000

CFUNC_SIGNATURE = types.int64(types.int64, types.int64, types.float64, types.CPointer(types.float64),
                              types.CPointer(types.float64), types.int64, types.float64, types.float64)


@intrinsic
def _store(typingctx, address, value):
    """Write numba's native value of ``value`` at ``address``, holding one reference of each array in it."""
    def codegen(context, builder, sig, args):
        ty = sig.args[1]
        ptr = builder.inttoptr(args[0], context.get_value_type(ty).as_pointer())
        context.nrt.incref(builder, ty, args[1])
        builder.store(args[1], ptr)
        return context.get_dummy_value()
    return types.none(types.int64, value), codegen


@intrinsic
def _load(typingctx, address, typeref):
    """The value of numba type ``typeref`` stored at ``address`` (_store), as a new reference."""
    ty = typeref.instance_type

    def codegen(context, builder, sig, args):
        ptr = builder.inttoptr(args[0], context.get_value_type(ty).as_pointer())
        value = builder.load(ptr)
        context.nrt.incref(builder, ty, value)
        return value
    return ty(types.int64, typeref), codegen


@intrinsic
def _drop(typingctx, address, like):
    """Release the references a _store at ``address`` holds; ``like``: a value of the stored type."""
    def codegen(context, builder, sig, args):
        ty = sig.args[1]
        ptr = builder.inttoptr(args[0], context.get_value_type(ty).as_pointer())
        context.nrt.decref(builder, ty, builder.load(ptr))
        return context.get_dummy_value()
    return types.none(types.int64, like), codegen


@intrinsic
def _call_entry(typingctx, address, mode, q, q_t, fq, fv, dt, args):
    """The compiled entry at ``address`` (numba's calling convention, the argument types of
    ``(mode, q, q_t, fq, fv, dt, *args)``, an int64 result) called with those arguments; its result, or
    KERNEL_ERROR when it raised. A call through the address: the entry is not linked into the
    caller."""
    argtys = (mode, q, q_t, fq, fv, dt) + tuple(args.types)

    def codegen(context, builder, sig, llargs):
        tup = llargs[-1]
        flat = list(llargs[1:-1]) + [builder.extract_value(tup, i) for i in range(len(args.types))]
        fnty = context.call_conv.get_function_type(types.int64, argtys)
        fn = builder.inttoptr(llargs[0], fnty.as_pointer())
        status, res = context.call_conv.call_function(builder, fn, types.int64, argtys, flat)
        return builder.select(status.is_ok, res, context.get_constant(types.int64, KERNEL_ERROR))
    return types.int64(address, mode, q, q_t, fq, fv, dt, args), codegen


def entry_signature(block_type):
    """The argument types of a set's compiled entry as the cfunc calls it: (mode, q, q_t, fq, fv,
    dt) then the stored arguments (H,) + tail of block_type (the tuple's second element)."""
    f1 = types.float64[::1]
    return (types.int64, f1, f1, types.float64, types.float64, types.float64) + tuple(block_type.types[1].types)


def entry_address(entry, block_type):
    """The machine address of ``entry`` compiled for ``entry_signature(block_type)`` (compiled or
    loaded from numba's cache now if it is not yet), checked to return int64."""
    sig = entry_signature(block_type)
    entry.compile(sig)
    cres = entry.overloads[sig]
    if cres.signature.return_type != types.int64:
        raise TypeError(f"entry_address: {entry.py_func.__name__} returns {cres.signature.return_type}, the "
                        "cfunc needs int64")
    return int(cres.library.get_pointer_to_function(cres.fndesc.mangled_name))


@njit(cache=True)
def store_block(address, value):
    _store(address, value)


@njit(cache=True)
def drop_block(address, like):
    _drop(address, like)


def _native_size(ty):
    ctx = cpu_target.target_context
    return ctx.get_abi_sizeof(ctx.get_value_type(ty))


_CFUNCS = {}
_PENDING = {}       # module name -> the argument type its module is being generated for (set_cfunc)

# The cfunc of one (entry, argument type), as a module of its own: numba caches a function by its
# source file, and the cfunc's body depends on the argument type, so each type gets a file (named by
# a hash of its text, which spells the type out; in a folder of the cache directory named by the
# shared kernel sources, util.numba_cache.native_dir) and numba's disk cache serves it in later
# processes: compiled once per machine, not once per process. Types that cannot be spelled out for good (a user's function in
# the law, a class that is not importable) get the same text compiled in this process only.
_CFUNC_MODULE = '''"""Generated by exu_aniso.kernel.native.set_cfunc: the native call of {entry_module}.{entry_name}
for the argument type {type_key}. Do not edit; the package's cache directory holds it."""
from numba import carray, cfunc

from exu_aniso.kernel.native import _PENDING, CFUNC_SIGNATURE, _call_entry, _load

BLOCK_TYPE = _PENDING[__name__]


# the entry ({entry_module}.{entry_name}) at the address stored first in the block: KERNEL_ERROR
# when it raised (the Python call repeats it and raises the message)
@cfunc(CFUNC_SIGNATURE, cache={cache})
def kernel(block, mode, dt, q, q_t, n, fq, fv):
    stored = _load(block, BLOCK_TYPE)
    return _call_entry(stored[0], mode, carray(q, (n,)), carray(q_t, (n,)), fq, fv, dt, stored[1])
'''


def _type_key(ty):
    """The numba type spelled out for good (named tuples by their importable classes, arrays,
    numbers), or None when it cannot be (anything else: a function, a class made at run time)."""
    if isinstance(ty, (types.NamedTuple, types.NamedUniTuple)):
        cls = ty.instance_class
        if getattr(sys.modules.get(cls.__module__), cls.__qualname__, None) is not cls:
            return None
        inner = [_type_key(t) for t in ty.types]
        return None if None in inner else f"{cls.__module__}.{cls.__qualname__}({', '.join(inner)})"
    if isinstance(ty, (types.Tuple, types.UniTuple)):
        inner = [_type_key(t) for t in ty.types]
        return None if None in inner else f"({', '.join(inner)})"
    if isinstance(ty, (types.Array, types.Float, types.Integer, types.Boolean)):
        return str(ty)
    return None


def set_cfunc(entry, block_type):
    """The cfunc of ``entry`` (a numba dispatcher: kernel.point.evaluate_covariant and its
    siblings) over the arguments stored as ``block_type``: the ``kernel`` of _CFUNC_MODULE for
    that type, loaded once per (entry, type) and process; from a file numba caches when the type
    can be spelled out (_type_key), else compiled in this process from the same text."""
    key = (entry, block_type)
    if key not in _CFUNCS:
        type_key = _type_key(block_type)
        text = _CFUNC_MODULE.format(entry_module=entry.py_func.__module__, entry_name=entry.py_func.__name__,
                                    type_key=type_key or str(block_type), cache=type_key is not None)
        name = "exu_aniso_native_" + hashlib.sha1(text.encode()).hexdigest()[:20]
        _PENDING[name] = block_type
        try:
            module = _cached_module(name, text) if type_key is not None else _module(name, text)
        finally:
            del _PENDING[name]
        _CFUNCS[key] = module.kernel
    return _CFUNCS[key]


def _cached_module(name, text):
    """The module of ``text`` from a file of the package's cache directory (numba caches by file)."""
    folder = native_dir()
    path = os.path.join(folder, name + ".py")
    if not os.path.exists(path):               # written once, whole: numba keys its cache on the file's stamp
        os.makedirs(folder, exist_ok=True)
        write_text(path, text)
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module                 # numba's cache refers to the module by its name
    spec.loader.exec_module(module)
    return module


def _module(name, text):
    """The module of ``text`` in this process only."""
    module = ModuleType(name)
    exec(compile(text, f"<{name}>", "exec"), module.__dict__)
    return module


class StoredArguments:
    """A tuple of arguments stored as numba's native value (_store) for a cfunc to load: ``address``
    where, ``type`` its numba type; ``store(values)`` stores another tuple of the same type (the
    old one's references given back), ``release()`` gives them back."""

    def __init__(self, values):
        self._stored = False
        self.type = typeof(values)
        self.memory = np.zeros(_native_size(self.type) // 8 + 1)
        self.address = int(self.memory.ctypes.data)
        self._drop = drop_block                # held: at interpreter exit the module may be gone first,
        self._finalizing = sys.is_finalizing   # and its globals (sys) None
        self.store(values)

    def store(self, values):
        if typeof(values) != self.type:
            raise TypeError(f"StoredArguments.store: values of type {typeof(values)}, stored as {self.type}")
        self.release()
        self.values = values
        store_block(self.address, values)
        self._stored = True

    def release(self):
        """Give back the stored references (no cfunc may load them until the next store)."""
        if self._stored:
            self._stored = False
            self._drop(self.address, self.values)

    def __del__(self):
        if not self._finalizing():             # at exit the process gives the memory back itself
            self.release()


# the stage kernel's arguments: kernel.sets.stage_gathered's (X, q, q_t, idx, qb, q_tb, Hn, data, ltg,
# ltg_total)
_F1, _F2, _I1 = types.float64[::1], types.float64[:, ::1], types.int64[::1]
STAGE_TYPE = types.Tuple((_F2, _F1, _F1, _I1, _F1, _F1, _F2, _F1, _I1, types.int64))


@cfunc(types.int64(types.int64), cache=True)
def stage_kernel(address):
    """The post-Newton commit of one set from its stored arguments (STAGE_TYPE): 0 written, 1 the
    last residual was at another state, -1 unresolved (kernel.sets.stage_candidate), KERNEL_ERROR."""
    a = _load(address, STAGE_TYPE)
    try:
        return stage_gathered(a[0], a[1], a[2], a[3], a[4], a[5], a[6], a[7], a[8], a[9])
    except Exception:          # noqa: BLE001 - the Python commit repeats it and raises the message
        return KERNEL_ERROR


class NativeBlock:
    """What the native callbacks of one set need: ``args``, the address of its compiled entry and
    the entry's arguments, ``(address, (H,) + tail)`` (StoredArguments), for ``kernel`` (its cfunc's
    address, ``set_cfunc``);
    ``stage``, the stage kernel's arguments (STAGE_TYPE); ``clock`` (4,): the start time of the
    step [s], the armed flag (1: the native callers may evaluate), the end time of the solve [s] and
    the longest step the native callers take [s] (a call farther from the start of the step goes to
    Python: a new solve that starts later) (read and written by the native callers and the Exudyn
    glue). ``store(H, stage)`` stores both
    again with another history view H and stage arguments."""

    def __init__(self, entry, H, tail, stage):
        self.tail = tuple(tail)
        self.entry = entry_address(entry, types.Tuple((types.int64, typeof((H,) + self.tail))))
        self.args = StoredArguments((self.entry, (H,) + self.tail))
        self.stage = StoredArguments(stage)
        if self.stage.type != STAGE_TYPE:
            raise TypeError(f"NativeBlock: stage arguments of type {self.stage.type}, the stage kernel takes "
                            f"{STAGE_TYPE}")
        self.cfunc = set_cfunc(entry, self.args.type)
        self.kernel = int(self.cfunc.address)
        self.clock = np.array([0.0, 0.0, math.inf, math.inf])

    @property
    def H(self):
        return self.args.values[1][0]

    def store(self, H, stage):
        self.args.store((self.entry, (H,) + self.tail))
        self.stage.store(stage)
