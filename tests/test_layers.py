"""The floors run one way (DESIGN, issue 13 item 6): a shared base (validation, constants,
variable registry, data files, atomic writes) that imports none of the others → ``burial``, the
``rockcem`` models, ``md`` → scenes, runner, CLI and plots. Read from the source with ``ast``,
lazy imports inside functions included."""

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
BASE = {"rockcem.validation", "rockcem.constants", "rockcem.variables", "rockcem._data",
        "rockcem._atomic", "rockcem._toml"}
SCENE_LAYER = {"rockcem.scene", "rockcem.runner", "rockcem.histories", "rockcem.wellfit",
               "rockcem.__main__", "rockcem._scene_stack", "rockcem._stack_dataset",
               "rockcem._stack_seismic", "rockcem._uncertain", "rockcem._uncertain_keys",
               "rockcem._uncertain_stack",
               "rockcem.cli", "rockcem.cli_wells", "rockcem._cli_files", "rockcem.plots"}


def _module_name(path):
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _imports(path):
    """Absolute names of the modules ``path`` imports (``from . import x`` as ``pkg.x``)."""
    name = _module_name(path)
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    out = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            out.update(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[:len(base) - node.level + 1]
                mod = ".".join(base + ([node.module] if node.module else []))
            else:
                mod = node.module
            out.add(mod)
            out.update(f"{mod}.{a.name}" for a in node.names)   # submodules named in `from`
    return out


def _modules(package):
    return {_module_name(p): p for p in sorted((ROOT / package).rglob("*.py"))}


MODULES = {**_modules("rockcem"), **_modules("burial"), **_modules("md")}
GRAPH = {m: {i for i in _imports(p) if i in MODULES and i != m} for m, p in MODULES.items()}


def _layer(name):
    if name in BASE:
        return "base"
    if name.startswith("rockcem.plots") or name in SCENE_LAYER:
        return "scene"
    return name.partition(".")[0]            # rockcem (models), burial, md


@pytest.mark.parametrize("module", sorted(BASE))
def test_base_imports_only_the_base(module):
    assert {i for i in GRAPH[module] if i != "rockcem"} <= BASE, GRAPH[module]


@pytest.mark.parametrize("module", sorted(m for m in MODULES if m.startswith("burial")))
def test_burial_imports_only_the_public_base(module):
    foreign = {i for i in GRAPH[module] if not i.startswith("burial") and i != "rockcem"}
    assert foreign <= BASE - {"rockcem._data", "rockcem._atomic", "rockcem._toml"}, foreign


@pytest.mark.parametrize("module", sorted(m for m in MODULES if _layer(m) != "scene"))
def test_lower_floors_do_not_import_the_scene_layer(module):
    up = {i for i in GRAPH[module] if _layer(i) == "scene"}
    assert not up, up


#: Private modules split out of a scene-layer module for its length, which call back into it:
#: one component for the cycle check (the stack's and the uncertain section's keys are the
#: scene's; the stack's Dataset, its seismic join and the uncertain members' evaluation the
#: runner's).
PART_OF = {"rockcem._scene_stack": "rockcem.scene", "rockcem._stack_dataset": "rockcem.runner",
           "rockcem._stack_seismic": "rockcem.runner", "rockcem._uncertain": "rockcem.runner",
           "rockcem._uncertain_keys": "rockcem.scene", "rockcem._uncertain_stack": "rockcem.runner"}


def test_no_import_cycles_in_the_scene_layer():
    scene = {PART_OF.get(m, m) for m in MODULES if _layer(m) == "scene"}
    graph = {}
    for m, imports in GRAPH.items():
        graph.setdefault(PART_OF.get(m, m), set()).update(PART_OF.get(i, i) for i in imports)
    for m in graph:
        graph[m].discard(m)
    seen, stack = {}, []

    def visit(m):
        seen[m] = "open"
        stack.append(m)
        for n in graph[m] & scene:
            if n == "rockcem.plots" and m.startswith("rockcem.plots."):
                continue                            # a submodule and its package
            if seen.get(n) == "open":
                raise AssertionError(" -> ".join(stack[stack.index(n):] + [n]))
            if n not in seen:
                visit(n)
        stack.pop()
        seen[m] = "done"

    for m in sorted(scene):
        if m not in seen:
            visit(m)
