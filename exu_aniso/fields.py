"""Tensor fields for the adhesion tensor B and the friction tensor F on a master surface.

Both are orthotropic fields ``P = lambda_1 e1 e1 + lambda_2 e2 e2`` built on a direction field
``e1(C)`` of the surface (e2 = e1 rotated by +90 deg in the tangent plane):

* adhesion: ``C = -B`` with ``lambda_k = eps_k`` (tangential penalty stiffness, N/m per point),
  ``B = -C`` (the papers' sign);
* friction: ``F`` with ``lambda_k = 1 / mu_k**2`` (mu_k: Coulomb coefficients along e_k).

Direction fields:

* ``isotropic``:   lambda_1 = lambda_2 (any surface);
* ``orthotropic``: constant angle in the transport frame (plane: from e_x towards e_y;
  cylinder: from e_phi towards e_z);
* ``polar``:       plane only, e1 = e_r, e2 = e_phi about the origin (papers' eq. 8). Undefined at
  the origin; with ``core_radius = r_c > 0`` the projector e_r e_r is regularised to
  ``(x x^T + r_c^2/2 I) / (|x|^2 + r_c^2)`` (smooth, SPD kept, isotropic mean at the origin,
  relative deviation from the exact field ~ (r_c/r)^2). With r_c = 0 evaluating at the origin
  raises ValueError;
* ``spiral``:      cylinder only, e1 along the helix of angle alpha (pitch p = 2 pi R tan alpha),
  e1 = cos(alpha) e_phi + sin(alpha) e_z (papers' second example).

Components: ``physical(surface, u)`` gives the (K, 3) components ``(s11, s12, s22)`` in the
surface transport frame and their derivative with respect to the arc-length coordinates of C;
``components(surface, xi)`` gives the components in the chart basis as the papers store them
(B covariant b_ij, F contravariant f^ij).
"""
from __future__ import annotations

import math

import numpy as np

from .validation import check_nonnegative, check_positive, check_real, check_spd

_ADHESION, _FRICTION = "adhesion", "friction"


