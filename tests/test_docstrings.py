"""numpydoc audit of the public API (the modules of the Sphinx API reference, docs/api/index.md).

Every public function, class and method defined in those modules must have a docstring whose
Parameters section documents exactly its parameters. The checks (``numpydoc.validate`` codes):

* GL08: the object has a docstring;
* PR01: every parameter of the signature is documented (for a class: of its ``__init__``);
* PR02: no documented parameter is missing from the signature (a renamed argument).

These are the checks that make the reference silent or wrong about an input. numpydoc's style
checks (summary on one line, See Also, Examples, imperative mood...) are left out: they do not
change what a reader can learn about a call. Methods that override a method of a class outside
wingmdao (OpenMDAO's ``setup``, ``compute``, ``linearize``...) are skipped: they implement the
framework's documented interface with its parameters; likewise a class whose constructor is a
framework's (PR01/PR02 not checked on it). Optional frameworks that are not installed
skip the modules that need them.

Modules in :data:`RATCHET` still have undocumented objects: each may have at most that many
(lower the number when you document more; remove the module when it reaches 0). Every other
module must pass in full.
"""

from __future__ import annotations

import importlib
import inspect
import pathlib
import pkgutil
import re

import pytest

numpydoc_validate = pytest.importorskip("numpydoc.validate")

CHECKS = ("GL08", "PR01", "PR02")
INDEX = pathlib.Path(__file__).resolve().parents[1] / "docs" / "api" / "index.md"

#: module -> most public objects failing CHECKS (only ever lowered)
RATCHET: dict[str, int] = {}


def api_modules():
    """The modules the API reference documents: the packages of docs/api/index.md, recursively,
    without private (``_``) modules."""
    packages = re.findall(r"^   (wingmdao\.[\w.]+)\s*$", INDEX.read_text(), re.M)
    assert packages, INDEX
    out = {}
    for name in packages:
        try:
            pkg = importlib.import_module(name)
        except ModuleNotFoundError as exc:  # an optional framework
            assert not (exc.name or "").startswith("wingmdao"), exc
            continue
        out[name] = pkg
        for info in pkgutil.walk_packages(getattr(pkg, "__path__", []), name + "."):
            if any(part.startswith("_") for part in info.name.split(".")):
                continue
            try:
                out[info.name] = importlib.import_module(info.name)
            except ModuleNotFoundError as exc:
                assert not (exc.name or "").startswith("wingmdao"), exc
    return out


def public_objects(module):
    """(qualified name, object) of the public functions, classes and methods defined in ``module``
    (re-exports and aliases under another name are audited where they are defined)."""
    for name, obj in vars(module).items():
        if name.startswith("_") or getattr(obj, "__module__", None) != module.__name__:
            continue
        if not (inspect.isfunction(obj) or inspect.isclass(obj)) or obj.__name__ != name:
            continue
        yield f"{module.__name__}.{name}", obj
        if not inspect.isclass(obj):
            continue
        external = [b for b in obj.__mro__[1:] if not b.__module__.startswith("wingmdao")]
        for attr, member in vars(obj).items():
            func = member.__func__ if isinstance(member, (staticmethod, classmethod)) else member
            if attr.startswith("_") or not inspect.isfunction(func):
                continue
            if any(attr in vars(base) for base in external):  # a framework method's override
                continue
            yield f"{module.__name__}.{name}.{attr}", func


def _external_init(cls) -> bool:
    """Whether ``cls`` takes its ``__init__`` from a class outside wingmdao (e.g. an OpenMDAO
    error): its parameters are that framework's."""
    owner = next(c for c in cls.__mro__ if "__init__" in vars(c))
    return owner is not object and not owner.__module__.startswith("wingmdao")


def audit() -> dict:
    """{module: [(qualified name, failing codes)]} of every audited module."""
    failures = {}
    for name, module in api_modules().items():
        failures[name] = []
        for qual, obj in public_objects(module):
            codes = {code for code, _ in numpydoc_validate.validate(qual)["errors"] if code in CHECKS}
            if inspect.isclass(obj) and _external_init(obj):  # the framework's constructor
                codes -= {"PR01", "PR02"}
            codes = sorted(codes)
            if codes:
                failures[name].append((qual, codes))
    return failures


@pytest.fixture(scope="module")
def failures():
    return audit()


def test_audit_finds_the_modules_and_can_fail(failures):
    assert {"wingmdao.cases", "wingmdao.sizing", "wingmdao.section.box"} <= set(failures)
    errors = {code for code, _ in numpydoc_validate.validate(f"{__name__}._undocumented")["errors"]}
    assert {"GL08"} <= errors
    errors = {code for code, _ in numpydoc_validate.validate(f"{__name__}._half_documented")["errors"]}
    assert {"PR01", "PR02"} <= errors


def _undocumented(x):
    return x


def _half_documented(x, y):
    """Add.

    Parameters
    ----------
    x : float
        One term.
    z : float
        Not a parameter.
    """
    return x + y


def test_documented_modules_pass_in_full(failures):
    bad = {m: f for m, f in failures.items() if f and m not in RATCHET}
    lines = [f"{qual}: {', '.join(codes)}" for m in sorted(bad) for qual, codes in bad[m]]
    assert not lines, "public objects without numpydoc Parameters (GL08/PR01/PR02):\n" + "\n".join(lines)


def test_ratchet(failures):
    over = {m: (len(failures[m]), n) for m, n in RATCHET.items() if m in failures and len(failures[m]) > n}
    assert not over, ("more undocumented public objects than allowed (module: found, allowed):\n"
                      + "\n".join(f"{m}: {found} > {n}: " + ", ".join(q for q, _ in failures[m])
                                  for m, (found, n) in over.items()))
