"""Labelled inputs across the public API (rockcem.validation.labelled).

Every public array function takes numpy, pandas and xarray inputs and returns the type it was
given: pandas aligned by index label, xarray broadcast by dimension name and aligned by
coordinate label. The expected values are the function's own numpy results on inputs paired by
hand (reordered by label, or broadcast to the outer product with numpy), so a labelled call is
checked against an independent pairing, never against itself; a few hand-computed values (the
Voigt average, the velocities of a modulus pair) check the phase alignment with no rockcem
arithmetic at all.
"""

from __future__ import annotations

import inspect
from dataclasses import dataclass, field

import numpy as np
import pandas as pd
import pytest
import xarray as xr

import rockcem.pore_fluids as pf
from rockcem import (anisotropy, bounds, contact_integral, elastic, fluids, frames, granular,
                     inclusions, models, reflectivity)
from rockcem.materials import Fluid, mineral
from rockcem.validation import UNIT_SPELLINGS, labelled

QUARTZ = mineral("quartz")
ILLITE = mineral("illite")
WATER = Fluid(K=2.25, rho=1.0)


@dataclass
class Case:
    """A public function, two of its per-sample arguments with three valid values each (every
    pair of them valid together), the rest fixed, and its phase arguments."""

    func: object
    x: tuple[str, list]
    y: tuple[str, list]
    fixed: dict = field(default_factory=dict)
    phases: tuple = ()
    unit: object = None          # the documented unit of the result (str, or per field)

    @property
    def id(self):
        return f"{self.func.__module__.rsplit('.', 1)[-1]}.{self.func.__name__}"


MOD = "GPa"
ROCK_UNITS = {"K_dry": MOD, "G_dry": MOD, "K_sat": MOD, "G_sat": MOD, "density": "g cm-3",
              "vp": "km s-1", "vs": "km s-1"}
FLUID_UNITS = {"K": MOD, "rho": "g cm-3", "vp": "km s-1"}
T3, P3 = ("temperature", [20.0, 60.0, 100.0]), ("pressure", [10.0, 30.0, 50.0])
PHI3 = ("phi", [0.05, 0.15, 0.25])
FR = [[0.8, 0.2], [0.6, 0.4], [0.9, 0.1]]          # two phases, three samples

