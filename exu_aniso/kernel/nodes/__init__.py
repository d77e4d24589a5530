"""The slave's node in the compiled contact sets, one type per node kind, resolved at compile time.

Why: a set's kernel (``exu_aniso.kernel.sets``) needs the kinematics of the Exudyn node its points
ride on: positions, velocities, point Jacobians, how point forces add up to generalized forces,
and the derivatives of all that for the Jacobian. Each node kind is a type, a named tuple without
fields (``RigidBody2D()``, ``ScrewJoint()``, ``RotationVector()``, ``EulerParameters()``, and
``LinearSlave()`` for mass points and cables under a moving master), and each function below is
an overload keyed by that type, as the surfaces of ``exu_aniso.geometry`` are: a kernel compiles
the code of its own node kind only, and adding a kind is a module with these functions and a line in
``MODELS``, not a branch in every function.

The node protocol (q, q_t: the node's coordinates and velocities without reference values; qt:
total coordinates; A (3, 3) rotation, G (3, nr) with omega_local = G q_t_rot; dA (nr, 9) dA_ij/dq_c
in row c as 3 i + j, Gt (3, nr) = G(e_t), both only where a kind needs them; b = (bx, by, bz) a
body-local point):

* ``node_frame(kind, q, q_t, ref, tangent, qt, A, G, dA, Gt)``: qt = ref + q, A and G; with
  tangent what the kind's derivatives need (Euler parameters: dA/de, G(e_t)).
* ``node_motion(kind, qt, q_t, G, nq)``: what the force path needs of the motion, once per call,
  as 6 numbers (a planar node's cos, sin of its angle and its rate; a 3D node's omega_local).
* ``node_point_xv(kind, qt, q_t, A, motion, bx, by, bz)``: (x, v, a_x, a_y): position x and
  velocity v of b (3-tuples) and a planar node's lever arm (a_x, a_y) (0, 0 for a 3D node).
* ``node_moment(kind, A, F0, F1, F2, bx, by, bz, ax, ay)``: the moment of the global force F at b
  (a planar node's about its axis in the third entry, a 3D node's b x A^T F).
* ``node_forces(kind, G, nq, Q, F0, F1, F2, M0, M1, M2)``: Q from the summed force and moment.
* ``node_point(kind, qt, q_t, A, G, dA, bx, by, bz, tangent, x, v, Jp, Jx, wl)``: x, v and the
  virtual-work Jacobian Jp (3, nq); with tangent the position Jacobian Jx = dx/dq where it is not
  Jp (Euler parameters); wl = omega_local of a 3D node.
* ``node_position_jacobian(kind, spare, Jp)``: the array node_point writes dx/dq into (spare or Jp).
* ``node_rotation_columns(kind, nq)``: (first, number) of the rotation coordinates.
* ``node_velocity_column(kind, c, q_t, A, dA, Gt, Jp, wl, bx, by, bz)``: dv/dq_c at fixed q_t for
  a rotation coordinate c (the point's velocity turning with the body).
* ``node_geometric(kind, A, G, dA, Jp, f, bx, by, bz, Kq)``: Kq += f . dJp/dq (the lever arm turning
  with the body) at a fixed global force f.
* ``node_coordinates(kind)``: the number of coordinates (a compile-time constant).

A moving master (a 3D node) adds ``master_derivatives(kind, qt, q_t, A, dA, Gt)`` (dA by its
rotation coordinates: the local increment for a rotation vector, e for Euler parameters),
``master_rate(kind, Gt, c)`` (dG_c q_t_rot) and ``master_normalisation(kind, A, G, dA, dAf, F, xr, y0,
y1, y2, col0, Kc)`` (the Euler parameters' terms of G(e) and A^T A).

The force paths take a set's points at once, one call per set and none per point:
``points_xv(kind, qt, q_t, A, G, b, X, V, L)`` (positions, velocities, lever arms) and
``generalized_force(kind, A, G, nq, b, F, L, Q)``. A moving master's slave goes through
``slave_points_xv``, ``slave_generalized_force`` and, per point in its Jacobian, ``slave_point``,
which take both a rigid slave's body-local points b and a linear slave's (idx, S, c);
``slave_is_linear(kind)`` is a constant. The formulas: ``planar``, ``spatial``, ``linear`` (one
module per family). No Exudyn here.
"""
from __future__ import annotations

