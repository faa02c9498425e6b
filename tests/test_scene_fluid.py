"""Issue 20: a scene's pore fluid follows the burial path ([fluid]): Batzle-Wang brine from each
depth's temperature and pore pressure, a hydrocarbon over an interval, mixed uniformly (Wood),
by Brie's law or in patches, and every model saturated with it."""

import numpy as np
import pytest

from rockcem import pore_fluids as pf
from rockcem.constants import STANDARD_ATMOSPHERE
from rockcem.fluids import gassmann
from rockcem.scene import run_scene, scene_from_dict

MODELS = {"hs_gassmann": {}, "self_consistent": {"aspect_ratio": 0.108},
          "generalized_gassmann": {}, "patchy_cement": {}}
BASE = {"name": "f", "lithology": "sandstone",
        "path": {"max_depth": 4000.0, "depth_step": 250.0}, "models": MODELS}
GAS = {"model": "batzle_wang", "salinity": 0.05, "hydrocarbon": "gas", "saturation": 0.8,
       "top": 2000.0, "base": 3000.0}


def run(fluid=None, **extra):
    raw = {**BASE, **extra}
    if fluid is not None:
        raw["fluid"] = fluid
    return run_scene(scene_from_dict(raw))


@pytest.fixture(scope="module")
def water():
    return run()


@pytest.fixture(scope="module")
def brine():
    return run({"model": "batzle_wang", "salinity": 0.05})


def test_constant_fluid_is_the_sources_water(water):
    ds = run({"model": "constant"})
    for name in ("vp", "vs", "density", "K_sat"):
        np.testing.assert_array_equal(ds[name].values, water[name].values)
    np.testing.assert_array_equal(ds.fluid_bulk_modulus.values, 2.2)
    np.testing.assert_array_equal(ds.fluid_density.values, 1.04)
    assert "fluid_density" not in water            # no [fluid]: no fluid outputs by default


def test_brine_follows_the_paths_temperature_and_pore_pressure(brine):
    T, P = brine.temperature.values, brine.pressure_pore.values + STANDARD_ATMOSPHERE
    b = pf.brine(T, P, 0.05)
    np.testing.assert_allclose(brine.fluid_bulk_modulus.values, b.K, rtol=1e-12)
    np.testing.assert_allclose(brine.fluid_density.values, b.rho, rtol=1e-12)
    np.testing.assert_allclose(brine.fluid_velocity.values, b.vp, rtol=1e-12)
    # brine stiffens then softens with depth (Batzle & Wang, Fig. 13): not one constant
    K = brine.fluid_bulk_modulus.values
    assert K.max() - K.min() > 0.2 and 0 < np.argmax(K) < K.size - 1


def test_no_model_frame_sees_the_fluid(brine, water):
    for name in ("K_dry", "G_dry"):
        np.testing.assert_allclose(brine[name], water[name], rtol=1e-12)


@pytest.mark.parametrize("model", ["hs_gassmann", "patchy_cement"])
def test_gassmann_models_are_saturated_with_the_depths_fluid(brine, water, model):
    """K_dry does not see the fluid; K_sat is Gassmann's with the depth's brine (the mineral
    modulus backed out of the water-saturated run, whose fluid is 2.2 GPa)."""
    b, w = brine.sel(model=model), water.sel(model=model)
    np.testing.assert_allclose(b.K_dry, w.K_dry, rtol=1e-12)
    np.testing.assert_allclose(b.G_sat, w.G_sat, rtol=1e-12)
    phi = brine.porosity.values
    # Gassmann solved for K_min from the water run (a root of a quadratic), then applied with
    # the brine: an independent path from the runner's own call
    Kd, Ks = w.K_dry.values, w.K_sat.values
    lo, hi = np.maximum(Ks, Kd) * (1 + 1e-9), np.full_like(Ks, 100.0)
    for _ in range(200):                           # bisection on K_min (K_sat rises with it)
        mid = 0.5 * (lo + hi)
        up = gassmann(Kd, mid, 2.2, phi) > Ks
        hi, lo = np.where(up, mid, hi), np.where(up, lo, mid)
    K_min = 0.5 * (lo + hi)
    expect = gassmann(Kd, K_min, brine.fluid_bulk_modulus.values, phi)
    np.testing.assert_allclose(b.K_sat, expect, rtol=1e-6)


