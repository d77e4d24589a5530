"""Command line: ``exu-aniso run SCENE``, ``exu-aniso params SCENE`` and ``exu-aniso compile``.

    exu-aniso run SCENE|all [--engine exudyn|reference] [--set NAME=VALUE ...] [--out DIR]
                            [--quiet] [--snapshot] [--view]
    exu-aniso params SCENE
    exu-aniso compile [SCENE ...|all]

SCENE: one of the scene catalog (``exu_aniso.catalog``: block, screw, particle, capstan, feeder,
fastening, nut, loosening, fe_block, fe_screw).

``run`` writes DIR/trajectory.csv (header row of plain names; SI units listed under "units" in
summary.json), DIR/summary.json
and DIR/trajectory.png; ``all`` runs both scenes into DIR/block and DIR/screw. Every file is
written to a temporary name and moved into place, so a failed run leaves no half-written
result. Exit code 0 on success, 2 on bad names or values (with a message naming the
parameter, the rule and the value), 1 when the simulation fails.

An Exudyn run longer than about 2 s shows its progress on stderr (``exu_aniso.util.progress``; ``--quiet``
turns it off). ``--snapshot`` also writes DIR/snapshot.png, the final state rendered by Exudyn's
raytracer (no display needed); ``--view`` opens Exudyn's SolutionViewer on each run once all are
written (needs a display: without one it exits with 2 before simulating). Both need the Exudyn engine.
"""
from __future__ import annotations

import argparse
import contextlib
import io
import os
import sys
import tempfile
import textwrap

import numpy as np

from exu_aniso.engines.failure import SimulationFailure
from exu_aniso.util.output import atomic_write as _atomic_write
from exu_aniso.engines.result import step_accounting, step_warning
from exu_aniso.util.output import csv_rows, json_safe, write_json
from exu_aniso.util.result_folder import ResultFolderError, result_folder, run_identity
from exu_aniso.catalog import MAIN_JOB, MODELS, SCENES
from exu_aniso.util.validation import ParameterError

ENGINES = ("exudyn", "reference")
# trajectory columns written to CSV, in this order, with their SI units (plain names are the public
# interface; the units go to summary.json "units"); energy_*: the run's energy ledger
COLUMNS = {name: scene.columns for name, scene in SCENES.items()}


class UsageError(Exception):
    """Bad command-line input (exit code 2)."""


def parse_sets(pairs):
    """['name=value', ...] -> {name: value} (strings; parsed and validated by the params class)."""
    out = {}
    for item in pairs or []:
        if "=" not in item:
            raise UsageError(f"--set expects NAME=VALUE; got {item!r}")
        name, value = item.split("=", 1)
        name = name.strip()
        if name in out:
            raise UsageError(f"--set {name} given twice")
        out[name] = value.strip()
    return out


def make_params(scene, sets):
    try:
        return SCENES[scene].Params.from_strings(sets)
    except (ValueError, TypeError) as e:
        raise UsageError(f"{scene}: {e}") from None


VIEW_NO_DISPLAY = "--view needs a display ({}); use --snapshot, or run under xvfb-run -a"


def simulate(scene, params, engine, progress=False, snapshot=None, solution_file=None):
    """Run one scene with one engine; returns the engine's Result. Exudyn engine only: progress on
    stderr, snapshot (PNG file name of the final state), solution_file (Exudyn solution for --view)."""
    sc = SCENES[scene]
    if engine == "reference":
        return sc.reference(params)
    return MODELS[scene].run(params, progress=progress, snapshot=snapshot, solutionFile=solution_file)


def view_problem():
    """Why --view cannot open a render window here (message for exit code 2), or None. Checked
    before simulating: without a display Exudyn's renderer.Start() aborts the whole process."""
    from exu_aniso.engines.exudyn_adapter.runner import DisplayProblem
    problem = DisplayProblem()
    return VIEW_NO_DISPLAY.format(problem) if problem else None