CASES = [
    Case(elastic.poisson_ratio, ("K", [20.0, 37.0, 50.0]), ("G", [10.0, 20.0, 30.0]), unit="1"),
    Case(elastic.p_wave_modulus, ("K", [20.0, 37.0, 50.0]), ("G", [10.0, 20.0, 30.0]),
         unit=MOD),
    Case(elastic.velocities, ("K", [20.0, 37.0, 50.0]), ("density", [2.0, 2.3, 2.6]),
         {"G": 20.0}, unit="km s-1"),
    *[Case(f, ("fractions", FR), ("G", [[44.0, 10.0], [40.0, 8.0], [30.0, 5.0]]),
           {"K": [37.0, 21.0]}, phases=("K", "G", "fractions"), unit=MOD)
      for f in (bounds.voigt, bounds.reuss, bounds.hill, bounds.hashin_shtrikman,
                bounds.hashin_shtrikman_upper, bounds.hashin_shtrikman_average)],
    Case(fluids.gassmann, ("K_dry", [5.0, 10.0, 15.0]), PHI3, {"K_min": 37.0, "K_fluid": 2.5},
         unit=MOD),
    Case(fluids.gassmann_dry, ("K_sat", [14.0, 18.0, 22.0]), ("phi", [0.2, 0.25, 0.3]),
         {"K_min": 37.0, "K_fluid": 2.5}, unit=MOD),
    Case(fluids.generalized_gassmann, ("K_frame", [[10.0, 1.0], [8.0, 1.0], [5.0, 0.5]]), PHI3,
         {"K_solid": [37.0, 21.0], "solid_fractions": [0.8, 0.2], "K_fluid": 2.5},
         phases=("K_frame", "K_solid", "solid_fractions"), unit=MOD),
    Case(fluids.generalized_gassmann_dry, ("K_sat", [14.0, 18.0, 22.0]), ("phi", [0.2, 0.25, 0.3]),
         {"K_solid": [37.0, 21.0], "solid_fractions": [0.8, 0.2], "K_fluid": 2.5},
         phases=("K_solid", "solid_fractions"), unit=MOD),
    Case(frames.krief_factor, PHI3, ("A", [2.0, 3.0, 4.0]), unit="1"),
    Case(frames.krief, ("K_min", [30.0, 37.0, 45.0]), PHI3, {"G_min": 44.0}, unit=MOD),
    Case(frames.krief_multimineral, ("solid_fractions", FR), PHI3,
         {"K_solid": [37.0, 21.0], "G_solid": [44.0, 7.0]},
         phases=("K_solid", "G_solid", "solid_fractions"), unit=MOD),
    Case(granular.hertz_mindlin, ("pressure", [5.0, 20.0, 40.0]), ("n", [6.0, 8.0, 9.0]),
         {"K0": 37.0, "G0": 44.0, "phic": 0.36}, unit=MOD),
    *[Case(f, ("pressure", [5.0, 20.0, 40.0]), ("phi", [0.1, 0.2, 0.3]),
           {"K0": 37.0, "G0": 44.0, "phic": 0.36, "n": 9.0}, unit=MOD)
      for f in (granular.soft_sand, granular.stiff_sand)],
    Case(granular.cement_radius, ("phi", [0.30, 0.33, 0.35]), ("n", [6.0, 8.0, 9.0]),
         {"phic": 0.36}, unit="1"),
    Case(granular.cement_porosity, ("alpha", [0.05, 0.1, 0.2]), ("n", [6.0, 8.0, 9.0]),
         {"phic": 0.36}, unit="1"),
    Case(granular.contact_cement, ("phi", [0.30, 0.33, 0.35]), ("n", [6.0, 8.0, 9.0]),
         {"K0": 37.0, "G0": 44.0, "Kc": 37.0, "Gc": 44.0, "phic": 0.36}, unit=MOD),
    *[Case(f, ("phi", [0.15, 0.2, 0.25]), ("n", [6.0, 8.0, 9.0]),
           {"K0": 37.0, "G0": 44.0, "Kc": 37.0, "Gc": 44.0, "phic": 0.36, "phib": 0.3},
           unit=MOD)
      for f in (granular.constant_cement, granular.increasing_cement)],
    Case(granular.patchy_cement, ("pressure", [5.0, 20.0, 40.0]),
         ("cement_fraction", [0.0, 0.02, 0.04]),
         {"K0": 37.0, "G0": 44.0, "Kc": 37.0, "Gc": 44.0, "phi": 0.3, "phic": 0.36, "n": 9.0},
         unit=MOD),
    Case(inclusions.berryman_pq, ("K_i", [0.0, 2.5, 20.0]), ("aspect_ratio", [0.01, 0.1, 1.0]),
         {"K_m": 37.0, "G_m": 44.0, "G_i": 0.0}, unit="1"),
    Case(inclusions.self_consistent, ("fractions", FR),
         ("aspect_ratio", [[1.0, 0.1], [1.0, 0.5], [0.5, 1.0]]),
         {"K": [37.0, 21.0], "G": [44.0, 7.0]}, phases=("K", "G", "fractions", "aspect_ratio"),
         unit={"K": MOD, "G": MOD}),
    Case(contact_integral.cemented_contact_stiffness, ("alpha", [0.05, 0.1, 0.2]),
         ("Lambda", [0.1, 1.0, 10.0]), unit="1"),
    Case(models.bulk_density, ("porosity", [0.05, 0.15, 0.25]),
         ("fluid_density", [0.8, 1.0, 1.1]),
         {"mineral_density": [2.65, 2.8], "solid_fractions": [0.8, 0.2]},
         phases=("mineral_density", "solid_fractions"), unit="g cm-3"),
    *[Case(f, ("solid_fractions", FR), ("porosity", [0.05, 0.15, 0.25]),
           {"minerals": [QUARTZ, ILLITE], "fluid": WATER, **kw},
           phases=("solid_fractions",), unit=ROCK_UNITS)
      for f, kw in ((models.hs_gassmann, {}), (models.self_consistent_model,
                                               {"aspect_ratio": 0.2}),
                    (models.generalized_gassmann_model, {}))],
    Case(models.patchy_cement_model, ("porosity", [0.25, 0.3, 0.33]),
         ("pressure", [5.0, 20.0, 40.0]),
         {"grain": QUARTZ, "cement": QUARTZ, "cement_fraction": 0.02, "fluid": WATER},
         unit=ROCK_UNITS),
    Case(anisotropy.thomsen, ("c11", [40.0, 45.0, 50.0]), ("c44", [10.0, 12.0, 14.0]),
         {"c13": 10.0, "c33": 35.0, "c66": 15.0}, unit="1"),
    Case(anisotropy.ti_bulk_modulus, ("c11", [40.0, 45.0, 50.0]), ("c13", [8.0, 10.0, 12.0]),
         {"c33": 35.0, "c66": 15.0}, unit=MOD),
    Case(anisotropy.ti_gassmann, ("c11", [20.0, 22.0, 25.0]), ("phi", [0.15, 0.2, 0.25]),
         {"c13": 5.0, "c33": 18.0, "c44": 7.0, "c66": 8.0, "K_min": 37.0, "K_fluid": 2.5},
         unit=MOD),
    Case(anisotropy.vertical_velocities, ("c33", [30.0, 35.0, 40.0]),
         ("rho", [2.2, 2.4, 2.6]), {"c44": 12.0}, unit="km s-1"),
    *[Case(f, ("vp2", [2.5, 3.0, 3.5]), ("angle", [0.0, 20.0, 35.0]),
           {"vp1": 2.0, "vs1": 1.0, "rho1": 2.2, "vs2": 1.4, "rho2": 2.3}, unit="1")
      for f in (reflectivity.zoeppritz_pp, reflectivity.aki_richards_pp,
                reflectivity.shuey_pp)],
    Case(reflectivity.zoeppritz_scattering, ("vp2", [2.5, 3.0, 3.5]),
         ("angle", [0.0, 20.0, 35.0]),
         {"vp1": 2.0, "vs1": 1.0, "rho1": 2.2, "vs2": 1.4, "rho2": 2.3}, unit="1"),
    Case(reflectivity.intercept_gradient, ("vp2", [2.5, 3.0, 3.5]), ("rho2", [2.1, 2.3, 2.5]),
         {"vp1": 2.0, "vs1": 1.0, "rho1": 2.2, "vs2": 1.4}, unit="1"),
    Case(reflectivity.avo_class, ("intercept", [0.1, 0.01, -0.1]),
         ("gradient", [-0.2, -0.1, 0.1]), unit="1"),
    Case(reflectivity.critical_angle, ("v1", [2.0, 2.5, 3.0]), ("v2", [3.0, 3.5, 4.0]),
         unit="degree"),
    Case(pf.water, T3, P3, unit=FLUID_UNITS),
    Case(pf.brine, T3, P3, {"salinity": 0.05}, unit=FLUID_UNITS),
    Case(pf.oil, T3, P3, {"api": 30.0, "gas_oil_ratio": 20.0}, unit=FLUID_UNITS),
    Case(pf.gas, T3, P3, {"gravity": 0.7}, unit=FLUID_UNITS),
    Case(pf.max_gas_oil_ratio, T3, P3, {"api": 30.0}, unit="1"),
    Case(pf.bubble_point_pressure, T3, ("gas_oil_ratio", [10.0, 50.0, 100.0]), {"api": 30.0},
         unit="MPa"),
    Case(pf.wood, ("fractions", FR), ("K", [[2.5, 0.05], [2.6, 0.1], [2.8, 0.2]]),
         {"rho": [1.05, 0.2]}, phases=("fractions", "K", "rho"), unit=FLUID_UNITS),
    Case(pf.brie, ("water_saturation", [0.2, 0.6, 1.0]), ("K_hydrocarbon", [0.05, 0.1, 0.5]),
         {"K_brine": 2.6, "rho_brine": 1.05, "rho_hydrocarbon": 0.2}, unit=FLUID_UNITS),
    Case(pf.patchy_saturation, ("saturations", FR), PHI3,
         {"K_dry": 8.0, "G_dry": 9.0, "K_min": 37.0, "K_fluids": [2.6, 0.1]},
         phases=("saturations", "K_fluids"), unit=MOD),
]
try:                                        # CO2 and methane need CoolProp (the fluids extra)
    import CoolProp  # noqa: F401
    CASES += [Case(pf.co2, T3, P3, unit=FLUID_UNITS), Case(pf.methane, T3, P3, unit=FLUID_UNITS)]