def test_self_consistent_model_takes_the_fluid_per_depth(brine):
    from rockcem.materials import Fluid, mineral
    from rockcem.models import self_consistent_model

    k = 9
    fluid = Fluid(float(brine.fluid_bulk_modulus[k]), float(brine.fluid_density[k]))
    solids = np.array([1.0 - brine.cement_fraction[k] / (1 - brine.porosity[k]),
                       brine.cement_fraction[k] / (1 - brine.porosity[k])])
    one = self_consistent_model([mineral("quartz"), mineral("quartz_cement")], solids,
                                float(brine.porosity[k]), fluid, aspect_ratio=0.108)
    assert float(brine.vp.sel(model="self_consistent")[k]) == pytest.approx(float(one.vp),
                                                                            rel=1e-9)


def test_wood_mixture_inside_the_interval_brine_outside(brine):
    ds = run(GAS)
    z = ds.depth.values
    inside = (z >= 2000) & (z <= 3000)
    np.testing.assert_array_equal(ds.hydrocarbon_saturation.values, np.where(inside, 0.8, 0.0))
    for name in ("vp", "fluid_bulk_modulus", "density"):
        np.testing.assert_array_equal(ds[name].values[..., ~inside],
                                      brine[name].values[..., ~inside])
    T = ds.temperature.values[inside]
    P = ds.pressure_pore.values[inside] + STANDARD_ATMOSPHERE
    g, b = pf.gas(T, P, 0.6), pf.brine(T, P, 0.05)
    K_wood = 1.0 / (0.2 / b.K + 0.8 / g.K)              # Wood 1955, closed form
    np.testing.assert_allclose(ds.fluid_bulk_modulus.values[inside], K_wood, rtol=1e-12)
    np.testing.assert_allclose(ds.fluid_density.values[inside], 0.2 * b.rho + 0.8 * g.rho,
                               rtol=1e-12)
    # a gas sand is slower and lighter than the brine sand, Vp/Vs lower
    vp, vs = ds.vp.values[:, inside], ds.vs.values[:, inside]
    assert np.all(vp < brine.vp.values[:, inside])
    assert np.all(vp / vs < brine.vp.values[:, inside] / brine.vs.values[:, inside])


def test_patchy_is_the_p_modulus_average_of_the_two_saturated_rocks(brine):
    """Patchy saturation from two separate runs — all brine, all gas — combined by hand."""
    ds = run({**GAS, "mixing": "patchy"})
    all_gas = run({**GAS, "saturation": 1.0})
    z = ds.depth.values
    inside = (z >= 2000) & (z <= 3000)
    for model in ("hs_gassmann", "patchy_cement"):
        b, g, p = (d.sel(model=model).isel(depth=inside) for d in (brine, all_gas, ds))
        M = 1.0 / (0.2 / (b.K_sat + 4 / 3 * b.G_sat) + 0.8 / (g.K_sat + 4 / 3 * g.G_sat))
        np.testing.assert_allclose(p.K_sat + 4 / 3 * p.G_sat, M, rtol=1e-10)
        rho = 0.2 * b.density + 0.8 * g.density
        np.testing.assert_allclose(p.vp, np.sqrt(M / rho), rtol=1e-10)
    # patchy is stiffer than uniform (Wood) saturation: its upper limit; and no stiffer than
    # the rock all brine-saturated, the stiffer patch
    wood = run(GAS)
    assert np.all(ds.vp.values[:, inside] >= wood.vp.values[:, inside] - 1e-12)
    M = lambda d: (d.K_sat + 4 / 3 * d.G_sat).values[:, inside]          # noqa: E731
    assert np.all(M(ds) <= M(brine) * (1 + 1e-12)) and np.all(M(ds) >= M(all_gas))
    assert np.all(ds.vp / ds.vs >= np.sqrt(4 / 3))                       # an isotropic solid
    assert "fluid_bulk_modulus" not in ds          # no single fluid in patches


def test_co2_sand_through_the_reference_equation_of_state():
    pytest.importorskip("CoolProp")
    ds = run({**GAS, "hydrocarbon": "co2"})
    z = ds.depth.values
    inside = (z >= 2000) & (z <= 3000)
    c = pf.co2(ds.temperature.values[inside],
               ds.pressure_pore.values[inside] + STANDARD_ATMOSPHERE)
    assert np.all((c.rho > 0.3) & (c.rho < 0.9))        # dense (supercritical) CO2 at 2-3 km
    np.testing.assert_allclose(ds.fluid_density.values[inside],
                               0.2 * pf.brine(ds.temperature.values[inside],
                                              ds.pressure_pore.values[inside]
                                              + STANDARD_ATMOSPHERE, 0.05).rho + 0.8 * c.rho,
                               rtol=1e-12)


