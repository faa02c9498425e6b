"""Saving and loading grain packs (resume from the last stage)."""

import os

import numpy as np
import pytest
import xarray as xr

from md.contact import QUARTZ
from md.space import Box
from md.state import Pack, load_pack, save_pack


def make_pack(rng, n=20, m=7):
    return Pack(positions=rng.uniform(0, 1e-3, (n, 3)), velocities=rng.normal(size=(n, 3)),
                angular_velocities=rng.normal(size=(n, 3)), radii=rng.uniform(1.8e-4, 2e-4, n),
                box=Box(2e-3, 2e-3, 0.0, 5e-3), material=QUARTZ,
                pairs=rng.integers(0, n, (m, 2)).astype(np.int32), history=rng.normal(size=(m, 3)),
                stage="settle", time=1.25e-3, metadata={"seed": 7, "porosity": 0.41})


def test_round_trip(rng, tmp_path):
    pack = make_pack(rng)
    back = load_pack(save_pack(pack, tmp_path / "pack.nc"))
    for name in ("positions", "velocities", "angular_velocities", "radii", "pairs", "history"):
        np.testing.assert_array_equal(getattr(back, name), getattr(pack, name))
    assert back.box == pack.box and back.material == pack.material
    assert back.stage == "settle" and back.time == pack.time and back.metadata == pack.metadata


def test_saved_pack_has_ordinary_permissions(rng, tmp_path):
    """Like any new file (umask applied), not private as the temporary file was made."""
    umask = os.umask(0)
    os.umask(umask)
    path = save_pack(make_pack(rng), tmp_path / "pack.nc")
    assert os.stat(path).st_mode & 0o777 == 0o666 & ~umask


def test_save_is_atomic(rng, tmp_path, monkeypatch):
    target = tmp_path / "pack.nc"
    target.write_bytes(b"previous stage")

    def broken(self, path, **kw):
        with open(path, "wb") as fh:
            fh.write(b"half")
        raise OSError("interrupted")

    monkeypatch.setattr(xr.Dataset, "to_netcdf", broken)
    with pytest.raises(OSError):
        save_pack(make_pack(rng), target)
    assert target.read_bytes() == b"previous stage" and os.listdir(tmp_path) == ["pack.nc"]


def test_bad_pack(rng, tmp_path):
    with pytest.raises(ValueError, match="positions"):
        Pack(np.zeros((3, 2)), np.zeros((3, 3)), np.zeros((3, 3)), np.ones(3),
             Box(1.0, 1.0, 0.0, 1.0), QUARTZ, np.zeros((0, 2), np.int32), np.zeros((0, 3)))
    with pytest.raises(ValueError, match="no pack file"):
        load_pack(tmp_path / "missing.nc")
