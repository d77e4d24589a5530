"""Edges where a run could be silently wrong: a non-finite ledger or state, engines on different time
grids, parameters outside a physical range or a run that would cost without bound, output paths that
cannot take the results, a ledger that cannot be recomputed from trajectory.csv.

Oracles here: the energy balance recomputed from the file's own columns and the scene's parameters
(work in = force x displacement by the trapezoid, kinetic = m |v|^2 / 2 + omega . J omega / 2, potential
= load x height) must equal the ledger's columns to round-off of the CSV (repr floats: exact); the time
grid of both engines is N = round(t_end / dt) equal steps (the same grid to 1e-12 s), and on that grid
the planar block's engines agree to the parity tolerance of tests/test_exudyn_scenes.py (1e-7)."""
from __future__ import annotations

import csv
import json
import math
import os

import numpy as np
import pytest

from exu_aniso import cli
from exu_aniso.engines import energy
from exu_aniso.engines.result import Result
from exu_aniso.scenes.block import simulate_block
from exu_aniso.catalog import SCENES
from exu_aniso.scenes.base import MAGNITUDE_LIMITS, MAX_STEPS, energy_ledger
from exu_aniso.scenes.block import BlockParams, block_inertia
from exu_aniso.scenes.screw import ScrewParams, screw_inertia
from exu_aniso.engines.timing import step_count, time_grid

exudyn = pytest.importorskip("exudyn")

from exu_aniso.models.block import RunBlock  # noqa: E402


# ----------------------------------------------------------------------------------------------
# the ledger cannot be fooled

def test_ledger_with_a_non_finite_term_is_open_and_says_where():
    n = 6
    t = np.linspace(0.0, 0.5, n)
    kinetic = np.linspace(0.0, 1.0, n)
    kinetic[3] = np.inf                     # an overflowed kinetic energy at t = 0.3 s
    with np.errstate(invalid="ignore"):
        _, s = energy.ledger(work_in=kinetic.copy(), kinetic=kinetic, potential=np.zeros(n), stored=np.zeros(n),
                             dissipated=np.zeros(n), t=t)
    assert s["energy_ok"] is False
    assert math.isnan(s["energy"]["residual"])
    assert s["energy_nonfinite"] == dict(column="energy_work_in", index=3, t=pytest.approx(0.3))
    with pytest.warns(energy.EnergyWarning, match="not finite at t = 0.3 s"):
        energy.warn_if_open(s, "test run")


def test_ledger_nan_from_the_first_sample():
    """The old ledger returned residual 0 and energy_ok true here (the scale was NaN)."""
    n = 4
    nan = np.full(n, np.nan)
    _, s = energy.ledger(work_in=np.zeros(n), kinetic=nan, potential=np.zeros(n), stored=np.zeros(n),
                         dissipated=np.zeros(n))
    assert s["energy_ok"] is False and s["energy_nonfinite"]["column"] == "energy_kinetic"
    assert s["energy_nonfinite"]["index"] == 0


def test_non_finite_state_opens_the_ledger():
    n = 5
    traj = dict(t=np.linspace(0.0, 0.4, n), x=np.array([0.0, 1.0, np.nan, 3.0, 4.0]))
    zero = np.zeros(n)
    with pytest.warns(energy.EnergyWarning, match="x is not finite at t = 0.2 s"):
        s = energy_ledger(dict(work_in=zero, kinetic=zero, potential=zero, stored=zero, dissipated=zero), traj, "test")
    assert s["energy_ok"] is False
    assert s["state_nonfinite"] == dict(column="x", index=2, t=pytest.approx(0.2))