def view_solution(scene, params, solution_file):
    """Exudyn's SolutionViewer on the solution a run wrote (the model is rebuilt from params)."""
    from exu_aniso.engines.exudyn_adapter.runner import ViewSolution
    ViewSolution(MODELS[scene].build(params), solution_file, title=f"exu-aniso {scene}")


def output_rows(t, step):
    """Indices of the samples written at the output step [s]: the first sample at or after each
    multiple of ``step`` from t[0], and the last. Every sample when the run kept its nominal step
    and ``step`` is that step; a run whose solver cut the step is written at the step asked for."""
    t = np.asarray(t, dtype=float)
    if len(t) < 2:
        return np.arange(len(t))
    k = np.floor((t - t[0]) / step * (1.0 + 1e-9) + 1e-9)     # the output interval of each sample
    first = np.flatnonzero(np.diff(k, prepend=-1.0) > 0)
    return first if first[-1] == len(t) - 1 else np.append(first, len(t) - 1)


def write_csv(path, scene, traj, step=None, stamp=None):
    """trajectory.csv: the scene's columns, at the output step ``step`` [s] (None: every sample);
    stamp: the run's identity, written as a first line "# stamp" (csv readers skip it with their
    comment option: ``util.output.read_table``, pandas' comment="#", numpy's comments="#")."""
    cols = [k for k in COLUMNS[scene] if k in traj]
    rows = slice(None) if step is None or "t" not in traj else output_rows(traj["t"], step)
    # each number as repr writes it: the shortest text that reads back to the same double
    rows = csv_rows(np.column_stack([np.asarray(traj[k], dtype=float)[rows] for k in cols])) if cols else b""
    head = "" if stamp is None else f"# {stamp}\n"
    _atomic_write(path, lambda f: f.write((head + ",".join(cols) + "\n").encode() + rows))


def plot_trajectory(path, scene, traj, title, params, incomplete=False, warning=None, stamp=None):
    """trajectory.png: the scene's plot (its scene module's Plot function, e.g. scenes.block.PlotBlock;
    see catalog). A failed run's plot says INCOMPLETE, an open
    energy ledger says so in red."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    sc = SCENES[scene]
    fig = plt.figure(figsize=sc.figsize)
    sc.plot(traj, params, fig)
    # the title wrapped to the figure's width (about 0.55 of the font size per character at 9 pt)
    width = max(int(sc.figsize[0] * 72 / (9 * 0.55)), 40)
    lines = [w for part in title.split("\n") for w in (textwrap.wrap(part, width) or [""])]
    fig.suptitle("\n".join(lines), fontsize=9, color="red" if incomplete or warning else "black")
    fig.tight_layout(rect=(0.0, 0.0, 1.0, 1.0 - 0.16 * len(lines) / sc.figsize[1]))
    if warning:      # the energy ledger does not close: say so on the figure itself
        fig.text(0.5, 0.01, warning, transform=fig.transFigure, ha="center", va="bottom", fontsize=8, color="red")
    if incomplete:   # a partial run must not pass for a finished one
        fig.text(0.5, 0.5, "INCOMPLETE", transform=fig.transFigure, ha="center", va="center", fontsize=40,
                 color="red", alpha=0.25, rotation=30)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110, metadata=None if stamp is None else {"Description": stamp})
    plt.close(fig)
    _atomic_write(path, lambda f: f.write(buf.getvalue()))


RESULT_FILES = ("trajectory.csv", "trajectory.png", "summary.json", "snapshot.png")


class IncompleteRun(RuntimeError):
    """A run whose state went non-finite (overflow, NaN), or one whose engine accepted steps without
    Newton's convergence (the reference engine's last resort at the step's floor, which Exudyn's
    solver would have failed at): its files are written with "complete": false and the command
    exits 1."""


def unconverged_steps(res):
    """The failure text of a run whose engine accepted steps without Newton's convergence (the
    reference engine's info: forced_accepts, max_forced_residual), or None."""
    n = int(res.info.get("forced_accepts") or 0)
    if not n:
        return None
    return (f"{n} step{'s' if n > 1 else ''} accepted without Newton's convergence (the largest scaled residual "
            f"{res.info['max_forced_residual']:.3g} against the tolerance {res.info.get('newton_tol', 1e-10):.3g}): "
            f"the results after the first of them are not the model's; use a smaller dt, or return_map exact "
            f"or radial where the seed map's jump at the stick/slip switch leaves a step without a root")


