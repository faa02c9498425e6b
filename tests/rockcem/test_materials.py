"""Tests of rockcem.materials and the catalogue in datasets/materials/*.toml.

The expected values are the published tables, typed in here: Carcione et al. 2022, Table 1;
Garcia & Medina, Tables I-II; Han & Guo (quartz, epoxy, epoxy-kaolinite). Conversions are checked
with the isotropic relations (Mavko et al. 2009, Sect. 2.2).
"""

import dataclasses
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rockcem.materials import Fluid, Mineral, fluid, fluids, mineral, minerals

DATA = Path(__file__).resolve().parents[2] / "datasets" / "materials"

# name: (K GPa, G GPa, rho g/cm3), typed from the published tables.
TABLE_MINERALS = {
    "smectite": (9.0, 6.0, 2.25),         # Carcione et al. 2022, Table 1
    "illite": (33.0, 28.0, 2.8),          # Carcione et al. 2022, Table 1
    "quartz": (40.0, 39.0, 2.65),         # Carcione et al. 2022, Table 1
    "quartz_cement": (35.0, 30.0, 2.60),  # Carcione et al. 2022, Table 1, "cement"
    "quartz_han_guo": (38.0, 44.0, 2.65),  # Han & Guo
    "epoxy": (6.8, 2.0, 0.98),            # Han & Guo
    "epoxy_kaolinite": (2.24, 1.57, 1.38),  # Han & Guo
}
# Garcia & Medina, Table II: (vp km/s, vs km/s, rho g/cm3).
TABLE_CEMENTS = {"hard_cement": (3.0, 1.8, 2.65), "soft_cement": (1.5, 0.9, 2.65)}


@pytest.mark.parametrize("name", sorted(TABLE_MINERALS))
def test_catalogue_minerals_match_published_tables(name):
    m = mineral(name)
    K, G, rho = TABLE_MINERALS[name]
    np.testing.assert_allclose([m.K, m.G, m.rho], [K, G, rho], rtol=1e-15)
    assert m.name == name and m.source


@pytest.mark.parametrize("name", sorted(TABLE_CEMENTS))
def test_catalogue_cements_from_garcia_medina_table2_velocities(name):
    vp, vs, rho = TABLE_CEMENTS[name]
    m = mineral(name)
    # Isotropic relations: G = rho vs^2, K = rho vp^2 - 4/3 G.
    np.testing.assert_allclose([m.G, m.K], [rho * vs**2, rho * vp**2 - 4.0 / 3.0 * rho * vs**2],
                               rtol=1e-14)
    np.testing.assert_allclose([m.vp, m.vs, m.rho], [vp, vs, rho], rtol=1e-14)


def test_hard_cement_by_hand():
    m = mineral("hard_cement")  # 2.65 * 1.8^2 = 8.586; 2.65 * (9 - 4.32) = 12.402
    np.testing.assert_allclose([m.K, m.G], [12.402, 8.586], rtol=1e-13)


def test_catalogue_quartz_garcia_medina_table1_poisson():
    m = mineral("quartz_garcia_medina")  # Table I: G = 44 GPa, nu = 0.08, rho = 2.65
    assert (m.G, m.rho) == (44.0, 2.65)
    np.testing.assert_allclose(m.poisson_ratio, 0.08, rtol=1e-13)
    # K from Young's modulus: E = 2G(1+nu), K = E/(3(1-2nu)) = 95.04/2.52.
    np.testing.assert_allclose(m.K, 95.04 / 2.52, rtol=1e-13)


def test_catalogue_fluids_carcione2022_table1():
    w = fluid("water")
    assert (w.K, w.rho) == (2.2, 1.04) and w.source
    v = fluid("vacuum")
    assert (v.K, v.rho) == (0.0, 0.0)
    assert set(fluids()) >= {"water", "vacuum"}


def test_catalogue_is_the_toml_file_and_every_entry_has_a_source():
    with open(DATA / "minerals.toml", "rb") as fh:
        raw = tomllib.load(fh)
    cat = minerals()
    assert set(cat) == set(raw)
    assert set(TABLE_MINERALS) | set(TABLE_CEMENTS) | {"quartz_garcia_medina"} <= set(cat)
    for name, entry in raw.items():
        assert entry.get("source"), name
        assert cat[name].source == entry["source"]
        if "K" in entry:
            assert (cat[name].K, cat[name].G, cat[name].rho) == (entry["K"], entry["G"], entry["rho"])
        else:  # converted entries say how
            assert "derived" in entry, name
    with open(DATA / "fluids.toml", "rb") as fh:
        assert set(tomllib.load(fh)) == set(fluids())


def test_all_catalogue_minerals_are_physical():
    for m in minerals().values():
        assert m.K > 0 and m.G >= 0 and m.rho > 0
        assert -1.0 < m.poisson_ratio <= 0.5
        np.testing.assert_allclose(m.rho * m.vp**2, m.K + 4.0 / 3.0 * m.G, rtol=1e-13)


