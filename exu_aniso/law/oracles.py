"""Analytic answers the scenes are checked against (numpy/scipy only; independent of the
contact-law code: force balances of Coulomb friction, not return maps).

The screw's steady sliding state is in ``exu_aniso.scenes.screw.steady_sliding``.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq

from exu_aniso.geometry.helicoid import lead_angle, normal_flank_angle


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
# a mass point on curved surfaces (the particle scene, exu_aniso.scenes.particle)

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


def conveying_velocity(amplitude, frequency, throw_angle, mu, gravity=9.81, periods=2000, samples=2000,
                       tolerance=1e-7, period_means=False):
    """Mean transport velocity [m/s] of a part on a linear vibratory conveyor, by the one-dimensional
    stick-slip analysis of Coulomb friction (the classic model of vibratory conveying).

    The track moves harmonically along the throw direction, ``amplitude`` A [m] at ``frequency`` f
    [Hz] and ``throw_angle`` beta [rad] from the track plane: u(t) = A sin(w t) (cos beta, sin beta)
    (tangential, normal), w = 2 pi f. The part stays on the track (throw number
    Gamma = A w^2 sin(beta) / g < 1), so its normal force per mass is n(t) = g - A w^2 sin(beta)
    sin(w t) > 0; along the track (friction coefficient ``mu`` in that direction, the track's
    direction of a principal axis of an orthotropic net, so no force across it) it
    * sticks, v = A w cos(beta) cos(w t), while the track's tangential acceleration can be carried:
      A w^2 cos(beta) |sin(w t)| <= mu n(t);
    * slides otherwise: dv/dt = -mu n(t) sign(v - w_t(t)), in closed form between events,
      v(t) = v0 - s mu (g (t - t0) + A w sin(beta) (cos(w t) - cos(w t0))), s = sign(v - w_t).
    Events (the relative velocity's zero; the stick limit) are located by scanning ``samples`` points
    per period and refining with brentq. The part starts at rest at t = 0 (the track at u = 0,
    moving); the result is the mean velocity over the first period after which two successive
    periods' means differ by less than ``tolerance`` times the track's velocity amplitude (at most
    ``periods`` periods; ValueError if not settled). With ``period_means`` it returns (that velocity,
    the list of every period's mean velocity from the start): the transient from rest, which a
    measurement over a finite window sees.

    Assumptions (the domain a simulation must lie in to be compared with it): a point mass (no
    rocking: the friction force's moment about the centre of mass must not lift an edge), rigid
    contact (stick means moving with the track exactly; no normal or tangential compliance or
    dashpot), one dimension (friction along the track only), the track's motion prescribed
    (unaffected by the part), Gamma < 1 (no flight phase), the periodic state reached."""
    for name, v in (("amplitude", amplitude), ("frequency", frequency), ("mu", mu), ("gravity", gravity)):
        if not (isinstance(v, (int, float, np.floating)) and math.isfinite(v) and v > 0):
            raise ValueError(f"conveying_velocity: {name} must be a finite number > 0; got {v!r}")
    if not (math.isfinite(throw_angle) and 0.0 <= throw_angle < 0.5 * math.pi):
        raise ValueError(f"conveying_velocity: throw_angle must lie in [0, pi/2) rad; got {throw_angle!r}")
    w = 2.0 * math.pi * frequency
    a_t, a_n = amplitude * w * w * math.cos(throw_angle), amplitude * w * w * math.sin(throw_angle)
    if a_n >= gravity:
        raise ValueError(f"conveying_velocity: the part leaves the track (throw number A w^2 sin(beta) / g = "
                         f"{a_n / gravity:.4g} >= 1); the analysis needs it on the track")
    V = amplitude * w * math.cos(throw_angle)          # track's tangential velocity amplitude
    T = 1.0 / frequency
    dt = T / samples

    def track_v(t):
        return V * math.cos(w * t)

    def carried(t):                                     # > 0 while sticking is possible
        return mu * (gravity - a_n * math.sin(w * t)) - a_t * abs(math.sin(w * t))

    def slide_v(t, t0, v0, s):
        return v0 - s * mu * (gravity * (t - t0) + a_n / w * (math.cos(w * t) - math.cos(w * t0)))

    def first_root(f, t0, t_max):
        """First t in (t0 + 1e-9 T, t_max] where f changes sign (an event right at t0 is the one that
        started the phase: skipped, so every phase advances the time)."""
        ta = min(t0 + 1e-9 * T, t_max)
        fa = f(ta)
        while ta < t_max:
            tb = min(ta + dt, t_max)
            fb = f(tb)
            if fa == 0.0:
                return ta
            if fa * fb <= 0.0:
                return brentq(f, ta, tb, xtol=1e-15 * T, rtol=1e-15)
            ta, fa = tb, fb
        return None

    # piecewise motion: phases (kind, t0, v0, s); the mean velocity per period integrates v exactly
    t, v = 0.0, 0.0
    mode = "slip"
    s = 1.0 if v - track_v(0.0) > 0 else -1.0
    means, horizon = [], periods * T
    x_period, period_end = 0.0, T

    def slide_x(t1, t0, v0, s):   # integral of slide_v from t0 to t1
        return (v0 * (t1 - t0) - s * mu * (0.5 * gravity * (t1 - t0) ** 2
                + a_n / w * (math.sin(w * t1) / w - math.sin(w * t0) / w - math.cos(w * t0) * (t1 - t0))))

    def stick_x(t1, t0):
        return amplitude * math.cos(throw_angle) * (math.sin(w * t1) - math.sin(w * t0))

    phases = 0
    while t < horizon:
        phases += 1
        if phases > 100 * periods:
            raise RuntimeError(f"conveying_velocity: more than {100 * periods} stick/slip phases in {periods} periods "
                               f"(t = {t:.6g} s): the event search does not advance")
        if mode == "slip":
            t0, v0 = t, v
            t_end = first_root(lambda tt: slide_v(tt, t0, v0, s) - track_v(tt), t0, period_end)
        else:
            t0 = t
            t_end = first_root(carried, t0, period_end)
        t_next = period_end if t_end is None else t_end
        x_period += slide_x(t_next, t0, v0, s) if mode == "slip" else stick_x(t_next, t0)
        v = slide_v(t_next, t0, v0, s) if mode == "slip" else track_v(t_next)
        t = t_next
        if t_end is not None:                            # an event: decide the next phase
            eps = 1e-9 * T
            if mode == "slip" and carried(t + eps) > 0.0:
                mode, v = "stick", track_v(t)
            else:                                        # (re)start sliding: the direction of the relative motion
                mode = "slip"
                acc_track = -a_t * math.sin(w * t)
                s = -1.0 if acc_track > 0.0 else 1.0     # the track runs away from the part: v - w_t turns negative
        if t >= period_end - 1e-12 * T:
            means.append(x_period / T)
            x_period, period_end = 0.0, period_end + T
            if len(means) >= 3 and abs(means[-1] - means[-2]) < tolerance * V:
                return (means[-1], list(means)) if period_means else means[-1]
    raise ValueError(f"conveying_velocity: no periodic state within {periods} periods (last means "
                     f"{means[-3:]}); raise periods")


# ----------------------------------------------------------------------------------------------
# fastening: torque-tension of a threaded joint (ISO 16047, VDI 2230)

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
