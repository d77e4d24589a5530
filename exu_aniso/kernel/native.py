"""A contact set's compiled call as a C function: what Exudyn's native force callback calls
(``exu_aniso.engines.exudyn_adapter._native``), with no Python in between.

A set's compiled entry takes ``(mode, q, q_t, fq, fv, dt, H, *tail)`` (``CovariantSet.entry``:
the history view H and the packed ``tail``: law bundle, points, scratch, outputs). Here those
arguments are stored once, as numba's own native value of the tuple ``(H,) + tail``, into a block
of memory (``NativeBlock``: arrays keep one reference each while stored, given back by ``release``
and when the block is collected); a cfunc made per tuple type (``set_cfunc``) loads the tuple from
the block's address and calls the entry with q, q_t given as C pointers:

    status = cfunc(block address, mode, dt [s], q, q_t, n, fq, fv)

the same compiled function with the same arguments as the Python-called entry, so the two give
the same numbers bit for bit (tests/test_native_callbacks.py). A kernel that raises (an ill-posed
contact state) returns ``KERNEL_ERROR``: the caller repeats the call from Python, where the error
is raised with its message. This module needs no Exudyn.
"""
from __future__ import annotations

import sys

import numpy as np
from numba import carray, cfunc, njit, typeof, types
from numba.core.registry import cpu_target
from numba.extending import intrinsic

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


def set_cfunc(entry, block_type):
    """The cfunc of ``entry`` (a numba dispatcher: kernel.point.evaluate_covariant and its
    siblings) over the arguments stored as ``block_type``; one per (entry, type) and process
    (its compiled entry is numba's cached one: the cfunc itself is a small wrapper)."""
    key = (entry, block_type)
    if key not in _CFUNCS:
        bt = block_type

        @njit
        def call(mode, q, q_t, fq, fv, dt, args):
            return entry(mode, q, q_t, fq, fv, dt, *args)

        @cfunc(CFUNC_SIGNATURE)
        def kernel(block, mode, dt, q, q_t, n, fq, fv):
            args = _load(block, bt)
            try:
                return call(mode, carray(q, (n,)), carray(q_t, (n,)), fq, fv, dt, args)
            except Exception:          # noqa: BLE001 - the Python call repeats it and raises the message
                return KERNEL_ERROR
        _CFUNCS[key] = kernel
    return _CFUNCS[key]


class NativeBlock:
    """The arguments ``(H,) + tail`` of a set's compiled entry stored for its cfunc. ``address``:
    where they are; ``kernel``: the cfunc's address; ``clock`` (2,): the start time of the step [s]
    and the armed flag (1: the native caller may evaluate; read and written by the caller and the
    Exudyn glue). ``store(H)`` stores the arguments again with another history view H."""

    def __init__(self, entry, H, tail):
        self._stored = False
        self.tail = tuple(tail)
        self.type = typeof((H,) + self.tail)
        self.memory = np.zeros(_native_size(self.type) // 8 + 1)
        self.address = int(self.memory.ctypes.data)
        self.cfunc = set_cfunc(entry, self.type)
        self.kernel = int(self.cfunc.address)
        self.clock = np.zeros(2)
        self._drop = drop_block                # held: at interpreter exit the module may be gone first
        self.store(H)

    def store(self, H):
        if typeof(H) != self.type[0]:
            raise TypeError(f"NativeBlock.store: history view of type {typeof(H)}, stored as {self.type[0]}")
        self.release()
        self.H = H
        store_block(self.address, (H,) + self.tail)
        self._stored = True

    def release(self):
        """Give back the stored references (the cfunc must not be called until the next store)."""
        if self._stored:
            self._stored = False
            self._drop(self.address, (self.H,) + self.tail)

    def __del__(self):
        if not sys.is_finalizing():            # at exit the process gives the memory back itself
            self.release()
