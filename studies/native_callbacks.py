"""Native callbacks against Python callbacks: what it costs when Exudyn calls the compiled contact
kernel through Python user functions, and what the native callbacks save.

    python studies/native_callbacks.py [--quick] [--repeats N] [--out DIR]

Every scene (full block on 4 corners and on an 8 x 8 grid, the reduced screw, the particle; their
defaults) is built twice per repeat, once with every contact set on Python user functions
(``CreateAnisotropicContact(nativeCallbacks=False)``) and once on the native callbacks (C++
functions that run the same compiled kernel: docs/native_callbacks.md), the two solved one after
the other (interleaved repeats, serial, process CPU time of the solve per step, medians with min and
max). ``identical``: the two runs' sensors (trajectory, history, dissipation) are equal bit for bit.
Writes ``native_callbacks.csv`` and ``report.md`` (default ``studies/results/native_callbacks``).
"""
from __future__ import annotations

import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
if HERE not in sys.path:
    sys.path.insert(0, HERE)

from _lib.studylib import Timer, finish, markdown_table, sweep, table, timing_args  # noqa: E402

NAME = "native_callbacks"
SCENES = [("block", dict(model="full", points="corners")), ("block", dict(model="full", points="grid:8")),
          ("screw", dict()), ("particle", dict())]
COLUMNS = ["scene [-]", "layout [-]", "python_per_step [s]", "python_min [s]", "python_max [s]",
           "native_per_step [s]", "native_min [s]", "native_max [s]", "native_over_python [-]",
           "newton_per_step [-]", "identical [-]"]


def _build(scene, p, native):
    """The scene's model with every contact set on the chosen callbacks."""
    from exu_aniso.engines.exudyn_adapter import create_contact
    builders = {"block": "exu_aniso.models.block:BuildBlock", "screw": "exu_aniso.models.screw:BuildScrew",
                "particle": "exu_aniso.models.particle:BuildParticle"}
    module, name = builders[scene].split(":")
    build = getattr(__import__(module, fromlist=[name]), name)
    create = create_contact.CreateAnisotropicContact

    def chosen(*args, **kwargs):
        kwargs["nativeCallbacks"] = native
        return create(*args, **kwargs)
    create_contact.CreateAnisotropicContact = chosen
    try:
        return build(p)
    finally:
        create_contact.CreateAnisotropicContact = create


def _sensors(model):
    mbs = model["mbs"]
    named = list(model.get("sensors", {}).values()) + [model["contact"][k] for k in ("sHistory", "sDissipation")
                                                       if k in model["contact"]]
    return [mbs.GetSensorStoredData(s) for s in named]


def run_case(case):
    """One scene, both callbacks, interleaved repeats: a row of COLUMNS."""
    from exu_aniso.engines.exudyn_adapter.runner import SolveTimed
    from exu_aniso.scenes.block import BlockParams
    from exu_aniso.scenes.particle import ParticleParams
    from exu_aniso.scenes.screw import ScrewParams
    P = {"block": BlockParams, "screw": ScrewParams, "particle": ParticleParams}[case["scene"]]
    p = P(**case["params"])
    warm = p.with_overrides(t_end=5 * p.dt)
    for native in (False, True):
        SolveTimed(*[_build(case["scene"], warm, native)[k] for k in ("mbs", "simulationSettings", "solverType")])
    cost = {False: [], True: []}
    sensors = {}
    for _ in range(case["repeats"]):
        for native in (False, True):
            model = _build(case["scene"], p, native)
            c0 = time.process_time()
            _, steps, its, _ = SolveTimed(model["mbs"], model["simulationSettings"], model["solverType"])
            cost[native].append(((time.process_time() - c0) / steps, its / steps))
            sensors[native] = _sensors(model)
    identical = all(np.array_equal(a, b) for a, b in zip(sensors[False], sensors[True]))
    py, nat = np.array(cost[False]), np.array(cost[True])
    layout = p.points if case["scene"] == "block" else "default"
    return [case["scene"], layout, float(np.median(py[:, 0])), float(py[:, 0].min()), float(py[:, 0].max()),
            float(np.median(nat[:, 0])), float(nat[:, 0].min()), float(nat[:, 0].max()),
            float(np.median(nat[:, 0] / py[:, 0])), float(np.median(nat[:, 1])), int(identical)]


def main(argv=None):
    args, reps = timing_args(NAME, __doc__.splitlines()[0], argv, quick_repeats=3)
    timer = Timer()
    t_end = 0.05 if args.quick else 0.5
    cases = [dict(scene=sc, params=dict(t_end=t_end, **ov), repeats=reps) for sc, ov in SCENES]
    rows = list(sweep(run_case, cases, args))
    table(os.path.join(args.out, "native_callbacks.csv"), COLUMNS, rows)

    def spread(r, i):
        return f"{r[i] * 1e6:.1f} [{r[i + 1] * 1e6:.1f}-{r[i + 2] * 1e6:.1f}]"
    cells = [[r[0], r[1], spread(r, 2), spread(r, 5), f"{r[8]:.2f}", f"{r[9]:.2f}", "yes" if r[10] else "NO"]
             for r in rows]
    head = ["scene", "layout", "Python callbacks us/step", "native us/step", "native / Python", "Newton/step",
            "identical"]
    for c in [head] + cells:
        print("  ".join(f"{x:>24s}" if i in (2, 3) else f"{x:>10s}" for i, x in enumerate(c)))
    body = (f"Process CPU time of the solve per step, median [min-max] of {reps} interleaved repeats, t_end = "
            f"{t_end} s, the scenes' defaults; the ratio formed repeat by repeat. identical: the sensors of the "
            "two runs equal bit for bit. File: `native_callbacks.csv`.\n\n" + markdown_table(head, cells))
    finish(args, timer, body, "Native callbacks against Python callbacks")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
