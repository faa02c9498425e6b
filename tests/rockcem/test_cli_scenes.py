"""Issue 22: a shipped scene written out as a file to start from keeps its data (horizon table,
calibration) wherever it is copied; a missing data file is named with where it was looked for,
each place once, saying what it is relative to."""

import os

import xarray as xr

from rockcem.scene import shipped_scenes


def test_write_a_shipped_scene_and_run_it_from_elsewhere(tmp_path, run_cli):
    out = run_cli(["scenes", "synthetic_basin_horizons", "-o", str(tmp_path / "my.toml")],
                  tmp_path)
    assert out.returncode == 0, out.stderr
    text = (tmp_path / "my.toml").read_text()
    assert text == shipped_scenes()["synthetic_basin_horizons"].read_text()
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    out = run_cli(["run", str(tmp_path / "my.toml"), "-q", "-o", "x.nc"], elsewhere)
    assert out.returncode == 0, out.stderr
    with xr.open_dataset(elsewhere / "x.nc") as ds:
        assert ds.sizes["depth"] == 52                 # the shipped table's 52 horizons


def test_print_a_shipped_scene_and_refusals(tmp_path, run_cli):
    out = run_cli(["scenes", "carcione2022_shale"], tmp_path)
    assert out.returncode == 0
    assert out.stdout == shipped_scenes()["carcione2022_shale"].read_text()
    out = run_cli(["scenes", "carcione2022_shael"], tmp_path)
    assert out.returncode == 2 and "did you mean 'carcione2022_shale'" in out.stderr
    out = run_cli(["scenes", "-o", "x.toml"], tmp_path)
    assert out.returncode == 2 and "give its name" in out.stderr
    assert os.listdir(tmp_path) == []


def test_a_missing_table_names_each_place_once(tmp_path, run_cli):
    text = shipped_scenes()["synthetic_basin_horizons"].read_text()
    (tmp_path / "s.toml").write_text(text.replace("synthetic_basin_history.csv", "gone.csv"))
    out = run_cli(["run", "s.toml", "-q"], tmp_path)          # the scene's folder is the cwd
    assert out.returncode == 2 and out.stderr.count("\n") == 1
    msg = out.stderr
    assert msg.count(str(tmp_path / "gone.csv")) == 1
    assert "(the scene file's folder and the working directory)" in msg
    assert "(the shipped data)" in msg
