"""Where numba caches this package's compiled kernels, and what a cached kernel is keyed on.

Why: numba keys a cached function on the modification time of its own source file only. The
contact kernel is composed from functions in other files (the surfaces of ``geometry``, the nets,
the return maps): after an edit of cone.py, a cache keyed on kernel/point.py alone would serve the
old cone. This module keys every compiled function of the package on exactly the sources it is
built from, so a stale kernel never runs and nothing else recompiles it:

* the **shared kernel sources** (``kernel_sources``): every module of the package that imports
  numba, except a surface's own module, and the modules of the package those import (their
  constants, e.g. ``law/history.py``): an edit of any of them recompiles every kernel;
* the **surface modules** (``geometry/<surface>.py``): a specialisation is keyed on the modules of
  the surfaces whose parameter types appear in its signature (with the surface modules those
  import): an edit of cone.py recompiles the cone's kernels only;
* a module counts by its syntax tree without docstrings (``_analyse``): an edit of a docstring or
  a comment recompiles nothing, nor does an edit of any other file (scenes, models, the command
  line, docs, tests, studies).

How: a cache locator of our own, first in numba's list, that declines every file outside the
package (other numba code in the process is untouched). Its source stamp, which numba stores in a
function's index and compares on load, is the hash of the shared sources (and of the function's
own module when that is a surface module); its disambiguator, which names the index file, is a hash
of the function's code and the shared sources (numba's default, the line number, moves with every
edit above it; an index is read only by the sources that wrote it, and one that cannot be read is
an empty one); and numba's index key
(``Cache._index_key``: signature, machine, bytecode) gains the hashes of the signature's surface
modules. The syntax trees are hashed once per file content: a small table in the cache directory
maps a file's sha1 to its tree hash and its imports, so an import of the package reads the files
and parses none that it has seen.

The base directory is ``NUMBA_CACHE_DIR`` when set, else ``~/.cache/exu_aniso`` (``XDG_CACHE_HOME``
honoured). This module must be imported before any module that defines a
``numba.njit(cache=True)`` function: ``exu_aniso/__init__.py`` imports it first.
"""
from __future__ import annotations

import ast
import hashlib
import json
import os
import sys

from numba.core import caching, types

_HERE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))      # the package exu_aniso
PACKAGE = os.path.basename(_HERE)

# the folder of the surface modules, each keyed on its own (every module in it but these)
SURFACE_FOLDER = "geometry"
SURFACE_SHARED = ("__init__.py", "core.py", "base.py")


def _base_dir():
    return os.environ.get("NUMBA_CACHE_DIR") or os.path.join(
        os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache"), "exu_aniso")


CACHE_DIR = os.path.join(_base_dir(), "kernels")
_TABLE = os.path.join(CACHE_DIR, "sources.json")


# --- the package's sources: tree hashes and imports ---------------------------------------------

def _strip_docstrings(tree):
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            body = node.body
            if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant) \
                    and isinstance(body[0].value.value, str):
                node.body = body[1:] or [ast.Pass()]
    return tree


def _module_of(relpath):
    """'kernel/point.py' -> 'exu_aniso.kernel.point'; 'kernel/nodes/__init__.py' -> 'exu_aniso.kernel.nodes'."""
    parts = relpath[:-3].split("/")
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join([PACKAGE] + parts)


def _analyse(relpath, text):
    """(tree hash, package modules imported, imports numba) of one source file."""
    tree = ast.parse(text)
    package = _module_of(relpath).split(".")
    if not relpath.endswith("__init__.py"):
        package = package[:-1]
    imported, numba = set(), False
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for a in node.names:
                numba |= a.name.split(".")[0] == "numba"
                if a.name.split(".")[0] == PACKAGE:
                    imported.add(a.name)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                base = ".".join(package[:len(package) - node.level + 1] + ([base] if base else []))
            numba |= base.split(".")[0] == "numba"
            if base.split(".")[0] == PACKAGE:
                imported.add(base)
                imported.update(f"{base}.{a.name}" for a in node.names)       # a submodule, if it is one
    digest = hashlib.sha1(ast.dump(_strip_docstrings(tree), include_attributes=False).encode()).hexdigest()
    return digest, sorted(imported), numba


def _read_sources():
    """{relative path: (tree hash, [imported package modules], imports numba)} of every .py file of
    the package, parsing only the contents the table has not seen."""
    try:
        with open(_TABLE) as f:
            table = json.load(f)
    except (OSError, ValueError):
        table = {}
    out, new = {}, False
    for folder, dirs, files in os.walk(_HERE):
        dirs[:] = sorted(d for d in dirs if d != "__pycache__")
        for name in sorted(files):
            if not name.endswith(".py"):
                continue
            path = os.path.join(folder, name)
            rel = os.path.relpath(path, _HERE).replace(os.sep, "/")
            with open(path, "rb") as f:
                text = f.read()
            raw = hashlib.sha1(text).hexdigest()
            if raw not in table:
                table[raw], new = list(_analyse(rel, text)), True
            out[rel] = tuple(table[raw])
    if new:
        _write_table(table)
    return out


def _write_table(table):
    try:
        os.makedirs(CACHE_DIR, exist_ok=True)
        tmp = f"{_TABLE}.tmp.{os.getpid()}"
        with open(tmp, "w") as f:
            json.dump(table, f)
        os.replace(tmp, _TABLE)
    except OSError:             # a read-only cache: the table is rebuilt in memory next time
        pass