except ImportError:
    pass
IDS = [c.id for c in CASES]

#: Public functions left undecorated, and why: they take no array of samples (names, paths,
#: catalogue entries, validators, Datasets, scenes and wells have their own readers).
NOT_ARRAY_FUNCTIONS = {"materials.mineral", "materials.fluid", "materials.minerals",
                       "materials.fluids", "inclusions.check_aspect_ratio",
                       "validity.validity_warnings"}
PUBLIC_MODULES = (elastic, bounds, fluids, frames, granular, inclusions, contact_integral, models,
                  anisotropy, pf, reflectivity)


def test_every_public_array_function_is_labelled_and_covered():
    """Each function exported by the public modules is decorated and in CASES, or is listed as
    taking no arrays; a new public function without the decorator fails here."""
    covered = {c.func.__wrapped__ for c in CASES}
    for module in PUBLIC_MODULES:
        for name in module.__all__:
            f = getattr(module, name)
            if not inspect.isfunction(f):
                continue
            key = f"{f.__module__.rsplit('.', 1)[-1]}.{name}"
            if key in NOT_ARRAY_FUNCTIONS:
                continue
            assert getattr(f, "__wrapped__", None) in covered, f"{key} is not labelled/tested"
    assert len(CASES) >= 45


def _in_signature_order(case):
    """x and y, the one earlier in the signature first (its labels order the result)."""
    names = list(inspect.signature(case.func).parameters)
    return sorted([case.x, case.y], key=lambda a: names.index(a[0]))


def _numpy(case, **arrays):
    """The function on numpy arrays paired by hand."""
    return case.func(**case.fixed, **{k: np.asarray(v) for k, v in arrays.items()})


def _leaves(out):
    """(field, array) pairs of a result: an array, or a (nested) NamedTuple of arrays."""
    if isinstance(out, tuple):
        fields = getattr(out, "_fields", [None] * len(out))
        return [leaf for f, v in zip(fields, out)
                for leaf in ([(f, v)] if not isinstance(v, tuple) else _leaves(v))]
    return [(None, out)]


def _same_structure(out, expected):
    """The same NamedTuple (nested) as the numpy result, or an array's stand-in."""
    if isinstance(expected, tuple):
        assert type(out) is type(expected)
        for o, e in zip(out, expected, strict=True):
            _same_structure(o, e)
    else:
        assert not isinstance(out, tuple)


def _unit(case, name):
    return case.unit if isinstance(case.unit, str) else case.unit.get(name)


@pytest.mark.parametrize("case", CASES, ids=IDS)
def test_pandas_aligned_by_index(case):
    """Two Series with the same labels in different orders are paired by label: the result is
    a Series (a NamedTuple of Series) on the first one's index, equal to the numpy result on
    the values paired by hand."""
    (xname, xv), (yname, yv) = _in_signature_order(case)
    labels = ["deep", "mid", "shallow"]
    order = [2, 0, 1]                               # the later argument in another order
    sx = _series_or_frame(xv, labels, xname in case.phases)
    sy = _series_or_frame(np.asarray(yv)[order], [labels[i] for i in order], yname in case.phases)
    sx.attrs["units"] = UNIT_SPELLINGS[case.func.input_units[xname]][1]   # a spelling of it
    out = case.func(**{**case.fixed, xname: sx, yname: sy})
    expected = _numpy(case, **{xname: xv, yname: yv})
    _same_structure(out, expected)
    for (name, got), (_, want) in zip(_leaves(out), _leaves(expected), strict=True):
        # a result per phase (krief_multimineral) is a DataFrame with the phase labels
        assert isinstance(got, pd.Series if np.ndim(want) == 1 else pd.DataFrame), name
        if np.ndim(want) == 2:
            assert list(got.columns) == ["m0", "m1"]
        assert list(got.index) == labels
        np.testing.assert_allclose(got.to_numpy(), want, rtol=1e-12, atol=0)
        assert got.attrs.get("units") == _unit(case, name)


def _series_or_frame(values, index, phase):
    values = np.asarray(values, dtype=float)
    if phase and values.ndim == 2:
        return pd.DataFrame(values, index=index, columns=["m0", "m1"])
    return pd.Series(values, index=index)


