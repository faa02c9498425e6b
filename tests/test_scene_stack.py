"""A stack of lithologies on one burial path (issue 31, ``[[layers]]``; rockcem._scene_stack).

Each layer of a stack is checked against the same lithology run alone as a plain scene on the
same path (built here from the shipped scene's TOML, not through the stack's code); the
interface arrays against the layers' profiles; the synthetic column against the layer each
depth lies in, by hand. Coarse depth steps keep them fast.
"""

import copy
import tomllib
import warnings

import numpy as np
import pytest

from rockcem.scene import read_scene_toml, run_scene, scene_from_dict

xr = pytest.importorskip("xarray")

PATH = {"gradient": 30.0, "sedimentation_rate": 40.0, "surface_temperature": 15.0,
        "max_depth": 4000.0, "depth_step": 250.0}
FLUID = {"model": "batzle_wang", "salinity": 0.05, "saturation": 0.8, "gas_gravity": 0.6}


def stack(**changes):
    """A shale seal (the shipped shale) over a sandstone reservoir (the shipped sandstone)."""
    raw = {"name": "stack_test", "path": dict(PATH),
           "stack": {"fluids": ["brine", "gas"], "reservoir": "reservoir"},
           "fluid": dict(FLUID),
           "layers": [{"name": "seal", "scene": "carcione2022_shale", "thickness": 2000.0,
                       "stand_in": "generalized_gassmann"},
                      {"name": "reservoir", "scene": "carcione2022_sandstone"}]}
    raw.update(changes)
    return raw


