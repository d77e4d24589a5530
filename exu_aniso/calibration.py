"""Calibrating the screw's adhesion B and friction F to a wanted advance per revolution and sliding torque.

Paper 001 (section 3) calibrates the adhesion and friction tensors of a screw "in order to prescribe
the resulting kinematics exactly by keeping the necessary sliding force at a certain level". This
module does that for the screw scene (``exu_aniso.scenes.screw.ScrewParams``, rotation drive).

Steady sliding in closed form: ``exu_aniso.scenes.screw.steady_sliding`` (the theory is in its module's
docstring).
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

from exu_aniso.scenes.screw import ScrewParams, pitch
from exu_aniso.scenes.screw import (CALIBRATED_MAPS, SteadySliding, sliding_onset_angle,  # noqa: F401
                                    steady_sliding)
from exu_aniso.util.validation import check_positive, check_real

ENGINES = ("reference", "exudyn")
UNKNOWNS = {"radial": ("eps_ratio", "mu_scale"), "exact": ("mu_ratio", "mu_2")}
# generalized-alpha (rho_inf 0.8) damps the unresolved torsional oscillation of screw and drive spring
# (omega ~ 2.8e3 rad/s for the defaults); with the trapezoidal rule it persists and its phase at the end
# of the run moves the fitted advance by up to ~1 % at dt = 1e-3 (5e-5 with generalized-alpha)
DEFAULT_BASE = ScrewParams(solver="generalized_alpha", t_end=0.5)


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
        from exu_aniso.scenes.screw import simulate_screw
        r = simulate_screw(p)
    else:
        from exu_aniso.models.screw import RunScrew
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