from collections import namedtuple

from numba import njit
from numba.extending import overload

from exu_aniso.kernel.nodes import linear, planar, spatial

RigidBody2D = namedtuple("RigidBody2D", ())           # Exudyn NodeRigidBody2D: (x, y, phi)
ScrewJoint = namedtuple("ScrewJoint", ())             # NodeGenericODE2 (psi, z): the reduced screw
RotationVector = namedtuple("RotationVector", ())     # NodeRigidBodyRotVecLG: (p, theta)
EulerParameters = namedtuple("EulerParameters", ())   # NodeRigidBodyEP: (p, e)
LinearSlave = namedtuple("LinearSlave", ())           # mass points and ANCF cables (x = c + S q)

# Exudyn's node type names (mbs.GetNode(n)["nodeType"]) -> the kind
NODE_KINDS = {"RigidBody2D": RigidBody2D(), "GenericODE2": ScrewJoint(), "RigidBodyRotVecLG": RotationVector(),
              "RigidBodyEP": EulerParameters()}

NodeModel = namedtuple("NodeModel", ("coordinates", "frame", "motion", "point_xv", "moment", "forces", "point",
                                     "position_jacobian", "rotation_columns", "velocity_column", "geometric"))
MasterModel = namedtuple("MasterModel", ("derivatives", "rate", "normalisation"))

MODELS = {
    RigidBody2D: NodeModel(3, planar.frame, planar.motion_2d, planar.point_xv_2d, planar.moment, planar.forces_2d,
                           planar.point_2d, planar.position_jacobian, planar.rotation_columns_2d,
                           planar.velocity_column, planar.geometric_2d),
    ScrewJoint: NodeModel(2, planar.frame, planar.motion_screw, planar.point_xv_screw, planar.moment,
                          planar.forces_screw, planar.point_screw, planar.position_jacobian,
                          planar.rotation_columns_screw, planar.velocity_column, planar.geometric_screw),
    RotationVector: NodeModel(6, spatial.frame_rv, spatial.motion, spatial.point_xv, spatial.moment, spatial.forces,
                              spatial.point_rv, spatial.position_jacobian_rv, spatial.rotation_columns,
                              spatial.velocity_column_rv, spatial.geometric_rv),
    EulerParameters: NodeModel(7, spatial.frame_ep, spatial.motion, spatial.point_xv, spatial.moment, spatial.forces,
                               spatial.point_ep, spatial.position_jacobian_ep, spatial.rotation_columns,
                               spatial.velocity_column_ep, spatial.geometric_ep),
    # points come from (idx, S, c): the slave_point functions; no frame, no rotation
    LinearSlave: NodeModel(None, linear.frame, None, None, None, None, None, linear.position_jacobian,
                           linear.rotation_columns, linear.velocity_column, linear.geometric),
}
MASTERS = {
    RotationVector: MasterModel(spatial.master_derivatives_rv, spatial.master_rate_rv,
                                spatial.master_normalisation_rv),
    EulerParameters: MasterModel(spatial.master_derivatives_ep, spatial.master_rate_ep,
                                 spatial.master_normalisation_ep),
}


def node_coordinates_of(kind):
    """The number of coordinates of a rigid node kind (an instance of one of MODELS' types)."""
    return MODELS[type(kind)].coordinates


def _model(kind, table=None, name=None):
    """The model of the numba type ``kind`` in table (MODELS), its function ``name``, or None (the
    overload then does not apply and numba says so)."""
    model = (MODELS if table is None else table).get(getattr(kind, "instance_class", None))
    fn = None if model is None else getattr(model, name)
    return fn


# --- the protocol: one stub and one overload each (resolved by the type of kind) ---------------

def node_frame(kind, q, q_t, ref, tangent, qt, A, G, dA, Gt):
    raise NotImplementedError("resolved at compile time by the node kind")


