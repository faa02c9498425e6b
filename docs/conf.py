"""Sphinx configuration of the rockcem documentation.

Build (from the repository root, with ``python -m pip install -e ".[docs]"``)::

    sphinx-build -W --keep-going -b html docs docs/_build/html

Some pages are written here at build time, into ``docs/_generated/`` (git-ignored), from the
package itself, so that they cannot fall behind it: the scene keys (``rockcem.scene.SCHEMA``), the
shipped scenes, the reference list (``rockcem.references.REFERENCES``, so that every
``[Carcione2022]_`` of a docstring resolves) and copies of the notebooks under ``notebooks/``
(stored with their outputs; they are not executed here). The API pages come from autosummary with
the template in ``_templates/autosummary/module.rst`` and the table of contents worked out below
(:func:`_api_context`): each public name is described once, in the module that defines it, and
listed with a link in every public module that re-exports it.

MathJax comes from its CDN (Sphinx's default). To read the pages offline, pass a local copy::

    sphinx-build ... -D mathjax_path=mathjax/es5/tex-mml-chtml.js   # relative to _static

and copy MathJax's ``es5`` folder to ``<build>/_static/mathjax/es5``.
"""

from __future__ import annotations

import importlib
import inspect
import pkgutil
import re
import shutil
from pathlib import Path

import sphinx.ext.autosummary

import rockcem

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
GENERATED = DOCS / "_generated"
TOP_PACKAGES = ("rockcem", "burial", "md")

# -- project -------------------------------------------------------------------------------------

project = "rockcem"
author = "The rockcem developers"
copyright = "The rockcem developers"
release = rockcem.__version__
version = release

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "numpydoc",
    "sphinx.ext.mathjax",
    "myst_nb",
    "sphinx_copybutton",
]

templates_path = ["_templates"]
exclude_patterns = ["_build", "_generated/*.inc", "**/.ipynb_checkpoints", ".gitignore"]
source_suffix = {".rst": "restructuredtext", ".md": "myst-nb", ".ipynb": "myst-nb"}
root_doc = "index"
default_role = "code"          # `x` in reST is code, as in Markdown

# -- HTML ----------------------------------------------------------------------------------------

html_theme = "pydata_sphinx_theme"
html_title = f"rockcem {release}"
html_static_path = ["_static"]
html_css_files = ["rockcem.css"]
html_show_sourcelink = False
html_theme_options = {
    "navbar_align": "left",
    "header_links_before_dropdown": 7,
    "show_toc_level": 2,
    "navigation_with_keys": False,
    "secondary_sidebar_items": ["page-toc"],
    "footer_start": ["copyright"],
    "footer_end": ["sphinx-version"],
}
# No left column on pages that have no section of their own to navigate.
html_sidebars = {page: [] for page in ("index", "getting_started", "disagreements", "references")}

# -- extensions ----------------------------------------------------------------------------------

autosummary_generate = True
# The one-line summaries end at the first full stop; not at the one of "eq." or "Sect.".
sphinx.ext.autosummary.WELL_KNOWN_ABBREVIATIONS = (
    *sphinx.ext.autosummary.WELL_KNOWN_ABBREVIATIONS,
    "eq.", "eqs.", "Eq.", "Eqs.", "Sect.", "Sects.", "App.", "Fig.", "Figs.", "approx.", "cf.")
autosummary_imported_members = False
autosummary_ignore_module_all = False
autodoc_member_order = "bysource"
autodoc_typehints = "none"          # the numpydoc sections give types and units
autodoc_default_options = {}

numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_validation_checks = set()
numpydoc_xref_param_type = False
numpydoc_attributes_as_param_list = True

myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence", "deflist", "attrs_inline"]
myst_heading_anchors = 3
nb_execution_mode = "off"           # the notebooks are stored with their outputs (and tested)
nb_merge_streams = True

copybutton_prompt_text = r">>> |\.\.\. |\$ "
copybutton_prompt_is_regexp = True

# intersphinx stays off: the build needs no network.


# -- pages written at build time -----------------------------------------------------------------

