"""Command line: both scenes, both engines, outputs, exit codes, nothing half-written."""
import csv
import json
import math
import os
import subprocess
import sys

import pytest

from exu_aniso.cli import main
from exu_aniso.scenes.block import BLOCK_SUMMARY_KEYS
from exu_aniso.scenes.screw import SCREW_SUMMARY_KEYS

QUICK = {"block": ["t_end=0.1", "dt=2e-3"], "screw": ["t_end=0.1", "dt=2e-3"]}


def run(args):
    return main(args)


@pytest.mark.parametrize("engine", ["reference", "exudyn"])
@pytest.mark.parametrize("scene", ["block", "screw"])
def test_run_writes_csv_summary_and_plot(tmp_path, scene, engine):
    out = tmp_path / scene
    sets = [x for s in QUICK[scene] for x in ("--set", s)]
    assert run(["run", scene, "--engine", engine, "--out", str(out)] + sets) == 0
    with open(out / "trajectory.csv") as f:
        rows = list(csv.reader(line for line in f if not line.startswith("#")))
    header = rows[0]
    assert header[:4] == (["t", "x", "y", "theta"] if scene == "block" else ["t", "angle", "z", "omega"])
    assert len(rows) - 1 == 51 and float(rows[-1][0]) == pytest.approx(0.1)
    summary = json.loads((out / "summary.json").read_text())
    keys = BLOCK_SUMMARY_KEYS if scene == "block" else SCREW_SUMMARY_KEYS
    assert set(keys) <= set(summary) and summary["engine"] == engine and summary["steps"] == 50
    assert (out / "trajectory.png").stat().st_size > 5000
    assert not [p for p in os.listdir(out) if p.startswith(".tmp-")]
    if scene == "block":  # the default drive pulls along +y through a spring: the block moved that way
        assert float(rows[-1][2]) > 0.0 and math.isfinite(summary["heading_deg"])


@pytest.mark.parametrize("args, message", [
    (["run", "block", "--set", "mass=-1"], "mass must be > 0"),
    (["run", "block", "--set", "nonsense=1"], "unknown parameter"),
    (["run", "screw", "--set", "return_map=closest"], "return_map"),
    (["run", "block", "--set", "dt=0"], "dt must be > 0"),
    (["run", "block", "--set", "t_end=nan"], "t_end"),
    (["run", "block", "--set", "mass"], "NAME=VALUE"),
    (["run", "all", "--set", "mass=2"], "applies to one scene"),
])
def test_bad_input_exit_code_and_message(tmp_path, capsys, args, message):
    out = tmp_path / "never"
    assert run(args + ["--out", str(out)]) == 2
    assert message in capsys.readouterr().err
    assert not out.exists()


def test_params_lists_every_name_with_unit(capsys):
    assert run(["params", "screw"]) == 0
    text = capsys.readouterr().out
    for name in ("radius", "helix_angle", "rings", "points_per_ring", "drive_stiffness"):
        assert name in text
    assert "deg" in text
    assert "Bounds on a run's cost" in text and "1,000,000 steps" in text


def test_params_of_a_flexible_scene_print_its_cost_bounds(capsys):
    """The elastic body's bounds (exu_aniso.fe.cost) are printed with the parameters, as checked."""
    from exu_aniso.fe import cost
    assert run(["params", "fe_block"]) == 0
    text = " ".join(capsys.readouterr().out.split())
    assert f"at most {cost.MAX_MODES} modes" in text and f"at most {cost.REFRESH_SECONDS_MAX:g} s per step" in text
    assert "cells <= 12" in text


def test_console_script_entry_point():
    r = subprocess.run([sys.executable, "-m", "exu_aniso.cli", "params", "block"], capture_output=True, text=True)
    assert r.returncode == 0 and "normal_load" in r.stdout


def test_run_all_in_worker_processes_reports_in_order(tmp_path, monkeypatch, capsys):
    """The first ``run all`` on a machine (kernels not compiled) runs the scenes in worker processes;
    forced here with warm kernels: the same files and report lines as in this process, in order."""
    from exu_aniso import cli
    monkeypatch.setattr(cli, "_parallel", lambda jobs, a: True)
    assert cli.main(["run", "all", "--out", str(tmp_path), "--quiet"]) == 0
    lines = [ln for ln in capsys.readouterr().out.splitlines() if ln]
    assert [ln.split(" ")[0] for ln in lines] == ["block", "screw"], lines
    for scene in ("block", "screw"):
        assert (tmp_path / scene / "summary.json").exists() and (tmp_path / scene / "trajectory.csv").exists()


def test_reference_steps_accepted_without_convergence_are_not_hidden(tmp_path, capsys):
    """The reference engine's last resort at its step's floor (accepting the smallest-residual iterate,
    the seed map's jump at stick/slip) is counted and said: the run exits 1, summary.json says
    "complete": false with the count and the largest residual (measured on this run: 4 steps, 0.094
    against 1e-10), the files are written."""
    out = tmp_path / "r"
    code = run(["run", "screw", "--engine", "reference", "--set", "return_map=seed", "--set", "t_end=0.3",
                "--out", str(out), "--quiet"])
    assert code == 1 and "accepted without Newton's convergence" in capsys.readouterr().err
    s = json.loads((out / "summary.json").read_text())
    assert s["complete"] is False and s["unconverged_steps"] >= 1 and s["unconverged_residual_max"] > 1e-10
    assert (out / "trajectory.csv").exists()
