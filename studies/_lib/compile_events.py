"""A pytest plugin that records numba's compilations per test: how many specialisations of which
function a test run compiled, and the seconds each took (its own, without the functions it compiled
on the way). For the suite's compile budget (docs/speed_notes.md):

    NUMBA_CACHE_DIR=$(mktemp -d) COMPILE_LOG=/tmp/compile_ PYTHONPATH=studies/_lib pytest -p compile_events

writes COMPILE_LOG + <xdist worker or "main"> + ".json": {"per_test": seconds, "per_fn": seconds,
"count": specialisations}. Compilations in the tests' subprocesses are not seen.
"""
import collections
import json
import os
import time

from numba.core import event

_stack = []
_per_test = collections.defaultdict(float)
_per_fn = collections.defaultdict(float)
_count = collections.Counter()
_current = ["<collect>"]


class _Listener(event.Listener):
    def on_start(self, ev):
        _stack.append((time.perf_counter(), [0.0]))

    def on_end(self, ev):
        start, inner = _stack.pop()
        spent = time.perf_counter() - start
        fn = ev.data["dispatcher"].py_func
        name = f"{fn.__module__}.{fn.__qualname__}"
        _per_fn[name] += spent - inner[0]
        _count[name] += 1
        if _stack:
            _stack[-1][1][0] += spent
        else:
            _per_test[_current[0]] += spent


event.register("numba:compile", _Listener())


def pytest_runtest_setup(item):
    _current[0] = item.nodeid


def pytest_sessionfinish(session):
    path = os.environ.get("COMPILE_LOG", "compile_") + os.environ.get("PYTEST_XDIST_WORKER", "main") + ".json"
    with open(path, "w") as f:
        json.dump({"per_test": _per_test, "per_fn": _per_fn, "count": _count}, f, indent=0)