def node_motion(kind, qt, q_t, G, nq):
    raise NotImplementedError("resolved at compile time by the node kind")


def node_point_xv(kind, qt, q_t, A, motion, bx, by, bz):
    raise NotImplementedError("resolved at compile time by the node kind")


def node_moment(kind, A, F0, F1, F2, bx, by, bz, ax, ay):
    raise NotImplementedError("resolved at compile time by the node kind")


def node_forces(kind, G, nq, Q, F0, F1, F2, M0, M1, M2):
    raise NotImplementedError("resolved at compile time by the node kind")


def node_point(kind, qt, q_t, A, G, dA, bx, by, bz, tangent, x, v, Jp, Jx, wl):
    raise NotImplementedError("resolved at compile time by the node kind")


def node_position_jacobian(kind, spare, Jp):
    raise NotImplementedError("resolved at compile time by the node kind")


def node_rotation_columns(kind, nq):
    raise NotImplementedError("resolved at compile time by the node kind")


def node_velocity_column(kind, c, q_t, A, dA, Gt, Jp, wl, bx, by, bz):
    raise NotImplementedError("resolved at compile time by the node kind")


def node_geometric(kind, A, G, dA, Jp, f, bx, by, bz, Kq):
    raise NotImplementedError("resolved at compile time by the node kind")


def node_coordinates(kind):
    raise NotImplementedError("resolved at compile time by the node kind")


def master_derivatives(kind, qt, q_t, A, dA, Gt):
    raise NotImplementedError("resolved at compile time by the master's node kind")


def master_rate(kind, Gt, c):
    raise NotImplementedError("resolved at compile time by the master's node kind")


def master_normalisation(kind, A, G, dA, dAf, F, xr, y0, y1, y2, col0, Kc):
    raise NotImplementedError("resolved at compile time by the master's node kind")


def slave_is_linear(kind):
    raise NotImplementedError("resolved at compile time by the node kind")


def slave_point(kind, k, b, idx, Sm, c, ref, q, q_t, qt, qs_t, A, G, dA, tangent, x, v, Jp, Jx, wl, cols):
    raise NotImplementedError("resolved at compile time by the node kind")


# inline="always" (numba IR) where a function runs per point or hands back an array, and on a force
# call's path (the frame, the points, the generalized force): a call between numba functions is an
# indirect call that passes every array exploded into its fields, with reference counts, about 30 ns
# per call layer with ten arrays (the 64 cubes' group Jacobian, sticking: 925 ns per point inlined,
# 1281 as calls; the compiled entry of a moving master's set on 4 points called in a numba loop:
# 1.23 -> 0.50 us, the fixed plane's 0.51 -> 0.39 us, 2026-11-27; the block's first run with an empty
# cache unchanged, 28 s CPU). The
# Jacobian's per-set functions stay calls: every inlined call site is typed again (the block's
# first run took 23 s CPU with all of them inlined, 18 s with none).
@overload(node_frame, inline="always")
def _node_frame(kind, q, q_t, ref, tangent, qt, A, G, dA, Gt):
    fn = _model(kind, name="frame")
    if fn is not None:
        return lambda kind, q, q_t, ref, tangent, qt, A, G, dA, Gt: fn(q, q_t, ref, tangent, qt, A, G, dA, Gt)


@overload(node_motion, inline="always")
def _node_motion(kind, qt, q_t, G, nq):
    fn = _model(kind, name="motion")
    if fn is not None:
        return lambda kind, qt, q_t, G, nq: fn(qt, q_t, G, nq)


@overload(node_point_xv, inline="always")
def _node_point_xv(kind, qt, q_t, A, motion, bx, by, bz):
    fn = _model(kind, name="point_xv")
    if fn is not None:
        return lambda kind, qt, q_t, A, motion, bx, by, bz: fn(qt, q_t, A, motion, bx, by, bz)


@overload(node_moment, inline="always")
def _node_moment(kind, A, F0, F1, F2, bx, by, bz, ax, ay):
    fn = _model(kind, name="moment")
    if fn is not None:
        return lambda kind, A, F0, F1, F2, bx, by, bz, ax, ay: fn(A, F0, F1, F2, bx, by, bz, ax, ay)


