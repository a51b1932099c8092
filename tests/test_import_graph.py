"""The package's import graph: no circles between its modules, imports at the top of the files.

The graph is read from the sources with ``ast``: top-level and function-level imports, relative
imports resolved, ``from pkg import name`` an edge to ``pkg.name`` when that is a module, else to
``pkg`` (or to the submodule a package loads the name from on first use, ``_EXPORTS``); a module
importing its own parent package is no edge.
"""

from __future__ import annotations

import ast
import importlib
import subprocess
import sys
from pathlib import Path

import wingmdao

PACKAGE = Path(wingmdao.__file__).parent

#: Optional frameworks: imported where they are used, so that ``import wingmdao`` and the commands
#: that do not use them run without them installed.
OPTIONAL = ("mphys", "openaerostruct", "mpi4py", "gmsh", "matplotlib", "meshio", "yaml", "h5py", "cyipopt",
            "sphinx", "panelaero")

#: Frameworks whose import costs start-up time ``wingmdao --help`` must not pay (OpenMDAO: ~1.3 s CPU).
HEAVY = OPTIONAL + ("openmdao",)

#: Modules of a heavy framework that load none of it: ``openmdao.core.analysis_error`` (the class
#: ``openmdao.api.AnalysisError``, 9 ms against 1.3 s for ``openmdao.api``).
LIGHT = ("openmdao.core.analysis_error",)

#: Modules that may import, inside functions, package modules that load a heavy framework (and
#: nothing else: every other import of theirs is at the top), each with its reason:
LAZY_HEAVY = {
    "wingmdao.utils.memory": "import_openmdao_without_plot_plugins imports OpenMDAO, on purpose, when called "
                             "(after it has switched OpenMDAO's plot plug-ins off)",
}

#: Every other import is at the top of its file (:func:`test_imports_at_the_top`): the command
#: modules of ``wingmdao.cli`` too, since the dispatcher (``wingmdao.cli.main``) imports a
#: command's module only when that command runs. Function-local imports left in the package: of
#: optional frameworks (and of the package modules that need one at import), and the two of
#: :data:`LAZY_HEAVY`.


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


_LAZY_EXPORTS: dict = {}


def _lazy_exports(modules: dict, package: str) -> dict:
    """``{name: submodule}`` of a package that loads its names on first use (``_EXPORTS``, PEP 562)."""
    if package not in _LAZY_EXPORTS:
        path, is_pkg = modules.get(package, (None, False))
        lazy = is_pkg and "_EXPORTS" in path.read_text(encoding="utf-8")
        _LAZY_EXPORTS[package] = {k: f"{package}.{v}" for k, v in
                                  importlib.import_module(package)._EXPORTS.items()} if lazy else {}
    return _LAZY_EXPORTS[package]


_IMPORTS: dict = {}


def _imports(modules: dict) -> list:
    """:func:`_scan_imports`, read once per set of modules."""
    key = tuple(sorted(modules))
    if key not in _IMPORTS:
        _IMPORTS[key] = list(_scan_imports(modules))
    return _IMPORTS[key]


def _scan_imports(modules: dict):
    """(module, imported name, line, inside a function) for every import of every module; an
    imported package module is named by the module itself (``from pkg import mod``: ``pkg.mod``), a
    name a package loads on first use by the submodule that defines it."""
    for module, (path, is_pkg) in modules.items():
        tree = ast.parse(path.read_text(encoding="utf-8"))
        local = {id(n) for f in ast.walk(tree) if isinstance(f, (ast.FunctionDef, ast.AsyncFunctionDef))
                 for n in ast.walk(f)}
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                base = _base(module, is_pkg, node)
                lazy = _lazy_exports(modules, base)
                names = [f"{base}.{a.name}" if f"{base}.{a.name}" in modules else lazy.get(a.name, base)
                         for a in node.names]
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