class TensorField:
    """An orthotropic tensor field (adhesion B or friction F); build it with Adhesion / Friction."""

    def __init__(self, kind, pattern, lam, angle=0.0, core_radius=0.0, matrix=None, label=""):
        self.kind = kind
        self.pattern = pattern
        self.lam = lam                  # eigenvalues of the positive tensor (C or F)
        self.angle = angle
        self.core_radius = core_radius
        self.sign = -1.0 if kind == _ADHESION else 1.0
        self.label = label
        if matrix is not None:          # constant components given directly (positive tensor)
            self._const = np.array(matrix, dtype=float)
        elif pattern in ("isotropic", "orthotropic", "spiral") and angle is not None:
            c, s = math.cos(angle), math.sin(angle)
            l1, l2 = lam
            self._const = np.array([l1 * c * c + l2 * s * s, (l1 - l2) * c * s, l1 * s * s + l2 * c * c])
        else:
            self._const = None

    def __repr__(self):
        return f"{'Adhesion' if self.kind == _ADHESION else 'Friction'}.{self.label}"

    @property
    def is_constant(self):
        return self._const is not None

    def check_surface(self, surface):
        """Raise if this direction field is not defined on the surface type."""
        if self.pattern == "polar" and surface.kind != "plane":
            raise ValueError(f"{self!r}: polar orthotropy is defined on a Plane only; got {surface!r}")
        if self.pattern == "spiral" and surface.kind != "cylinder":
            raise ValueError(f"{self!r}: spiral orthotropy is defined on a Cylinder only; got {surface!r}")
        if self.pattern == "spiral" and self.angle is None:
            raise ValueError(f"{self!r}: a spiral given by its lead needs a surface of exu_aniso (the protocol's "
                             f"Cylinder, Cone, SurfaceOfRevolution, ...); got {surface!r}")

    def physical(self, u, derivatives=True):
        """Components (K, 3) of B (adhesion, negative definite) or F in the transport frame, and
        their derivative (K, 3, 2) with respect to the arc-length coordinates of C."""
        u = np.asarray(u, dtype=float)
        K = u.shape[0]
        if self._const is not None:
            P = np.broadcast_to(self.sign * self._const, (K, 3)).copy()
            return P, (np.zeros((K, 3, 2)) if derivatives else None)
        x, y = u[:, 0], u[:, 1]
        rc2 = self.core_radius ** 2
        d = x * x + y * y + rc2
        if not np.all(np.isfinite(d)):
            raise ValueError(f"{self!r}: point coordinates too large or not finite for the polar field: "
                             f"x^2 + y^2 overflows (max |x|, |y| = {np.max(np.abs(u[:, :2])):.3g} m)")
        if np.any(d <= 0.0):
            raise ValueError(f"{self!r}: polar orthotropy is undefined at the polar origin (x = y = 0); "
                             "set core_radius > 0 to regularise it there")
        M = np.stack([(x * x + 0.5 * rc2) / d, x * y / d, (y * y + 0.5 * rc2) / d], axis=-1)
        l1, l2 = self.lam
        P = self.sign * (l2 * np.array([1.0, 0.0, 1.0]) + (l1 - l2) * M)
        dP = None
        if derivatives:
            dM = np.empty((K, 3, 2))
            dM[:, 0, 0] = (2 * x - 2 * x * M[:, 0]) / d
            dM[:, 0, 1] = (-2 * y * M[:, 0]) / d
            dM[:, 1, 0] = (y - 2 * x * M[:, 1]) / d
            dM[:, 1, 1] = (x - 2 * y * M[:, 1]) / d
            dM[:, 2, 0] = (-2 * x * M[:, 2]) / d
            dM[:, 2, 1] = (2 * y - 2 * y * M[:, 2]) / d
            dP = self.sign * (l1 - l2) * dM
        return P, dP

    def components(self, surface, xi):
        """Components in the chart basis at chart coordinates xi: B -> covariant b_ij,
        F -> contravariant f^ij, as a 2x2 array."""
        self.check_surface(surface)
        L = surface.transport_matrix(xi)
        u = surface.frame_position(xi)[None, :]
        p = self.physical(u, derivatives=False)[0][0]
        P = np.array([[p[0], p[1]], [p[1], p[2]]])
        if self.kind == _ADHESION:
            return L.T @ P @ L
        Li = np.linalg.inv(L)
        return Li @ P @ Li.T


def _pair(kind, n1, v1, n2, v2):
    if kind == _ADHESION:
        return check_positive(n1, v1), check_positive(n2, v2)
    return 1.0 / check_positive(n1, v1) ** 2, 1.0 / check_positive(n2, v2) ** 2


def _helix(helix_angle):
    a = check_real("helix_angle", helix_angle)
    if not -0.5 * math.pi < a < 0.5 * math.pi:
        raise ValueError(f"helix_angle must lie in (-pi/2, pi/2) rad; got {a!r}")
    return a


def _spiral(kind, n1, v1, n2, v2, helix_angle, lead):
    """A spiral net given by its helix angle (at the surface's radius: Cylinder, Cone) or by its
    lead [m of the second surface coordinate per turn] (any surface of revolution)."""
    lam = _pair(kind, n1, v1, n2, v2)
    if (helix_angle is None) == (lead is None):
        raise ValueError(f"spiral: give exactly one of helix_angle [rad] and lead [m per turn]; got "
                         f"helix_angle={helix_angle!r}, lead={lead!r}")
    name = "Adhesion" if kind == _ADHESION else "Friction"
    if lead is not None:
        f = TensorField(kind, "spiral", lam, angle=None, label=f"spiral({v1}, {v2}, lead={lead})")
        f.lead = check_real("lead", lead)
        return f
    a = _helix(helix_angle)
    return TensorField(kind, "spiral", lam, angle=a, label=f"spiral({v1}, {v2}, helix_angle={a})")