def test_cli_exits_1_on_a_non_finite_state(tmp_path, monkeypatch, capsys):
    """A run whose state went non-finite writes its files with complete=false and exits 1."""
    p = BlockParams(t_end=0.01)
    res = simulate_block(p)
    traj = dict(res.trajectory)
    traj["vx"] = traj["vx"].copy()
    traj["vx"][4:] = np.nan
    summary = dict(res.summary, energy_ok=False, state_nonfinite=dict(column="vx", index=4, t=float(traj["t"][4])))
    monkeypatch.setattr(cli, "simulate", lambda *a, **k: Result(traj, summary, p, {}))
    out = tmp_path / "run"
    rc = cli.main(["run", "block", "--engine", "reference", "--set", "t_end=0.01", "--out", str(out), "--quiet"])
    assert rc == 1
    assert "vx at t = 0.004 s" in capsys.readouterr().err
    s = json.loads((out / "summary.json").read_text())
    assert s["complete"] is False and "non-finite" in s["failure"]
    assert (out / "trajectory.csv").exists()


# ----------------------------------------------------------------------------------------------
# one time grid for both engines

@pytest.mark.parametrize("t_end, dt, n", [(1.0, 1e-3, 1000), (0.193688, 0.000909523, 213), (0.25, 0.1, 2),
                                          (0.36, 0.1, 4), (0.1, 0.1, 1)])
def test_step_count_is_round_t_end_over_dt(t_end, dt, n):
    p = BlockParams(t_end=t_end, dt=dt)
    assert step_count(p) == n == round(t_end / dt)
    g = time_grid(p)
    assert len(g) == n + 1 and g[-1] == t_end and np.allclose(np.diff(g), t_end / n, rtol=1e-12)


def test_engines_share_the_grid_when_t_end_is_no_multiple_of_dt():
    """Before: the reference stepped dt plus a short last step, Exudyn t_end / N: theta_end differed 1.8 %."""
    p = BlockParams(t_end=0.193688, dt=0.000909523, points="grid:2", drive="force", force=3.0)
    ref, exu = simulate_block(p), RunBlock(p)
    np.testing.assert_allclose(ref.trajectory["t"], time_grid(p), atol=1e-12)
    np.testing.assert_allclose(exu.trajectory["t"], time_grid(p), atol=1e-12)
    for k in ("x", "y", "theta", "vx", "vy", "omega"):
        scale = np.max(np.abs(ref.trajectory[k]))
        assert np.max(np.abs(exu.trajectory[k] - ref.trajectory[k])) <= 1e-7 * scale, k


# ----------------------------------------------------------------------------------------------
# validation bounds what a run will cost and refuses magnitudes outside a physical range

REFUSED = [
    ("block", "dt=1e-9", "t_end / dt"),
    ("block", "points=grid:100000", "contact points"),
    ("block", "points=grid:200", "contact points"),
    ("block", "mu_1=1e300", "mu_1"),
    ("block", "size=1e300", "size"),
    ("block", "t_end=1e300", "t_end"),
    ("screw", "rings=1e300", "rings"),
    ("screw", "rings=2000", "contact points"),        # 2000 x 8 = 16,000 points
    ("particle", "vy0=1e200", "vy0"),
    ("capstan", "elements=1e9", "elements"),
    ("feeder", "parts=1e9", "parts"),
    ("feeder", "parts=3000", "contact points"),
    ("capstan", "elements=5000", "contact points"),
    ("fastening", "head_points=20000", "contact points"),
]


@pytest.mark.parametrize("scene, setting, named", REFUSED)
def test_refused_before_anything_is_built(scene, setting, named, tmp_path, capsys):
    out = tmp_path / "out"
    rc = cli.main(["run", scene, "--set", setting, "--out", str(out), "--quiet"])
    err = capsys.readouterr().err
    assert rc == 2, err
    assert named in err and err.count("\n") == 1, err
    assert not out.exists()


def test_point_steps_and_memory_bounds():
    with pytest.raises(ValueError, match="contact points x steps"):
        BlockParams(points="grid:100", t_end=200.0)
    with pytest.raises(ValueError, match=f"{MAX_STEPS:,} steps"):
        ScrewParams(t_end=2000.0)