def check_out(out):
    """Refuse (UsageError) an --out that cannot take the results, before anything is simulated: a file
    on its path, a directory that cannot be created or written, or a result file name that is taken by
    something that is not a file. Leaves no directory behind (one made to try is removed)."""
    path = os.path.abspath(out)
    up = path
    while not os.path.exists(up):
        up = os.path.dirname(up)
    if not os.path.isdir(up):
        raise UsageError(f"--out must be a directory (created if missing); got {out!r}, but {up!r} is a file")
    if up != path:        # try to create it, then remove what was made: a killed run leaves no empty --out
        try:
            os.makedirs(path)
        except OSError as e:
            raise UsageError(f"--out must be a directory that can be created; got {out!r}: "
                             f"{e.strerror or e}") from None
        d = path
        while d != up:
            os.rmdir(d)
            d = os.path.dirname(d)
    elif not os.access(path, os.W_OK | os.X_OK):
        raise UsageError(f"--out must be a writable directory; got {out!r} (no write permission)")
    for name in RESULT_FILES:
        f = os.path.join(path, name)
        if os.path.lexists(f) and not os.path.isfile(f):
            raise UsageError(f"--out {out!r}: {name} exists and is not a file (a directory?); "
                             "remove it or choose another --out")


def run_scene(scene, params, engine, out, progress=False, snapshot=False, solution_file=None, output_step=None):
    """Simulate and write trajectory.csv, trajectory.png and summary.json ("complete": true), and
    with ``snapshot`` snapshot.png (Exudyn engine; only when the run completes); output_step: the
    step of trajectory.csv [s] (None: the scene's dt; write_outputs). The files go into a staging
    folder beside ``out`` that replaces ``out`` whole at the end (``util.result_folder.result_folder``: a
    lock refuses a second run into the same folder, a killed run leaves the earlier results as they
    were), and each carries the run's identity (run_id, params_hash: ``util.result_folder.run_identity``).

    When the simulation fails with a SimulationFailure carrying a partial trajectory, the three
    files are still written ("complete": false, the failure message, the plot marked INCOMPLETE)
    and the failure is re-raised; any other simulation error writes summary.json only. Either way
    the folder then holds the failed run's files alone. A run whose state went non-finite writes
    its files with "complete": false and raises IncompleteRun. Bad input found while preparing
    the run (ParameterError) writes nothing and leaves ``out`` as it was."""
    identity = run_identity(params.as_dict())
    with result_folder(out) as staging, tempfile.TemporaryDirectory(prefix="exu-aniso-snapshot-") as tmp:
        shot = os.path.join(tmp, "snapshot.png") if snapshot else None
        try:
            res = simulate(scene, params, engine, progress=progress, solution_file=solution_file, snapshot=shot)
        except SimulationFailure as failure:
            if failure.partial is not None:
                write_outputs(scene, params, engine, staging, failure.partial, failure.as_dict(), output_step,
                              identity)
            else:
                write_summary(staging, dict(failure.as_dict(), engine=engine, params=params.as_dict(), **identity))
            raise
        except ParameterError:       # bad input found while preparing the run: nothing is written (exit 2)
            raise
        except Exception as e:
            write_summary(staging, dict(complete=False, failure=f"{type(e).__name__}: {e}", engine=engine,
                                        params=params.as_dict(), **identity))
            raise
        bad = res.summary.get("state_nonfinite")
        if bad is not None:
            message = (f"the state went non-finite: {bad['column']} at t = {bad['t']:.6g} s (an overflow or a NaN; "
                       "check the parameters' magnitudes)")
            write_outputs(scene, params, engine, staging, res, dict(
                complete=False, failure=message, time_reached=bad["t"], end_time=float(res.trajectory["t"][-1])),
                output_step, identity)
            raise IncompleteRun(message)
        message = unconverged_steps(res)
        if message is not None:
            end = float(res.trajectory["t"][-1])
            write_outputs(scene, params, engine, staging, res, dict(
                complete=False, failure=message, time_reached=end, end_time=end,
                unconverged_steps=int(res.info["forced_accepts"]),
                unconverged_residual_max=float(res.info["max_forced_residual"])), output_step, identity)
            raise IncompleteRun(message)
        if shot is not None and os.path.exists(shot):
            _atomic_write(os.path.join(staging, "snapshot.png"), lambda f: f.write(open(shot, "rb").read()))
        return write_outputs(scene, params, engine, staging, res, output_step=output_step, identity=identity)


