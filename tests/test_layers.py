"""The package's layers, read from its imports (AST, every import including those inside
functions): each module imports only from its own layer or the layers below it, and no modules
import each other in a loop. Layers from the ground up: util; geometry and the return maps (law);
fields and nets; the contact kernel; the engines (the Exudyn adapter, the reference integrator, the
energy ledger); the scenes; the Exudyn model scripts; calibration; the catalog; the command line."""
import ast
import os

import exu_aniso

LAYERS = {"util": 0, "geometry": 1, "law": 1, "fe": 1, "fields": 2, "kernel": 3, "engines": 4, "scenes": 5, "models": 6,
          "calibration": 7, "catalog": 8, "cli": 9}
ROOT = os.path.dirname(exu_aniso.__file__)


def _modules():
    """{dotted name: path} of every module of the package but its face (exu_aniso/__init__.py)."""
    out = {}
    for folder, _, files in os.walk(ROOT):
        for f in files:
            if f.endswith(".py"):
                rel = os.path.relpath(os.path.join(folder, f), ROOT)[:-3].replace(os.sep, ".")
                name = "exu_aniso." + (rel[:-len(".__init__")] if rel.endswith(".__init__") else rel)
                if name != "exu_aniso.__init__":
                    out[name] = os.path.join(folder, f)
    return out


def _imports(name, path, modules):
    """The package modules that module name imports (absolute and relative, at any depth); ``from P
    import m`` of a submodule m counts as importing P.m, not the package face P."""
    pkg = name if path.endswith("__init__.py") else name.rsplit(".", 1)[0]
    found = set()
    for node in ast.walk(ast.parse(open(path).read())):
        if isinstance(node, ast.Import):
            found |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = pkg.split(".")
                base = ".".join(parts[:len(parts) - node.level + 1] + ([base] if base else []))
            subs = {f"{base}.{a.name}" for a in node.names} & set(modules)
            found |= subs if len(subs) == len(node.names) else subs | {base}
    return found


def _graph():
    mods = _modules()
    return {m: sorted(i for i in _imports(m, p, mods) if i in mods and i != m) for m, p in mods.items()}


def _layer(module):
    return LAYERS[module.split(".")[1]]


def test_every_module_has_a_layer():
    assert all(m.split(".")[1] in LAYERS for m in _modules()), sorted(_modules())


def test_no_import_runs_up_a_layer():
    up = [(a, b) for a, targets in _graph().items() for b in targets if _layer(b) > _layer(a)]
    assert not up, up


def _cycles(graph):
    """The import loops of a graph {module: [modules it imports]} found by a depth-first search."""
    state, cycles = {}, []

    def visit(m, path):
        state[m] = 1
        for n in graph[m]:
            if state.get(n) == 1:
                cycles.append(path[path.index(n):] + [n])
            elif n not in state:
                visit(n, path + [n])
        state[m] = 2

    for m in graph:
        if m not in state:
            visit(m, [m])
    return cycles


def test_no_import_cycles():
    cycles = _cycles(_graph())
    assert not cycles, cycles


def test_the_checks_can_fail():
    """The cycle search and the layer rule see what they must (a guard against a vacuous pass)."""
    assert _cycles({"a": ["b"], "b": ["c"], "c": ["a"]}) == [["a", "b", "c", "a"]]
    assert _cycles({"a": ["b"], "b": []}) == []
    g = _graph()
    assert "exu_aniso.kernel.sets" in g["exu_aniso.kernel.packed_sets"]
    assert _layer("exu_aniso.cli") > _layer("exu_aniso.scenes.base") > _layer("exu_aniso.kernel.point")
    assert _private_imports("from exu_aniso.kernel.point import _x\nfrom exu_aniso.geometry import _core\n",
                            "exu_aniso.scenes.a") == [(1, "exu_aniso.kernel.point._x"), (2, "exu_aniso.geometry._core")]
    assert _private_imports("from exu_aniso.scenes.b import _x\n", "exu_aniso.scenes.a") == []
    assert _private_imports("from exu_aniso.engines import energy\nenergy._f()\n", "exu_aniso.scenes.a") == [
        (2, "exu_aniso.engines.energy._f")]


def _package(name):
    """The package a module belongs to: exu_aniso.X, or exu_aniso.engines.exudyn_adapter for the
    Exudyn adapter (a package of its own inside the engines)."""
    parts = name.split(".")
    return ".".join(parts[:3] if parts[1:3] == ["engines", "exudyn_adapter"] else parts[:2])


def _private_imports(source, name):
    """(line, what) of every private name (a leading underscore: a name or a module on the path) that
    module name imports from another package of exu_aniso, or reads as an attribute of a module of
    another package it imported (``energy._helper``)."""
    found, modules = [], {}
    tree = ast.parse(source)
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("exu_aniso") and not node.level:
            for a in node.names:
                path = node.module.split(".") + [a.name]
                modules[a.asname or a.name] = ".".join(path)
                if any(p.startswith("_") and not p.startswith("__") for p in path) and \
                        _package(node.module) != _package(name):
                    found.append((node.lineno, ".".join(path)))
        elif isinstance(node, ast.Import):
            modules.update({a.asname: a.name for a in node.names if a.asname and a.name.startswith("exu_aniso")})
    for node in ast.walk(tree):
        if (isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and node.value.id in modules
                and node.attr.startswith("_") and not node.attr.startswith("__")
                and _package(modules[node.value.id]) != _package(name)):
            found.append((node.lineno, f"{modules[node.value.id]}.{node.attr}"))
    return found


def test_no_private_name_is_imported_across_packages():
    """A name with a leading underscore stays in its package: a module of another package imports
    only public names (the C++ extensions' own modules, _native and _float_text, are reached through
    the public names of their packages)."""
    bad = {name: _private_imports(open(path).read(), name) for name, path in _modules().items()}
    assert not {k: v for k, v in bad.items() if v}, bad


# the names under which the compiled kernels receive a node kind or a return map: types, resolved at
# compile time (exu_aniso.kernel.nodes, law.return_maps.MAPS), never compared as run-time codes
_KIND_NAMES = {"kind", "mkind", "method"}


def _kind_comparisons(source):
    """(line, text) of every comparison with a node-kind or return-map argument in source."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Compare):
            names = [node.left] + list(node.comparators)
            if any(isinstance(n, ast.Name) and n.id in _KIND_NAMES for n in names):
                found.append((node.lineno, ast.unparse(node)))
    return found


def test_kernels_choose_node_kind_and_map_by_type():
    """No 'if kind == ...' in the compiled kernels: a kernel compiles the code of its own node kind
    and return map only (the first run's compile time), and a new kind is a module, not a branch."""
    paths = [os.path.join(ROOT, "law", "return_maps.py")]
    for folder, _, files in os.walk(os.path.join(ROOT, "kernel")):
        paths += [os.path.join(folder, f) for f in files if f.endswith(".py")]
    found = {os.path.relpath(p, ROOT): c for p in paths for c in [_kind_comparisons(open(p).read())] if c}
    assert not found, found
    assert _kind_comparisons("def f(kind):\n    return 1 if kind == 3 else 2\n") == [(2, "kind == 3")]
