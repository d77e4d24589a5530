"""A contact set: one Exudyn ObjectGenericODE2 between a slave and a ContactLaw, its force and
Jacobian user functions, and the history it stages at a converged step. ``ContactSet`` evaluates
the law with numpy (any slave, any master); ``CompiledSet`` (ground master), ``CompiledPairSet``
(moving master) and ``CompiledGroupSet`` (a group of rigid bodies) call the compiled kernel
(exu_aniso.kernel.sets) on Exudyn's own vectors (``SystemViews``), through the native callbacks where
they are built; ``CompiledPointLaw`` is the law at free points through that kernel, for a slave the
kernel has no node kind for."""
from __future__ import annotations

import math
from typing import NamedTuple

import exudyn as exu
import numpy as np

from exu_aniso.engines.exudyn_adapter.native_callbacks import Delegate, extension
from exu_aniso.kernel.native import NativeBlock
from exu_aniso.kernel.compiling import entry_point
from exu_aniso.kernel.sets import CANDIDATE, FORCE, JACOBIAN, gather_coordinates, stage_candidate
from exu_aniso.law.history import HISTORY_FIELDS, N_HISTORY, UNRESOLVED

_SOS = exu.ConfigurationType.StartOfStep
_CUR = exu.ConfigurationType.Current
_STATUS = HISTORY_FIELDS.index("status")
_DISSIPATED = HISTORY_FIELDS.index("dissipated_energy")


class CompiledPointLaw:
    """The contact law at K points through the compiled kernel, for a slave whose kinematics the
    kernel has no node kind for (the floating frame): the set kernel of K free points (a linear
    slave over 3K coordinates, x_k = q[3k:3k+3], S = I), so that one compiled call gives the point
    forces (FORCE: Q = f), and df/dx, df/dv as its Jacobian's diagonal blocks (JACOBIAN with (fq, fv)
    = (1, 0) and (0, 1)). evaluate() answers as ContactLaw.evaluate for what the contact set reads (force,
    stiffness, damping, history and its status)."""

    def __init__(self, law, K):
        from exu_aniso.kernel.packed_sets import CovariantSet
        from exu_aniso.kernel.sets import LinearMap
        idx = np.arange(3 * K, dtype=np.int64).reshape(K, 3)
        self.K = K
        self.pk = CovariantSet(law, LinearMap(idx, np.broadcast_to(np.eye(3), (K, 3, 3)), np.zeros((K, 3)), 3 * K),
                               np.zeros(3 * K), None)
        self.damped = law.d_N > 0.0 or law.d_T > 0.0
        self._blocks = (np.arange(3 * K).reshape(K, 3)[:, :, None], np.arange(3 * K).reshape(K, 3)[:, None, :])

    def evaluate(self, x, v, history, tangent=True, dt=None):
        pk, K = self.pk, self.K
        pk.H[:] = 0.0 if history is None else np.reshape(history, (K, N_HISTORY))
        q, q_t = np.ascontiguousarray(x, dtype=float).ravel(), np.ascontiguousarray(v, dtype=float).ravel()
        dt = 0.0 if dt is None else float(dt)
        pk.evaluate(FORCE, q, q_t, 0.0, 0.0, dt)
        force, history = pk.Q.reshape(K, 3).copy(), pk.Hn.copy()
        stiffness = damping = None
        if tangent:
            pk.evaluate(JACOBIAN, q, q_t, 1.0, 0.0, dt)
            stiffness = -pk.J[self._blocks]
            damping = np.zeros((K, 3, 3))
            if self.damped:
                pk.evaluate(JACOBIAN, q, q_t, 0.0, 1.0, dt)
                damping = -pk.J[self._blocks]
        return PointStates(force, stiffness, damping, history)


class PointStates(NamedTuple):
    """What CompiledPointLaw.evaluate gives: force (K, 3) [N], stiffness = df/dx and damping =
    df/dv (K, 3, 3) or None, the history candidate (K, 9)."""
    force: np.ndarray
    stiffness: np.ndarray
    damping: np.ndarray
    history: np.ndarray

    @property
    def status(self):
        """Each point's state (K,) int: OPEN, STICK, SLIP or UNRESOLVED (law.history)."""
        return self.history[:, _STATUS].astype(int)



