"""Ours against Exudyn's C++ spring-dampers at the same points: CPU time per step, serial timing.

    python studies/baseline.py [--quick] [--repeats 5] [--implementation numpy] [--out DIR]

The baseline models, what replaces the contact and why the comparison is fair are described in
``studies/_lib/baseline.py`` (shared with ``studies/benchmarks.py``, whose ``baseline.csv`` and
report section are the committed version of this table). This script measures the ratio table
alone: every scene of ``RATIO_SCENES`` at the package's and at Exudyn's default solver settings,
ours, the floor (empty callbacks) and the baseline in interleaved repeats in this process (median
CPU time of the solve per step). Writes ``baseline.csv``, ``report.md`` and
``timing.json`` (default ``studies/results/baseline``, which git ignores) and prints the table.
``--quick``: 0.05 s instead of 0.2 s simulated, 3 repeats instead of 5.

``--targets``: only the speed targets (``studies/_lib/targets.py``: each scene at the package's
settings against a cube on as many C++ springs at Exudyn's defaults, with its floor; the compiled
call's fixed and per-point cost), every model solved once per repeat, the repeats interleaved;
0.5 s simulated (``--quick``: 0.05 s, under a minute once the kernels are compiled). Writes
``targets.csv``, ``force_call.csv``, ``report.md`` and prints the table: per scene ours and the
yardstick per step, median [min-max] over the repeats, the ratio formed repeat by repeat (median
[min-max]), the target and whether the median meets it, Newton iterations per step and the floor.
"""
from __future__ import annotations

import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
if HERE not in sys.path:
    sys.path.insert(0, HERE)

from _lib import baseline, target_tables, target_timing  # noqa: E402
from _lib.studylib import Timer, finish, markdown_table, parse_args, sweep, table  # noqa: E402

NAME = "baseline"


def main(argv=None):
    def extra(ap):
        ap.add_argument("--repeats", type=int, default=None, help="timing repeats (default 3 quick, 5 full)")
        ap.add_argument("--implementation", default=None, help="contact kernel passed to BuildBlock/BuildScrew "
                        "(auto | compiled | numpy; default: their default)")
        ap.add_argument("--targets", action="store_true", help="only the speed targets (studies/_lib/targets.py)")
    args = parse_args(NAME, __doc__.splitlines()[0], argv, extra, parallel=False, results_doc=False)
    timer = Timer()
    reps = args.repeats or (3 if args.quick else 5)
    if reps < 1:
        raise SystemExit(f"{NAME}: --repeats must be >= 1; got {reps}")
    if args.targets:
        res = target_timing.measure(args.quick, reps)
        table(os.path.join(args.out, "targets.csv"), target_tables.TARGET_COLUMNS,
              target_tables.target_table_rows(res.rows))
        table(os.path.join(args.out, "force_call.csv"), target_tables.FORCE_CALL_COLUMNS,
              target_tables.force_call_table_rows(res.calls))
        target_tables.print_targets(res.rows)
        finish(args, timer, target_tables.markdown(res), "Speed targets: ours / a cube on C++ springs")
        return 0
    opts = {} if args.implementation is None else {"implementation": args.implementation}
    rows = sweep(baseline.ratio_case, baseline.ratio_cases(args.quick, reps, opts), args)
    table(os.path.join(args.out, "baseline.csv"), baseline.BASE_COLUMNS, baseline.table_rows(rows))
    baseline.print_ratio_table(rows)
    t_end = baseline.ratio_cases(args.quick, reps)[0]["params"]["t_end"]
    body = (f"Median process CPU time of the solve per step over {reps} interleaved repeats, t_end = {t_end} s, "
            "dt = 1e-3 s; the baseline replaces the contact by Exudyn's C++ spring-dampers with our per-point "
            "stiffnesses (our law in pure stick with isotropic adhesion); the floor is that baseline plus the "
            "contact's Exudyn items with user functions that do nothing; settings: the package's (full Newton, "
            "tolerance 1e-10) or Exudyn's defaults (modified Newton, relative tolerance 1e-8). File: `baseline.csv`."
            "\n\n"
            + markdown_table(["scene", "model", "drive", "settings", "K", "ours us/step", "floor us/step",
                              "C++ us/step", "ours/C++", "floor/C++", "Newton/step ours", "Newton/step C++"],
                             [[r["scene"], r["model"], r["drive"], r["settings"], r["K"], r["ours_step_s"] * 1e6,
                               r["floor_step_s"] * 1e6, r["base_step_s"] * 1e6, r["ratio_step"],
                               r["floor_ratio_step"], r["ours_newton_per_step"], r["base_newton_per_step"]]
                              for r in rows]))
    finish(args, timer, body, "Ours / Exudyn C++ spring-dampers")
    return 0


if __name__ == "__main__":
    sys.exit(main())
