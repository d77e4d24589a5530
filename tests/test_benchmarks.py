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

from exu_aniso.util.output import read_table  # noqa: E402


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
    # the speed targets and the compiled call: their structure is tests/test_targets.py's; here, that
    # this run wrote them
    from _lib import targets
    G = read_table(bench_out / "targets.csv")
    assert G["scene [-]"] == [t.label for t in targets.TARGETS]
    assert "Speed targets" in (bench_out / "report.md").read_text()
    assert (bench_out / "force_call.csv").stat().st_size > 0
    # scale: every (M, variant) measured; a group calls Exudyn's force callback once per
    # residual (M per residual for one set per body: counted, not assumed); memory of fresh processes
    S = read_table(bench_out / "scale.csv")
    assert sorted(set(S["contact [-]"])) == ["empty", "group", "sets", "springs"]
    assert _positive_finite(S["per_body_per_step [us]"]) and _positive_finite(S["ratio_to_springs [-]"])
    for M, c, f in zip(S["bodies [-]"], S["contact [-]"], S["force_calls_per_newton [-]"]):
        if c in ("sets", "group"):
            per_residual = f * (1.0 if c == "group" else 1.0 / M)
            assert 1.0 < per_residual < 2.0, (M, c, f)     # one call per residual, plus the initial ones
    Mem = read_table(bench_out / "memory.csv")
    assert _positive_finite(Mem["peak [MB]"]) and all(p >= b for p, b in zip(Mem["peak [MB]"], Mem["after_build [MB]"]))
    # the long run: ours, the C++ springs at both settings and the floor, the same steps each
    L = read_table(bench_out / "long_run.csv")
    assert list(zip(L["model [-]"], L["settings [-]"])) == [("ours", "ours"), ("C++ springs", "exudyn"),
                                                            ("C++ springs", "ours"), ("floor", "ours")]
    assert _positive_finite(L["cpu [s]"]) and _positive_finite(L["ours_over_this [-]"])
    assert len(set(L["steps [-]"])) == 1 and "A long run" in (bench_out / "report.md").read_text()


def test_the_long_runs_yardstick_is_a_shaken_nut_on_springs():
    """The long run's yardstick (studies/_lib/long_run.py) is the model it claims: no item of it has a
    Python user function, and over two cycles its nut follows the driver's D sin(2 pi f t) by the springs
    in series, k_drag / (k_drag + 2 k_stick) of it: its largest shift within 5 %, and at every step
    within 10 % of that amplitude (the shaker's spring detunes the heavy driver by drag_stiffness /
    (DRIVER_MASS (2 pi f)^2), 1.6 %, which shifts its phase by 0.1 rad over two cycles)."""
    from _lib import long_run
    p = long_run.joint_params(2)
    m = long_run.BuildShakenNut(p, "ours")
    mbs = m["mbs"]
    for kind, count, get in (("object", mbs.systemData.NumberOfObjects(), mbs.GetObject),
                             ("load", mbs.systemData.NumberOfLoads(), mbs.GetLoad)):
        for i in range(count):
            functions = {k: v for k, v in get(i).items() if k.endswith("UserFunction") and v != 0}
            assert not functions, (kind, i, functions)
    assert mbs.SolveDynamic(m["simulationSettings"], solverType=m["solverType"])
    X = mbs.GetSensorStoredData(0)
    t = X[:, 0]
    D = p.shake_displacement
    share = p.drag_stiffness / (p.drag_stiffness + 2.0 * p.sticking_stiffness)
    assert np.max(np.abs(X[:, 1])) == pytest.approx(share * D, rel=5e-2)
    assert np.max(np.abs(X[:, 1] - share * D * np.sin(2 * np.pi * p.shake_frequency * t))) < 0.1 * share * D


