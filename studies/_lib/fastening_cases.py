"""Cases of studies/fastening.py (not part of the installed package): one fastening run per case dict,
reduced to the numbers the study tabulates; the timed runs of its speed/error section; the analytic map
of VDI 2230's linearized thread term against the exact one.
"""
from __future__ import annotations

import math
import statistics
import time
import warnings

import numpy as np

CURVE_SAMPLES = 120         # samples of a torque-tension curve kept for the figure
TRACE_SAMPLES = 60          # samples of a head-ring trace kept for the figure


# ----------------------------------------------------------------------------------------------
# torque-tension at a target torque

def clamp_force_at_torque(torque, clamp_force, target):
    """Clamp force [N] where the drive torque first reaches ``target`` [N m] (linear between the two
    samples around the crossing); None if the run never reaches it."""
    T, F = np.asarray(torque, float), np.asarray(clamp_force, float)
    hit = np.nonzero(T >= target)[0]
    if not len(hit):
        return None
    i = int(hit[0])
    if i == 0:
        return float(F[0])
    return float(F[i - 1] + (target - T[i - 1]) * (F[i] - F[i - 1]) / (T[i] - T[i - 1]))


def clamp_force_at_torque_theory(p, target):
    """The formula's clamp force [N] at the torque ``target``: the thread carries clamp force plus
    axial_load, the head the clamp force, so T = (T_th/F)(F + F_a) + (T_h/F) F and
    F = (target - (T_th/F) F_a) / (T/F)."""
    from exu_aniso.scenes.fastening import theory
    th = theory(p)[0]
    return (target - th["thread_torque_per_clamp_force_theory"] * p.axial_load) / th["torque_per_clamp_force_theory"]


# ----------------------------------------------------------------------------------------------
# the head ring's instantaneous torque (orthotropic bearing)

def ring_check(p, traj):
    """The head torque per clamp force against the ring formula at the ring's *current* orientation:
    the head's points turn with the bolt while the lay stays with the part, so at the bolt angle a the
    lay lies at head_net_angle - a from the ring's points (threads.orthotropic_ring_torque_factor).
    Over the tightening phase (scenes.fastening.tightening): the largest relative error, the range
    of the formula, the bolt angles, and a thinned trace (relative lay angle [deg], simulated, formula)."""
    from exu_aniso.scenes.fastening import head_ring_factor, tightening
    F = np.asarray(traj["clamp_force"], float)
    tight = tightening(F)
    ang = np.asarray(traj["angle"], float)[tight]
    sim = np.asarray(traj["head_torque"], float)[tight] / (F[tight] * p.head_radius)
    rel = math.radians(p.head_net_angle) - ang
    formula = head_ring_factor(p, ang)
    pick = np.unique(np.linspace(0, len(sim) - 1, TRACE_SAMPLES).round().astype(int))
    return dict(ring_max_error=float(np.max(np.abs(sim / formula - 1.0))),
                ring_formula_min=float(formula.min()), ring_formula_max=float(formula.max()),
                tight_angle_from_deg=float(math.degrees(ang[0])), tight_angle_to_deg=float(math.degrees(ang[-1])),
                trace=dict(relative_lay_deg=np.degrees(rel[pick]).tolist(), simulated=sim[pick].tolist(),
                           formula=formula[pick].tolist()))


# ----------------------------------------------------------------------------------------------
# one run

def _failure_text(f):
    cause = (f.cause or str(f)).strip().splitlines()
    return f"stopped at t = {f.time_reached:.4g} s: {cause[-1] if cause else 'solver failure'}"


def run_case(case):
    """case: dict(params=dict of FasteningParams fields, options=dict for RunFastening (optional),
    target=torque [N m] (optional: the clamp force there), ring=True (optional: ring_check)).
    Returns dict(status="ok" or the failure's text, summary=the run's summary (energy ledger
    included), plus clamp_force_at_target, its theory, a thinned torque-tension curve, the ring check)."""
    from exu_aniso.engines.failure import SimulationFailure
    from exu_aniso.models.fastening import RunFastening
    from exu_aniso.scenes.fastening import FasteningParams
    p = FasteningParams(**case["params"])
    t0 = time.perf_counter()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            r = RunFastening(p, **case.get("options", {}))
    except SimulationFailure as f:
        return dict(status=_failure_text(f), summary={}, run_s=time.perf_counter() - t0)
    s, tr = r.summary, r.trajectory
    out = dict(status="ok", summary={k: v for k, v in s.items() if k != "undefined"},
               undefined=dict(s.get("undefined") or {}), run_s=time.perf_counter() - t0)
    if "target" in case:
        out["clamp_force_at_target"] = clamp_force_at_torque(tr["torque"], tr["clamp_force"], case["target"])
        out["clamp_force_at_target_theory"] = clamp_force_at_torque_theory(p, case["target"])
        pick = np.unique(np.linspace(0, len(tr["t"]) - 1, CURVE_SAMPLES).round().astype(int))
        out["curve"] = dict(clamp_force=np.asarray(tr["clamp_force"])[pick].tolist(),
                            torque=np.asarray(tr["torque"])[pick].tolist())
    if case.get("ring"):
        out.update(ring_check(p, tr))
    return out


# ----------------------------------------------------------------------------------------------
# timed runs (the speed/error section): interleaved repeats in this process