@pytest.mark.parametrize("case", CASES, ids=IDS)
def test_pandas_without_units_has_none(case):
    """No unit is made up: without ``attrs['units']`` in the inputs, none in the result."""
    xname, xv = case.x
    out = case.func(**{**case.fixed, xname: _series_or_frame(xv, list("abc"),
                                                            xname in case.phases),
                       case.y[0]: np.asarray(case.y[1])})
    for name, got in _leaves(out):
        assert isinstance(got, (pd.Series, pd.DataFrame)) and "units" not in got.attrs, name


@pytest.mark.parametrize("case", CASES, ids=IDS)
def test_xarray_broadcast_by_dimension_name(case):
    """Two DataArrays on different dimensions broadcast to their outer product, coordinates
    kept; each value equals the numpy result at that pair (numpy broadcast by hand)."""
    (xname, xv), (yname, yv) = _in_signature_order(case)
    xv, yv = np.asarray(xv, dtype=float), np.asarray(yv, dtype=float)
    xa = _dataarray(xv, "well", [3.0, 1.0, 2.0], xname in case.phases)
    ya = _dataarray(yv, "sample", ["s1", "s2", "s3"], yname in case.phases)
    ya.attrs["units"] = UNIT_SPELLINGS[case.func.input_units[yname]][1]
    out = case.func(**{**case.fixed, xname: xa, yname: ya})
    # numpy: x along axis 0, y along axis 1 (the phases, if any, stay last)
    xn = xv[:, None, :] if xv.ndim == 2 else xv[:, None]
    yn = yv[None, :, :] if yv.ndim == 2 else yv[None, :]
    expected = _numpy(case, **{xname: xn, yname: yn})
    _same_structure(out, expected)
    for (name, got), (_, want) in zip(_leaves(out), _leaves(expected), strict=True):
        assert isinstance(got, xr.DataArray), name
        # a result per phase (krief_multimineral) keeps the phase dimension, last
        assert got.dims == ("well", "sample", "mineral")[:np.ndim(want)]
        assert list(got["well"].values) == [3.0, 1.0, 2.0]
        assert list(got["sample"].values) == ["s1", "s2", "s3"]
        assert list(got["label"].values) == ["x0", "x1", "x2"]     # a non-index coordinate
        np.testing.assert_allclose(got.values, want, rtol=1e-12, atol=0)
        assert got.attrs.get("units") == _unit(case, name)


def _dataarray(values, dim, coord, phase):
    if values.ndim == 2:                    # phases on the last dimension
        da = xr.DataArray(values, dims=(dim, "mineral"),
                          coords={dim: coord, "mineral": ["quartz", "clay"]})
    else:
        da = xr.DataArray(values, dims=dim, coords={dim: coord})
    if dim == "well":
        da = da.assign_coords(label=(dim, ["x0", "x1", "x2"]))
    return da


@pytest.mark.parametrize("case", CASES, ids=IDS)
def test_xarray_aligned_by_coordinate(case):
    """Two DataArrays on the same dimension with their labels in different orders are paired
    by label (not by position), in the first one's order."""
    (xname, xv), (yname, yv) = _in_signature_order(case)
    xv, yv = np.asarray(xv, dtype=float), np.asarray(yv, dtype=float)
    order = [1, 2, 0]
    xa = _dataarray(xv, "depth", [100.0, 200.0, 300.0], xname in case.phases)
    ya = _dataarray(yv[order], "depth", [[100.0, 200.0, 300.0][i] for i in order],
                    yname in case.phases)
    out = case.func(**{**case.fixed, xname: xa, yname: ya})
    expected = _numpy(case, **{xname: xv, yname: yv})
    for (name, got), (_, want) in zip(_leaves(out), _leaves(expected), strict=True):
        assert got.dims == ("depth", "mineral")[:np.ndim(want)]
        assert list(got["depth"].values) == [100.0, 200.0, 300.0]
        np.testing.assert_allclose(got.values, want, rtol=1e-12, atol=0)


@pytest.mark.parametrize("case", CASES, ids=IDS)
def test_numpy_stays_numpy(case):
    """numpy in, numpy out: the same objects the function below the decorator returns."""
    xname, xv = case.x
    kw = {**case.fixed, xname: np.asarray(xv), case.y[0]: np.asarray(case.y[1])}
    out, core = case.func(**kw), case.func.__wrapped__(**kw)
    assert type(out) is type(core)
    for (_, got), (_, want) in zip(_leaves(out), _leaves(core), strict=True):
        assert type(got) is type(want)
        np.testing.assert_array_equal(got, want)


@pytest.mark.parametrize("case", CASES, ids=IDS)
@pytest.mark.parametrize("bad", ["bool", "bool list", "bool Series", "bool DataArray", "masked"])
def test_booleans_and_masked_arrays_refused_by_name(case, bad, expect_value_error):
    """``True`` is not 1 °C, and a masked value is not a valid one: both refused, naming the
    argument."""
    name, v = case.x
    v = np.asarray(v, dtype=float)
    value = {"bool": True, "bool list": [True, 2.0],
             "bool Series": pd.Series(v > v.mean()) if v.ndim == 1 else pd.DataFrame(v > 0.5),
             "bool DataArray": xr.DataArray(v > v.mean()),
             "masked": np.ma.masked_array(v, mask=np.eye(*v.shape, dtype=bool)
                                          if v.ndim == 2 else [False, True, False])}[bad]
    if bad == "bool" and name in case.phases and v.ndim == 2:
        value = [[True, False]] * 3
    expect_value_error(lambda: case.func(**{**case.fixed, name: value,
                                            case.y[0]: np.asarray(case.y[1])}), name)


