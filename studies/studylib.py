"""Plumbing shared by the study scripts in ``studies/`` (not part of the installed package).

Every study is a script ``studies/NAME.py`` that

1. parses the common command line (``parse_args``): ``--quick`` (a small sweep the test suite runs
   in seconds), ``--out DIR`` (default ``docs/results/NAME``, the committed results; with
   ``--quick`` ``studies/results/NAME``, which git ignores), ``--serial`` / ``--processes N``
   (multiprocessing through Exudyn's ``ParameterVariation``, default: all cores) and ``--mpi``
   (``ParameterVariation(..., useMPI=True)``: start the script with
   ``mpiexec -n 4 python -m mpi4py.futures studies/NAME.py --mpi`` on a cluster; needs mpi4py);
2. computes its cases with ``sweep`` (one call of ``exudyn.processing.ParameterVariation``;
   the case function must be defined at module level so that worker processes can find it);
3. writes CSV tables with the unit in every column name (``table``), e.g. ``t [s]``, ``r_spread [-]``;
4. plots *from the CSV files it wrote* (``read_table``) into PNGs beside them;
5. writes ``report.md`` (its section of the results document: tables generated from the CSV,
   figure links, the wall time of the run and the machine) and ``timing.json``.

All files are written atomically (``exu_aniso.output``); a study that fails leaves no file
half-written. ``python studies/run_all.py`` runs every study and assembles ``docs/RESULTS.md``.
"""
from __future__ import annotations

import argparse
import os
import platform
import sys
import time

from exu_aniso.output import read_table, write_json, write_table, write_text

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
__all__ = ["HERE", "parse_args", "sweep", "table", "read_table", "write_json", "write_text", "Timer",
           "machine", "markdown_table", "finish"]


def parse_args(name, description, argv=None, extra=None):
    """Common study command line; ``extra(parser)`` may add study-specific options."""
    ap = argparse.ArgumentParser(prog=f"studies/{name}.py", description=description)
    ap.add_argument("--quick", action="store_true", help="small sweep with short runs (what the test suite runs)")
    ap.add_argument("--out", default=None,
                    help="output directory (default docs/results/NAME; with --quick studies/results/NAME)")
    ap.add_argument("--serial", action="store_true", help="no multiprocessing (one case after the other)")
    ap.add_argument("--processes", type=int, default=None, help="worker processes (default: all cores)")
    ap.add_argument("--mpi", action="store_true",
                    help="distribute with MPI (ParameterVariation useMPI; needs mpi4py, run under mpiexec)")
    if extra is not None:
        extra(ap)
    args = ap.parse_args(argv)
    args.name = name
    if args.out is None:
        args.out = os.path.join(HERE, "results", name) if args.quick else os.path.join(ROOT, "docs", "results", name)
    os.makedirs(args.out, exist_ok=True)
    return args


def _call_case(parameterSet):
    """ParameterVariation's parameter function: run case number parameterSet['case']."""
    data = parameterSet["functionData"]
    i = int(parameterSet["case"])
    case = data["cases"][i]
    t0 = time.perf_counter()
    result = data["function"](case)
    if data["progress"]:
        print(f"  [{data['name']}] case {i + 1}/{len(data['cases'])} done in {time.perf_counter() - t0:.1f} s: "
              + ", ".join(f"{k}={v}" for k, v in case.items()), flush=True)
    return result


def sweep(function, cases, args, progress=True):
    """Evaluate ``function(case)`` for every dict in ``cases`` with Exudyn's ParameterVariation
    (multiprocessing unless ``args.serial``; MPI with ``args.mpi``); returns the results in case
    order. ``function`` must be a module-level function (picklable by reference)."""
    from exudyn.processing import ParameterVariation

    cases = list(cases)
    if not cases:
        return []
    parallel = not args.serial and len(cases) > 1
    kw = dict(useMPI=True) if args.mpi else {}
    data = dict(function=function, cases=cases, progress=progress, name=args.name)
    _, values = ParameterVariation(_call_case, parameters={"case": list(range(len(cases)))},
                                   useMultiProcessing=parallel or args.mpi, showProgress=False,
                                   numberOfThreads=args.processes or os.cpu_count(), parameterFunctionData=data, **kw)
    return list(values)


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