class Adhesion:
    """Adhesion tensor fields B = -(eps_1 e1 e1 + eps_2 e2 e2); stiffnesses in N/m (per point)."""

    @staticmethod
    def isotropic(stiffness):
        l1, l2 = _pair(_ADHESION, "stiffness", stiffness, "stiffness", stiffness)
        return TensorField(_ADHESION, "isotropic", (l1, l2), label=f"isotropic({stiffness})")

    @staticmethod
    def orthotropic(eps_1, eps_2, angle=0.0):
        """Constant orthotropy; angle [rad] of e1 in the transport frame."""
        lam = _pair(_ADHESION, "eps_1", eps_1, "eps_2", eps_2)
        return TensorField(_ADHESION, "orthotropic", lam, angle=check_real("angle", angle),
                           label=f"orthotropic({eps_1}, {eps_2}, angle={angle})")

    @staticmethod
    def polar(eps_r, eps_phi, core_radius=0.0):
        """Polar orthotropy on a plane (papers' eq. 8): radial eps_r, circumferential eps_phi."""
        lam = _pair(_ADHESION, "eps_r", eps_r, "eps_phi", eps_phi)
        return TensorField(_ADHESION, "polar", lam, core_radius=check_nonnegative("core_radius", core_radius),
                           label=f"polar({eps_r}, {eps_phi}, core_radius={core_radius})")

    @staticmethod
    def spiral(eps_1, eps_2, helix_angle=None, lead=None):
        """Spiral orthotropy: eps_1 along the helix, eps_2 across; the helix by its angle [rad] at
        the surface's radius (Cylinder, Cone) or by its lead [m per turn] (any surface of revolution)."""
        return _spiral(_ADHESION, "eps_1", eps_1, "eps_2", eps_2, helix_angle, lead)

    @staticmethod
    def from_matrix(B):
        """Constant B given by its 2x2 transport-frame components, papers' sign (negative definite)."""
        b = check_spd("B", B, sign=-1.0)
        return TensorField(_ADHESION, "matrix", None, matrix=[-b[0], -b[1], -b[2]], label=f"from_matrix({b})")


class Friction:
    """Friction tensor fields F = e1 e1 / mu_1^2 + e2 e2 / mu_2^2 (Coulomb coefficients mu_k > 0)."""

    @staticmethod
    def isotropic(mu):
        lam = _pair(_FRICTION, "mu", mu, "mu", mu)
        return TensorField(_FRICTION, "isotropic", lam, label=f"isotropic({mu})")

    @staticmethod
    def orthotropic(mu_1, mu_2, angle=0.0):
        lam = _pair(_FRICTION, "mu_1", mu_1, "mu_2", mu_2)
        return TensorField(_FRICTION, "orthotropic", lam, angle=check_real("angle", angle),
                           label=f"orthotropic({mu_1}, {mu_2}, angle={angle})")

    @staticmethod
    def polar(mu_r, mu_phi, core_radius=0.0):
        lam = _pair(_FRICTION, "mu_r", mu_r, "mu_phi", mu_phi)
        return TensorField(_FRICTION, "polar", lam, core_radius=check_nonnegative("core_radius", core_radius),
                           label=f"polar({mu_r}, {mu_phi}, core_radius={core_radius})")

    @staticmethod
    def spiral(mu_1, mu_2, helix_angle=None, lead=None):
        """Spiral friction net, as Adhesion.spiral (mu_1 along the helix, mu_2 across)."""
        return _spiral(_FRICTION, "mu_1", mu_1, "mu_2", mu_2, helix_angle, lead)

    @staticmethod
    def from_matrix(F):
        """Constant F given by its 2x2 transport-frame components (symmetric positive definite)."""
        f = check_spd("F", F)
        return TensorField(_FRICTION, "matrix", None, matrix=list(f), label=f"from_matrix({f})")
