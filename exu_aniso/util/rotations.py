"""Rotations in numpy, one definition for the engines (the compiled kernel has its own in
``exu_aniso.kernel.sets``, held equal by the tests): the skew matrix, Rodrigues' formula and the
angle wrap. Not ``exudyn.rigidBodyUtilities``: the reference engine runs without Exudyn, and
Exudyn 1.13's ``RotationVector2RotationMatrix`` is not a rotation beyond |th| = 2 pi (compared with
scipy's ``Rotation.from_rotvec``)."""
from __future__ import annotations

import math

import numpy as np


def skew(a):
    """[a]x (3, 3): skew(a) @ b = a x b."""
    return np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])


def rotation_matrix(th):
    """Rodrigues' formula: exp([th]x), the rotation by the rotation vector th (3,) [rad]."""
    th = np.asarray(th, dtype=float)
    phi = math.sqrt(th @ th)
    W = skew(th)
    if phi < 1e-8:
        return np.eye(3) + W + 0.5 * W @ W
    return np.eye(3) + math.sin(phi) / phi * W + (1.0 - math.cos(phi)) / phi ** 2 * W @ W


def wrap_angle(a):
    """The angle a [rad] wrapped to (-pi, pi]."""
    return math.pi - (math.pi - a) % (2.0 * math.pi)
