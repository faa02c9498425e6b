"""The scene's pore fluid (issue 30): every hydrocarbon of the table computed by its own source,
every fluid's validity in the scene's warnings (CO2 and methane against their equations of
state's ranges), Brie's law and the patchy fluid density at hand-computed values, and CoolProp
absent or broken named in one line."""

import sys

import numpy as np
import pytest

from rockcem import pore_fluids as pf
from rockcem.constants import STANDARD_ATMOSPHERE
from rockcem.scene import HYDROCARBONS, run_scene, scene_from_dict

BASE = {"name": "f", "lithology": "sandstone",
        "path": {"max_depth": 4000.0, "depth_step": 500.0}, "models": {"hs_gassmann": {}}}
RESERVOIR = {"model": "batzle_wang", "salinity": 0.05, "saturation": 0.8, "top": 2000.0,
             "base": 3000.0}


def run(fluid, **extra):
    return run_scene(scene_from_dict({**BASE, "fluid": fluid, **extra}))


def state(ds):
    """The reservoir's depths and their temperature and absolute pore pressure."""
    z = ds.depth.values
    inside = (z >= 2000.0) & (z <= 3000.0)
    return inside, ds.temperature.values[inside], \
        ds.pressure_pore.values[inside] + STANDARD_ATMOSPHERE


def test_the_hydrocarbon_table_is_what_these_tests_cover():
    assert set(HYDROCARBONS) == {"none", "gas", "oil", "co2", "methane"}


@pytest.mark.parametrize("kind", ["gas", "oil", "co2", "methane"])
def test_every_hydrocarbon_is_computed_by_its_own_source(kind):
    """With the hydrocarbon in every pore of the interval (saturation 1) the scene's fluid is
    the hydrocarbon itself, as its own function gives it at each depth's T and P: a table entry
    that called another fluid's function would show here."""
    if kind in ("co2", "methane"):
        pytest.importorskip("CoolProp")
    given = {"gas": {"gas_gravity": 0.7}, "oil": {"oil_api": 35.0, "gas_oil_ratio": 40.0},
             "co2": {}, "methane": {}}[kind]
    ds = run({**RESERVOIR, "saturation": 1.0, "hydrocarbon": kind, **given})
    inside, T, P = state(ds)
    expect = {"gas": lambda: pf.gas(T, P, 0.7),
              "oil": lambda: pf.oil(T, P, api=35.0, gas_oil_ratio=40.0, gas_gravity=0.6),
              "co2": lambda: pf.co2(T, P), "methane": lambda: pf.methane(T, P)}[kind]()
    np.testing.assert_allclose(ds.fluid_bulk_modulus.values[inside], expect.K, rtol=1e-12)
    np.testing.assert_allclose(ds.fluid_density.values[inside], expect.rho, rtol=1e-12)


def test_brie_mixes_with_the_water_saturation():
    """Brie et al. (1995): K = (K_brine - K_hc) S_w^e + K_hc with S_w = 1 - 0.8 = 0.2, by hand
    (with the hydrocarbon's saturation in its place K would be 12 times larger here)."""
    ds = run({**RESERVOIR, "hydrocarbon": "gas", "mixing": "brie", "brie_exponent": 3.0})
    inside, T, P = state(ds)
    b, g = pf.brine(T, P, 0.05), pf.gas(T, P, 0.6)
    np.testing.assert_allclose(ds.fluid_bulk_modulus.values[inside],
                               (b.K - g.K) * 0.2**3 + g.K, rtol=1e-12)
    np.testing.assert_allclose(ds.fluid_density.values[inside], 0.2 * b.rho + 0.8 * g.rho,
                               rtol=1e-12)
    outside = ds.fluid_bulk_modulus.values[~inside]
    np.testing.assert_allclose(outside, pf.brine(ds.temperature.values[~inside],
                                                 ds.pressure_pore.values[~inside]
                                                 + STANDARD_ATMOSPHERE, 0.05).K, rtol=1e-12)


def test_patchy_fluid_density_is_the_saturation_weighted_mean():
    """The patchy scene's fluid density: 0.2 brine + 0.8 gas in the interval, brine outside."""
    ds = run({**RESERVOIR, "hydrocarbon": "gas", "mixing": "patchy"})
    inside, T, P = state(ds)
    b, g = pf.brine(T, P, 0.05), pf.gas(T, P, 0.6)
    np.testing.assert_allclose(ds.fluid_density.values[inside], 0.2 * b.rho + 0.8 * g.rho,
                               rtol=1e-12)
    z = ds.depth.values
    brine_all = pf.brine(ds.temperature.values, ds.pressure_pore.values + STANDARD_ATMOSPHERE,
                         0.05)
    np.testing.assert_allclose(ds.fluid_density.values[~inside], brine_all.rho[~inside],
                               rtol=1e-12)
    np.testing.assert_array_equal(ds.hydrocarbon_saturation.values, np.where(
        (z >= 2000.0) & (z <= 3000.0), 0.8, 0.0))