def write_summary(out, summary):
    """summary.json as strict JSON: undefined values are null (never NaN, which JSON does not
    have), each named with its reason under "undefined" (non-finite numbers: "not finite")."""
    undefined = dict(summary.get("undefined") or {})
    clean = json_safe({k: v for k, v in summary.items() if k != "undefined"}, undefined)
    clean["undefined"] = undefined
    write_json(os.path.join(out, "summary.json"), clean)


def write_outputs(scene, params, engine, out, res, failure=None, output_step=None, identity=None):
    """The three result files of one run; failure: None (complete) or SimulationFailure.as_dict();
    output_step [s]: the step of trajectory.csv (None: the scene's nominal step dt; 0: every step
    the solver took, the samples the energy ledger is integrated over); identity: dict run_id,
    params_hash (None: a new one, ``run_identity``), in summary.json, in trajectory.csv's first line
    (a comment) and in trajectory.png's metadata. summary.json also says how the steps went
    (nominal_steps, step_reductions, smallest_step, step_warning)."""
    if identity is None:
        identity = run_identity(params.as_dict())
    summary = dict(complete=failure is None, **identity)
    summary.update(res.summary)
    if failure is not None:
        summary.update(failure)
    summary["engine"] = engine
    if "t" in res.trajectory and len(res.trajectory["t"]) > 1:
        summary.update(step_accounting(res.trajectory["t"], params.dt))
        summary["step_warning"] = step_warning(summary, len(res.trajectory["t"]) - 1, params.dt)
    summary["output_step"] = params.dt if output_step is None else output_step
    summary["params"] = params.as_dict()
    summary["units"] = {k: u for k, u in COLUMNS[scene].items() if k in res.trajectory}
    stamp = f"exu-aniso run_id={identity['run_id']} params_hash={identity['params_hash']} scene={scene} engine={engine}"
    write_csv(os.path.join(out, "trajectory.csv"), scene, res.trajectory, summary["output_step"] or None, stamp)
    keys = SCENES[scene].title_keys_for(params)
    model = getattr(params, "model", None)
    title = f"{scene} ({engine}, {params.return_map} map{', ' + model if model else ''}): " + ", ".join(
        f"{k} = {summary[k]:.4g}" if summary.get(k) is not None else f"{k} undefined" for k in keys)
    if failure is not None:
        title = (f"INCOMPLETE: stopped at t = {failure['time_reached']:.4g} s of {failure['end_time']:.4g} s\n"
                 + title)
    warning = None
    if summary.get("energy_ok") is False:
        warning = (f"WARNING: energy ledger open, residual {summary['energy']['residual']:.3g} > "
                   f"{summary['energy_tolerance']:.3g}")
    plot_trajectory(os.path.join(out, "trajectory.png"), scene, res.trajectory, title, params,
                    incomplete=failure is not None, warning=warning, stamp=stamp)
    write_summary(out, summary)
    return summary