class PointTangent(NamedTuple):
    """q-derivatives of the slave point kinematics for the Jacobian: dx (K, 3, n) = dx/dq,
    geometric (n, n) = sum_k f_k . dJp_k/dq at the point forces f and dv (K, 3, n) = dv/dq at fixed
    q_t = dJp/dq q_t (the slave's tangent_terms; both None for a linear slave, whose Jp is constant),
    and the law's damping Dv = df/dv (K, 3, 3). dx equals Jp except for Euler parameters: x = p + A(e)
    b with A quadratic in e, so along e itself dx/de e = 2 A b while the virtual-work Jacobian
    -A [b]x G(e) e = 0 (the unit norm is Exudyn's separate constraint)."""
    dx: np.ndarray
    geometric: np.ndarray
    dv: np.ndarray
    damping: np.ndarray


class ContactSet:
    """One contact set: the GenericODE2 object between a slave and a ContactLaw, evaluated with numpy
    (state-free: the history lives in Exudyn's data node)."""

    force_calls = 0             # calls of the force user function Exudyn made (each costs Exudyn 2 vectors)
    _native = None              # kernel.native.NativeBlock when Exudyn calls the native force (CompiledSet)
    point_law = None            # CompiledPointLaw: the law at the points through the compiled kernel (else law)

    def __init__(self, mbs, law, slave, points, master):
        self.law = law
        self.slave = slave
        self.points = points
        self.master = master
        self.K = slave.number_of_points(points)
        self.nData = None

    def native_calls(self):
        """(native, delegated) force calls of this set so far: none on the numpy route."""
        return 0, 0

    def disarm(self):
        """Nothing to disarm on the numpy route (CompiledSet.disarm)."""

    def _split(self, q, q_t):
        ns = self.slave.n
        return q[:ns], q_t[:ns], q[ns:], q_t[ns:]

    def initial_history(self, q, q_t):
        """The history (K * 9,) of the points at the initial coordinates q, q_t (the set's): the
        candidate from a history of zeros, so that points in contact start sticking there."""
        return self.state(None, q, q_t, None, tangent=False)[0].history.ravel()

    def state(self, mbs, q, q_t, history, tangent, dt=None):
        """Evaluate the law (dt: time since the converged history, see ContactLaw.evaluate); returns
        (ContactState, slave Jp, F_global, master Jp or None, tangent data of the slave points for
        _add_geometric: PointTangent when tangent and the master is ground, else None)."""
        qs, vs, qm, vm = self._split(q, q_t)
        x, v, Jp, _ = self.slave.points(qs, vs, self.points)
        if self.master is None:
            st = (self.point_law or self.law).evaluate(x, v, history, tangent, dt)
            tg = None
            if tangent and self.slave.linear:          # Jp constant: dx/dq = Jp, dJp/dq = 0
                tg = PointTangent(Jp, None, None, st.damping)
            elif tangent:
                geo, dv = self.slave.tangent_terms(qs, vs, self.points, st.force)
                tg = PointTangent(self.slave.position_jacobian(qs, self.points, Jp), geo, dv, st.damping)
            return st, Jp, st.force, None, tg
        p, A, w, vp = self.master.frame(qm, vm)
        d = x - p
        x_rel = d @ A
        v_rel = (v - vp - np.cross(w, d)) @ A
        st = self.law.evaluate(x_rel, v_rel, history, tangent, dt)
        F = st.force @ A.T
        b_master = x_rel                       # reaction at the master's material point at S
        Jm = self.master.points(qm, vm, b_master)[2]
        return st, Jp, F, Jm, None

    def history(self, mbs, configuration):
        h = mbs.GetNodeOutput(self.nData, exu.OutputVariableType.Coordinates, configuration=configuration)
        return np.asarray(h, dtype=float).reshape(self.K, N_HISTORY)

    # --- read-only views for graphics and post-processing (never called by the solver) -----------
    def history_at(self, mbs, configuration=None):
        """History (K, 9) in an exu.ConfigurationType (e.g. Visualization: what the renderer and the
        SolutionViewer show); None: the initial history given to the node (works before Assemble)."""
        if configuration is None:
            return np.asarray(mbs.GetNodeParameter(self.nData, "initialCoordinates"), dtype=float).reshape(
                self.K, N_HISTORY)
        return self.history(mbs, configuration)

    def points_and_master_pose(self, mbs, configuration=None):
        """Slave points in the master frame (K, 3) and the master's pose: position (3,) and rotation
        matrix (3, 3) (master frame -> global; the origin and the identity for a ground master), in an
        exu.ConfigurationType; None: the nodes' initial coordinates (works before Assemble). Global
        positions are p + A x. Positions only: the law is not evaluated."""
        def coordinates(nd):
            if configuration is None:
                return nd.q0
            return nd.coordinates(mbs, exu.OutputVariableType.Coordinates, configuration)
        x = self.slave.points(coordinates(self.slave), np.zeros(self.slave.n), self.points)[0]
        if self.master is None:
            return x, np.zeros(3), np.eye(3)
        p, A, _, _ = self.master.frame(coordinates(self.master), np.zeros(self.master.n))
        return (x - p) @ A, np.array(p, dtype=float), A

    def body_position(self, mbs, configuration=None):
        """Global position (3,) of the slave body's local origin (node reference point; the joint
        origin of a screw-joint node; the start of the first element of a cable) in a configuration
        (None: initial coordinates)."""
        q = self.slave.q0 if configuration is None else self.slave.coordinates(
            mbs, exu.OutputVariableType.Coordinates, configuration)
        return self.slave.points(q, np.zeros(self.slave.n), np.zeros((1, 3)))[0][0]

    @staticmethod
    def step_time(mbs, t):
        """Time since the start of the step [s] (the age of the converged history)."""
        return t - mbs.systemData.GetTime(_SOS)

    def force(self, mbs, t, itemNumber, q, q_t):
        self.force_calls += 1
        st, Jp, F, Jm, _ = self.state(mbs, q, q_t, self.history(mbs, _SOS), tangent=False, dt=self.step_time(mbs, t))
        Q = F.reshape(-1) @ Jp.reshape(-1, Jp.shape[2])                 # sum_k Jp_k^T F_k
        if Jm is not None:
            Q = np.concatenate([Q, -np.einsum("kij,ki->j", Jm, F)])
        return Q.tolist()

    def generalized_force(self, q, q_t, history):
        """The contact object's generalized force Q over its coordinates at q, q_t (the set's
        coordinates, reference values excluded) from the converged history (K, 9), as a residual of
        the solver with no time elapsed since that history (post-processing: what the solver saw).
        Samples at once: q, q_t (n, nq) and history (n, K, 9) or (n, K*9) give Q (n, nq)."""
        q, q_t, H = np.asarray(q, dtype=float), np.asarray(q_t, dtype=float), np.asarray(history, dtype=float)
        if q.ndim == 1:
            return self._generalized_force(q, q_t, H.reshape(-1, N_HISTORY))
        if q.ndim != 2 or q_t.shape != q.shape or H.size != len(q) * self.K * N_HISTORY:
            raise ValueError(f"generalizedForce: q, q_t (n, nq) and history (n, K, {N_HISTORY}) over the same "
                             f"samples, K = {self.K}; got q {q.shape}, q_t {q_t.shape}, history {H.shape}")
        return self._sample_forces(q, q_t, H.reshape(len(q), self.K, N_HISTORY))

    def _generalized_force(self, q, q_t, H):
        _, Jp, F, Jm, _ = self.state(None, q, q_t, H, tangent=False, dt=0.0)
        Q = F.reshape(-1) @ Jp.reshape(-1, Jp.shape[2])
        return Q if Jm is None else np.concatenate([Q, -np.einsum("kij,ki->j", Jm, F)])

    def _sample_forces(self, q, q_t, H):
        return np.array([self._generalized_force(q[n], q_t[n], H[n]) for n in range(len(q))])

    def jacobian(self, mbs, t, itemNumber, q, q_t, fODE2, fODE2_t):
        """-(fODE2 dQ/dq + fODE2_t dQ/dq_t) of Q = sum_k Jp_k^T f_k(x_k, v_k) (ground master)."""
        st, Jp, _, _, tg = self.state(mbs, q, q_t, self.history(mbs, _SOS), tangent=True, dt=self.step_time(mbs, t))
        n = Jp.shape[2]
        rows = Jp.reshape(-1, n).T                                       # sum_k Jp_k^T M_k R_k as one product
        Kq = rows @ (st.stiffness @ tg.dx).reshape(-1, n)
        Dq = rows @ (st.damping @ Jp).reshape(-1, n)
        self._add_geometric(Kq, Jp, tg)
        return -(fODE2 * Kq + fODE2_t * Dq)

    @staticmethod
    def _add_geometric(Kq, Jp, tg):
        """Add the terms of dQ/dq that come from Jp depending on q (every node type; tg: the
        PointTangent of state()). With v = Jp q_t and f = f(x, v):

            dQ/dq = sum_k Jp^T Kx Jp + sum_k f . dJp/dq + sum_k Jp^T Dv (dJp/dq q_t),

        the first (law stiffness) is in Kq already; the second is the lever arms turning at fixed
        point forces (the reference's geometric term), the third the point velocities turning
        with the body (nonzero only with normal damping: Dv = df/dv). A linear slave has none."""
        if tg.geometric is None:
            return
        Kq += tg.geometric
        if np.any(tg.damping):
            n = Jp.shape[2]
            Kq += Jp.reshape(-1, n).T @ (tg.damping @ tg.dv).reshape(-1, n)

    def candidate(self, mbs, t, q, q_t):
        """The history candidate (K, 9) at the converged state q, q_t (the set's coordinates) at time
        t, or None when a contact point's motion in the step is unresolved."""
        H = self.state(mbs, q, q_t, self.history(mbs, _SOS), tangent=False, dt=self.step_time(mbs, t))[0].history
        return None if np.any(H[:, _STATUS] == UNRESOLVED) else H

    def stage(self, mbs, t):
        """Put the history candidate at the converged state (Exudyn's Current coordinates) at time t
        into the Current data coordinates, in place; False (nothing written) when a point's step is
        unresolved. The numpy route fetches the views and its indices afresh at every commit (its
        own cost is far above theirs), so it never holds a view across a re-assembly."""
        self._indices(mbs)
        V = SystemViews(mbs)
        self._check_indices(V)
        H = self.candidate(mbs, t, V.q[self.ltgODE2], V.q_t[self.ltgODE2])
        if H is None:
            return False
        V.data[self.ltg] = H.ravel()
        V.data[self.ltgTotal] = H[:, _DISSIPATED].sum()
        return True

    def locate(self, mbs, oContact):
        """Remember where the set's coordinates and history live in the system vectors (after
        Assemble): ODE2 indices of the contact object, data indices of the history and total."""
        self.oContact = oContact
        self.ltgODE2 = None

    def _indices(self, mbs):
        self.ltgODE2 = np.asarray(mbs.systemData.GetObjectLTGODE2(self.oContact), dtype=np.int64)
        self.ltg = np.asarray(mbs.systemData.GetNodeLTGData(self.nData), dtype=np.int64)
        self.ltgTotal = int(mbs.systemData.GetNodeLTGData(self.nTotal)[0])

    def _check_indices(self, V):
        """Assert that the set's indices lie in the system vectors of the views V: the object's
        coordinates (slave, then master), the history (one range of K * 9 data coordinates) and
        the total dissipation (one data coordinate)."""
        n = self.slave.n + (self.master.n if self.master is not None else 0)
        assert self.ltgODE2.shape == (n,) and 0 <= self.ltgODE2.min() and self.ltgODE2.max() < V.q.size, \
            (self.ltgODE2, V.sizes)
        assert np.array_equal(self.ltg, self.ltg[0] + np.arange(self.K * N_HISTORY)), self.ltg
        assert 0 <= self.ltg[0] and self.ltg[-1] < V.data.size and 0 <= self.ltgTotal < V.data.size, V.sizes


