"""Calibrating the screw's adhesion B and friction F to a wanted advance per revolution and sliding torque.

Paper 001 (section 3) calibrates the adhesion and friction tensors of a screw "in order to prescribe
the resulting kinematics exactly by keeping the necessary sliding force at a certain level". This
module does that for the screw scene (``exu_aniso.scenes.ScrewParams``, rotation drive).

Steady sliding in closed form (``steady_sliding``)
--------------------------------------------------
In the reduced model the screw stays on the hole axis, so every point carries the same normal force;
the total is ``N = eps_n * interference``. In steady sliding (rotation speed and axial speed
constant, inertia forces zero) the total tangential traction the hole exerts on the screw is
``T = -(tau e_phi + axial_load e_z)``: ``tau`` balances the drive torque (torque = R * tau with
the hole radius R: the traction acts where the slip is measured, see kernel.py step 5) and the axial
part balances the axial load. Write
``S = -T = tau e_phi + axial_load e_z`` in the helix frame (e1 = cos a e_phi + sin a e_z,
e2 = -sin a e_phi + cos a e_z). Sliding puts it on the friction ellipse

    (S.e1)^2 / mu_1^2 + (S.e2)^2 / mu_2^2 = N^2          ->  tau (quadratic, positive root),

which gives the sliding torque. It is also the threshold of sustained sliding under the torque drive
(below it the screw sticks). The direction of the slip rate depends on the return map:

* ``radial``: slip along ``C^-1 S`` (components S_i / eps_i): the ADHESION ratio r = eps_1/eps_2 sets
  the kinematics and the friction coefficients do not;
* ``exact``: slip along ``F S`` (components S_i / mu_i^2): the kinematics follow from mu_1/mu_2
  only, B does not matter in steady sliding;
* ``seed``: no closed form. Its steady state follows the dominant eigenvector of C F and depends
  on the step size (see studies/screw_driving.py), so it is not calibrated here.

The advance per revolution is ``2 pi R v_z / v_phi`` (R the hole radius, where the slip is measured).
Without axial load this is ``adv / pitch = (1 - r) / (1 + r tan^2 a)`` with r = eps_1/eps_2 (radial)
or r = (mu_1/mu_2)^2 (exact): the thread limit adv/pitch -> 1 as r -> 0, and adv = 0 for r = 1.

Calibration (``calibrate_screw``)
---------------------------------
Which parameter controls which target decides the parametrisation (logarithmic, so the unknowns
are unbounded and scale-free):

* radial: x = (ln(eps_1/eps_2), ln s). eps_1 stays at the base value (it sets the elastic travel
  before sliding), eps_2 = eps_1 / r; mu_1 and mu_2 are the base values times s. The ratio alone
  sets the advance, and s then sets the torque: the problem is triangular and well posed.
* exact: x = (ln(mu_1/mu_2), ln mu_2): the ratio sets the advance, the level sets the torque.

The starting point solves the closed form. ``scipy.optimize.least_squares`` then solves the residual
of the simulation (relative errors of advance and torque, from the chosen ``engine``). The Jacobian
comes from the closed form by default, because the simulation follows the closed form to about 1e-4.
It stops at the first simulation whose relative errors are both below ``tol``. A simulation on the
OTHER engine then verifies the parameters it found.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .scenes import ScrewParams, pitch
from .validation import check_positive, check_real

ENGINES = ("reference", "exudyn")
CALIBRATED_MAPS = ("radial", "exact")
UNKNOWNS = {"radial": ("eps_ratio", "mu_scale"), "exact": ("mu_ratio", "mu_2")}
# generalized-alpha (rho_inf 0.8) damps the unresolved torsional oscillation of screw and drive spring
# (omega ~ 2.8e3 rad/s for the defaults); with the trapezoidal rule it persists and its phase at the end
# of the run moves the fitted advance by up to ~1 % at dt = 1e-3 (5e-5 with generalized-alpha)
DEFAULT_BASE = ScrewParams(solver="generalized_alpha", t_end=0.5)


@dataclass(frozen=True)
class SteadySliding:
    """Closed-form steady sliding state of the screw scene (SI units).

    advance_per_rev [m], advance_ratio = advance_per_rev / pitch [-], torque = drive torque while
    sliding (= sticking threshold of the torque drive) [N m], circumferential_traction = tau [N]
    (total), normal_force = N [N] (total), slip_direction = unit slip-rate direction (e_phi, e_z)."""

    advance_per_rev: float
    advance_ratio: float
    torque: float
    circumferential_traction: float
    normal_force: float
    slip_direction: tuple


def _helix_components(p):
    a = math.radians(p.helix_angle)
    return math.cos(a), math.sin(a)


def _friction_coefficients(p):
    return (p.mu_1, p.mu_1) if p.friction == "isotropic" else (p.mu_1, p.mu_2)


def _adhesion_stiffnesses(p):
    return (p.eps_1, p.eps_1) if p.adhesion == "isotropic" else (p.eps_1, p.eps_2)


def steady_sliding(p: ScrewParams) -> SteadySliding:
    """Steady sliding of the screw scene in closed form (see the module docstring).

    Valid for return_map 'radial' and 'exact', the reduced model (the full model agrees while the
    screw stays centred) and positive rotation. Raises ValueError for the seed map, or when the axial
    load exceeds the axial friction capacity (then no steady sliding rotation exists)."""
    if not isinstance(p, ScrewParams):
        raise TypeError(f"p must be ScrewParams; got {type(p).__name__}")
    if p.return_map not in CALIBRATED_MAPS:
        raise ValueError(f"return_map must be one of {CALIBRATED_MAPS} for the closed form (the seed map's steady "
                         f"state depends on the step size); got {p.return_map!r}")
    c, s = _helix_components(p)
    mu1, mu2 = _friction_coefficients(p)
    eps1, eps2 = _adhesion_stiffnesses(p)
    N = p.eps_n * p.interference
    Fa = p.axial_load
    f1, f2 = 1.0 / mu1 ** 2, 1.0 / mu2 ** 2
    # S = tau e_phi + Fa e_z; S1 = tau c + Fa s, S2 = -tau s + Fa c; f1 S1^2 + f2 S2^2 = N^2
    A = f1 * c * c + f2 * s * s
    B = Fa * c * s * (f1 - f2)
    C = Fa * Fa * (f1 * s * s + f2 * c * c) - N * N
    disc = B * B - A * C
    if N <= 0.0 or disc < 0.0 or (-B + math.sqrt(disc)) <= 0.0:
        raise ValueError(f"axial_load: |axial_load| = {abs(Fa)!r} N must stay below the axial friction capacity "
                         f"(normal force eps_n * interference = {N!r} N) for a steady sliding rotation")
    tau = (-B + math.sqrt(disc)) / A
    S1, S2 = tau * c + Fa * s, -tau * s + Fa * c
    w1, w2 = (S1 / eps1, S2 / eps2) if p.return_map == "radial" else (S1 * f1, S2 * f2)
    v_phi, v_z = c * w1 - s * w2, s * w1 + c * w2
    if not v_phi > 0.0:
        raise ValueError("the closed form needs a slip with positive rotation; this parameter set slides backwards")
    adv = 2.0 * math.pi * p.radius * v_z / v_phi
    pt = pitch(p)
    norm = math.hypot(v_phi, v_z)
    return SteadySliding(advance_per_rev=adv, advance_ratio=adv / pt if pt != 0.0 else float("nan"),
                         torque=p.radius * tau, circumferential_traction=tau, normal_force=N,
                         slip_direction=(v_phi / norm, v_z / norm))


def sliding_onset_angle(p: ScrewParams) -> float:
    """Driver rotation [rad] until the screw starts to slide under the rotation drive (estimate):
    elastic circumferential travel of the contact (axial direction free, stiffness
    1 / (cos^2 a / eps_1 + sin^2 a / eps_2)) plus the wind-up of the drive spring."""
    c, s = _helix_components(p)
    eps1, eps2 = _adhesion_stiffnesses(p)
    st = steady_sliding(p)
    k_phi = 1.0 / (c * c / eps1 + s * s / eps2)
    return st.circumferential_traction / k_phi / p.radius + st.torque / p.drive_stiffness


# ----------------------------------------------------------------------------------------------
# parametrisation

def _apply(base, x):
    """Parameters for the log unknowns x (see UNKNOWNS)."""
    if base.return_map == "radial":
        r, scale = math.exp(x[0]), math.exp(x[1])
        return base.with_overrides(eps_2=base.eps_1 / r, mu_1=base.mu_1 * scale, mu_2=base.mu_2 * scale)
    q, mu2 = math.exp(x[0]), math.exp(x[1])
    return base.with_overrides(mu_1=q * mu2, mu_2=mu2)


def _unknown_values(base, p):
    if base.return_map == "radial":
        return {"eps_ratio": p.eps_1 / p.eps_2, "mu_scale": p.mu_1 / base.mu_1}
    return {"mu_ratio": p.mu_1 / p.mu_2, "mu_2": p.mu_2}


def _x_of(base, p):
    return np.log(list(_unknown_values(base, p).values()))


def closed_form_guess(target_advance_per_rev, target_torque, base):
    """Log unknowns x solving the closed form exactly (``steady_sliding``) for the two targets."""
    from scipy.optimize import least_squares

    def res(x):
        st = steady_sliding(_apply(base, x))
        return np.array([st.advance_per_rev / target_advance_per_rev - 1.0, st.torque / target_torque - 1.0])

    a = target_advance_per_rev / pitch(base)
    t2 = math.tan(math.radians(base.helix_angle)) ** 2
    r0 = (1.0 - a) / (1.0 + a * t2)                       # axial_load = 0 inversion of the advance
    x0 = np.array([math.log(r0), 0.0]) if base.return_map == "radial" else np.array([0.5 * math.log(r0),
                                                                                       math.log(base.mu_2)])
    st0 = steady_sliding(_apply(base, x0))
    x0[1] += math.log(target_torque / st0.torque)         # torque is proportional to the friction level
    sol = least_squares(res, x0, xtol=1e-14, ftol=1e-14, gtol=1e-14, max_nfev=200)
    return sol.x


# ----------------------------------------------------------------------------------------------
# simulation

def _simulate(p, engine):
    if engine == "reference":
        from .reference import simulate_screw
        r = simulate_screw(p)
    else:
        from .models.screw import RunScrew
        r = RunScrew(p, contactOutputs=False)
    return r.summary


def run_for_targets(p, engine):
    """(advance_per_rev [m], torque_mean [N m]) of one simulation of p with engine."""
    s = _simulate(p, engine)
    if s["advance_per_rev"] is None:
        raise ValueError(f"advance_per_rev undefined for this parameter set ({engine}): "
                         f"{s['undefined']['advance_per_rev']}")
    return float(s["advance_per_rev"]), float(s["torque_mean"])


@dataclass
class CalibrationResult:
    """Outcome of ``calibrate_screw``.

    params: calibrated ScrewParams; unknowns: name -> value of the calibrated quantities;
    advance_per_rev [m] / torque [N m]: what the optimizing engine achieved; iterations: number of
    simulations the optimizer ran; residual: max relative error of the two targets at params;
    guess: unknowns from the closed form alone; verification: dict(engine, advance_per_rev, torque,
    advance_error, torque_error) from an independent simulation on the other engine (None if skipped)."""

    params: ScrewParams
    unknowns: dict
    advance_per_rev: float
    torque: float
    iterations: int
    residual: float
    guess: dict
    engine: str
    target_advance_per_rev: float
    target_torque: float
    verification: dict | None = None
    history: list = field(default_factory=list)


class _Done(Exception):
    pass


def _check_targets(target_advance_per_rev, target_torque, base):
    a = check_real("target_advance_per_rev", target_advance_per_rev)
    tq = check_real("target_torque", target_torque)
    pt = pitch(base)
    if pt == 0.0:
        raise ValueError(f"base.helix_angle must be nonzero (pitch 0 has no thread advance); got {base.helix_angle!r}")
    if not 0.0 < a / pt < 1.0:
        raise ValueError(f"target_advance_per_rev must satisfy 0 < target_advance_per_rev / pitch < 1 "
                         f"(pitch = 2 pi R tan(helix_angle) = {pt!r} m); got {a!r} m (ratio {a / pt!r})")
    if not tq > 0.0:
        raise ValueError(f"target_torque must be > 0 (a sliding torque resists positive rotation); got {tq!r} N m")
    return a, tq


def calibrate_screw(target_advance_per_rev, target_torque, base=None, engine="reference", *, tol=1e-4,
                    max_simulations=12, jacobian="closed_form", verify=True):
    """Find B and F of the screw scene for a target advance per revolution [m] and sliding torque [N m].

    base: ScrewParams (default DEFAULT_BASE: defaults with generalized-alpha, t_end 0.5 s); the calibration keeps all of its fields except the
    unknowns (``UNKNOWNS[base.return_map]``, see the module docstring). The drive is forced to
    'rotation', and t_end is raised if the last half of the run would not all be sliding.
    engine: 'reference' or 'exudyn' runs the optimization; the other one verifies (``verify=True``).
    tol: stop when both relative errors are <= tol. jacobian: 'closed_form' (derivative of the closed
    form) or '2-point' (finite differences of the simulation, 2 extra runs per Jacobian).
    Raises ValueError naming the parameter for infeasible targets (0 < advance/pitch < 1 and torque > 0
    required) or unsupported settings."""
    from scipy.optimize import least_squares

    base = DEFAULT_BASE if base is None else base
    if not isinstance(base, ScrewParams):
        raise TypeError(f"base must be ScrewParams; got {type(base).__name__}")
    if engine not in ENGINES:
        raise ValueError(f"engine must be one of {ENGINES}; got {engine!r}")
    if jacobian not in ("closed_form", "2-point"):
        raise ValueError(f"jacobian must be 'closed_form' or '2-point'; got {jacobian!r}")
    tol = check_positive("tol", tol)
    if base.return_map not in CALIBRATED_MAPS:
        raise ValueError(f"base.return_map must be one of {CALIBRATED_MAPS} (the seed map's steady sliding depends "
                         f"on the step size, so there is nothing step-independent to calibrate); "
                         f"got {base.return_map!r}")
    if base.return_map == "radial" and base.adhesion != "spiral":
        raise ValueError(f"base.adhesion must be 'spiral' for the radial map (its ratio eps_1/eps_2 sets the advance); "
                         f"got {base.adhesion!r}")
    if base.return_map == "exact" and base.friction != "spiral":
        raise ValueError(f"base.friction must be 'spiral' for the exact map (mu_1/mu_2 sets the advance); "
                         f"got {base.friction!r}")
    a, tq = _check_targets(target_advance_per_rev, target_torque, base)
    base = base.with_overrides(drive="rotation")
    if not base.rotation_speed > 0.0:
        raise ValueError(f"base.rotation_speed must be > 0 for the calibration runs; got {base.rotation_speed!r}")

    x0 = closed_form_guess(a, tq, base)
    guess = _unknown_values(base, _apply(base, x0))

    def params_for(x):
        p = _apply(base, x)
        t_need = 2.5 * sliding_onset_angle(p) / p.rotation_speed   # last half of the run slides
        return p.with_overrides(t_end=t_need) if t_need > p.t_end else p

    history = []
    best = {}

    def residual(x):
        p = params_for(x)
        adv, torque = run_for_targets(p, engine)
        res = np.array([adv / a - 1.0, torque / tq - 1.0])
        if not np.all(np.isfinite(res)):
            raise RuntimeError(f"simulation with {engine} gave advance {adv!r}, torque {torque!r} for {p}")
        history.append(dict(_unknown_values(base, p), advance_per_rev=adv, torque=torque))
        if not best or np.max(np.abs(res)) < best["err"]:
            best.update(err=float(np.max(np.abs(res))), p=p, adv=adv, torque=torque)
        if np.max(np.abs(res)) <= tol:
            raise _Done
        if len(history) >= max_simulations:
            raise _Done
        return res

    def closed_form_jacobian(x):
        J = np.zeros((2, 2))
        f0 = steady_sliding(_apply(base, x))
        h = 1e-6
        for j in range(2):
            xp = np.array(x, float)
            xp[j] += h
            f1 = steady_sliding(_apply(base, xp))
            J[0, j] = (f1.advance_per_rev - f0.advance_per_rev) / (h * a)
            J[1, j] = (f1.torque - f0.torque) / (h * tq)
        return J

    try:
        least_squares(residual, x0, jac=closed_form_jacobian if jacobian == "closed_form" else "2-point",
                      diff_step=1e-4, xtol=1e-10, ftol=1e-12, gtol=1e-12, max_nfev=max_simulations)
    except _Done:
        pass
    p = best["p"]
    result = CalibrationResult(params=p, unknowns=_unknown_values(base, p), advance_per_rev=best["adv"],
                               torque=best["torque"], iterations=len(history), residual=best["err"], guess=guess,
                               engine=engine, target_advance_per_rev=a, target_torque=tq, history=history)
    if verify:
        other = ENGINES[1 - ENGINES.index(engine)]
        adv, torque = run_for_targets(p, other)
        result.verification = dict(engine=other, advance_per_rev=adv, torque=torque,
                                   advance_error=adv / a - 1.0, torque_error=torque / tq - 1.0)
    return result


__all__ = ["SteadySliding", "steady_sliding", "sliding_onset_angle", "closed_form_guess", "calibrate_screw",
           "CalibrationResult", "run_for_targets", "UNKNOWNS", "ENGINES", "CALIBRATED_MAPS", "DEFAULT_BASE"]