def test_masked_array_message_says_masked():
    with pytest.raises(ValueError, match=r"temperature is a numpy masked array"):
        pf.brine(np.ma.masked_array([20.0, 60.0], mask=[False, True]), 30.0, 0.05)


# --- hand-computed values: the phases paired by label --------------------------------------

def test_voigt_phases_paired_by_column_label():
    """Voigt average 0.8·37 + 0.2·76.8 = 44.96 GPa and 0.5·37 + 0.5·76.8 = 56.9: the moduli
    given per mineral in another order than the DataFrame's columns."""
    f = pd.DataFrame({"quartz": [0.8, 0.5], "calcite": [0.2, 0.5]}, index=[1500.0, 2500.0])
    K = pd.Series({"calcite": 76.8, "quartz": 37.0})
    G = pd.Series({"quartz": 44.0, "calcite": 32.0})
    out = bounds.voigt(K, G, f)
    assert list(out.K.index) == [1500.0, 2500.0]
    np.testing.assert_allclose(out.K.to_numpy(), [44.96, 56.9], rtol=1e-14)
    np.testing.assert_allclose(out.G.to_numpy(), [0.8 * 44 + 0.2 * 32, 38.0], rtol=1e-14)


def test_voigt_phases_paired_by_coordinate_label():
    """As above with xarray: the phases along a dimension, matched by its coordinate."""
    f = xr.DataArray([[0.8, 0.2], [0.5, 0.5]], dims=("depth", "mineral"),
                     coords={"depth": [1500.0, 2500.0], "mineral": ["quartz", "calcite"]})
    K = xr.DataArray([76.8, 37.0], dims="mineral", coords={"mineral": ["calcite", "quartz"]},
                     attrs={"units": "GPa"})
    out = bounds.voigt(K, np.array([44.0, 32.0]), f)
    assert out.K.dims == ("depth",) and "mineral" not in out.K.coords
    np.testing.assert_allclose(out.K.values, [44.96, 56.9], rtol=1e-14)
    assert out.K.attrs == {"units": "GPa"}


def test_zero_dimensional_dataarray_stays_a_dataarray():
    """A 0-d DataArray (a value picked with .sel) gives 0-d DataArrays, its scalar coordinate
    and unit kept: vp = √((36 + 4·27/3)/2) = 6 km/s."""
    K = xr.DataArray(36.0, coords={"depth": 1500.0}, attrs={"units": "GPa"})
    v = elastic.velocities(K, 27.0, 2.0)
    assert isinstance(v.vp, xr.DataArray) and v.vp.dims == () and float(v.vp["depth"]) == 1500.0
    assert float(v.vp) == pytest.approx(6.0, rel=1e-15) and v.vp.attrs == {"units": "km s-1"}


def test_velocities_hand_computed_by_label():
    """vp = √((K + 4G/3)/ρ), vs = √(G/ρ): K 36, G 27 at ρ 2 gives vp √36 = 6, vs √13.5; K 16,
    G 12 at ρ 8 gives vp √4 = 2, vs √1.5; the densities given in reverse label order."""
    K = pd.Series([36.0, 16.0], index=["a", "b"])
    G = pd.Series([27.0, 12.0], index=["a", "b"])
    rho = pd.Series([8.0, 2.0], index=["b", "a"])
    v = elastic.velocities(K, G, rho)
    np.testing.assert_allclose(v.vp.to_numpy(), [6.0, 2.0], rtol=1e-14)
    np.testing.assert_allclose(v.vs.to_numpy(), [np.sqrt(13.5), np.sqrt(1.5)], rtol=1e-14)


def test_issue_example_brine_series_in_other_orders():
    """Issue 30's case: two Series with their indexes in different orders are paired by label;
    the result equals brine at the states paired by hand."""
    T = pd.Series([20.0, 60.0, 100.0], index=["a", "b", "c"])
    P = pd.Series([50.0, 10.0, 30.0], index=["c", "a", "b"])
    out = pf.brine(T, P, 0.05)
    for label, t, p in (("a", 20.0, 10.0), ("b", 60.0, 30.0), ("c", 100.0, 50.0)):
        assert out.K[label] == pf.brine(t, p, 0.05).K


# --- refusals -----------------------------------------------------------------------------

def test_different_labels_refused_naming_both():
    T = pd.Series([20.0, 60.0], index=["a", "b"])
    P = pd.Series([10.0, 30.0], index=["a", "c"])
    with pytest.raises(ValueError, match=r"pressure and temperature do not have the same labels"
                                         r".*'c'"):
        pf.brine(T, P, 0.05)
    with pytest.raises(ValueError, match=r"pressure and temperature .*along dimension 'depth'"):
        pf.brine(xr.DataArray([20.0, 60.0], dims="depth", coords={"depth": [1, 2]}),
                 xr.DataArray([10.0, 30.0], dims="depth", coords={"depth": [1, 3]}), 0.05)


def test_repeated_labels_in_other_orders_refused():
    T = pd.Series([20.0, 60.0, 80.0], index=["a", "a", "b"])
    P = pd.Series([10.0, 30.0, 40.0], index=["a", "b", "a"])
    with pytest.raises(ValueError, match=r"repeats a label"):
        pf.brine(T, P, 0.05)
    # the same repeated index, in the same order, pairs by position as it must
    same = pf.brine(T, P.set_axis(T.index), 0.05)
    np.testing.assert_array_equal(same.K.to_numpy(),
                                  pf.brine(T.to_numpy(), P.to_numpy(), 0.05).K)