def _write_if_changed(path: Path, text: str) -> None:
    """Write ``text`` to ``path`` unless it already holds it (keeps incremental builds quiet)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    if not path.exists() or path.read_text(encoding="utf-8") != text:
        path.write_text(text, encoding="utf-8")


def _rst_escape(text: str) -> str:
    """Escape the characters reST would read as markup in plain descriptive text."""
    return re.sub(r"([\\`*_|\[\]<>])", r"\\\1", str(text))


def _copy_notebooks() -> None:
    for notebook in sorted((ROOT / "notebooks").glob("*.ipynb")):
        target = GENERATED / "notebooks" / notebook.name
        target.parent.mkdir(parents=True, exist_ok=True)
        if not target.exists() or target.read_bytes() != notebook.read_bytes():
            shutil.copyfile(notebook, target)


def _citations() -> None:
    from rockcem.references import REFERENCES

    lines = [f".. [{key}] {_rst_escape(text)}" for key, text in sorted(REFERENCES.items())]
    _write_if_changed(GENERATED / "citations.inc", "\n\n".join(lines) + "\n")


def _scene_keys() -> None:
    """The key tables of ``rockcem schema`` as reST list tables, one per section."""
    from rockcem.scene import SCHEMA

    def shown(default):
        if type(default) is object:         # the schema's "required" sentinel
            return "required"
        return "–" if default is None else f"``{default!r}``"

    out = []
    for section, keys in SCHEMA.items():
        title = "top level" if section == "scene" else f"[{section}]"
        out += [f".. rubric:: {title}", "", ".. list-table::", "   :header-rows: 1",
                "   :widths: 20 10 11 15 44", "   :class: scene-keys", "",
                "   * - key", "     - kind", "     - unit", "     - default", "     - meaning"]
        for key, (default, kind, unit, doc) in keys.items():
            out += [f"   * - ``{key}``", f"     - {kind}", f"     - {_rst_escape(unit) or '–'}",
                    f"     - {shown(default)}", f"     - {_rst_escape(doc)}"]
        out.append("")
    _write_if_changed(GENERATED / "scene_keys.inc", "\n".join(out))

    from md.experiment import schema_lines

    block = ["::", ""] + ["   " + line for line in schema_lines()] + [""]
    _write_if_changed(GENERATED / "md_study_keys.inc", "\n".join(block))


def _shipped_scenes() -> None:
    import tomllib

    from rockcem.scene import shipped_scenes

    out = [".. list-table::", "   :header-rows: 1", "   :widths: 35 65", "   :class: scene-list", "",
           "   * - scene", "     - description"]
    for name, path in shipped_scenes().items():
        with open(path, "rb") as fh:
            description = tomllib.load(fh).get("description", "")
        out += [f"   * - ``{name}``", f"     - {_rst_escape(description) or '–'}"]
    _write_if_changed(GENERATED / "shipped_scenes.inc", "\n".join(out) + "\n")


# -- the API pages -------------------------------------------------------------------------------

def _modules(public: bool = True) -> list:
    """rockcem, burial, md and their submodules (the private ones only if ``public`` is False)."""
    found = []

    def walk(name):
        module = importlib.import_module(name)
        found.append(module)
        for info in pkgutil.iter_modules(getattr(module, "__path__", [])):
            if public and info.name.startswith("_"):
                continue
            walk(f"{name}.{info.name}")

    for top in TOP_PACKAGES:
        walk(top)
    return found


def _defines(module, name: str) -> bool:
    """Whether ``module``'s source assigns the module-level name ``name``."""
    try:
        source = inspect.getsource(module)
    except (OSError, TypeError):
        return False
    return re.search(rf"^{re.escape(name)}\s*(:[^=\n]*)?=", source, re.MULTILINE) is not None


def _is_public(modname: str) -> bool:
    return not any(part.startswith("_") for part in modname.split("."))


_ALIASES: dict[str, str] = {}     # exported name -> where it is described, e.g. burial.quartz_cement


def _api_context() -> dict:
    """Per public module: its submodules, the names it describes and the names it lists.

    A function or class is described where it is defined (``__module__``), or, where that module
    is private, in the public module nearest to it that exports it; a constant where its module
    assigns it. Every other public module that exports a name lists it with a link.
    """
    modules = _modules()
    by_name = {m.__name__: m for m in modules}
    exporters: dict[int, list] = {}
    for module in modules:
        for name in module.__all__:
            exporters.setdefault(id(getattr(module, name)), []).append((module.__name__, name))

    def home(module, name, obj):
        if inspect.isclass(obj) or callable(obj):
            modname = getattr(obj, "__module__", module.__name__)
            objname = getattr(obj, "__name__", name)
            if modname in by_name and _is_public(modname) and objname in by_name[modname].__all__:
                return modname, objname
            candidates = [m for m, n in exporters[id(obj)] if n == name]
            return max(candidates, key=lambda m: (len(_common_prefix(m, modname)), -len(m))), name
        if _defines(module, name):
            return module.__name__, name
        for modname, exported in exporters.get(id(obj), []):
            if exported == name and _defines(by_name[modname], name):
                return modname, name
        return module.__name__, name

    context = {}
    _ALIASES.clear()
    for module in modules:
        describe, listed, aliases = [], [], []
        for name in module.__all__:
            obj = getattr(module, name)
            if inspect.ismodule(obj):
                continue
            modname, objname = home(module, name, obj)
            target = f"{modname}.{objname}"
            # relative to the page's module, as autosummary wants it there
            listed.append("~" + target.removeprefix(f"{module.__name__}."))
            if objname != name:
                aliases.append((name, target))
            if target != f"{module.__name__}.{name}":
                _ALIASES[f"{module.__name__}.{name}"] = target
            if modname == module.__name__ and objname == name:
                describe.append((_kind(obj), name, _options(obj)))
        children = sorted(m.__name__.rpartition(".")[2] for m in modules
                          if m.__name__.rpartition(".")[0] == module.__name__)
        # A submodule whose name the package reuses for something else (md.bond_stiffness, a
        # module and a function) would be taken for that thing by autosummary: its page is
        # written here instead (_shadowed_pages) and joined by a plain toctree.
        shadowed = [c for c in children if not inspect.ismodule(getattr(module, c, None))]
        context[module.__name__] = {"describe": describe, "listed": listed, "aliases": aliases,
                                    "submodules": [c for c in children if c not in shadowed],
                                    "shadowed": shadowed}
    return context


