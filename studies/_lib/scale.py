"""Scale with the model: M cubes sliding on a plane, each on its 4 corners (the block's
law with the exact map), pushed by constant C++ forces that differ from cube to cube, so every cube
slides its own way.

The contact has normal damping, CUBE_NORMAL_DAMPING, 10% of critical for a cube's vertical mode on
its normal stiffness (2 * 0.1 * sqrt(eps_n * m), eps_n = 1e6 N/m and m = 1 kg: 200 N s/m over the 4
corners), and the C++ springs the same along z. Without it (``damped=False``) the push and the
friction torque set the cube rocking at about 195 Hz (sqrt(eps_n size^2 / 4 / I), I = m size^2 / 6)
and nothing but generalized-alpha's numerical damping stops it: the trailing corners lift off and
land again for the whole run (8 cubes, 0.5 s: a point changes between open, stick and slip at 64% of
the steps, 1.2 changes per step in the second half; damped: none opens, and none changes after t =
0.006 s, the start from stick into slip), and the
benchmark then times that chatter (4.7 Newton iterations per step instead of 3.6) rather than the
cost of many bodies.

Contact variants (``BuildCubes``):
* ``sets``: one contact set per cube (M Exudyn objects, M force callbacks per residual);
* ``group``: one group over all cubes (``bodyNumber`` a list: one object, one compiled call);
* ``springs``: the yardstick, 4 C++ ``CartesianSpringDamper``s per cube (the block's stiffnesses
  shared by the 4 points), no Python in the loop;
* ``empty``: the group's Exudyn items with user functions that return zeros (the floor).

Every variant runs Exudyn's sparse linear solver. Ours run at the package's Newton settings
(``exu_aniso.engines.exudyn_adapter.runner.SimulationSettingsFor``: modified Newton, contractivity 0.01, tolerance 1e-10),
the springs and the floor at Exudyn's defaults. Figures are process CPU time of the whole solve per
nominal step and per body, medians of interleaved repeats. Callbacks per Newton iteration are
counted in a separate, untimed run. Peak memory (``memory_rows``) is the peak resident set size of
a fresh process that builds and solves one case (``python -m _lib.scale --memory ...`` in studies/)."""
from __future__ import annotations

import json
import os
import subprocess
import sys
import time

import exudyn as exu
import numpy as np
from exudyn.itemInterface import ObjectGenericODE2
from exudyn.utilities import InertiaCuboid

import exu_aniso  # noqa: F401  (binds mbs.CreateAnisotropicContact)
from exu_aniso.engines.exudyn_adapter.runner import SimulationSettingsFor, SolveTimed
from exu_aniso.scenes.block import BlockParams, block_contact_law, block_points

from .baseline import _cartesian_springs, empty_contact, exudyn_defaults
from .studylib import markdown_table

CONTACTS = ("sets", "group", "springs", "empty")
BODIES = (4, 16, 64)
BODIES_QUICK = (2, 8)
PER_ROW = 8                                        # cubes per row on the plane


CUBE_NORMAL_DAMPING = 200.0                        # N s/m per cube, over its points (module doc)


def cube_params(points="corners", damped=True):
    return BlockParams(model="full", points=points, return_map="exact",
                       normal_damping=CUBE_NORMAL_DAMPING if damped else 0.0)


