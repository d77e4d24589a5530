"""Progress display (exu_aniso.util.progress): the formatter on synthetic input, the rate limiting with a
fake clock (terminal and log modes), and the Exudyn pre-step hook (chaining, counts, removal)."""
import io

import pytest

from exu_aniso.util.progress import (AFTER_ENV, DEFAULT_AFTER, LOG_INTERVAL, TTY_INTERVAL, Progress, default_after,
                                eta_seconds, format_duration, format_progress, fraction_done)


class FakeClock:
    def __init__(self, now=100.0):
        self.now = now

    def __call__(self):
        return self.now


class FakeTTY(io.StringIO):
    def isatty(self):
        return True


@pytest.mark.parametrize("seconds, text", [
    (0.0, "0.0 s"), (0.44, "0.4 s"), (9.94, "9.9 s"), (12.4, "12 s"), (59.4, "59 s"), (125.0, "2 min 05 s"),
    (3725.0, "1 h 02 min"), (None, "?"), (float("nan"), "?"), (float("inf"), "?"), (-1.0, "?")])
def test_format_duration(seconds, text):
    assert format_duration(seconds) == text


def test_fraction_and_eta():
    assert fraction_done(0.5, 2.0) == 0.25
    assert fraction_done(1.5, 2.0, start_time=1.0) == 0.5
    assert fraction_done(-1.0, 2.0) == 0.0 and fraction_done(3.0, 2.0) == 1.0
    assert fraction_done(1.0, 1.0, start_time=1.0) == 1.0          # empty span: done
    assert eta_seconds(0.25, 1.0) == pytest.approx(3.0)            # a quarter in 1 s: 3 s to go
    assert eta_seconds(1.0, 5.0) == 0.0
    assert eta_seconds(0.0, 1.0) is None and eta_seconds(0.5, 0.0) is None


def test_format_progress_percent_eta_rate_newton():
    line = format_progress("block", 0.5, 2.0, elapsed=1.0, steps=500, newton_iterations=1250)
    assert line == ("block:  25.0 % (t = 0.5 of 2 s), ETA 3.0 s, 500 steps/s, 1250 Newton iterations "
                    "(2.50 per step)")
    # a run started at t = 1: the percentage and the ETA count from there
    line = format_progress("", 1.5, 3.0, elapsed=30.0, steps=6000, newton_iterations=6000, start_time=1.0)
    assert line.startswith(" 25.0 % (t = 1.5 of 3 s), ETA 1 min 30 s, 200 steps/s, 6000 Newton iterations")
    # before the first step nothing is known about the rate
    assert "ETA ?, ? steps/s, 0 Newton iterations" in format_progress("screw", 0.0, 1.0, 0.3, 0, 0)


def test_default_after_from_environment(monkeypatch):
    monkeypatch.delenv(AFTER_ENV, raising=False)
    assert default_after() == DEFAULT_AFTER == 2.0
    for text, value in (("0", 0.0), ("0.5", 0.5), ("abc", 2.0), ("-1", 2.0), ("nan", 2.0), ("", 2.0)):
        monkeypatch.setenv(AFTER_ENV, text)
        assert default_after() == value, text


def _drive(progress, clock, calls):
    """Feed (clock, t, steps, newton) calls through due/update as the pre-step hook does."""
    for now, t, steps, newton in calls:
        clock.now = now
        if progress.due():
            progress.update(t, steps, newton)


def test_log_mode_plain_lines_every_interval_and_a_final_line():
    clock, out = FakeClock(), io.StringIO()
    p = Progress("block", stream=out, after=2.0, clock=clock).start(10.0)
    assert not p.tty and p.interval == LOG_INTERVAL
    # set-up takes 0.5 s; then 1000 steps per second of wall time, 0.1 s simulated per wall second
    calls = [(100.5 + w, 0.1 * w, int(1000 * w), int(2000 * w)) for w in [i * 0.01 for i in range(0, 601)]]
    _drive(p, clock, calls)
    lines = out.getvalue().splitlines()
    assert "\r" not in out.getvalue()
    # first line when 2 s have passed since the start (at w = 1.5), then every 2 s: w = 3.5, 5.5
    assert len(lines) == 3 and p.shown == 3
    assert lines[0] == ("block:   1.5 % (t = 0.15 of 10 s), ETA 1 min 38 s, 1000 steps/s, "
                        "3000 Newton iterations (2.00 per step)")
    assert lines[1].startswith("block:   3.5 % (t = 0.35 of 10 s)")
    clock.now = 106.5
    p.finish(t=10.0, steps=6000, newton_iterations=12000)
    assert out.getvalue().splitlines()[-1] == ("block: 100.0 % (t = 10 s) in 6.5 s, 1000 steps/s, "
                                               "12000 Newton iterations")


