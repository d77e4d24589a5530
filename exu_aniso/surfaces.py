"""Analytical rigid master surfaces: closest point projection and surface geometry.

Notation (papers' symbols): ``xi = (xi1, xi2)`` surface (convective) coordinates of the
projection point C, ``xi3`` signed normal gap, ``rho_i = d rho / d xi^i`` covariant basis,
``n`` unit normal (out of the master body), ``m_ij = rho_i . rho_j`` metric, ``m^ij`` its inverse,
``h_ij = rho_ij . n`` curvature. ``r_s = rho(xi) + n xi3``.

Two views of the same surface:

* the *chart* view (``project``, ``at``): the coordinates the user chose (plane: Cartesian
  ``(x, y)`` or polar ``(r, phi)``; cylinder: ``(phi, z)``), used to express tensor components
  in the surface basis as the papers do;
* the *transport frame* view (``frame``, batch over K points): an orthonormal tangent frame
  ``E = [a_1, a_2]`` in which parallel transport keeps components constant (plane: e_x, e_y;
  cylinder: e_phi, e_z) plus the arc-length coordinates ``u`` of C. The contact pipeline stores
  its history in this frame. ``Lambda = E^T [rho_1, rho_2]`` links the two.

All positions are in the master frame (ground, or the body the master surface is fixed to).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .validation import check_positive, check_vector


def wrap_angle(a):
    """Map an angle (or array of angles) to (-pi, pi]."""
    return np.pi - np.mod(np.pi - a, 2.0 * np.pi)


@dataclass
class Projection:
    """Closest point projection of one slave point (chart view). Shapes: rho (2, 3) rows rho_1,
    rho_2; rho2 (2, 2, 3) second derivatives rho_ij; m, m_inv, h (2, 2)."""

    xi: np.ndarray
    xi3: float
    point: np.ndarray
    rho: np.ndarray
    rho2: np.ndarray
    n: np.ndarray
    m: np.ndarray
    m_inv: np.ndarray
    h: np.ndarray

    @property
    def rho_contra(self):
        """Contravariant basis rho^i = m^ij rho_j, rows."""
        return self.m_inv @ self.rho


@dataclass
class Frame:
    """Transport-frame geometry of K slave points (batch view).

    gap (K,) = xi3; n (K, 3); E (K, 3, 2) columns a_1, a_2; u (K, 2) chart-free coordinates of
    C (plane: x, y; cylinder: phi, z); du_dx (K, 2, 3) derivative of the arc-length increment of C
    with respect to the slave position; dE_dx (K, 3, 2, 3); dn_dx (K, 3, 3); d2u_dx2 (K, 2, 3, 3)
    second derivative of the arc-length coordinates (the tangent of the conjugate force du_dx^T T).

    Why du_dx and not E carries the traction: slip is measured at the contact point C (papers'
    ``v_s - v = xi_dot^i rho_i``), and ``du_dx = (A^-1)^ij rho_j`` in frame components, with
    ``A_ij = m_ij - xi3 h_ij`` (SPEC section 7). The force on the slave point that is work
    conjugate to that slip is ``du_dx^T T``: its work is exactly ``T . du``. On a plane
    ``du_dx = E^T``; in a hole of radius R a slave point at distance d > R from the axis gets the
    tangential force (R / d) T_phi, so the friction torque about the axis is R T_phi.
    """

    gap: np.ndarray
    n: np.ndarray
    E: np.ndarray
    u: np.ndarray
    du_dx: np.ndarray
    dE_dx: np.ndarray | None
    dn_dx: np.ndarray | None
    d2u_dx2: np.ndarray | None = None


class Plane:
    """The plane z = 0 of the master frame, normal +z; slave side z > 0.

    coordinates: "cartesian" -> xi = (x, y); "polar" -> xi = (r, phi) about the origin,
    rho_1 = e_r, rho_2 = r e_phi, m = diag(1, r^2) (undefined at r = 0).
    """

    kind = "plane"

    def __init__(self, coordinates="cartesian"):
        if coordinates not in ("cartesian", "polar"):
            raise ValueError(f"Plane: coordinates must be 'cartesian' or 'polar'; got {coordinates!r}")
        self.coordinates = coordinates

    def __repr__(self):
        return f"Plane(coordinates={self.coordinates!r})"

    # --- chart view -------------------------------------------------------------------------
    def at(self, xi):
        """Surface geometry at chart coordinates xi (xi3 = 0)."""
        xi = check_vector("xi", xi, 2)
        z = np.zeros(3)
        if self.coordinates == "cartesian":
            point = np.array([xi[0], xi[1], 0.0])
            rho = np.array([[1.0, 0, 0], [0, 1.0, 0]])
            rho2 = np.zeros((2, 2, 3))
        else:
            r, phi = xi
            if not r > 0.0:
                raise ValueError(f"Plane(coordinates='polar'): the chart is singular at r = {r!r}; "
                                 "polar coordinates need r > 0 (the polar origin has no phi)")
            er = np.array([math.cos(phi), math.sin(phi), 0.0])
            ep = np.array([-math.sin(phi), math.cos(phi), 0.0])
            point = r * er
            rho = np.array([er, r * ep])
            rho2 = np.array([[z, ep], [ep, -r * er]])
        n = np.array([0.0, 0.0, 1.0])
        m = rho @ rho.T
        return Projection(np.array(xi, dtype=float), 0.0, point, rho, rho2, n, m, np.linalg.inv(m),
                          rho2 @ n)

    def project(self, x):
        """Closest point projection of the slave point x (3,)."""
        x = check_vector("x", x, 3)
        if self.coordinates == "cartesian":
            xi = (x[0], x[1])
        else:
            r = math.hypot(x[0], x[1])
            if r == 0.0:
                raise ValueError("Plane(coordinates='polar'): slave point at the polar origin "
                                 "(x = y = 0), where phi and the basis rho_2 = r e_phi are undefined")
            xi = (r, math.atan2(x[1], x[0]))
        p = self.at(xi)
        p.xi3 = float(x[2])
        return p

    # --- transport frame view ----------------------------------------------------------------
    def frame(self, x, derivatives=True):
        x = np.asarray(x, dtype=float)
        K = x.shape[0]
        E = np.zeros((K, 3, 2))
        E[:, 0, 0] = E[:, 1, 1] = 1.0
        n = np.zeros((K, 3))
        n[:, 2] = 1.0
        du_dx = np.zeros((K, 2, 3))
        du_dx[:, 0, 0] = du_dx[:, 1, 1] = 1.0
        dE = dn = d2u = None
        if derivatives:
            dE = np.zeros((K, 3, 2, 3))
            dn = np.zeros((K, 3, 3))
            d2u = np.zeros((K, 2, 3, 3))
        return Frame(x[:, 2].copy(), n, E, x[:, :2].copy(), du_dx, dE, dn, d2u)

    @staticmethod
    def resolve(u, u_old, predicted=None):
        """Arc-length increment du (K, 2), coordinates to store and the unresolved flag (K,) of a
        step from u_old to u. The plane has no periodic coordinate: never unresolved."""
        return u - u_old, np.array(u, dtype=float), np.zeros(np.shape(u)[:-1], dtype=bool)

    @classmethod
    def increment(cls, u, u_old):
        """Arc-length increment of C in the transport frame (K, 2)."""
        return cls.resolve(u, u_old)[0]

    @classmethod
    def continue_coordinates(cls, u, u_old):
        """Coordinates to store for the next step (no wrap on a plane)."""
        return cls.resolve(u, u_old)[1]

    def transport_matrix(self, xi):
        """Lambda = E^T [rho_1, rho_2] at chart coordinates xi: maps chart to frame components."""
        return self.at(xi).rho[:, :2].T.copy()

    def frame_position(self, xi):
        """Transport-frame coordinates u of the chart point xi."""
        p = self.at(xi).point
        return np.array([p[0], p[1]])

    @staticmethod
    def transport_vector(vec, xi_old, xi_new):
        """Parallel transport of a tangent vector on the plane: the vector itself."""
        return np.array(vec, dtype=float)

    def increment_vector(self, xi_old, xi_new):
        """Tangential displacement of C from xi_old to xi_new (3,): the chord on the plane."""
        return self.at(xi_new).point - self.at(xi_old).point


class Cylinder:
    """Circular cylinder of radius R about the axis through ``axis_point`` along ``axis_direction``.

    side: "inside" (a hole; slave inside, n towards the axis, xi3 = R - dist) or "outside"
    (a shaft; n away from the axis, xi3 = dist - R). Chart xi = (phi, z): rho_1 = R e_phi,
    rho_2 = e_axis, m = diag(R^2, 1), h_11 = +R (inside) / -R (outside). phi is measured about the
    axis from ``e_ref`` (the master-frame axis least aligned with the cylinder axis, made
    orthogonal to it). The axis itself (dist = 0) is singular.
    """

    kind = "cylinder"

    def __init__(self, radius, axis_point=(0.0, 0.0, 0.0), axis_direction=(0.0, 0.0, 1.0), side="inside"):
        self.radius = check_positive("radius", radius)
        self.axis_point = check_vector("axis_point", axis_point, 3)
        a = check_vector("axis_direction", axis_direction, 3)
        na = np.linalg.norm(a)
        if not na > 0.0:
            raise ValueError(f"Cylinder: axis_direction must be a non-zero vector; got {a.tolist()}")
        a = a / na
        if side not in ("inside", "outside"):
            raise ValueError(f"Cylinder: side must be 'inside' (hole) or 'outside' (shaft); got {side!r}")
        self.side = side
        self.sign = 1.0 if side == "outside" else -1.0  # n = sign * e_rho
        ref = np.eye(3)[int(np.argmin(np.abs(a)))]
        e1 = ref - (ref @ a) * a
        e1 /= np.linalg.norm(e1)
        self.axes = np.array([e1, np.cross(a, e1), a])  # rows: e_ref, e_ref2, e_axis
        self.coordinates = "cylindrical"

    def __repr__(self):
        return (f"Cylinder(radius={self.radius}, axis_point={list(self.axis_point)}, "
                f"axis_direction={list(self.axes[2])}, side={self.side!r})")

    def _local(self, x):
        return (np.asarray(x, dtype=float) - self.axis_point) @ self.axes.T

    # --- chart view -------------------------------------------------------------------------
    def at(self, xi):
        xi = check_vector("xi", xi, 2)
        phi, z = xi
        R = self.radius
        e1, e2, a = self.axes
        er = math.cos(phi) * e1 + math.sin(phi) * e2
        ep = -math.sin(phi) * e1 + math.cos(phi) * e2
        point = self.axis_point + R * er + z * a
        rho = np.array([R * ep, a])
        zero = np.zeros(3)
        rho2 = np.array([[-R * er, zero], [zero, zero]])
        n = self.sign * er
        m = rho @ rho.T
        return Projection(np.array(xi, dtype=float), 0.0, point, rho, rho2, n, m, np.linalg.inv(m),
                          rho2 @ n)

    def project(self, x):
        x = check_vector("x", x, 3)
        loc = self._local(x)
        dist = math.hypot(loc[0], loc[1])
        if not dist > 1e-14 * self.radius:
            raise ValueError("Cylinder: slave point on the cylinder axis; the closest point "
                             "projection is not unique there (every phi is equally close)")
        p = self.at((math.atan2(loc[1], loc[0]), loc[2]))
        p.xi3 = float(self.sign * (dist - self.radius))
        return p

    # --- transport frame view ----------------------------------------------------------------
    def gap(self, x):
        """xi3 (K,) without the projection (defined on the axis too)."""
        loc = self._local(x)
        return self.sign * (np.hypot(loc[:, 0], loc[:, 1]) - self.radius)

    def frame(self, x, derivatives=True):
        loc = self._local(x)
        K = loc.shape[0]
        dist = np.hypot(loc[:, 0], loc[:, 1])
        if np.any(dist <= 1e-14 * self.radius):
            raise ValueError("Cylinder: slave point on the cylinder axis; the closest point "
                             "projection is not unique there (every phi is equally close)")
        c, s = loc[:, 0] / dist, loc[:, 1] / dist
        e1, e2, a = self.axes
        er = c[:, None] * e1 + s[:, None] * e2
        ep = -s[:, None] * e1 + c[:, None] * e2
        E = np.stack([ep, np.broadcast_to(a, (K, 3))], axis=-1)
        n = self.sign * er
        u = np.stack([np.arctan2(s, c), loc[:, 2]], axis=-1)
        du_dx = np.empty((K, 2, 3))
        du_dx[:, 0, :] = self.radius * ep / dist[:, None]
        du_dx[:, 1, :] = a
        dE = dn = d2u = None
        if derivatives:
            dphi = ep / dist[:, None]                          # d phi / dx
            dE = np.zeros((K, 3, 2, 3))
            dE[:, :, 0, :] = -er[:, :, None] * dphi[:, None, :]  # d e_phi = -e_rho dphi
            dn = self.sign * ep[:, :, None] * dphi[:, None, :]   # d e_rho = e_phi dphi
            d2u = np.zeros((K, 2, 3, 3))                         # d(R e_phi / d)/dx = -R (e_r e_phi + e_phi e_r) / d^2
            d2u[:, 0] = -(self.radius / (dist * dist))[:, None, None] * (
                er[:, :, None] * ep[:, None, :] + ep[:, :, None] * er[:, None, :])
        return Frame(self.sign * (dist - self.radius), n, E, u, du_dx, dE, dn, d2u)

    # Largest distance between the branch of dphi that the predicted increment selects and the
    # predicted increment itself [rad]; farther than this the step did not resolve the rotation.
    BRANCH_TOLERANCE = 0.5 * math.pi

    def resolve(self, u, u_old, predicted=None):
        """Arc-length increment du = (R dphi, dz) (K, 2), coordinates to store (phi unwrapped, so it
        counts revolutions) and the unresolved flag (K,) of a step from u_old to u.

        phi is periodic, so the positions alone give dphi only modulo 2 pi. Without a prediction
        the shortest branch is taken (|dphi| <= pi). With ``predicted`` (K, 2), the arc-length
        increment expected from the velocity (engines pass du_dx v dt), the branch closest to
        predicted[:, 0] / R is taken, so a point may turn many times per step; the step is flagged
        unresolved when that branch still lies more than BRANCH_TOLERANCE from the prediction."""
        d = np.asarray(u, dtype=float) - u_old
        dphi = wrap_angle(d[..., 0])
        unresolved = np.zeros(dphi.shape, dtype=bool)
        if predicted is not None:
            p = np.asarray(predicted, dtype=float)[..., 0] / self.radius
            dphi = dphi + 2.0 * np.pi * np.round((p - dphi) / (2.0 * np.pi))
            unresolved = np.abs(dphi - p) > self.BRANCH_TOLERANCE
        out = np.array(u, dtype=float)
        out[..., 0] = u_old[..., 0] + dphi
        return np.stack([self.radius * dphi, d[..., 1]], axis=-1), out, unresolved

    def increment(self, u, u_old):
        """Arc-length increment (R * wrapped dphi, dz): small across phi = +-pi."""
        return self.resolve(u, u_old)[0]

    def continue_coordinates(self, u, u_old):
        """Unwrapped phi to store (counts revolutions), z as is."""
        return self.resolve(u, u_old)[1]

    def transport_matrix(self, xi):
        """Lambda = E^T [rho_1, rho_2] = diag(R, 1)."""
        return np.diag([self.radius, 1.0])

    def frame_position(self, xi):
        return np.array(xi, dtype=float)

    def transport_vector(self, vec, xi_old, xi_new):
        """Parallel transport of a tangent vector along the cylinder: rotation about the axis by
        the wrapped angle increment (the surface is developable, so this is path independent)."""
        a = self.axes[2]
        t = float(wrap_angle(xi_new[0] - xi_old[0]))
        c, s = math.cos(t), math.sin(t)
        vec = np.asarray(vec, dtype=float)
        return vec * c + np.cross(a, vec) * s + a * (a @ vec) * (1.0 - c)

    def increment_vector(self, xi_old, xi_new):
        """Geodesic (unrolled) displacement of C, expressed at xi_new: R dphi e_phi + dz e_axis."""
        d = self.increment(np.asarray(xi_new, dtype=float), np.asarray(xi_old, dtype=float))
        rho = self.at(xi_new).rho
        return d[0] * rho[0] / self.radius + d[1] * rho[1]
