"""Closed forms of a threaded joint: the torque and tension of a screw thread that slides under
Coulomb friction (ISO 16047, VDI 2230), the ring of a head's bearing face, the thread's axial
stiffness and the joint's tightening slope. numpy only; independent of the contact-law code (force
balances of Coulomb friction, not return maps). The fastening scene is held to them.

Angles in rad; lengths in m; ``d2`` the thread's pitch diameter, ``pitch`` its lead per turn (one
start), ``flank_angle`` the full thread angle beta (metric: pi/3).
"""
from __future__ import annotations

import math

import numpy as np

from exu_aniso.geometry.helicoid import lead_angle, normal_flank_angle


def _check_thread(d2, pitch, flank_angle):
    for name, v in (("d2", d2), ("pitch", pitch)):
        if not (math.isfinite(v) and v > 0.0):
            raise ValueError(f"{name} must be a finite number > 0; got {v!r}")
    if not (math.isfinite(flank_angle) and 0.0 <= flank_angle < math.pi):
        raise ValueError(f"flank_angle must lie in [0, pi) rad; got {flank_angle!r}")


def thread_torque_per_force(d2, pitch, flank_angle, mu_thread):
    """Thread torque per axial force [m] while the thread slides in tightening (ISO 16047 / VDI 2230):
    (d2/2) (tan phi + mu / cos beta_n) / (1 - mu tan phi / cos beta_n). The force balance of a point
    on the flank at the pitch radius under Coulomb friction along the helix; flank_angle is the full
    thread angle beta [rad] (metric: pi/3)."""
    _check_thread(d2, pitch, flank_angle)
    lead = lead_angle(pitch, 0.5 * d2)
    t = math.tan(lead)
    m = mu_thread / math.cos(normal_flank_angle(flank_angle, lead))
    if not m * t < 1.0:
        names = "d2, pitch" if t > 1.0 else "mu_thread"      # a lead angle past 45 deg is the geometry's fault
        raise ValueError(f"{names}: the thread locks under any tightening torque: mu_thread tan(phi) / cos(beta_n) "
                         f"= {m * t:.3g} must be < 1, with the lead angle phi = atan(pitch / (pi d2)) = "
                         f"{math.degrees(lead):.6g} deg; got mu_thread={mu_thread!r}, d2={d2!r} m, pitch={pitch!r} m")
    return 0.5 * d2 * (t + m) / (1.0 - m * t)


def thread_loosening_torque_per_force(d2, pitch, flank_angle, mu_thread):
    """Thread torque per axial force [m] that turns a tightened thread back (breaks it loose), the
    magnitude of the torque against the loosening: (d2/2) (mu / cos beta_n - tan phi) / (1 + mu tan phi /
    cos beta_n), the tightening's force balance with the friction reversed (the axial force now helps
    the turning). Negative for a thread that does not lock: it turns back on its own."""
    _check_thread(d2, pitch, flank_angle)
    lead = lead_angle(pitch, 0.5 * d2)
    t = math.tan(lead)
    m = mu_thread / math.cos(normal_flank_angle(flank_angle, lead))
    return 0.5 * d2 * (m - t) / (1.0 + m * t)


def loosening_torque_per_clamp_force_vdi2230(d2, pitch, mu_thread, mu_head, head_radius):
    """VDI 2230's linearization of the loosening torque per clamp force for metric threads (60 deg):
    -0.16 P + 0.58 d2 mu_G + mu_K r_K."""
    return -0.16 * pitch + 0.58 * d2 * mu_thread + mu_head * head_radius


def torque_per_clamp_force_vdi2230(d2, pitch, mu_thread, mu_head, head_radius):
    """VDI 2230's linearization of T/F for metric threads (60 deg): 0.16 P + 0.58 d2 mu_G + mu_K r_K."""
    return 0.16 * pitch + 0.58 * d2 * mu_thread + mu_head * head_radius


def mu_thread_iso16047(thread_torque_per_force_, d2, pitch, flank_angle):
    """Thread friction that ISO 16047's evaluation backs out of a thread torque per clamp force [m]:
    mu_th = (T_th/F - P/(2 pi)) / (d2 / (2 cos(beta/2))) (for 60 deg the standard's 0.577 d2)."""
    _check_thread(d2, pitch, flank_angle)
    return (thread_torque_per_force_ - pitch / (2.0 * math.pi)) * 2.0 * math.cos(0.5 * flank_angle) / d2


def mu_head_iso16047(head_torque_per_force, head_radius):
    """Head (bearing) friction of ISO 16047's evaluation: mu_b = T_b / (F r_K), r_K the mean bearing radius."""
    return head_torque_per_force / head_radius