def BuildCubes(M, contact, t_end, dt, points="corners", storeHistory=False, floor=None, damped=True):
    """M cubes (module doc) with the given contact variant; returns dict(mbs, simulationSettings,
    solverType, contacts). floor (contact "springs" only): None, or "sets" / "group" to add the
    Exudyn items of one contact set per cube / of one group with user functions that do nothing
    (``baseline.empty_contact``: the speed targets' floor, the springs carrying the cubes); damped:
    the contact's (and the springs') normal damping CUBE_NORMAL_DAMPING, or none."""
    if contact not in CONTACTS:
        raise ValueError(f"contact must be one of {CONTACTS}; got {contact!r}")
    if floor not in (None, "sets", "group") or (floor is not None and contact != "springs"):
        raise ValueError(f"floor must be None, or 'sets' / 'group' with contact 'springs'; got {floor!r} "
                         f"with {contact!r}")
    p = cube_params(points, damped).with_overrides(t_end=t_end, dt=dt)
    law = block_contact_law(p)
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    a, gap = p.size, -p.normal_load / p.eps_n
    local = block_points(p)
    K = local.shape[0]
    bodies, contacts = [], []
    for i in range(M):
        x0, y0 = 3 * a * (i % PER_ROW), 3 * a * (i // PER_ROW)
        o = mbs.CreateRigidBody(inertia=InertiaCuboid(density=p.mass / a ** 3, sideLengths=[a] * 3),
                                referencePosition=[x0, y0, 0.5 * a + gap], gravity=[0.0, 0.0, -9.81],
                                nodeType=exu.NodeType.RotationEulerParameters)
        mbs.CreateForce(itemNumber=o, loadVector=[p.force * (3.0 + 0.05 * i), p.force * (1.5 - 0.04 * i),
                                                  -p.normal_load])
        bodies.append(o)
        if contact == "sets":
            contacts.append(mbs.CreateAnisotropicContact(bodyNumber=o, localPoints=local, contactLaw=law,
                                                         show=False, storeHistory=storeHistory))
        elif contact == "springs":
            anchors = local + np.array([x0, y0, 0.0])
            anchors[:, 2] = 0.0
            _cartesian_springs(mbs, o, local, anchors, [[p.eps_1 / K, p.eps_1 / K, p.eps_n / K]] * K,
                               [[0.0, 0.0, p.normal_damping / K]] * K)
            if floor == "sets":
                empty_contact(mbs, [mbs.GetObject(o)["nodeNumber"]], K, storeHistory)
    if contact == "group":
        contacts.append(mbs.CreateAnisotropicContact(bodyNumber=bodies, localPoints=local, contactLaw=law, show=False,
                                                     storeHistory=storeHistory))
    elif contact == "empty":
        _empty_group(mbs, bodies)
    if floor == "group":
        empty_contact(mbs, [mbs.GetObject(o)["nodeNumber"] for o in bodies], M * K, storeHistory,
                      sparse=True)
    mbs.Assemble()
    ss = SimulationSettingsFor(p)[0] if contact in ("sets", "group") else exudyn_defaults(t_end, dt)
    ss.linearSolver.solverType = exu.LinearSolverType.EigenSparse
    return dict(mbs=mbs, simulationSettings=ss, solverType=exu.DynamicSolverType.GeneralizedAlpha,
                contacts=contacts, SC=SC)


def _empty_group(mbs, bodies):
    """The group's object over all cube nodes with user functions returning zeros (a sparse empty
    Jacobian) and the post-Newton function that does nothing."""
    import scipy.sparse as sp
    nodes = [mbs.GetObject(o)["nodeNumber"] for o in bodies]
    n = sum(len(mbs.GetNodeParameter(nd, "referenceCoordinates")) for nd in nodes)
    zq, zJ = np.zeros(n), sp.csr_matrix((n, n))
    mbs.AddObject(ObjectGenericODE2(nodeNumbers=nodes, forceUserFunction=lambda mbs, t, i, q, q_t: zq,
                                    jacobianUserFunction=lambda mbs, t, i, q, q_t, fq, fv: zJ))
    mbs.SetPostNewtonUserFunction(lambda mbs, t: [0.0, -1.0])


def _solve(model):
    c0 = time.process_time()
    _, steps, iters, _ = SolveTimed(model["mbs"], model["simulationSettings"], model["solverType"])
    return time.process_time() - c0, steps, iters


def count_callbacks(M, contact, t_end, dt):
    """(force callbacks, Jacobian callbacks, Newton iterations, steps) of one untimed run: the force
    calls as the adapter counts them (``contact_force_calls``: Python and native calls), the Jacobian
    user functions the contact classes give Exudyn (numpy route: jacobian; compiled:
    jacobian_in_place) wrapped with counters while the model is built, plus the native ones
    (``native_jacobians``: Exudyn calls the kernel without Python)."""
    from exu_aniso.engines.exudyn_adapter import commit, contact_set
    counts = [0]
    names = {contact_set.ContactSet: "jacobian", contact_set.CompiledSet: "jacobian_in_place"}
    saved = {cls: cls.__dict__[name] for cls, name in names.items()}

    def counted(f):
        def w(*a, **k):
            counts[0] += 1
            return f(*a, **k)
        return w
    try:
        for cls, f in saved.items():
            setattr(cls, names[cls], counted(f))
        model = BuildCubes(M, contact, t_end, dt)
        _, steps, iters = _solve(model)
    finally:
        for cls, f in saved.items():
            setattr(cls, names[cls], f)
    native = sum(cs.native_jacobians()[0] for cs in model["mbs"].variables.get(commit.SETS_KEY, ())
                 if isinstance(cs, contact_set.CompiledSet))
    return commit.contact_force_calls(model["mbs"]), counts[0] + native, iters, steps


def scale_rows(quick=False, repeats=5):
    """Per-body cost of every contact variant against M (module doc); one dict per (M, contact)."""
    t_end, dt = (0.02, 1e-3) if quick else (0.2, 1e-3)
    nominal = int(round(t_end / dt))
    Ms = BODIES_QUICK if quick else BODIES
    for M in Ms:                                          # warm-up: kernels compiled or loaded
        for c in CONTACTS:
            _solve(BuildCubes(M, c, 3 * dt, dt))
    times = {(M, c): [] for M in Ms for c in CONTACTS}
    for _ in range(repeats):                              # interleaved
        for M in Ms:
            for c in CONTACTS:
                times[(M, c)].append(_solve(BuildCubes(M, c, t_end, dt)))
    rows = []
    for M in Ms:
        springs = float(np.median([t for t, _, _ in times[(M, "springs")]])) / nominal / M
        for c in CONTACTS:
            T = np.array(times[(M, c)], dtype=float)
            per_body = float(np.median(T[:, 0])) / nominal / M
            row = dict(bodies=M, contact=c, per_body_us=per_body * 1e6, per_step_us=per_body * M * 1e6,
                       newton_per_step=float(np.median(T[:, 2] / T[:, 1])), steps=float(np.median(T[:, 1])),
                       ratio_to_springs=per_body / springs, force_calls_per_newton=float("nan"),
                       jacobian_calls_per_step=float("nan"))
            if c in ("sets", "group"):
                nf, nj, iters, steps = count_callbacks(M, c, t_end, dt)
                row["force_calls_per_newton"] = nf / iters
                row["jacobian_calls_per_step"] = nj / steps
            rows.append(row)
    first = {r["contact"]: r["per_body_us"] for r in rows if r["bodies"] == Ms[0]}
    for r in rows:
        r["per_body_vs_fewest"] = r["per_body_us"] / first[r["contact"]]
    return rows


SCALE_COLUMNS = ["bodies [-]", "contact [-]", "per_body_per_step [us]", "per_step [us]", "per_body_vs_fewest [-]",
                 "ratio_to_springs [-]", "newton_per_step [-]", "force_calls_per_newton [-]",
                 "jacobian_calls_per_step [-]", "steps [-]"]


def scale_table_rows(rows):
    return [[r["bodies"], r["contact"], r["per_body_us"], r["per_step_us"], r["per_body_vs_fewest"],
             r["ratio_to_springs"], r["newton_per_step"], r["force_calls_per_newton"], r["jacobian_calls_per_step"],
             r["steps"]] for r in rows]


def scale_markdown(rows, repeats):
    return ("M cubes on a plane, 4 corners each, exact map, sliding under different constant forces; "
            "Exudyn's sparse solver; ours at the package's Newton settings, the C++ springs and the floor "
            f"(`empty`) at Exudyn's defaults. Process CPU time per nominal step and body, median of {repeats} "
            "interleaved repeats; `x fewest`: per-body cost over that at the fewest bodies; callbacks counted "
            "in an untimed run. File: `scale.csv`.\n\n"
            + markdown_table(["bodies", "contact", "us/body/step", "x fewest", "/ springs", "Newton/step",
                              "force callbacks / Newton it.", "Jacobian callbacks / step"],
                             [[r["bodies"], r["contact"], r["per_body_us"], r["per_body_vs_fewest"],
                               r["ratio_to_springs"], r["newton_per_step"], r["force_calls_per_newton"],
                               r["jacobian_calls_per_step"]] for r in rows]))


# ----------------------------------------------------------------------------------------------
# peak memory of one case in a fresh process

MEMORY_CASES = [  # (bodies, point layout, steps, storeHistory)
    (1, "corners", 800, False), (1, "grid:32", 800, False), (1, "grid:32", 800, True),
    (64, "corners", 800, False), (64, "corners", 800, True)]
MEMORY_CASES_QUICK = [(1, "corners", 50, False), (1, "grid:8", 50, True)]


def peak_memory(M, points, steps, store_history):
    """Peak resident set size [MB] of a fresh Python process that builds M cubes (one group) with the
    point layout and solves `steps` steps of 1 ms, and the same process's peak right after building
    (the model without the solve)."""
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    out = subprocess.run([sys.executable, "-m", "_lib.scale", "--memory", str(M), points, str(steps),
                          "1" if store_history else "0"], check=True, capture_output=True, text=True, cwd=here,
                         timeout=900)
    return json.loads(out.stdout.strip().splitlines()[-1])


def memory_rows(quick=False):
    peak_memory(1, "corners", 2, False)   # warm-up: a first process may compile kernels (LLVM's memory)
    rows = []
    for M, points, steps, store in (MEMORY_CASES_QUICK if quick else MEMORY_CASES):
        m = peak_memory(M, points, steps, store)
        K = M * block_points(cube_params(points)).shape[0]
        rows.append(dict(bodies=M, points=K, steps=steps, store_history=store, built_mb=m["built_mb"],
                         peak_mb=m["peak_mb"], history_mb=9 * K * (steps + 1) * 8 / 1e6 if store else 0.0))
    return rows


MEMORY_COLUMNS = ["bodies [-]", "points [-]", "steps [-]", "store_history [-]", "after_build [MB]", "peak [MB]",
                  "history_sensor_data [MB]"]


def memory_table_rows(rows):
    return [[r["bodies"], r["points"], r["steps"], r["store_history"], r["built_mb"], r["peak_mb"], r["history_mb"]]
            for r in rows]


def peak_rss_mb():
    """This process's peak resident set size [MB]: VmHWM of /proc/self/status, the high-water mark
    of the process image, which starts afresh at exec. (getrusage's ru_maxrss does not: it keeps the
    peak of the forked parent's copy, so a child started by a big process, such as the benchmark
    after its timing runs, reported the parent's size in every case.) ru_maxrss where there is no
    /proc."""
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) / 1024.0          # kB
    except OSError:
        pass
    import resource
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def _memory_main(M, points, steps, store):
    rss_mb = peak_rss_mb
    model = BuildCubes(int(M), "group", int(steps) * 1e-3, 1e-3, points=points, storeHistory=store == "1")
    built = rss_mb()
    _solve(model)
    print(json.dumps(dict(built_mb=built, peak_mb=rss_mb())))


