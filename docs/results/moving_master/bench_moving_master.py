"""Cost per step and Newton iterations of a moving master against the same scene with a fixed one.

The block scene (models/block.py, full 6-DOF model, 4 corner points) as the package builds it
(the plane fixed to ground), and the same scene with the plane carried by a free plate (a rigid
body of 1e9 kg, no load: it stays where it is to ~1e-9 m, or moves uniformly with ``--plate-speed``
and a force drive, Galilean invariant); the block's contact is then a moving-master set over the
block's and the plate's coordinates (contactBuilder of BuildBlock: nothing else of the scene changes).

Runs, interleaved over --reps repetitions (medians reported, after one warm-up round that compiles
or loads the kernels): fixed master (compiled), moving master compiled with its analytic Jacobian,
moving master compiled with Exudyn's numerical Jacobian, moving master numpy (numerical Jacobian:
the route before the compiled moving master). Full Newton (the package's settings) and Exudyn's
modified Newton.

    NUMBA_CACHE_DIR=/tmp/numba_master python docs/results/moving_master/bench_moving_master.py
"""
import argparse
import os
import statistics
import sys

import exudyn as exu
import numpy as np

from exu_aniso.models.block import BuildBlock
from exu_aniso.engines.exudyn_adapter.runner import SolveTimed
from exu_aniso.scenes.block import BlockParams

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "studies"))
from _lib.target_models import plate_builder  # noqa: E402  (the free plate of the speed targets)


def run(config, modified, node_type):
    kind, impl, jac = config
    opts = dict(nodeType=node_type)
    if kind == "fixed":
        opts.update(implementation=impl, jacobian=jac)
    else:
        nt = exu.NodeType.RotationEulerParameters if node_type == "EP" else exu.NodeType.RotationRotationVector
        opts.update(contactBuilder=plate_builder(P, SPEED, nt, impl, jac))
    model = BuildBlock(P, **opts)
    ss = model["simulationSettings"]
    ss.timeIntegration.newton.useModifiedNewton = modified
    wall, steps, iters, info = SolveTimed(model["mbs"], ss, model["solverType"], contacts=[model["contact"]])
    pos = model["mbs"].GetSensorStoredData(model["sensors"]["sPosition"])
    return wall / steps, iters / steps, steps, pos


CONFIGS = {"fixed master, compiled": ("fixed", "compiled", "analytic"),
           "moving master, compiled, analytic J": ("moving", "compiled", "analytic"),
           "moving master, compiled, numerical J": ("moving", "compiled", "numerical"),
           "moving master, numpy, numerical J": ("moving", "numpy", "analytic")}

if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--t-end", type=float, default=0.5)
    ap.add_argument("--node-type", default="EP", choices=("EP", "RotVecLG"))
    ap.add_argument("--plate-speed", type=float, default=0.0, help="uniform plate velocity [m/s] (force drive)")
    ap.add_argument("--modified", action="store_true", help="Exudyn's modified Newton instead of full Newton")
    ap.add_argument("--skip-numpy", action="store_true")
    a = ap.parse_args()
    SPEED = a.plate_speed
    P = BlockParams(model="full", t_end=a.t_end, **({"drive": "force"} if SPEED else {}))
    configs = {k: v for k, v in CONFIGS.items() if not (a.skip_numpy and v[1] == "numpy")}
    res = {k: [] for k in configs}
    paths = {}
    for rep in range(a.reps + 1):                 # round 0: warm-up (compile or load the kernels)
        for name, cfg in configs.items():
            t_step, it_step, steps, pos = run(cfg, a.modified, a.node_type)
            if rep:
                res[name].append((t_step, it_step, steps))
            paths[name] = pos
    print(f"block scene, full model, {a.node_type} nodes, t_end {a.t_end} s, {'modified' if a.modified else 'full'} "
          f"Newton, plate speed {SPEED} m/s; medians of {a.reps} interleaved runs")
    base = statistics.median(r[0] for r in res["fixed master, compiled"])
    ref = paths["fixed master, compiled"]
    for name, r in res.items():
        t = statistics.median(x[0] for x in r)
        # the plate at rest: the block's path is the fixed master's (the plate moves by ~1e-9 m)
        dev = np.max(np.abs(paths[name][:, 1:4] - ref[:, 1:4])) if len(paths[name]) == len(ref) and not SPEED \
            else float("nan")
        print(f"  {name:38s} {1e6 * t:9.1f} us/step ({t / base:5.2f} x fixed)   Newton {r[0][1]:.3f}/step   "
              f"steps {r[0][2]}   max |block x - fixed's| {dev:.1e} m")
