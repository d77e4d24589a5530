"""The block-path and return-map studies, run in quick mode: physical properties of their CSV output.

Bounds come from the full runs committed in docs/results/block_paths and docs/results/return_maps
(`python studies/block_paths.py`, `python studies/return_maps.py`); the quick runs use the same
scenes (fewer ratios / step sizes), so the same numbers apply.
"""
from __future__ import annotations

import math
import os

import pytest

from exu_aniso.util.output import read_table    # what the studies write their CSV files with (studies/_lib/studylib.py)


def _row(tab, **match):
    n = len(next(iter(tab.values())))
    hits = [i for i in range(n) if all(tab[k][i] == v for k, v in match.items())]
    assert len(hits) == 1, match
    return {k: tab[k][hits[0]] for k in tab}


@pytest.fixture(scope="module")
def block_paths(tmp_path_factory, quick_study):
    out = tmp_path_factory.mktemp("block_paths")
    quick_study("block_paths", out)
    return out


@pytest.fixture(scope="module")
def return_maps(tmp_path_factory, quick_study):
    out = tmp_path_factory.mktemp("return_maps")
    quick_study("return_maps", out)
    return out


def test_block_paths_near_circle_and_ratio_trend(block_paths):
    S = read_table(block_paths / "summary.csv")
    key = {"drive [-]": "displacement"}
    hi = _row(S, **key, **{"ratio [-]": 100.0, "return_map [-]": "radial"})
    lo = _row(S, **key, **{"ratio [-]": 0.1, "return_map [-]": "radial"})
    # near circle: the full run gives spread 0.0131 over 62 deg; the criterion of the study is 0.02 / 60 deg
    assert hi["spread [-]"] < 0.02 and abs(hi["swept [deg]"]) >= 60.0
    assert hi["near_circle [-]"] == 1
    # the radius is pinned by the stiff radial adhesion: quasi-static r cos(phi)^(1/ratio) = r0 within 1 %
    assert abs(hi["r_end [m]"] / hi["r_quasistatic [m]"] - 1.0) < 0.01
    # stiff radial adhesion gives a tighter path than stiff circumferential adhesion
    assert hi["spread [-]"] < 0.1 * lo["spread [-]"]
    # the block turns with the rail (a sled on a circle): rotation close to the swept angle
    assert abs(hi["rotation [deg]"] - hi["swept [deg]"]) < 10.0


def test_block_paths_map_oracles(block_paths):
    S = read_table(block_paths / "summary.csv")
    key = {"drive [-]": "displacement"}
    # ratio 1 (isotropic B and F): the three maps coincide and the path is the straight line x = x0
    iso = [_row(S, **key, **{"ratio [-]": 1.0, "return_map [-]": m}) for m in ("seed", "exact", "radial")]
    for r in iso[1:]:
        assert r["r_end [m]"] == pytest.approx(iso[0]["r_end [m]"], rel=1e-9)
    y_end = math.sqrt(iso[0]["r_end [m]"] ** 2 - 0.25)
    assert iso[0]["r_end [m]"] == pytest.approx(math.hypot(0.5, y_end), rel=1e-12)
    assert abs(iso[0]["rotation [deg]"]) < 1e-6
    # exact map: B does not act in steady sliding (isotropic F): same straight path for every ratio
    ex = [_row(S, **key, **{"ratio [-]": q, "return_map [-]": "exact"}) for q in (0.1, 1.0, 100.0)]
    for r in ex:
        assert r["r_end [m]"] == pytest.approx(ex[1]["r_end [m]"], rel=2e-3)
    # every case dissipates
    assert all(v > 0.0 for v in S["dissipated [J]"])
    # Exudyn vs reference engine within the stated tolerance
    X = read_table(block_paths / "xcheck.csv")
    assert all(d <= t for d, t in zip(X["max_diff [m]"], X["tol [m]"]))
    P = read_table(block_paths / "paths.csv")
    assert len(P["x [m]"]) >= 9 * 150


def test_return_maps_rates_jump_dissipation(return_maps):
    R = read_table(return_maps / "refinement.csv")
    n = len(R["dt [s]"])
    for scene in ("block", "screw"):
        for m in ("exact", "radial"):
            rates = [R["rate [-]"][i] for i in range(n) if R["scene [-]"][i] == scene
                     and R["return_map [-]"][i] == m and R["rate [-]"][i] == R["rate [-]"][i]]
            # quick: one rate (2e-3 -> 1e-3 against 5e-4); full run: block >= 1.3, screw tail >= 3
            assert rates and min(rates) > 0.8, (scene, m, rates)
    # dissipation: never negative per step and point; every run dissipates
    assert all(v == 0 for v in R["negative_steps [-]"])
    assert all(v >= -1e-12 for v in R["min_step_dissipation [J]"])
    assert all(v > 0 for v in R["dissipated [J]"])
    # exact and radial never need step reductions here; seed does on the block
    for i in range(n):
        if R["return_map [-]"][i] != "seed":
            assert R["step_reductions [-]"][i] == 0
    assert sum(R["step_reductions [-]"][i] for i in range(n) if R["return_map [-]"][i] == "seed") > 0
    J = read_table(return_maps / "jump.csv")
    jmax = {}
    for s, m, j in zip(J["setting [-]"], J["return_map [-]"], J["jump [-]"]):
        jmax[(s, m)] = max(jmax.get((s, m), 0.0), j)
    for (s, m), j in jmax.items():
        if m == "seed":
            assert j > 0.1, (s, m, j)
        else:
            assert j < 1e-6, (s, m, j)
    # the oblique example of the return maps: C isotropic, mu 0.2/0.6, trial at 45 deg: exact and radial keep 45 deg, seed about 6
    ang = {m: _row(J, **{"setting [-]": "C isotropic, F mu 0.2/0.6", "return_map [-]": m,
                        "trial_angle [deg]": 45.0})["returned_angle [deg]"] for m in ("seed", "exact", "radial")}
    assert ang["exact"] == pytest.approx(45.0, abs=1e-5) and ang["radial"] == pytest.approx(45.0, abs=1e-9)
    assert 3.0 < ang["seed"] < 10.0
    assert os.path.exists(return_maps / "report.md") and os.path.exists(return_maps / "jump.png")
