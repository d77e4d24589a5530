"""Newton settings, work against precision: which of Exudyn's Newton settings gives the
accuracy a scene needs at the least cost.

    python studies/newton_settings.py [--quick] [--repeats N] [--out DIR]

Every scene (block planar and full on 4 corners, full block on an 8 x 8 grid, screw reduced and
full; their default drives) is solved at six Newton settings (``studies/_lib/baseline.py``
``apply_settings``): full Newton at tolerance 1e-10 (the reference of the errors), the package's
(Exudyn's modified Newton with a fresh Jacobian when an iteration contracts by less than 0.01,
tolerance 1e-10: ``exu_aniso.engines.exudyn_adapter.runner.SimulationSettingsFor``), Exudyn's defaults (modified Newton,
contractivity 0.5, relative tolerance 1e-8), the package's contractivity at Exudyn's tolerances, Exudyn's defaults with a fresh Jacobian at every step
(``modifiedNewtonJacUpdatePerStep``) and full Newton at Exudyn's tolerances. Cost: median process
CPU time of the solve per step over interleaved repeats (serial). Error: the largest difference of
the body coordinates from the full-Newton run at the same time, over the run, relative to the
largest displacement of that run (the Newton error; the time-step error is the subject of
``studies/work_precision.py``). Writes ``newton_settings.csv``, ``report.md`` (default
``studies/results/newton_settings``).

Not among the scenes: the screw under its torque drive at the default torque. Its step load
overshoots to twice the static torque, 0.100 N m against a sliding torque of 0.101 N m: the thread
grazes its slip limit at every oscillation, and the run is not converged in the step (axial advance
at 0.5 s 1.2e-4, 2.4e-4, 1.6e-4, 3.2e-4 m for dt = 1, 0.5, 0.25, 0.125 ms under full Newton), so
any two settings that cut a step differently disagree by O(1) (README "Solver settings").
"""
from __future__ import annotations

import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
if HERE not in sys.path:
    sys.path.insert(0, HERE)

from _lib import baseline  # noqa: E402
from _lib.studylib import Timer, finish, markdown_table, sweep, table, timing_args  # noqa: E402

NAME = "newton_settings"
REFERENCE = "full_newton_1e-10"
SETTINGS = (REFERENCE, "package", "package_1e-8", "exudyn", "jacobian_per_step", "full_newton_1e-8")
SCENES = [("block", dict(model="planar", points="corners")), ("block", dict(model="full", points="corners")),
          ("block", dict(model="full", points="grid:8")), ("screw", dict(model="reduced")),
          ("screw", dict(model="full"))]
COLUMNS = ["scene [-]", "model [-]", "points [-]", "settings [-]", "cpu_per_step [s]",
           "cpu_per_simulated_second [s/s]", "newton_per_step [-]", "steps [-]", "error_vs_full_newton [-]",
           "cpu_per_step_min [s]", "cpu_per_step_max [s]"]


def _coordinates(model):
    """(t, body coordinates) from the stored sensors (baseline.BaselineTrajectory)."""
    Q = np.asarray(baseline.BaselineTrajectory(model), dtype=float)
    return Q[:, 0], Q[:, 1:]


def run_case(case):
    """One scene at every setting, interleaved repeats; rows of COLUMNS."""
    from exu_aniso.models.block import BuildBlock
    from exu_aniso.engines.exudyn_adapter.runner import SolveTimed
    from exu_aniso.models.screw import BuildScrew
    from exu_aniso.scenes.block import BlockParams
    from exu_aniso.scenes.screw import ScrewParams
    P, build = (BlockParams, BuildBlock) if case["scene"] == "block" else (ScrewParams, BuildScrew)
    p = P(**case["params"])
    warm = p.with_overrides(t_end=5 * p.dt)
    SolveTimed(*[build(warm)[k] for k in ("mbs", "simulationSettings", "solverType")])
    cost = {s: [] for s in SETTINGS}
    last = {}
    for _ in range(case["repeats"]):
        for s in SETTINGS:
            model = baseline.apply_settings(build(p), s)
            c0 = time.process_time()
            _, steps, its, _ = SolveTimed(model["mbs"], model["simulationSettings"], model["solverType"])
            cost[s].append((time.process_time() - c0, steps, its))
            last[s] = model
    t_ref, q_ref = _coordinates(last[REFERENCE])
    scale = max(float(np.abs(q_ref - q_ref[0]).max()), 1e-300)
    rows = []
    for s in SETTINGS:
        c = np.array(cost[s], dtype=float)
        t, q = _coordinates(last[s])
        qi = np.column_stack([np.interp(t_ref, t, q[:, j]) for j in range(q.shape[1])])
        points = p.points if case["scene"] == "block" else f"{p.rings} x {p.points_per_ring}"
        rows.append([case["scene"], p.model, points, s, float(np.median(c[:, 0] / c[:, 1])),
                     float(np.median(c[:, 0])) / p.t_end, float(np.median(c[:, 2] / c[:, 1])), int(c[0, 1]),
                     float(np.abs(qi - q_ref).max()) / scale, float(np.min(c[:, 0] / c[:, 1])),
                     float(np.max(c[:, 0] / c[:, 1]))])
    return rows


def main(argv=None):
    args, reps = timing_args(NAME, __doc__.splitlines()[0], argv, quick_repeats=3)
    timer = Timer()
    t_end = 0.1 if args.quick else 0.5
    cases = [dict(scene=sc, params=dict(t_end=t_end, **ov), repeats=reps) for sc, ov in SCENES]
    rows = [r for res in sweep(run_case, cases, args) for r in res]
    table(os.path.join(args.out, "newton_settings.csv"), COLUMNS, rows)
    print(f"{'scene':6s} {'model':8s} {'points':8s} {'settings':18s} {'us/step [min-max]':>22s} {'Newton/step':>11s} "
          f"{'error':>9s}")
    for r in rows:
        spread = f"{r[4] * 1e6:.1f} [{r[9] * 1e6:.1f}-{r[10] * 1e6:.1f}]"
        print(f"{r[0]:6s} {r[1]:8s} {r[2]:8s} {r[3]:18s} {spread:>22s} {r[6]:11.2f} {r[8]:9.1e}")
    body = (f"Median process CPU time of the solve per step over {reps} interleaved repeats, t_end = {t_end} s, the "
            "scenes' default step and drives. Error: largest difference of the body coordinates from the run with "
            "full Newton at tolerance 1e-10, relative to its largest displacement. File: `newton_settings.csv`.\n\n"
            + markdown_table(["scene", "model", "points", "settings", "us/step median [min-max]", "Newton/step",
                              "error vs full Newton"],
                             [[r[0], r[1], r[2], r[3], f"{r[4] * 1e6:.1f} [{r[9] * 1e6:.1f}-{r[10] * 1e6:.1f}]", r[6],
                               r[8]] for r in rows]))
    finish(args, timer, body, "Newton settings: work against precision")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
