"""Rock state datasets of burial (sandstone and shale) and the variable registry."""

import subprocess
import sys

import numpy as np
import pytest
import xarray as xr

from burial import (intergranular_volume, linear_path, path_from_nodes, pressures, quartz_cement,
                    sandstone_state, shale_state, smectite_fraction)
from rockcem.variables import variable_attrs


@pytest.fixture(scope="module")
def path():
    return linear_path(30.0, 40.0, 15.0, 5000.0, depth_step=100.0)


def test_sandstone_state_values(path):
    ds = sandstone_state(path)
    igv = intergranular_volume(0.36, pressures(path).max_effective, 0.2, 0.01)
    phip = quartz_cement(path, 0.36, 0.3, 0.65)
    open_ = ds.pore_filled.values == 0
    np.testing.assert_allclose(ds.porosity.values[open_], (igv - phip)[open_], rtol=1e-14)
    np.testing.assert_allclose(ds.porosity + ds.cement_fraction, ds.intergranular_volume,
                               rtol=1e-14)
    assert float(ds.porosity.min()) >= 0.0
    np.testing.assert_allclose(ds.grain_fraction + ds.intergranular_volume, 1.0, rtol=1e-14)
    assert ds.depth.attrs["positive"] == "down" and ds.depth.attrs["standard_name"] == "depth"
    for name in ("porosity", "temperature", "pressure_effective", "burial_time"):
        assert ds[name].attrs["units"] == variable_attrs(name)["units"]


def test_shale_state_values(path):
    ds = shale_state(path)
    np.testing.assert_allclose(ds.smectite_fraction, smectite_fraction(path, 0.99), rtol=1e-14)
    pe = pressures(path).max_effective
    np.testing.assert_allclose(ds.porosity, 0.35 * np.exp(-0.01 * pe), rtol=1e-14)
    assert "cement_fraction" not in ds


def test_state_netcdf_round_trip(path, tmp_path):
    ds = sandstone_state(path)
    out = tmp_path / "state.nc"
    ds.to_netcdf(out, engine="netcdf4")
    back = xr.load_dataset(out, engine="netcdf4")
    xr.testing.assert_identical(ds, back)
    assert back.temperature.attrs["units"] == "degree_Celsius"
    assert list(back.pore_filled.attrs["flag_values"]) == [0, 1]


def test_packages_become_depths():
    t = np.linspace(0, 100, 60)
    final = np.array([3000.0, 1000.0, 2000.0])
    z = final[:, None] * t / 100
    ds = sandstone_state(path_from_nodes(t, z, 15 + 0.03 * z))
    np.testing.assert_array_equal(ds.depth, [1000.0, 2000.0, 3000.0])
    single = sandstone_state(path_from_nodes(t, final[1:2, None] * t / 100,
                                             15 + 0.03 * final[1:2, None] * t / 100))
    assert float(ds.cement_fraction.sel(depth=1000.0)) == pytest.approx(
        float(single.cement_fraction.isel(depth=0)), rel=1e-14)


def test_import_burial_does_not_load_xarray_or_numba():
    code = "import sys, burial; print([m for m in ('numba', 'xarray') if m in sys.modules])"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


def test_unknown_variable_suggests():
    with pytest.raises(ValueError, match="porosity"):
        variable_attrs("porosty")


def test_carcione2022_fig10_shale_porosity_and_density(path):
    """Fig. 10: shale porosity falls and bulk density (eq. 24, smectite 2.25, illite 2.8, water
    1.04 g/cm3, Table 1) rises with depth for G = 30 degC/km."""
    from rockcem.models import bulk_density

    ds = shale_state(path)
    beta = np.stack([ds.smectite_fraction.values, ds.illite_fraction.values], axis=-1)
    rho = bulk_density([2.25, 2.8], beta, ds.porosity.values, 1.04)
    expected = (1 - ds.porosity) * (2.25 * ds.smectite_fraction + 2.8 * ds.illite_fraction) \
        + ds.porosity * 1.04
    np.testing.assert_allclose(rho, expected, rtol=1e-14)
    assert np.all(np.diff(ds.porosity) < 0) and np.all(np.diff(rho) > 0)
    assert rho[0] == pytest.approx(0.65 * (0.99 * 2.25 + 0.01 * 2.8) + 0.35 * 1.04, rel=1e-14)
