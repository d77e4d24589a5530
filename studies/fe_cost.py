"""The cost of a finite-element body: a step that refreshes the floating-frame body's Jacobian,
measured against the estimate the finite-element scenes check before they build anything
(``exu_aniso.fe.cost``).

    python studies/fe_cost.py [--quick] [--out DIR]

Each case is the elastic block (``exu-aniso run fe_block``) pressed within one step (t_press = dt =
1 ms, drive_ramp 0), a press so abrupt that Newton refreshes the Jacobian in the steps after it, run
for 3 and for 9 steps in this process; the per-step figure is the difference of the two runs' solve
time over the difference of their steps (model building, the basis and the first step cancel). Beside
it: the estimate ``exu_aniso.fe.cost.refresh_seconds(nodes, modes)`` and their ratio. Cases: the
bottom nodes' static modes (the default basis) on 3 to 7 cells and with 100 eigenmodes besides on 6
cells, the full mesh on 4 cells, eigenmodes alone (30 and 200) on 6 cells; quick: 3 and 4 cells. Writes ``fe_cost.csv`` and
``report.md`` (default ``studies/results/fe_cost``).
"""
from __future__ import annotations

import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
if HERE not in sys.path:
    sys.path.insert(0, HERE)
from _lib.studylib import Timer, finish, markdown_table, parse_args, table  # noqa: E402

NAME = "fe_cost"
CASES = ([dict(cells=c) for c in (3, 4, 5, 6, 7)]
         + [dict(cells=6, modes=100), dict(cells=4, model="full")]
         + [dict(cells=6, basis="eigenmodes", modes=m) for m in (30, 200)])
QUICK = [dict(cells=3), dict(cells=4)]
COLUMNS = ["case [-]", "nodes [-]", "modes [-]", "per_step [s]", "estimate [s]", "estimate_ratio [-]",
           "newton_per_step [-]"]
SHORT, LONG = 3, 9


def run(case, steps):
    """The solve's wall time [s], its steps and Newton iterations for fe_block with case's parameters."""
    from exu_aniso.models.fe_block import RunFeBlock
    from exu_aniso.scenes.fe_block import FeBlockParams
    p = FeBlockParams(t_press=1e-3, drive_ramp=0.0, t_end=steps * 1e-3, **case)
    s = RunFeBlock(p).summary
    return s["wall_s"], s["steps"], s["newton_iterations"], p


def measure(cases):
    from exu_aniso.fe.cost import refresh_seconds
    rows = []
    for case in cases:
        w0, s0, n0, p = run(case, SHORT)
        w1, s1, n1, _ = run(case, LONG)
        nodes, modes = (p.cells + 1) ** 3, p.body_modes()
        per_step = (w1 - w0) / (s1 - s0)
        estimate = refresh_seconds(nodes, modes)
        rows.append([" ".join(f"{k}={v}" for k, v in case.items()), nodes, modes, per_step, estimate,
                     estimate / per_step, (n1 - n0) / (s1 - s0)])
        print(f"{NAME}: {rows[-1][0]}: {per_step:.3g} s per step, estimate {estimate:.3g} s", file=sys.stderr)
    return rows


def main(argv=None):
    args = parse_args(NAME, __doc__.splitlines()[0], argv, parallel=False, results_doc=False)
    timer = Timer()
    rows = measure(QUICK if args.quick else CASES)
    table(os.path.join(args.out, f"{NAME}.csv"), COLUMNS, rows)
    body = ("Per step after the abrupt press (the solve's wall time of 9 steps less 3 steps, over 6 steps), "
            "the estimate of a step that refreshes the Jacobian (exu_aniso.fe.cost) and their ratio:\n\n"
            + markdown_table(COLUMNS, rows, fmt="{:.3g}"))
    finish(args, timer, body, "The cost of a finite-element body")
    return 0


if __name__ == "__main__":
    sys.exit(main())