@overload(node_forces, inline="always")
def _node_forces(kind, G, nq, Q, F0, F1, F2, M0, M1, M2):
    fn = _model(kind, name="forces")
    if fn is not None:
        return lambda kind, G, nq, Q, F0, F1, F2, M0, M1, M2: fn(G, nq, Q, F0, F1, F2, M0, M1, M2)


@overload(node_point, inline="always")
def _node_point(kind, qt, q_t, A, G, dA, bx, by, bz, tangent, x, v, Jp, Jx, wl):
    fn = _model(kind, name="point")
    if fn is not None:
        return (lambda kind, qt, q_t, A, G, dA, bx, by, bz, tangent, x, v, Jp, Jx, wl:
                fn(qt, q_t, A, G, dA, bx, by, bz, tangent, x, v, Jp, Jx, wl))


@overload(node_position_jacobian, inline="always")
def _node_position_jacobian(kind, spare, Jp):
    fn = _model(kind, name="position_jacobian")
    if fn is not None:
        return lambda kind, spare, Jp: fn(spare, Jp)


@overload(node_rotation_columns)
def _node_rotation_columns(kind, nq):
    fn = _model(kind, name="rotation_columns")
    if fn is not None:
        return lambda kind, nq: fn(nq)


@overload(node_velocity_column)
def _node_velocity_column(kind, c, q_t, A, dA, Gt, Jp, wl, bx, by, bz):
    fn = _model(kind, name="velocity_column")
    if fn is not None:
        return lambda kind, c, q_t, A, dA, Gt, Jp, wl, bx, by, bz: fn(c, q_t, A, dA, Gt, Jp, wl, bx, by, bz)


@overload(node_geometric)
def _node_geometric(kind, A, G, dA, Jp, f, bx, by, bz, Kq):
    fn = _model(kind, name="geometric")
    if fn is not None:
        return lambda kind, A, G, dA, Jp, f, bx, by, bz, Kq: fn(A, G, dA, Jp, f, bx, by, bz, Kq)


@overload(node_coordinates, inline="always")
def _node_coordinates(kind):
    n = _model(kind, name="coordinates")
    if n is not None:
        return lambda kind: n


@overload(master_derivatives)
def _master_derivatives(kind, qt, q_t, A, dA, Gt):
    fn = _model(kind, MASTERS, "derivatives")
    if fn is not None:
        return lambda kind, qt, q_t, A, dA, Gt: fn(qt, q_t, A, dA, Gt)


@overload(master_rate)
def _master_rate(kind, Gt, c):
    fn = _model(kind, MASTERS, "rate")
    if fn is not None:
        return lambda kind, Gt, c: fn(Gt, c)


@overload(master_normalisation)
def _master_normalisation(kind, A, G, dA, dAf, F, xr, y0, y1, y2, col0, Kc):
    fn = _model(kind, MASTERS, "normalisation")
    if fn is not None:
        return (lambda kind, A, G, dA, dAf, F, xr, y0, y1, y2, col0, Kc:
                fn(A, G, dA, dAf, F, xr, y0, y1, y2, col0, Kc))


def _is_linear(kind):
    return getattr(kind, "instance_class", None) is LinearSlave


@overload(slave_is_linear, inline="always")
def _slave_is_linear(kind):
    if getattr(kind, "instance_class", None) in MODELS:
        flag = _is_linear(kind)
        return lambda kind: flag


@overload(slave_point, inline="always")
def _slave_point(kind, k, b, idx, Sm, c, ref, q, q_t, qt, qs_t, A, G, dA, tangent, x, v, Jp, Jx, wl, cols):
    if _is_linear(kind):
        def impl(kind, k, b, idx, Sm, c, ref, q, q_t, qt, qs_t, A, G, dA, tangent, x, v, Jp, Jx, wl, cols):
            linear.point(k, idx, Sm, c, ref, q, q_t, x, v, Jp, cols)
            return 0.0, 0.0, 0.0
        return impl
    fn = _model(kind, name="point")
    if fn is not None:
        def rigid(kind, k, b, idx, Sm, c, ref, q, q_t, qt, qs_t, A, G, dA, tangent, x, v, Jp, Jx, wl, cols):
            bx, by, bz = b[k, 0], b[k, 1], b[k, 2]
            fn(qt, qs_t, A, G, dA, bx, by, bz, tangent, x, v, Jp, Jx, wl)
            return bx, by, bz
        return rigid


