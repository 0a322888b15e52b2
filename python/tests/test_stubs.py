"""The type stubs declare every public name of the native module, every public attribute of
Model and Shape, and every exception attribute (so editors complete what exists)."""

import ast
from pathlib import Path

import ccrkit
from ccrkit import _native

STUBS = Path(ccrkit.__file__).parent


def declared():
    tree = ast.parse((STUBS / "_native.pyi").read_text())
    top, members = set(), {}
    for node in tree.body:
        if isinstance(node, (ast.ClassDef, ast.FunctionDef)):
            top.add(node.name)
        elif isinstance(node, ast.AnnAssign):  # module constants (`DEFAULT_METHOD: str`)
            top.add(node.target.id)
        if isinstance(node, ast.ClassDef):
            names = set()
            for n in node.body:
                if isinstance(n, ast.FunctionDef):
                    names.add(n.name)
                elif isinstance(n, ast.AnnAssign):
                    names.add(n.target.id)
            members[node.name] = names
    return top, members


def test_stubs_cover_the_native_module():
    top, members = declared()
    public = {n for n in dir(_native) if not n.startswith("__")}
    assert public <= top, public - top
    for cls in ("Model", "Shape", "Reach", "Plan"):
        attrs = {n for n in dir(getattr(_native, cls)) if not n.startswith("_")}
        assert attrs <= members[cls], (cls, attrs - members[cls])
    try:
        ccrkit.Model.from_toml("")
    except ccrkit.SolveError as e:
        attrs = {n for n in vars(e) if not n.startswith("_")}
        assert attrs <= members["SolveError"], attrs - members["SolveError"]
    init = ast.parse((STUBS / "__init__.pyi").read_text())
    names = {a.asname or a.name for n in init.body if isinstance(n, ast.ImportFrom) for a in n.names}
    names |= {n.name for n in init.body if isinstance(n, ast.FunctionDef)}
    assert set(ccrkit.__all__) <= names, set(ccrkit.__all__) - names