def _common_prefix(a: str, b: str) -> str:
    parts = []
    for x, y in zip(a.split("."), b.split(".")):
        if x != y:
            break
        parts.append(x)
    return ".".join(parts)


def _kind(obj) -> str:
    if inspect.isclass(obj):
        return "exception" if issubclass(obj, BaseException) else "class"
    return "function" if callable(obj) else "data"


def _options(obj) -> list[str]:
    if inspect.isclass(obj):
        return [":members:"]
    if not callable(obj) and len(repr(obj)) > 70:
        return [":no-value:"]
    return []


def _resolve_alias(app, env, node, contnode):
    """Resolve what the Python domain could not: an exported name (``burial.quartz_cement``,
    described as ``burial.quartz.quartz_cement``), a name relative to a parent module of the
    docstring it is in, or a short name that only one described object ends with."""
    if node.get("refdomain") != "py":
        return None
    python = env.get_domain("py")
    target = node.get("reftarget", "")
    parts = (node.get("py:module") or "").split(".") if node.get("py:module") else []
    candidates = [target] + [".".join(parts[:i] + [target]) for i in range(len(parts), 0, -1)]
    for name in candidates:
        head, _, rest = name.rpartition(".")          # a member of an exported class
        name = _ALIASES.get(name) or (f"{_ALIASES[head]}.{rest}" if head in _ALIASES else name)
        if name in python.objects:
            return python.resolve_xref(env, node["refdoc"], app.builder, node["reftype"], name,
                                       node, contnode)
    ends = [name for name in python.objects if name.endswith(f".{target}")]
    if len(ends) == 1:
        return python.resolve_xref(env, node["refdoc"], app.builder, node["reftype"], ends[0],
                                   node, contnode)
    return None


def _skip_member(app, what, name, obj, skip, options):
    """Leave out the fields a NamedTuple documents as "Alias for field number N"."""
    doc = getattr(obj, "__doc__", None) or ""
    if what == "class" and doc.startswith("Alias for field number"):
        return True
    return None


def _drop_type_docstring(app, what, name, obj, options, lines):
    """A constant with no docstring of its own shows its value, not the docstring of ``float``."""
    if what in ("data", "attribute") and not callable(obj) and lines:
        own = inspect.cleandoc(type(obj).__doc__ or "").splitlines()
        if own and lines[0].strip() == own[0].strip():
            lines[:] = []


def _shadowed_pages(context: dict) -> None:
    """Write the API pages of the submodules autosummary would mistake (see _api_context)."""
    import jinja2

    env = jinja2.Environment(loader=jinja2.FileSystemLoader(DOCS / "_templates" / "autosummary"))
    env.filters["escape"] = lambda text: re.sub(r"([\\`*_|])", r"\\\1", text)
    env.filters["underline"] = lambda text, char="=": f"{text}\n{char * len(text)}"
    template = env.get_template("module.rst")
    for package, info in context.items():
        for child in info["shadowed"]:
            fullname = f"{package}.{child}"
            _write_if_changed(DOCS / "api" / "generated" / f"{fullname}.rst",
                              template.render(fullname=fullname, api=context) + "\n")


# Written when Sphinx reads this file, before it looks for sources.
_copy_notebooks()
_citations()
_scene_keys()
_shipped_scenes()
autosummary_context = {"api": _api_context()}
_shadowed_pages(autosummary_context["api"])


_CELL = re.compile(r"<td>.*?</td>", re.DOTALL)
_PRE = re.compile(r'(<span class="pre">)([^<]+)(</span>)')


def _break_long_names(app, exception):
    """Let long dotted names in table cells (``md.along_depth.carry_down``) break after a dot or
    an underscore (``<wbr>``, which copies as nothing), so that tables fit the column."""
    if exception is not None or app.builder.format != "html":
        return
    def cell(match):
        return _PRE.sub(lambda m: m.group(1) + re.sub(r"([._])(?=\w)", r"\1<wbr>", m.group(2))
                        + m.group(3), match.group(0))
    for page in Path(app.outdir).rglob("*.html"):
        text = page.read_text(encoding="utf-8")
        if "<td>" in text:
            new = _CELL.sub(cell, text)
            if new != text:
                page.write_text(new, encoding="utf-8")


def setup(app):
    app.connect("autodoc-skip-member", _skip_member)
    app.connect("missing-reference", _resolve_alias)
    app.connect("build-finished", _break_long_names)
    app.connect("autodoc-process-docstring", _drop_type_docstring, priority=100)
