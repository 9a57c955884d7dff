"""The package's Python code names no model: every per-model fact, and every model a tool
picks by default, comes from the spec (``brdf_rs.models()``, ``_spec.tool_defaults()``).
Only the references, which define the models, and the engine presets of ``lut.py``, which
are the engines' conventions, name them; docstrings and comments may, as examples."""

from __future__ import annotations

import ast
import re
from pathlib import Path

import brdf_rs
from brdf_rs import _spec

PACKAGE = Path(brdf_rs.__file__).resolve().parent

#: Files that define models by name.
REFERENCES = {"reference.py", "_mpref.py"}
#: Functions whose strings are allowed to name models: the engine presets.
PRESET_TABLES = {("lut.py", "_presets")}
#: Strings that equal a model name but mean something else: the kind of a family-A
#: model's diffuse term, as ``models()`` reports it under ``"diffuse"``.
NOT_MODELS = {("_spec.py", "lambert")}


def _docstrings(tree: ast.AST) -> set[int]:
    ids = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
            body = node.body
            if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant):
                ids.add(id(body[0].value))
    return ids


def _preset_strings(tree: ast.AST, name: str) -> set[int]:
    ids = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.FunctionDef) and (name, node.name) in PRESET_TABLES:
            ids.update(id(n) for n in ast.walk(node) if isinstance(n, ast.Constant))
    return ids


def _named_models(path: Path, pattern: re.Pattern[str]) -> list[str]:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    skip = _docstrings(tree) | _preset_strings(tree, path.name)
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Constant) and isinstance(node.value, str) and id(node) not in skip:
            for name in pattern.findall(node.value):
                if (path.name, node.value) not in NOT_MODELS:
                    found.append(f"{path.name}:{node.lineno}: {name} in {node.value[:60]!r}")
    return found


def test_no_python_module_names_a_model_outside_the_references():
    names = sorted(_spec.specs(), key=len, reverse=True)
    pattern = re.compile(r"(?<![A-Za-z0-9_])(" + "|".join(names) + r")(?![A-Za-z0-9_])")
    files = [p for p in sorted(PACKAGE.glob("*.py")) if p.name not in REFERENCES]
    assert len(files) > 10
    found = [hit for path in files for hit in _named_models(path, pattern)]
    assert not found, "model names outside the spec:\n" + "\n".join(found)


def test_the_scan_finds_a_model_name_in_code_but_not_in_a_docstring(tmp_path):
    pattern = re.compile(r"(?<![A-Za-z0-9_])(ggx)(?![A-Za-z0-9_])")
    path = tmp_path / "example.py"
    path.write_text(
        '"""Uses ``"ggx"``."""\n\n# ggx\n\ndef f():\n    """ggx"""\n    return f"a {1} ggx"\n'
    )
    assert [hit.split(":")[1] for hit in _named_models(path, pattern)] == ["7"]


def test_the_tool_defaults_name_models_of_the_spec():
    defaults = _spec.tool_defaults()
    specs = _spec.specs()
    models = [
        defaults["table"]["model"],
        defaults["dfg"],
        defaults["plain_diffuse"],
        defaults["albedo_check"]["model"],
        *defaults["bench"],
    ]
    assert all(m in specs for m in models), models
    assert defaults["dfg"] in _spec.with_dfg()
    assert defaults["plain_diffuse"] in _spec.in_slot("diffuse")
