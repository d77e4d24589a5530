"""Command line experience: progress on stderr (--quiet), --snapshot (raytraced PNG), --view (refused
without a display, before simulating; never opens a window here), and the plot functions of
the scenes (matplotlib conventions, closed-form lines)."""
import json
import math
import os

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402

from exu_aniso import cli  # noqa: E402
from exu_aniso.calibration import steady_sliding  # noqa: E402
from exu_aniso.scenes.block import PlotBlockPath  # noqa: E402
from exu_aniso.scenes.screw import PlotScrewAdvance, PlotScrewTorque  # noqa: E402
from exu_aniso.util.progress import AFTER_ENV  # noqa: E402
from exu_aniso.scenes.block import BlockParams  # noqa: E402
from exu_aniso.scenes.screw import ScrewParams

SHORT = {scene: ["--set", "t_end=0.05", "--set", "dt=1e-3"] for scene in ("block", "screw")}
VIEW_MESSAGE = "--view needs a display (DISPLAY is not set); use --snapshot, or run under xvfb-run -a"


@pytest.fixture
def no_windows(monkeypatch):
    """Exudyn must not open a window in this test, whatever happens: the solution viewer and dialogs
    are suppressed. The renderer flag is left False so that the display check is really exercised
    (the CLI refuses --view before anything could call renderer.Start())."""
    import exudyn
    ui = exudyn.special.userInterface
    for name in ("suppressSolutionViewer", "suppressDialogs", "suppressPlots"):
        monkeypatch.setattr(ui, name, True)
    monkeypatch.setattr(ui, "suppressRenderer", False)
    return ui


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


# ----------------------------------------------------------------------------------------------
# progress

@pytest.mark.parametrize("scene", ["block", "screw"])
def test_progress_on_stderr_for_a_long_run(tmp_path, capsys, monkeypatch, scene):
    monkeypatch.setenv(AFTER_ENV, "0")          # every run counts as long
    assert cli.main(["run", scene, "--out", str(tmp_path)] + SHORT[scene]) == 0
    err = capsys.readouterr().err
    lines = err.splitlines()
    assert lines, "no progress on stderr"
    assert all(line.startswith(f"{scene}: ") for line in lines), err   # progress only (stderr is no TTY)
    assert "ETA" in lines[0] and "steps/s" in lines[0] and "Newton iterations" in lines[0]
    assert lines[-1].startswith(f"{scene}: 100.0 % (t = 0.05 s) in ")
    assert "\r" not in err                      # plain lines into a file or pipe


def test_quiet_silences_progress(tmp_path, capsys, monkeypatch):
    monkeypatch.setenv(AFTER_ENV, "0")
    assert cli.main(["run", "block", "--quiet", "--out", str(tmp_path)] + SHORT["block"]) == 0
    captured = capsys.readouterr()
    assert captured.err == "" and "block [exudyn]" in captured.out


def test_short_run_shows_no_progress(tmp_path, capsys, monkeypatch):
    monkeypatch.delenv(AFTER_ENV, raising=False)   # default: only runs longer than about 2 s
    assert cli.main(["run", "screw", "--out", str(tmp_path)] + SHORT["screw"]) == 0
    assert capsys.readouterr().err == ""


# ----------------------------------------------------------------------------------------------
# snapshot

