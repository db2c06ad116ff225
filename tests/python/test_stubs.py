"""The .pyi stubs describe the compiled module: same public names, same signatures' arguments."""
from __future__ import annotations

import ast
import inspect
from pathlib import Path

from packsim import _packsim

STUB = Path(__file__).resolve().parents[2] / "python" / "packsim" / "_packsim.pyi"


def _stub():
    tree = ast.parse(STUB.read_text())
    funcs, classes = {}, {}
    for node in tree.body:
        if isinstance(node, ast.FunctionDef):
            funcs[node.name] = [a.arg for a in node.args.args]
        elif isinstance(node, ast.ClassDef):
            classes[node.name] = {n.name for n in node.body if isinstance(n, ast.FunctionDef)}
    return funcs, classes


def test_stub_matches_module():
    funcs, classes = _stub()
    public = {n for n in dir(_packsim) if not n.startswith("_")}
    assert public == set(funcs) | set(classes)
    for name, args in funcs.items():
        doc = getattr(_packsim, name).__doc__.splitlines()[0]  # pybind11 signature line
        for a in args:
            assert f"{a}:" in doc, (name, a, doc)
    for cls, members in classes.items():
        assert members <= set(dir(getattr(_packsim, cls)))
    assert inspect.isclass(_packsim.RunHandle)