def _real_parameters():
    for name, sc in SCENES.items():
        for k, (default, unit, _, rule) in sc.Params.TABLE.items():
            if isinstance(rule, tuple) or rule in ("int >= 1", "int >= 0") or "grid" in str(rule):
                continue
            if MAGNITUDE_LIMITS.get(unit, (None, None))[1] is not None:
                yield name, k, unit, rule


@pytest.mark.parametrize("scene, name, unit, rule", list(_real_parameters()))
def test_every_real_parameter_has_a_physical_range(scene, name, unit, rule):
    """Ten times the unit's largest magnitude is refused with the parameter named (by this rule or a
    scene rule that is tighter)."""
    hi = MAGNITUDE_LIMITS[unit][1]
    with pytest.raises(ValueError, match=name):
        SCENES[scene].Params.from_strings({name: repr(10.0 * hi)})


# ----------------------------------------------------------------------------------------------
# output paths

def test_out_that_cannot_be_created_exits_2(capsys):
    assert cli.main(["run", "block", "--out", "/proc/exu-aniso-test/x", "--quiet"]) == 2
    assert "--out" in capsys.readouterr().err


def test_result_name_taken_by_a_directory_exits_2_and_writes_nothing(tmp_path, capsys):
    (tmp_path / "summary.json").mkdir()
    assert cli.main(["run", "block", "--engine", "reference", "--set", "t_end=0.01", "--out", str(tmp_path),
                     "--quiet"]) == 2
    assert "summary.json exists and is not a file" in capsys.readouterr().err
    assert sorted(os.listdir(tmp_path)) == ["summary.json"]


def test_out_is_created_only_when_results_are_written(tmp_path, monkeypatch):
    """A run killed while simulating leaves no empty --out: the folder does not exist until its results
    are moved into place (its parent holds the run's hidden lock and staging folder meanwhile; the
    staging folder goes when the results are in place)."""
    out = tmp_path / "a" / "b"
    seen = []
    real = cli.simulate

    def spy(*a, **k):
        seen.append((out.exists(), sorted(n.split("-")[0] for n in os.listdir(tmp_path / "a"))))
        return real(*a, **k)

    monkeypatch.setattr(cli, "simulate", spy)
    assert cli.main(["run", "block", "--engine", "reference", "--set", "t_end=0.01", "--out", str(out),
                     "--quiet"]) == 0
    assert seen == [(False, [".b.lock", ".b.staging"])]
    assert (out / "summary.json").exists() and sorted(os.listdir(tmp_path / "a")) == [".b.lock", "b"]


# ----------------------------------------------------------------------------------------------
# every column a ledger needs is in trajectory.csv

def _read_csv(path):
    with open(path) as f:
        rows = list(csv.reader(line for line in f if not line.startswith("#")))
    return {k: np.array([float(r[i]) for r in rows[1:]]) for i, k in enumerate(rows[0])}


def _trapezoid(f, x):
    return np.concatenate([[0.0], np.cumsum(0.5 * (f[1:] + f[:-1]) * np.diff(x))])


def _recompute_block(c, p):
    a = math.radians(p.drive_angle)
    s = math.cos(a) * c["x"] + math.sin(a) * c["y"]
    m, J = block_inertia(p)
    v2 = c["vx"] ** 2 + c["vy"] ** 2 + c.get("vz", 0.0 * c["t"]) ** 2
    w2 = c["omega"] ** 2 + c.get("omega_x", 0.0 * c["t"]) ** 2 + c.get("omega_y", 0.0 * c["t"]) ** 2
    kinetic = 0.5 * m * v2 + 0.5 * J[0, 0] * w2
    return _trapezoid(c["drive_force"], s), kinetic - kinetic[0], p.normal_load * (c["z"] - c["z"][0])