def test_the_fluid_is_a_sweep_dimension(brine):
    raw = {**BASE, "fluid": {k: v for k, v in GAS.items() if k != "hydrocarbon"},
           "sweep": {"fluid.hydrocarbon": ["none", "gas", "oil"]}}
    ds = run_scene(scene_from_dict(raw))
    assert list(ds.hydrocarbon.values) == ["none", "gas", "oil"]
    np.testing.assert_array_equal(ds.vp.sel(hydrocarbon="none").values, brine.vp.values)
    np.testing.assert_array_equal(ds.vp.sel(hydrocarbon="gas").values, run(GAS).vp.values)
    np.testing.assert_array_equal(ds.hydrocarbon_saturation.sel(hydrocarbon="none").values, 0.0)


def test_fluid_warnings_name_the_depths():
    ds = run({"model": "batzle_wang", "salinity": 0.32})
    assert "salinity above 0.3" in ds.attrs["validity_warnings"]


@pytest.mark.parametrize("fluid,message", [
    ({"hydrocarbon": "gas"}, "fluid.saturation is required"),
    ({"hydrocarbon": "gaz", "saturation": 0.5}, "did you mean 'gas'"),
    ({"model": "batzle-wang"}, "did you mean 'batzle_wang'"),
    ({"salinity": 0.1}, "fluid.salinity does not apply to fluid.model = 'constant'"),
    ({"hydrocarbon": "gas", "saturation": 0.5, "oil_api": 30.0},
     "fluid.oil_api does not apply"),
    ({"saturation": 0.5}, "fluid.saturation does not apply to fluid.hydrocarbon = 'none'"),
    ({"hydrocarbon": "gas", "saturation": 1.5}, r"fluid.saturation must lie in \[0, 1\]"),
    ({"model": "batzle_wang", "salinity": 0.35}, r"fluid.salinity must lie in \[0, 0.35\)"),
    ({"hydrocarbon": "gas", "saturation": 0.5, "top": 3000.0, "base": 2000.0}, "top < base"),
    ({"hydrocarbon": "gas", "saturation": 0.5, "top": 9000.0}, "holds no depth"),
    ({"hydrocarbon": "oil", "saturation": 0.5, "gas_oil_ratio": 500.0},
     r"\[fluid\] \(fluid.hydrocarbon = 'oil'\).*gas_oil_ratio"),
])
def test_bad_fluid_sections_are_named(fluid, message):
    with pytest.raises(ValueError, match=message):
        run(fluid)


def test_a_swept_hydrocarbon_needs_its_saturation_at_load():
    with pytest.raises(ValueError, match="fluid.saturation is required with hydrocarbon = "
                                         "'gas'"):
        scene_from_dict({**BASE, "fluid": {"model": "batzle_wang"},
                         "sweep": {"fluid.hydrocarbon": ["none", "gas"]}})


def test_patchy_scene_refuses_a_single_fluid_modulus_output():
    with pytest.raises(ValueError, match="'fluid_bulk_modulus' is not available.*patchy"):
        run({**GAS, "mixing": "patchy"}, outputs=["vp", "fluid_bulk_modulus"])


def test_templates_take_the_scenes_brine(brine):
    """The plots' template lines are saturated with the scene's brine (its median over the
    profile), not the catalogue water the Dataset no longer names."""
    import matplotlib.pyplot as plt

    from rockcem.plots import rock_physics_template, velocity_porosity

    assert brine.attrs["fluid"] == "brine"
    assert brine.attrs["brine_bulk_modulus"] == pytest.approx(
        float(np.median(brine.fluid_bulk_modulus)), rel=1e-12)
    assert "Batzle & Wang brine, salinity 0.05" in brine.attrs["pore_fluid"]
    for plot in (rock_physics_template, velocity_porosity):
        fig = plot(brine)
        titles = " ".join(t.get_text() for t in fig.findobj(plt.Text))
        assert "brine (median)" in titles
        plt.close(fig)


def test_each_horizon_gets_its_own_present_day_brine():
    """On a horizon table the fluid follows each horizon's present-day temperature and pore
    pressure (an uplifted horizon is cooler than its deepest burial)."""
    from rockcem.scene import load_scene

    scene = load_scene("synthetic_basin_horizons")
    ds = run_scene(scene.replace(**{"fluid.model": "batzle_wang", "fluid.salinity": 0.1}))
    b = pf.brine(ds.temperature.values, ds.pressure_pore.values + STANDARD_ATMOSPHERE, 0.1)
    np.testing.assert_allclose(ds.fluid_bulk_modulus.values, b.K, rtol=1e-12)
    assert ds.fluid_bulk_modulus.dims == ("depth",) and "horizon" in ds.coords


