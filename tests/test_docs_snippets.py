"""The Python of the documentation runs, and says what the pages beside it say.

Every ```python block of a page in :data:`PAGES` is run, the page's blocks in order as one
program, in a fresh process in an empty folder (so files it writes land there); a page with
Python that is not run is in :data:`NOT_RUN` with the reason. The shipped scenes' descriptions
(``rockcem scenes``) name no file that a pip install does not ship.
"""

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"

#: Pages whose Python is run.
PAGES = ["getting_started.md", "user_guide/pore_fluids.md", "user_guide/wells.md",
         "user_guide/burial.md", "user_guide/models.md", "user_guide/labelled_inputs.md",
         "user_guide/avo.md"]
#: Pages with Python that is not run here, and why.
NOT_RUN = {"user_guide/md_engine.md": "settles an MD pack; the first run compiles numba's "
                                      "kernels (minutes on a cold cache; tests/md covers it)"}


def blocks(page: str) -> list[str]:
    """The ```python blocks of a page, in order."""
    text = (DOCS / page).read_text(encoding="utf-8")
    return re.findall(r"^```python\n(.*?)^```", text, flags=re.S | re.M)


def run_page(page, folder):
    """Run a page's Python in ``folder``, with the rockcem under test; returns stdout."""
    import rockcem

    root = str(Path(rockcem.__file__).resolve().parents[1])
    env = {**os.environ, "MPLBACKEND": "Agg", "PYTHONPATH": os.pathsep.join(
        [root] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p])}
    code = "\n".join(blocks(page))
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         cwd=folder, env=env, timeout=600)
    assert out.returncode == 0, f"{page}:\n{out.stderr[-3000:]}"
    return out.stdout


def test_every_page_with_python_is_run_or_excused():
    with_python = {str(p.relative_to(DOCS)) for p in DOCS.rglob("*.md")
                   if "_build" not in p.parts and blocks(str(p.relative_to(DOCS)))}
    assert with_python == set(PAGES) | set(NOT_RUN)


@pytest.mark.parametrize("page", ["getting_started.md", "user_guide/burial.md",
                                  "user_guide/models.md"])
def test_snippets_run(page, tmp_path):
    run_page(page, tmp_path)


def test_labelled_inputs_snippets_print_what_the_page_says(tmp_path):
    """The labelled-inputs page: the xarray brine on (depth, scenario) in GPa, and the Voigt
    average of phases matched by label, 0.8 x 37 + 0.2 x 76.8 = 44.96 and 56.9 GPa."""
    printed = run_page("user_guide/labelled_inputs.md", tmp_path)
    assert "('depth', 'scenario') GPa" in printed
    values = re.findall(r"^(\d+(?:\.\d+)?)\s+([\d.]+)$", printed, re.M)
    assert [(float(z), round(float(v), 2)) for z, v in values][-2:] == [(1500.0, 44.96),
                                                                        (2500.0, 56.9)]


def test_pore_fluid_snippet_prints_the_page_s_brine_table(tmp_path):
    """The page's snippets print what the page says: the brine at 80 °C and 30 MPa of the
    first is its comment's values, the brine at 0, 2000 and 4000 m of the second is the page's
    table there (K, rho, vp), and its warning names the salinity."""
    printed = run_page("user_guide/pore_fluids.md", tmp_path).splitlines()
    text = (DOCS / "user_guide/pore_fluids.md").read_text(encoding="utf-8")
    said = re.search(r"# ([\d.]+) GPa, ([\d.]+) g/cm³, ([\d.]+) km/s", text).groups()
    assert [round(float(v), 3) for v in printed[0].split()] == list(map(float, said))
    arrays = next(line for line in printed if line.startswith("["))
    K, rho, vp = (list(map(float, part.split())) for part in re.findall(r"\[([^\]]*)\]", arrays))
    table = {float(m[0]): tuple(map(float, m[1:])) for m in re.findall(
        r"^\| (\d+) \| [\d.]+ \| [\d.]+ \| ([\d.]+) \| ([\d.]+) \| ([\d.]+) \|$", text, re.M)}
    assert [table[z] for z in (0.0, 2000.0, 4000.0)] == list(zip(K, rho, vp))
    assert "salinity above 0.3" in printed[-1]


@pytest.mark.slow
def test_wells_snippet_fit_is_the_page_s(tmp_path):
    """The snippet's fit gives the values the page states (6.47 ± 0.09 and 39.9 ± 1.7 MPa)."""
    printed = run_page("user_guide/wells.md", tmp_path)
    n = re.search(r"coordination_number = ([\d.]+) \+- ([\d.]+)", printed)
    delta = re.search(r"delta = ([\d.]+) \+- ([\d.]+)", printed)
    # the page's values to the digits it gives (the summary prints 3 significant digits:
    # 1.75 may be 1.7 to one decimal)
    assert abs(float(n[1]) - 6.47) <= 0.0051 and abs(float(n[2]) - 0.09) <= 0.0051
    assert abs(float(delta[1]) - 39.9) <= 0.051 and abs(float(delta[2]) - 1.7) <= 0.051
    text = (DOCS / "user_guide/wells.md").read_text(encoding="utf-8")
    assert "6.47 ±\n0.09 and 39.9 ± 1.7 MPa" in text or "6.47 ± 0.09 and 39.9 ± 1.7 MPa" in text
    assert (tmp_path / "synthetic_well.png").is_file()


def test_scene_descriptions_name_only_shipped_files():
    """Issue 30: `rockcem scenes` pointed at benchmarks/ and docs/ files, which a pip install
    does not ship; a file a description names must be one of the shipped datasets."""
    from rockcem._data import data_path
    from rockcem.scene import read_scene_toml, shipped_scenes

    shipped = {p.name for p in data_path().rglob("*") if p.is_file()}
    for name, path in shipped_scenes().items():
        description = read_scene_toml(path)[0].get("description", "")
        assert not re.search(r"\b(docs|benchmarks|notebooks|tests)/", description), name
        for file in re.findall(r"[\w./-]+\.(?:py|md|ipynb|toml|csv|las|nc)\b", description):
            assert Path(file).name in shipped, (name, file)


def test_avo_snippet_prints_the_page_s_classes(tmp_path):
    """The AVO page's snippet runs the shipped stack scene (CO2 through CoolProp) and prints
    Model 4's class at 1-4 km for brine, gas and CO2: the classes of the page's table, which
    benchmarks/avo_scene.py made; and it writes its three figures."""
    pytest.importorskip("CoolProp")
    printed = run_page("user_guide/avo.md", tmp_path)
    rows = re.findall(r"^(\d+)\.0\s+(\S+)\s+(\S+)\s+(\S+)\s*$", printed, re.M)
    text = (DOCS / "user_guide/avo.md").read_text(encoding="utf-8")
    table = {m[0]: (m[1], m[2], m[3]) for m in re.findall(
        r"^\| (\d+) \| 4 \(patchy cement\) \| [-\d.]+ \| [-\d.]+ \| (\w+) \| [-\d.]+ \| "
        r"[-\d.]+ \| (\w+) \| [-\d.]+ \| [-\d.]+ \| (\w+) \|$", text, re.M)}
    assert sorted(table) == ["1000", "2000", "3000", "4000"]
    assert {z: (b, g, c) for z, b, g, c in rows} == table
    for name in ("avo_class.png", "avo_crossplot.png", "avo_synthetic.png"):
        assert (tmp_path / name).is_file(), name
