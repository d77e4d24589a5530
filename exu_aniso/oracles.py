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


# ----------------------------------------------------------------------------------------------
# a mass point on curved surfaces (the particle scene, exu_aniso.scene_particle)

def departure_angle(mu, radius, gravity, speed):
    """Angle [rad] from the top at which a mass point sliding over a rough sphere leaves it.

    Textbook mechanics in the polar angle theta from the top and the speed v: theta' = v / R,
    v' = g sin(theta) - mu N / m with N / m = g cos(theta) - v^2 / R; the point leaves where N
    reaches 0. Integrated with scipy's solve_ivp (rtol 1e-11) to the event N = 0. Raises
    ValueError when the point does not even press on the top (v0^2 >= g R) or never leaves
    within 100 R / sqrt(g R) (it stops on the top half: mu large)."""
    from scipy.integrate import solve_ivp
    R, g, v0, mu = float(radius), float(gravity), float(speed), float(mu)
    if not (R > 0 and g > 0 and mu >= 0 and v0 >= 0):
        raise ValueError(f"departure_angle: needs radius > 0, gravity > 0, mu >= 0, speed >= 0; got "
                         f"{radius!r}, {gravity!r}, {mu!r}, {speed!r}")
    if v0 * v0 >= g * R:
        raise ValueError(f"departure_angle: speed^2 = {v0 * v0:.6g} >= g R = {g * R:.6g}: the point leaves at "
                         "the top")

    def rhs(t, y):
        th, v = y
        return [v / R, g * math.sin(th) - mu * max(g * math.cos(th) - v * v / R, 0.0)]

    def leave(t, y):
        return g * math.cos(y[0]) - y[1] ** 2 / R
    leave.terminal = True
    leave.direction = -1
    sol = solve_ivp(rhs, (0.0, 100.0 * math.sqrt(R / g)), [0.0, v0], events=leave, rtol=1e-11, atol=1e-13)
    if not len(sol.t_events[0]):
        raise ValueError(f"departure_angle: the point does not leave the sphere (mu = {mu}, speed = {v0})")
    return float(sol.y_events[0][0][0])


def coasting_speed(speed, mu, angle):
    """Speed [m/s] of a mass point coasting along a great circle inside a spherical cavity without
    gravity after turning by ``angle`` [rad] about the centre: N = m v^2 / R, so
    m dv/dt = -mu m v^2 / R, i.e. dv / dpsi = -mu v and v = v0 exp(-mu psi) (independent of R)."""
    return float(speed) * np.exp(-float(mu) * np.asarray(angle, dtype=float))


def incline_acceleration(mu, slope, gravity):
    """Acceleration [m/s^2] down the slope of a mass point sliding along the top line of a cylinder
    whose axis is inclined by ``slope`` [rad]: N = m g cos(slope), a = g (sin(slope) - mu cos(slope))
    while it slides downhill (uphill the friction adds: -g (sin + mu cos) in the uphill sense)."""
    return float(gravity) * (math.sin(slope) - float(mu) * math.cos(slope))


def startup_impulse_error(case, mu, radius, gravity, speed, dt):
    """The first-order start-up error of the particle oracles (exu_aniso.scene_particle) that both
    engines share: a point that starts sliding at t = 0 starts with the history of
    CreateAnisotropicContact(initializeHistory=True), sticking with T = 0, so its initial acceleration
    carries no friction, and the trapezoidal rule, which averages a_0 into the first step, misses half
    a step of the friction impulse, mu |N0| dt / 2 (from the second step on friction is full). The
    point then moves as if launched faster by dv = mu |N0| dt / (2 m):

    * departure: d theta_d = (d theta_d / d v0) dv [rad], the derivative of ``departure_angle`` by
      central differences, |N0| / m = g - v0^2 / R;
    * cavity: the speed ratio v / v0 is too high by dv / v0 = mu v0 dt / (2 R).
    Returns that error (the simulation minus the textbook value) to first order in dt."""
    if case == "departure":
        dv = mu * (gravity - speed * speed / radius) * dt / 2.0
        h = 1e-4 * speed
        slope = (departure_angle(mu, radius, gravity, speed + h)
                 - departure_angle(mu, radius, gravity, speed - h)) / (2 * h)
        return slope * dv
    if case == "cavity":
        return mu * speed * dt / (2.0 * radius)
    raise ValueError(f"startup_impulse_error: case must be 'departure' or 'cavity'; got {case!r}")
