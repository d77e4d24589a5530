"""The contact law as a set's kernel calls it: the law at a point (``kernel.point``) in a loop over the
set's points (``kernel.sets.point_states``), compiled once per law (surface, nets and return map)
and called by the set kernels through its machine address, so that neither holds the other's code;
and the law of a ContactLaw packed for it (``law_bundle``)."""
from __future__ import annotations

from collections import namedtuple

from numba import njit, types
from numba.extending import intrinsic, overload

from exu_aniso.kernel.compiling import compiled_address, register_kernel
from exu_aniso.kernel.point import LawParams, contact_force, point_tangent, put_row, row_at
from exu_aniso.kernel.sets import S_LAW, Y_DV, Y_F, Y_GAP, Y_INFO, Y_KX, Y_V, Y_X
from exu_aniso.kernel.sets import point_states as sets_point_states
from exu_aniso.kernel.stored import StoredArguments, _deref
from exu_aniso.law.history import UNRESOLVED
from exu_aniso.law.return_maps import MAPS

CovariantLaw = namedtuple("CovariantLaw", ("surface", "adhesion", "friction", "law"))


# The law of a set's kernel: contact_force inlined into one loop over the points, and a Jacobian call's
# point_tangent in a second loop, in a function of its own compiled once per law (tangent a run-time
# flag). Inlined into every loop of the set kernels instead (and with derivatives), the law was copied
# and compiled several times per kernel: the block's first compilation 35 -> 24 s.
@overload(sets_point_states)
def _point_states_covariant(law, Y, H, Hn, first, count, dt, tangent, S):
    if getattr(law, "instance_class", None) is CovariantLaw:
        def impl(law, Y, H, Hn, first, count, dt, tangent, S):
            W = S[S_LAW:S_LAW + 3]
            dT = W[0, 0:2, :]
            sp, netB, netF, lp = law.surface, law.adhesion, law.friction, law.law
            ncontact = 0
            unresolved = False
            for k in range(first, first + count):
                # by element, no view of a row (see history_row)
                x = (Y[k, Y_X, 0], Y[k, Y_X, 1], Y[k, Y_X, 2])
                v = (Y[k, Y_V, 0], Y[k, Y_V, 1], Y[k, Y_V, 2])
                st, xi3, state, f, hn = contact_force(sp, netB, netF, lp, x, v, row_at(H, k), dt, dT)
                Y[k, Y_F, 0], Y[k, Y_F, 1], Y[k, Y_F, 2] = f[0], f[1], f[2]
                Y[k, Y_INFO, 2] = st
                Y[k, Y_GAP, 0] = xi3
                ncontact += st > 0
                unresolved |= st == UNRESOLVED
                if tangent:                # the state for the second loop, in the rows of df/dx and df/dv;
                    _put_state(Y, k, state)    # a Jacobian call keeps the last residual's candidate
                else:
                    put_row(Hn, k, hn)
            if tangent:
                for k in range(first, first + count):
                    state = _get_state(Y, k)
                    point_tangent(sp, netB, netF, lp, state, Y[k, Y_KX:Y_KX + 3], Y[k, Y_DV:Y_DV + 3], W)
            return ncontact, unresolved
        return impl
    return None


# ----------------------------------------------------------------------------------------------
# A set's kernel calls its law through an address: the set kernels (kernel.sets, below) are compiled
# once per node kind and the law (law_entry) once per surface, nets and return map, and neither holds
# the other's code. Compiled into one unit per (law, node kind), every new pairing compiled the set
# kernel again (docs/guide/decisions.md).

LawCall = namedtuple("LawCall", ("entry", "law"))
LawCall.__doc__ = """What a set's kernel gets for its law, two int64 addresses: ``entry``, the machine code of
law_entry compiled for the law bundle's type; ``law``, the bundle stored (kernel.stored.StoredArguments)."""

_F3, _F2 = types.float64[:, :, ::1], types.float64[:, ::1]
# law_entry's arguments after the bundle's pointer: Y, H, Hn, first, count, dt, tangent, S (kernel.sets.point_states)
LAW_ARGS = (_F3, _F2, _F2, types.int64, types.int64, types.float64, types.boolean, _F3)


@njit(cache=True)
def law_entry(law, Y, H, Hn, first, count, dt, tangent, S):
    """kernel.sets.point_states of the law bundle at the pointer ``law`` (a CPointer of its type): the
    number of points in contact, or -1 minus that number when a point's step is unresolved."""
    ncontact, unresolved = sets_point_states(_deref(law), Y, H, Hn, first, count, dt, tangent, S)
    return -1 - ncontact if unresolved else ncontact