def test_sweeping_the_fluid_model_is_its_own_dimension(water, brine):
    """``fluid.model`` sweeps along ``fluid_model``: ``model`` is the models' dimension (the
    sweep failed after running every member)."""
    raw = {**BASE, "fluid": {"salinity": 0.05},
           "sweep": {"fluid.model": ["constant", "batzle_wang"]}}
    ds = run_scene(scene_from_dict(raw))
    assert ds.vp.dims == ("fluid_model", "model", "depth")
    np.testing.assert_array_equal(ds.vp.sel(fluid_model="constant").values, water.vp.values)
    np.testing.assert_array_equal(ds.vp.sel(fluid_model="batzle_wang").values, brine.vp.values)


def test_a_sweep_over_the_fluid_says_so_and_the_template_takes_the_members_brine():
    import matplotlib.pyplot as plt

    from rockcem.plots import rock_physics_template

    raw = {**BASE, "fluid": {"model": "batzle_wang", "hydrocarbon": "gas", "saturation": 0.8,
                             "top": 2000.0, "base": 3000.0},
           "sweep": {"fluid.salinity": [0.0, 0.2]}}
    ds = run_scene(scene_from_dict(raw))
    text = ds.attrs["pore_fluid"]
    assert text.startswith("varies over the sweep:")
    assert "[salinity = 0.0] Batzle & Wang brine, salinity 0;" in text
    assert "[salinity = 0.2] Batzle & Wang brine, salinity 0.2;" in text
    assert "brine_bulk_modulus" not in ds.attrs          # no one brine for every member
    one = ds.sel(salinity=0.2)
    brine = one.fluid_bulk_modulus.values[one.hydrocarbon_saturation.values == 0.0]
    fig = rock_physics_template(one)
    title = " ".join(t.get_text() for t in fig.findobj(plt.Text))
    assert "brine (median)" in title
    plt.close(fig)
    assert float(np.median(brine)) > 3.0                 # the 20 % NaCl brine, not the fresh
    with pytest.raises(ValueError, match="brine differs between its sweep members"):
        rock_physics_template(ds.drop_vars(["fluid_bulk_modulus"]))


@pytest.mark.parametrize("fluid,sweep,message", [
    ({"gas_gravity": 0.7}, {"fluid.hydrocarbon": ["co2", "methane"]},
     r"does not apply to fluid.hydrocarbon swept over \['co2', 'methane'\]"),
    ({"hydrocarbon": "gas", "saturation": 0.5, "top": 2000.0}, {"fluid.base": [1500.0, 3000.0]},
     r"fluid.top \(2000 m\) and fluid.base \(1500 m\) must make an interval"),
])
def test_swept_fluid_keys_are_checked_at_load(fluid, sweep, message):
    with pytest.raises(ValueError, match=message):
        scene_from_dict({**BASE, "fluid": fluid, "sweep": sweep})


def test_the_catalogue_fluid_and_batzle_wang_brine_are_not_both_given():
    with pytest.raises(ValueError, match="materials.fluid = 'vacuum' does not apply to "
                                         "fluid.model = 'batzle_wang'"):
        scene_from_dict({**BASE, "materials": {"fluid": "vacuum"},
                         "fluid": {"model": "batzle_wang"}})



def test_fresh_batzle_wang_water_along_the_path_against_iapws95():
    """The scene's fluid of salinity 0 against an independent equation of state: IAPWS-95
    (CoolProp) at each depth's temperature and absolute pore pressure, within Batzle & Wang's
    accuracy (0.6 % in density, 1.4 % in velocity to 250 degC)."""
    CP = pytest.importorskip("CoolProp.CoolProp")
    ds = run({"model": "batzle_wang"})
    T = ds.temperature.values + 273.15
    P = (ds.pressure_pore.values + STANDARD_ATMOSPHERE) * 1e6
    rho = np.array([CP.PropsSI("D", "T", t, "P", p, "Water") for t, p in zip(T, P)]) / 1000.0
    c = np.array([CP.PropsSI("A", "T", t, "P", p, "Water") for t, p in zip(T, P)]) / 1000.0
    np.testing.assert_allclose(ds.fluid_density.values, rho, rtol=6e-3)
    np.testing.assert_allclose(ds.fluid_velocity.values, c, rtol=1.4e-2)
