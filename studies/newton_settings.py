"""Newton settings, work against precision (issue 13): which of Exudyn's Newton settings gives the
accuracy a scene needs at the least cost.

    python studies/newton_settings.py [--quick] [--repeats N] [--out DIR]

Every scene (block planar and full, screw reduced and full; their default drives, so Python drives
included as a user runs them) is solved at four Newton settings (``studies/_lib/baseline.py``
``apply_settings``): the package's (full Newton, relative and absolute tolerance 1e-10), Exudyn's
defaults (modified Newton, relative tolerance 1e-8), Exudyn's defaults with a fresh Jacobian at
every step (``modifiedNewtonJacUpdatePerStep``) and full Newton at Exudyn's tolerances. Cost:
median process CPU time of the solve per step over interleaved repeats (serial). Error: the largest
difference of the body coordinates from the package's run at the same step, over the run,
relative to the largest displacement of that run (the Newton error; the time-step error is the
subject of ``studies/work_precision.py``). Writes
``newton_settings.csv``, ``report.md`` (default ``studies/results/newton_settings``).
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
from _lib.studylib import Timer, finish, markdown_table, parse_args, sweep, table  # noqa: E402

NAME = "newton_settings"
SETTINGS = ("package", "exudyn", "jacobian_per_step", "full_newton_1e-8")
SCENES = [("block", dict(model="planar", points="corners")), ("block", dict(model="full", points="corners")),
          ("screw", dict(model="reduced")), ("screw", dict(model="full", drive="torque"))]
COLUMNS = ["scene [-]", "model [-]", "settings [-]", "cpu_per_step [s]", "cpu_per_simulated_second [s/s]",
           "newton_per_step [-]", "steps [-]", "error_vs_package [-]"]


def _coordinates(model):
    """(t, body coordinates) from the stored sensors (baseline.BaselineTrajectory)."""
    Q = np.asarray(baseline.BaselineTrajectory(model), dtype=float)
    return Q[:, 0], Q[:, 1:]


def run_case(case):
    """One scene at every setting, interleaved repeats; rows of COLUMNS."""
    from exu_aniso.models.block import BuildBlock, SolveTimed
    from exu_aniso.models.screw import BuildScrew
    from exu_aniso.scenes import BlockParams, ScrewParams
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
    t_ref, q_ref = _coordinates(last["package"])
    scale = max(float(np.abs(q_ref - q_ref[0]).max()), 1e-300)
    rows = []
    for s in SETTINGS:
        c = np.array(cost[s], dtype=float)
        t, q = _coordinates(last[s])
        qi = np.column_stack([np.interp(t_ref, t, q[:, j]) for j in range(q.shape[1])])
        rows.append([case["scene"], p.model, s, float(np.median(c[:, 0] / c[:, 1])), float(np.median(c[:, 0])) / p.t_end,
                     float(np.median(c[:, 2] / c[:, 1])), int(c[0, 1]), float(np.abs(qi - q_ref).max()) / scale])
    return rows


def main(argv=None):
    def extra(ap):
        ap.add_argument("--repeats", type=int, default=None, help="timing repeats (default 3 quick, 5 full)")
    args = parse_args(NAME, __doc__.splitlines()[0], argv, extra, parallel=False, results_doc=False)
    timer = Timer()
    reps = args.repeats or (3 if args.quick else 5)
    t_end = 0.1 if args.quick else 0.5
    cases = [dict(scene=sc, params=dict(t_end=t_end, **ov), repeats=reps) for sc, ov in SCENES]
    rows = [r for res in sweep(run_case, cases, args) for r in res]
    table(os.path.join(args.out, "newton_settings.csv"), COLUMNS, rows)
    print(f"{'scene':6s} {'model':8s} {'settings':18s} {'us/step':>8s} {'Newton/step':>11s} {'error':>9s}")
    for r in rows:
        print(f"{r[0]:6s} {r[1]:8s} {r[2]:18s} {r[3] * 1e6:8.1f} {r[5]:11.2f} {r[7]:9.1e}")
    body = (f"Median process CPU time of the solve per step over {reps} interleaved repeats, t_end = {t_end} s, the "
            "scenes' default step and drives. Error: largest difference of the body coordinates from the package "
            "setting's run, relative to its largest displacement. File: `newton_settings.csv`.\n\n"
            + markdown_table(["scene", "model", "settings", "us/step", "Newton/step", "error vs package"],
                             [[r[0], r[1], r[2], r[3] * 1e6, r[5], r[7]] for r in rows]))
    finish(args, timer, body, "Newton settings: work against precision")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
