"""The contact sets packed for their compiled call: the points, the history, the scratch and the
outputs of a set on one node kind (``CovariantSet``), on a moving master (``CovariantPairSet``) and on
a group of nodes (``CovariantGroupSet``), and the set kernels of ``kernel.sets`` with the law's call
(``law_call``) at every point (``evaluate_covariant`` and its group, linear and pair forms).

Call modes (``mode``): FORCE (0) the generalized force and the history candidate, JACOBIAN (1) the
Jacobian, CANDIDATE (2) the history candidate alone (``kernel.sets``)."""
from __future__ import annotations

import numpy as np
from numba import njit

from exu_aniso.kernel.compiling import entry_point, register_kernel
from exu_aniso.kernel.law_call import law_bundle, law_call
from exu_aniso.kernel.nodes import NODE_KINDS, LinearSlave, node_coordinates_of
from exu_aniso.kernel.sets import (FORCE, S_J, S_VEC, Y_ROWS, LinearMap, evaluate_group, evaluate_linear,
                                   evaluate_pair, evaluate_set)


@njit(cache=True, inline="always")
def _remember(mode, q, q_t, X):
    """Mode FORCE (a residual) keeps its state in X (2, n): the candidate in P[2] belongs to it."""
    if mode == FORCE:
        for i in range(q.shape[0]):
            X[0, i] = q[i]
            X[1, i] = q_t[i]


@njit(cache=True)
def evaluate_covariant(mode, q, q_t, fq, fv, dt, H, ref, law, P, S, Y, X, kind):
    """kernel.sets.evaluate_set (modes 0 force, 1 Jacobian, 2 history candidate) with the covariant
    kernel at every point. H (K, 9): the converged history (the Exudyn adapter passes a view of
    Exudyn's StartOfStep data coordinates: nothing is copied per step); P (3, K, 9): body-local
    points, a history buffer for callers without one (CovariantSet.H), the candidate; Y (K, Y_ROWS, 3):
    the point buffer (kernel.sets.point_states); X (2, n): the state (q, q_t) of the last mode-0
    call, whose candidate P[2] holds."""
    nq = q.shape[0]
    _remember(mode, q, q_t, X)
    return evaluate_set(kind, q, q_t, ref, P[0, :, :3], H, law, mode, fq, fv, dt, S[S_VEC, 6, :nq],
                        S[S_J, :nq, :nq], P[2], S, Y)


@njit(cache=True)
def evaluate_covariant_group(mode, q, q_t, fq, fv, dt, H, ref, law, P, S, Y, X, kind, Q, Jb):
    """kernel.sets.evaluate_group (the same points on nb rigid nodes) with the covariant kernel; P (3,
    nb * Kb, 9) with the body-local points in the first Kb rows of P[0]; Jb (nb, nq, nq)."""
    _remember(mode, q, q_t, X)
    Kb = P.shape[1] // Jb.shape[0]
    return evaluate_group(kind, q, q_t, ref, P[0, :Kb, :3], H, law, mode, fq, fv, dt, Q, Jb, P[2], S, Y)


@njit(cache=True)
def evaluate_covariant_linear(mode, q, q_t, fq, fv, dt, H, ref, law, P, S, Y, X, idx, Sm, c, Q, J):
    """kernel.sets.evaluate_linear (a linear slave: mass points, ANCF cables) with the covariant kernel."""
    _remember(mode, q, q_t, X)
    return evaluate_linear(q, q_t, ref, idx, Sm, c, H, law, mode, fq, fv, dt, Q, J, P[2], S, Y)


@njit(cache=True)
def evaluate_covariant_pair(mode, q, q_t, fq, fv, dt, H, ref, law, P, S, Y, X, T, kind, mkind, idx, Sm, c, cols, Q,
                            J):
    """kernel.sets.evaluate_pair (a moving master: the surface on a 3D rigid node) with the covariant kernel;
    P, Y, X as evaluate_covariant."""
    _remember(mode, q, q_t, X)
    return evaluate_pair(kind, mkind, q, q_t, ref, P[0, :, :3], idx, Sm, c, H, law, mode, fq, fv, dt, Q, J, P[2],
                         S, T, cols, Y)


