"""No docstring holds a control character: in a non-raw docstring ``\\to``, ``\\beta`` or
``\\nu`` is a tab, a backspace or a newline, which the rendered maths shows as garbage (a
Sphinx build once broke on one)."""

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
FILES = sorted(p for pkg in ("rockcem", "burial", "md") for p in (ROOT / pkg).rglob("*.py"))
CONTROL = {"\t": "\\t", "\a": "\\a", "\b": "\\b", "\v": "\\v", "\f": "\\f", "\r": "\\r"}


@pytest.mark.parametrize("path", FILES, ids=[str(p.relative_to(ROOT)) for p in FILES])
def test_no_control_characters_in_docstrings(path):
    tree = ast.parse(path.read_text(encoding="utf-8"))
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
            doc = ast.get_docstring(node, clean=False) or ""
            found = sorted({CONTROL[c] for c in doc if c in CONTROL})
            assert not found, (f"{path.name}: docstring of {getattr(node, 'name', 'module')} "
                               f"holds {found}: escape the backslash (\\\\to) or make it raw")