def orthotropic_ring_torque_factor(mu_1, mu_2, lay_angle, n_points):
    """Head torque per clamp force per unit radius [-] of a ring of n_points equally loaded points at
    angles 2 pi k / n, each sliding along the circle (direction e_phi), on an orthotropic Coulomb
    surface (mu_1 along the lay at lay_angle [rad], mu_2 across) under the associated law: the friction
    force for slip direction s is N F s / sqrt(s.F s), F = diag(mu_1^2, mu_2^2) in the lay's frame, so
    its work per slip is N sqrt(mu_1^2 cos^2 a + mu_2^2 sin^2 a), a the angle of s from the lay. Returns
    the mean of sqrt(...) over the ring (= mu for mu_1 = mu_2 = mu)."""
    k = np.arange(int(n_points))
    a = 2.0 * math.pi * k / n_points + 0.5 * math.pi - lay_angle
    return float(np.mean(np.sqrt((mu_1 * np.cos(a)) ** 2 + (mu_2 * np.sin(a)) ** 2)))


def thread_axial_stiffness(normal_stiffness, d2, pitch, flank_angle, mu_thread):
    """Axial stiffness [N/m] of a flank contact (penalty ``normal_stiffness`` [N/m], total) while it
    slides along the helix in tightening: an axial offset delta of the bolt from the flank opens the
    normal gap delta n_z, and the force on the bolt, N (n - mu t) with N = eps_N delta n_z, has the
    axial part eps_N n_z (n_z - mu t_z). At the pitch radius r with h = P / (2 pi) and c = tan(beta/2):
    the flank's normal n = (-r c, -h, r) / W (cylindrical e_r, e_phi, e_z), W^2 = r^2 (1 + c^2) + h^2,
    the helix tangent t = (0, r, h) / sqrt(r^2 + h^2)."""
    _check_thread(d2, pitch, flank_angle)
    r, h, c = 0.5 * d2, pitch / (2.0 * math.pi), math.tan(0.5 * flank_angle)
    nz = r / math.sqrt(r * r * (1.0 + c * c) + h * h)
    tz = h / math.hypot(r, h)
    return normal_stiffness * nz * (nz - mu_thread * tz)


def clamp_force_per_angle(joint_stiffness, pitch, compliances=()):
    """Tightening slope dF/dangle [N/rad]: the lead P / (2 pi) over the joint's compliance and the
    contact compliances in series, (P / 2 pi) / (1/k_joint + sum c_i)."""
    return pitch / (2.0 * math.pi) / (1.0 / joint_stiffness + sum(compliances))


# ----------------------------------------------------------------------------------------------
# a free nut on a vertical bolt (the nut scene)

def _flank(d2, pitch, flank_angle):
    """(r, h, W, L) of a flank at the pitch radius: r = d2 / 2, h = P / (2 pi), W = sqrt(r^2 (1 + c^2) +
    h^2) with c = tan(beta / 2) (|rho_1 x rho_2| of the helicoid), L = sqrt(r^2 + h^2) (the helix's
    speed per radian)."""
    _check_thread(d2, pitch, flank_angle)
    r, h, c = 0.5 * d2, pitch / (2.0 * math.pi), math.tan(0.5 * flank_angle)
    return r, h, math.sqrt(r * r * (1.0 + c * c) + h * h), math.hypot(r, h)


def self_locking_friction(d2, pitch, flank_angle):
    """The least friction along the helix [-] that holds a nut on a vertical bolt under its own weight,
    tan(phi) cos(beta_n) (phi the lead angle, beta_n the flank's half angle in the section normal to
    the helix): at rest the flank's ring of normal forces N turns the nut by the torque N r h / W
    about the axis, which friction mu N r L / W ... must hold, mu >= h L / (r W) = tan(phi) cos(beta_n).
    A box on an incline of the lead angle (beta = 0) needs tan(phi); a V thread locks with less."""
    r, h, W, L = _flank(d2, pitch, flank_angle)
    return h * L / (r * W)


def nut_descent(d2, pitch, flank_angle, mu, mass, inertia, gravity):
    """A nut running down a vertical bolt under its weight, sliding on the bolt's flank at the pitch
    radius with Coulomb friction mu along the helix (a uniform ring of contact, a rigid nut of
    ``mass`` [kg] and axial moment of inertia ``inertia`` [kg m^2] on the screw joint z = h psi):
    (axial acceleration [m/s^2] (negative: down), angular acceleration [rad/s^2], the ring's total
    normal force [N]).

    The nut's axial and torque balances with the flank's normal n = (r c, -h, r) / W (cylindrical
    e_r, e_phi, e_z; the radial parts cancel round the ring) and friction mu N along the helix
    t = (0, r, h) / L against the descent: m h psi'' = -m g + N (r / W + mu h / L) and
    J psi'' = N r (mu r / L - h / W). Raises ValueError, naming mu, when mu is at or above
    ``self_locking_friction`` (the nut holds: no descent)."""
    r, h, W, L = _flank(d2, pitch, flank_angle)
    B = r * (mu * r / L - h / W)
    if not B < 0.0:
        raise ValueError(f"mu: the nut holds, mu = {mu!r} >= the self-locking friction "
                         f"{self_locking_friction(d2, pitch, flank_angle):.6g} (no descent)")
    A = r / W + mu * h / L
    psi_dd = -mass * gravity / (mass * h - inertia * A / B)
    return h * psi_dd, psi_dd, inertia * psi_dd / B