def main(argv=None):
    ap = argparse.ArgumentParser(prog="exu-aniso", description="Anisotropic frictional contact scenes for Exudyn")
    sub = ap.add_subparsers(dest="command", required=True)
    r = sub.add_parser("run", help="run a scene and write trajectory.csv, summary.json, trajectory.png")
    r.add_argument("scene", choices=(*SCENES, "all"),
                   help=f"a scene, or all: the main job, {' and '.join(MAIN_JOB)} (each into OUT/SCENE)")
    r.add_argument("--engine", choices=ENGINES, default="exudyn")
    r.add_argument("--set", dest="sets", action="append", default=[], metavar="NAME=VALUE",
                   help="override a parameter (see 'exu-aniso params SCENE'); repeatable")
    r.add_argument("--out", default="results", help="output directory (default: results)")
    r.add_argument("--output-step", type=float, default=None, metavar="DT",
                   help="time step of trajectory.csv [s] (default: the scene's dt; a run whose solver cut the "
                        "step is still written at this step; 0: every step the solver took, from which the energy "
                        "ledger can be recomputed)")
    r.add_argument("--quiet", action="store_true",
                   help="no progress display on stderr (shown for Exudyn runs longer than about 2 s)")
    r.add_argument("--snapshot", action="store_true",
                   help="also write DIR/snapshot.png: the final state rendered by Exudyn's raytracer "
                        "(no display needed; Exudyn engine)")
    r.add_argument("--view", action="store_true",
                   help="open Exudyn's SolutionViewer on the result after the run "
                        "(needs a display; Exudyn engine)")
    p = sub.add_parser("params", help="list the parameters of a scene with unit, default and rule")
    p.add_argument("scene", choices=tuple(SCENES))
    c = sub.add_parser("compile", help="compile the contact kernels of scenes' default runs now (pip install does "
                                       "it for the main job)")
    c.add_argument("scenes", nargs="*", metavar="SCENE",
                   help=f"scenes ({', '.join(SCENES)}), or all: the main job, {' and '.join(MAIN_JOB)} (default)")
    a = ap.parse_args(argv)
    try:
        if a.command == "params":
            print(SCENES[a.scene].Params.describe())
            return 0
        if a.command == "compile":
            unknown = [x for x in a.scenes if x not in (*SCENES, "all")]
            if unknown:
                raise UsageError(f"compile: no scene {unknown[0]!r}; choose from {', '.join(SCENES)} or all")
            return compile_kernels(a.scenes or ["all"])
        sets = parse_sets(a.sets)
        if a.output_step is not None and not (np.isfinite(a.output_step) and a.output_step >= 0):
            raise UsageError(f"--output-step must be a finite time step >= 0 [s] (0: every step the solver "
                             f"took); got {a.output_step!r}")
        scenes = MAIN_JOB if a.scene == "all" else (a.scene,)
        if a.scene == "all" and sets:
            raise UsageError(f"--set applies to one scene; run one of {', '.join(SCENES)} to override parameters")
        jobs = [(s, make_params(s, sets), os.path.join(a.out, s) if a.scene == "all" else a.out) for s in scenes]
        for _, _, out in jobs:
            check_out(out)
        for s in scenes:
            if a.engine == "reference" and SCENES[s].reference is None:
                raise UsageError(f"{s}: the reference engine has no model of this scene; use --engine exudyn")
        if (a.snapshot or a.view) and a.engine != "exudyn":
            raise UsageError("--snapshot and --view need --engine exudyn "
                             "(the reference engine has no Exudyn model to render)")
        if a.view and view_problem():
            raise UsageError(view_problem())
    except UsageError as e:
        print(f"exu-aniso: error: {e}", file=sys.stderr)
        return 2
    # --view: the runs' Exudyn solution files live in a temporary directory until the viewer closes
    try:
        with tempfile.TemporaryDirectory(prefix="exu-aniso-view-") if a.view else contextlib.nullcontext() as tmp:
            return _run_jobs(jobs, a, tmp)
    except KeyboardInterrupt:       # Ctrl-C: a run's folder is replaced only when the run ends (result_folder)
        print(f"\nexu-aniso: interrupted; {a.out} holds what it held before the interrupted run "
              f"(runs that ended before it are in place)", file=sys.stderr)
        return 130