def test_catalogue_returns_equal_values_each_time_and_is_not_shared_state():
    first = minerals()
    first["quartz"] = Mineral(1.0, 1.0, 1.0, "fake")
    assert mineral("quartz") == Mineral(40.0, 39.0, 2.65, "quartz", mineral("quartz").source)


@pytest.mark.parametrize("lookup, typo, suggestion", [
    (mineral, "quarz", "quartz"), (mineral, "ilite", "illite"), (mineral, "Smectite", "smectite"),
    (fluid, "watr", "water"),
])
def test_unknown_name_suggests_closest(lookup, typo, suggestion):
    with pytest.raises(ValueError, match=rf"did you mean '{suggestion}'\?"):
        lookup(typo)


def test_unknown_name_without_close_match_lists_known():
    with pytest.raises(ValueError, match=r"unknown mineral 'zzzzzz'.*known: .*quartz") as info:
        mineral("zzzzzz")
    assert "did you mean" not in str(info.value)


def test_mineral_properties_written_out():
    m = Mineral(40.0, 39.0, 2.65, "quartz")
    np.testing.assert_allclose(m.poisson_ratio, (120.0 - 78.0) / (2 * (120.0 + 39.0)), rtol=1e-15)
    np.testing.assert_allclose([m.vp, m.vs], [math.sqrt(92.0 / 2.65), math.sqrt(39.0 / 2.65)],
                               rtol=1e-15)
    assert Mineral(2.2, 0.0, 1.0).poisson_ratio == 0.5
    with pytest.raises(dataclasses.FrozenInstanceError):
        m.K = 1.0


@settings(max_examples=50, deadline=None)
@given(st.floats(0.5, 8.0), st.just(0.0) | st.floats(1e-3, 0.8), st.floats(0.5, 5.0))
def test_from_velocities_round_trip(vp, vs_over_vp, rho):
    vs = vs_over_vp * vp  # vs/vp < sqrt(3)/2 keeps K > 0
    m = Mineral.from_velocities(vp, vs, rho)
    np.testing.assert_allclose([m.vp, m.vs], [vp, vs], rtol=1e-12, atol=1e-300)
    np.testing.assert_allclose(m.G, rho * vs**2, rtol=1e-14, atol=1e-300)


@settings(max_examples=50, deadline=None)
@given(st.floats(0.1, 100.0), st.floats(-0.99, 0.49), st.floats(0.5, 5.0))
def test_from_poisson_round_trip(G, nu, rho):
    m = Mineral.from_poisson(G, nu, rho)
    np.testing.assert_allclose(m.poisson_ratio, nu, rtol=1e-11, atol=1e-13)
    # Mavko et al. 2009, Sect. 2.2: lambda = 2 G nu / (1 - 2 nu), K = lambda + 2/3 G.
    np.testing.assert_allclose(m.K, 2 * G * nu / (1 - 2 * nu) + 2 * G / 3, rtol=1e-12)


BAD_MINERALS = [
    pytest.param(lambda: Mineral(0.0, 1.0, 1.0), "K", id="K-zero"),
    pytest.param(lambda: Mineral(-1.0, 1.0, 1.0), "K", id="K-negative"),
    pytest.param(lambda: Mineral(1.0, -1.0, 1.0), "G", id="G-negative"),
    pytest.param(lambda: Mineral(1.0, 1.0, 0.0), "rho", id="rho-zero"),
    pytest.param(lambda: Mineral(float("nan"), 1.0, 1.0), "K", id="K-nan"),
    pytest.param(lambda: Mineral(1.0, float("inf"), 1.0), "G", id="G-inf"),
    pytest.param(lambda: Mineral.from_velocities(1.0, 1.0, 2.0), "vp", id="vp-too-small"),
    pytest.param(lambda: Mineral.from_velocities(3.0, -1.0, 2.0), "vs", id="vs-negative"),
    pytest.param(lambda: Mineral.from_poisson(10.0, 0.5, 2.0), "poisson_ratio", id="nu-0.5"),
    pytest.param(lambda: Mineral.from_poisson(10.0, -1.0, 2.0), "poisson_ratio", id="nu--1"),
    pytest.param(lambda: Mineral.from_poisson(0.0, 0.2, 2.0), "K", id="G-zero-gives-K-zero"),
    pytest.param(lambda: Fluid(-1.0, 1.0), "K", id="fluid-K-negative"),
    pytest.param(lambda: Fluid(1.0, -1.0), "rho", id="fluid-rho-negative"),
    pytest.param(lambda: Fluid(float("nan"), 1.0), "K", id="fluid-K-nan"),
]


@pytest.mark.parametrize("call, name", BAD_MINERALS)
def test_bad_material_raises_value_error_naming_field(call, name):
    with pytest.raises(ValueError, match=rf"\b{name}\b"):
        call()