# ----------------------------------------------------------------------------------------------
# a bearing ring that slides sideways (friction neutralised by transverse slip)

def ring_torque_factor(spin_ratio):
    """The friction torque of a ring of radius r pressed by N, sliding sideways at speed v while it
    turns at omega, over mu N r [-]: G(s) = (1 / 2 pi) int (s - sin phi) / sqrt(1 + s^2 - 2 s sin phi)
    dphi, s = omega r / v the spin ratio (Coulomb friction against every point's slip velocity v e_x +
    omega r e_phi). G(0) = 0, G ~ s / 2 for s << 1 (a sideways slip takes the friction's grip on the
    turning away), G -> 1 as s grows (no sideways slip: the whole ring's mu N r). Integrated with
    scipy's quad to 1e-13."""
    from scipy.integrate import quad
    s = float(spin_ratio)
    if not (math.isfinite(s) and s >= 0.0):
        raise ValueError(f"spin_ratio must be a finite number >= 0; got {spin_ratio!r}")

    def integrand(phi):
        w = math.sqrt(max(1.0 + s * s - 2.0 * s * math.sin(phi), 0.0))
        return (s - math.sin(phi)) / w if w > 0.0 else 0.0
    value, _ = quad(integrand, 0.0, 2.0 * math.pi, points=[0.5 * math.pi], epsabs=1e-13, epsrel=1e-13, limit=200)
    return value / (2.0 * math.pi)


def ring_drag_factor(spin_ratio):
    """The friction force against the sideways slide of the ring of ``ring_torque_factor``, over mu N [-]:
    D(s) = (1 / 2 pi) int (1 - s sin phi) / sqrt(1 + s^2 - 2 s sin phi) dphi; D(0) = 1 (no turning: the
    ring's whole friction resists the slide), D -> 0 as the turning takes over. (Across the slide the
    ring's friction cancels.)"""
    from scipy.integrate import quad
    s = float(spin_ratio)
    if not (math.isfinite(s) and s >= 0.0):
        raise ValueError(f"spin_ratio must be a finite number >= 0; got {spin_ratio!r}")

    def integrand(phi):
        w = math.sqrt(max(1.0 + s * s - 2.0 * s * math.sin(phi), 0.0))
        return (1.0 - s * math.sin(phi)) / w if w > 0.0 else 0.0
    value, _ = quad(integrand, 0.0, 2.0 * math.pi, points=[0.5 * math.pi], epsabs=1e-13, epsrel=1e-13, limit=200)
    return value / (2.0 * math.pi)


def ring_spin_ratio(torque_ratio):
    """The spin ratio s = omega r / v at which a sideways-sliding ring's friction torque equals an
    applied torque, ``torque_ratio`` = T / (mu N r) in [0, 1): G(s) = T / (mu N r) (``ring_torque_factor``,
    increasing from 0 to 1). Raises ValueError, naming the torque, at or above 1 (the torque outgrows
    the whole ring's friction: the ring spins up without bound)."""
    from scipy.optimize import brentq
    g = float(torque_ratio)
    if not (math.isfinite(g) and 0.0 <= g < 1.0):
        raise ValueError(f"torque: T / (mu N r) = {torque_ratio!r} must lie in [0, 1) for a steady spin (at 1 the "
                         "torque outgrows the ring's whole friction)")
    if g == 0.0:
        return 0.0
    hi = 1.0
    while ring_torque_factor(hi) < g:
        hi *= 2.0
    return brentq(lambda s: ring_torque_factor(s) - g, 0.0, hi, xtol=1e-14, rtol=1e-14)


# ----------------------------------------------------------------------------------------------
# a preloaded joint whose nut slides sideways (the loosening scene's joint)

def flank_load_per_axial_force(d2, pitch, flank_angle):
    """The flank's total normal force per axial force carried by the thread [-], W / r = 1 / n_z: the
    flank's normal n at the pitch radius has the axial part n_z = r / W (``_flank``), so a uniform ring
    of normal forces N carries N r / W along the axis (the radial parts cancel round the ring, the
    friction's axial part is left out, as the rings below leave it)."""
    r, _, W, _ = _flank(d2, pitch, flank_angle)
    return W / r


