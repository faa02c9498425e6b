"""[models.md] keys checked before any settling, the MD depths of ``count``, the MD stage
folder and damaged stage files (issue 30). Nothing here settles a pack: ``md.protocols.
prepare_pack`` (where the pack is settled) is replaced by a stub that fails the test."""

import warnings
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from rockcem import cli
from rockcem.scene import run_scene, scene_from_dict


class Settled(Exception):
    """Raised where the pack would be settled: every check came first."""


@pytest.fixture
def no_settling(monkeypatch):
    import md.protocols

    def settle(*args, **kwargs):
        raise Settled

    monkeypatch.setattr(md.protocols, "prepare_pack", settle)


def scene(tmp_path, **md):
    table = {"depths": [1000.0, 2500.0], "size": [3.0, 3.0, 8.0], "resolution": 2.0,
             "workdir": str(tmp_path / "md"), **md}
    return scene_from_dict({"name": "keys", "lithology": "sandstone",
                            "path": {"max_depth": 3000.0, "depth_step": 100.0},
                            "sandstone": {"start_temperature": 70.0},
                            "models": {"md": table}})


def test_a_good_table_reaches_the_settling(tmp_path, no_settling):
    with pytest.raises(Settled):
        run_scene(scene(tmp_path))


@pytest.mark.parametrize("key, value, message", [
    ("seed", -1, r"seed must be an integer >= 0 \(numpy's random seeds\); got -1"),
    ("interface", "fasset", r"interface must be one of facet, patch, paper; got 'fasset'"),
    ("measure", "pulse", r"measure = 'pulse' needs anisotropy = 'isotropic'"),
    ("anisotropy", "orthorhombic", r"anisotropy must be one of ti, isotropic"),
    ("full_sample", "voxels", r"full_sample must be one of voxel, lattice; got 'voxels'"),
    ("compaction", "squeeze", r"compaction must be one of reconstruct, hertz"),
    ("cement_history", "old", r"cement_history must be one of grown, fresh"),
    ("trust_threshold", 1.5, r"trust_threshold must lie in \(0, 1\); got 1.5"),
    ("fall_stiffness_factor", 0.0, r"fall_stiffness_factor must lie in \(0, 1\]; got 0.0"),
    ("size", [3.0, 4.5, 8.0], r"size \[3.0, 4.5, 8.0\]: the cement lattice needs the box's "
                              r"width in y a whole multiple of its width in x"),
    ("size", [3.0, 3.0, 4.0], r"size: the height must be at least 5"),
    ("resolution_check", 2.5, r"resolution_check must be 0 or lie in \[1, 2\); got 2.5"),
    ("samples", 0, r"samples must lie in \[1, 50\]"),
    ("radius_spread", 1.0, r"radius_spread must lie in \[0, 1\)"),
])
def test_a_bad_key_is_refused_before_settling_naming_it(tmp_path, no_settling, key, value,
                                                        message):
    with pytest.raises(ValueError, match=r"^scene section \[models.md\]: " + message):
        run_scene(scene(tmp_path, **{key: value}))


def test_slab_too_thick_for_four_slabs_is_refused_before_settling(tmp_path, no_settling):
    """Hertzian compaction (porosity near 0.37): a pack settled to 8 diameters at a porosity of
    0.4 is 8 x 0.6 / 0.63 = 7.62 diameters tall, 3 slabs of 2 diameters, 4 of 1.9."""
    with pytest.raises(ValueError, match=r"slab = 2 grain diameters is too thick: the "
                                         r"compacted sample, about 7.62 diameters tall .* "
                                         r"holds 3 slab\(s\).* give slab <= 1.9"):
        run_scene(scene(tmp_path, slab=2.0, compaction="hertz"))
    with pytest.raises(Settled):
        run_scene(scene(tmp_path, slab=1.9, compaction="hertz"))


def test_a_lattice_too_large_is_refused_with_its_estimate(tmp_path, no_settling):
    """Omega 40 on the default box of 4 x 4 x 12 diameters (radius spread 0.1, mean radius
    0.95 R): 192 (2 x 40 / 0.95)^3 = 1.147e8 cells, 40 GB at 350 bytes per cell; the largest
    resolution under 1e7 cells is 0.95 / 2 (1e7 / 192)^(1/3) = 17.7."""
    with pytest.raises(ValueError, match=r"resolution = 40 on a box of \[4.0, 4.0, 12.0\] "
                                         r"diameters is a cement lattice of about 1.15e\+08 "
                                         r"cells per member.* about 40.1 GB .* give "
                                         r"resolution <= 17.7"):
        run_scene(scene(tmp_path, resolution=40.0, size=[4.0, 4.0, 12.0]))


def test_count_spreads_the_md_depths_below_the_surface():
    """41 profile depths 0-4000 m, loaded from 100 m (40 of them): count = 3 takes the loaded
    depths at positions round(39 k / 3), k = 1, 2, 3, of the loaded ones: 13, 26, 39, the
    profile depths 1400, 2700 and 4000 m; the default count is 3; count = 40 takes them all."""
    from rockcem._md_backend import md_depth_indices

    depth = np.arange(0.0, 4001.0, 100.0)
    stress = depth * 0.01
    pick = md_depth_indices(depth, stress, {"depths": None, "count": 3})
    assert depth[pick].tolist() == [1400.0, 2700.0, 4000.0]
    assert md_depth_indices(depth, stress, {"depths": None, "count": None}).tolist() == \
        pick.tolist()
    assert depth[md_depth_indices(depth, stress, {"depths": None, "count": 1})].tolist() == \
        [4000.0]
    assert md_depth_indices(depth, stress, {"depths": None, "count": 40}).tolist() == \
        list(range(1, 41))
    for bad in (0, 41):
        with pytest.raises(ValueError, match=r"count must lie in \[1, 40\]"):
            md_depth_indices(depth, stress, {"depths": None, "count": bad})