class SystemViews:
    """numpy views of Exudyn's own system vectors (``copy=False``, Exudyn 1.13): the Current ODE2
    coordinates q [m, rad] and velocities q_t [m/s, rad/s], the Current data coordinates and the
    StartOfStep data coordinates. Writing into them writes into Exudyn's memory. They stay valid
    through solves and through re-assemblies of the same sizes; Exudyn reallocates a vector when
    it grows (Assemble of a larger system), so a holder compares ``sizes`` (ODE2, data) with the
    system's before it uses them again (CompiledSet._load_history)."""

    def __init__(self, mbs):
        sd = mbs.systemData
        self.sizes = (sd.ODE2Size(), sd.DataSize())
        self.q = sd.GetODE2Coordinates(configuration=_CUR, copy=False)
        self.q_t = sd.GetODE2Coordinates_t(configuration=_CUR, copy=False)
        self.data = sd.GetDataCoordinates(configuration=_CUR, copy=False)
        self.data0 = sd.GetDataCoordinates(configuration=_SOS, copy=False)
        for v, size in ((self.q, self.sizes[0]), (self.q_t, self.sizes[0]), (self.data, self.sizes[1]),
                        (self.data0, self.sizes[1])):
            assert v.shape == (size,) and v.dtype == np.float64 and v.flags.c_contiguous and v.flags.writeable, \
                (v.shape, v.dtype, v.flags, self.sizes)

    def current(self, mbs):
        """True while the system's sizes (ODE2, data) are those at fetch time. With the new-solve rule
        of CompiledSet._load_history this misses only a system re-assembled smaller and then back
        to the same sizes between two solves, the second starting at the first one's last commit."""
        sd = mbs.systemData
        return sd.ODE2Size() == self.sizes[0] and sd.DataSize() == self.sizes[1]