@pytest.mark.parametrize("kind, given, words", [
    ("gas", {"gas_gravity": 1.9}, "gas (Batzle & Wang 1992) at 2000–3000 m: gravity outside"),
    ("oil", {"oil_api": 5.0}, "oil (Batzle & Wang 1992) at 2000–3000 m: reference density"),
])
def test_every_hydrocarbons_validity_is_in_the_scenes_warnings(kind, given, words):
    ds = run({**RESERVOIR, "hydrocarbon": kind, **given})
    assert words in ds.attrs["validity_warnings"]


def test_methane_beyond_setzmann_wagner_is_warned_in_the_scene():
    """A path to 495 degC with methane in every pore: Setzmann-Wagner is stated valid to
    625 K (351.85 degC), reached at (351.85 - 15) / 0.06 = 5614 m; the scene says so for the
    depths beyond, 6000-8000 m on this 500 m grid."""
    pytest.importorskip("CoolProp")
    ds = run_scene(scene_from_dict({
        **BASE, "path": {"max_depth": 8000.0, "depth_step": 500.0, "gradient": 60.0},
        "fluid": {"hydrocarbon": "methane", "saturation": 0.8}}))
    assert float(ds.temperature.max()) == pytest.approx(495.0)
    lines = ds.attrs["validity_warnings"].split("\n")
    assert ("methane (Setzmann–Wagner) at 6000–8000 m: temperature above 351.85 °C, the end of "
            "the equation of state's stated range: extrapolated") in lines


@pytest.fixture
def broken_coolprop(tmp_path, monkeypatch):
    """A CoolProp that is found (its package is on the path) but fails to import, as a build
    whose compiled module cannot load."""
    pkg = tmp_path / "CoolProp"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "CoolProp.py").write_text(
        "raise ImportError('libCoolProp.so: cannot open shared object file')\n")
    for name in [m for m in sys.modules if m == "CoolProp" or m.startswith("CoolProp.")]:
        monkeypatch.delitem(sys.modules, name)
    monkeypatch.syspath_prepend(str(tmp_path))
    return pkg


def test_a_broken_coolprop_is_named_not_blamed_on_a_missing_install(broken_coolprop):
    with pytest.raises(ImportError) as err:
        pf.co2(50.0, 20.0)
    text = str(err.value)
    assert "fails to import (ImportError: libCoolProp.so: cannot open shared object file)" in text
    assert str(broken_coolprop) in text and "--force-reinstall" in text
    assert "rockcem[fluids]" not in text                    # not the advice to install it
    assert err.value.__cause__ is None and err.value.__context__ is None    # no chained traceback


def test_a_broken_coolprop_in_a_scene_is_one_value_error(broken_coolprop):
    """The scene's check at load tries CoolProp and says, in one line under the scene's key,
    that it fails to import (the CLI prints a ValueError as one line, exit 2)."""
    with pytest.raises(ValueError, match=r"^scene key fluid.hydrocarbon = 'co2' needs CoolProp: "
                                         r"CoolProp is installed at .* but fails to "
                                         r"import \(ImportError: libCoolProp.so") as err:
        scene_from_dict({**BASE, "fluid": {**RESERVOIR, "hydrocarbon": "co2"}})
    assert "\n" not in str(err.value)


def test_an_absent_coolprop_is_blamed_on_the_fluid_that_needs_it(monkeypatch):
    """sandstone_fluids sweeps gas (Batzle & Wang's, no CoolProp) before CO2: the message
    names CO2, the first fluid that needs CoolProp, not gas."""
    from rockcem.scene import load_scene

    monkeypatch.setitem(sys.modules, "CoolProp", None)
    monkeypatch.setitem(sys.modules, "CoolProp.CoolProp", None)
    with pytest.raises(ValueError, match=r"^scene key fluid.hydrocarbon = 'co2' needs CoolProp: "
                                         r"CoolProp \(reference equations of state\) is not "
                                         r"installed"):
        load_scene("sandstone_fluids")


def test_an_absent_coolprop_says_it_is_not_installed(monkeypatch):
    monkeypatch.setitem(sys.modules, "CoolProp", None)
    monkeypatch.setitem(sys.modules, "CoolProp.CoolProp", None)
    with pytest.raises(ImportError, match=r"^methane\(\) needs CoolProp: CoolProp \(reference "
                                          r"equations of state\) is not installed: pip install "
                                          r"'rockcem\[fluids\]'$"):
        pf.methane(50.0, 10.0)
    # an out-of-range input is refused by name before CoolProp is looked for
    with pytest.raises(ValueError, match="temperature must be at most 1376.85"):
        pf.co2(5000.0, 100.0)


def test_the_gas_sands_of_sandstone_fluids_need_no_coolprop(monkeypatch):
    """``gas`` is Batzle & Wang's: a scene with only it runs with CoolProp absent."""
    monkeypatch.setitem(sys.modules, "CoolProp", None)
    monkeypatch.setitem(sys.modules, "CoolProp.CoolProp", None)
    ds = run({**RESERVOIR, "hydrocarbon": "gas"})
    assert np.all(np.isfinite(ds.fluid_bulk_modulus.values))
