"""The netCDF files of every shipped scene read as CF: checked with cf_xarray (axes,
coordinates, standard names) and its pint unit registry (UDUNITS strings), and on the raw file
with netCDF4 (no fill value on coordinates, no empty units, no time coordinate).

Scenes of the linear basin model run on a coarse depth grid (``path.depth_step``) to stay
fast; the MD scene (a grain-pack experiment, minutes) is not run here.
"""

import pytest

from rockcem.scene import read_scene_toml, run_scene, shipped_scenes, write_dataset

pytest.importorskip("cf_xarray")
pytest.importorskip("pint")
netCDF4 = pytest.importorskip("netCDF4")
xr = pytest.importorskip("xarray")

#: CF standard names the scene Datasets use, with the canonical units of the CF standard name
#: table (version 84): depth in m, temperature_in_ground in K.
CANONICAL_UNITS = {"depth": "m", "temperature_in_ground": "K"}

SCENES = sorted(name for name in shipped_scenes() if "md" not in read_scene_toml(name)[0])


#: A burial scene with the MD engine as a model runs a small pack at two depths here.
TINY_MD = {"count": 2, "size": [3.0, 3.0, 8.0], "resolution": 2.0, "resolution_check": 1.5}


@pytest.fixture(scope="module", params=SCENES)
def written(request, tmp_path_factory):
    from rockcem.scene import scene_from_dict, scene_path

    raw, _ = read_scene_toml(request.param)
    if "md" in raw.get("models", {}):
        keep = {k: v for k, v in raw["models"]["md"].items() if k not in ("depths", "count")}
        raw["models"]["md"] = {**keep, **TINY_MD,
                               "workdir": str(tmp_path_factory.mktemp("md_work"))}
    scene = scene_from_dict(raw, base_dir=scene_path(request.param).parent)
    if scene.sections["path"]["kind"] == "linear":       # a table history has its own depths
        scene = scene.replace(**{"path.depth_step": 500.0 if scene.sweep else 250.0})
    ds = run_scene(scene)
    return write_dataset(ds, tmp_path_factory.mktemp("cf") / f"{request.param}.nc")


def test_shipped_scenes_are_all_checked():
    assert {"carcione2022_sandstone", "carcione2022_shale"} <= set(SCENES)
    md_scenes = [n for n in shipped_scenes() if "md" in read_scene_toml(n)[0]]
    assert {"garcia_medina_cement", "garcia_medina_full"} <= set(md_scenes)
    assert len(SCENES) == len(shipped_scenes()) - len(md_scenes)   # all but the MD scenes


def test_cf_axes_coordinates_and_standard_names(written):
    from cf_xarray.units import units as udunits

    ds = xr.load_dataset(written, engine="netcdf4")        # CF decoding on, times included
    assert ds.attrs["Conventions"].startswith("CF-")
    assert ds.cf.axes == {"Z": ["depth"]}                  # no T axis: nothing looks like time
    assert ds.cf.coordinates == {"vertical": ["depth"]}
    assert "time" not in ds.variables
    names = ds.cf.standard_names
    assert set(names) <= set(CANONICAL_UNITS), names
    for standard_name, variables in names.items():
        canonical = udunits.Unit(CANONICAL_UNITS[standard_name])
        for name in variables:
            assert udunits.Unit(ds[name].attrs["units"]).is_compatible_with(canonical), name
    # Every 1-D profile made a coordinate, as a user plotting against it would: none is
    # guessed to be time (a variable named "time" is).
    profiles = [n for n in ds.data_vars if ds[n].dims == ("depth",)]
    guessed = ds.set_coords(profiles).cf.guess_coord_axis()
    assert "T" not in guessed.cf.axes and "time" not in guessed.cf.coordinates


def test_every_variable_has_parseable_units_and_a_long_name(written):
    from cf_xarray.units import units as udunits

    ds = xr.load_dataset(written, engine="netcdf4")
    for name, var in ds.variables.items():
        assert var.attrs.get("long_name"), name
        if var.dtype.kind in "OSU":                        # labels (model, horizon): no units
            assert "units" not in var.attrs, name
            continue
        units = var.attrs["units"]
        assert units.strip(), f"{name} has empty units"
        udunits.Unit(units)                                # raises for a non-UDUNITS string
    for name in ds.data_vars:
        if "flag_values" in ds[name].attrs:
            assert len(ds[name].attrs["flag_values"]) == len(
                ds[name].attrs["flag_meanings"].split()), name


def test_raw_file_coordinates_have_no_fill_value(written):
    with netCDF4.Dataset(written) as nc:
        for name in nc.dimensions:
            if name in nc.variables:
                assert "_FillValue" not in nc.variables[name].ncattrs(), name
                assert "missing_value" not in nc.variables[name].ncattrs(), name
        for var in nc.variables.values():
            assert "units" not in var.ncattrs() or var.getncattr("units") != "", var.name


def test_burial_state_file_coordinates_have_no_fill_value(tmp_path):
    """The burial package's own Datasets are written as CF too (no NaN fill on depth)."""
    import burial

    path = burial.linear_path(gradient=30.0, sedimentation_rate=40.0, surface_temperature=15.0,
                              max_depth=1000.0, depth_step=250.0)
    for state in (burial.sandstone_state(path), burial.shale_state(path)):
        out = write_dataset(state, tmp_path / "state.nc")
        with netCDF4.Dataset(out) as nc:
            assert "_FillValue" not in nc.variables["depth"].ncattrs()
            assert "burial_time" in nc.variables and "time" not in nc.variables


def test_scene_output_key_time_is_read_as_burial_time():
    """Scene files written before the rename list ``time``; it selects ``burial_time``."""
    from rockcem.scene import scene_from_dict

    raw, _ = read_scene_toml("carcione2022_sandstone")
    raw = {**raw, "outputs": ["time", "porosity"], "models": {}}
    assert scene_from_dict(raw).outputs == ("burial_time", "porosity")
    raw["outputs"] = ["burial_time"]
    assert scene_from_dict(raw).outputs == ("burial_time",)
