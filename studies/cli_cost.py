"""The scenes as a user runs them: the cost per step of ``exu-aniso run ...`` with the scene's
sensors, energy ledger, result files and plot, against the yardstick of the speed targets.

    python studies/cli_cost.py [--quick] [--repeats N] [--out DIR]

What the command line does for ``run SCENE`` (``exu_aniso.cli.simulate``, then
``exu_aniso.cli.write_outputs``: trajectory.csv, trajectory.png, summary.json) is run in this process
at two simulated lengths, and so is the yardstick: a rigid cube on as many C++
``CartesianSpringDamper`` as the scene has contact points, at Exudyn's defaults
(``studies/_lib/yardstick.py``, ``BuildCube``). Every repeat runs each case's short and long run and
the yardstick's, interleaved; a per-step figure is the process CPU time of the long run minus the
short one over the difference of their steps: start-up, compilation (cached), model building and
the fixed part of the output cancel. One process, not one per run: a fresh process's own start-up
varies by about 0.1 s, as much as 5000 steps of the 4-corner block (the spread this study had when it
timed ``python -m exu_aniso.cli`` in fresh processes).

Per step, median [min-max] of the repeats: the command line's total and its parts (the solve, with
the scene's sensors stored every step; the trajectory and energy ledger made from them; the files
and the plot; model building, which should cancel), the yardstick, and their ratio next to the
target of the same model in the speed targets (``python studies/benchmarks.py``: the solve alone).
Writes ``cli_cost.csv`` and ``report.md`` (default ``studies/results/cli_cost``).
"""
from __future__ import annotations

import gc
import os
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
if HERE not in sys.path:
    sys.path.insert(0, HERE)

from _lib.studylib import Timer, finish, markdown_table, table, timing_args  # noqa: E402
from _lib.target_timing import DT, timed_solve  # noqa: E402
from _lib.yardstick import BuildCube  # noqa: E402

from exu_aniso import cli  # noqa: E402

NAME = "cli_cost"
# (scene, --set overrides, contact points (the yardstick's springs), the speed target's row and ratio)
CASES = [("block", ("model=full", "points=corners"), 4, "full block, 4 corners", 3.0),
         ("block", ("model=full", "points=grid:8"), 64, "full block, 8 x 8 grid", 0.6),
         ("screw", (), 24, "reduced screw (default ScrewParams)", 1.2)]
PARTS = ("total", "solve", "trajectory_and_ledger", "files_and_plot", "model_building")
COLUMNS = (["scene [-]", "overrides [-]", "steps_short [-]", "steps_long [-]"]
           + [f"{p}{s} [us]" for p in PARTS for s in ("", "_min", "_max")]
           + ["yardstick [us]", "yardstick_min [us]", "yardstick_max [us]", "ratio [-]", "ratio_min [-]",
              "ratio_max [-]", "target_row [-]", "target [-]", "holds [-]"])


def run_cli(scene, overrides, t_end, out):
    """What ``exu-aniso run SCENE --set ...`` does after parsing: ({part: process CPU [s]}, steps)."""
    params = cli.make_params(scene, cli.parse_sets(list(overrides) + [f"t_end={t_end}"]))
    gc.collect()                  # the previous runs' garbage is not collected on this run's time
    c0 = time.process_time()
    res = cli.simulate(scene, params, "exudyn")
    c1 = time.process_time()
    cli.write_outputs(scene, params, "exudyn", out, res)
    c2 = time.process_time()
    solve, post = res.info["solve_cpu_s"], res.info["post_cpu_s"]
    return dict(total=c2 - c0, solve=solve, trajectory_and_ledger=post, files_and_plot=c2 - c1,
                model_building=(c1 - c0) - solve - post), int(res.summary["steps"])


def run_cube(K, t_end):
    """The yardstick's solve: (process CPU [s], steps)."""
    model = BuildCube(K, t_end, DT)
    gc.collect()
    cpu, _, steps, _ = timed_solve(model)
    return cpu, steps


def _stats(v):
    v = np.asarray(v, dtype=float)
    return [float(np.median(v)), float(v.min()), float(v.max())]