@intrinsic
def _call_law(typingctx, entry, law, Y, H, Hn, first, count, dt, tangent, S):
    """law_entry at the address ``entry`` with the bundle stored at ``law`` and the rest of its
    arguments (LAW_ARGS: C-contiguous arrays): its result. An exception it raises propagates to the
    caller with its message."""
    for name, got, want in (("Y", Y, _F3), ("H", H, _F2), ("Hn", Hn, _F2), ("S", S, _F3)):
        if not (isinstance(got, types.Array) and got.ndim == want.ndim and got.dtype == want.dtype
                and got.layout == "C"):
            raise TypeError(f"the law's call: {name} is {got}, law_entry takes {want}")
    argtys = (types.voidptr,) + LAW_ARGS

    def codegen(context, builder, sig, llargs):
        fnty = context.call_conv.get_function_type(types.int64, argtys)
        fn = builder.inttoptr(llargs[0], fnty.as_pointer())
        args = [builder.inttoptr(llargs[1], context.get_value_type(types.voidptr))]
        args += [context.cast(builder, v, t, want) for v, t, want in zip(llargs[2:], sig.args[2:], LAW_ARGS)]
        status, result = context.call_conv.call_function(builder, fn, types.int64, argtys, args)
        with builder.if_then(status.is_error, likely=False):
            context.call_conv.return_status_propagate(builder, status)
        return result
    return types.int64(entry, law, Y, H, Hn, first, count, dt, tangent, S), codegen


@overload(sets_point_states)
def _point_states_called(law, Y, H, Hn, first, count, dt, tangent, S):
    if getattr(law, "instance_class", None) is LawCall:
        def impl(law, Y, H, Hn, first, count, dt, tangent, S):
            r = _call_law(law.entry, law.law, Y, H, Hn, first, count, dt, tangent, S)
            return (-1 - r, True) if r < 0 else (r, False)
        return impl
    return None


@njit(cache=True)
def call_law(law, Y, H, Hn, first, count, dt, tangent, S):
    """kernel.sets.point_states through a LawCall ``law``, for a Python caller (ContactLaw.evaluate):
    compiled once, whatever the law; returns (points in contact, any unresolved)."""
    return sets_point_states(law, Y, H, Hn, first, count, dt, tangent, S)


def law_call(bundle):
    """The law bundle (law_bundle) stored, and law_entry compiled for its type (or loaded from the
    cache; announced when it compiles): (LawCall, the stored bundle, which must outlive every call)."""
    stored = StoredArguments(bundle)
    address = compiled_address(law_entry, (types.CPointer(stored.type),) + LAW_ARGS, (bundle,))
    return LawCall(address, stored.address), stored


@njit(cache=True, inline="always")
def _put_state(Y, k, state):
    """contact_force's state of point k (15 numbers) into the 5 rows from Y[k, Y_KX] (df/dx and df/dv's
    rows, written after it is read)."""
    for i in range(15):
        Y[k, Y_KX + i // 3, i % 3] = state[i]


@njit(cache=True, inline="always")
def _get_state(Y, k):
    """The state _put_state wrote."""
    r = Y[k]
    a, b, c, d, e = r[Y_KX], r[Y_KX + 1], r[Y_KX + 2], r[Y_KX + 3], r[Y_KX + 4]
    return (a[0], a[1], a[2], b[0], b[1], b[2], c[0], c[1], c[2], d[0], d[1], d[2], e[0], e[1], e[2])


def law_params(contact_law):
    """The law parameters of a ContactLaw for the kernel (LawParams: penalty, dashpots, the return map
    as its type, law.return_maps.MAPS)."""
    return LawParams(float(contact_law.eps_N), float(contact_law.d_N), float(contact_law.d_T),
                     MAPS[contact_law.return_map])


def law_bundle(contact_law):
    """The law of a ContactLaw packed for the compiled kernels (surface, nets, law parameters; named tuples)."""
    nB, nF = contact_law._nets
    return CovariantLaw(contact_law.surface.params, nB, nF, law_params(contact_law))


def _law_name(args, entry):
    """A law's compiled code in words: its surface, nets and return map."""
    law = next((a for a in args if isinstance(a, CovariantLaw)), None)
    if law is None:
        return "a contact law"
    return (f"the contact law for {type(law.surface).__name__.replace('Params', '')}, "
            f"{type(law.adhesion).__name__} adhesion, {type(law.friction).__name__} friction, "
            f"{type(law.law.method).__name__.lower()} map")


register_kernel(law_entry, "law", _law_name)
