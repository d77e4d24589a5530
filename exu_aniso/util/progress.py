"""Progress of a running simulation on stderr: simulated time in percent, ETA, steps/s, Newton iterations.

A run that finishes within ``after`` seconds (default 2 s, environment variable
``EXU_ANISO_PROGRESS_AFTER`` overrides it, e.g. 0 in tests) prints nothing. A longer run prints

    block: 45.2 % (t = 0.904 of 2 s), ETA 3.1 s, 1520 steps/s, 4210 Newton iterations (2.77 per step)

on a terminal as ONE line rewritten in place with a carriage return, at most ``TTY_INTERVAL``
(0.25 s) apart; into a file or pipe as plain lines every ``LOG_INTERVAL`` (2 s). Once anything has
been printed, ``finish`` closes with a final line (total wall time, or where the run stopped).

The solver side is ``exu_aniso.engines.exudyn_adapter.runner.exudyn_pre_step``: an Exudyn pre-step
user function (chained with any existing one) that reads a clock and returns until the next update is
due; only then does it read the step count and Newton iterations of the solver. This module does not
import exudyn. The ETA extrapolates the wall time per simulated second so far.
"""
from __future__ import annotations

import math
import os
import sys
import time

AFTER_ENV = "EXU_ANISO_PROGRESS_AFTER"   # seconds before the first update (tests set 0)
DEFAULT_AFTER = 2.0                      # [s] runs shorter than this print nothing
TTY_INTERVAL = 0.25                      # [s] between rewrites of the line on a terminal
LOG_INTERVAL = 2.0                       # [s] between plain lines into a file or pipe


def default_after():
    """Seconds before the first update: $EXU_ANISO_PROGRESS_AFTER if set to a number >= 0, else 2."""
    text = os.environ.get(AFTER_ENV, "").strip()
    if text:
        try:
            v = float(text)
        except ValueError:
            v = float("nan")
        if math.isfinite(v) and v >= 0.0:
            return v
    return DEFAULT_AFTER


def format_duration(seconds):
    """'0.4 s', '12 s', '2 min 05 s', '1 h 02 min'; '?' when unknown (None, negative or not finite)."""
    if seconds is None or not math.isfinite(seconds) or seconds < 0.0:
        return "?"
    if seconds < 10.0:
        return f"{seconds:.1f} s"
    s = int(round(seconds))
    if s < 60:
        return f"{s} s"
    if s < 3600:
        return f"{s // 60} min {s % 60:02d} s"
    return f"{s // 3600} h {(s % 3600) // 60:02d} min"


def fraction_done(t, end_time, start_time=0.0):
    """Simulated fraction of [start_time, end_time] reached at t, clipped to [0, 1]."""
    span = end_time - start_time
    if not span > 0.0:
        return 1.0
    return min(max((t - start_time) / span, 0.0), 1.0)


def eta_seconds(fraction, elapsed):
    """Remaining wall time at the rate so far (elapsed per fraction done); None before any progress."""
    if not (fraction > 0.0 and elapsed > 0.0):
        return None
    return elapsed * (1.0 - fraction) / fraction


def format_progress(label, t, end_time, elapsed, steps, newton_iterations, start_time=0.0):
    """One progress line (no line end): t the simulated time reached [s] of [start_time, end_time],
    elapsed the wall time spent on it [s], steps taken in that time, newton_iterations the total so
    far. ETA (at the simulated rate so far) and steps/s are '?' before the first step."""
    frac = fraction_done(t, end_time, start_time)
    rate = f"{steps / elapsed:.0f}" if steps > 0 and elapsed > 0.0 else "?"
    eta = eta_seconds(frac, elapsed) if steps > 0 else None
    per_step = f" ({newton_iterations / steps:.2f} per step)" if steps > 0 else ""
    head = f"{label}: " if label else ""
    return (f"{head}{100.0 * frac:5.1f} % (t = {t:.4g} of {end_time:.4g} s), ETA {format_duration(eta)}, "
            f"{rate} steps/s, {newton_iterations} Newton iterations{per_step}")