def test_target_yardstick_is_a_cube_on_springs():
    """The yardstick of the speed targets (studies/_lib/yardstick.py) is the model it claims: a cube on
    K C++ springs (eps_1/K in x, y, eps_n/K in z) carrying the normal load N, under a constant force
    (P, P/2, -N) and gravity, released from the position where the springs carry N. It sinks by
    m g / eps_n on average (released, it swings between 0 and twice that); in the plane it sways
    about a displacement of the order of P/eps_1 (the force acts above the springs, so the cube also
    tilts: measured mean 1.14 P/eps_1 in x), proportional to P up to the geometric stiffness of the
    preload (twice P: twice the sway to 5 %)."""
    from _lib import yardstick
    from exu_aniso.scenes.block import BlockParams
    p = BlockParams(model="full")
    for K in (4, 24, 64):
        pts = yardstick.cube_points(K, p.size)
        assert pts.shape == (K, 3) and len({tuple(b) for b in pts}) == K
        assert np.all(np.abs(pts[:, :2]) <= 0.5 * p.size + 1e-15) and np.all(pts[:, 2] == -0.5 * p.size)
    runs = []
    for P in (p.force, 2 * p.force):
        m = yardstick.BuildCube(24, 0.2, 1e-3, p.with_overrides(force=P))
        assert m["mbs"].SolveDynamic(m["simulationSettings"], solverType=m["solverType"])
        runs.append(m["mbs"].GetSensorStoredData(0))
    u1, u2 = (X[:, 1:3] - [p.x0, p.y0] for X in runs)
    static = p.force / p.eps_1
    np.testing.assert_allclose(u2, 2 * u1, rtol=0, atol=0.05 * np.abs(u2).max())
    assert 0.5 * static < np.mean(u1[:, 0]) < 2.0 * static
    sink = runs[0][0, 3] - runs[0][:, 3]
    assert 0.5 < np.mean(sink) / (9.81 * p.mass / p.eps_n) < 2.0


def test_linear_fit_recovers_a_line():
    """The benchmark's cost model cost = a + b K (printed by studies/benchmarks.py, never asserted on
    timings: timed tests flake on a busy machine) recovers a known line exactly and R^2 = 1."""
    import benchmarks
    K = np.array([1.0, 4.0, 16.0, 64.0])
    a, b, r2 = benchmarks.linear_fit(K, 3e-5 + 2.5e-6 * K)
    assert a == pytest.approx(3e-5, rel=1e-9) and b == pytest.approx(2.5e-6, rel=1e-9)
    assert r2 == pytest.approx(1.0, abs=1e-12)
    _, _, r2_noise = benchmarks.linear_fit(K, np.array([1.0, -1.0, 1.0, -1.0]))
    assert r2_noise < 0.5


def test_work_precision_errors_fall_with_dt(wp_out):
    """Converging settings (every map but seed, both solvers, both models): the error against the fine
    solution falls at every halving of dt; the seed map is exempt (its sliding depends on dt)."""
    T = read_table(wp_out / "work_precision.csv")
    assert set(T["status [-]"]) == {"ok"}
    assert _positive_finite(T["cpu [s]"]) and _positive_finite(T["cpu_per_step [s]"])
    O = read_table(wp_out / "orders.csv")
    fams = dict(zip(O["family [-]"], range(len(O["family [-]"]))))
    converging = ["block exudyn", "block exact", "block generalized_alpha", "block full", "block oracle harmonic",
                  "screw exudyn", "screw exact", "screw generalized_alpha", "screw full",
                  "block full_newton", "screw full_newton"]
    for f in converging:
        j = fams[f]
        assert O["decreasing [-]"][j] == "yes", f
        assert O["observed_order [-]"][j] > 1.0, (f, O["observed_order [-]"][j])
    assert (wp_out / "work_precision.png").stat().st_size > 0


def test_work_precision_smooth_case_second_order(wp_out):
    """Trapezoidal rule on the smooth oracle (isotropic stick, spring drive = forced oscillator):
    observed order > 1 against the analytic solution (2 expected) and the error at the smallest step
    below 1e-3 relative."""
    O = read_table(wp_out / "orders.csv")
    j = O["family [-]"].index("block oracle harmonic")
    print(f"harmonic oracle: order {O['oracle_order [-]'][j]:.3f}, error {O['oracle_error_rel_at_dt_min [-]'][j]:.2e}")
    assert O["oracle_order [-]"][j] > 1.5
    assert O["oracle_error_rel_at_dt_min [-]"][j] < 1e-3
    T = read_table(wp_out / "work_precision.csv")
    idx = [i for i in range(len(T["dt [s]"])) if T["family [-]"][i] == "block oracle coulomb"]
    # constant acceleration: the trapezoidal rule reproduces (P - mu m g)/m to round-off
    assert max(T["oracle_error_rel [-]"][i] for i in idx) < 1e-9


# ----------------------------------------------------------------------------------------------
# the C++ baseline is our law in pure stick with isotropic adhesion

STICK = dict(adhesion="isotropic", friction="isotropic", mu_1=50.0, eps_1=1e4)


