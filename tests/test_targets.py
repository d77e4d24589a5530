"""The speed-target machinery (studies/_lib/targets.py, timed by target_timing.py, tabled by
target_tables.py, its user's body in target_models.py; ``python studies/baseline.py --targets``): the
table has one row per declared target with its spread, ratios formed repeat by repeat, and the
compiled call's fit over its point layouts. Structure only: no speed is checked (timings flake on a
busy machine)."""
from __future__ import annotations

import math
import os
import sys

import numpy as np
import pytest

pytest.importorskip("exudyn")

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "studies"))

from exu_aniso.util.output import read_table  # noqa: E402
from _suite import HANG_S


def _positive_finite(values):
    v = np.asarray(values, dtype=float)
    return v.size > 0 and bool(np.all(np.isfinite(v)) and np.all(v > 0))


def test_targets_declared():
    """TARGETS is declarative (label, ours, yardstick, target) and covers every target of the brief."""
    from _lib import targets
    labels = [t.label for t in targets.TARGETS]
    assert len(set(labels)) == len(labels)
    for t in targets.TARGETS:
        label, build, yardstick, target = t
        assert target is None or target > 0          # None: a row that explains another
        assert target is not None or not isinstance(build, targets.CallFit)
        if isinstance(build, targets.CallFit):
            assert yardstick is None and build.part in ("fixed", "per_point")
        else:
            assert isinstance(build, targets.Run) and isinstance(yardstick, (targets.Run, targets.PerBody))
            assert build.floor is None or build.cube is not None
    goals = {t.label: t.target for t in targets.TARGETS}
    assert goals["full block, 4 corners"] == 3.0 and goals["full block, 8 x 8 grid"] == 0.6
    assert goals["64 cubes, one contact set each"] == goals["64 cubes, one group"] == 3.0
    assert goals["reduced screw (default ScrewParams)"] == 1.2
    assert goals["moving master (full block, 4 corners, on a free plate)"] == 1.2
    assert goals["moving master against the same two bodies with the contact on the fixed plane"] == 1.2
    assert goals["compiled call on the plane, as Exudyn makes it: fixed part [us]"] == 0.5
    assert goals["compiled call on the plane, as Exudyn makes it: per point [us]"] == 0.05
    assert [K for K in (1, 4, 16, 64, 256)] == [
        {"center": 1, "corners": 4}.get(p) or int(p.split(":")[1]) ** 2 for p in targets.CALL_LAYOUTS]
    # every model is timed once per repeat, however many rows use it
    names = [r.name for r in targets.runs_of(targets.TARGETS)]
    assert len(names) == len(set(names))


def test_row_ratio_formed_repeat_by_repeat():
    """A ratio is the median of ours_i / yardstick_i (not the ratio of medians), with min and max;
    per-body rows divide by the bodies; met compares the median ratio with the target."""
    from _lib import target_tables, target_timing, targets
    a = targets.Run("a", None, floor=targets.Run("fa", None), cube=targets.Run("c", None))
    b = targets.Run("b", None, bodies=8)
    big = targets.Run("a64", None, bodies=64)
    T = {"a": [1.0, 2.0, 10.0], "b": [1.0, 4.0, 2.0], "fa": [0.5, 0.5, 0.5], "c": [0.25, 0.25, 0.25],
         "a64": [8.0, 16.0, 8.0]}
    T = {k: np.column_stack([v, v, [10] * 3, [30, 30, 40]]) for k, v in T.items()}
    row = target_timing._row(targets.Target("x", a, b, 2.0), T, 10, 0.01, 3, None)
    assert row["ratio"] == pytest.approx(1.0) and (row["ratio_min"], row["ratio_max"]) == (0.5, 5.0)
    assert row["ours_us"] == pytest.approx(2e5) and row["yardstick_us"] == pytest.approx(2e5)
    assert row["met"] and row["ours_newton"] == 3.0
    assert row["ours_minus_floor_us"] == pytest.approx(1.5e5)
    assert row["floor_minus_cube_us"] == pytest.approx(2.5e4)
    # per body: (8, 16, 8) / 64 over (1, 4, 2) / 8 = 1, 0.5, 0.5
    per = target_timing._row(targets.Target("y", big, targets.PerBody(b), 1.2), T, 10, 0.01, 3, None)
    assert per["unit"] == "us/body/step" and per["ratio"] == pytest.approx(0.5)
    assert per["ratio_max"] == pytest.approx(1.0) and per["ours_us"] == pytest.approx(8.0 / 64 / 10 * 1e6)
    # a row without a target: the same figures, "met" neither yes nor no
    plain = target_timing._row(targets.Target("z", a, b, None), T, 10, 0.01, 3, None)
    assert plain["met"] is None and math.isnan(plain["target"]) and plain["ratio"] == pytest.approx(1.0)
    assert target_tables._cells(plain)[5:7] == ["-", "-"]