class CovariantSet:
    """A contact set on the covariant kernel packed for the compiled call: the law (``bundle``: surface,
    nets, law parameters as named tuples; ``law``: the LawCall the set's kernel gets), points, history
    and outputs. Views: H (converged history, written by the caller), Q, J, Hn."""

    def __init__(self, contact_law, node_kind, ref, points):
        self._take_law(contact_law)
        self.linear = node_kind if isinstance(node_kind, LinearMap) else None
        if self.linear is not None:     # node_kind: a LinearMap (mass points, cables); points unused
            self.kind, nq = LinearSlave(), self.linear.n
            b = np.zeros((self.linear.idx.shape[0], 3))
        else:
            self.kind = NODE_KINDS[node_kind]
            nq = node_coordinates_of(self.kind)
            b = np.asarray(points, dtype=float)
        self.ref = np.asarray(ref, dtype=float)
        self._buffers(b, nq)
        if self.linear is not None:
            self.Q, self.J = np.zeros(nq), np.zeros((nq, nq))
        else:
            self.Q = self.S[S_VEC, 6, :nq]
            self.J = self.S[S_J, :nq, :nq]

        if self.linear is not None:
            lm = self.linear
            self._fn, self.tail = evaluate_covariant_linear, (self.ref, self.law, self.P, self.S, self.Y, self.X,
                                                                lm.idx, lm.S, lm.c, self.Q, self.J)
        else:
            self._fn, self.tail = evaluate_covariant, (self.ref, self.law, self.P, self.S, self.Y, self.X, self.kind)
        self._entry = None

    def _take_law(self, contact_law):
        """The law bundle (``bundle``), its call for the set's kernel (``law``, law_call) and the stored
        bundle the call reads, held as long as the set."""
        self.bundle = law_bundle(contact_law)
        self.law, self._stored_law = law_call(self.bundle)

    def _buffers(self, b, n):
        """The packed arrays of K points b (K, 3) over n coordinates: P (3, K, 9) (points, converged
        history H, candidate Hn), the scratch S, the point buffer Y (K, Y_ROWS, 3) and X (2, n),
        the state (q, q_t) of the last residual (mode 0), whose candidate Hn holds."""
        from exu_aniso.kernel.sets import SCRATCH_SLOTS
        self.P = np.zeros((3, b.shape[0], 9))
        self.P[0, :, :3] = b
        self.S = np.zeros((SCRATCH_SLOTS, 9, 9))
        self.H, self.Hn = self.P[1], self.P[2]
        self.Y = np.zeros((b.shape[0], Y_ROWS, 3))
        self.X = np.full((2, n), np.nan)

    def evaluate(self, mode, q, q_t, fq, fv, dt):
        """One compiled call (mode: see evaluate_covariant); q, q_t: the set's coordinates. Returns
        the number of points in contact, or -1 when a point's motion in the step is unresolved."""
        q = np.ascontiguousarray(q, dtype=np.float64)
        q_t = np.ascontiguousarray(q_t, dtype=np.float64)
        return self.entry()(int(mode), q, q_t, float(fq), float(fv), float(dt), self.H, *self.tail)

    def entry(self):
        """The compiled function for this set's argument types (``compiling.entry_point``): callers that
        pass C-contiguous float64 q, q_t, an int mode, float fq, fv, dt and a C-contiguous (K, 9)
        float64 history H may call ``entry()(mode, q, q_t, fq, fv, dt, H, *tail)`` directly (the
        Exudyn adapter does, with H a view of Exudyn's StartOfStep data coordinates)."""
        if self._entry is None:
            z = np.zeros(self.X.shape[1])
            self._entry = entry_point(self._fn, (FORCE, z, z, 0.0, 0.0, 0.0, self.H) + self.tail)
        return self._entry


