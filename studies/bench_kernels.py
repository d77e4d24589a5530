"""Kernel cost: the compiled return map called point by point from Python versus one batch call.

    python studies/bench_kernels.py [--quick] [--repeats 7] [--out DIR]

Prints, per return map and number of points K, the median wall time of one evaluation (with
tangent) over the repeats for (a) a Python loop calling ``return_map_point`` K times (input
checks and one compiled call each), (b) one ``return_map_batch`` call (one compiled loop), their
ratio measured in the same run; and the cost of one full contact-set evaluation
``ContactLaw.evaluate`` (projection + nets + law + tangent, the covariant kernel) per point.

Writes ``bench_kernels.json`` (meta and rows), ``bench_kernels.csv``, ``report.md`` and
``timing.json`` into ``--out`` (default ``studies/results/bench_kernels``, which git ignores; the
figures quoted in README.md come from a full run). Timings are taken in this process, one after
the other (``--processes`` and ``--mpi`` are refused). ``--quick``: K = 1 and 16 only, 3 repeats,
a quarter of the calls per repeat (about a second).
"""
from __future__ import annotations

import os
import platform
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
if HERE not in sys.path:
    sys.path.insert(0, HERE)

from _lib.studylib import Timer, finish, markdown_table, median_call_time, parse_args, table, write_json  # noqa: E402

from exu_aniso import Adhesion, ContactLaw, Friction, Plane, RETURN_MAPS, return_map_batch, return_map_point  # noqa: E402

NAME = "bench_kernels"


def slipping_inputs(K, rng):
    F = np.tile([1 / 0.2**2, 0.0, 1 / 0.6**2], (K, 1))
    B = np.tile([-1e4, 0.0, -3e3], (K, 1))
    T_tr = rng.normal(size=(K, 2)) * 10.0
    return T_tr, np.ones(K), B, F


def run(repeats=7, sizes=(1, 4, 16, 64), calls=400):
    """Rows of the table; ``calls``: evaluations per repeat of a single point (K points: calls / K)."""
    rng = np.random.default_rng(0)
    rows = []
    for method in RETURN_MAPS:
        for K in sizes:
            T_tr, N, B, F = slipping_inputs(K, rng)
            pts = [(tuple(T_tr[k]), float(N[k]), tuple(B[k]), tuple(F[k])) for k in range(K)]
            inner = max(1, calls // K)
            t_point = median_call_time(lambda: [return_map_point(*p, method) for p in pts], repeats, inner)
            t_batch = median_call_time(lambda: return_map_batch(T_tr, N, B, F, method), repeats, inner)
            rows.append({"kernel": "return_map", "map": method, "K": K, "point_loop_s": t_point,
                         "batch_s": t_batch, "batch_over_point": t_batch / t_point})
    law = ContactLaw(Plane(), Adhesion.polar(1e4, 1e3, 1e-3), Friction.polar(0.2, 0.6, 1e-3), 1e6)
    for K in sizes:
        x = np.c_[rng.uniform(0.2, 1.0, (K, 2)), -1e-5 * np.ones(K)]
        H = law.initial_history(K)
        H[:, 2:4] = x[:, :2] - 1e-3
        H[:, 4] = 1.0
        t = median_call_time(lambda: law.evaluate(x, None, H), repeats, max(1, calls // 2 // K))
        rows.append({"kernel": "contact_set", "map": law.return_map, "K": K, "batch_s": t, "per_point_s": t / K})
    return rows


CSV_COLUMNS = ["kernel [-]", "map [-]", "K [-]", "point_loop [s]", "batch [s]", "batch_over_loop [-]",
               "batch_per_point [s]"]


def main(argv=None):
    args = parse_args(NAME, __doc__.splitlines()[0], argv,
                      extra=lambda ap: ap.add_argument("--repeats", type=int, default=None,
                                                       help="timing repeats (default 7; --quick: 3)"),
                      parallel=False, results_doc=False)
    timer = Timer()
    repeats = args.repeats or (3 if args.quick else 7)
    if repeats < 1:
        raise SystemExit(f"{NAME}: --repeats must be >= 1; got {repeats}")
    sizes, calls = ((1, 16), 100) if args.quick else ((1, 4, 16, 64), 400)
    rows = run(repeats, sizes, calls)
    print(f"{'kernel':12s} {'map':7s} {'K':>3s} {'point loop [us]':>16s} {'batch [us]':>11s} "
          f"{'batch/loop':>11s}")
    for r in rows:
        if r["kernel"] == "return_map":
            print(f"{r['kernel']:12s} {r['map']:7s} {r['K']:3d} {r['point_loop_s'] * 1e6:16.1f} "
                  f"{r['batch_s'] * 1e6:11.1f} {r['batch_over_point']:11.2f}")
        else:
            print(f"{r['kernel']:12s} {r['map']:7s} {r['K']:3d} {'':16s} {r['batch_s'] * 1e6:11.1f} "
                  f"   ({r['per_point_s'] * 1e6:.1f} us per point)")
    meta = {"machine": platform.machine(), "cpus": os.cpu_count(), "python": platform.python_version(),
            "numpy": np.__version__, "date": time.strftime("%Y-%m-%d"), "repeats": repeats, "quick": bool(args.quick)}
    write_json(os.path.join(args.out, f"{NAME}.json"), {"meta": meta, "rows": rows})
    nan = float("nan")
    csv_rows = [[r["kernel"], r["map"], r["K"], r.get("point_loop_s", nan), r["batch_s"], r.get("batch_over_point", nan),
                 r.get("per_point_s", r["batch_s"] / r["K"])] for r in rows]
    table(os.path.join(args.out, f"{NAME}.csv"), CSV_COLUMNS, csv_rows)
    def us(v):
        return "-" if v != v else v * 1e6
    body = (f"Median wall time of one evaluation with tangent over {repeats} repeats (`return_map`: a Python loop "
            "of `return_map_point`, one `return_map_batch`; `contact_set`: one `ContactLaw.evaluate`, polar "
            "fields). Files: `bench_kernels.csv`, `bench_kernels.json`.\n\n"
            + markdown_table(["kernel", "map", "K", "point loop [us]", "batch [us]", "batch / loop",
                              "batch per point [us]"],
                             [c[:3] + [us(c[3]), us(c[4]), "-" if c[5] != c[5] else c[5], us(c[6])]
                              for c in csv_rows]))
    finish(args, timer, body, "Law kernels: per-point calls against one batch call")
    return 0


if __name__ == "__main__":
    sys.exit(main())