def _blank(image):
    """True if the picture shows nothing but background and the corner texts."""
    rgb = np.asarray(image, dtype=float)[..., :3]
    h, w = rgb.shape[:2]
    centre = rgb[h // 4: 3 * h // 4, w // 4: 3 * w // 4]
    drawn = np.any(np.abs(centre - centre.reshape(-1, 3).max(axis=0)) > 0.1, axis=-1).mean()
    return centre.std() < 0.05 or drawn < 0.05


@pytest.mark.parametrize("scene, sets", [("block", []), ("screw", []), ("screw", ["--set", "model=full"]),
                                         ("block", ["--set", "model=full"])])
def test_snapshot_writes_a_png_that_is_not_blank(tmp_path, capsys, scene, sets):
    out = tmp_path / "run"
    assert cli.main(["run", scene, "--snapshot", "--quiet", "--out", str(out)] + SHORT[scene] + sets) == 0
    image = plt.imread(out / "snapshot.png")
    assert image.shape[:2] == (600, 800)
    assert not _blank(image), "snapshot.png shows no body"
    assert _blank(np.ones_like(image)) and not [p for p in os.listdir(out) if p.startswith(".tmp-")]
    assert sorted(os.listdir(out)) == ["snapshot.png", "summary.json", "trajectory.csv", "trajectory.png"]


def test_snapshot_shows_the_final_state(tmp_path):
    """The screw turns about 100 degrees in 0.3 s: the picture of the final state differs from the
    initial one (its alternating colours turn with it)."""
    from exu_aniso.engines.exudyn_adapter.runner import SnapshotImage
    from exu_aniso.models.screw import BuildScrew, RunScrew
    p = ScrewParams(t_end=0.3)
    initial = SnapshotImage(BuildScrew(p)).astype(float)
    RunScrew(p, contactOutputs=False, snapshot=str(tmp_path / "final.png"))
    final = plt.imread(tmp_path / "final.png")[..., :3] * 255.0
    assert np.abs(final - initial).mean() > 1.0


def test_snapshot_and_view_need_the_exudyn_engine(tmp_path, capsys):
    for flag in ("--snapshot", "--view"):
        assert cli.main(["run", "block", "--engine", "reference", flag, "--out", str(tmp_path / "x")]) == 2
        assert "need --engine exudyn" in capsys.readouterr().err
    assert os.listdir(tmp_path) == []


# ----------------------------------------------------------------------------------------------
# view

def test_view_without_display_exits_2_before_simulating(tmp_path, capsys, monkeypatch, no_windows):
    monkeypatch.delenv("DISPLAY", raising=False)
    called = []
    monkeypatch.setattr(cli, "simulate", lambda *a, **k: called.append(a))
    out = tmp_path / "never"
    for scene in ("block", "all"):
        assert cli.main(["run", scene, "--view", "--out", str(out)]) == 2
        err = capsys.readouterr().err
        assert VIEW_MESSAGE in err and "Traceback" not in err
    assert not called and not out.exists() and os.listdir(tmp_path) == []


def test_view_with_a_display_that_does_not_answer_exits_2_before_simulating(tmp_path, capsys, monkeypatch,
                                                                             no_windows):
    """DISPLAY set, but no X server behind it (Exudyn's renderer would abort the process): exit 2
    with the display named, nothing simulated; a server that answers (a socket listening at the
    display's address) passes the check."""
    import socket
    from exu_aniso.engines.exudyn_adapter.runner import DisplayProblem
    monkeypatch.setenv("DISPLAY", ":4242")
    called = []
    monkeypatch.setattr(cli, "simulate", lambda *a, **k: called.append(a))
    assert cli.main(["run", "block", "--view", "--out", str(tmp_path / "never")]) == 2
    err = capsys.readouterr().err
    assert "DISPLAY=:4242 does not answer (no X server at /tmp/.X11-unix/X4242)" in err and "xvfb-run -a" in err
    assert not called and not (tmp_path / "never").exists()
    with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as server:   # Linux's abstract name of :4242
        server.bind("\0/tmp/.X11-unix/X4242")
        server.listen(1)
        assert DisplayProblem() is None
    assert "does not answer" in DisplayProblem()


def test_view_solution_refuses_without_display(monkeypatch, no_windows):
    from exu_aniso.models.block import BuildBlock
    from exu_aniso.engines.exudyn_adapter.runner import ViewSolution
    monkeypatch.delenv("DISPLAY", raising=False)
    with pytest.raises(RuntimeError, match="needs a display"):
        ViewSolution(BuildBlock(BlockParams(t_end=0.01)), "nothing.sol")


def test_view_with_suppressed_windows_plays_the_stored_solution(tmp_path, capsys, monkeypatch, no_windows):
    """With a (fake) display and Exudyn's windows suppressed, --view runs its whole path: the run
    stores Exudyn's solution, all results are written, then the viewer gets the stored solution."""
    from exu_aniso.engines.exudyn_adapter import runner
    monkeypatch.setenv("DISPLAY", ":99")
    monkeypatch.setattr(no_windows, "suppressRenderer", True)
    seen = []
    original = runner.ViewSolution

    def spy(model, fileName, title=""):
        from exudyn.utilities import LoadSolutionFile
        sol = LoadSolutionFile(fileName, verbose=False)
        written = os.path.exists(tmp_path / "run" / "summary.json")
        seen.append((title, sol["nRows"], float(sol["data"][-1][0]), written))
        return original(model, fileName, title)

    monkeypatch.setattr(runner, "ViewSolution", spy)
    args = ["run", "screw", "--view", "--quiet", "--out", str(tmp_path / "run")] + SHORT["screw"]
    assert cli.main(args) == 0
    assert len(seen) == 1
    title, rows, t_last, written_before = seen[0]
    assert title == "exu-aniso screw" and rows >= 10 and t_last == pytest.approx(0.05) and written_before
    assert json.loads((tmp_path / "run" / "summary.json").read_text())["complete"] is True


# ----------------------------------------------------------------------------------------------
# plots

def _screw_traj(p, revs=2.0, n=200):
    st = steady_sliding(p)
    angle = np.linspace(0.0, 2.0 * math.pi * revs, n)
    t = np.linspace(0.0, p.t_end, n)
    return dict(t=t, angle=angle, z=st.advance_per_rev * angle / (2.0 * math.pi) + 1e-5,
                torque=np.full(n, st.torque))


def _closed_form_lines(ax):
    return [line for line in ax.get_lines() if line.get_gid() == "closed_form"]


def _legend_texts(ax):
    return [t.get_text() for t in ax.get_legend().get_texts()]


@pytest.mark.parametrize("return_map", ["radial", "exact"])
def test_plot_screw_advance_draws_the_closed_form_line(return_map):
    p = ScrewParams(return_map=return_map)
    fig, ax = plt.subplots()
    assert PlotScrewAdvance(_screw_traj(p), p, ax=ax) is ax
    (line,) = _closed_form_lines(ax)
    x, y = np.asarray(line.get_xdata(), float), np.asarray(line.get_ydata(), float)
    slope = (y[-1] - y[0]) / (x[-1] - x[0])                      # mm per revolution
    assert slope == pytest.approx(steady_sliding(p).advance_per_rev * 1e3, rel=1e-12)
    assert any("closed form" in text for text in _legend_texts(ax))
    assert ax.get_xlabel() == "rotation [rev]" and ax.get_ylabel() == "axial position z [mm]"


@pytest.mark.parametrize("return_map", ["radial", "exact"])
def test_plot_screw_torque_draws_the_closed_form_sliding_torque(return_map):
    p = ScrewParams(return_map=return_map)
    fig, ax = plt.subplots()
    assert PlotScrewTorque(_screw_traj(p), p, ax=ax) is ax
    (line,) = _closed_form_lines(ax)
    assert np.asarray(line.get_ydata(), float) == pytest.approx([steady_sliding(p).torque] * 2, rel=1e-12)
    assert ax.get_xlabel() == "t [s]"


def test_seed_map_has_no_closed_form_and_the_legend_says_so():
    p = ScrewParams(return_map="seed")
    traj = _screw_traj(ScrewParams())
    for plot in (PlotScrewAdvance, PlotScrewTorque):
        fig, ax = plt.subplots()
        assert plot(traj, p, ax=ax) is ax
        assert _closed_form_lines(ax) == []
        assert any("seed map: no closed form" in text for text in _legend_texts(ax))


def test_plot_functions_create_a_figure_without_ax():
    before = set(plt.get_fignums())
    ax = PlotScrewTorque(_screw_traj(ScrewParams()), ScrewParams())
    assert ax.figure.number not in before and len(ax.figure.axes) == 1


@pytest.mark.parametrize("fields, net_labels", [
    (dict(), ["B and F net: polar (rays e1, circles e2)"]),
    (dict(adhesion="orthotropic", adhesion_angle=30.0, friction="orthotropic", friction_angle=30.0),
     ["B and F net: lines along e1 (30 deg)"]),
    (dict(adhesion="orthotropic", adhesion_angle=30.0, friction="polar"),
     ["B net: lines along e1 (30 deg)", "F net: polar (rays e1, circles e2)"]),
    (dict(adhesion="isotropic", friction="isotropic"), []),
])
def test_plot_block_path_over_the_field_net(fields, net_labels):
    p = BlockParams(**fields)
    s = np.linspace(0.0, 1.0, 50)
    traj = dict(x=p.x0 - 0.05 * s, y=p.y0 + 0.2 * s)
    fig, ax = plt.subplots()
    assert PlotBlockPath(traj, p, ax=ax) is ax
    nets = [c for c in ax.collections if isinstance(c, LineCollection)]
    assert [c.get_label() for c in nets] == net_labels
    assert all(len(c.get_segments()) >= 5 for c in nets)
    texts = _legend_texts(ax)
    assert "start" in texts and "centre path" in texts
    assert ("polar origin" in texts) == ("polar" in (p.adhesion, p.friction))
    if not net_labels:
        assert "isotropic B and F: no net" in texts
    start = [line for line in ax.get_lines() if line.get_label() == "start"][0]
    assert (start.get_xdata()[0], start.get_ydata()[0]) == (p.x0, p.y0)
    x0, x1 = ax.get_xlim()
    y0, y1 = ax.get_ylim()
    assert x0 < traj["x"].min() and x1 > traj["x"].max() and y0 < 0.0 < 0.2 < y1


def test_trajectory_png_keeps_incomplete_watermark_and_energy_warning(tmp_path, monkeypatch):
    """cli.plot_trajectory draws with the plot functions and still marks an incomplete run and an
    open energy ledger on the figure."""
    from matplotlib.figure import Figure
    texts = []
    original = Figure.savefig

    def spy(self, *a, **k):
        texts.extend((t.get_text(), t.get_color()) for t in self.texts)
        texts.extend((t.get_text(), None) for ax in self.axes for t in ax.get_legend().get_texts())
        return original(self, *a, **k)

    monkeypatch.setattr(Figure, "savefig", spy)
    p = ScrewParams()
    cli.plot_trajectory(str(tmp_path / "t.png"), "screw", _screw_traj(p), "title", p, incomplete=True,
                        warning="WARNING: energy ledger open")
    assert ("INCOMPLETE", "red") in texts and ("WARNING: energy ledger open", "red") in texts
    assert any(t.startswith("closed-form sliding torque") for t, _ in texts)
    assert (tmp_path / "t.png").stat().st_size > 5000


def test_drawn_lines_are_thinned_but_keep_their_ends():
    """A plotted line gets at most PLOT_VERTICES (+ the last) vertices, first and last kept: the
    legend's placement tests every vertex, which made long runs' plots cost more than their solve."""
    import numpy as np
    from exu_aniso.scenes import plotting
    t = np.arange(10001.0)
    a, b = plotting.drawn(t, 2 * t)
    assert a[0] == 0 and a[-1] == 10000 and len(a) <= plotting.PLOT_VERTICES + 1 and np.array_equal(b, 2 * a)
    short = np.arange(5.0)
    assert plotting.drawn(short)[0] is short


# ----------------------------------------------------------------------------------------------
# what a run cost: the steps against the nominal step

def test_step_accounting_and_its_warning():
    from exu_aniso.engines.result import step_accounting, step_warning
    dt = 0.01
    regular = np.linspace(0.0, 1.0, 101)
    acc = step_accounting(regular, dt)
    assert acc == dict(nominal_steps=100, step_reductions=0, smallest_step=pytest.approx(dt), reduced_between=[])
    assert step_warning(acc, 100, dt) is None
    cut = np.concatenate([np.linspace(0.0, 0.5, 51), 0.5 + np.cumsum(np.full(16, dt / 16)), np.linspace(0.52, 1.0, 49)])
    acc = step_accounting(cut, dt)
    assert acc["nominal_steps"] == 100 and acc["step_reductions"] == 16 and acc["smallest_step"] == pytest.approx(dt / 16)
    text = step_warning(acc, len(cut) - 1, dt)
    assert "115 steps where 100 were planned" in text and "--set dt" in text and "eps_n" in text
    assert acc["reduced_between"] == pytest.approx([0.5, 0.51]) and "between t = 0.5 and 0.51 s" in text
    # the last step shortened to land on the end time after the cuts is no reduction (the fe_screw scene's
    # run ended on a 0.000625 s step and its warning said the cuts spread over the whole run)
    landing = np.concatenate([cut, [cut[-1] + 0.4 * dt]])
    acc = step_accounting(landing, dt)
    assert acc["step_reductions"] == 16 and acc["reduced_between"] == pytest.approx([0.5, 0.51])
    # more than 10x the nominal steps
    many = np.concatenate([np.linspace(0.0, 0.9, 10), 0.9 + np.cumsum(np.full(200, 0.1 / 200))])
    assert "209 steps where 10 were planned" in step_warning(step_accounting(many, 0.1), 209, 0.1)


def test_output_rows_are_the_output_step():
    t = np.array([0.0, 0.1, 0.2, 0.3])
    assert cli.output_rows(t, 0.1).tolist() == [0, 1, 2, 3]
    refined = np.array([0.0, 0.05, 0.1, 0.125, 0.15, 0.175, 0.2, 0.3, 0.35])
    assert cli.output_rows(refined, 0.1).tolist() == [0, 2, 6, 7, 8]        # 0, 0.1, 0.2, 0.3 and the last
    assert cli.output_rows(refined, 0.2).tolist() == [0, 6, 8]


def test_a_run_whose_solver_cut_the_step_says_so_and_writes_its_output_step(tmp_path, capsys):
    """The full block with dt 0.05 s and eps_n 1e10 N/m: Newton needs smaller steps, so Exudyn takes
    12 steps where 4 were planned (the step cut to dt / 4). summary.json counts them, and
    trajectory.csv is written at the nominal step (or --output-step), not at every internal step."""
    import csv
    args = ["run", "block", "--quiet", "--set", "model=full", "--set", "dt=0.05", "--set", "eps_n=1e10",
            "--set", "t_end=0.2"]
    assert cli.main(args + ["--out", str(tmp_path / "a")]) == 0
    s = json.loads((tmp_path / "a" / "summary.json").read_text())
    assert s["nominal_steps"] == 4 and s["steps"] > 4 and s["step_reductions"] > 0 and s["smallest_step"] < 0.05
    assert s["output_step"] == 0.05 and s["step_warning"] is None          # cut to dt / 4: below the warning
    rows = list(csv.reader(open(tmp_path / "a" / "trajectory.csv")))[2:]
    assert [round(float(r[0]), 9) for r in rows] == [0.0, 0.05, 0.1, 0.15, 0.2]
    assert cli.main(args + ["--out", str(tmp_path / "b"), "--output-step", "0.1"]) == 0
    rows = list(csv.reader(open(tmp_path / "b" / "trajectory.csv")))[2:]
    assert [round(float(r[0]), 9) for r in rows] == [0.0, 0.1, 0.2]
    assert cli.main(args + ["--out", str(tmp_path / "c"), "--output-step", "0"]) == 0    # every step taken
    rows = list(csv.reader(open(tmp_path / "c" / "trajectory.csv")))[2:]
    assert len(rows) == s["steps"] + 1
    assert cli.main(args + ["--out", str(tmp_path / "d"), "--output-step", "-1"]) == 2
    assert "--output-step must be a finite time step >= 0" in capsys.readouterr().err