class CompiledSet(ContactSet):
    """The same contact set evaluated by the compiled kernel ``exu_aniso.kernel.sets`` (ground
    master, a surface numba compiles): one compiled call per user function on arrays packed once
    (``kernel.CovariantSet``).

    What is not recomputed or copied:
    * the converged history is not copied: the kernel reads it from the StartOfStep data
      coordinates (a view of Exudyn's vector, which changes only when a step is accepted);
    * q, q_t are read from the Current ODE2 coordinates (views: Exudyn's q, q_t lists are these
      numbers, at the object's coordinates), never from the lists: a slice of the views when the
      object's coordinates are one range of the system vector (a body, a group of consecutive
      bodies), else gathered at its indices into float64 buffers by a compiled loop
      (``gather_coordinates``; a moving master: the slave's range, then the master's);
    * every residual (FORCE) also leaves its history candidate and its state; the post-Newton commit
      takes the candidate of the last residual when that state is the converged one (it is: Newton
      stops after a residual), and evaluates afresh otherwise, and writes it into the Current data
      coordinates (a view) in place. Exudyn's accept (Current -> StartOfStep) is the commit, its
      reject (StartOfStep -> Current) the rollback.

    The views are fetched again (_views) at the first step of a solve (a start-of-step time that
    is neither the last one nor the last commit's) and whenever the system's sizes changed."""

    def __init__(self, mbs, law, slave, points, master):
        super().__init__(mbs, law, slave, points, master)
        from exu_aniso.kernel.sets import LinearMap
        # a linear slave (mass points, cables) goes to kernel.sets.evaluate_linear, a rigid one to evaluate_set
        kind = LinearMap(*slave.linear_map(points), slave.n) if slave.linear else slave.kind
        self.pk = self._pack(law, kind, slave, points, master)
        self._t = None                        # time of the Newton solve of the current arguments
        self._t0 = None                       # its start-of-step time [s]
        self._dt = 0.0
        self._committed_t = None              # time of the last commit [s]
        self.recomputed = 0                   # commits that had to evaluate afresh (diagnostics)
        # the compiled function itself (numba's dispatch done once) and its packed arguments: q, q_t
        # are the views of Exudyn's Current coordinates at the object's range (_views) or float64
        # buffers they are gathered into (_gathered; the kernel keeps no reference to them: a
        # residual copies its state into X); fODE2, fODE2_t are floats
        self._entry, self._tail = self.pk.entry(), self.pk.tail
        self._V = None                        # SystemViews
        self._gathered = True
        self._gather, self._gather_args = None, None   # gather_coordinates and its arguments (_views)
        self._qb, self._q_tb = np.zeros(self.pk.X.shape[1]), np.zeros(self.pk.X.shape[1])   # own buffers
        self._q, self._q_t = self._qb, self._q_tb
        self._force_args = None               # the force call's arguments, made with dt by _load_history
        self._mbs_address = None              # the C++ system's address: the native registry's key

    def _generalized_force(self, q, q_t, H):
        return self._sample_forces(q[None], q_t[None], H[None])[0]

    def _sample_forces(self, q, q_t, H):
        """ContactSet.generalized_force from the set's own compiled kernel, one call per sample
        (FORCE on each sample's history; the residual's state is forgotten afterwards, so a later
        commit evaluates afresh)."""
        entry, tail, Q = self.pk.entry(), self.pk.tail, self.pk.Q
        q, q_t = np.ascontiguousarray(q), np.ascontiguousarray(q_t)
        H = np.ascontiguousarray(H)
        out = np.empty((len(q), len(Q)))
        for n in range(len(q)):
            entry(FORCE, q[n], q_t[n], 0.0, 0.0, 0.0, H[n], *tail)
            out[n] = Q
        self.pk.X[:] = np.nan
        return out

    def initial_history(self, q, q_t):
        """As ContactSet.initial_history, from the set's own compiled kernel (CANDIDATE: the candidate
        from the zero history the packed set starts with), so no other compiled entry is needed."""
        self.pk.evaluate(CANDIDATE, q, q_t, 0.0, 0.0, 0.0)
        return self.pk.Hn.ravel().copy()

    @staticmethod
    def _pack(law, kind, slave, points, master):
        """The set packed for its compiled kernel (CompiledPairSet: a moving master's)."""
        from exu_aniso.kernel.packed_sets import CovariantSet
        return CovariantSet(law, kind, slave.ref, points)

    def _views(self, mbs):
        """(Re)fetch the views of Exudyn's vectors and the set's indices, assert them, and make the
        set's slices: the history (K, 9) in the StartOfStep data and its q, q_t in the Current ODE2
        vectors (one range: slices of the views; else the buffers and the gather's arguments)."""
        self._indices(mbs)
        V = SystemViews(mbs)
        self._check_indices(V)
        a, n = self.ltgODE2, self.ltgODE2.size
        self._gathered = not np.array_equal(a, a[0] + np.arange(n))
        if self._gathered:
            self._q, self._q_t = self._qb, self._q_tb
            self._gather_args = (V.q, V.q_t, np.ascontiguousarray(a, dtype=np.int64), self._qb, self._q_tb)
            self._gather = entry_point(gather_coordinates, self._gather_args)
        else:
            self._q, self._q_t = V.q[a[0]:a[0] + n], V.q_t[a[0]:a[0] + n]
            self._gather, self._gather_args = None, None
        h = int(self.ltg[0])
        self._h0 = V.data0[h:h + self.K * N_HISTORY].reshape(self.K, N_HISTORY)
        self._V = V
        # the commit's compiled function (numba's dispatch done once: it cost ~1 us per step) and arguments
        self._stage_args = (self.pk.X, self._q, self._q_t, self.pk.Hn, V.data, np.ascontiguousarray(self.ltg),
                            int(self.ltgTotal))
        self._stage = entry_point(stage_candidate, self._stage_args)
        if self._native is not None:          # the native callers read the new views from now on
            self._native.store(self._h0, self._native_stage_args(V))

    def _native_stage_args(self, V):
        """The native post-Newton commit's arguments (kernel.native.STAGE_TYPE) over the views V: the
        set's coordinates gathered at its indices into its buffers, then stage_candidate."""
        return (self.pk.X, V.q, V.q_t, np.ascontiguousarray(self.ltgODE2, dtype=np.int64), self._qb, self._q_tb,
                self.pk.Hn, V.data, np.ascontiguousarray(self.ltg, dtype=np.int64), int(self.ltgTotal))

    def _load_history(self, mbs, t):
        t0 = mbs.systemData.GetTime(_SOS)
        # the last commit: the native post-Newton's while the native callers are armed (it moves their clock)
        native = self._native is not None and self._native.clock[1] != 0.0
        committed = self._native.clock[0] if native else self._committed_t
        if self._V is None or (t0 != self._t0 and t0 != committed) or not self._V.current(mbs):
            self._views(mbs)                  # a new solve, or a re-assembled system
        self._t = t
        self._t0 = t0
        self._dt = t - t0
        self._force_args = (FORCE, self._q, self._q_t, 0.0, 0.0, self._dt, self._h0) + self._tail
        if self._native is not None:          # views checked, start of the step known: the native callers may go on
            self._native.clock[:2] = (t0, 1.0)

    # --- the native force callback (_native.cpp): Exudyn calls the kernel without Python -------------
    def use_native(self, mbs):
        """Give Exudyn the native force callback for this set's object (after locate): its kernel
        (kernel.native: the same compiled entry over the same arguments) is registered for (mbs,
        object), unarmed; the first call of a solve goes to ``native_delegate``, which arms it."""
        f, i = np.zeros(0), np.zeros(0, dtype=np.int64)          # stage arguments until the views are known
        self._native = NativeBlock(self.pk._fn, self.pk.H, self._tail,
                                   (self.pk.X, f, f, i, self._qb, self._q_tb, self.pk.Hn, f, i, 0))
        self._mbs_address = extension.system_address(mbs)
        extension.register_set(mbs, self.oContact, self._native.kernel, self._native.args.address,
                               self._native.stage.address, self.pk.Q.ctypes.data, self.pk.X.shape[1],
                               self._native.clock.ctypes.data, Delegate(self, mbs), self.pk.J)
        return extension.force

    def native_delegate(self, mbs, t):
        """The native callback's call in Python (its first call of every solve, a call at or before
        the start of the step, a call the kernel raised in): checks the views (_load_history, which
        arms the native caller), reads the solve's end time and step (the native callers take steps up to
        twice the nominal one: a later call is a new solve, which Python checks) and evaluates the force
        into Q."""
        self.force_calls += 1
        self._load_history(mbs, t)
        ss = mbs.sys.get("simulationSettings")
        ti = ss.timeIntegration if ss is not None else None
        clock = self._native.clock
        clock[2] = float(ti.endTime) if ti is not None else math.inf
        clock[3] = (2.0 * (ti.endTime - ti.startTime) / max(int(ti.numberOfSteps), 1) if ti is not None
                    else math.inf)
        if self._gathered:
            self._gather(*self._gather_args)
        self._entry(*self._force_args)

    def disarm(self):
        """The next native call goes to Python first (native_delegate): at the end of a solve."""
        if self._native is not None:
            self._native.clock[1] = 0.0

    def step_done(self, t):
        """After an accepted step at t (every set committed): the native caller's next step starts at
        t; after the solve's last step (t within half a step of its end time) its next call goes to
        Python first."""
        clock = self._native.clock            # start of the step, armed, end of the solve
        h = t - clock[0]
        clock[0] = t
        if t + 0.5 * h >= clock[2]:
            clock[1] = 0.0

    def native_calls(self):
        """(native, delegated) force calls of this set so far."""
        if self._native is None:
            return 0, 0
        return extension.calls(self._mbs_address, self.oContact)

    def native_jacobians(self):
        """(native, delegated) Jacobian calls of this set so far."""
        if self._native is None:
            return 0, 0
        return extension.jacobian_calls(self._mbs_address, self.oContact)

    def __del__(self):
        # at the interpreter's exit the extension's module may be torn down before this set: its
        # registry goes with the process then, and nothing is released
        release = getattr(extension, "release_set", None)
        if self._native is not None and callable(release):
            release(self._mbs_address, self.oContact, self._native.args.address)

    def force(self, mbs, t, itemNumber, q, q_t):
        """Generalized contact forces at the given q, q_t (the set's coordinates, any values: for
        direct calls, e.g. finite differences); Exudyn calls force_in_place."""
        if t != self._t:
            self._load_history(mbs, t)
        self._qb[:] = q
        self._q_tb[:] = q_t
        self._entry(FORCE, self._qb, self._q_tb, 0.0, 0.0, self._dt, self._h0, *self._tail)
        return self.pk.Q

    def jacobian(self, mbs, t, itemNumber, q, q_t, fODE2, fODE2_t):
        """As force: the Jacobian at the given q, q_t; Exudyn calls jacobian_in_place."""
        if t != self._t:
            self._load_history(mbs, t)
        self._qb[:] = q
        self._q_tb[:] = q_t
        self._entry(JACOBIAN, self._qb, self._q_tb, fODE2, fODE2_t, self._dt, self._h0, *self._tail)
        return self.pk.J

    def force_in_place(self, mbs, t, itemNumber, q, q_t):
        """The force user function given to Exudyn: the lists q, q_t Exudyn passes are its Current
        coordinates at the object's indices, read here from the views instead (a slice, or gathered
        when the indices are not one range; tests/test_history_in_place.py checks they are equal)."""
        self.force_calls += 1
        if t != self._t:
            self._load_history(mbs, t)
        if self._gathered:
            self._gather(*self._gather_args)
        self._entry(*self._force_args)
        return self.pk.Q

    def jacobian_in_place(self, mbs, t, itemNumber, q, q_t, fODE2, fODE2_t):
        """The Jacobian user function given to Exudyn (q, q_t as in force_in_place)."""
        if t != self._t:
            self._load_history(mbs, t)
        if self._gathered:
            self._gather(*self._gather_args)
        self._entry(JACOBIAN, self._q, self._q_t, fODE2, fODE2_t, self._dt, self._h0, *self._tail)
        return self.pk.J

    def stage(self, mbs, t):
        if t != self._t:
            self._load_history(mbs, t)
        if self._gathered:                    # the object's coordinates are not one range
            self._gather(*self._gather_args)
        q, q_t = self._q, self._q_t
        code = self._stage(*self._stage_args)
        if code == 1:                         # the last residual was not at the converged state
            self.recomputed += 1
            self._entry(CANDIDATE, q, q_t, 0.0, 0.0, self._dt, self._h0, *self._tail)
            self.pk.X[0] = q                  # the candidate now belongs to this state
            self.pk.X[1] = q_t
            code = self._stage(*self._stage_args)
        if code == 0:
            self._committed_t = t
            # the next call reloads (and checks the views), even at this time: a solve that
            # continues from here may follow a re-assembly
            self._t = None
        return code == 0