class Progress:
    """Rate-limited progress display of one run.

    label: prefix of the line (e.g. the scene); stream: default sys.stderr (looked up at start);
    after: seconds before the first update (None: ``default_after()``); interval: seconds between
    updates (None: TTY_INTERVAL on a terminal, LOG_INTERVAL otherwise); tty: rewrite one line with
    '\\r' (None: stream.isatty()); clock: wall clock (time.perf_counter; tests pass a fake).

    Use: ``start(end_time)``, then ``due(now)`` (cheap) and ``update(t, steps, newton)`` when due
    (the first call is due at once: it marks the first step, so that the rates leave out the
    solver's set-up), then ``finish(...)``."""

    def __init__(self, label="", stream=None, after=None, interval=None, tty=None, clock=time.perf_counter):
        self.label = label
        self.stream = stream
        self.after = default_after() if after is None else float(after)
        self.interval = interval
        self.tty = tty
        self.clock = clock
        self.shown = 0            # number of updates written
        self.next_due = math.inf
        self._width = 0
        self.t0 = None

    def start(self, end_time, start_time=0.0):
        if self.stream is None:
            self.stream = sys.stderr
        if self.tty is None:
            isatty = getattr(self.stream, "isatty", None)
            try:
                self.tty = bool(isatty()) if isatty is not None else False
            except (ValueError, OSError):   # closed stream
                self.tty = False
        if self.interval is None:
            self.interval = TTY_INTERVAL if self.tty else LOG_INTERVAL
        self.end_time, self.start_time = float(end_time), float(start_time)
        self.t0 = self.clock()
        self.first = None         # (clock, t, steps) at the first step: rates exclude the solver's set-up
        self.next_due = -math.inf  # the first call only records the start of stepping
        self.shown = 0
        return self

    def due(self, now=None):
        return (self.clock() if now is None else now) >= self.next_due

    def _write(self, text, final=False):
        if self.tty:
            pad = " " * max(self._width - len(text), 0)   # wipe the rest of a longer previous line
            self._width = len(text)
            self.stream.write("\r" + text + pad + ("\n" if final else ""))
        else:
            self.stream.write(text + "\n")
        try:
            self.stream.flush()
        except (AttributeError, ValueError, OSError):
            pass

    def update(self, t, steps, newton_iterations, now=None):
        """Call when ``due`` with the simulated time reached t and the counts so far. The first call
        (at the first step) records where stepping started; later ones write the line (steps/s and
        ETA from the stepping since then) and schedule the next update."""
        now = self.clock() if now is None else now
        if self.first is None:
            self.first = (now, float(t), int(steps))
            self.next_due = self.t0 + self.after
            if not now >= self.next_due:
                return
        c0, tt0, s0 = self.first
        self._write(format_progress(self.label, t, self.end_time, now - c0, steps - s0, newton_iterations,
                                    tt0))
        self.shown += 1
        self.next_due = now + self.interval

    def finish(self, t=None, steps=None, newton_iterations=None, ok=True, now=None):
        """Close the display: a final line if anything was shown (nothing for a short run)."""
        self.next_due = math.inf
        if not self.shown:
            return
        now = self.clock() if now is None else now
        elapsed = now - self.t0
        head = f"{self.label}: " if self.label else ""
        if ok:
            c0, _, s0 = self.first if self.first is not None else (self.t0, 0.0, 0)
            rate = f", {(steps - s0) / (now - c0):.0f} steps/s" if steps and now > c0 else ""
            its = f", {newton_iterations} Newton iterations" if newton_iterations is not None else ""
            ended = (f"100.0 % (t = {self.end_time:.4g} s)" if t is None or t >= self.end_time * (1.0 - 1e-9)
                     else f"ended by the model at t = {t:.4g} of {self.end_time:.4g} s")
            text = f"{head}{ended} in {format_duration(elapsed)}{rate}{its}"
        else:
            where = f" at t = {t:.4g} of {self.end_time:.4g} s" if t is not None else ""
            text = f"{head}stopped{where} after {format_duration(elapsed)}"
        self._write(text, final=True)


def make_progress(progress, label=""):
    """None for a falsy ``progress``; a Progress(label) for True; a Progress instance as it is."""
    if progress is None or progress is False:
        return None
    if progress is True:
        return Progress(label)
    if isinstance(progress, Progress):
        return progress
    raise TypeError("progress must be a bool or an exu_aniso.util.progress.Progress; "
                    f"got {type(progress).__name__}")