COMPILE_STEPS = 5       # time steps of a compile run: every kernel of the scene's default run is called in them


def compile_kernels(scenes):
    """``exu-aniso compile``: compile (or find in the cache) every contact kernel that the scenes'
    default runs use, by simulating each scene's Exudyn model for COMPILE_STEPS time steps, its times
    scaled alike (the whole default run where the scene's rules forbid that; nothing written),
    several scenes in parallel worker processes on several cores. Prints how many kernels (contact
    laws and set kernels) it compiled and the wall time. Exit code 0, or 1 when a run failed."""
    import time

    names = list(dict.fromkeys(s for x in scenes for s in (MAIN_JOB if x == "all" else (x,))))
    start = time.perf_counter()
    done = list(_alongside(_compile_scene, [(s,) for s in names]))
    failures = [f for f, _ in done if f]
    for f in failures:
        print(f"exu-aniso: compile: {f}", file=sys.stderr)
    compiled = sum(n for _, n in done)
    print(f"exu-aniso: the contact kernels of {', '.join(names)}: {compiled} compiled, the others found in the "
          f"cache, in {time.perf_counter() - start:.1f} s", file=sys.stderr)
    return 1 if failures else 0


def _compile_scene(scene):
    """Simulate COMPILE_STEPS steps of a scene's defaults (its kernels compiled or loaded on the way):
    (None or the failure's message, the number of kernels compiled: laws and set kernels)."""
    from exu_aniso.kernel import compiling
    before = len(compiling.compiled_here)          # this process may have compiled another scene's before
    try:
        defaults = SCENES[scene].Params()
        # every time of the scene (t_end, a pressing's duration, ...) but the step scaled alike
        factor = COMPILE_STEPS * defaults.dt / defaults.t_end
        sets = {name: repr(getattr(defaults, name) * factor) for name, (_, unit, _, _) in defaults.TABLE.items()
                if unit == "s" and name != "dt"}
        try:
            params = make_params(scene, sets)
        except UsageError:      # a scene whose rules forbid so short a run (whole periods of a drive): all of it
            params = defaults
        simulate(scene, params, "exudyn")
    except Exception as e:      # noqa: BLE001 - reported, the exit code says it
        return f"{scene}: {type(e).__name__}: {e}", len(compiling.compiled_here) - before
    return None, len(compiling.compiled_here) - before


def _run_job(scene, params, engine, out, progress, snapshot, solution_file, output_step=None):
    """Run one scene (run_scene) and say how it went, as _run_jobs prints it: (exit code, the
    stdout line or None, the stderr message or None). Everything a worker process returns is this
    plain tuple."""
    try:
        summary = run_scene(scene, params, engine, out, progress=progress, snapshot=snapshot,
                            solution_file=solution_file, output_step=output_step)
    except SimulationFailure as e:  # message with time, step size and contact state; partial results kept
        kept = "partial trajectory.csv, trajectory.png and" if e.partial is not None else "only"
        return 1, None, (f"exu-aniso: {scene} ({engine}) did not complete: {e}\n"
                         f"({kept} summary.json with \"complete\": false written to {out})")
    except IncompleteRun as e:
        return 1, None, (f"exu-aniso: {scene} ({engine}) did not complete: {e}\n(trajectory.csv, trajectory.png "
                         f"and summary.json with \"complete\": false written to {out})")
    except (ParameterError, ResultFolderError) as e:  # bad input found while preparing the run, or its folder
        return 2, None, f"exu-aniso: error: {scene}: {e}"
    except Exception as e:  # report the failure with context, keep the exit code meaningful
        return 1, None, f"exu-aniso: {scene} ({engine}) failed: {type(e).__name__}: {e}"
    # basis_warning (fe_screw): printed as a BasisWarning while the run was made, as an EnergyWarning is
    show = {k: v for k, v in summary.items() if k not in ("params", "units", "step_warning", "basis_warning")}
    warning = summary.get("step_warning")
    return 0, f"{scene} [{engine}] -> {out}: " + ", ".join(
        f"{k}={v:.6g}" if isinstance(v, float) else f"{k}={v}" for k, v in show.items()), (
        f"exu-aniso: warning: {scene}: {warning}" if warning else None)


