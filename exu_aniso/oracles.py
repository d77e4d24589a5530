"""Analytic answers the scenes are checked against (numpy/scipy only; independent of the
contact-law code: force balances of Coulomb friction, not return maps).

The screw's steady sliding state is in ``exu_aniso.calibration.steady_sliding``.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq


def orthotropic_heading(pull_angle, pull, normal_force, mu_1, mu_2):
    """Heading [rad] of the steady sliding of a body pulled from rest by a constant force
    ``pull`` [N] at ``pull_angle`` [rad] from e_1 on a plane with orthotropic Coulomb friction
    (coefficient mu_1 along e_1, mu_2 along e_2) and the associated (maximum-dissipation) law,
    under the normal force ``normal_force`` [N].

    The friction force for the sliding direction v is -|N| F^-1 v / sqrt(v.F^-1 v),
    F^-1 = diag(mu_1^2, mu_2^2); the heading is the v where pull + friction is parallel to v
    (then the body accelerates along v and the direction stays constant). Solved with brentq in
    the quadrant of the pull (the problem is symmetric under reflections of either axis). Raises
    ValueError when the pull lies inside the friction ellipse (the body sticks) or an input is
    not finite / not positive."""
    for name, v in (("pull", pull), ("normal_force", normal_force), ("mu_1", mu_1), ("mu_2", mu_2)):
        if not (isinstance(v, (int, float, np.floating)) and math.isfinite(v) and v > 0):
            raise ValueError(f"orthotropic_heading: {name} must be a finite number > 0; got {v!r}")
    if not math.isfinite(pull_angle):
        raise ValueError(f"orthotropic_heading: pull_angle must be finite; got {pull_angle!r}")
    px, py = pull * math.cos(pull_angle), pull * math.sin(pull_angle)
    if (px / (mu_1 * normal_force)) ** 2 + (py / (mu_2 * normal_force)) ** 2 <= 1.0:
        raise ValueError(f"orthotropic_heading: the pull ({px:.6g}, {py:.6g}) N lies inside the friction ellipse "
                         f"(mu_1 |N|, mu_2 |N|) = ({mu_1 * normal_force:.6g}, {mu_2 * normal_force:.6g}) N: "
                         "the body sticks, there is no sliding heading")
    ax, ay = abs(px), abs(py)
    if ay <= 1e-15 * pull:
        phi = 0.0
    elif ax <= 1e-15 * pull:
        phi = 0.5 * math.pi
    else:
        m1, m2 = mu_1 ** 2, mu_2 ** 2

        def cross(phi):              # (pull + friction(phi)) x v
            c, s = math.cos(phi), math.sin(phi)
            k = normal_force / math.sqrt(m1 * c * c + m2 * s * s)
            return (ax - k * m1 * c) * s - (ay - k * m2 * s) * c

        phi = brentq(cross, 0.0, 0.5 * math.pi, xtol=1e-15, maxiter=200)
    return math.atan2(math.copysign(math.sin(phi), py), math.copysign(math.cos(phi), px))
