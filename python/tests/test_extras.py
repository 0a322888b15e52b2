"""The extras install what the examples import: every module that `examples/python/*.py`
imports beyond the standard library, numpy (a dependency) and ccrkit itself is named by the
`dask` extra (`pip install "./python[dask]"`), and the `test` extra holds the `dask` one."""

import ast
import re
import sys

import pytest

from conftest import ROOT

tomllib = pytest.importorskip("tomllib")  # Python >= 3.11; the check is the same everywhere


def _project():
    with open(ROOT / "python" / "pyproject.toml", "rb") as f:
        return tomllib.load(f)["project"]


def _requirements(reqs):
    """Requirement strings as {name: {extras}} (`dask[distributed]>=2023` -> dask: {distributed})."""
    out = {}
    for r in reqs:
        m = re.match(r"\s*([A-Za-z0-9_.-]+)\s*(?:\[([^\]]*)\])?", r)
        assert m, f"cannot read requirement {r!r}"
        extras = {e.strip() for e in (m.group(2) or "").split(",") if e.strip()}
        out.setdefault(m.group(1).lower().replace("_", "-"), set()).update(extras)
    return out


def _imports(path):
    """Dotted names of the modules a Python file imports (absolute imports only)."""
    names = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            names.update(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            names.add(node.module)
    return names


def _missing(imports, installed):
    """Imports that `installed` ({name: {extras}}) does not provide: a top-level package must be
    named, and `pkg.sub` needs `pkg[sub]` or the package `sub` when pkg has such an extra
    (`dask.distributed` comes with `dask[distributed]`)."""
    std = set(sys.stdlib_module_names) | {"__future__", "ccrkit"}
    missing = []
    for name in sorted(imports):
        top, _, rest = name.partition(".")
        if top in std:
            continue
        if top not in installed:
            missing.append(name)
        elif top == "dask" and rest.startswith("distributed"):
            if "distributed" not in installed[top] and "distributed" not in installed:
                missing.append(name)
    return missing


def test_dask_extra_covers_every_example_import():
    project = _project()
    installed = _requirements(project["dependencies"])
    extra = _requirements(project["optional-dependencies"]["dask"])
    for k, v in extra.items():
        installed.setdefault(k, set()).update(v)
    imports = set()
    for path in sorted((ROOT / "examples" / "python").glob("*.py")):
        imports |= _imports(path)
    assert {"matplotlib", "dask.distributed"} <= imports, imports
    assert _missing(imports, installed) == []


def test_test_extra_holds_the_dask_extra():
    extras = _project()["optional-dependencies"]
    test, dask = _requirements(extras["test"]), _requirements(extras["dask"])
    assert "pytest" in test
    for name, wanted in dask.items():
        assert name in test and wanted <= test[name], (name, test)


def test_missing_names_what_is_not_installed():
    # The check itself on known input: a bare `dask` does not give `dask.distributed`.
    imports = {"os", "numpy", "matplotlib.pyplot", "dask.distributed"}
    assert _missing(imports, {"numpy": set(), "dask": set()}) == [
        "dask.distributed",
        "matplotlib.pyplot",
    ]
    assert _missing(imports, {"numpy": set(), "dask": {"distributed"}, "matplotlib": set()}) == []