def chatter(M=8, t_end=0.5, dt=1e-3, damped=True):
    """How the M cubes' contact points change state (module doc): dict of the steps at which some
    point changed between open, stick and slip, the time of the last such step [s], the steps with
    an open point, and the changes per step over the run and over its second half. One group, the
    history sensor on. ``python -m _lib.scale --chatter`` (in studies/) prints it damped and undamped."""
    from exu_aniso.law.history import H_STATUS, N_HISTORY, OPEN
    model = BuildCubes(M, "group", t_end, dt, storeHistory=True, damped=damped)
    _solve(model)
    H = model["mbs"].GetSensorStoredData(model["contacts"][0]["sHistory"])
    status = H[:, 1:].reshape(H.shape[0], -1, N_HISTORY)[:, :, H_STATUS]
    changes = (status[1:] != status[:-1]).sum(axis=1)
    at = np.nonzero(changes)[0]
    return dict(steps_with_a_change=int(at.size), last_change_s=float(H[at[-1] + 1, 0]) if at.size else None,
                steps_with_an_open_point=int((status == OPEN).any(axis=1).sum()),
                changes_per_step=float(changes.mean()), second_half=float(changes[changes.size // 2:].mean()))


if __name__ == "__main__" and len(sys.argv) == 6 and sys.argv[1] == "--memory":
    _memory_main(*sys.argv[2:])
elif __name__ == "__main__" and sys.argv[1:] == ["--chatter"]:
    for damped in (False, True):
        print("damped" if damped else "undamped", chatter(damped=damped))