def test_count_reaches_the_md_run(tmp_path, no_settling, monkeypatch):
    """A scene with ``count`` hands carry_down the stresses of those depths."""
    import md.along_depth

    seen = {}
    real = md.along_depth.carry_down

    def spy(max_stress, cement_fraction, **kw):
        seen["n"] = len(max_stress)
        return real(max_stress, cement_fraction, **kw)

    monkeypatch.setattr(md.along_depth, "carry_down", spy)
    table = scene(tmp_path).sections["models.md"] | {"depths": None, "count": 4}
    s = scene_from_dict({"name": "keys", "lithology": "sandstone",
                         "path": {"max_depth": 3000.0, "depth_step": 100.0},
                         "models": {"md": {k: v for k, v in table.items() if v is not None}}})
    with pytest.raises(Settled):
        run_scene(s)
    assert seen["n"] == 4


# ----------------------------------------------------------------------------- stage folder
SCENE = ('name = "stages"\nlithology = "sandstone"\n[path]\nmax_depth = 2000.0\n'
         '[models.md]\ncount = 1\nsize = [3.0, 3.0, 8.0]\n{extra}\n')


def test_the_stage_folder_follows_o(tmp_path, capsys, monkeypatch):
    import rockcem._md_backend as backend

    seen = {}

    def md_model(*args, workdir, **kw):
        seen["workdir"] = workdir
        raise ValueError("stop here")

    monkeypatch.setattr(backend, "md_model", md_model)
    monkeypatch.chdir(tmp_path)
    (tmp_path / "s.toml").write_text(SCENE.format(extra=""))
    assert cli.main(["run", "s.toml", "-o", "sub/out.nc", "-q"]) == 2
    assert seen["workdir"] == Path("sub/out_md_work")


@pytest.mark.parametrize("workdir, message", [
    ("out.nc", "models.md.workdir 'out.nc' is the output file"),
    ("a_file", "models.md.workdir 'a_file' is a file: it must be a folder"),
    ("a_file/md", "models.md.workdir 'a_file/md' lies under the file a_file"),
])
def test_a_workdir_that_cannot_be_a_folder_is_refused_at_the_start(tmp_path, capsys,
                                                                   monkeypatch, workdir,
                                                                   message):
    import rockcem._md_backend as backend

    def md_model(*args, **kw):
        raise AssertionError("the run started")

    monkeypatch.setattr(backend, "md_model", md_model)
    monkeypatch.chdir(tmp_path)
    (tmp_path / "a_file").write_text("x")
    (tmp_path / "s.toml").write_text(SCENE.format(extra=f'workdir = "{workdir}"'))
    assert cli.main(["run", "s.toml", "-o", "out.nc", "-q"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and message in err[0]


def test_a_workdir_that_is_a_file_is_refused_from_python(tmp_path, no_settling):
    (tmp_path / "f").write_text("x")
    with pytest.raises(ValueError, match=r"\[models.md\]: workdir '.*f' is a file"):
        run_scene(scene(tmp_path, workdir=str(tmp_path / "f")))


# ----------------------------------------------------------------------------- stage files
def member_file(path, key, drop=()):
    from md.along_depth import _member_variables

    xr.Dataset({v: ((), 1.0) for v in _member_variables() if v not in drop},
               attrs={"options_key": key}).to_netcdf(path, engine="netcdf4")
    return path


def test_a_readable_stage_file_is_read_back(tmp_path):
    from md.along_depth import _member_variables, _saved

    path = member_file(tmp_path / "m.nc", "k1")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        done = _saved(path, "k1", _member_variables())
        assert _saved(path, "other", _member_variables()) is None      # other options
    assert float(done["p_modulus"]) == 1.0


@pytest.mark.parametrize("damage", ["empty", "truncated", "missing"])
def test_a_damaged_stage_file_is_redone_with_a_warning_naming_it(tmp_path, damage):
    from md.along_depth import StageFileWarning, _member_variables, _saved

    path = member_file(tmp_path / "m.nc", "k1", drop=("shear_modulus",) if damage == "missing"
                       else ())
    if damage == "empty":
        path.write_bytes(b"")
    elif damage == "truncated":
        path.write_bytes(path.read_bytes()[:200])
    with pytest.warns(StageFileWarning, match=rf"MD stage file {path} cannot be read .*: that "
                                              rf"stage is redone"):
        assert _saved(path, "k1", _member_variables()) is None


def test_a_folder_in_place_of_a_stage_file_is_named(tmp_path):
    from md.along_depth import _saved

    (tmp_path / "m.nc").mkdir()
    with pytest.raises(ValueError, match=r"MD stage file .*m.nc is a folder: remove it"):
        _saved(tmp_path / "m.nc", "k1")


def test_a_damaged_pack_stage_file_is_redone(tmp_path):
    from md.along_depth import StageFileWarning, _saved_pack

    (tmp_path / "compact.nc").write_bytes(b"CDF\x01 cut short")
    with pytest.warns(StageFileWarning, match=r"compact.nc cannot be read"):
        assert _saved_pack(tmp_path / "compact.nc", "k") is None