def test_dimension_sizes_without_coordinates_must_agree():
    with pytest.raises(ValueError, match=r"pressure and temperature have 3 and 2 entries along "
                                         r"dimension 'depth'"):
        pf.brine(xr.DataArray([20.0, 60.0], dims="depth"),
                 xr.DataArray([10.0, 30.0, 40.0], dims="depth"), 0.05)


def test_pandas_and_xarray_mixed_refused():
    with pytest.raises(ValueError, match=r"temperature given as pandas and pressure as xarray"):
        pf.brine(pd.Series([20.0]), xr.DataArray([10.0], dims="x"), 0.05)


def test_dataframe_for_a_per_sample_argument_refused():
    with pytest.raises(ValueError, match=r"temperature is a DataFrame"):
        pf.brine(pd.DataFrame({"t": [20.0]}), 10.0, 0.05)


def test_dataset_refused():
    ds = xr.Dataset({"temperature": ("depth", [20.0, 60.0])})
    with pytest.raises(ValueError, match=r"temperature is an xarray Dataset"):
        pf.brine(ds, 10.0, 0.05)


def test_phase_dimension_must_agree():
    f = xr.DataArray([[0.8, 0.2]], dims=("depth", "mineral"))
    K = xr.DataArray([37.0, 21.0], dims="phase")
    with pytest.raises(ValueError, match=r"fractions has its phases along its last dimension "
                                         r"'mineral' but K along 'phase'"):
        bounds.voigt(K, [44.0, 7.0], f)


def test_phase_labels_must_agree():
    f = pd.DataFrame({"quartz": [0.8], "calcite": [0.2]})
    K = pd.Series({"quartz": 37.0, "clay": 21.0})
    with pytest.raises(ValueError, match=r"do not have the same labels along the phases"):
        bounds.voigt(K, [44.0, 7.0], f)


def test_numpy_array_adding_dimensions_refused():
    """A numpy array beside labelled ones broadcasts by position; one that would add a
    dimension the labels cannot name is refused rather than returned unlabelled."""
    T = xr.DataArray([20.0, 60.0], dims="depth")
    with pytest.raises(ValueError, match=r"brine: the labelled inputs span dimensions"):
        pf.brine(T, np.array([[10.0], [30.0], [50.0]]), 0.05)
    same = pf.brine(T, np.array([10.0, 30.0]), 0.05)          # same length: paired by position
    np.testing.assert_array_equal(same.K.values, pf.brine([20.0, 60.0], [10.0, 30.0], 0.05).K)


def test_decorator_names_unknown_phase_argument():
    with pytest.raises(TypeError, match=r"no argument named \['y'\]"):
        labelled(lambda x: x, phases=("y",))


@pytest.mark.parametrize("kind", ["pandas", "xarray"])
def test_a_fluid_refuses_labelled_values(kind):
    """materials.Fluid keeps numbers or numpy arrays, paired by position in the models: a
    labelled K or rho would lose its labels there, so it is refused by name."""
    import pandas as pd
    import xarray as xr

    from rockcem.materials import Fluid

    value = (pd.Series([2.2, 2.3], index=[10, 20]) if kind == "pandas"
             else xr.DataArray([2.2, 2.3], dims="depth"))
    with pytest.raises(ValueError, match=r"Fluid 'brine': K is a (Series|DataArray).*to_numpy"):
        Fluid(value, 1.0, "brine")
    assert Fluid(value.to_numpy(), 1.0).K.tolist() == [2.2, 2.3]


# --- units of the inputs ---------------------------------------------------------------------

#: The words by which a docstring states each unit of the table (dimensionless: none of them).
DOC_MARKS = {"GPa": "GPa", "MPa": "MPa", "g cm-3": "g/cm³", "degC": "°C", "km s-1": "km/s",
             "L/L": "L/L", "degAPI": "API", "degree": "degree"}


def _param_docs(func):
    """{argument: description} from a numpydoc Parameters section (grouped names split)."""
    from numpydoc.docscrape import FunctionDoc

    out = {}
    for p in FunctionDoc(func)["Parameters"]:
        for name in p.name.split(","):
            out[name.strip()] = (p.type + " " + " ".join(p.desc)).strip()
    return out


def _described(func, name, seen=()):
    """The description of argument ``name``, following "As in :func:`other`" (in its
    description, or "Same parameters as :func:`other`" in the docstring where it has none) to
    the function that documents it on its own."""
    import importlib
    import re

    docs = _param_docs(func)
    text = docs.get(name, "")
    for ref in re.findall(r":func:`~?([\w.]+)`", text if name in docs else func.__doc__):
        if "." in ref:
            mod, _, attr = ref.rpartition(".")
            other = getattr(importlib.import_module(mod), attr, None)
        else:
            other = getattr(inspect.getmodule(func), ref, None)
        if other is not None and other not in seen and name in _param_docs(other):
            return _described(other, name, (*seen, func))
    assert name in docs, f"{func.__name__}: {name} is not documented"
    return text


@pytest.mark.parametrize("case", CASES, ids=IDS)
def test_every_argument_has_its_documented_unit(case):
    """Each argument of each labelled function is a quantity with a unit in the table, or one of
    the listed non-quantities; the unit is the one its docstring states (GPa, MPa, g/cm³, °C,
    L/L, API), and an argument taken as dimensionless states none of them."""
    from rockcem.validation import NOT_QUANTITIES

    table = case.func.input_units
    for name in inspect.signature(case.func).parameters:
        if name in NOT_QUANTITIES:
            assert name not in table
            continue
        assert name in table, f"{case.id}: {name} has no unit"
        text = _described(case.func, name)
        if table[name] == "1":
            found = [m for m in DOC_MARKS.values() if m in text]
            assert not found, f"{case.id}: {name} is taken as dimensionless, its doc says {found}"
        else:
            assert DOC_MARKS[table[name]] in text, f"{case.id}: {name}: {text!r}"