def test_user_body_rests_on_four_corners():
    """The user's box starts with its 4 corners at the static penetration m g / (4 eps_N) on the
    sphere's inside and the cone's inside (each corner's distance to the surface)."""
    from _lib import target_models
    pen = target_models.USER_MASS * 9.81 / (4 * target_models.USER_NORMAL_STIFFNESS)
    for surface in ("sphere", "cone"):
        x0, A, local, surf = target_models.user_body_pose(surface)
        X = np.asarray(x0) + local @ np.asarray(A).T
        if surface == "sphere":
            C = np.array([0.0, 0.0, target_models.BOWL_RADIUS])
            depth = np.linalg.norm(X - C, axis=1) - target_models.BOWL_RADIUS
        else:
            ha, R0 = target_models.TROUGH_HALF_ANGLE, target_models.TROUGH_RADIUS
            rho = np.hypot(X[:, 1], X[:, 2] - R0)
            depth = (rho - (R0 + X[:, 0] * math.tan(ha))) * math.cos(ha)
        np.testing.assert_allclose(depth, pen, rtol=1e-6)
        assert type(surf).__name__ == {"sphere": "Sphere", "cone": "Cone"}[surface] and surf.side == "inside"


def test_targets_quick_run(tmp_path, quick_study):
    """``python studies/baseline.py --targets --quick --repeats 2``: every target a row with finite,
    positive figures and spreads that bracket the medians; ratio rows finite and positive; met
    consistent with the median; the compiled call measured on K = 1 to 256 points, all in contact."""
    from _lib import targets
    quick_study("baseline", tmp_path, timeout=HANG_S, args=("--targets", "--repeats", "2"))
    G = read_table(tmp_path / "targets.csv")
    assert G["scene [-]"] == [t.label for t in targets.TARGETS]
    assert set(G["repeats [-]"]) == {2.0}
    for j, kind in enumerate(G["kind [-]"]):
        o, lo, hi = G["ours [us]"][j], G["ours_min [us]"][j], G["ours_max [us]"][j]
        assert math.isfinite(o) and lo <= o <= hi, (G["scene [-]"][j], lo, o, hi)
        untargeted = not math.isfinite(G["target [-]"][j])      # a row that explains another
        assert str(G["met [-]"][j]) == "None" if untargeted else str(G["met [-]"][j]) in ("True", "False")
        if kind == "ratio":
            assert o > 0
            for c in ("yardstick_per_step [us]", "ratio [-]", "ratio_min [-]", "ratio_max [-]",
                      "ours_newton_per_step [-]", "yardstick_newton_per_step [-]", "ours_wall [us]"):
                assert _positive_finite([G[c][j]]), (G["scene [-]"][j], c)
            r = G["ratio [-]"][j]
            assert G["ratio_min [-]"][j] <= r <= G["ratio_max [-]"][j]
            assert untargeted or str(G["met [-]"][j]) == str(r <= G["target [-]"][j])
        else:
            assert kind == "absolute" and str(G["met [-]"][j]) == str(o <= G["target [-]"][j])
    floors = [j for j, f in enumerate(G["floor_model [-]"]) if f]
    assert floors and _positive_finite([G["floor [us]"][j] for j in floors])
    C = read_table(tmp_path / "force_call.csv")
    assert C["K [-]"] == [1.0, 4.0, 16.0, 64.0, 256.0] and C["in_contact [-]"] == C["K [-]"]
    assert _positive_finite(C["callback [us]"]) and _positive_finite(C["entry [us]"])
    report = (tmp_path / "report.md").read_text()
    assert "ratio median [min-max]" in report and "compiled call" in report