@pytest.mark.parametrize("model", ["planar", "full"])
def test_baseline_block_equals_contact_in_stick(model):
    """Isotropic adhesion, every point sticking (mu = 50, pull 1 N < tipping): our contact is a linear
    spring per point, anchored at the initial contact point, and the C++ CartesianSpringDamper model
    gives the same trajectory to Newton tolerance (same solver, same steps)."""
    from _lib import baseline
    from exu_aniso.models.block import RunBlock
    from exu_aniso.scenes.block import BlockParams
    p = BlockParams(model=model, t_end=0.1, dt=1e-3, drive="force", force=1.0, drive_angle=30.0, points="corners",
                    **STICK)
    ours = RunBlock(p)
    m, cpu, steps, _ = baseline.RunBaseline("block", p)
    assert steps == ours.summary["steps"] == 100 and cpu > 0
    assert ours.summary["slip_distance"] == 0.0          # pure stick: the law is linear
    Q = baseline.BaselineTrajectory(m)
    tr = ours.trajectory
    if model == "planar":
        a = np.column_stack([Q[:, 1] + p.x0, Q[:, 2] + p.y0])
        rot = np.max(np.abs(Q[:, 3] - tr["theta"]))
    else:
        a = Q[:, 1:3]
        rot = np.max(np.abs(Q[:, 3] - tr["z"]))          # height (normal spring)
    b = np.column_stack([tr["x"], tr["y"]])
    moved = np.max(np.linalg.norm(b - b[0], axis=1))
    err = np.max(np.linalg.norm(a - b, axis=1))
    print(f"block {model}: moved {moved:.3e} m, max difference {err:.2e} m, theta/z {rot:.2e}")
    assert moved > 1e-5
    assert err < 1e-9 * moved + 1e-15 and rot < 1e-12


@pytest.mark.parametrize("symmetry", [True, False])
def test_baseline_reduced_screw_equals_contact_in_stick(symmetry):
    """Reduced screw turned by the rotation drive, isotropic stick: torque -eps/K R^2 psi per
    point is exactly linear in psi, so the coordinate springs reproduce our run (0.5 rad turned),
    with one representative point (lumped spring pair) or all 24 points (a pair per point)."""
    from _lib import baseline
    from exu_aniso.models.screw import RunScrew
    from exu_aniso.scenes.screw import ScrewParams
    p = ScrewParams(model="reduced", t_end=0.1, dt=1e-3, drive="rotation", **STICK)
    ours = RunScrew(p, contactOutputs=False, symmetry=symmetry)
    m, _, steps, _ = baseline.RunBaseline("screw", p, symmetry=symmetry)
    assert len(m["springs"]) == (2 if symmetry else 48)
    assert ours.trajectory["slip_distance"][-1] == 0.0 and steps == ours.summary["steps"]
    Q = baseline.BaselineTrajectory(m)
    tr = ours.trajectory
    turned = np.max(np.abs(tr["angle"]))
    print(f"screw reduced: turned {turned:.3f} rad, difference {np.max(np.abs(Q[:, 1] - tr['angle'])):.2e} rad")
    assert turned > 0.1
    np.testing.assert_allclose(Q[:, 1], tr["angle"], rtol=0, atol=1e-10 * turned)
    np.testing.assert_allclose(Q[:, 2], tr["z"], rtol=0, atol=1e-15)


def test_baseline_argument_errors():
    from _lib import baseline
    from exu_aniso.scenes.block import BlockParams
    from exu_aniso.scenes.screw import ScrewParams
    with pytest.raises(ValueError, match="nodeType"):
        baseline.BuildBlockBaseline(BlockParams(), nodeType="bad")
    with pytest.raises(ValueError, match="drive 'rotation'"):
        baseline.BuildScrewBaseline(ScrewParams(model="full", drive="rotation"))


def test_a_fresh_processes_peak_memory_is_its_own():
    """The memory rows' child process reports its own peak, not its parent's: started from a parent
    that holds 400 MB more, the child's figure for a small model stays below the parent's size
    (getrusage's ru_maxrss kept the forked parent's peak; VmHWM starts afresh at exec)."""
    import resource

    from _lib import scale
    if not os.path.exists("/proc/self/status"):
        pytest.skip("no /proc: the peak comes from ru_maxrss")
    ballast = np.ones(50_000_000)                           # 400 MB, touched
    parent = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    m = scale.peak_memory(1, "corners", 5, False)
    assert ballast[-1] == 1.0 and parent > 400.0
    assert 0.0 < m["built_mb"] <= m["peak_mb"] < parent - 300.0, (m, parent)