def run(raw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")       # the models' validity warnings
        return run_scene(scene_from_dict(raw))


@pytest.fixture(scope="module")
def two():
    return run(stack())


def alone(name, fluid):
    """The shipped scene ``name`` alone on the stack's path, with the stack's [fluid] (and
    the hydrocarbon at every depth), as a plain scene."""
    raw, _ = read_scene_toml(name)
    raw = copy.deepcopy(raw)
    raw.pop("sweep", None)
    raw["path"] = dict(PATH)
    raw["fluid"] = dict(FLUID) if fluid != "brine" else {"model": "batzle_wang",
                                                         "salinity": 0.05}
    if fluid != "brine":
        raw["fluid"]["hydrocarbon"] = fluid
    return run(raw)


# --- each layer is its lithology run alone ----------------------------------------------------
@pytest.mark.parametrize("layer, scene, fluid", [
    ("seal", "carcione2022_shale", "brine"), ("seal", "carcione2022_shale", "gas"),
    ("reservoir", "carcione2022_sandstone", "brine"),
    ("reservoir", "carcione2022_sandstone", "gas")])
def test_a_layer_equals_its_lithology_run_alone(two, layer, scene, fluid):
    """The seal holds brine whatever the reservoir's fluid; the reservoir its fluid at every
    depth; every variable of the plain run, every model, to 1e-12."""
    ref = alone(scene, fluid if layer == "reservoir" else "brine")
    got = two.sel(layer=layer)
    if "fluid" in got.dims:
        got = got.sel(fluid=fluid)
    np.testing.assert_array_equal(got.depth, ref.depth)
    checked = 0
    for name in ref.data_vars:
        if name == "hydrocarbon_saturation" and layer == "seal":
            continue
        var = got[name].sel(fluid=fluid) if "fluid" in got[name].dims else got[name]
        for model in (ref.model.values if "model" in ref[name].dims else [None]):
            a = var if model is None else var.sel(model=model)
            b = ref[name] if model is None else ref[name].sel(model=model)
            np.testing.assert_allclose(a.values, b.values, rtol=1e-12, atol=0, err_msg=name)
            checked += 1
    assert checked >= 14
    if layer == "seal":                           # a model the shale does not have
        assert np.isnan(got.vp.sel(model="patchy_cement")).all()


def test_the_reservoir_fluid_changes_the_sand_only(two):
    sand = two.vp.sel(layer="reservoir", model="hs_gassmann")
    seal = two.vp.sel(layer="seal", model="hs_gassmann")
    assert (sand.sel(fluid="gas") < sand.sel(fluid="brine")).all()     # gas softens the sand
    np.testing.assert_array_equal(seal.sel(fluid="gas"), seal.sel(fluid="brine"))
    sat = two.hydrocarbon_saturation
    assert (sat.sel(layer="reservoir", fluid="gas") == 0.8).all()
    assert (sat.sel(layer="seal") == 0.0).all() and (sat.sel(fluid="brine") == 0.0).all()


# --- interfaces -------------------------------------------------------------------------------
def test_interface_arrays_are_the_layers_profiles(two):
    from rockcem.scene import interface_properties

    ip = interface_properties(two)
    assert list(two.interface.values) == ["seal/reservoir"]
    for arr in ip:
        assert arr.dims == ("interface", "fluid", "model", "depth")
        assert arr.shape == (1, 2, 4, two.depth.size)
    for side, layer in ((0, "seal"), (3, "reservoir")):
        vp, vs, rho = ip[side:side + 3]
        for model in two.model.values:
            own = "generalized_gassmann" if layer == "seal" and model == "patchy_cement" \
                else model
            for fluid in ("brine", "gas"):
                here = dict(interface="seal/reservoir", fluid=fluid, model=model)
                prof = two.sel(layer=layer, fluid=fluid)
                np.testing.assert_array_equal(vp.sel(here), prof.vp.sel(model=own))
                np.testing.assert_array_equal(vs.sel(here), prof.vs.sel(model=own))
                np.testing.assert_array_equal(rho.sel(here), prof.density)
    assert list(two.model_of_layer.sel(layer="seal").values) == [
        "hs_gassmann", "self_consistent", "generalized_gassmann", "generalized_gassmann"]
    assert list(two.model_of_layer.sel(layer="reservoir").values) == list(two.model.values)


def test_interfaces_read_back_from_the_file(two, tmp_path):
    from rockcem.scene import interface_properties
    from rockcem.scene import write_dataset

    back = xr.load_dataset(write_dataset(two, tmp_path / "stack.nc"))
    for a, b in zip(interface_properties(two), interface_properties(back)):
        np.testing.assert_array_equal(a.values, b.values)
    with pytest.raises(ValueError, match="stack scene's Dataset"):
        interface_properties(alone("carcione2022_sandstone", "brine"))


# --- the synthetic column ---------------------------------------------------------------------
def test_the_column_takes_the_layer_at_each_depth(two):
    """Seal 0-2000 m (2000 m itself is the reservoir's top), the reservoir below."""
    depth = two.depth.values
    expected = np.where(depth < 2000.0, "seal", "reservoir")
    assert list(two.column_layer.values) == list(expected)
    for i, z in enumerate(depth):
        layer = expected[i]
        for model in two.model.values:
            own = "generalized_gassmann" if layer == "seal" and model == "patchy_cement" \
                else model
            for fluid in ("brine", "gas"):
                prof = two.sel(layer=layer, fluid=fluid, depth=z)
                col = two.sel(fluid=fluid, model=model, depth=z)
                assert float(col.column_vp) == float(prof.vp.sel(model=own))
                assert float(col.column_vs) == float(prof.vs.sel(model=own))
                assert float(col.column_density) == float(prof.density)


def test_three_layers(tmp_path):
    """A shale, a sand and a second, softer shale: two interfaces, each its pair of layers;
    the column 0-1000 m, 1000-1500 m, and below."""
    from rockcem.scene import interface_properties

    raw = stack(layers=[
        {"name": "seal", "scene": "carcione2022_shale", "thickness": 1000.0,
         "models": {"hs_gassmann": {}}, "stand_in": "hs_gassmann"},     # its models replaced
        {"name": "reservoir", "lithology": "sandstone", "thickness": 500.0,
         "sandstone": {"igv_final": 0.2}, "models": {"hs_gassmann": {}, "patchy_cement": {}}},
        {"name": "base", "lithology": "shale", "shale": {"porosity0": 0.4},
         "models": {"hs_gassmann": {}}, "stand_in": "hs_gassmann"}])
    ds = run(raw)
    assert list(ds.layer.values) == ["seal", "reservoir", "base"]
    assert list(ds.interface.values) == ["seal/reservoir", "reservoir/base"]
    assert list(ds.model.values) == ["hs_gassmann", "patchy_cement"]
    ip = interface_properties(ds)
    lower = ip.vp2.sel(interface="reservoir/base", fluid="gas")
    upper = ip.vp1.sel(interface="reservoir/base", fluid="gas")
    np.testing.assert_array_equal(upper.sel(model="patchy_cement"),
                                  ds.vp.sel(layer="reservoir", fluid="gas",
                                            model="patchy_cement"))
    np.testing.assert_array_equal(lower.sel(model="patchy_cement"),
                                  ds.vp.sel(layer="base", fluid="gas", model="hs_gassmann"))
    # The base shale's porosity is its own (Athy from 0.4), not the seal's (0.35).
    assert float(ds.porosity.sel(layer="base", depth=0.0)) == 0.4
    assert float(ds.porosity.sel(layer="seal", depth=0.0)) == 0.35
    depth = ds.depth.values
    expected = np.select([depth < 1000.0, depth < 1500.0], ["seal", "reservoir"], "base")
    assert list(ds.column_layer.values) == list(expected)
    np.testing.assert_array_equal(
        ds.column_vp.sel(fluid="gas", model="hs_gassmann").values,
        [float(ds.vp.sel(layer=lay, fluid="gas", model="hs_gassmann", depth=z))
         for lay, z in zip(expected, depth)])


def test_no_thickness_no_column():
    raw = stack()
    raw["layers"][0].pop("thickness")
    ds = run(raw)
    assert "column_vp" not in ds and "interface" in ds.dims


def test_a_stack_on_a_table_of_horizons(tmp_path):
    """The stack's path table is read beside the stack's file (not beside a layer's scene);
    the depth axis is the horizons', each layer equal to its lithology run alone there."""
    import shutil

    from rockcem._data import data_path
    from rockcem.scene import load_scene

    shutil.copy(data_path("wells") / "synthetic_basin_history.csv", tmp_path / "history.csv")
    text = (
        'name = "horizons_stack"\n[path]\nkind = "horizons"\ntable = "history.csv"\n'
        '[[layers]]\nname = "seal"\nscene = "carcione2022_shale"\n'
        '[[layers]]\nname = "sand"\nscene = "synthetic_basin_horizons"\n'
        'stand_in = "hs_gassmann"\n[layers.models.hs_gassmann]\n')
    (tmp_path / "stack.toml").write_text(text)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = run_scene(load_scene(tmp_path / "stack.toml"))
        raw, _ = read_scene_toml("synthetic_basin_horizons")
        raw = {**raw, "models": {"hs_gassmann": {}}}
        raw["path"] = {"kind": "horizons", "table": str(tmp_path / "history.csv")}
        ref = run_scene(scene_from_dict(raw))
    assert list(ds.model.values) == ["hs_gassmann", "self_consistent", "generalized_gassmann"]
    np.testing.assert_array_equal(ds.depth, ref.depth)
    np.testing.assert_array_equal(ds.horizon, ref.horizon)
    np.testing.assert_allclose(ds.vp.sel(layer="sand", fluid="brine", model="hs_gassmann"),
                               ref.vp.sel(model="hs_gassmann"), rtol=1e-12, atol=0)
    np.testing.assert_allclose(ds.cement_fraction.sel(layer="sand"), ref.cement_fraction,
                               rtol=1e-12, atol=0)


# --- the scene text -----------------------------------------------------------------------------
def test_a_stack_scene_round_trips_through_its_text():
    scene = scene_from_dict(stack())
    coarser = scene.replace(**{"path.depth_step": 1000.0})
    assert coarser.sections["path"]["depth_step"] == 1000.0
    assert [la.name for la in coarser.layers] == ["seal", "reservoir"]
    assert tomllib.loads(coarser.text)["layers"][0]["stand_in"] == "generalized_gassmann"
    assert coarser.lithology == "stack" and not coarser.sweep


def test_plain_scenes_have_no_layers():
    raw, _ = read_scene_toml("carcione2022_sandstone")
    scene = scene_from_dict(raw).replace(**{"path.depth_step": 1000.0})
    assert scene.layers == () and scene.lithology == "sandstone"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = run_scene(scene)
    assert "layer" not in ds.dims and "fluid" not in ds.dims


def test_the_shipped_avo_scene():
    pytest.importorskip("CoolProp")
    from rockcem.scene import load_scene

    scene = load_scene("carcione2022_avo")
    assert [(la.name, la.lithology) for la in scene.layers] == [("seal", "shale"),
                                                                 ("reservoir", "sandstone")]
    assert scene.sections["stack"]["fluids"] == ["brine", "gas", "co2"]
    assert scene.sections["path"]["depth_step"] == 5.0     # 41 angles x 12 members a depth
    assert scene.sections["seismic"]["max_angle"] == 40.0
    assert set(scene.layers[1].scenes) == {"brine", "gas", "co2"}


# --- keys refused by name -----------------------------------------------------------------------
def _layer(i, **keys):
    raw = stack()
    raw["layers"][i].update(keys)
    return raw


def _without(i, key):
    raw = stack()
    raw["layers"][i].pop(key)
    return raw


BAD = [
    (stack(path={**PATH, "gradent": 30.0}), r"^unknown scene key path.gradent; did you mean "
                                             r"'gradient'"),
    (stack(pressure={"water_density": "1"}), r"^scene key pressure.water_density must be a "
                                             r"number"),
    (stack(lithology="shale"), r"scene key 'lithology' does not apply to a stack"),
    (stack(sweep={"path.gradient": [20.0, 30.0]}), r"'sweep' does not apply to a stack"),
    (stack(models={}), r"'models' does not apply to a stack.*\[layers.models"),
    (stack(layerz=[]), r"unknown scene key 'layerz' of a stack; did you mean 'layers'"),
    (_layer(0, thicknes=3.0), r"unknown scene key layers\[0\].thicknes; did you mean "
                              r"'thickness'"),
    (_layer(1, path={}), r"layers\[1\].path does not apply to a layer"),
    (_layer(1, name="seal"), r"layers\[1\].name: 'seal' names two layers"),
    (_layer(1, name="a/b"), r"layers\[1\].name must be letters"),
    (stack(layers=[{"name": "seal", "scene": "carcione2022_shale"}]),
     r"at least two layers .*got 1"),
    (stack(layers={"name": "seal"}), r"array of tables"),
    (_layer(1, lithology="limestone"), r"contradicts scene 'carcione2022_sandstone'"),
    (stack(layers=[stack()["layers"][0], {"name": "reservoir", "lithology": "limestone",
                                          "models": {"hs_gassmann": {}}}]),
     r"lithology must be 'sandstone' or 'shale'; got 'limestone'"),
    (stack(layers=[stack()["layers"][0], {"name": "reservoir", "models": {"hs_gassmann": {}}}]),
     r"layers\[1\] \(reservoir\).lithology is required"),
    (_layer(0, thickness=0.0), r"layers\[0\] \(seal\).thickness must be > 0 m; got 0"),
    (_layer(0, thickness=-5.0), r"thickness must be > 0 m; got -5"),
    (_layer(1, thickness=100.0), r"the last layer fills the column"),
    (_layer(0, thickness=4000.0), r"at or below path.max_depth \(4000 m\)"),
    (_without(0, "stand_in"), r"layer 'seal' has no model 'patchy_cement', which layer "
                              r"'reservoir' has"),
    (_layer(0, stand_in="patchy_cement"), r"stand_in = 'patchy_cement' is not one of the "
                                          r"layer's models"),
    (_layer(1, stand_in="hs_gassmann"), r"layers\[1\] \(reservoir\).stand_in: the layer has "
                                        r"every model"),
    (_layer(0, models={"md": {}, "generalized_gassmann": {}}),
     r"layer 'seal': model 'md' \(the MD grain pack\) is a sandstone model"),
    (_layer(1, models={}), r"layer 'reservoir' has no model"),
    (_layer(0, scene="no_such_scene"), r"scene key layers\[0\] \(seal\).scene: no scene file"),
    (_layer(0, scene="garcia_medina_cement"), r"is an MD study scene"),
    (stack(stack={"fluids": ["brine", "gass"], "reservoir": "reservoir"}),
     r"stack.fluids: unknown fluid 'gass'; did you mean 'gas'"),
    (stack(stack={"fluids": ["gas", "gas"], "reservoir": "reservoir"}), r"names 'gas' twice"),
    (stack(stack={"fluids": ["brine", "gas"]}), r"stack.reservoir is required"),
    (stack(stack={"fluids": ["brine"], "reservoir": "reservior"}, fluid={}),
     r"no layer 'reservior'; did you mean 'reservoir'"),
    (stack(fluid={**FLUID, "top": 2000.0}), r"fluid.top does not apply to a stack"),
    (stack(fluid={**FLUID, "hydrocarbon": "gas"}), r"fluid.hydrocarbon does not apply to a "
                                                   r"stack.*\[stack\] fluids"),
    (stack(fluid={"model": "batzle_wang"}), r"fluid.saturation is required"),
    (stack(stack={"fluids": ["brine"]}), r"fluid.saturation does not apply to "
                                         r"stack.fluids = \['brine'\]"),
    (stack(fluid={**FLUID, "saturation": 1.5}), r"fluid.saturation must lie in \[0, 1\]"),
    (_layer(1, sandstone={"igv_final": "0.2"}), r"layer 'reservoir'.*sandstone.igv_final must "
                                                r"be a number"),
    (_layer(1, outputs=["vpp"]), r"layer 'reservoir'.*output 'vpp'"),
]


@pytest.mark.parametrize("raw, message", BAD, ids=[m[:40] for _, m in BAD])
def test_keys_refused_by_name(raw, message):
    with pytest.raises(ValueError, match=message):
        scene_from_dict(raw)


def test_a_stack_section_needs_layers():
    raw, _ = read_scene_toml("carcione2022_sandstone")
    with pytest.raises(ValueError, match=r"\[stack\] applies to a stack of layers"):
        scene_from_dict({**raw, "stack": {"fluids": ["brine"]}})


def test_the_docs_stack_example_is_a_valid_scene():
    """The TOML of the scenes page's stack section loads, with the layers and keys it shows."""
    import re
    from pathlib import Path

    page = Path(__file__).resolve().parents[1] / "docs/user_guide/scenes.md"
    text = page.read_text(encoding="utf-8").split("## Stacks of layers")[1]
    block = re.search(r"^```toml\n(.*?)^```", text, flags=re.S | re.M).group(1)
    scene = scene_from_dict(tomllib.loads(block))
    assert [la.name for la in scene.layers] == ["seal", "reservoir"]
    assert scene.models == ("hs_gassmann", "self_consistent", "generalized_gassmann",
                            "patchy_cement")
    assert set(scene.layers[1].scenes) == {"brine", "gas"}
    sand = scene.layers[1].scenes["gas"].sections["sandstone"]
    assert sand["igv_final"] == 0.18 and sand["grain_size"] == 0.3      # override, and taken