def test_input_units_agree_with_the_variable_registry():
    """An argument named like a variable of datasets/variables.toml takes the unit there."""
    import tomllib

    from rockcem._data import data_path
    from rockcem.validation import INPUT_UNITS

    with open(data_path("variables.toml"), "rb") as fh:
        registry = tomllib.load(fh)
    shared = [k for k in INPUT_UNITS if k in registry]
    assert {"temperature", "porosity", "density", "delta", "K_dry"} <= set(shared)
    for name in shared:
        assert registry[name]["units"] in UNIT_SPELLINGS[INPUT_UNITS[name]], name


def test_spellings_are_one_unit_for_a_units_library():
    """Every accepted spelling that pint (with cf_xarray's UDUNITS registry) reads is the same
    unit as the first, factor 1 (20 of it is 20 of the first); the refused look-alikes are not.
    Spellings pint does not know (``fraction``, ``g/cc`` is known, ``API`` is not) are the
    table's own."""
    units = pytest.importorskip("cf_xarray.units").units
    read = 0
    for unit, spellings in UNIT_SPELLINGS.items():
        if unit == "degAPI":
            continue
        for s in spellings:
            try:
                q = units.Quantity(20.0, s)
            except Exception:  # noqa: BLE001 (pint: UndefinedUnitError, AssertionError, ...)
                continue
            read += 1
            base = units.Quantity(20.0, "dimensionless" if unit == "L/L" else unit)
            assert q.to(base.units).magnitude == pytest.approx(20.0, rel=1e-15), (unit, s)
    assert read >= 35
    for wrong, unit in (("K", "degC"), ("degF", "degC"), ("kPa", "MPa"), ("Pa", "GPa"),
                        ("kg m-3", "g cm-3"), ("m/s", "km s-1"), ("%", "1"), ("ft", "m")):
        assert units.Quantity(20.0, wrong).to(unit).magnitude != pytest.approx(20.0)
        assert wrong not in UNIT_SPELLINGS[unit]


def _wrap(kind, values, unit, dim="depth"):
    values = np.asarray(values, dtype=float)
    if kind == "pandas":
        obj = (pd.Series(values, index=[10.0, 20.0, 30.0][:len(values)]) if values.ndim == 1
               else pd.DataFrame(values, columns=["m0", "m1"]))
    else:
        obj = xr.DataArray(values, dims=(dim,) if values.ndim == 1 else (dim, "mineral"))
    obj.attrs["units"] = unit
    return obj


#: A function of each module the decorator serves, an argument, a unit it must refuse and the
#: unit it takes.
WRONG_UNITS = [
    (elastic.velocities, "density", [2.0, 2.3, 2.6], {"K": 30.0, "G": 20.0}, "kg m-3", "g cm-3"),
    (bounds.voigt, "fractions", FR, {"K": [37.0, 21.0], "G": [44.0, 7.0]}, "%", "1"),
    (fluids.gassmann, "K_dry", [5.0, 10.0, 15.0], {"K_min": 37.0, "K_fluid": 2.5, "phi": 0.2},
     "MPa", "GPa"),
    (reflectivity.zoeppritz_pp, "vp2", [2.5, 3.0, 3.5],
     {"vp1": 2.0, "vs1": 1.0, "rho1": 2.2, "vs2": 1.4, "rho2": 2.3, "angle": 20.0}, "m s-1",
     "km s-1"),
    (frames.krief, "phi", [0.1, 0.2, 0.3], {"K_min": 37.0, "G_min": 44.0}, "%", "1"),
    (granular.hertz_mindlin, "pressure", [5.0, 20.0, 40.0],
     {"K0": 37.0, "G0": 44.0, "phic": 0.36, "n": 9.0}, "kPa", "MPa"),
    (inclusions.berryman_pq, "K_i", [0.0, 2.5, 20.0],
     {"K_m": 37.0, "G_m": 44.0, "G_i": 0.0, "aspect_ratio": 0.1}, "Pa", "GPa"),
    (contact_integral.cemented_contact_stiffness, "alpha", [0.05, 0.1, 0.2], {"Lambda": 1.0},
     "mm", "1"),
    (models.bulk_density, "fluid_density", [0.8, 1.0, 1.1],
     {"mineral_density": [2.65, 2.8], "solid_fractions": [0.8, 0.2], "porosity": 0.2},
     "kg/m3", "g cm-3"),
    (anisotropy.vertical_velocities, "rho", [2.2, 2.4, 2.6], {"c33": 35.0, "c44": 12.0},
     "kg m-3", "g cm-3"),
    (pf.brine, "temperature", [20.0, 60.0, 100.0], {"pressure": 10.0, "salinity": 0.05},
     "K", "degC"),
    (pf.oil, "gas_oil_ratio", [10.0, 20.0, 30.0], {"temperature": 60.0, "pressure": 20.0,
                                                   "api": 30.0}, "scf/bbl", "L/L"),
    (pf.brie, "rho_brine", [1.0, 1.05, 1.1], {"water_saturation": 0.5, "K_brine": 2.6,
                                              "K_hydrocarbon": 0.1, "rho_hydrocarbon": 0.2},
     "kg/m3", "g cm-3"),
]
try:
    import CoolProp  # noqa: F401
    WRONG_UNITS.append((pf.co2, "pressure", [10.0, 20.0, 30.0], {"temperature": 60.0}, "bar",
                        "MPa"))
except ImportError:
    pass


