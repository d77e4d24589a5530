"""Where numba caches this package's compiled kernels: a directory named by a hash of the source.

Why: numba keys a cached function on its own source file only. The contact kernel is composed
from functions in other files (the surfaces of ``geometry``, the nets, the return maps): after an
edit of cone.py, a cache keyed on kernel/point.py alone would serve the old cone. A directory per
source hash makes every change of any module a fresh cache, so a stale kernel never runs.

Only functions defined in this package are redirected (a cache locator of our own, first in
numba's list, that declines every other file); other numba code in the process is untouched.
The base directory is ``NUMBA_CACHE_DIR`` when set, else ``~/.cache/exu_aniso``
(``XDG_CACHE_HOME`` honoured). This module must be imported before any module that defines a
``numba.njit(cache=True)`` function: ``exu_aniso/__init__.py`` imports it first.
"""
from __future__ import annotations

import hashlib
import os

from numba.core import caching

_HERE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))      # the package exu_aniso


def source_hash():
    """sha1 (16 hex digits) of every .py file of the package (names and contents)."""
    h = hashlib.sha1()
    for folder, _, files in sorted(os.walk(_HERE)):
        if "__pycache__" in folder:
            continue
        for name in sorted(files):
            if name.endswith(".py"):
                with open(os.path.join(folder, name), "rb") as f:
                    h.update(os.path.relpath(os.path.join(folder, name), _HERE).encode() + b"\0" + f.read())
    return h.hexdigest()[:16]


def cache_dir():
    base = os.environ.get("NUMBA_CACHE_DIR") or os.path.join(
        os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache"), "exu_aniso")
    return os.path.join(base, "kernels-" + source_hash())


CACHE_DIR = cache_dir()


class _PackageLocator(caching._SourceFileBackedLocatorMixin, caching._CacheLocator):
    """Cache files of this package's functions in CACHE_DIR; declines any other source file."""

    def __init__(self, py_func, py_file):
        self._py_file = py_file
        self._lineno = py_func.__code__.co_firstlineno
        self._cache_path = os.path.join(CACHE_DIR, os.path.relpath(os.path.dirname(py_file), _HERE))

    def get_cache_path(self):
        return self._cache_path

    @classmethod
    def from_function(cls, py_func, py_file):
        if not os.path.abspath(py_file).startswith(_HERE + os.sep):
            return None
        return super().from_function(py_func, py_file)


if _PackageLocator not in caching.CacheImpl._locator_classes:
    caching.CacheImpl._locator_classes.insert(0, _PackageLocator)