def test_tty_mode_rewrites_one_line_at_most_four_times_a_second():
    clock, out = FakeClock(), FakeTTY()
    p = Progress("screw", stream=out, after=0.0, clock=clock).start(1.0)
    assert p.tty and p.interval == TTY_INTERVAL
    calls = [(100.0 + w, w, int(100 * w), int(100 * w)) for w in [i * 0.01 for i in range(0, 101)]]
    _drive(p, clock, calls)
    text = out.getvalue()
    assert "\n" not in text and text.count("\r") == p.shown
    assert 4 <= p.shown <= 5            # 1 s of stepping at 0.25 s intervals (plus the first update)
    clock.now = 101.0
    p.finish(t=1.0, steps=100, newton_iterations=100, ok=False)
    last = out.getvalue().split("\r")[-1]
    assert last.startswith("screw: stopped at t = 1 of 1 s after 1.0 s") and last.endswith("\n")


def test_tty_mode_wipes_a_longer_previous_line():
    out = FakeTTY()
    p = Progress("x", stream=out, after=0.0, clock=FakeClock()).start(1.0)
    p._write("a long line")
    p._write("short")
    assert out.getvalue() == "\ra long line\rshort      "


def test_short_run_prints_nothing():
    clock, out = FakeClock(), io.StringIO()
    p = Progress("block", stream=out, after=2.0, clock=clock).start(1.0)
    _drive(p, clock, [(100.0 + 0.1 * i, 0.1 * i, i, i) for i in range(15)])
    clock.now = 101.5
    p.finish(t=1.0, steps=15, newton_iterations=15)
    assert out.getvalue() == "" and p.shown == 0


def test_exudyn_hook_chains_counts_and_is_removed():
    """SolveTimed with progress: the system's own pre-step function still runs every step and is
    restored afterwards; the lines carry the solver's step and Newton counts (full Newton: 2 iterations
    in every step of this sliding block)."""
    from exu_aniso.models.block import BuildBlock
    from exu_aniso.engines.exudyn_adapter.runner import SolveTimed
    from exu_aniso.scenes.block import BlockParams
    model = BuildBlock(BlockParams(t_end=0.05, dt=1e-3), newton="full")
    mbs = model["mbs"]
    calls = []

    def own(mbs, t):
        calls.append(t)
        return True

    mbs.SetPreStepUserFunction(own)
    out = io.StringIO()
    wall, steps, iters, info = SolveTimed(mbs, model["simulationSettings"], model["solverType"],
                                          progress=Progress("block", stream=out, after=0.0, interval=0.0))
    assert steps == 50 and len(calls) == 50
    lines = out.getvalue().splitlines()
    assert len(lines) >= 10 and lines[-1].startswith("block: 100.0 % (t = 0.05 s) in ")
    assert lines[-1].endswith(f"steps/s, {iters} Newton iterations")
    last = lines[-2]                                        # the last running update: 49 steps done
    assert "98.0 % (t = 0.049 of 0.05 s)" in last and "(2.00 per step)" in last
    assert mbs.GetPreStepUserFunction()["function"] is own


def test_exudyn_hook_is_off_by_default_and_leaves_no_function(capsys, monkeypatch):
    monkeypatch.delenv(AFTER_ENV, raising=False)
    from exu_aniso.models.block import BuildBlock, RunBlock
    from exu_aniso.engines.exudyn_adapter.runner import SolveTimed
    from exu_aniso.scenes.block import BlockParams
    model = BuildBlock(BlockParams(t_end=0.01))
    SolveTimed(model["mbs"], model["simulationSettings"], model["solverType"], progress=True)
    assert model["mbs"].GetPreStepUserFunction() == 0
    RunBlock(BlockParams(t_end=0.01))
    assert capsys.readouterr().err == ""                   # short run: nothing even when on; off by default
    with pytest.raises(TypeError, match="progress must be a bool"):
        RunBlock(BlockParams(t_end=0.01), progress="yes")