def timed_runs(configs, repeats):
    """configs: list of dict(label, params, options). Each configuration is first run once untimed for
    20 steps (first-call costs: numba caches, imports); then ``repeats`` rounds, each running every
    configuration once in the given order (interleaved, so a slow phase of the machine hits all of them).
    Per configuration: the medians of the solve's wall time (the summary's wall_s: SolveDynamic alone)
    and of the whole RunFastening call (build, solve, the torques and the energy ledger from the
    trajectory), the last run's summary, and for a run that stops, its failure text, time, steps and the
    largest tilt of the bolt up to the failure."""
    from exu_aniso.engines.failure import SimulationFailure
    from exu_aniso.models.fastening import RunFastening
    from exu_aniso.scenes.fastening import FasteningParams
    params = [FasteningParams(**c["params"]) for c in configs]
    for c, p in zip(configs, params):
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                RunFastening(p.with_overrides(t_end=20 * p.dt), **c.get("options", {}))
        except Exception:        # noqa: BLE001  (a configuration that stops is timed and reported below)
            pass
    runs = [[] for _ in configs]
    for _ in range(repeats):
        for c, p, rec in zip(configs, params, runs):
            t0 = time.perf_counter()
            try:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    r = RunFastening(p, **c.get("options", {}))
                rec.append(dict(status="ok", run_s=time.perf_counter() - t0, wall_s=r.summary["wall_s"],
                                summary={k: v for k, v in r.summary.items() if k != "undefined"}))
            except SimulationFailure as f:
                tilt = (float(np.degrees(np.max(f.partial.trajectory["tilt"])))
                        if f.partial is not None and len(f.partial.trajectory["tilt"]) else float("nan"))
                rec.append(dict(status=_failure_text(f), run_s=time.perf_counter() - t0, wall_s=float("nan"),
                                summary=dict(steps=f.steps, newton_iterations=f.newton_iterations,
                                             time_reached=f.time_reached, tilt_max_deg=tilt)))
    out = []
    for c, rec in zip(configs, runs):
        last = rec[-1]
        out.append(dict(label=c["label"], params=c["params"], options=c.get("options", {}), status=last["status"],
                        statuses=sorted({x["status"] for x in rec}), repeats=len(rec),
                        wall_s=statistics.median(x["wall_s"] for x in rec),
                        run_s=statistics.median(x["run_s"] for x in rec), summary=last["summary"]))
    return out


# ----------------------------------------------------------------------------------------------
# VDI 2230's linearization against the exact thread term (analytic)

def pitch_for_lead(lead_deg, d2):
    """Pitch [m] of the lead angle [deg] at the pitch diameter d2: P = pi d2 tan(lead)."""
    return math.pi * d2 * math.tan(math.radians(lead_deg))


def vdi_thread_error(lead_deg, flank_deg, mu, d2):
    """Relative error of VDI 2230's thread term 0.16 P + 0.58 d2 mu_G against the exact one
    (threads.thread_torque_per_force) at this lead angle [deg], full flank angle [deg] and mu_G."""
    from exu_aniso.scenes import threads
    P = pitch_for_lead(lead_deg, d2)
    exact = threads.thread_torque_per_force(d2, P, math.radians(flank_deg), mu)
    return threads.torque_per_clamp_force_vdi2230(d2, P, mu, 0.0, 0.0) / exact - 1.0


def vdi_band(lead_deg, mu, d2, tol, flank_range=(0.0, 90.0)):
    """Flank angles [deg] (lo, hi) within flank_range where |VDI error| <= tol at this lead angle. The
    error falls monotonically with the flank angle (checked on a 1 deg grid here): from + (0.58 > 0.5 /
    cos(beta_n / 2) at small flank angles) through zero near 60 deg to -; lo / hi are the crossings
    of +tol / -tol (the range's ends where there is none; NaN, NaN if the error stays outside)."""
    from scipy.optimize import brentq
    a, b = flank_range
    grid = np.arange(a, b + 0.5, 1.0)
    e = np.array([vdi_thread_error(lead_deg, f, mu, d2) for f in grid])
    if not np.all(np.diff(e) < 0.0):
        raise ValueError(f"VDI error not monotone in the flank angle at lead {lead_deg} deg")

    def cross(level):
        return brentq(lambda f: vdi_thread_error(lead_deg, f, mu, d2) - level, a, b, xtol=1e-10)

    if e[0] < -tol or e[-1] > tol:
        return float("nan"), float("nan")
    lo = a if e[0] <= tol else cross(tol)
    hi = b if e[-1] >= -tol else cross(-tol)
    return float(lo), float(hi)


def vdi_lead_limit(flank_deg, mu, d2, tol, lead_range=(1.0, 10.0)):
    """Smallest lead angle [deg] in lead_range beyond which |VDI error| > tol at this flank angle
    (NaN if it stays within tol over the range; the range's start if it is outside already)."""
    from scipy.optimize import brentq
    a, b = lead_range
    grid = np.linspace(a, b, 91)
    e = np.abs([vdi_thread_error(lead, flank_deg, mu, d2) for lead in grid])
    out = np.nonzero(e > tol)[0]
    if not len(out):
        return float("nan")
    i = int(out[0])
    if i == 0:
        return float(a)
    return float(brentq(lambda lead: abs(vdi_thread_error(lead, flank_deg, mu, d2)) - tol, grid[i - 1], grid[i],
                        xtol=1e-10))
