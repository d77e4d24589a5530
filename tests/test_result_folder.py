"""A result folder holds one run's files, whole (exu_aniso.util.result_folder.result_folder, cli.run_scene):
a run killed while writing leaves the earlier run's files as they were, a failed rerun leaves its own
files alone, a rerun without --snapshot leaves no old snapshot, a second run into a folder in use is
refused, every file names its run (run_id, params_hash), and a folder that is not a result folder is
never replaced."""
import json
import os
import signal
import subprocess
import sys
import time

import pytest
from PIL import Image

from exu_aniso import cli
from exu_aniso.util.result_folder import FolderInUse, result_folder, run_identity

QUICK = ["--set", "t_end=0.1", "--set", "dt=2e-3", "--quiet"]


def _identity(out):
    """run_id and params_hash as summary.json, trajectory.csv's first line and trajectory.png say."""
    s = json.loads((out / "summary.json").read_text())
    line = (out / "trajectory.csv").read_text().splitlines()[0]
    assert line.startswith("# exu-aniso ")
    csv = dict(kv.split("=") for kv in line[len("# exu-aniso "):].split())
    png = Image.open(out / "trajectory.png").info["Description"]
    assert png == line[2:]
    assert (s["run_id"], s["params_hash"]) == (csv["run_id"], csv["params_hash"])
    return s["run_id"], s["params_hash"]


def test_every_file_names_its_run(tmp_path):
    """Two runs with the same parameters: two run ids, one parameters' hash; other parameters, another
    hash. The three files of a run agree."""
    ids = []
    for name, extra in (("a", []), ("b", []), ("c", ["--set", "mu_1=0.4"])):
        assert cli.main(["run", "block", "--out", str(tmp_path / name)] + QUICK + extra) == 0
        ids.append(_identity(tmp_path / name))
    assert ids[0][0] != ids[1][0] and ids[0][1] == ids[1][1] != ids[2][1]
    assert run_identity({"a": 1.0, "b": "x"})["params_hash"] == run_identity({"b": "x", "a": 1.0})["params_hash"]


def test_interrupted_while_writing_keeps_the_earlier_run(tmp_path, monkeypatch, capsys):
    """The second run is interrupted after its trajectory.csv is written (KeyboardInterrupt in the
    plot, as Ctrl-C would): exit 130 with a line, not a traceback, and the folder is still the first
    run's, every file of it."""
    out = tmp_path / "r"
    assert cli.main(["run", "block", "--out", str(out)] + QUICK) == 0
    first = _identity(out)
    before = {n: (out / n).read_bytes() for n in os.listdir(out)}

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt
    monkeypatch.setattr(cli, "plot_trajectory", interrupted)
    assert cli.main(["run", "block", "--out", str(out), "--set", "mu_1=0.5"] + QUICK) == 130
    err = capsys.readouterr().err
    assert "interrupted" in err and "Traceback" not in err
    assert {n: (out / n).read_bytes() for n in os.listdir(out)} == before and _identity(out) == first
    assert not [n for n in os.listdir(tmp_path) if ".staging-" in n]


def test_killed_run_leaves_the_earlier_run_and_the_next_run_clears_its_staging(tmp_path):
    """A real process killed (SIGKILL) while it simulates: the earlier results stay whole; the next run
    into the folder removes the killed run's hidden staging folder."""
    out = tmp_path / "r"
    assert cli.main(["run", "block", "--out", str(out)] + QUICK) == 0
    first = _identity(out)
    proc = subprocess.Popen([sys.executable, "-m", "exu_aniso.cli", "run", "block", "--out", str(out), "--quiet",
                             "--set", "t_end=1000", "--set", "mu_1=0.5"], stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    try:
        deadline = time.time() + 120
        while not [n for n in os.listdir(tmp_path) if ".staging-" in n] and time.time() < deadline:
            time.sleep(0.05)
        assert proc.poll() is None, "the long run ended before it could be killed"
        time.sleep(0.5)
    finally:
        proc.send_signal(signal.SIGKILL)
        proc.wait()
    assert _identity(out) == first and sorted(os.listdir(out)) == ["summary.json", "trajectory.csv",
                                                                   "trajectory.png"]
    assert [n for n in os.listdir(tmp_path) if ".staging-" in n]
    assert cli.main(["run", "block", "--out", str(out)] + QUICK) == 0
    assert not [n for n in os.listdir(tmp_path) if ".staging-" in n] and _identity(out)[0] != first[0]


def test_a_failed_rerun_leaves_its_own_files_only(tmp_path, monkeypatch, capsys):
    """A rerun that fails without a trajectory writes summary.json ("complete": false) and nothing of
    the earlier run stays beside it; so does a rerun without --snapshot (no old snapshot.png)."""
    out = tmp_path / "r"
    assert cli.main(["run", "block", "--out", str(out)] + QUICK) == 0
    (out / "snapshot.png").write_bytes((out / "trajectory.png").read_bytes())     # as a --snapshot run leaves
    assert cli.main(["run", "block", "--out", str(out)] + QUICK) == 0
    assert sorted(os.listdir(out)) == ["summary.json", "trajectory.csv", "trajectory.png"]

    def broken(*args, **kwargs):
        raise RuntimeError("the solver broke")
    monkeypatch.setattr(cli, "simulate", broken)
    assert cli.main(["run", "block", "--out", str(out)] + QUICK) == 1
    assert os.listdir(out) == ["summary.json"]
    s = json.loads((out / "summary.json").read_text())
    assert s["complete"] is False and "the solver broke" in s["failure"] and s["run_id"]


def test_a_folder_in_use_is_refused(tmp_path, capsys):
    """While a run holds the folder's lock, a second run into it exits 2 naming the process, and writes
    nothing; afterwards the folder is free again."""
    out = tmp_path / "r"
    with result_folder(str(out)):
        assert cli.main(["run", "block", "--out", str(out)] + QUICK) == 2
        err = capsys.readouterr().err
        assert "another run (process" in err and str(os.getpid()) in err and not out.exists()
        with pytest.raises(FolderInUse):
            with result_folder(str(out)):
                pass
    assert cli.main(["run", "block", "--out", str(out)] + QUICK) == 0


@pytest.mark.parametrize("name", ["", "."])
def test_the_current_folder_is_not_a_result_folder(tmp_path, monkeypatch, capsys, name):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "mine.txt").write_text("the user's")
    assert cli.main(["run", "block", "--out", name] + QUICK) == 2
    assert "current folder" in capsys.readouterr().err and os.listdir(tmp_path) == ["mine.txt"]


def test_a_folder_with_other_files_is_never_replaced(tmp_path, capsys):
    out = tmp_path / "r"
    out.mkdir()
    (out / "notes.md").write_text("the user's")
    assert cli.main(["run", "block", "--out", str(out)] + QUICK) == 2
    assert "notes.md" in capsys.readouterr().err and os.listdir(out) == ["notes.md"]