class CompiledPairSet(CompiledSet):
    """A contact set with a moving master (the surface on a 3D rigid body) on the compiled kernel
    ``kernel.sets.evaluate_pair`` (``kernel.CovariantPairSet``): the slave's and the master's
    coordinates (the contact object's) in one compiled call, with the consistent Jacobian over both
    (so ``jacobian="analytic"`` applies). Its coordinates are two ranges of Exudyn's ODE2 vector,
    gathered from the views at every call (``gather_coordinates``). Everything else as CompiledSet."""

    @staticmethod
    def _pack(law, kind, slave, points, master):
        from exu_aniso.kernel.packed_sets import CovariantPairSet
        return CovariantPairSet(law, kind, slave.ref, points, master.kind, master.ref)


class CompiledGroupSet(CompiledSet):
    """A group (RigidGroup: the same points on several rigid bodies) on the compiled kernel
    ``kernel.sets.evaluate_group`` (``kernel.CovariantGroupSet``): one compiled call for all bodies;
    the Jacobian goes to Exudyn as a sparse matrix of the bodies' diagonal blocks."""

    @staticmethod
    def _pack(law, kind, slave, points, master):
        from exu_aniso.kernel.packed_sets import CovariantGroupSet
        return CovariantGroupSet(law, kind, slave.ref, points, len(slave.bodies))