def _heavy_name(name: str) -> bool:
    """Whether importing ``name`` (not a package module) loads a heavy framework."""
    return name.split(".")[0] in HEAVY and not any(name == m or name.startswith(m + ".") for m in LIGHT)


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
            if m not in heavy and any(_heavy_name(n) or n in heavy for n in names):
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


def _optional_modules(modules: dict) -> set:
    """Package modules that need an optional framework at import (their top-level imports load one)."""
    top = {m: set() for m in modules}
    for module, name, _, local in _imports(modules):
        if not local:
            top[module].add(name)
    out, changed = set(), True
    while changed:
        changed = False
        for m, names in top.items():
            if m not in out and any(n.split(".")[0] in OPTIONAL or n in out for n in names):
                out.add(m)
                changed = True
    return out


def _lazy(module: str) -> bool:
    return any(module == m or module.startswith(m + ".") for m in LAZY_HEAVY)


def _local_imports(modules: dict) -> list:
    """``(module, imported name, line)`` of every function-local import that is not allowed: all but
    those of an optional framework (or of a package module that needs one at import) and, in a
    :data:`LAZY_HEAVY` module, those of a package module or framework that loads a heavy framework."""
    heavy, optional = _loads_heavy(modules), _optional_modules(modules)
    bad = []
    for module, name, line, local in _imports(modules):
        if not local or name.split(".")[0] in OPTIONAL or name in optional:
            continue
        if _lazy(module) and (name in heavy or _heavy_name(name)):
            continue
        bad.append((module, name, line))
    return bad


def test_imports_at_the_top():
    """Every import of a package module is at the top of its file (standard library, numpy, scipy,
    casadi, OpenMDAO and the package's own modules), except those :func:`_local_imports` allows."""
    modules = _modules()
    bad = [f"{modules[m][0].relative_to(PACKAGE.parent)}:{line}: {name}" for m, name, line in _local_imports(modules)]
    assert not bad, f"{len(bad)} function-local import(s) that belong at the top of the file:\n" + "\n".join(bad)


def test_local_import_check_can_fail(tmp_path):
    """A function-local import of the standard library, of numpy or of a package module is caught;
    one of an optional framework is not."""
    pkg = tmp_path / "wingmdao"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "light.py").write_text("import numpy\n")
    (pkg / "user.py").write_text("def f():\n    import os\n    import numpy as np\n"
                                 "    from wingmdao import light\n    import matplotlib\n")
    modules = {"wingmdao": (pkg / "__init__.py", True), "wingmdao.light": (pkg / "light.py", False),
               "wingmdao.user": (pkg / "user.py", False)}
    assert [(n, line) for _, n, line in _local_imports(modules)] == [("os", 2), ("numpy", 3), ("wingmdao.light", 4)]


def test_lazy_heavy_entries_are_used():
    """Each module of :data:`LAZY_HEAVY` still has a local import of a heavy module (else the entry goes)."""
    modules = _modules()
    heavy = _loads_heavy(modules)
    users = {m for m in LAZY_HEAVY if any(_lazy(mod) and (mod == m or mod.startswith(m + ".")) and local and
                                          (name in heavy or _heavy_name(name))
                                          for mod, name, _, local in _imports(modules))}
    assert sorted(set(LAZY_HEAVY) - users) == []


