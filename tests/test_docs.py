"""The documentation builds with warnings as errors, and its API pages list the public functions.

One Sphinx build (about half a minute) into a temporary folder, as the README says to build it:
``sphinx-build -W --keep-going -b html docs <folder>``. Sphinx and its extensions are in the
``test`` extra, so CI builds the documentation; the test is skipped only where Sphinx is missing.
"""

import importlib
import inspect
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"

# Pages a reader reaches from the front page: a model family, a study, a notebook, the API.
PAGES = [
    "index.html",
    "getting_started.html",
    "user_guide/scenes.html",
    "user_guide/md_engine.html",
    "models/carcione2022.html",
    "models/pore_fluids.html",
    "disagreements.html",
    "studies/index.html",
    "studies/md_cement_findings.html",
    "_generated/notebooks/well_workflow.html",
    "references.html",
    "api/index.html",
]
# Modules whose every public function and class must be in the API pages.
MODULES = ["rockcem.pore_fluids", "rockcem.scene", "rockcem.models", "rockcem.granular", "burial",
           "md"]


@pytest.fixture(scope="module")
def html(tmp_path_factory):
    pytest.importorskip("sphinx")
    import rockcem

    # Document the rockcem under test (the installed one in CI), as the run_cli fixture runs it.
    where = str(Path(rockcem.__file__).resolve().parents[1])
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(
        [where] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p])}
    out = tmp_path_factory.mktemp("docs") / "html"
    result = subprocess.run(
        [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html", str(DOCS),
         str(out)],
        cwd=out.parent, env=env, capture_output=True, text=True, timeout=600, check=False)
    assert result.returncode == 0, f"sphinx-build failed:\n{result.stderr[-6000:]}"
    return out


@pytest.mark.slow
def test_docs_build_without_warnings(html):
    missing = [page for page in PAGES if not (html / page).is_file()]
    assert not missing, f"pages not built: {missing}"
    # Every model family and every benchmark study has its page.
    for family in (DOCS / "models").glob("*.rst"):
        assert (html / "models" / f"{family.stem}.html").is_file(), family.name
    for study in (DOCS / "studies").glob("*.md"):
        assert (html / "studies" / f"{study.stem}.html").is_file(), study.name
    # The citations of the docstrings resolve to the reference list.
    assert 'id="carcione2022"' in (html / "references.html").read_text(encoding="utf-8").lower()


@pytest.mark.slow
def test_docs_api_pages_list_every_public_function(html):
    api = html / "api" / "generated"
    ids = set()
    for page in api.glob("*.html"):
        ids.update(re.findall(r'id="([^"]+)"', page.read_text(encoding="utf-8")))
    for modname in MODULES:
        module = importlib.import_module(modname)
        # (long names in table cells may break after a dot or underscore: <wbr>, see conf.py)
        page = (api / f"{modname}.html").read_text(encoding="utf-8").replace("<wbr>", "")
        for name in module.__all__:
            obj = getattr(module, name)
            if inspect.ismodule(obj) or not callable(obj):
                continue
            # listed on the module's page (by the name it is defined under) ...
            assert f'<span class="pre">{obj.__name__}</span>' in page, f"{modname}.{name}"
            # ... and described on one of the API pages
            described = {f"{modname}.{name}", f"{obj.__module__}.{obj.__name__}"}
            assert described & ids, f"{modname}.{name} is described on no API page"
    # The functions the README and the user guide name, by their public names.
    for name in ["rockcem.pore_fluids.brine", "rockcem.scene.run_scene", "burial.quartz_cement",
                 "md.settle"]:
        modname, _, attr = name.rpartition(".")
        obj = getattr(importlib.import_module(modname), attr)
        assert {name, f"{obj.__module__}.{obj.__name__}"} & ids, name
