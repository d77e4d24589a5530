"""Kernel cost: per-point return map with plain floats versus all points at once with numpy.

    python studies/bench_kernels.py [--repeats 7] [--out studies/results/bench_kernels.json]

Prints, per return map and number of points K, the median wall time of one evaluation (with
tangent) over the repeats for (a) a Python loop calling ``return_map_point`` K times, (b) one
vectorised ``return_map_batch`` call, their ratio measured in the same run, (c) the automatic
choice ``return_map_batch(..., vectorize=None)`` the contact set uses; and the cost of one full
contact-set evaluation ``ContactLaw.evaluate`` (projection + fields + law + tangent) per point.
"""
from __future__ import annotations

import argparse
import json
import os
import platform
import tempfile
import time

import numpy as np

from exu_aniso import Adhesion, ContactLaw, Friction, Plane, RETURN_MAPS, return_map_batch, return_map_point


def _median_time(fn, repeats, inner):
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        for _ in range(inner):
            fn()
        times.append((time.perf_counter() - t0) / inner)
    return float(np.median(times))


def slipping_inputs(K, rng):
    F = np.tile([1 / 0.2**2, 0.0, 1 / 0.6**2], (K, 1))
    B = np.tile([-1e4, 0.0, -3e3], (K, 1))
    T_tr = rng.normal(size=(K, 2)) * 10.0
    return T_tr, np.ones(K), B, F


def run(repeats=7, sizes=(1, 4, 16, 64)):
    rng = np.random.default_rng(0)
    rows = []
    for method in RETURN_MAPS:
        for K in sizes:
            T_tr, N, B, F = slipping_inputs(K, rng)
            pts = [(tuple(T_tr[k]), float(N[k]), tuple(B[k]), tuple(F[k])) for k in range(K)]
            inner = max(1, 400 // K)
            t_point = _median_time(lambda: [return_map_point(*p, method) for p in pts], repeats, inner)
            t_batch = _median_time(lambda: return_map_batch(T_tr, N, B, F, method, vectorize=True), repeats, inner)
            t_auto = _median_time(lambda: return_map_batch(T_tr, N, B, F, method), repeats, inner)
            rows.append({"kernel": "return_map", "map": method, "K": K, "point_loop_s": t_point,
                         "batch_s": t_batch, "batch_over_point": t_batch / t_point, "auto_s": t_auto})
    law = ContactLaw(Plane("polar"), Adhesion.polar(1e4, 1e3, 1e-3), Friction.polar(0.2, 0.6, 1e-3), 1e6)
    for K in sizes:
        x = np.c_[rng.uniform(0.2, 1.0, (K, 2)), -1e-5 * np.ones(K)]
        H = law.initial_history(K)
        H[:, 2:4] = x[:, :2] - 1e-3
        H[:, 4] = 1.0
        t = _median_time(lambda: law.evaluate(x, None, H), repeats, max(1, 200 // K))
        rows.append({"kernel": "contact_set", "map": law.return_map, "K": K, "batch_s": t, "per_point_s": t / K})
    return rows


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=7)
    ap.add_argument("--out", default=os.path.join(os.path.dirname(__file__), "results", "bench_kernels.json"))
    a = ap.parse_args(argv)
    rows = run(a.repeats)
    print(f"{'kernel':12s} {'map':7s} {'K':>3s} {'point loop [us]':>16s} {'numpy [us]':>11s} "
          f"{'numpy/loop':>11s} {'auto [us]':>10s}")
    for r in rows:
        if r["kernel"] == "return_map":
            print(f"{r['kernel']:12s} {r['map']:7s} {r['K']:3d} {r['point_loop_s'] * 1e6:16.1f} "
                  f"{r['batch_s'] * 1e6:11.1f} {r['batch_over_point']:11.2f} {r['auto_s'] * 1e6:10.1f}")
        else:
            print(f"{r['kernel']:12s} {r['map']:7s} {r['K']:3d} {'':16s} {r['batch_s'] * 1e6:11.1f} "
                  f"   ({r['per_point_s'] * 1e6:.1f} us per point)")
    os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)
    meta = {"machine": platform.machine(), "cpus": os.cpu_count(), "python": platform.python_version(),
            "numpy": np.__version__, "date": time.strftime("%Y-%m-%d"), "repeats": a.repeats}
    fd, tmp = tempfile.mkstemp(dir=os.path.dirname(os.path.abspath(a.out)), suffix=".tmp")
    with os.fdopen(fd, "w") as f:
        json.dump({"meta": meta, "rows": rows}, f, indent=1)
    os.replace(tmp, a.out)
    print(f"wrote {a.out}")


if __name__ == "__main__":
    main()