def test_cli_help_imports_no_command_and_no_heavy_framework():
    """``wingmdao --help`` imports no command module (the dispatcher imports one when its command
    runs) and no heavy framework (of OpenMDAO only the :data:`LIGHT` modules)."""
    code = ("import sys, wingmdao.cli as c; c.build_parser(()); "
            "print(' '.join(m for m in sys.modules if m.startswith('wingmdao.cli.') "
            "and not m.split('.')[-1].startswith('_'))); "
            f"print(' '.join(m for m in {OPTIONAL!r} + ('openmdao.api', 'openmdao.core.problem') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         cwd=PACKAGE.parent)
    commands, heavy = out.stdout.split("\n")[:2]
    assert (commands, heavy) == ("", "")


#: what ``wingmdao COMMAND --help`` must not load: CasADi, SciPy and OpenMDAO beyond :data:`LIGHT`
#: (``openmdao.core.analysis_error`` and the packages and warnings module it loads)
_HELP_RUNNER = """
import sys
from wingmdao.cli import main
try:
    main(sys.argv[1:])
except SystemExit:
    pass
light = {'openmdao', 'openmdao.core', 'openmdao.utils', 'openmdao.utils.om_warnings'} | set(%r)
print('LOADED', ' '.join(sorted(m for m in sys.modules if m.split('.')[0] in ('casadi', 'scipy')
                                or (m.split('.')[0] == 'openmdao' and m not in light))))
"""


def _help_loads(argv) -> list:
    """The heavy modules in ``sys.modules`` after ``wingmdao ARGV`` ran (in a fresh interpreter)."""
    out = subprocess.run([sys.executable, "-c", _HELP_RUNNER % (LIGHT,), *argv], capture_output=True, text=True,
                         check=True, cwd=PACKAGE.parent)
    return out.stdout.rsplit("LOADED", 1)[1].split()


def test_command_help_loads_no_numerical_framework():
    """``wingmdao COMMAND --help`` of every command builds its parser (:mod:`wingmdao.cli.parsers`)
    without OpenMDAO, CasADi or SciPy: the dispatcher imports the command's run module only after
    parsing, and argparse exits on ``--help`` before that. A run does load them (the check can fail)."""
    import wingmdao.cli as cli

    loaded = {name: _help_loads([name, "--help"]) for name in cli.COMMANDS}
    assert {k: v for k, v in loaded.items() if v} == {}
    assert "casadi" in _help_loads(["section", "--width", "1", "--height", "1", "--solid", "--json", "-"])


def test_cli_parsers_load_no_heavy_framework():
    """No parser module imports, at its top, a module that loads a heavy framework (read from the sources)."""
    modules = _modules()
    heavy = _loads_heavy(modules)
    parsers = {m for m in modules if m.startswith("wingmdao.cli.parsers")}
    assert parsers and sorted(parsers & heavy) == []
    assert not {"wingmdao.names", "wingmdao.cli", "wingmdao.cli._args", "wingmdao.cli._io"} & heavy


def test_cli_commands_table():
    """:data:`wingmdao.cli.COMMANDS` names every command module of ``wingmdao.cli`` (a public module),
    and each module registers exactly its commands, in the table's order, with the table's help."""
    import wingmdao.cli as cli

    public = {p.stem for p in (PACKAGE / "cli").glob("*.py") if not p.stem.startswith("_")}
    assert {c.module for c in cli.COMMANDS.values()} == public
    # every command module has its parser module, of the same name
    assert {p.stem for p in (PACKAGE / "cli" / "parsers").glob("*.py") if p.stem != "__init__"} == public
    sub = next(a for a in cli.build_parser()._actions if a.dest == "command")
    assert list(sub.choices) == list(cli.COMMANDS)
    helps = {a.dest: a.help for a in sub._choices_actions}
    assert helps == {name: c.help for name, c in cli.COMMANDS.items()}


def test_command_modules_load_openmdao_without_plot_plugins():
    """A command module that loads OpenMDAO imports ``wingmdao.cli._openmdao`` before any module that
    loads it (OpenMDAO without the matplotlib of its report plugins)."""
    modules = _modules()
    heavy = _loads_heavy(modules)
    bad = []
    for module in sorted(m for m in heavy if m.startswith("wingmdao.cli.") and not m.split(".")[-1].startswith("_")):
        first = next(name for mod, name, _, local in _imports(modules)
                     if mod == module and not local and (name in heavy or _heavy_name(name)
                                                                     or name == "wingmdao.cli._openmdao"))
        if first != "wingmdao.cli._openmdao":
            bad.append(f"{module}: {first}")
    assert bad == []