class Sources:
    """The package's kernel sources and their hashes (module docstring)."""

    def __init__(self, sources):
        self.sources = sources
        by_module = {_module_of(rel): rel for rel in sources}
        self.surface_modules = {rel for rel in sources if rel.startswith(SURFACE_FOLDER + "/")
                                and rel.count("/") == 1 and rel.split("/")[1] not in SURFACE_SHARED}

        def imports(rel):
            return {by_module[m] for m in sources[rel][1] if m in by_module}

        def closure(start, follow):
            """start and the modules it imports that follow(module) admits, transitively."""
            found, todo = set(), list(start)
            while todo:
                m = todo.pop()
                if m not in found:
                    found.add(m)
                    todo += [i for i in imports(m) if follow(i)]
            return sorted(found)

        # the modules that import numba (but a surface's) and the package modules they import (not
        # through a package's __init__: it re-exports)
        self.kernel_sources = closure(
            [rel for rel, (_, _, numba) in sources.items() if numba and rel not in self.surface_modules],
            lambda m: not m.endswith("__init__.py") and m not in self.surface_modules)
        self.shared_hash = self._combine(self.kernel_sources)
        self._surface_hash = {_module_of(rel): self._combine(closure([rel], lambda m: m in self.surface_modules))
                              for rel in self.surface_modules}

    def _combine(self, rels):
        h = hashlib.sha1()
        for rel in rels:
            h.update(rel.encode() + b"\0" + self.sources[rel][0].encode())
        return h.hexdigest()[:16]

    def surface_hash(self, module):
        """The hash of a surface module (by its dotted name) and the surface modules it imports;
        None for a module that is not one."""
        return self._surface_hash.get(module)


SOURCES = Sources(_read_sources())


def signature_surfaces(sig):
    """The hashes of the surface modules whose parameter types appear in the numba signature sig
    (argument types, tuples, named tuples and pointers searched through), sorted."""
    found, todo = set(), list(sig if isinstance(sig, tuple) else getattr(sig, "args", ()))
    while todo:
        t = todo.pop()
        if isinstance(t, (types.NamedTuple, types.NamedUniTuple)):
            h = SOURCES.surface_hash(getattr(t.instance_class, "__module__", ""))
            if h is not None:
                found.add(h)
        if isinstance(t, (types.BaseTuple,)):
            todo.extend(t.types)
        if isinstance(t, types.CPointer):
            todo.append(t.dtype)
    return tuple(sorted(found))


class _PackageLocator(caching._SourceFileBackedLocatorMixin, caching._CacheLocator):
    """Cache files of this package's functions in CACHE_DIR, keyed as the module docstring says;
    declines any other source file."""

    def __init__(self, py_func, py_file):
        self._py_file = py_file
        rel = os.path.relpath(py_file, _HERE).replace(os.sep, "/")
        self._cache_path = os.path.join(CACHE_DIR, os.path.dirname(rel))
        own = SOURCES.surface_hash(_module_of(rel)) or ""
        self._stamp = (SOURCES.shared_hash, own)
        code = py_func.__code__
        # the function's code and the shared sources: an index is only read by the sources that wrote it
        # (its keys name the types of their day, which another version may not have)
        self._code = hashlib.sha1(py_func.__qualname__.encode() + code.co_code + repr(code.co_names).encode()
                                  + SOURCES.shared_hash.encode()).hexdigest()[:12]

    def get_cache_path(self):
        return self._cache_path

    def get_source_stamp(self):
        return self._stamp

    def get_disambiguator(self):
        return self._code

    @classmethod
    def from_function(cls, py_func, py_file):
        if not os.path.abspath(py_file).startswith(_HERE + os.sep):
            return None
        return super().from_function(py_func, py_file)


_numba_index_key = caching.Cache._index_key
_numba_load_index = caching.IndexDataCacheFile._load_index


def _load_index(self):
    """numba's index of a function's cache; for this package's functions an index that cannot be read
    (its keys name a type a surface module no longer has) is an empty one, as numba treats a stale one."""
    if not os.path.abspath(self._cache_path).startswith(os.path.abspath(CACHE_DIR) + os.sep):
        return _numba_load_index(self)
    try:
        return _numba_load_index(self)
    except Exception:       # noqa: BLE001 - unpickling a stale index: recompile and write it anew
        return {}


def _index_key(self, sig, codegen):
    """numba's index key, with the hashes of the signature's surface modules for this package's functions."""
    key = _numba_index_key(self, sig, codegen)
    if isinstance(self._impl.locator, _PackageLocator):
        key = key + (signature_surfaces(sig),)
    return key


if _PackageLocator not in caching.CacheImpl._locator_classes:
    caching.CacheImpl._locator_classes.insert(0, _PackageLocator)
    caching.Cache._index_key = _index_key
    caching.IndexDataCacheFile._load_index = _load_index


def native_dir():
    """The folder of the generated native callback modules (kernel.native): their text names only
    the argument types, their machine code holds the shared kernel sources, so the folder is named
    by the shared hash."""
    return os.path.join(CACHE_DIR, "native-" + SOURCES.shared_hash)
