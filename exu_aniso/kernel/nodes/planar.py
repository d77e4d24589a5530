"""Planar rigid nodes: the body turns about the global z axis by one rotation coordinate.

``RigidBody2D``: Exudyn's ``NodeRigidBody2D``, q = (x, y, phi); a body-local point b goes to
x = (x + a_x, y + a_y, b_z) with (a_x, a_y) = R(phi) (b_x, b_y).
``ScrewJoint``: a ``NodeGenericODE2`` with q = (psi, z) (the reduced screw: a turn psi about the
axis and the advance z along it); b goes to x = (a_x, a_y, b_z + z) with (a_x, a_y) = R(psi) (b_x, b_y).

The functions follow the node protocol of ``exu_aniso.kernel.nodes`` (its docstring: arguments
and what each returns); unused arguments (A, G, dA of a 3D node) are there for the one signature.
The velocity of a point is v = Jp q_t; the moment about the axis of a force F at the point is
a_x F_y - a_y F_x; the lever arm turns with the body (the geometric term of the Jacobian)."""
from __future__ import annotations

import math

from numba import njit


@njit(cache=True, inline="always")
def frame(q, q_t, ref, tangent, qt, A, G, dA, Gt):
    """Total coordinates qt = ref + q (a planar node has no rotation matrix)."""
    for i in range(q.shape[0]):
        qt[i] = ref[i] + q[i]


@njit(cache=True, inline="always")
def motion_2d(qt, q_t, G, nq):
    """(cos phi, sin phi, dphi/dt, 0, 0, 0)."""
    return math.cos(qt[2]), math.sin(qt[2]), q_t[2], 0.0, 0.0, 0.0


@njit(cache=True, inline="always")
def motion_screw(qt, q_t, G, nq):
    """(cos psi, sin psi, dpsi/dt, 0, 0, 0)."""
    return math.cos(qt[0]), math.sin(qt[0]), q_t[0], 0.0, 0.0, 0.0


@njit(cache=True, inline="always")
def point_xv_2d(qt, q_t, A, motion, bx, by, bz):
    c, s, w = motion[0], motion[1], motion[2]
    ax, ay = c * bx - s * by, s * bx + c * by
    return (qt[0] + ax, qt[1] + ay, bz), (q_t[0] - w * ay, q_t[1] + w * ax, 0.0), ax, ay


@njit(cache=True, inline="always")
def point_xv_screw(qt, q_t, A, motion, bx, by, bz):
    c, s, w = motion[0], motion[1], motion[2]
    ax, ay = c * bx - s * by, s * bx + c * by
    return (ax, ay, bz + qt[1]), (-w * ay, w * ax, q_t[1]), ax, ay


@njit(cache=True, inline="always")
def moment(A, F0, F1, F2, bx, by, bz, ax, ay):
    """The moment about the axis (third entry) of F at the point with lever arm (a_x, a_y)."""
    return 0.0, 0.0, ax * F1 - ay * F0


@njit(cache=True, inline="always")
def forces_2d(G, nq, Q, F0, F1, F2, M0, M1, M2):
    Q[0], Q[1], Q[2] = F0, F1, M2


@njit(cache=True, inline="always")
def forces_screw(G, nq, Q, F0, F1, F2, M0, M1, M2):
    Q[0], Q[1] = M2, F2


@njit(cache=True, inline="always")
def point_2d(qt, q_t, A, G, dA, bx, by, bz, tangent, x, v, Jp, Jx, wl):
    c, s = math.cos(qt[2]), math.sin(qt[2])
    xp, vp, ax, ay = point_xv_2d(qt, q_t, A, (c, s, q_t[2], 0.0, 0.0, 0.0), bx, by, bz)
    for i in range(3):
        x[i], v[i] = xp[i], vp[i]
    for i in range(3):
        for j in range(3):
            Jp[i, j] = 0.0
    Jp[0, 0] = 1.0
    Jp[1, 1] = 1.0
    Jp[0, 2] = -ay
    Jp[1, 2] = ax


@njit(cache=True, inline="always")
def point_screw(qt, q_t, A, G, dA, bx, by, bz, tangent, x, v, Jp, Jx, wl):
    c, s = math.cos(qt[0]), math.sin(qt[0])
    xp, vp, ax, ay = point_xv_screw(qt, q_t, A, (c, s, q_t[0], 0.0, 0.0, 0.0), bx, by, bz)
    for i in range(3):
        x[i], v[i] = xp[i], vp[i]
    for i in range(3):
        for j in range(2):
            Jp[i, j] = 0.0
    Jp[0, 0] = -ay
    Jp[1, 0] = ax
    Jp[2, 1] = 1.0


@njit(cache=True, inline="always")
def position_jacobian(spare, Jp):
    """dx/dq is Jp."""
    return Jp


@njit(cache=True)
def rotation_columns_2d(nq):
    return 2, 1


@njit(cache=True)
def rotation_columns_screw(nq):
    return 0, 1


@njit(cache=True)
def velocity_column(c, q_t, A, dA, Gt, Jp, wl, bx, by, bz):
    """d(w (-a_y, a_x))/d(angle) = w (-a_x, -a_y), with a_x = Jp[1, c], a_y = -Jp[0, c]."""
    w = q_t[c]
    return -w * Jp[1, c], w * Jp[0, c], 0.0


@njit(cache=True)
def geometric_2d(A, G, dA, Jp, f, bx, by, bz, Kq):
    Kq[2, 2] -= Jp[1, 2] * f[0] - Jp[0, 2] * f[1]


@njit(cache=True)
def geometric_screw(A, G, dA, Jp, f, bx, by, bz, Kq):
    Kq[0, 0] -= Jp[1, 0] * f[0] - Jp[0, 0] * f[1]
