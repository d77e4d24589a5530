"""What a first run compiles, and how long it takes: the contact kernels of every scene's default run
compiled from an empty cache.

    python studies/compile_times.py [--quick] [--out DIR]

Each scene runs ``exu-aniso compile SCENE`` in a fresh process with an empty kernel cache (its own
``NUMBA_CACHE_DIR``), one scene after the other: the kernels it compiles, its contact laws (one per
surface, nets and return map) and its set kernels (one per node kind, fixed or moving master), what
each is for (``exu_aniso.kernel.compiling.kernel_name``) and its compilation's wall time, which holds
every function it calls; the process's whole wall time (imports, the kernels, the small compiled
helpers of the energy ledger and the native callbacks, five time steps) and how many compiled
functions its cache then holds. The range of each kind's times is what the compile announcement
quotes (``exu_aniso.kernel.compiling.COMPILE_SECONDS``; tests/test_compile_cache.py holds the two
together).
--quick: the block only. Writes ``compile_times.json`` and ``report.md`` (default
``studies/results/compile_times``).
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
if HERE not in sys.path:
    sys.path.insert(0, HERE)

from _lib.studylib import Timer, finish, markdown_table, timing_args  # noqa: E402

from exu_aniso.catalog import SCENES  # noqa: E402
from exu_aniso.util.output import write_json  # noqa: E402

NAME = "compile_times"

# run in the fresh process: compile the scene, print what was compiled as JSON on the last line
_PROBE = """
import json, sys
from exu_aniso import cli
from exu_aniso.kernel import compiling
failure, _ = cli._compile_scene(sys.argv[1])
print(json.dumps(dict(failure=failure, kernels=[dict(kernel=name, kind=compiling.kernel_kind(entry), seconds=s)
                                                  for (entry, _), (name, s) in compiling.compiled_here.items()])))
"""


def compile_scene(scene):
    """One scene compiled from an empty cache in a fresh process: a dict of its kernels, wall time
    and cached functions."""
    with tempfile.TemporaryDirectory(prefix="exu-aniso-compile-times-") as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        start = time.perf_counter()
        done = subprocess.run([sys.executable, "-c", _PROBE, scene], env=env, capture_output=True, text=True,
                              check=True)
        wall = time.perf_counter() - start
        out = json.loads(done.stdout.strip().splitlines()[-1])
        if out["failure"]:
            raise RuntimeError(f"{scene}: {out['failure']}")
        functions = sum(1 for _, _, files in os.walk(cache) for f in files if f.endswith(".nbc"))
    return dict(scene=scene, wall_s=wall, cached_functions=functions, kernels=out["kernels"])


def _by_kind(kernels):
    """The compilations' times [s] by kind of kernel ("law", "fixed", "moving")."""
    out = {}
    for k in kernels:
        out.setdefault(k["kind"], []).append(k["seconds"])
    return out


def main(argv=None):
    args, _ = timing_args(NAME, __doc__, argv, quick_repeats=1, full_repeats=1)
    timer = Timer()
    scenes = ("block",) if args.quick else tuple(SCENES)
    rows = [compile_scene(s) for s in scenes]
    kernels = [dict(scene=r["scene"], **k) for r in rows for k in r["kernels"]]
    os.makedirs(args.out, exist_ok=True)
    write_json(os.path.join(args.out, "compile_times.json"), dict(scenes=rows, kernels=kernels))
    body = ("Each scene's default run compiled from an empty kernel cache in a fresh process "
            "(`exu-aniso compile SCENE`), one scene after the other.\n\n"
            + markdown_table(["scene", "kernel", "kind", "its compilation [s]"],
                             [[k["scene"], k["kernel"], k["kind"], f"{k['seconds']:.1f}"] for k in kernels])
            + "\n\n" + markdown_table(["scene", "process wall time [s]", "compiled functions cached"],
                                      [[r["scene"], f"{r['wall_s']:.1f}", str(r["cached_functions"])]
                                       for r in rows])
            + "\n\nThe ranges the compile announcement quotes, by kind: "
            + "; ".join(f"{kind} {min(t):.1f} to {max(t):.1f} s" for kind, t in _by_kind(kernels).items()) + ".\n")
    finish(args, timer, body, "Compile times")


if __name__ == "__main__":
    main()