def _recompute_screw(c, p):
    m, J = screw_inertia(p)
    work = _trapezoid(c["torque"], c["angle"]) + _trapezoid(c["axial_force"], c["z"])
    if p.model == "full":
        w = np.column_stack([c["omega_x"], c["omega_y"], c["omega"]])
        axis = np.column_stack([c["axis_x"], c["axis_y"], c["axis_z"]])
        w_ax = np.einsum("ni,ni->n", w, axis)
        rot = J[0, 0] * np.einsum("ni,ni->n", w, w) + (J[2, 2] - J[0, 0]) * w_ax ** 2
        v2 = c["vx"] ** 2 + c["vy"] ** 2 + c["vz"] ** 2
    else:
        rot, v2 = J[2, 2] * c["omega"] ** 2, c["vz"] ** 2
    kinetic = 0.5 * m * v2 + 0.5 * rot
    return work, kinetic - kinetic[0], 0.0 * work


@pytest.mark.parametrize("engine", ["reference", "exudyn"])
@pytest.mark.parametrize("scene, sets", [
    ("block", ["model=planar", "t_end=0.05"]),
    ("block", ["model=full", "t_end=0.05", "drive_angle=30"]),
    ("screw", ["model=reduced", "t_end=0.05"]),
    ("screw", ["model=full", "t_end=0.05", "axial_load=2"]),
])
def test_ledger_recomputed_from_csv(scene, sets, engine, tmp_path):
    args = ["run", scene, "--engine", engine, "--out", str(tmp_path), "--quiet"]
    for s in sets:
        args += ["--set", s]
    assert cli.main(args) == 0
    c = _read_csv(tmp_path / "trajectory.csv")
    p = SCENES[scene].Params.from_strings(dict(s.split("=") for s in sets))
    work, kinetic, potential = (_recompute_block if scene == "block" else _recompute_screw)(c, p)
    scale = max(np.max(np.abs(c["energy_work_in"])), np.max(np.abs(c["energy_kinetic"])), 1e-300)
    for name, mine in (("work_in", work), ("kinetic", kinetic), ("potential", potential)):
        assert np.max(np.abs(mine - c["energy_" + name])) <= 1e-9 * scale, name
    residual = work - kinetic - potential - c["energy_stored"] - c["energy_dissipated"]
    assert np.max(np.abs(residual - c["energy_residual"])) <= 1e-9 * scale
    s = json.loads((tmp_path / "summary.json").read_text())
    assert s["energy_ok"] is (s["energy"]["residual"] <= s["energy_tolerance"])


def _ledger_sums(c, stored, dissipated, scale):
    """The ledger's columns (changes from the first sample) are the sums of the term columns the file
    holds, to round-off, and its residual is work - kinetic - potential - stored - dissipated."""
    for name, total in (("kinetic", c["kinetic_energy"]), ("stored", stored), ("dissipated", dissipated)):
        np.testing.assert_allclose(c["energy_" + name], total - total[0], rtol=0, atol=1e-12 * scale, err_msg=name)
    residual = (c["energy_work_in"] - c["energy_kinetic"] - c["energy_potential"] - c["energy_stored"]
                - c["energy_dissipated"])
    np.testing.assert_allclose(residual, c["energy_residual"], rtol=0, atol=1e-12 * scale)
    assert c["kinetic_energy"].min() >= 0.0 and c["contact_stored_energy"].min() >= -1e-12 * scale
    friction = c["dissipated_energy"] - c["dissipated_energy"][0]
    assert np.all(c["contact_dissipated_energy"] - friction >= -1e-9 * scale)    # dashpots dissipate


