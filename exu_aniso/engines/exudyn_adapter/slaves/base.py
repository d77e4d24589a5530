"""What every slave answers: the interface the contact set and the constructor read.

A slave carries the contact points of one contact set: a rigid body or a group of them, mass points,
cables, the nodes of a finite-element body (full, or reduced in a floating frame). Its numpy
kinematics give, at the set's coordinates q (reference values excluded) and velocities q_t, the
points' global positions x (K, 3), velocities v (K, 3) and virtual-work Jacobians Jp (K, 3, n); the
compiled route has its own copy of the rigid and linear kinematics (exu_aniso.kernel.nodes), held
equal to these kind by kind by tests/test_jacobian_nodes.py.

Attributes every slave has: ``kind`` (Exudyn's node type name, or the object's where the kernel has
no node kind), ``n`` (coordinates), ``nodes`` (Exudyn node numbers, the contact object's order),
``node`` (the first), ``ref``, ``q0``, ``v0`` (n,) (reference, initial coordinates and velocities).
Methods: ``number_of_points(b)``, ``coordinates(mbs, variable, configuration)``, ``points(q, q_t,
b)`` -> (x, v, Jp, A or None), ``point_derivatives(q, b)`` (dJp/dq, None when Jp is constant),
``position_jacobian(q, b, Jp)`` (dx/dq), ``tangent_terms(q, q_t, b, F)`` (a slave whose Jp depends on
q) and ``check_points(points)``."""
from __future__ import annotations

import numpy as np


class Slave:
    """The defaults of the interface above; a slave kind overrides what differs."""

    linear = False
    """True when x = c + S q with a constant point Jacobian S (no geometric Jacobian terms)."""

    points_are_nodes = False
    """True when the contact points are nodes of the body (a mesh), chosen by localPoints as node
    indices or positions (resolved, and a node twice refused, by the slave), with no offset from
    them: the constructor then passes zero offsets and asks check_points nothing."""

    compiled_route = "set"
    """The compiled kernel for its kinematics: "set" (kernel.sets.evaluate_set or evaluate_linear;
    with a moving master evaluate_pair), "group" (evaluate_group) or None (no node kind in the
    kernel: numpy kinematics, the law at the points compiled where the law compiles)."""

    moving_master = True
    """Whether its contact set may have a surface carried by a moving body."""

    def check_points(self, points):
        """Refuse local points (K, 3) the slave cannot carry: the same point twice (each row is one
        contact point with the law's stiffness)."""
        _, inverse, counts = np.unique(points, axis=0, return_inverse=True, return_counts=True)
        if (counts > 1).any():
            rows = np.flatnonzero(counts[np.ravel(inverse)] > 1)
            raise ValueError(f"CreateAnisotropicContact: localPoints lists a point more than once (rows "
                             f"{rows[:6].tolist()}: {points[rows[0]].tolist()}); each row is one contact point, so "
                             f"give each once (its stiffness is the contact law's per point)")
