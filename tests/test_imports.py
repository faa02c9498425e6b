"""What importing the package pulls in: `import rockcem` never imports numba (or xarray)."""

import subprocess
import sys

import pytest


@pytest.mark.parametrize("module", ["rockcem", "rockcem.models", "rockcem.calibrate"])
def test_import_does_not_load_numba(module):
    code = (f"import sys, {module}; "
            "bad = [m for m in ('numba', 'xarray') if m in sys.modules]; "
            "print(','.join(bad))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == ""


def test_small_self_consistent_does_not_load_numba():
    """Model 2 below rockcem.inclusions._NUMBA_MIN_POINTS stays on the numpy path: no numba."""
    code = ("import sys, numpy as np; from rockcem import inclusions, models, materials; "
            "n = inclusions._NUMBA_MIN_POINTS // 10; "
            "phi = np.linspace(0.36, 0.02, n); "
            "beta = np.stack([0.9 + 0 * phi, 0.1 + 0 * phi], -1); "
            "q, c, w = (materials.mineral('quartz'), materials.mineral('quartz_cement'), "
            "materials.fluid('water')); "
            "models.self_consistent_model([q, c], beta, phi, w, aspect_ratio=0.108); "
            "print('numba' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_cli_materials_lists_catalogue():
    out = subprocess.run([sys.executable, "-m", "rockcem.cli", "materials"], capture_output=True,
                         text=True, check=True)
    assert "quartz" in out.stdout and "water" in out.stdout


def test_cli_bad_command_exit_code_2():
    out = subprocess.run([sys.executable, "-m", "rockcem.cli", "nonsense"], capture_output=True,
                         text=True)
    assert out.returncode == 2


def test_datasets_found_outside_the_source_tree(tmp_path):
    """The installed package has all its sub-packages and data files (run from outside the
    checkout, so the import is the installed wheel in CI, not the source tree)."""
    code = ("import rockcem.plots, burial, md; "
            "from rockcem.scene import shipped_scenes; from rockcem.materials import mineral; "
            "from rockcem.variables import variable_attrs; "
            "print(len(shipped_scenes()) > 0 and mineral('quartz').K == 40.0 "
            "and variable_attrs('vp')['units'] == 'km s-1')")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         cwd=tmp_path, check=True)
    assert out.stdout.strip() == "True"


def test_engine_numpy_never_loads_numba_and_scenes_default_to_it():
    """engine="numpy" keeps a large Model 2 (above the numba threshold) off numba, and a scene's
    models.self_consistent.engine defaults to "numpy" (DESIGN: a scene without MD never imports
    numba)."""
    code = ("import sys, numpy as np; from rockcem.models import self_consistent_model; "
            "from rockcem.materials import mineral, fluid; "
            "from rockcem.inclusions import _NUMBA_MIN_POINTS; "
            "from rockcem.scene import SCHEMA; "
            "phi = np.linspace(0.35, 0.05, _NUMBA_MIN_POINTS + 10); "
            "m = self_consistent_model([mineral('quartz')], np.ones((phi.size, 1)), phi, "
            "fluid('water'), aspect_ratio=0.108, engine='numpy'); "
            "print('numba' in sys.modules, SCHEMA['models.self_consistent']['engine'][0])")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.split() == ["False", "numpy"]


def test_bad_engine_names_the_argument(expect_value_error):
    from rockcem.inclusions import self_consistent

    expect_value_error(lambda: self_consistent([40.0, 2.0], [30.0, 0.0], [0.7, 0.3],
                                               engine="fast"), "engine")


def test_subpackages_are_attributes_imported_on_first_use():
    """``import rockcem; rockcem.pore_fluids`` works, and only when asked does it import the
    sub-package (PEP 562 module __getattr__): import rockcem stays as light as the models."""
    code = ("import sys, rockcem; "
            "before = [m for m in ('rockcem.pore_fluids', 'rockcem.scene', 'rockcem.plots') "
            "if m in sys.modules]; "
            "k = rockcem.pore_fluids.brine(20.0, 10.0, 0.05).K; "
            "print(before, 'rockcem.pore_fluids' in sys.modules, "
            "rockcem.scene.run_scene.__module__, 'pore_fluids' in dir(rockcem)); "
            "rockcem.no_such_thing")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.stdout.split() == ["[]", "True", "rockcem.scene", "True"]
    assert "AttributeError: module 'rockcem' has no attribute 'no_such_thing'" in out.stderr


def test_every_public_sub_module_is_an_attribute():
    """The sub-modules a user reaches for, each by ``rockcem.<name>`` after ``import rockcem``
    alone (listed here by hand, not read from rockcem._LAZY)."""
    names = ["anisotropy", "calibrate", "contact_integral", "plots", "pore_fluids", "references",
             "scene", "variables", "wells", "validity", "models", "granular", "materials"]
    code = ("import rockcem; "
            f"print(all(getattr(rockcem, n).__name__ == 'rockcem.' + n for n in {names!r}), "
            f"set({names!r}) <= set(dir(rockcem)))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.split() == ["True", "True"]