def measure(t_short, t_long, repeats):
    """Rows of COLUMNS: per case, the per-step figures of every repeat (long minus short, interleaved)."""
    parts = {i: {p: [] for p in PARTS} for i in range(len(CASES))}
    cube, ratio, steps = {i: [] for i in range(len(CASES))}, {i: [] for i in range(len(CASES))}, {}
    with tempfile.TemporaryDirectory() as tmp:
        for i, (scene, over, K, _, _) in enumerate(CASES):       # warm-up: kernels compiled or loaded
            run_cli(scene, over, t_short, os.path.join(tmp, f"warm{i}"))
            run_cube(K, t_short)
        for _ in range(repeats):
            for i, (scene, over, K, _, _) in enumerate(CASES):
                a0, s0 = run_cli(scene, over, t_short, os.path.join(tmp, f"short{i}"))
                a1, s1 = run_cli(scene, over, t_long, os.path.join(tmp, f"long{i}"))
                y0, n0 = run_cube(K, t_short)
                y1, n1 = run_cube(K, t_long)
                if s1 <= s0 or n1 <= n0:
                    raise RuntimeError(f"{scene} {over}: no more steps at t_end {t_long} than at {t_short}")
                for p in PARTS:
                    parts[i][p].append((a1[p] - a0[p]) / (s1 - s0) * 1e6)
                cube[i].append((y1 - y0) / (n1 - n0) * 1e6)
                ratio[i].append(parts[i]["total"][-1] / cube[i][-1])
                steps[i] = (s0, s1)
    rows = []
    for i, (scene, over, K, row, target) in enumerate(CASES):
        r = _stats(ratio[i])
        rows.append([scene, " ".join(over) or "defaults", *steps[i]]
                    + [x for p in PARTS for x in _stats(parts[i][p])]
                    + _stats(cube[i]) + r + [row, target, "yes" if r[0] <= target else "no"])
    return rows


def _cell(r, name, fmt="{:.1f}"):
    i = COLUMNS.index(f"{name} [us]") if f"{name} [us]" in COLUMNS else COLUMNS.index(f"{name} [-]")
    return f"{fmt.format(r[i])} [{fmt.format(r[i + 1])}-{fmt.format(r[i + 2])}]"


def main(argv=None):
    args, reps = timing_args(NAME, __doc__.splitlines()[0], argv, quick_repeats=1)
    timer = Timer()
    t_short, t_long = (0.02, 0.12) if args.quick else (0.5, 10.5)   # 10,000 steps apart
    rows = measure(t_short, t_long, reps)
    table(os.path.join(args.out, "cli_cost.csv"), COLUMNS, rows)
    head = ["scene", "overrides", "command line us/step", "solve", "trajectory and ledger", "files and plot",
            "model building", "yardstick us/step", "ratio", "target", "holds"]
    cells = [[r[0], r[1], _cell(r, "total"), _cell(r, "solve"), _cell(r, "trajectory_and_ledger"),
              _cell(r, "files_and_plot"), _cell(r, "model_building"), _cell(r, "yardstick"),
              _cell(r, "ratio", "{:.2f}"), f"{r[-2]:g}x", r[-1]] for r in rows]
    for c in [head] + cells:
        print(" | ".join(c))
    body = (f"`exu-aniso run SCENE --set t_end=T ...` as the command line runs it (simulate, then trajectory.csv, "
            f"trajectory.png, summary.json), in this process at T = {t_short} and {t_long} s, and the yardstick "
            f"(a cube on as many C++ springs as the scene has points, Exudyn's defaults) at the same lengths; "
            f"{reps} interleaved repeats; per step: process CPU time of the long run minus the short one over the "
            "difference of their steps, median [min-max]. The ratio is formed repeat by repeat; the target is the "
            "same model's in the speed targets (`python studies/benchmarks.py`, where it is the solve alone). "
            "File: `cli_cost.csv`.\n\n" + markdown_table(head, cells))
    finish(args, timer, body, "The scenes as a user runs them: cost per step of the command line")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
