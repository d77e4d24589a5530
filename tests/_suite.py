"""What the tests share about the suite itself: its subprocesses' hang guard and the bounded set of
compiled specialisations the default run covers.

HANG_S [s]: the timeout of every subprocess a test starts (a study's quick run, a command line, a
script of the docs). It guards against a hang and is never a check of speed: it is 25 times the
longest such subprocess measured with a cold kernel cache on this 2-core machine with the other core
busy (the quick benchmark study behind tests/test_benchmarks.py's fixture, 72 s: ``pytest
--durations=40`` of a fresh clone's suite from an empty ``NUMBA_CACHE_DIR``, the other xdist worker
running), so how fast the machine is cannot decide a test's outcome.

``covering(cases, axes)``: a product of parametrized cases cut to a covering set for the default
run. Every compiled law is specialised for its surface, nets and return map, every set kernel for
its node kind (a cold compilation costs 6-10 s here for a law, up to 9 s for a set kernel, 22-30 s
for a moving master's: ``kernel.compiling.COMPILE_SECONDS``), so a full product of those axes in the
default run costs minutes of compilation for what one case per value already checks.
The default run keeps a small set of cases that together bring every value of every axis (greedy set
cover); the others are marked ``slow`` (``pytest -m slow`` runs the whole product).

The suite runs on pytest-xdist, one worker per core, a test file's tests on one worker
(``--dist loadfile``: its module fixtures made once, its random draws in order). Handing each test
to the free worker instead (``--dist loadgroup``) was measured slower from a cold cache (17.0 against
16.2 min): two workers compiled the same kernels.
"""
import pytest

HANG_S = 1800


# The moving-master pairings (slave node kind, master node kind) the default run compiles a set kernel
# for (22-30 s each): the feeder's, the fastening's, a linear slave's (mass points, cables) and the
# rotation-vector block on a rotation-vector plate (tests/test_moving_master_compiled.py); a test of
# another pairing belongs to the slow set
DEFAULT_PAIRS = {("RigidBodyEP", "RigidBodyEP"), ("RigidBodyRotVecLG", "RigidBodyEP"), ("Point", "RigidBodyRotVecLG"),
                 ("Cable", "RigidBodyRotVecLG"), ("RigidBodyRotVecLG", "RigidBodyRotVecLG")}


def covering(cases, axes, ids=None, prefer=None):
    """pytest.param of every case (tuples), those that cover no new value of the axes marked slow.
    An axis is an index into a case, or a tuple of indices whose combinations are to be covered
    (e.g. (node kind, route): every node kind on each route). ids: the cases' ids (default: their
    values joined by '-'); prefer(case): True for the cases to take first among those that cover as
    many new values (e.g. kernels the default run compiles anyway)."""
    axes = [a if isinstance(a, tuple) else (a,) for a in axes]
    values = [{(a, tuple(case[i] for i in a)) for a in axes} for case in cases]
    seen, chosen = set(), set()
    while True:             # greedy set cover: the case with the most values not yet covered (the first of equals)
        k = max(range(len(cases)), key=lambda j: (len(values[j] - seen), bool(prefer and prefer(cases[j])), -j))
        if not values[k] - seen:
            break
        seen |= values[k]
        chosen.add(k)
    return [pytest.param(*case, marks=() if k in chosen else (pytest.mark.slow,),
                         id=ids[k] if ids else "-".join(str(v) for v in case)) for k, case in enumerate(cases)]