def _joint_rings(d2, pitch, flank_angle, mu_thread, mu_bearing, bearing_radius):
    for name, v in (("mu_thread", mu_thread), ("mu_bearing", mu_bearing), ("bearing_radius", bearing_radius)):
        if not (math.isfinite(v) and v > 0.0):
            raise ValueError(f"{name} must be a finite number > 0; got {v!r}")
    r2 = 0.5 * d2
    return pitch / (2.0 * math.pi), r2, mu_thread * flank_load_per_axial_force(d2, pitch, flank_angle)


def joint_rotation_per_path(d2, pitch, flank_angle, mu_thread, mu_bearing, bearing_radius):
    """The angle a preloaded nut turns loose per unit of its sideways slip path [rad/m] while its
    thread ring (radius d2 / 2, friction mu_thread on a flank loaded by F W / r) and its bearing ring
    (``bearing_radius``, mu_bearing, loaded by F) both slide, uniform and closed: every point slips at
    v e_x + omega r e_phi, and the pitch's torque F P / (2 pi) meets the rings' friction torques,
    F h = mu_t (W / r) F r2 G(c r2) + mu_K F r_K G(c r_K) with c = omega / v (``ring_torque_factor``;
    F cancels). c = 0 at zero lead; it grows without bound as the lead's torque nears the rings' whole
    friction, and ValueError (naming the frictions) says so at or above it (the nut is not
    self-locking and runs off without any slip)."""
    from scipy.optimize import brentq
    h, r2, mu_t = _joint_rings(d2, pitch, flank_angle, mu_thread, mu_bearing, bearing_radius)
    limit = mu_t * r2 + mu_bearing * bearing_radius
    if not h < limit:
        raise ValueError(f"mu_thread, mu_bearing: the lead's torque per force P / (2 pi) = {h:.6g} m reaches the "
                         f"rings' whole friction {limit:.6g} m: the joint is not self-locking")

    def excess(c):
        return mu_t * r2 * ring_torque_factor(c * r2) + mu_bearing * bearing_radius * ring_torque_factor(
            c * bearing_radius) - h
    hi = 1.0 / bearing_radius
    while excess(hi) < 0.0:
        hi *= 2.0
    return brentq(excess, 0.0, hi, xtol=1e-12, rtol=1e-13)


def joint_slide_force_per_preload(d2, pitch, flank_angle, mu_thread, mu_bearing, bearing_radius):
    """The sideways force that keeps the nut of ``joint_rotation_per_path`` sliding, over the preload
    [-]: the rings' friction against the slide at the common c, mu_t (W / r) D(c r2) + mu_K D(c r_K)
    (``ring_drag_factor``): the plateau of the transverse force's hysteresis loop, and the force at
    which the nut, turned by the lead's torque, starts to slide as a whole."""
    h, r2, mu_t = _joint_rings(d2, pitch, flank_angle, mu_thread, mu_bearing, bearing_radius)
    c = joint_rotation_per_path(d2, pitch, flank_angle, mu_thread, mu_bearing, bearing_radius)
    return mu_t * ring_drag_factor(c * r2) + mu_bearing * ring_drag_factor(c * bearing_radius)


def guided_beam_stiffness(youngs_modulus, diameter, length):
    """The lateral stiffness [N/m] of a round beam clamped at one end and guided at the other (the end
    shifts without turning): 12 E I / L^3 with I = pi d^4 / 64, the bolt's shank between a head and a
    nut that hold it square."""
    for name, v in (("youngs_modulus", youngs_modulus), ("diameter", diameter), ("length", length)):
        if not (math.isfinite(v) and v > 0.0):
            raise ValueError(f"{name} must be a finite number > 0; got {v!r}")
    return 12.0 * youngs_modulus * math.pi * diameter ** 4 / 64.0 / length ** 3


def guided_shear_beam_stiffness(section, length):
    """The lateral stiffness [N/m] of the guided beam of ``guided_beam_stiffness`` when its shear
    counts too (a Timoshenko beam): 1 / (L^3 / (12 E I) + L / (kappa G A)), the bending's and the
    shear's compliances in series (the clamped-guided beam carries a constant shear force Q and a
    moment that runs from Q L / 2 to -Q L / 2). section: an ``exu_aniso.fe.beam.RoundSection``
    (E I [N m^2], kappa G A [N])."""
    if not (math.isfinite(length) and length > 0.0):
        raise ValueError(f"length must be a finite number > 0; got {length!r}")
    return 1.0 / (length ** 3 / (12.0 * section.bending_stiffness) + length / section.shear_stiffness)