@pytest.mark.parametrize("kind", ["xarray", "pandas"])
@pytest.mark.parametrize("func, name, values, fixed, wrong, unit", WRONG_UNITS,
                         ids=[f"{w[0].__module__.rsplit('.', 1)[-1]}.{w[0].__name__}"
                              for w in WRONG_UNITS])
def test_a_wrong_unit_is_refused_by_name(kind, func, name, values, fixed, wrong, unit):
    """A labelled input whose attrs['units'] is another unit than the function's is refused,
    the message naming the function, the argument, the unit given and the unit taken; the
    same values in the right unit are computed as numpy computes them."""
    with pytest.raises(ValueError, match=rf"^{func.__name__}: {name} has units '{wrong}' but "
                                         rf"takes {unit} \(spelled"):
        func(**fixed, **{name: _wrap(kind, values, wrong)})
    good = func(**fixed, **{name: _wrap(kind, values, unit)})
    want = func(**fixed, **{name: np.asarray(values)})
    for (_, got), (_, w) in zip(_leaves(good), _leaves(want), strict=True):
        np.testing.assert_array_equal(np.asarray(got), w)


def test_all_modules_that_use_the_decorator_have_a_wrong_unit_case():
    modules = {c.func.__module__ for c in CASES}
    assert modules <= {f.__module__ for f, *_ in WRONG_UNITS}, \
        modules - {f.__module__ for f, *_ in WRONG_UNITS}


def _identity_in(unit):
    """A labelled function taking ``x`` in ``unit`` (its ``input_units``)."""
    return labelled(lambda x: np.asarray(x) * 1.0, units="1", input_units={"x": unit})


@pytest.mark.parametrize("kind", ["xarray", "pandas"])
@pytest.mark.parametrize("unit, spelling", [(u, s) for u, ss in UNIT_SPELLINGS.items()
                                            for s in ss])
def test_every_accepted_spelling_is_accepted(kind, unit, spelling):
    """Each spelling of each unit passes, also with spaces around it; the values are those
    given."""
    f = _identity_in(unit)
    for text in (spelling, f" {spelling} "):
        out = f(_wrap(kind, [1.0, 2.0, 3.0], text))
        np.testing.assert_array_equal(np.asarray(out), [1.0, 2.0, 3.0])


@pytest.mark.parametrize("func, name, spelling, fixed", [
    (pf.water, "temperature", "degree_Celsius", {"pressure": 10.0}),
    (pf.water, "temperature", "°C", {"pressure": 10.0}),
    (pf.water, "pressure", "megapascal", {"temperature": 60.0}),
    (elastic.velocities, "density", "g/cc", {"K": 30.0, "G": 20.0}),
    (elastic.p_wave_modulus, "K", "gigapascal", {"G": 20.0}),
    (frames.krief_factor, "phi", "", {}),
    (pf.oil, "api", "°API", {"temperature": 60.0, "pressure": 20.0}),
])
def test_spellings_accepted_by_real_functions(func, name, spelling, fixed):
    values = {"temperature": [20.0, 60.0], "pressure": [10.0, 30.0], "density": [2.0, 2.5],
              "K": [30.0, 37.0], "phi": [0.1, 0.2], "api": [20.0, 30.0]}[name]
    for kind in ("xarray", "pandas"):
        out = func(**fixed, **{name: _wrap(kind, values, spelling)})
        want = func(**fixed, **{name: np.asarray(values)})
        for (_, got), (_, w) in zip(_leaves(out), _leaves(want), strict=True):
            np.testing.assert_array_equal(np.asarray(got), w)


def test_units_that_are_not_text_are_refused_and_none_is_no_unit():
    f = _identity_in("MPa")
    da = xr.DataArray([1.0, 2.0], dims="depth", attrs={"units": 1e6})
    with pytest.raises(ValueError, match=r"<lambda>: x has units 1000000.0 but takes MPa"):
        f(da)
    np.testing.assert_array_equal(f(da.assign_attrs(units=None)).values, [1.0, 2.0])
    with pytest.raises(ValueError, match=r"x has units '' but takes MPa"):   # "" is unit 1
        f(da.assign_attrs(units=""))


def test_phase_arguments_and_dataframes_are_checked_too():
    fr = pd.DataFrame([[0.8, 0.2], [0.6, 0.4]], columns=["q", "c"])
    K = pd.Series([37.0, 21.0], index=["q", "c"])
    G = pd.Series([44.0, 7.0], index=["q", "c"])
    K.attrs["units"] = "Pa"
    with pytest.raises(ValueError, match=r"voigt: K has units 'Pa' but takes GPa"):
        bounds.voigt(K, G, fr)
    K.attrs["units"] = "GPa"
    fr.attrs["units"] = "%"
    with pytest.raises(ValueError, match=r"voigt: fractions has units '%' but takes 1"):
        bounds.voigt(K, G, fr)


def test_input_units_override_and_its_checks():
    f = labelled(lambda pressure: np.asarray(pressure), input_units={"pressure": "GPa"})
    assert f.input_units == {"pressure": "GPa"}          # the override, not the table's MPa
    with pytest.raises(ValueError, match="pressure has units 'MPa' but takes GPa"):
        f(xr.DataArray([1.0], dims="d", attrs={"units": "MPa"}))
    assert labelled(lambda pressure: pressure).input_units == {"pressure": "MPa"}
    with pytest.raises(TypeError, match=r"no argument named \['y'\]"):
        labelled(lambda x: x, input_units={"y": "MPa"})
    with pytest.raises(TypeError, match=r"input_units \['bar'\] are not units"):
        labelled(lambda x: x, input_units={"x": "bar"})