def _parallel(jobs, a):
    """True when the jobs run in worker processes, one per scene: several Exudyn jobs whose contact
    kernels are not compiled yet (the first run on a machine), on more than one core. Each scene
    compiles its own kernels (its surface and fields), so on 2 cores the first ``run all`` takes
    the longer compile, not the sum (docs/guide/command_line.md). The
    last job runs in this process, the others in workers started before it (one process start
    and its imports fewer, and the screw, which compiles longest, starts first). Warm runs stay in
    this process (a worker's start costs more than the runs)."""
    if len(jobs) < 2 or a.engine != "exudyn" or (os.cpu_count() or 1) < 2:
        return False
    from exu_aniso.kernel.compiling import kernels_cached
    from exu_aniso.kernel.law_call import law_entry
    return not kernels_cached(law_entry)


def _run_jobs(jobs, a, tmp):
    """Run the scenes (exit 1 at the first failure, in the order of jobs); then, with --view, view
    each one. Several scenes with kernels still to compile run in parallel worker processes
    (_parallel); their reports are printed in order, and those after a failure are not."""
    parallel = _parallel(jobs, a)
    # in parallel, the first job alone shows its progress (two progress lines would overwrite each other)
    args = [(scene, params, a.engine, out, not a.quiet and (k == 0 or not parallel), a.snapshot,
             os.path.join(tmp, f"{scene}.sol") if tmp is not None else None, a.output_step)
            for k, (scene, params, out) in enumerate(jobs)]
    if parallel:
        # in order, the first reports as their workers finish
        code = _print_reports(_alongside(_run_job, args))
    else:
        code = _print_reports(_run_job(*x) for x in args)
    if code:
        return code
    for scene, params, _, _, _, _, solution_file, _ in args:
        if solution_file is None:
            continue
        sys.stdout.flush()
        try:
            view_solution(scene, params, solution_file)
        except Exception as e:
            print(f"exu-aniso: --view of {scene} failed: {type(e).__name__}: {e}", file=sys.stderr)
            return 1
    return 0


def _alongside(fn, calls):
    """fn(*c) for each c of calls, in order: the last in this process, which is ready first (its imports
    are done), the others in worker processes meanwhile (one per core but this one). A generator:
    each result as it is needed. (run all's last scene, the screw, compiles longest.)"""
    import concurrent.futures
    import multiprocessing
    workers = min(len(calls) - 1, (os.cpu_count() or 1) - 1)
    if workers < 1:
        yield from (fn(*c) for c in calls)
        return
    with concurrent.futures.ProcessPoolExecutor(max_workers=workers,
                                                mp_context=multiprocessing.get_context("spawn")) as pool:
        futures = [pool.submit(fn, *c) for c in calls[:-1]]
        last = fn(*calls[-1])
        yield from (f.result() for f in futures)
        yield last


def _print_reports(reports):
    """Print the reports of _run_job in order up to the first failure; its exit code (0: none)."""
    for code, line, message in reports:
        if line is not None:
            print(line, flush=True)
        if message is not None:
            print(message, file=sys.stderr, flush=True)
        if code:
            return code
    return 0


if __name__ == "__main__":
    sys.exit(main())
