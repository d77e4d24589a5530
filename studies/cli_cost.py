"""The scenes as a user runs them: the cost per step of ``exu-aniso run ...`` with the scene's
sensors, energy ledger, result files and plots, next to the benchmark's solve-only figure.

    python studies/cli_cost.py [--quick] [--repeats N] [--out DIR]

Each case is run by the command line (``python -m exu_aniso.cli run SCENE --set ... --quiet``) at two
simulated lengths, interleaved, in fresh processes; the CPU time of the child process (user +
system, ``resource.getrusage(RUSAGE_CHILDREN)``) of the long run minus that of the short run of the
same repeat, divided by the difference of their steps (the ``steps=`` of the summary line), is what
one more step costs a user: start-up, compilation (cached), model building and the fixed part of
the output cancel. ``benchmark [us]``: the same model's "ours" in the speed targets of
``docs/results/benchmarks/targets.csv`` (``python studies/benchmarks.py``: the solve alone), and
``cli_over_benchmark``, what the command line adds per step (sensors stored every step, the ledger,
trajectory.csv and the plots). Writes ``cli_cost.csv`` and ``report.md`` (default
``studies/results/cli_cost``).
"""
from __future__ import annotations

import os
import re
import resource
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
if HERE not in sys.path:
    sys.path.insert(0, HERE)

from _lib.studylib import Timer, finish, markdown_table, read_table, table, timing_args  # noqa: E402

NAME = "cli_cost"
ROOT = os.path.dirname(HERE)
TARGETS_CSV = os.path.join(ROOT, "docs", "results", "benchmarks", "targets.csv")
# (scene, --set overrides, the row of the speed targets with the same model)
CASES = [("block", ("model=full", "points=corners"), "full block, 4 corners"),
         ("block", ("model=full", "points=grid:8"), "full block, 8 x 8 grid"),
         ("screw", (), "reduced screw (default ScrewParams)")]
COLUMNS = ["scene [-]", "overrides [-]", "t_short [s]", "t_long [s]", "steps_short [-]", "steps_long [-]",
           "cli_per_step [us]", "cli_min [us]", "cli_max [us]", "benchmark [us]", "cli_over_benchmark [-]"]


def _run(scene, overrides, t_end, out):
    """One command-line run in a fresh process: (child CPU time [s], steps)."""
    cmd = [sys.executable, "-m", "exu_aniso.cli", "run", scene, "--out", out, "--quiet", "--set", f"t_end={t_end}"]
    for o in overrides:
        cmd += ["--set", o]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    res = subprocess.run(cmd, capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if res.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed ({res.returncode}):\n{res.stderr[-2000:]}")
    steps = re.search(r"\bsteps=(\d+)", res.stdout)
    if steps is None:
        raise RuntimeError(f"{' '.join(cmd)}: no steps= in its summary line:\n{res.stdout[-1000:]}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return cpu, int(steps.group(1))


def _benchmark_figures():
    """{target row: ours [us]} from the committed speed targets, or {} without them."""
    if not os.path.exists(TARGETS_CSV):
        return {}
    T = read_table(TARGETS_CSV)
    return dict(zip(T["scene [-]"], T["ours [us]"]))


def measure(t_short, t_long, repeats):
    """Rows of COLUMNS: per case the per-step cost of every repeat (long minus short, interleaved)."""
    bench = _benchmark_figures()
    per_step = {i: [] for i in range(len(CASES))}
    steps = {}
    with tempfile.TemporaryDirectory() as tmp:
        for i, (scene, over, _) in enumerate(CASES):           # warm-up: kernels compiled or loaded
            _run(scene, over, t_short, os.path.join(tmp, f"warm{i}"))
        for _ in range(repeats):
            for i, (scene, over, _) in enumerate(CASES):
                c0, s0 = _run(scene, over, t_short, os.path.join(tmp, f"short{i}"))
                c1, s1 = _run(scene, over, t_long, os.path.join(tmp, f"long{i}"))
                if s1 <= s0:
                    raise RuntimeError(f"{scene} {over}: {s1} steps at t_end {t_long} against {s0} at {t_short}")
                per_step[i].append((c1 - c0) / (s1 - s0) * 1e6)
                steps[i] = (s0, s1)
    rows = []
    for i, (scene, over, target) in enumerate(CASES):
        v = np.array(per_step[i])
        b = float(bench.get(target, float("nan")))
        med = float(np.median(v))
        rows.append([scene, " ".join(over) or "defaults", t_short, t_long, steps[i][0], steps[i][1], med,
                     float(v.min()), float(v.max()), b, med / b])
    return rows


def main(argv=None):
    args, reps = timing_args(NAME, __doc__.splitlines()[0], argv, quick_repeats=1)
    timer = Timer()
    # 5000 steps apart: a fresh process's own CPU time varies by ~0.1 s, 20 us per step over them
    t_short, t_long = (0.02, 0.12) if args.quick else (0.5, 5.5)
    rows = measure(t_short, t_long, reps)
    table(os.path.join(args.out, "cli_cost.csv"), COLUMNS, rows)
    head = ["scene", "overrides", "steps short, long", "command line us/step", "benchmark us/step",
            "command line / benchmark"]
    cells = [[r[0], r[1], f"{r[4]}, {r[5]}", f"{r[6]:.1f} [{r[7]:.1f}-{r[8]:.1f}]", f"{r[9]:.1f}", f"{r[10]:.2f}"]
             for r in rows]
    for c in [head] + cells:
        print("  ".join(f"{x:>22s}" for x in c))
    body = (f"`exu-aniso run SCENE --set t_end=T ...` in fresh processes at T = {t_short} and {t_long} s, "
            f"{reps} interleaved repeats: child CPU time of the long run minus the short run over the "
            "difference of their steps, median [min-max]; the benchmark: the same model's solve alone "
            "(`docs/results/benchmarks/targets.csv`, `python studies/benchmarks.py`). File: `cli_cost.csv`.\n\n"
            + markdown_table(head, cells))
    finish(args, timer, body, "The scenes as a user runs them: cost per step of the command line")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
