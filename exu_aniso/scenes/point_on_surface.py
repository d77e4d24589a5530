"""Closed forms of a mass point on a curved surface under gravity and Coulomb friction: leaving the
top of a rough sphere, coasting in a spherical cavity, sliding down an inclined line, and the
first-order start-up error of a sampled run against them. numpy/scipy only; independent of the
contact-law code (the equations of motion along the path, not return maps). The particle scene
(``exu_aniso.scenes.particle``) is held to them.
"""
from __future__ import annotations

import math

import numpy as np


class OutsideDomain(ValueError):
    """An oracle's own assumptions fail for these inputs (e.g. friction stops the point before the
    event the oracle predicts): the message names the parameter and the rule. Bad inputs (not
    finite, out of range) raise plain ValueError; a scene reports an OutsideDomain as "no theory"."""


def departure_angle(mu, radius, gravity, speed):
    """Angle [rad] from the top at which a mass point sliding over a rough sphere leaves it.

    Textbook mechanics in the polar angle theta from the top and the speed v [m/s] along the path:
    theta' = v / R, v' = g sin(theta) - s mu N / m with N / m = g cos(theta) - v^2 / R and s the
    sign of v (Coulomb friction opposes the sliding); the point leaves where N reaches 0.
    Integrated with scipy's solve_ivp (rtol 1e-11) to the event N = 0, segment by segment between
    the zeros of v.

    Domain (else OutsideDomain, a ValueError naming the parameter and the rule): where v reaches 0
    on the sphere (N > 0 there) the point sticks if static friction can hold it, |g sin(theta)| <=
    mu g cos(theta), i.e. tan|theta| <= mu: it never leaves, so there is no departure angle. That
    is the case for ``speed`` = 0 (it rests on the top) and for every stop on the way down: moving
    downhill, v can only fall to 0 where v' = g (sin - mu cos) <= 0, which is the sticking rule
    itself (equal static and kinetic mu), so friction always holds a point it has stopped. (Were
    the rule violated at a zero of v, the point would slide on in the direction of the tangential
    load with the friction's sign turned; the segment loop does that.) A point that creeps to a
    stop only as t -> oo (tan(theta) -> mu exactly) has not left within the horizon
    1000 sqrt(R / g): OutsideDomain too. The OutsideDomain of a stop carries ``stop_angle`` [rad].
    ValueError when an input is out of range, or when the point does not press on the top
    (v0^2 >= g R: it leaves at once)."""
    from scipy.integrate import solve_ivp
    R, g, v0, mu = float(radius), float(gravity), float(speed), float(mu)
    if not (R > 0 and g > 0 and mu >= 0 and v0 >= 0):
        raise ValueError(f"departure_angle: needs radius > 0, gravity > 0, mu >= 0, speed >= 0; got "
                         f"{radius!r}, {gravity!r}, {mu!r}, {speed!r}")
    if v0 * v0 >= g * R:
        raise ValueError(f"departure_angle: speed^2 = {v0 * v0:.6g} >= g R = {g * R:.6g}: the point leaves at "
                         "the top")

    def leave(t, y, s):
        return g * math.cos(y[0]) - y[1] ** 2 / R
    leave.terminal = True
    leave.direction = -1

    def stop(t, y, s):
        return y[1]
    stop.terminal = True

    th, v, horizon = 0.0, v0, 1000.0 * math.sqrt(R / g)
    for _ in range(8):                    # segments between zeros of v (one, unless the point stops)
        if v == 0.0:
            load, hold = g * math.sin(th), mu * g * math.cos(th)
            if abs(load) <= hold:
                rule = (f"(sticking rule |g sin(theta)| = {abs(load):.6g} <= mu g cos(theta) = {hold:.6g} m/s^2): it "
                        "never leaves the sphere")
                if th == 0.0:
                    e = OutsideDomain(f"departure_angle: speed = 0: the point rests on the top, where friction "
                                      f"holds it {rule}")
                else:
                    e = OutsideDomain(f"departure_angle: mu = {mu:g}: friction stops the point (speed = {v0:g} m/s "
                                      f"at the top) at theta = {math.degrees(th):.6g} deg and holds it there {rule}; "
                                      "a departure angle needs a smaller mu or a larger speed")
                e.stop_angle = th
                raise e
            s = math.copysign(1.0, load)
        else:
            s = math.copysign(1.0, v)
        stop.direction = -s

        def rhs(t, y, s):
            return [y[1] / R, g * math.sin(y[0]) - s * mu * max(g * math.cos(y[0]) - y[1] ** 2 / R, 0.0)]
        sol = solve_ivp(rhs, (0.0, horizon), [th, v], events=(leave, stop), args=(s,), rtol=1e-11, atol=1e-13)
        if len(sol.t_events[0]):
            return float(sol.y_events[0][0][0])
        if not len(sol.t_events[1]):
            break
        th, v = float(sol.y_events[1][0][0]), 0.0
    raise OutsideDomain(f"departure_angle: the point does not leave the sphere within {horizon:.3g} s (mu = {mu:g}, "
                        f"speed = {v0:g} m/s): it creeps to a stop at tan(theta) = mu")


def coasting_speed(speed, mu, angle):
    """Speed [m/s] of a mass point coasting along a great circle inside a spherical cavity without
    gravity after turning by ``angle`` [rad] about the centre: N = m v^2 / R, so
    m dv/dt = -mu m v^2 / R, i.e. dv / dpsi = -mu v and v = v0 exp(-mu psi) (independent of R).

    Domain: no gravity, the point on the inside (N = m v^2 / R > 0 keeps it in contact as long as it
    moves; v never reaches 0), Coulomb friction alone with one ``mu`` along the path (a tangential
    dashpot adds -d_T v: dv/dpsi = -mu v - d_T R / m, not this law)."""
    return float(speed) * np.exp(-float(mu) * np.asarray(angle, dtype=float))


def incline_acceleration(mu, slope, gravity):
    """Acceleration [m/s^2] down the slope of a mass point sliding along the top line of a cylinder
    whose axis is inclined by ``slope`` [rad]: N = m g cos(slope), a = g (sin(slope) - mu cos(slope))
    while it slides downhill (uphill the friction adds: -g (sin + mu cos) in the uphill sense).

    Domain: the point slides toward +x (x down the slope for slope > 0) and presses on the cylinder
    (gravity > 0), Coulomb friction alone with one ``mu`` along the axis (a tangential dashpot adds
    -d_T v / m). A point at rest does not slide at all when tan|slope| <= mu."""
    return float(gravity) * (math.sin(slope) - float(mu) * math.cos(slope))


def startup_impulse_error(case, mu, radius, gravity, speed, dt):
    """The first-order start-up error of the particle oracles (exu_aniso.scenes.particle) that both
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
