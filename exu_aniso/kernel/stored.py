"""Values stored as numba's native representation in a block of memory, for compiled code that
finds them by address: ``StoredArguments`` holds a tuple there (one reference to each array in it
while stored), ``_load`` reads it back in compiled code. The native callbacks store a set's
arguments so (``kernel.native``), and a set's kernel finds its contact law so (``kernel.point``);
``machine_address`` is where a compiled function's code starts, for a call through that address.
This module needs no Exudyn.
"""
from __future__ import annotations

import sys

import numpy as np
from numba import njit, typeof, types
from numba.core.registry import cpu_target
from numba.extending import intrinsic


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


def _value_at(context, builder, ty, ptr):
    """The value of numba type ty that _store wrote at the LLVM pointer ptr, as a new reference."""
    value = builder.load(builder.bitcast(ptr, context.get_value_type(ty).as_pointer()))
    context.nrt.incref(builder, ty, value)
    return value


@intrinsic
def _load(typingctx, address, typeref):
    """The value of numba type ``typeref`` stored at ``address`` (_store), as a new reference."""
    ty = typeref.instance_type

    def codegen(context, builder, sig, args):
        return _value_at(context, builder, ty, builder.inttoptr(args[0], context.get_value_type(types.voidptr)))
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
def _deref(typingctx, pointer):
    """The value at ``pointer`` (a CPointer of the stored value's type: a _store at its address), as a
    new reference."""
    ty = pointer.dtype

    def codegen(context, builder, sig, args):
        return _value_at(context, builder, ty, args[0])
    return ty(pointer), codegen


@njit(cache=True)
def store_block(address, value):
    _store(address, value)


@njit(cache=True)
def drop_block(address, like):
    _drop(address, like)


def machine_address(fn, sig):
    """The machine address of the numba dispatcher ``fn`` compiled for the argument types ``sig``
    (compiled, or loaded from numba's cache, now if it is not yet), with its compiled result."""
    fn.compile(sig)
    cres = fn.overloads[sig]
    return int(cres.library.get_pointer_to_function(cres.fndesc.mangled_name)), cres


def _native_size(ty):
    ctx = cpu_target.target_context
    return ctx.get_abi_sizeof(ctx.get_value_type(ty))


class StoredArguments:
    """A tuple stored as numba's native value (_store) for compiled code to load (_load, _deref):
    ``address`` where, ``type`` its numba type; ``store(values)`` stores another tuple of the same type (the
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