class CovariantPairSet(CovariantSet):
    """A contact set with a moving master (the surface carried by a 3D rigid node) packed for
    kernel.sets.evaluate_pair: the slave (node_kind: a rigid kind's name, or a LinearMap for mass
    points and cables, with the slave's reference coordinates ref) and the master (master_kind
    "RigidBodyRotVecLG" or "RigidBodyEP", reference coordinates master_ref); coordinates are the
    slave's then the master's. The same interface as CovariantSet: H, Q (n,), J (n, n), Hn, X, tail,
    evaluate, entry."""

    def __init__(self, contact_law, node_kind, ref, points, master_kind, master_ref):
        from exu_aniso.kernel.sets import PAIR_SLOTS
        if master_kind not in ("RigidBodyRotVecLG", "RigidBodyEP"):
            raise ValueError(f"a moving master is a 3D rigid node (RigidBodyRotVecLG or RigidBodyEP); got {master_kind!r}")
        self._take_law(contact_law)
        self.mkind = NODE_KINDS[master_kind]
        nm = node_coordinates_of(self.mkind)
        self.linear = node_kind if isinstance(node_kind, LinearMap) else None
        if self.linear is not None:
            lm = self.linear
            self.kind, ns, m = LinearSlave(), lm.n, lm.idx.shape[1]
            b = np.zeros((lm.idx.shape[0], 3))
            idx, Sm, c = lm.idx, lm.S, lm.c
        else:
            self.kind = NODE_KINDS[node_kind]
            ns = m = node_coordinates_of(self.kind)
            b = np.asarray(points, dtype=float)
            idx, Sm, c = np.zeros((b.shape[0], 0), dtype=np.int64), np.zeros((b.shape[0], 3, 0)), np.zeros((b.shape[0], 3))
        n = ns + nm
        self.ref = np.ascontiguousarray(np.concatenate([np.asarray(ref, dtype=float), np.asarray(master_ref, dtype=float)]))
        if self.ref.shape != (n,):
            raise ValueError(f"reference coordinates: {self.ref.shape[0]} for {ns} slave and {nm} master coordinates")
        self._buffers(b, n)
        w = max(9, m + nm)
        self.T = np.zeros((PAIR_SLOTS, w, w))
        self.cols = np.zeros(m + nm, dtype=np.int64)
        self.Q, self.J = np.zeros(n), np.zeros((n, n))
        self._fn = evaluate_covariant_pair
        self.tail = (self.ref, self.law, self.P, self.S, self.Y, self.X, self.T, self.kind, self.mkind, idx, Sm, c,
                     self.cols, self.Q, self.J)
        self._entry = None


class CovariantGroupSet(CovariantSet):
    """A group: the same body-local points on nb rigid nodes of one kind (node_kind), packed for
    kernel.sets.evaluate_group; ref: the nodes' reference coordinates one after the other. The same
    interface as CovariantSet (H, Hn: nb * K rows, body by body; Q (nb * nq,)), but the Jacobian is
    Jb (nb, nq, nq), its diagonal blocks, and J is a scipy CSR matrix over Jb's memory (what the
    Exudyn adapter returns: Exudyn adds its nb * nq^2 entries, not (nb nq)^2)."""

    def __init__(self, contact_law, node_kind, ref, points, nb):
        import scipy.sparse as sp

        self._take_law(contact_law)
        self.linear = None
        self.kind = NODE_KINDS[node_kind]
        nq = node_coordinates_of(self.kind)
        n = nb * nq
        b = np.asarray(points, dtype=float)
        self.ref = np.ascontiguousarray(ref, dtype=float)
        if self.ref.shape != (n,):
            raise ValueError(f"reference coordinates: {self.ref.shape[0]} for {nb} nodes of {nq} coordinates")
        self._buffers(np.tile(b, (nb, 1)), n)
        self.Q = np.zeros(n)
        self.Jb = np.zeros((nb, nq, nq))
        rows = np.arange(n)
        indices = (rows // nq * nq)[:, None] + np.arange(nq)[None, :]       # row i: its body's nq columns
        self.J = sp.csr_matrix((self.Jb.reshape(-1), indices.reshape(-1), np.arange(0, n * nq + 1, nq)),
                               shape=(n, n), copy=False)
        if not np.shares_memory(self.J.data, self.Jb):                       # scipy copied: J would go stale
            raise RuntimeError("scipy.sparse.csr_matrix copied the Jacobian blocks; the group needs a view")
        self._fn, self.tail = evaluate_covariant_group, (self.ref, self.law, self.P, self.S, self.Y, self.X, self.kind, self.Q,
                                                         self.Jb)
        self._entry = None


NODE_KINDS_MODULE = LinearSlave.__module__


def _a(word):
    return ("an " if word[0].lower() in "aeiou" else "a ") + word


def _set_name(args, entry):
    """A set kernel in words: the node kinds its arguments specialise it for."""
    kinds = [type(a).__name__ for a in args if type(a).__module__ == NODE_KINDS_MODULE]
    if not kinds or kinds == ["LinearSlave"]:      # mass points, cables, a finite-element body's nodes
        nodes = "a linear slave"
    elif entry is evaluate_covariant_group:
        nodes = f"a group of {kinds[0]} nodes"
    elif len(kinds) == 1:
        nodes = f"{_a(kinds[0])} node"
    else:
        nodes = f"{_a(kinds[0].replace('LinearSlave', 'linear'))} slave on {_a(kinds[-1])} master"
    return f"the contact set kernel for {nodes}"


for _entry in (evaluate_covariant, evaluate_covariant_group, evaluate_covariant_linear):
    register_kernel(_entry, "fixed", _set_name)
register_kernel(evaluate_covariant_pair, "moving", _set_name)
