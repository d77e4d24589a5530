"""Nut: a free nut on a vertical bolt, its descent against the closed form under step refinement for
both models (speed against error), and its self-locking threshold located by bisection.

Usage: python studies/nut.py [--quick] [--serial] [--out DIR]
"""
from __future__ import annotations

import math
import os
import sys
import warnings

HERE = os.path.dirname(os.path.abspath(__file__))
if HERE not in sys.path:
    sys.path.insert(0, HERE)
from _lib.studylib import (Timer, finish, markdown_table, parse_args, plot_error_against_wall, read_table,  # noqa: E402
                           sweep, table)

from exu_aniso.scenes.nut import NutParams, nut_closed_forms  # noqa: E402

DTS = [4e-4, 2e-4, 1e-4, 5e-5]
MODELS = ("reduced", "full")
BISECTION_WIDTH = 2e-3          # the bracket's width at the end, relative to the closed form


def run_case(c):
    """One Exudyn run: the measured descent acceleration, its closed form, the relative error, the cost
    (NaN, with the outcome, where the run fails or the nut does not run down)."""
    from exu_aniso.engines.failure import SimulationFailure
    from exu_aniso.models.nut import RunNut
    nan = float("nan")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            s = RunNut(NutParams(model=c["model"], dt=c["dt"])).summary
        except SimulationFailure as e:
            return dict(measured=nan, theory=nan, error=nan, residual=nan, ok=False, wall=nan, iterations=nan,
                        outcome=f"failed at t = {e.time_reached:.3g} s")
    a, t = s["descent_acceleration"], s["descent_acceleration_theory"]
    outcome = "runs down" if a is not None else "stops (" + s["undefined"]["descent_acceleration"] + ")"
    return dict(measured=nan if a is None else a, theory=t, error=nan if a is None else (a - t) / abs(t),
                residual=s["energy"]["residual"], ok=s["energy_ok"], wall=s["wall_s"],
                iterations=s["newton_iterations"], outcome=outcome)


def bisect_threshold():
    """The self-locking friction located by runs of the default reduced model alone: held or running
    down, from 0.5 and 1.5 times the closed form until the bracket is BISECTION_WIDTH of it wide.
    Returns (the bracket's middle, the closed form, the runs)."""
    from exu_aniso.models.nut import RunNut
    mu_c = nut_closed_forms(NutParams())["self_locking_mu_theory"]
    lo, hi, runs = 0.5 * mu_c, 1.5 * mu_c, 0
    while hi - lo > BISECTION_WIDTH * mu_c:
        mid = 0.5 * (lo + hi)
        held = RunNut(NutParams(mu_thread=mid)).summary["held"]
        lo, hi = (lo, mid) if held else (mid, hi)
        runs += 1
    return 0.5 * (lo + hi), mu_c, runs


COLS = ["model [-]", "dt [s]", "descent_acceleration [m/s^2]", "theory [m/s^2]", "error [-]", "energy_residual [-]",
        "wall [s]", "newton_iterations [-]", "outcome [-]"]


def main(argv=None):
    args = parse_args("nut", __doc__.splitlines()[0], argv)
    timer = Timer()
    dts = DTS[1:3] if args.quick else DTS
    cases = [dict(model=m, dt=dt) for m in MODELS for dt in dts]
    out = sweep(run_case, cases, args)
    path = table(os.path.join(args.out, "refinement.csv"), COLS,
                 [[c["model"], c["dt"], o["measured"], o["theory"], o["error"], o["residual"], o["wall"],
                   o["iterations"], o["outcome"]] for c, o in zip(cases, out)])
    found, mu_c, runs = bisect_threshold()
    table(os.path.join(args.out, "threshold.csv"), ["found [-]", "theory [-]", "error [-]", "runs [-]"],
          [[found, mu_c, found / mu_c - 1.0, runs]])
    fig = plot_error_against_wall(args.out, "refinement.csv", "model [-]", ("reduced", "full"), "nut.png",
                                  ylabel="|relative error| of the descent acceleration [-]")
    T = read_table(path)
    rows = [[T[c][i] for c in COLS] for i in range(len(cases))]
    p = NutParams()
    body = f"""
Scene: `exu_aniso/scenes/nut.py` (NutParams; Exudyn model `exu_aniso/models/nut.py`): an M10 nut (d2 =
{1e3 * p.d2:g} mm, P = {1e3 * p.pitch:g} mm, 60 deg thread, {1e3 * p.nut_mass:g} g, J = {p.nut_inertia:g} kg m^2)
on a fixed vertical bolt, greased (mu = {p.mu_thread:g} along the helix), its weight rising over {p.load_time:g} s;
the closed forms are `exu_aniso/scenes/threads.py` (`nut_descent`, `self_locking_friction`).

**Descent against the closed form** (`exu-aniso run nut --set model=MODEL --set dt=DT`, {p.t_end:g} s; a run that
stops where it should run down leaves its ledger open and warns): the
reduced model (the nut on a screw joint, one representative point carrying the totals) and the full 6-DOF nut
({p.turns} turns x {p.points_per_turn} points). "error" is (measured - closed form) / |closed form|, the measured
acceleration a straight line through vz over the run's second half.

{markdown_table(COLS, rows, fmt="{:.4g}")}
![error against wall time](./{fig})

{verdict(T)}

**Self-locking threshold by bisection** (the default reduced model, held or running down after
{p.t_end:g} s): {runs} runs narrow the bracket from 0.5 to 1.5 times tan(phi) cos(beta_n) = {mu_c:.6g} down to
{BISECTION_WIDTH:g} of it; its middle {found:.6g} lies {100 * (found / mu_c - 1):+.3f} % from the closed form. A
box on an incline of the lead angle (the flank angle left out) would put it at tan(phi) = {p.pitch / (math.pi * p.d2):.6g}.
"""
    finish(args, timer, body, "Nut: a free nut's descent and self-locking against the closed forms")
    return 0


def verdict(T):
    """The report's reading of the refinement table, from its numbers."""
    def errors(model):
        return [(T["dt [s]"][i], T["error [-]"][i], T["outcome [-]"][i]) for i, m in enumerate(T["model [-]"])
                if m == model]
    red, full = errors("reduced"), errors("full")
    worst = max(abs(e) for _, e, _ in red)
    bad = [f"dt = {dt:g} s: {o}" for dt, e, o in full if not math.isfinite(e)]
    good = ", ".join(f"{100 * abs(e):.3g} % at dt = {dt:g} s" for dt, e, _ in full if math.isfinite(e))
    return (f"The reduced model meets the uniform ring's closed form within {worst:.2g} at every step (first order "
            f"in the step), and its longest step costs least: the reduced model at dt = {max(d for d, _, _ in red):g} s "
            f"is the scene's default. The full nut's points sit at different heights along the turns, so its ring's "
            f"load is not quite uniform and it tilts a little; under the trapezoidal rule it needs a short step "
            f"({'; '.join(bad) if bad else 'every step runs'}), and then lies {good} off.")


if __name__ == "__main__":
    sys.exit(main())
