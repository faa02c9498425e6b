"""Issue 24: the MD entry points refuse what would exhaust memory or read garbage, in one line
naming the argument or scene key."""

import numpy as np
import pytest
import xarray as xr

import md
from md.deposit import MAX_GRAINS, check_size, grain_count
from md.experiment import md_scene_from_dict


def test_grain_count_against_its_closed_form():
    # Equal radii r = 1 (d = 2): 0.6 of the box volume over the sphere volume 4/3 pi.
    size = (10.0, 10.0, 20.0)
    assert grain_count(size, (1.0, 1.0)) == round(0.6 * 2000 * 8 / (4.0 / 3.0 * np.pi))


@pytest.mark.parametrize("size,message", [
    ((1e4, 1e4, 1e4), r"holds about 1\.\d+e\+12 grains; at most 100000"),
    ((np.nan, 4.0, 12.0), "positive finite"),
    ((4.0, 4.0), "positive finite"),
    ((4.0, 4.0, "12"), None),                      # a numeric string reads as the number
    ((2.0, 4.0, 12.0), "wider than two"),
    ((4.0, 4.0, 4.0), "at least 5"),
    ("abc", "three numbers"),
])
def test_settle_refuses_a_box_before_allocating(size, message):
    if message is None:
        assert check_size(size) == (4.0, 4.0, 12.0)
        return
    with pytest.raises(ValueError, match=f"^size.*{message}"):
        md.settle(size)


def test_the_largest_allowed_box_is_allowed():
    # radii uniform in [0.9, 1]: mean volume 4/3 pi (1 - 0.9^4) / (4 x 0.1); d = 2
    per_cube = 0.6 * 8.0 / (4.0 / 3.0 * np.pi * (1 - 0.9**4) / 0.4)
    side = (MAX_GRAINS / per_cube) ** (1 / 3)
    assert check_size((0.99 * side,) * 3)
    with pytest.raises(ValueError, match="grains"):
        check_size((1.01 * side,) * 3)


@pytest.mark.parametrize("raw,message", [
    ({"name": "../x", "md": {}}, "name must be a plain file name"),
    ({"name": "", "md": {}}, "name must be a plain file name"),
    ({"name": 3, "md": {}}, "name must be a string"),
    ({"name": "x", "output": "", "md": {}}, "output must name a file"),
    ({"name": "x", "md": {"size": [200.0, 200.0, 200.0]}}, "md.size .* grains"),
    ({"name": "x", "md": {"size": [2.0, 4.0, 12.0]}}, "md.size: the box must be wider"),
])
def test_md_scene_refusals_outside_the_cli(raw, message):
    with pytest.raises(ValueError, match=message):
        md_scene_from_dict(raw)


def test_md_scene_default_output_is_the_name():
    assert md_scene_from_dict({"name": "study", "md": {}})["output"] == "study.nc"


@pytest.mark.parametrize("content,message", [
    (b"", "cannot be read as netCDF"),
    (b"\x89HDF\r\n\x1a\n" + b"x" * 50, "cannot be read as netCDF"),
    (b"not a netcdf file at all", "cannot be read as netCDF"),
    (b"CDF\x01" + b"\x00" * 28, "is not a rockcem pack file"),     # a valid, empty netCDF 3
])
def test_load_pack_on_a_corrupt_file(tmp_path, content, message):
    path = tmp_path / "pack.nc"
    path.write_bytes(content)
    with pytest.raises(ValueError, match=f"pack.nc.* {message}"):
        md.load_pack(path)


def test_load_pack_on_a_truncated_and_on_a_foreign_netcdf(tmp_path):
    foreign = tmp_path / "foreign.nc"
    xr.Dataset({"x": ("i", np.arange(1000.0))}).to_netcdf(foreign, engine="netcdf4")
    with pytest.raises(ValueError, match="foreign.nc is not a rockcem pack file"):
        md.load_pack(foreign)
    truncated = tmp_path / "truncated.nc"
    truncated.write_bytes(foreign.read_bytes()[: foreign.stat().st_size // 2])
    with pytest.raises(ValueError, match="cannot be read as netCDF"):
        md.load_pack(truncated)
