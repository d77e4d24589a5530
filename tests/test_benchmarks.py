"""Benchmark, work-precision and C++-baseline studies (studies/benchmarks.py, work_precision.py; the
baseline models of studies/_lib/baseline.py). The scripts run in their quick mode; the assertions
are properties that hold on any machine load: timings positive and finite (the cost model's fit is
checked on synthetic data), errors falling with the step size at second order on a smooth case,
and the C++ baseline equal to our contact where our law is a linear spring (pure stick, isotropic
adhesion). No time bounds."""
from __future__ import annotations

import os
import sys

import numpy as np
import pytest

pytest.importorskip("exudyn")

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "studies"))

from exu_aniso.output import read_table  # noqa: E402


@pytest.fixture(scope="module")
def bench_out(tmp_path_factory, quick_study):
    out = tmp_path_factory.mktemp("benchmarks")
    quick_study("benchmarks", out)
    return out


@pytest.fixture(scope="module")
def wp_out(tmp_path_factory, quick_study):
    out = tmp_path_factory.mktemp("work_precision")
    quick_study("work_precision", out)
    return out


def _positive_finite(values):
    v = np.asarray(values, dtype=float)
    return v.size > 0 and bool(np.all(np.isfinite(v)) and np.all(v > 0))


def test_benchmark_timings_positive_and_finite(bench_out):
    T = read_table(bench_out / "benchmarks.csv")
    assert set(T["status [-]"]) == {"ok"}, T["status [-]"]
    for c in ("cpu_per_step [s]", "cpu_per_sim_second [s/s]", "cpu_per_point_eval [s]", "wall_per_step [s]",
              "cpu_per_step_min [s]",
              "newton_per_step [-]", "relative_to_base [-]"):
        assert _positive_finite(T[c]), c
    assert {"block", "screw"} <= set(T["scene [-]"])
    assert {"exudyn", "reference"} <= set(T["implementation [-]"])
    for factor in ("K", "return_map", "model", "jacobian", "solver"):
        assert factor in T["factor [-]"], factor
    # the step count is deterministic, so per simulated second = per step x steps / t_end exactly,
    # and the fastest repeat is never slower than the median
    for j in range(len(T["K [-]"])):
        assert T["cpu_per_sim_second [s/s]"][j] == pytest.approx(
            T["cpu_per_step [s]"][j] * T["steps [-]"][j] / T["t_end [s]"][j], rel=1e-9)
        assert T["cpu_per_step_min [s]"][j] <= T["cpu_per_step [s]"][j]
    K = read_table(bench_out / "kernel.csv")
    assert _positive_finite(K["per_point [s]"]) and set(K["K [-]"]) == {1.0, 64.0}
    B = read_table(bench_out / "baseline.csv")
    for c in ("ours_per_step [s]", "baseline_per_step [s]", "ours_over_baseline [-]",
              "ours_over_baseline_per_newton [-]"):
        assert _positive_finite(B[c]), c
    assert {("block", "planar"), ("block", "full"), ("screw", "reduced"), ("screw", "full")} <= set(
        zip(B["scene [-]"], B["model [-]"]))
    assert (bench_out / "cost_vs_points.png").stat().st_size > 0
    assert "ours/C++" in (bench_out / "report.md").read_text()
    # the speed targets: every row measured, its ratio the quotient of its medians, met = ratio <= target
    from _lib import targets
    G = read_table(bench_out / "targets.csv")
    assert G["scene [-]"] == [label for label, _, _, _ in targets.TARGETS]
    for c in ("ours_per_step [us]", "yardstick_per_step [us]", "ratio [-]", "ours_newton_per_step [-]"):
        assert _positive_finite(G[c]), c
    for o, y, r, t, met in zip(G["ours_per_step [us]"], G["yardstick_per_step [us]"], G["ratio [-]"],
                               G["target [-]"], G["met [-]"]):
        assert r == pytest.approx(o / y, rel=1e-9) and str(met) == str(r <= t)
    assert "Speed targets" in (bench_out / "report.md").read_text()


def test_target_yardstick_is_a_cube_on_springs():
    """The yardstick of the speed targets (studies/_lib/targets.py) is the model it claims: a cube on
    K C++ springs (eps_1/K in x, y, eps_n/K in z) carrying the normal load N, under a constant force
    (P, P/2, -N) and gravity, released from the position where the springs carry N. It sinks by
    m g / eps_n on average (released, it swings between 0 and twice that); in the plane it sways
    about a displacement of the order of P/eps_1 (the force acts above the springs, so the cube also
    tilts: measured mean 1.14 P/eps_1 in x), proportional to P up to the geometric stiffness of the
    preload (twice P: twice the sway to 5 %)."""
    from _lib import targets
    from exu_aniso.scenes import BlockParams
    p = BlockParams(model="full")
    for K in (4, 24, 64):
        pts = targets.cube_points(K, p.size)
        assert pts.shape == (K, 3) and len({tuple(b) for b in pts}) == K
        assert np.all(np.abs(pts[:, :2]) <= 0.5 * p.size + 1e-15) and np.all(pts[:, 2] == -0.5 * p.size)
    runs = []
    for P in (p.force, 2 * p.force):
        m = targets.BuildCube(24, 0.2, 1e-3, p.with_overrides(force=P))
        assert m["mbs"].SolveDynamic(m["simulationSettings"], solverType=m["solverType"])
        runs.append(m["mbs"].GetSensorStoredData(0))
    u1, u2 = (X[:, 1:3] - [p.x0, p.y0] for X in runs)
    static = p.force / p.eps_1
    np.testing.assert_allclose(u2, 2 * u1, rtol=0, atol=0.05 * np.abs(u2).max())
    assert 0.5 * static < np.mean(u1[:, 0]) < 2.0 * static
    sink = runs[0][0, 3] - runs[0][:, 3]
    assert 0.5 < np.mean(sink) / (9.81 * p.mass / p.eps_n) < 2.0
