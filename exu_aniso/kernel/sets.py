"""Compiled contact sets (numba): the point kinematics of the slave body's Exudyn node and the
generalized force, Jacobian and history candidate of one contact set in one compiled call.

Why it exists: inside Exudyn the contact law runs in user functions that are called 5-6 times per
time step; one compiled call per user function evaluates a whole set: positions, velocities and
point Jacobians of the body-fixed points, the contact law at every point (``point_states``: the
covariant kernel of ``exu_aniso.kernel.point``, called through the address of its compiled code, so a
set's kernel is compiled once per node kind, whatever the law) and the generalized quantities of the
node. ``tests/test_fastpath.py`` holds this route equal to the
numpy route (``exudyn_adapter.contact_set.ContactSet``).

Node kinds of ``evaluate_set`` (rigid bodies, the slave's Exudyn node type): types of
``exu_aniso.kernel.nodes`` (``RigidBody2D()``, ``ScrewJoint()`` for a ``NodeGenericODE2`` with (psi,
z), ``RotationVector()``, ``EulerParameters()``), whose functions (``node_frame``, ``node_point``,
...) a kernel resolves at compile time: it holds the code of its own node kind only.
Linear slaves (``evaluate_linear``): every point linear in the coordinates, x = c + S q_total with
a constant S (mass points: S = I; ANCF cables: Hermite shape functions), so Jp = S and dJp/dq = 0.
A group (``evaluate_group``): the same points on several rigid nodes of one kind in one call, the
Jacobian as its diagonal blocks (many parts on one surface).
A moving master (``evaluate_pair``): the surface carried by a 3D rigid node (``RotationVector()`` or
``EulerParameters()``), any slave of the two functions above (a linear one as ``LinearSlave()``);
the law at the slave point relative to the master, the reaction on the master, the Jacobian over
both nodes' coordinates (``tests/test_moving_master_compiled.py``). A force call (FORCE, and the history candidate,
CANDIDATE) of a rigid set or a pair takes a lean path of its own (``_set_forces``, ``_pair_forces``):
the points' kinematics into a buffer Y, the point law without its tangent at all of them in one
call (``point_states``), the generalized force summed as force and moment per body; the tangent
path (JACOBIAN) is the rest of each function.
This module needs no Exudyn.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from exu_aniso.kernel.nodes import (generalized_force, master_derivatives, master_normalisation, master_rate,
                                    node_coordinates, node_frame, node_geometric, node_point, node_position_jacobian,
                                    node_rotation_columns, node_velocity_column, points_xv, slave_generalized_force,
                                    slave_is_linear, slave_point, slave_points_xv)
from exu_aniso.law.history import H_DISSIPATED, H_STATUS, N_HISTORY, UNRESOLVED

# What a set kernel's call computes (its ``mode``): FORCE the generalized force Q and the history
# candidate Hn, JACOBIAN the Jacobian J = -(fq dQ/dq + fv dQ/dq_t), CANDIDATE the history candidate
# alone (what a commit needs when the last residual was not at the converged state)
FORCE, JACOBIAN, CANDIDATE = 0, 1, 2

# The set kernels' scratch S (SCRATCH_SLOTS, 9, 9), one 9 x 9 slot per named piece: slots 0-8 belong to
# the point law (point_states: S_LAW), the others to the set kernels, which take these views of them
SCRATCH_SLOTS = 19
S_LAW = 0          # slots 0-8: the point law's
S_A = 9            # the slave's rotation A [:3, :3]
S_G = 10           # the slave's G [:3, :4]; Euler parameters, JACOBIAN: G(e_t) [3:6, :4]
S_JP = 11          # a point's Jacobian Jp [:3, :nq]
S_KJ = 12          # _add_congruent's product M R [:3, :nq]
S_DA = 14          # Euler parameters, JACOBIAN: dA/de_m [3:7, :9]
S_KQ = 15          # evaluate_set, JACOBIAN: sum Jp^T Kx Jp [:nq, :nq]
S_PAIR_Q = 15      # the pair kernels: the slave's q_total [0], the master's q_total [1], local omega [2], omega [3]
S_DQ = 16          # evaluate_set, JACOBIAN: sum Jp^T Dv Jp [:nq, :nq]
S_MASTER = 16      # the pair kernels: the master's A [:3, :3] and G [3:6, :4]
S_VEC = 17         # rows: q_total [0], x [1], v [2], the local angular velocity [4], the set's Q [6]
#                    (CovariantSet.Q) and in JACOBIAN dx/dq [6:9] (Euler parameters)
S_J = 18           # the set's Jacobian J [:nq, :nq] (CovariantSet.J)


# the rows of a set's point buffer Y (K, Y_ROWS, 3), a block per point: its position and velocity
# (master frame, relative to the master), the force on it, (ax, ay, status) (a planar node's lever
# arm, the law's status), df/dx (3 rows), df/dv (3 rows), under a moving master the force in
# global axes, and the normal gap xi3 [m] the law found ([Y_GAP, 0])
Y_X, Y_V, Y_F, Y_INFO, Y_KX, Y_DV, Y_FG, Y_GAP = 0, 1, 2, 3, 4, 7, 10, 11
Y_ROWS = 12


def point_states(law, Y, H, Hn, first, count, dt, tangent, S):
    """The contact law at the points k = first, ..., first + count - 1 of the buffer Y: at Y[k, Y_X]
    with velocity Y[k, Y_V] from the converged history H[k] and dt [s] since it, the force into
    Y[k, Y_F], the status into Y[k, Y_INFO, 2] and the normal gap into Y[k, Y_GAP, 0]; with tangent
    also df/dx and df/dv into Y[k, Y_KX:Y_KX + 3] and Y[k, Y_DV:Y_DV + 3]; the history candidate into Hn[k] (not with tangent:
    a Jacobian call leaves the candidate of the last residual). Returns (points in contact, any
    unresolved). Resolved at compile time by the type of ``law`` (overloads in
    ``exu_aniso.kernel.point``: a LawCall, the law's compiled code called through its address, as
    the set kernels get it; a law bundle, the covariant kernel itself, as that code runs it). Give
    ``tangent`` as a run-time bool (``mode == JACOBIAN``), never a literal, or it compiles twice."""
    raise NotImplementedError("point_states is resolved at compile time")


@njit(cache=True, inline="always")
def _set_forces(kind, q, q_t, ref, b, H, law, mode, dt, Q, Hn, S, Y):
    """evaluate_set without derivatives (modes 0 and 2), in three passes over the points: their
    positions and velocities from the node's frame (computed once per call) into Y, the point law
    at all of them (point_states: the law's one compiled loop), and the
    generalized force summed without a per-point Jacobian: the force on the translation coordinates
    and, for a 3D node, the local moment m = sum b x A^T f, mapped once by Q_rot = G^T m (= sum
    Jp_rot^T f, Jp_rot = -A [b]x G); for a planar node the moment about the rotation axis. A point
    out of contact has f = 0 and adds nothing.

    evaluate_set and this function are inlined (numba IR) into their callers: every compiled unit
    links what it calls and optimizes it all again, so fewer levels compile faster."""
    nq = q.shape[0]
    K = b.shape[0]
    A, G = S[S_A, :3, :3], S[S_G, :3, :4]
    qt = S[S_VEC, 0, :nq]
    node_frame(kind, q, q_t, ref, False, qt, A, G, A, G)
    points_xv(kind, qt, q_t, A, G, b, Y[:, Y_X], Y[:, Y_V], Y[:, Y_INFO, :2])
    ncontact, unresolved = point_states(law, Y, H, Hn, 0, K, dt, mode == JACOBIAN, S)
    if mode == FORCE:
        generalized_force(kind, A, G, nq, b, Y[:, Y_F], Y[:, Y_INFO, :2], Q)
    return -1 if unresolved else ncontact


@njit(cache=True, inline="always")
def _add_congruent(L, M, R, LR, out):
    """out (n, n) += L^T M R for L, R (3, n) and M (3, 3), forming LR = M R (3 x n) first (about a
    third of the multiply-adds of the entry-by-entry sum for n = 7)."""
    n = L.shape[1]
    for i in range(3):
        for c in range(n):
            LR[i, c] = M[i, 0] * R[0, c] + M[i, 1] * R[1, c] + M[i, 2] * R[2, c]
    for a in range(n):
        l0, l1, l2 = L[0, a], L[1, a], L[2, a]
        for c in range(n):
            out[a, c] += l0 * LR[0, c] + l1 * LR[1, c] + l2 * LR[2, c]


@njit(cache=True, inline="always")
def evaluate_set(kind, q, q_t, ref, b, H, law, mode, fq, fv, dt, Q, J, Hn, S, Y):
    """One contact set on one node. q, q_t: node coordinates (without reference values), ref:
    reference coordinates, b (K, 3) body-local points, H (K, 9) converged history, dt time since
    H [s] (0: no branch prediction), S: scratch of shape (SCRATCH_SLOTS, 9, 9), Y (K, Y_ROWS, 3) the
    point buffer (point_states).
    FORCE: Q (n,) = generalized force sum Jp^T f;
    JACOBIAN: J (n, n) = -(fq dQ/dq + fv dQ/dq_t) (Exudyn's ODE2 Jacobian convention), complete
            for every node kind: with v = Jp q_t,
            dQ/dq = sum Jp^T Kx Jp + sum f . dJp/dq + sum Jp^T Dv (dJp/dq q_t), dQ/dq_t = sum Jp^T Dv Jp
            (lever arms and point velocities turning with the body; see exudyn_adapter.slaves.rigid
            RigidNode.point_derivatives; rotation-vector nodes by the local increment);
    CANDIDATE: Hn (K, 9) = history candidate (FORCE writes it too: the post-Newton commit takes it
            from the last residual, evaluated at the converged state). Returns the number of points
            in contact, or -1 when a point's motion in the step is unresolved (status 3)."""
    if mode != JACOBIAN:
        return _set_forces(kind, q, q_t, ref, b, H, law, mode, dt, Q, Hn, S, Y)
    nq = q.shape[0]
    K = b.shape[0]
    # scratch views of S (slots 0-8 belong to contact_point)
    A, G, Jp = S[S_A, :3, :3], S[S_G, :3, :4], S[S_JP, :3, :nq]
    Kq, Dq = S[S_KQ, :nq, :nq], S[S_DQ, :nq, :nq]
    qt, x, v, wl = S[S_VEC, 0, :nq], S[S_VEC, 1, :3], S[S_VEC, 2, :3], S[S_VEC, 4, :3]
    KJ = S[S_KJ, :3, :nq]             # scratch of _add_congruent (3 x nq)
    tangent = mode == JACOBIAN
    if tangent:
        for i in range(nq):
            for j in range(nq):
                Kq[i, j] = 0.0
                Dq[i, j] = 0.0
    # EP derivatives (JACOBIAN): dA/de_m and G(e_t)
    dA, Gt = S[S_DA, 3:7, :9], S[S_G, 3:6, :4]
    node_frame(kind, q, q_t, ref, tangent, qt, A, G, dA, Gt)
    # dx/dq: Jp except for Euler parameters (see exudyn_adapter.contact_set.PointTangent)
    Jx = node_position_jacobian(kind, S[S_VEC, 6:9, :nq], Jp)
    c0, nc = node_rotation_columns(kind, nq)
    ncontact = 0
    unresolved = False
    for k in range(K):
        bx, by, bz = b[k, 0], b[k, 1], b[k, 2]
        node_point(kind, qt, q_t, A, G, dA, bx, by, bz, tangent, x, v, Jp, Jx, wl)
        for i in range(3):
            Y[k, Y_X, i] = x[i]
            Y[k, Y_V, i] = v[i]
        touching, stuck_step = point_states(law, Y, H, Hn, k, 1, dt, tangent, S)
        ncontact += touching
        unresolved |= stuck_step
        if not touching:
            continue
        f, Kx, Dv = Y[k, Y_F], Y[k, Y_KX:Y_KX + 3], Y[k, Y_DV:Y_DV + 3]
        damped = _nonzero(Dv)
        # Kq += Jp^T Kx Jx, Dq += Jp^T Dv Jp
        _add_congruent(Jp, Kx, Jx, KJ, Kq)
        if damped:
            _add_congruent(Jp, Dv, Jp, KJ, Dq)
        # velocity of the points turning with the body: Kq[:, c] += Jp^T Dv dv/dq_c (Dv = 0 without damping)
        if damped:
            for c in range(c0, c0 + nc):
                d0, d1, d2 = node_velocity_column(kind, c, q_t, A, dA, Gt, Jp, wl, bx, by, bz)
                e0 = Dv[0, 0] * d0 + Dv[0, 1] * d1 + Dv[0, 2] * d2
                e1 = Dv[1, 0] * d0 + Dv[1, 1] * d1 + Dv[1, 2] * d2
                e2 = Dv[2, 0] * d0 + Dv[2, 1] * d1 + Dv[2, 2] * d2
                for a in range(nq):
                    Kq[a, c] += Jp[0, a] * e0 + Jp[1, a] * e1 + Jp[2, a] * e2
        node_geometric(kind, A, G, dA, Jp, f, bx, by, bz, Kq)
    if mode == JACOBIAN:
        for i in range(nq):
            for j in range(nq):
                J[i, j] = -(fq * Kq[i, j] + fv * Dq[i, j])
    return -1 if unresolved else ncontact


@njit(cache=True, inline="always")
def evaluate_group(kind, q, q_t, ref, b, H, law, mode, fq, fv, dt, Q, Jb, Hn, S, Y):
    """One contact set on nb rigid nodes of one kind (a group: the same body-local points b (Kb, 3)
    on every body, one compiled call for all). q, q_t, ref: the nodes' coordinates one after the
    other (nb * nq); H, Hn (nb * Kb, 9): body by body; Q (nb * nq,); Jb (nb, nq, nq): the diagonal
    blocks of the Jacobian (no body's force depends on another's coordinates). Each body is
    evaluate_set on its slices; returns the points in contact, or -1 (a point's step unresolved)."""
    nb = Jb.shape[0]
    nq = Jb.shape[1]
    Kb = b.shape[0]
    ncontact = 0
    unresolved = False
    for j in range(nb):
        c, p = j * nq, j * Kb
        r = evaluate_set(kind, q[c:c + nq], q_t[c:c + nq], ref[c:c + nq], b, H[p:p + Kb], law, mode, fq, fv, dt,
                         Q[c:c + nq], Jb[j], Hn[p:p + Kb], S, Y[p:p + Kb])
        if r < 0:
            unresolved = True
        else:
            ncontact += r
    return -1 if unresolved else ncontact


@njit(cache=True)
def _nonzero(M):
    """True if the 3 x 3 matrix M has a nonzero entry (Dv = 0 without damping)."""
    for i in range(3):
        for j in range(3):
            if M[i, j] != 0.0:
                return True
    return False


@njit(cache=True, inline="always")
def evaluate_linear(q, q_t, ref, idx, Sm, c, H, law, mode, fq, fv, dt, Q, J, Hn, S, Y):
    """A contact set on a linear slave: point k at x_k = c_k + S_k q_total[idx_k], velocity
    v_k = S_k q_t[idx_k], with constant S_k (3, m) over the m set coordinates idx_k (K, m) (a mass
    point: S = I over its own coordinates, c = b; an ANCF cable: the Hermite shape functions of its
    element at the point). q, q_t, ref: the set's coordinates; H (K, 9) converged history; dt time
    since H; S scratch (SCRATCH_SLOTS, 9, 9), slots 0-8 belong to the point law; Y (K, Y_ROWS, 3)
    the point buffer (point_states).
    FORCE: Q (n,) = sum S_k^T f_k; JACOBIAN: J (n, n) = -(fq dQ/dq + fv dQ/dq_t) with
    dQ/dq = sum S^T Kx S and dQ/dq_t = sum S^T Dv S (Jp = S is constant: no geometric terms);
    CANDIDATE: Hn (K, 9) = history candidate (FORCE too). Returns the number of points in contact, or
    -1 when a point's motion in the step is unresolved."""
    K, m = idx.shape[0], idx.shape[1]
    n = q.shape[0]
    if mode == FORCE:
        for i in range(n):
            Q[i] = 0.0
    elif mode == JACOBIAN:
        for i in range(n):
            for j in range(n):
                J[i, j] = 0.0
    for k in range(K):
        for i in range(3):
            xi, vi = c[k, i], 0.0
            for a in range(m):
                g = idx[k, a]
                xi += Sm[k, i, a] * (ref[g] + q[g])
                vi += Sm[k, i, a] * q_t[g]
            Y[k, Y_X, i], Y[k, Y_V, i] = xi, vi
    ncontact, unresolved = point_states(law, Y, H, Hn, 0, K, dt, mode == JACOBIAN, S)
    for k in range(K):
        st = Y[k, Y_INFO, 2]
        f, Kx, Dv = Y[k, Y_F], Y[k, Y_KX:Y_KX + 3], Y[k, Y_DV:Y_DV + 3]
        if mode == FORCE:
            for a in range(m):
                Q[idx[k, a]] += Sm[k, 0, a] * f[0] + Sm[k, 1, a] * f[1] + Sm[k, 2, a] * f[2]
        elif mode == JACOBIAN and st > 0:
            # J[idx_a, idx_b] -= S_a^T (fq Kx + fv Dv) S_b
            for a in range(m):
                for b in range(m):
                    s_ab = 0.0
                    for i in range(3):
                        if Sm[k, i, a] == 0.0:
                            continue
                        for j in range(3):
                            s_ab += Sm[k, i, a] * (fq * Kx[i, j] + fv * Dv[i, j]) * Sm[k, j, b]
                    J[idx[k, a], idx[k, b]] -= s_ab
    return -1 if unresolved else ncontact


@njit(cache=True)
def stage_candidate(X, q, q_t, Hn, data, ltg, ltg_total):
    """Post-Newton commit of one contact set, compiled (numpy calls on arrays of a few numbers cost
    more than the work): if the state (q, q_t) of the last residual, X (2, n), is the converged
    state q, q_t, and no point's step is unresolved (status UNRESOLVED), copy the candidate Hn
    (K, N_HISTORY) into the data coordinates at ltg (K * N_HISTORY indices; data: Exudyn's Current data vector,
    a view) and its total dissipation [J] into data[ltg_total]. Returns 0 (written), 1 (the last residual was at another
    state: evaluate the candidate afresh, nothing written) or -1 (unresolved, nothing written)."""
    for i in range(q.shape[0]):
        if X[0, i] != q[i] or X[1, i] != q_t[i]:
            return 1
    K = Hn.shape[0]
    for k in range(K):
        if Hn[k, H_STATUS] == UNRESOLVED:
            return -1
    total = 0.0
    for k in range(K):
        for j in range(N_HISTORY):
            data[ltg[N_HISTORY * k + j]] = Hn[k, j]
        total += Hn[k, H_DISSIPATED]
    data[ltg_total] = total
    return 0


@njit(cache=True)
def gather_coordinates(q, q_t, idx, qb, q_tb):
    """qb[i] = q[idx[i]], q_tb[i] = q_t[idx[i]]: a contact object's coordinates and velocities, at its
    indices idx in Exudyn's ODE2 vector, from the views q, q_t of the Current ones into the set's
    float64 buffers (compiled: a loop over a few numbers in numba costs less than converting
    Exudyn's lists or numpy's fancy indexing)."""
    for i in range(idx.shape[0]):
        j = idx[i]
        qb[i] = q[j]
        q_tb[i] = q_t[j]


@njit(cache=True)
def stage_gathered(X, q, q_t, idx, qb, q_tb, Hn, data, ltg, ltg_total):
    """stage_candidate at the set's coordinates gathered (gather_coordinates) from the system's
    Current q, q_t (views): the native post-Newton commit of one set (kernel.native.stage_kernel)."""
    gather_coordinates(q, q_t, idx, qb, q_tb)
    return stage_candidate(X, qb, q_tb, Hn, data, ltg, ltg_total)


# --- a moving master: the surface carried by a 3D rigid node -------------------------------------

PAIR_SLOTS = 8   # pair scratch T (PAIR_SLOTS, w, w), w = max(9, coordinates of one point's columns)


@njit(cache=True, inline="always")
def _master_frame(mkind, qm, qm_t, refm, tangent, qtm, A, G, dA, Gt, wl, w):
    """The master's node (a 3D kind: RotationVector() or EulerParameters()): total coordinates qtm,
    A, G, local and global angular velocity wl = G q_t_rot, w = A wl; with tangent dA[c, 3 i + j] =
    dA_ij/dq_c over its rotation coordinates c and what its kind needs besides (master_derivatives:
    a rotation vector by the local increment, dA_c = A [e_c]x; Euler parameters by e_c itself, and
    Gt = G(e_t))."""
    nm = qm.shape[0]
    node_frame(mkind, qm, qm_t, refm, False, qtm, A, G, dA, Gt)
    for i in range(3):
        s = 0.0
        for j in range(nm - 3):
            s += G[i, j] * qm_t[3 + j]
        wl[i] = s
    for i in range(3):
        w[i] = A[i, 0] * wl[0] + A[i, 1] * wl[1] + A[i, 2] * wl[2]
    if tangent:
        master_derivatives(mkind, qtm, qm_t, A, dA, Gt)


@njit(cache=True, inline="always")
def _pair_forces(kind, mkind, q, q_t, ref, b, idx, Sm, c, H, law, mode, dt, Q, Hn, S, Y):
    """evaluate_pair without derivatives (modes 0 and 2), as _set_forces for a fixed master: both
    frames once per call, the points relative to the master into Y, the law at all of them
    (point_states), and the generalized force summed without a Jacobian per point. The slave gets
    F = A f: a rigid slave as force and moment (_set_forces), a linear slave through its constant
    S_k; the master the reaction, -sum F and -G^T sum (x_rel x A^T F) at its material points x_rel."""
    n = q.shape[0]
    nm = node_coordinates(mkind)
    ns = n - nm
    As, Gs = S[S_A, :3, :3], S[S_G, :3, :4]
    qts = S[S_PAIR_Q, 0, :(0 if slave_is_linear(kind) else ns)]
    qtm, wlm, w = S[S_PAIR_Q, 1, :nm], S[S_PAIR_Q, 2, :3], S[S_PAIR_Q, 3, :3]
    Am, Gm = S[S_MASTER, :3, :3], S[S_MASTER, 3:6, :4]
    node_frame(kind, q[:ns], q_t[:ns], ref[:ns], False, qts, As, Gs, As, Gs)
    _master_frame(mkind, q[ns:], q_t[ns:], ref[ns:], False, qtm, Am, Gm, Am, Gm, wlm, w)
    vp0, vp1, vp2 = q_t[ns], q_t[ns + 1], q_t[ns + 2]
    # the slave's points in global axes, then relative to the master, in its frame (as evaluate_pair)
    slave_points_xv(kind, b, idx, Sm, c, ref, q, q_t, qts, As, Gs, Y[:, Y_X], Y[:, Y_V], Y[:, Y_INFO, :2])
    K = H.shape[0]
    for k in range(K):
        d0, d1, d2 = Y[k, Y_X, 0] - qtm[0], Y[k, Y_X, 1] - qtm[1], Y[k, Y_X, 2] - qtm[2]
        e0 = Y[k, Y_V, 0] - vp0 - (w[1] * d2 - w[2] * d1)
        e1 = Y[k, Y_V, 1] - vp1 - (w[2] * d0 - w[0] * d2)
        e2 = Y[k, Y_V, 2] - vp2 - (w[0] * d1 - w[1] * d0)
        for j in range(3):
            Y[k, Y_X, j] = Am[0, j] * d0 + Am[1, j] * d1 + Am[2, j] * d2
            Y[k, Y_V, j] = Am[0, j] * e0 + Am[1, j] * e1 + Am[2, j] * e2
    ncontact, unresolved = point_states(law, Y, H, Hn, 0, K, dt, mode == JACOBIAN, S)
    if mode == FORCE:
        for i in range(n):
            Q[i] = 0.0
        FS0 = FS1 = FS2 = 0.0                            # on the slave (the master gets -F)
        Y0 = Y1 = Y2 = 0.0                               # on the master: sum x_rel x A^T F
        for k in range(K):
            f0, f1, f2 = Y[k, Y_F, 0], Y[k, Y_F, 1], Y[k, Y_F, 2]
            xr0, xr1, xr2 = Y[k, Y_X, 0], Y[k, Y_X, 1], Y[k, Y_X, 2]
            F0 = Am[0, 0] * f0 + Am[0, 1] * f1 + Am[0, 2] * f2            # F = A f
            F1 = Am[1, 0] * f0 + Am[1, 1] * f1 + Am[1, 2] * f2
            F2 = Am[2, 0] * f0 + Am[2, 1] * f1 + Am[2, 2] * f2
            Y[k, Y_FG, 0], Y[k, Y_FG, 1], Y[k, Y_FG, 2] = F0, F1, F2
            g0 = Am[0, 0] * F0 + Am[1, 0] * F1 + Am[2, 0] * F2                   # A^T F
            g1 = Am[0, 1] * F0 + Am[1, 1] * F1 + Am[2, 1] * F2
            g2 = Am[0, 2] * F0 + Am[1, 2] * F1 + Am[2, 2] * F2
            Y0 += xr1 * g2 - xr2 * g1
            Y1 += xr2 * g0 - xr0 * g2
            Y2 += xr0 * g1 - xr1 * g0
            FS0 += F0
            FS1 += F1
            FS2 += F2
        slave_generalized_force(kind, As, Gs, ns, b, idx, Sm, Y[:, Y_FG], Y[:, Y_INFO, :2], Q)
        Q[ns], Q[ns + 1], Q[ns + 2] = Q[ns] - FS0, Q[ns + 1] - FS1, Q[ns + 2] - FS2
        for r2 in range(nm - 3):
            Q[ns + 3 + r2] -= Gm[0, r2] * Y0 + Gm[1, r2] * Y1 + Gm[2, r2] * Y2
    return -1 if unresolved else ncontact


@njit(cache=True, inline="always")
def evaluate_pair(kind, mkind, q, q_t, ref, b, idx, Sm, c, H, law, mode, fq, fv, dt, Q, J, Hn, S, T, cols, Y):
    """One contact set between a slave and a moving master: the surface carried by a 3D rigid node
    (mkind: RotationVector() or EulerParameters(), exu_aniso.kernel.nodes). Coordinates q, q_t, ref
    (n,) are the slave's (ns) then the master's (nm = 6 or 7), as the contact's ObjectGenericODE2 lists
    its nodes. Slave: a rigid node kind with body-local points b (K, 3) (as evaluate_set), or
    LinearSlave(), a linear slave (mass points, cables: x_k = c_k + Sm_k q_total[idx_k] over slave coordinates, as
    evaluate_linear; b unused). H (K, 9) converged history, dt time since H. Scratch: S
    (SCRATCH_SLOTS, 9, 9) (slots 0-8 belong to the point law, the slave's views are evaluate_set's),
    T (PAIR_SLOTS, w, w) with w >= max(9, m + nm) (m: slave columns of a point, ns rigid, idx.shape[1]
    linear), cols (m + nm,) int64.

    Kinematics (exudyn_adapter.contact_set.ContactSet.state): master position p, rotation A, global angular
    velocity w, velocity vp; d = x - p; the law at x_rel = A^T d, v_rel = A^T (v - vp - w x d) (master
    frame) gives f; F = A f. Q_slave = Jp^T F; the master gets the reaction at its material point
    b = x_rel: Q_master = -Jm^T F with Jm = [I, -A [b]x G], i.e. -F and -G^T (b x A^T F).
    FORCE: Q (n,) (and Hn, as CANDIDATE); CANDIDATE: Hn (K, 9) history candidate;
    JACOBIAN: J (n, n) = -(fq dQ/dq + fv dQ/dq_t) over all coordinates, consistent: with L (n, 3) the
    map Q = sum_k L_k f_k and X, V, Vt (3, n) the derivatives of x_rel by q and of v_rel by q and q_t
    (through the slave's point, the master's position, rotation and angular velocity),
        dQ/dq = sum L (Kx X + Dv V) + sum (dL/dq) f,  dQ/dq_t = sum L Dv Vt,
    where (dL/dq) f holds the slave's lever arms (node_geometric with F), the turning F = A f and,
    for the master's rows, its point b = x_rel moving (through X) and, for Euler parameters, G(e) and
    A^T A. Rotation-vector coordinates (slave and master) are differentiated by the local
    increment (A -> A (I + [dtheta]x)), Euler parameters by e. Returns the number of points in
    contact, or -1 when a point's motion in the step is unresolved (as evaluate_set)."""
    if mode != JACOBIAN:
        return _pair_forces(kind, mkind, q, q_t, ref, b, idx, Sm, c, H, law, mode, dt, Q, Hn, S, Y)
    n = q.shape[0]
    nm = node_coordinates(mkind)
    ns = n - nm
    nr = nm - 3
    K = H.shape[0]
    linear = slave_is_linear(kind)
    m = idx.shape[1] if linear else ns
    na = m + nm
    tangent = mode == JACOBIAN
    # the slave's views (evaluate_set's slots) and the law's outputs
    As, Gs = S[S_A, :3, :3], S[S_G, :3, :4]
    dAs, Gts = S[S_DA, 3:7, :9], S[S_G, 3:6, :4]
    x, v, wls = S[S_VEC, 1, :3], S[S_VEC, 2, :3], S[S_VEC, 4, :3]
    qts = S[S_PAIR_Q, 0, :(0 if linear else ns)]
    qs, qs_t, refs = q[:ns], q_t[:ns], ref[:ns]
    # the pair's views: slave point Jacobians (compact columns), derivatives, tangent blocks, master
    Jp = T[0, 0:3, :m]
    Jx = node_position_jacobian(kind, T[0, 3:6, :m], Jp)
    X, V, Vt, Lt = T[1, 0:3, :na], T[1, 3:6, :na], T[1, 6:9, :na], T[2, 0:3, :na]
    Kc, Dc = T[3, :na, :na], T[4, :na, :na]
    Am, Gm, Gtm = T[5, 0:3, 0:3], T[5, 3:6, 0:4], T[5, 6:9, 0:4]
    dAm, dAf = T[6, 0:4, 0:9], T[6, 4:8, 0:3]
    qtm, wlm, w, d, u = T[7, 0, :nm], T[7, 1, :3], T[7, 2, :3], T[7, 3, :3], T[7, 4, :3]
    F, g, xr, vr = T[7, 5, :3], T[7, 6, :3], T[7, 7, :3], T[7, 8, :3]
    node_frame(kind, qs, qs_t, refs, tangent, qts, As, Gs, dAs, Gts)
    _master_frame(mkind, q[ns:], q_t[ns:], ref[ns:], tangent, qtm, Am, Gm, dAm, Gtm, wlm, w)
    vp0, vp1, vp2 = q_t[ns], q_t[ns + 1], q_t[ns + 2]
    c0, nc = node_rotation_columns(kind, ns)
    for a in range(m):
        cols[a] = a
    for i in range(nm):
        cols[m + i] = ns + i
    if mode == JACOBIAN:
        # a rigid slave: every point has all n columns, Kc and Dc (n, n) sum over the points; a linear
        # slave: the point's columns only, Kc and Dc per point, added into J by cols
        if linear:
            for i in range(n):
                for j in range(n):
                    J[i, j] = 0.0
        for i in range(na):
            for j in range(na):
                Kc[i, j] = 0.0
                Dc[i, j] = 0.0
    ncontact = 0
    unresolved = False
    bx = by = bz = 0.0
    for k in range(K):
        # the slave point
        bx, by, bz = slave_point(kind, k, b, idx, Sm, c, ref, q, q_t, qts, qs_t, As, Gs, dAs, tangent, x, v, Jp, Jx,
                                 wls, cols)
        # relative to the master, in its frame
        for i in range(3):
            d[i] = x[i] - qtm[i]
        u[0] = v[0] - vp0 - (w[1] * d[2] - w[2] * d[1])
        u[1] = v[1] - vp1 - (w[2] * d[0] - w[0] * d[2])
        u[2] = v[2] - vp2 - (w[0] * d[1] - w[1] * d[0])
        for j in range(3):
            xr[j] = Am[0, j] * d[0] + Am[1, j] * d[1] + Am[2, j] * d[2]
            vr[j] = Am[0, j] * u[0] + Am[1, j] * u[1] + Am[2, j] * u[2]
        for i in range(3):
            Y[k, Y_X, i], Y[k, Y_V, i] = xr[i], vr[i]
        touching, stuck_step = point_states(law, Y, H, Hn, k, 1, dt, tangent, S)
        ncontact += touching
        unresolved |= stuck_step
        if not touching:
            continue
        f, Kx, Dv = Y[k, Y_F], Y[k, Y_KX:Y_KX + 3], Y[k, Y_DV:Y_DV + 3]
        # F = A f (global), g = A^T F, y = b x g at the master's material point b = x_rel
        for i in range(3):
            F[i] = Am[i, 0] * f[0] + Am[i, 1] * f[1] + Am[i, 2] * f[2]
        for j in range(3):
            g[j] = Am[0, j] * F[0] + Am[1, j] * F[1] + Am[2, j] * F[2]
        y0, y1, y2 = xr[1] * g[2] - xr[2] * g[1], xr[2] * g[0] - xr[0] * g[2], xr[0] * g[1] - xr[1] * g[0]
        damped = _nonzero(Dv)
        # columns of X = dx_rel/dq and of L^T (Q = L f): slave, master translation, master rotation
        for a in range(m):
            for j in range(3):
                X[j, a] = Am[0, j] * Jx[0, a] + Am[1, j] * Jx[1, a] + Am[2, j] * Jx[2, a]
                Lt[j, a] = Am[0, j] * Jp[0, a] + Am[1, j] * Jp[1, a] + Am[2, j] * Jp[2, a]
        for i in range(3):
            for j in range(3):
                X[j, m + i] = -Am[i, j]
                Lt[j, m + i] = -Am[i, j]
        for cc in range(nr):
            col = m + 3 + cc
            for j in range(3):         # dA_c^T d
                X[j, col] = dAm[cc, j] * d[0] + dAm[cc, 3 + j] * d[1] + dAm[cc, 6 + j] * d[2]
            # -A^T A (G_c x b): the master's rotation row of L
            gc0, gc1, gc2 = Gm[0, cc], Gm[1, cc], Gm[2, cc]
            z0, z1, z2 = gc1 * xr[2] - gc2 * xr[1], gc2 * xr[0] - gc0 * xr[2], gc0 * xr[1] - gc1 * xr[0]
            e0 = Am[0, 0] * z0 + Am[0, 1] * z1 + Am[0, 2] * z2
            e1 = Am[1, 0] * z0 + Am[1, 1] * z1 + Am[1, 2] * z2
            e2 = Am[2, 0] * z0 + Am[2, 1] * z1 + Am[2, 2] * z2
            for j in range(3):
                Lt[j, col] = -(Am[0, j] * e0 + Am[1, j] * e1 + Am[2, j] * e2)
        if damped:
            # V = dv_rel/dq (q_t fixed), Vt = dv_rel/dq_t
            for a in range(m):
                t0 = -(w[1] * Jx[2, a] - w[2] * Jx[1, a])          # -(w x dx/dq_a)
                t1 = -(w[2] * Jx[0, a] - w[0] * Jx[2, a])
                t2 = -(w[0] * Jx[1, a] - w[1] * Jx[0, a])
                if c0 <= a < c0 + nc:                               # the slave point's velocity turning
                    e0, e1, e2 = node_velocity_column(kind, a, qs_t, As, dAs, Gts, Jp, wls, bx, by, bz)
                    t0, t1, t2 = t0 + e0, t1 + e1, t2 + e2
                for j in range(3):
                    V[j, a] = Am[0, j] * t0 + Am[1, j] * t1 + Am[2, j] * t2
                    Vt[j, a] = Lt[j, a]
            for i in range(3):                                      # d(-w x d)/dp_i = w x e_i
                t0 = 0.0 if i == 0 else (-w[2] if i == 1 else w[1])
                t1 = w[2] if i == 0 else (0.0 if i == 1 else -w[0])
                t2 = -w[1] if i == 0 else (w[0] if i == 1 else 0.0)
                for j in range(3):
                    V[j, m + i] = Am[0, j] * t0 + Am[1, j] * t1 + Am[2, j] * t2
                    Vt[j, m + i] = -Am[i, j]
            for cc in range(nr):
                col = m + 3 + cc
                # dw_c = dA_c wl + A dG_c q_t_rot, dG_c q_t_rot = G(e_c) e_t = -G(e_t) e_c (EP; 0 by the local increment)
                s0, s1, s2 = master_rate(mkind, Gtm, cc)
                dw0 = dAm[cc, 0] * wlm[0] + dAm[cc, 1] * wlm[1] + dAm[cc, 2] * wlm[2] + Am[0, 0] * s0 + Am[0, 1] * s1 + Am[0, 2] * s2
                dw1 = dAm[cc, 3] * wlm[0] + dAm[cc, 4] * wlm[1] + dAm[cc, 5] * wlm[2] + Am[1, 0] * s0 + Am[1, 1] * s1 + Am[1, 2] * s2
                dw2 = dAm[cc, 6] * wlm[0] + dAm[cc, 7] * wlm[1] + dAm[cc, 8] * wlm[2] + Am[2, 0] * s0 + Am[2, 1] * s1 + Am[2, 2] * s2
                t0, t1, t2 = dw1 * d[2] - dw2 * d[1], dw2 * d[0] - dw0 * d[2], dw0 * d[1] - dw1 * d[0]
                # dw/d(q_t rot c) = A G_c: Vt = -A^T ((A G_c) x d)
                a0 = Am[0, 0] * Gm[0, cc] + Am[0, 1] * Gm[1, cc] + Am[0, 2] * Gm[2, cc]
                a1 = Am[1, 0] * Gm[0, cc] + Am[1, 1] * Gm[1, cc] + Am[1, 2] * Gm[2, cc]
                a2 = Am[2, 0] * Gm[0, cc] + Am[2, 1] * Gm[1, cc] + Am[2, 2] * Gm[2, cc]
                r0, r1, r2 = a1 * d[2] - a2 * d[1], a2 * d[0] - a0 * d[2], a0 * d[1] - a1 * d[0]
                for j in range(3):     # dA_c^T u - A^T (dw_c x d)
                    V[j, col] = (dAm[cc, j] * u[0] + dAm[cc, 3 + j] * u[1] + dAm[cc, 6 + j] * u[2]
                                 - (Am[0, j] * t0 + Am[1, j] * t1 + Am[2, j] * t2))
                    Vt[j, col] = -(Am[0, j] * r0 + Am[1, j] * r1 + Am[2, j] * r2)
        # law terms: Kc += L (Kx X + Dv V), Dc += L Dv Vt
        for a in range(na):
            l0, l1, l2 = Lt[0, a], Lt[1, a], Lt[2, a]
            k0 = l0 * Kx[0, 0] + l1 * Kx[1, 0] + l2 * Kx[2, 0]
            k1 = l0 * Kx[0, 1] + l1 * Kx[1, 1] + l2 * Kx[2, 1]
            k2 = l0 * Kx[0, 2] + l1 * Kx[1, 2] + l2 * Kx[2, 2]
            if damped:
                e0 = l0 * Dv[0, 0] + l1 * Dv[1, 0] + l2 * Dv[2, 0]
                e1 = l0 * Dv[0, 1] + l1 * Dv[1, 1] + l2 * Dv[2, 1]
                e2 = l0 * Dv[0, 2] + l1 * Dv[1, 2] + l2 * Dv[2, 2]
                for bb in range(na):
                    Kc[a, bb] += (k0 * X[0, bb] + k1 * X[1, bb] + k2 * X[2, bb]
                                  + e0 * V[0, bb] + e1 * V[1, bb] + e2 * V[2, bb])
                    Dc[a, bb] += e0 * Vt[0, bb] + e1 * Vt[1, bb] + e2 * Vt[2, bb]
            else:
                for bb in range(na):
                    Kc[a, bb] += k0 * X[0, bb] + k1 * X[1, bb] + k2 * X[2, bb]
        # geometric terms (dL/dq) f: the slave's lever arms at fixed F (rigid slaves)
        node_geometric(kind, As, Gs, dAs, Jp, F, bx, by, bz, Kc)
        # F = A f turning with the master: slave rows Jp^T dA_c f, master translation rows -dA_c f
        for cc in range(nr):
            col = m + 3 + cc
            for i in range(3):
                dAf[cc, i] = dAm[cc, 3 * i] * f[0] + dAm[cc, 3 * i + 1] * f[1] + dAm[cc, 3 * i + 2] * f[2]
            for a in range(m):
                Kc[a, col] += Jp[0, a] * dAf[cc, 0] + Jp[1, a] * dAf[cc, 1] + Jp[2, a] * dAf[cc, 2]
            for i in range(3):
                Kc[m + i, col] -= dAf[cc, i]
        # master rotation rows -G^T (b x g): the material point b = x_rel moving, -G_r . (db x g) = (G_r x g) . db
        for r in range(nr):
            gr0, gr1, gr2 = Gm[0, r], Gm[1, r], Gm[2, r]
            h0, h1, h2 = gr1 * g[2] - gr2 * g[1], gr2 * g[0] - gr0 * g[2], gr0 * g[1] - gr1 * g[0]
            for bb in range(na):
                Kc[m + 3 + r, bb] += h0 * X[0, bb] + h1 * X[1, bb] + h2 * X[2, bb]
        master_normalisation(mkind, Am, Gm, dAm, dAf, F, xr, y0, y1, y2, m + 3, Kc)
        if linear:
            for a in range(na):
                ra = cols[a]
                for bb in range(na):
                    J[ra, cols[bb]] -= fq * Kc[a, bb] + fv * Dc[a, bb]
                    Kc[a, bb] = 0.0
                    Dc[a, bb] = 0.0
    if mode == JACOBIAN and not linear:
        for i in range(n):
            for j in range(n):
                J[i, j] = -(fq * Kc[i, j] + fv * Dc[i, j])
    return -1 if unresolved else ncontact


class LinearMap:
    """The kinematics of a linear slave for the compiled kernels: idx (K, m) int64 set-coordinate
    indices, S (K, 3, m) constant point Jacobians, c (K, 3) offsets; n set coordinates."""

    def __init__(self, idx, S, c, n):
        self.idx = np.ascontiguousarray(idx, dtype=np.int64)
        self.S = np.ascontiguousarray(S, dtype=float)
        self.c = np.ascontiguousarray(c, dtype=float)
        self.n = int(n)
