"""The package's import graph: no circles between its modules, imports at the top of the files.

The graph is read from the sources with ``ast``: top-level and function-level imports, relative
imports resolved, ``from pkg import name`` an edge to ``pkg.name`` when that is a module, else to
``pkg``; a module importing its own parent package is no edge.
"""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import wingmdao

PACKAGE = Path(wingmdao.__file__).parent

#: Optional or heavy frameworks: imported where they are used, so that ``import wingmdao`` and
#: ``wingmdao --help`` do without them.
OPTIONAL = ("mphys", "openaerostruct", "mpi4py", "gmsh", "matplotlib", "meshio", "yaml", "h5py", "cyipopt",
            "sphinx", "panelaero")

#: Imports that belong at the top of a file: the package's own modules and its core dependencies.
CORE = ("numpy", "scipy", "casadi", "openmdao")

#: Frameworks whose import costs start-up time the CLI's help must not pay (OpenMDAO: ~2.4 s).
HEAVY = OPTIONAL + ("openmdao",)

#: Modules that may import, inside functions, package modules that load a heavy framework:
#: ``wingmdao --help`` imports every command module (the CLI's discovery), so a command imports
#: its implementation (OpenMDAO problems, cases, FE models) only when the command runs.
LAZY_HEAVY = {
    "wingmdao.cli": "command modules, all imported to build `wingmdao --help`: implementations load when run",
}


#: Function-local imports of the package's modules (and numpy/scipy/casadi/openmdao) left inside
#: functions: nearly all in the modules ``wingmdao --help`` imports (the cases and the CLI commands),
#: whose imports of the numerical modules stay local so that the help loads no framework. Everything
#: else imports at the top; this count is an upper bound that new code must not raise.
LOCAL_IMPORTS_LEFT = 363


def _modules() -> dict:
    """{dotted name: (path, is_package)} of every module of the package."""
    out = {}
    for path in PACKAGE.rglob("*.py"):
        parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
        is_pkg = parts[-1] == "__init__"
        out[".".join(parts[:-1] if is_pkg else parts)] = (path, is_pkg)
    return out


def _base(module: str, is_pkg: bool, node: ast.ImportFrom) -> str:
    if not node.level:
        return node.module
    parts = module.split(".")[: None if is_pkg else -1]
    parts = parts[: len(parts) - (node.level - 1)]
    return ".".join(parts + ([node.module] if node.module else []))


def _imports(modules: dict):
    """(module, imported name, line, inside a function) for every import of every module; an
    imported package module is named by the module itself (``from pkg import mod``: ``pkg.mod``)."""
    for module, (path, is_pkg) in modules.items():
        tree = ast.parse(path.read_text(encoding="utf-8"))
        local = {id(n) for f in ast.walk(tree) if isinstance(f, (ast.FunctionDef, ast.AsyncFunctionDef))
                 for n in ast.walk(f)}
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                base = _base(module, is_pkg, node)
                names = [f"{base}.{a.name}" if f"{base}.{a.name}" in modules else base for a in node.names]
            else:
                continue
            for name in names:
                if name == "wingmdao" or name.startswith("wingmdao."):
                    while name not in modules:
                        name = name.rsplit(".", 1)[0]
                yield module, name, node.lineno, id(node) in local


def _graph(modules: dict) -> dict:
    edges = {m: set() for m in modules}
    for module, name, _, _ in _imports(modules):
        if name in modules and not (module == name or module.startswith(name + ".")):
            edges[module].add(name)
    return edges


def _cycles(edges: dict) -> list:
    """One cycle (a list of modules, first = last) per strongly connected component (Tarjan)."""
    index, low, stack, on_stack, components = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(edges[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = set()
            while True:
                w = stack.pop()
                on_stack.discard(w)
                comp.add(w)
                if w == v:
                    break
            if len(comp) > 1:
                components.append(comp)

    sys.setrecursionlimit(max(sys.getrecursionlimit(), 10 * len(edges)))
    for v in sorted(edges):
        if v not in index:
            visit(v)
    cycles = []
    for comp in components:  # a shortest way from the component's first module back to it
        start = min(comp)
        paths, frontier, cycle = {start: [start]}, [start], None
        while cycle is None:
            nxt = []
            for v in frontier:
                for w in sorted(edges[v] & comp):
                    if w == start and cycle is None:
                        cycle = paths[v] + [start]
                    elif w not in paths:
                        paths[w] = paths[v] + [w]
                        nxt.append(w)
            frontier = nxt
        cycles.append(cycle)
    return cycles


def _loads_heavy(modules: dict) -> set:
    """Package modules whose top-level imports (followed through the package) load a heavy framework."""
    top = {m: set() for m in modules}
    for module, name, _, local in _imports(modules):
        if not local:
            top[module].add(name)
    heavy = set()
    changed = True
    while changed:
        changed = False
        for m, names in top.items():
            if m not in heavy and any(n.split(".")[0] in HEAVY or n in heavy for n in names):
                heavy.add(m)
                changed = True
    return heavy


def test_no_import_cycles():
    cycles = _cycles(_graph(_modules()))
    for cycle in cycles:
        print(" -> ".join(cycle))
    assert not cycles, f"{len(cycles)} import circle(s): " + "; ".join(" -> ".join(c) for c in cycles)


def test_cycle_detection():
    edges = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}
    assert _cycles(edges) == [["a", "b", "c", "a"]]
    assert _cycles({"a": {"b"}, "b": set()}) == []


def test_imports_at_the_top():
    """Inside functions only optional frameworks, and, in :data:`LAZY_HEAVY`, package modules that
    load a heavy framework; the package's own modules and numpy/scipy/casadi/openmdao at the top."""
    modules = _modules()
    heavy = _loads_heavy(modules)
    bad = []
    for module, name, line, local in _imports(modules):
        root = name.split(".")[0]
        if not local or root in OPTIONAL or root not in CORE + ("wingmdao",):
            continue
        lazy = any(module == m or module.startswith(m + ".") for m in LAZY_HEAVY)
        if lazy and (name in heavy or root in HEAVY):
            continue
        bad.append(f"{modules[module][0].relative_to(PACKAGE.parent)}:{line}: {name}")
    print("\n".join(bad))
    assert len(bad) <= LOCAL_IMPORTS_LEFT, f"{len(bad)} function-local imports (at most {LOCAL_IMPORTS_LEFT}):\n" + \
        "\n".join(bad)


def test_cli_help_imports_no_heavy_framework():
    code = ("import sys, wingmdao.cli as c; c.build_parser(); "
            f"print(' '.join(m for m in {HEAVY!r} if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         cwd=PACKAGE.parent)
    assert out.stdout.split() == []
