"""The shipped well example (synthetic basin with hiatus and uplift, synthetic LAS) and the
well commands of the CLI: compare, fit, plot --well."""

import tomllib

import numpy as np
import pytest

from rockcem._data import data_path
from rockcem.cli import main
from rockcem.scene import load_scene, run_scene
from rockcem.synthetic_well import synthetic_well
from rockcem.variables import variable_attrs
from rockcem.wells import read_well

TRUE = {"models.patchy_cement.coordination_number": 6.5, "models.patchy_cement.delta": 40.0}


@pytest.fixture(scope="module")
def las():
    return data_path("wells", "synthetic_well.las")


def test_shipped_las_is_the_documented_synthetic(las):
    """The LAS file is what datasets/wells/README.md says: the scene at TRUE plus noise."""
    well = read_well(las)
    scene = load_scene("synthetic_basin_horizons").replace(**TRUE)
    depth = np.arange(1000.0, 10300.0 + 1.0, 10.0) * 0.3048
    again = synthetic_well(run_scene(scene), depth, model="patchy_cement", seed=2026,
                           sigma={"vp": 0.06, "vs": 0.04, "density": 0.025, "porosity": 0.012})
    np.testing.assert_allclose(well.depth, depth, rtol=1e-12)
    for v in ("vp", "vs", "density", "porosity"):
        np.testing.assert_allclose(well[v], again[v], rtol=0, atol=6e-7, err_msg=v)  # %.6f
    assert "SYNTHETIC DATA" in las.read_text()


def test_shipped_history_compacts_at_the_deepest_burial():
    from burial import intergranular_volume
    from rockcem.constants import STANDARD_GRAVITY

    deep = run_scene(load_scene("synthetic_basin_horizons")).isel(depth=-1)
    assert deep.horizon == "H80" and float(deep.depth) == 3200.0
    # Buried to 3500 m at 15 Ma, uplifted to 2900 m, now at 3200 m: compacted as at 3500 m.
    pe_max = 1e-3 * STANDARD_GRAVITY * (2.5 - 1.04) * 3500.0
    np.testing.assert_allclose(deep.intergranular_volume,
                               intergranular_volume(0.36, pe_max, 0.2, 0.01), rtol=1e-14)


def test_cli_compare_fit_and_plot(las, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main(["run", "synthetic_basin_horizons", "-q", "-o", "s.nc"]) == 0
    import xarray as xr

    back = xr.load_dataset(tmp_path / "s.nc", engine="netcdf4")
    assert back.horizon.values[-1] == "H80"
    assert back.horizon.attrs["long_name"] == variable_attrs("horizon")["long_name"]
    assert main(["compare", "s.nc", "--well", str(las), "--intervals", "300", "1500",
                 "3200"]) == 0
    out = capsys.readouterr().out
    assert "patchy_cement" in out and "hs_gassmann" in out and "1500" in out
    assert main(["plot", "s.nc", "--well", str(las)]) == 0
    assert (tmp_path / "s_depth_well.png").stat().st_size > 0
    assert main(["plot", "s.nc", "--well", str(las), "--kind", "template"]) == 0
    assert (tmp_path / "s_template_well.png").stat().st_size > 0
    assert main(["fit", "synthetic_basin_horizons", "--well", str(las), "--model",
                 "patchy_cement", "--log", "vp", "--log", "vs", "--free",
                 "models.patchy_cement.coordination_number", "--free",
                 "models.patchy_cement.delta=0:300", "--depth", "500", "3100",
                 "--error", "vp=0.06", "--error", "vs=0.04", "-o", "cal.toml"]) == 0
    out = capsys.readouterr().out
    cal = tomllib.loads((tmp_path / "cal.toml").read_text())
    for k, true in TRUE.items():
        assert abs(cal["parameters"][k] - true) < 3.0 * cal["uncertainty"][k], out
    assert (tmp_path / "synthetic_basin_horizons_well_fit.png").stat().st_size > 0
    assert main(["fit", "synthetic_basin_horizons", "--well", str(las), "--free",
                 "sandstone.nope"]) == 2
    assert "not a key of this scene" in capsys.readouterr().err
    assert main(["compare", "s.nc", "--well", "missing.las"]) == 2
    capsys.readouterr()
    assert main(["fit", "s.nc", "--well", str(las), "--free", "sandstone.beta"]) == 2
    assert "not the netCDF output of a run" in capsys.readouterr().err
    assert main(["fit", "synthetic_basin_horizons", "--well", str(las), "--free",
                 "path.gradient", "--model", "patchy_cement"]) == 2
    assert "does not apply to a path of kind 'horizons'" in capsys.readouterr().err