def test_fe_block_ledger_recomputed_from_csv(tmp_path):
    """The flexible block's file: the work in (the drive's force over the driver's travel, a closed form
    of time, and the press's force over the plate's height, by the trapezoid), the drive spring's energy
    k s^2 / 2 and its dashpot's dissipation (the force less k s over s) recomputed from the columns; the
    body's kinetic and strain energy and the contact's terms are columns, and the ledger is their sum."""
    sets = dict(cells="2", t_end="0.4", t_press="0.1", travel="0.01", drive_ramp="0.05")
    args = ["run", "fe_block", "--out", str(tmp_path), "--quiet"]
    for kv in sets.items():
        args += ["--set", "=".join(kv)]
    assert cli.main(args) == 0
    c = _read_csv(tmp_path / "trajectory.csv")
    p = SCENES["fe_block"].Params.from_strings(sets)
    speed = p.travel / (p.t_end - p.t_press - 0.5 * p.drive_ramp)
    tau = np.clip(c["t"] - p.t_press, 0.0, None)
    travel = np.where(tau < p.drive_ramp, 0.5 * speed * tau ** 2 / p.drive_ramp, speed * (tau - 0.5 * p.drive_ramp))
    work = _trapezoid(c["drive_force"], travel) + _trapezoid(c["force_z"], c["z_top"])
    scale = np.max(np.abs(c["energy_work_in"]))
    assert scale > 0.0
    np.testing.assert_allclose(work, c["energy_work_in"], rtol=0, atol=1e-9 * scale)
    k, s = p.drive_stiffness, c["drive_stretch"]
    np.testing.assert_allclose(c["drive_spring_energy"], 0.5 * k * s ** 2, rtol=1e-12, atol=1e-15 * scale)
    np.testing.assert_allclose(c["drive_dashpot_dissipated_energy"], _trapezoid(c["drive_force"] - k * s, s),
                               rtol=0, atol=1e-9 * scale)
    assert np.all(np.diff(c["rayleigh_dissipated_energy"]) >= -1e-12 * scale)
    _ledger_sums(c, c["contact_stored_energy"] + c["strain_energy"] + c["drive_spring_energy"],
                 c["contact_dissipated_energy"] + (c["rayleigh_dissipated_energy"]
                                                   + c["drive_dashpot_dissipated_energy"]), scale)
    assert np.all(c["energy_potential"] == 0.0) and c["strain_energy"][-1] > 0.0


def test_fe_screw_ledger_recomputed_from_csv(tmp_path):
    """The flexible screw's file: the work in (the drive's torque over the head's angle and the axial
    load over z) recomputed; the shank's kinetic and strain energy, the Rayleigh damping's and the
    contact's terms are columns, and the ledger is their sum."""
    sets = dict(cells_theta="8", cells_z="1", t_end="0.05")
    args = ["run", "fe_screw", "--out", str(tmp_path), "--quiet"]
    for kv in sets.items():
        args += ["--set", "=".join(kv)]
    assert cli.main(args) == 0
    c = _read_csv(tmp_path / "trajectory.csv")
    work = _trapezoid(c["torque"], c["angle"]) + _trapezoid(c["axial_force"], c["z"])
    scale = np.max(np.abs(c["energy_work_in"]))
    assert scale > 0.0
    np.testing.assert_allclose(work, c["energy_work_in"], rtol=0, atol=1e-9 * scale)
    assert np.all(np.diff(c["rayleigh_dissipated_energy"]) >= -1e-12 * scale)
    _ledger_sums(c, c["contact_stored_energy"] + c["strain_energy"],
                 c["contact_dissipated_energy"] + c["rayleigh_dissipated_energy"], scale)


# ----------------------------------------------------------------------------------------------
# a step that collapses stops with a message instead of creeping on

@pytest.mark.slow
def test_step_collapse_stops_at_the_floor(tmp_path, capsys):
    """Before: 747,696 steps instead of 40 in 48 s, exit 0 and a 243 MB trajectory.csv."""
    rc = cli.main(["run", "block", "--set", "model=full", "--set", "dt=0.05", "--set", "eps_n=1e10",
                   "--set", "t_end=0.3", "--out", str(tmp_path), "--quiet"])
    err = capsys.readouterr().err
    assert rc == 1
    assert "the step fell to its floor" in err and "0.000977 of the nominal step" in err
    assert json.loads((tmp_path / "summary.json").read_text())["complete"] is False