# --- a set's points at once: what the force paths call (one call per set, no call per point) -----

@njit(cache=True, inline="always")
def points_xv(kind, qt, q_t, A, G, b, X, V, L):
    """Positions X (K, 3), velocities V (K, 3) and planar lever arms L (K, 2) (0 for a 3D node) of
    the body-local points b (K, 3) of a rigid node at total coordinates qt (node_frame's A, G)."""
    motion = node_motion(kind, qt, q_t, G, qt.shape[0])
    for k in range(b.shape[0]):
        x, v, ax, ay = node_point_xv(kind, qt, q_t, A, motion, b[k, 0], b[k, 1], b[k, 2])
        X[k, 0], X[k, 1], X[k, 2] = x[0], x[1], x[2]
        V[k, 0], V[k, 1], V[k, 2] = v[0], v[1], v[2]
        L[k, 0], L[k, 1] = ax, ay


@njit(cache=True, inline="always")
def generalized_force(kind, A, G, nq, b, F, L, Q):
    """Q[:nq] = sum_k Jp_k^T F_k of a rigid node with global point forces F (K, 3) at b (K, 3)
    (lever arms L from points_xv), summed as force and moment without a Jacobian per point: a 3D
    node's local moment m = sum b x A^T F mapped once by Q_rot = G^T m (= sum Jp_rot^T F, Jp_rot =
    -A [b]x G), a planar node's moment about its axis. A point out of contact has F = 0."""
    F0 = F1 = F2 = M0 = M1 = M2 = 0.0
    for k in range(b.shape[0]):
        f0, f1, f2 = F[k, 0], F[k, 1], F[k, 2]
        F0 += f0
        F1 += f1
        F2 += f2
        m0, m1, m2 = node_moment(kind, A, f0, f1, f2, b[k, 0], b[k, 1], b[k, 2], L[k, 0], L[k, 1])
        M0 += m0
        M1 += m1
        M2 += m2
    node_forces(kind, G, nq, Q, F0, F1, F2, M0, M1, M2)


def slave_points_xv(kind, b, idx, Sm, c, ref, q, q_t, qt, A, G, X, V, L):
    raise NotImplementedError("resolved at compile time by the node kind")


def slave_generalized_force(kind, A, G, nq, b, idx, Sm, F, L, Q):
    raise NotImplementedError("resolved at compile time by the node kind")


@overload(slave_points_xv, inline="always")
def _slave_points_xv(kind, b, idx, Sm, c, ref, q, q_t, qt, A, G, X, V, L):
    """points_xv of a rigid slave; a linear slave's points from (idx, S, c)."""
    if _is_linear(kind):
        return (lambda kind, b, idx, Sm, c, ref, q, q_t, qt, A, G, X, V, L:
                linear.points_xv(idx, Sm, c, ref, q, q_t, X, V, L))
    if getattr(kind, "instance_class", None) in MODELS:
        return (lambda kind, b, idx, Sm, c, ref, q, q_t, qt, A, G, X, V, L:
                points_xv(kind, qt, q_t, A, G, b, X, V, L))


@overload(slave_generalized_force, inline="always")
def _slave_generalized_force(kind, A, G, nq, b, idx, Sm, F, L, Q):
    """generalized_force of a rigid slave; a linear slave's Q[idx_k] += S_k^T F_k."""
    if _is_linear(kind):
        return lambda kind, A, G, nq, b, idx, Sm, F, L, Q: linear.generalized_force(idx, Sm, F, Q)
    if getattr(kind, "instance_class", None) in MODELS:
        return lambda kind, A, G, nq, b, idx, Sm, F, L, Q: generalized_force(kind, A, G, nq, b, F, L, Q)
