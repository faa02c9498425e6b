"""Scenes: schema validation, the runner, netCDF output, sweeps and the paper's statements."""

import os
import subprocess
import sys

import numpy as np
import pytest
import xarray as xr

from rockcem.scene import load_scene, run_scene, scene_from_dict, shipped_scenes, write_dataset

SANDSTONE = {"name": "t", "lithology": "sandstone",
             "path": {"max_depth": 4000.0, "depth_step": 100.0},
             "models": {"hs_gassmann": {}, "patchy_cement": {}}}


def coarse(name, step=50.0):
    """A shipped scene at a coarser depth step, to keep the tests fast."""
    return load_scene(name).replace(**{"path.depth_step": step})


@pytest.mark.parametrize("name", sorted(shipped_scenes()))
def test_shipped_scenes_validate(name):
    from rockcem.scene import read_scene_toml

    raw, _ = read_scene_toml(name)
    if "md" in raw:                               # an MD scene, validated by the md engine
        from md.experiment import md_scene_from_dict

        assert md_scene_from_dict(raw)["name"] == name
        with pytest.raises(ValueError, match="MD scene"):
            load_scene(name)
        return
    s = load_scene(name)
    assert s.name == name and s.outputs


# --- the paper's statements ---------------------------------------------------------------------
def test_carcione2022_sandstone_statements():
    ds = run_scene(coarse("carcione2022_sandstone"))
    assert list(ds.model.values) == ["hs_gassmann", "self_consistent", "generalized_gassmann",
                                     "patchy_cement"]
    # Velocities and density increase with depth (Sect. 6.2, Fig. 16).
    assert np.all(np.diff(ds.density) >= -1e-12)
    assert np.all(ds.vp.diff("depth") > -1e-9) and np.all(ds.vs.diff("depth") > -1e-9)
    # Models 1 and 3 nearly coincide; all models within a few hundred m/s.
    m1, m3 = ds.vp.sel(model="hs_gassmann"), ds.vp.sel(model="generalized_gassmann")
    assert float(abs(m1 - m3).max()) < 0.02
    assert float((ds.vp.max("model") - ds.vp.min("model")).max()) < 0.5


def test_carcione2022_shale_statements():
    ds = run_scene(coarse("carcione2022_shale"))
    assert ds.sizes["gradient"] == 2
    assert np.all(ds.vp.diff("depth") > 0) and np.all(ds.density.diff("depth") > 0)
    m1 = ds.vp.sel(model="hs_gassmann")
    m3 = ds.vp.sel(model="generalized_gassmann")
    assert float(abs(m1 - m3).max()) < 0.05
    # Lower gradient: more smectite, lower velocities (Fig. 12).
    deep = ds.depth > 1000
    lo, hi = ds.sel(gradient=20.0), ds.sel(gradient=30.0)
    assert np.all((lo.smectite_fraction > hi.smectite_fraction)[deep.values])
    assert np.all((lo.vp < hi.vp).values[:, deep.values])


def test_carcione2022_fig18_gradients_and_fig19_cement_location():
    ds = run_scene(coarse("carcione2022_sandstone_gradients"))
    lo, hi = ds.sel(gradient=20.0), ds.sel(gradient=30.0)
    assert np.all((lo.vp <= hi.vp + 1e-9).values)
    loc = run_scene(coarse("carcione2022_sandstone_cement_location"))
    diff = abs(loc.vp.sel(scheme=1) - loc.vp.sel(scheme=2)) / loc.vp.sel(scheme=1)
    assert float(diff.max()) < 0.08            # "the differences are minimal in practice"


def test_carcione2022_fig15_heating_rates():
    ds = run_scene(coarse("carcione2022_sandstone_heating_rates", 100.0))
    c = ds.cement_fraction.sel(depth=3000.0)
    assert float(c.sel(heating_rate=0.4)) > float(c.sel(heating_rate=1.2)) \
        > float(c.sel(heating_rate=2.0))
    assert float(ds.burial_time.sel(depth=3000.0, heating_rate=0.4)) == pytest.approx(225.0)


# --- output -------------------------------------------------------------------------------------
def test_netcdf_round_trip(tmp_path):
    ds = run_scene(scene_from_dict(SANDSTONE))
    path = write_dataset(ds, tmp_path / "out.nc")
    back = xr.load_dataset(path, engine="netcdf4")
    xr.testing.assert_identical(ds, back)
    assert back.attrs["Conventions"].startswith("CF")
    assert "lithology" in back.attrs["scene_toml"]
    assert back.vp.attrs["units"] == "km s-1" and back.depth.attrs["positive"] == "down"
    assert back.burial_time.attrs["units"] == "Myr"
    again = scene_from_dict(__import__("tomllib").loads(back.attrs["scene_toml"]))
    assert again.sections == scene_from_dict(SANDSTONE).sections


def test_write_is_atomic(tmp_path, monkeypatch):
    target = tmp_path / "out.nc"
    target.write_bytes(b"previous result")
    ds = run_scene(scene_from_dict(SANDSTONE))

    def broken(self, path, **kw):
        with open(path, "wb") as fh:
            fh.write(b"half")
        raise OSError("disk full")

    monkeypatch.setattr(xr.Dataset, "to_netcdf", broken)
    with pytest.raises(OSError):
        write_dataset(ds, target)
    assert target.read_bytes() == b"previous result"
    assert os.listdir(tmp_path) == ["out.nc"]


def test_sweep_dimensions_and_plotting():
    import matplotlib

    matplotlib.use("Agg")
    raw = dict(SANDSTONE, sweep={"path.gradient": [20.0, 25.0, 30.0],
                                 "models.patchy_cement.delta": [40.0, 100.0]})
    ds = run_scene(scene_from_dict(raw))
    assert dict(ds.sizes) == {"depth": 41, "model": 2, "gradient": 3, "delta": 2}
    one = run_scene(scene_from_dict(dict(SANDSTONE, path={**SANDSTONE["path"], "gradient": 25.0},
                                         models={"patchy_cement": {"delta": 40.0}})))
    np.testing.assert_allclose(ds.vp.sel(gradient=25.0, delta=40.0, model="patchy_cement"),
                               one.vp.sel(model="patchy_cement"), rtol=1e-13)
    ds.vp.sel(model="hs_gassmann", gradient=20.0, delta=40.0).plot(y="depth", yincrease=False)


# --- compute only what is asked -----------------------------------------------------------------
def test_shale_scene_never_runs_cement_kinetics(monkeypatch):
    import burial

    def forbidden(*a, **k):
        raise AssertionError("quartz cement kinetics called by a shale scene")

    monkeypatch.setattr(burial, "quartz_cement", forbidden)
    ds = run_scene(coarse("carcione2022_shale", 200.0))
    assert "vp" in ds


def test_one_model_asked_one_model_computed(monkeypatch):
    from rockcem import models

    called = []
    for name in ("hs_gassmann", "self_consistent_model", "generalized_gassmann_model",
                 "patchy_cement_model"):
        fn = getattr(models, name)
        monkeypatch.setattr(models, name,
                            lambda *a, _f=fn, _n=name, **k: called.append(_n) or _f(*a, **k))
    ds = run_scene(scene_from_dict(dict(SANDSTONE, models={"hs_gassmann": {}})))
    assert called == ["hs_gassmann"] and list(ds.model.values) == ["hs_gassmann"]
    called.clear()
    ds = run_scene(scene_from_dict(dict(SANDSTONE, outputs=["temperature"])))
    assert called == [] and list(ds.data_vars) == ["temperature"]


def test_scene_run_imports_no_numba():
    code = ("import sys; from rockcem.scene import load_scene, run_scene; "
            "run_scene(load_scene('carcione2022_sandstone').replace(**{'path.depth_step': 500.0}));"
            " print('numba' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


# --- bad scenes ---------------------------------------------------------------------------------
BAD = [
    ({"litology": "sandstone"}, "did you mean 'lithology'"),
    ({"path": {"gradiant": 30.0}}, "did you mean 'gradient'"),
    ({"path": {"gradient": "thirty"}}, "path.gradient must be a number"),
    ({"path": {"gradient": -30.0}}, "gradient"),
    ({"materials": {"grain": "quarz"}}, "did you mean 'quartz'"),
    ({"models": {"hs_gasmann": {}}}, "did you mean 'hs_gassmann'"),
    ({"models": {"self_consistent": {}}}, "aspect_ratio is required"),
    ({"outputs": ["vp", "porosty"]}, "did you mean 'porosity'"),
    ({"lithology": "limestone"}, "sandstone' or 'shale"),
    ({"sweep": {"path.gradiant": [20.0]}}, "did you mean 'path.gradient'"),
    ({"sandstone": {"grain_size": 0.0}}, "grain_size"),
    ({"name": None}, "required"),
    # issue 24: silently ignored or empty before
    ({"path": {"heating_rate": 1.2, "sedimentation_rate": 40.0}}, "both given"),
    ({"path": {"heating_rate": 1.2}, "sweep": {"path.sedimentation_rate": [20.0, 40.0]}},
     "both given"),
    ({"outputs": []}, "outputs must name at least one variable"),
    ({"output": ""}, "output must name a file"),
]


@pytest.mark.parametrize("change,message", BAD)
def test_bad_scene(change, message, tmp_path, run_cli):
    raw = {**SANDSTONE, **change}
    raw = {k: v for k, v in raw.items() if v is not None}
    if "litology" in change:
        raw.pop("lithology")
    with pytest.raises(ValueError, match=message):
        run_scene(scene_from_dict(raw))
    # From the command line: exit code 2, one line, no traceback, no output file.
    scene_file = tmp_path / "bad.toml"
    from rockcem.scene import _to_toml

    scene_file.write_text(_to_toml(raw))
    out = run_cli(["run", str(scene_file), "-q"], tmp_path)
    assert out.returncode == 2
    assert out.stderr.count("\n") == 1 and "Traceback" not in out.stderr
    assert sorted(os.listdir(tmp_path)) == ["bad.toml"]


def test_not_toml(tmp_path):
    bad = tmp_path / "x.toml"
    bad.write_text("name = [unclosed")
    with pytest.raises(ValueError, match="not valid TOML"):
        load_scene(bad)


def test_cli_demo_writes_file_and_figure(tmp_path, run_cli):
    out = run_cli(["demo", "-q"], tmp_path)
    assert out.returncode == 0, out.stderr
    assert (tmp_path / "carcione2022_sandstone.nc").exists()
    ds = xr.load_dataset(tmp_path / "carcione2022_sandstone.nc")
    assert ds.sizes["depth"] == 6001 and ds.sizes["model"] == 4


def test_cli_run_output_option_and_scenes(tmp_path, run_cli):
    out = run_cli(["run", "carcione2022_sandstone_heating_rates", "-o", "h.nc"], tmp_path)
    assert out.returncode == 0, out.stderr
    assert "wrote h.nc" in out.stdout and (tmp_path / "h.nc").exists()
    listing = run_cli(["scenes"], tmp_path)
    assert all(name in listing.stdout for name in shipped_scenes())


def test_sweep_on_a_real_local_dask_cluster():
    """A sweep run on a dask.distributed LocalCluster equals the serial run."""
    pytest.importorskip("dask.distributed")
    raw = dict(SANDSTONE, sweep={"path.gradient": [20.0, 30.0], "sandstone.grain_size": [0.2, 0.4]})
    scene = scene_from_dict(raw)
    serial = run_scene(scene)
    parallel = run_scene(scene, scheduler="local")
    xr.testing.assert_allclose(serial.drop_attrs(), parallel.drop_attrs(), rtol=1e-14)
    assert dict(parallel.sizes) == {"depth": 41, "model": 2, "gradient": 2, "grain_size": 2}


def test_cli_plot(tmp_path, run_cli):
    raw = dict(SANDSTONE, sweep={"path.gradient": [20.0, 30.0]})
    write_dataset(run_scene(scene_from_dict(raw)), tmp_path / "s.nc")
    for kind in ("depth", "vp-porosity", "template"):
        out = run_cli(["plot", "s.nc", "--kind", kind], tmp_path)
        assert out.returncode == 0, out.stderr
        assert (tmp_path / f"s_{kind}.png").stat().st_size > 10_000
    bad = run_cli(["plot", "missing.nc"], tmp_path)
    assert bad.returncode == 2 and "no such file" in bad.stderr


def test_file_opens_with_netcdf4_directly(tmp_path):
    """Tools other than xarray (ncdump, netCDF4-python) see the variables, units and dims."""
    netCDF4 = pytest.importorskip("netCDF4")
    path = write_dataset(run_scene(scene_from_dict(SANDSTONE)), tmp_path / "s.nc")
    with netCDF4.Dataset(path) as nc:
        assert nc.variables["vp"].dimensions == ("model", "depth")
        assert nc.variables["vp"].units == "km s-1"
        assert nc.variables["depth"].positive == "down"
        assert list(nc.variables["model"][:]) == ["hs_gassmann", "patchy_cement"]
        assert nc.getncattr("Conventions").startswith("CF")


# --- calibrated parameters (calibration files) --------------------------------------------------
CALIBRATED = {"coordination_number": 6.0, "delta": 20.0, "contact_cement_limit": 0.03,
              "scheme": 1}


def write_cal(path, parameters=CALIBRATED, **head):
    from rockcem.calibrate import write_calibration

    return write_calibration(path, **{"name": "t", "model": "patchy_cement",
                                      "parameters": parameters,
                                      "uncertainty": {"coordination_number": 0.5},
                                      "misfit": {"vp": 0.02}, **head})


def test_calibrated_scene_applies_and_records_the_calibration(tmp_path):
    import hashlib
    import json

    cal = write_cal(tmp_path / "cal.toml")
    scene = scene_from_dict(dict(SANDSTONE, models={"patchy_cement": {"calibration": str(cal),
                                                                      "f": 0.5}}))
    knobs = scene.sections["models.patchy_cement"]
    assert {k: knobs[k] for k in CALIBRATED} == CALIBRATED and knobs["f"] == 0.5
    ds = run_scene(scene)
    direct = run_scene(scene_from_dict(dict(SANDSTONE, models={"patchy_cement": {
        **CALIBRATED, "f": 0.5}})))
    np.testing.assert_allclose(ds.vp, direct.vp, rtol=1e-14)
    info = json.loads(ds.attrs["calibration_json"])["patchy_cement"]
    assert info["path"] == str(cal.resolve()) and info["name"] == "t"
    assert info["sha256"] == hashlib.sha256(cal.read_bytes()).hexdigest()
    assert info["parameters"]["delta"] == 20.0 and info["misfit"] == {"vp": 0.02}
    assert ds.attrs["calibration"].startswith("patchy_cement: t (")
    assert "calibration" not in direct.attrs
    back = xr.load_dataset(write_dataset(ds, tmp_path / "o.nc"), engine="netcdf4")
    assert back.attrs["calibration_json"] == ds.attrs["calibration_json"]


def test_calibration_path_relative_to_the_scene_file(tmp_path, run_cli):
    folder = tmp_path / "scenes"
    folder.mkdir()
    write_cal(folder / "cal.toml")
    from rockcem.scene import _to_toml

    raw = dict(SANDSTONE, models={"patchy_cement": {"calibration": "cal.toml"}})
    (folder / "s.toml").write_text(_to_toml(raw))
    elsewhere = tmp_path / "run"
    elsewhere.mkdir()
    out = run_cli(["run", str(folder / "s.toml"), "-q", "-o", "s.nc"], elsewhere)
    assert out.returncode == 0, out.stderr
    ds = xr.load_dataset(elsewhere / "s.nc")
    assert str((folder / "cal.toml").resolve()) in ds.attrs["calibration"]
    # A changed copy (replace, sweep members) still finds it.
    scene = load_scene(folder / "s.toml").replace(**{"path.depth_step": 200.0})
    assert scene.sections["models.patchy_cement"]["delta"] == 20.0


BAD_CALIBRATIONS = [
    ("missing", {}, "not found"),
    ("foreign", {"parameters": {**CALIBRATED, "cement_efficiency": 0.5}},
     "'cement_efficiency' of calibration 't'.*not a parameter of model 'patchy_cement'"),
    ("twice", {"scene": {"delta": 40.0}}, "models.patchy_cement.delta is also set by"),
    ("format", {"text": 'format = "other/2"\nmodel = "patchy_cement"\n'}, "format"),
    ("toml", {"text": "format = [unclosed"}, "not valid TOML"),
    ("scheme", {"parameters": {**CALIBRATED, "scheme": 3}}, "scheme"),
    ("empty", {"text": 'format = "rockcem-calibration/1"\nmodel = "patchy_cement"\n'},
     r"\[parameters\]"),
]


@pytest.mark.parametrize("case,change,message", BAD_CALIBRATIONS,
                         ids=[c[0] for c in BAD_CALIBRATIONS])
def test_bad_calibration(case, change, message, tmp_path, run_cli):
    cal = tmp_path / "cal.toml"
    if "text" in change:
        cal.write_text(change["text"])
    elif case == "scheme":                # not writable through write_calibration: hand-edit
        write_cal(cal)
        cal.write_text(cal.read_text().replace("scheme = 1", "scheme = 3"))
    elif case != "missing":
        write_cal(cal, change.get("parameters", CALIBRATED))
    table = {"calibration": str(cal), **change.get("scene", {})}
    raw = dict(SANDSTONE, models={"patchy_cement": table})
    with pytest.raises(ValueError, match=message):
        scene_from_dict(raw)
    from rockcem.scene import _to_toml

    (tmp_path / "bad.toml").write_text(_to_toml(raw))
    out = run_cli(["run", "bad.toml", "-q"], tmp_path)
    assert out.returncode == 2
    assert out.stderr.count("\n") == 1 and "Traceback" not in out.stderr
    assert "calibration" in out.stderr
    assert not (tmp_path / "t.nc").exists()


def test_calibration_only_for_patchy_cement():
    raw = dict(SANDSTONE, models={"hs_gassmann": {"calibration": "x.toml"}})
    with pytest.raises(ValueError, match="unknown scene key models.hs_gassmann.calibration"):
        scene_from_dict(raw)


def test_shipped_calibrated_sandstone():
    """The calibrated sandstone differs from the paper's only in Model 4, whose parameters are
    the shipped calibration's."""
    from rockcem.calibrate import load_calibration

    cal = load_calibration("garcia_medina_compacted_patchy")
    calibrated = run_scene(coarse("carcione2022_sandstone_calibrated", 100.0))
    paper = run_scene(coarse("carcione2022_sandstone", 100.0))
    for m in ("hs_gassmann", "self_consistent", "generalized_gassmann"):
        np.testing.assert_allclose(calibrated.vp.sel(model=m), paper.vp.sel(model=m), rtol=1e-14)
    shallow = calibrated.depth < 3000
    diff = (calibrated.vp - paper.vp).sel(model="patchy_cement").where(shallow, drop=True)
    assert float(diff.max()) < -0.1            # no pre-stress, fewer contacts: a softer frame
    knobs = load_scene("carcione2022_sandstone_calibrated").sections["models.patchy_cement"]
    assert all(knobs[k] == v for k, v in cal["parameters"].items())
    assert "garcia_medina_compacted_patchy" in calibrated.attrs["calibration"]
    # Fitted to the full-size MD study (pendular contact cement, compacted, hard): the patchy
    # frame follows the MD's steep rise and plateau in S_c only to about 23 % rms, and the data
    # do not determine phi_p0, which is held (docs/studies/md_calibration.md).
    assert cal["model"] == "patchy_cement" and 0 < cal["misfit"]["vp"] < 0.3
    assert cal["identifiability"]["held"] == ["contact_cement_limit"]
    assert cal["parameters"]["contact_cement_limit"] == 0.05


def test_sweep_over_calibration_files(tmp_path):
    paths = [str(write_cal(tmp_path / f"c{n:g}.toml", {"coordination_number": n}, name=f"c{n:g}"))
             for n in (5.0, 7.0)]
    raw = dict(SANDSTONE, models={"patchy_cement": {}},
               sweep={"models.patchy_cement.calibration": paths})
    ds = run_scene(scene_from_dict(raw))
    assert list(ds.calibration.values) == paths
    one = run_scene(scene_from_dict(dict(SANDSTONE, models={"patchy_cement": {
        "coordination_number": 7.0}})))
    np.testing.assert_allclose(ds.vp.sel(calibration=paths[1]), one.vp, rtol=1e-14)
    assert "c5" in ds.attrs["calibration"] and "c7" in ds.attrs["calibration"]


def test_calibration_for_another_model_is_refused(tmp_path):
    """A calibration file fitted for contact_cement cannot fill [models.patchy_cement]."""
    from pathlib import Path

    from rockcem.calibrate import write_calibration

    write_calibration(tmp_path / "cct.toml", name="cct", model="contact_cement",
                      parameters={"coordination_number": 6.0})
    text = (Path(__file__).parents[1] / "datasets" / "scenes"
            / "carcione2022_sandstone_calibrated.toml").read_text()
    scene = tmp_path / "s.toml"
    scene.write_text(text.replace('calibration = "garcia_medina_compacted_patchy"',
                                  'calibration = "cct.toml"'))
    with pytest.raises(ValueError, match="is for model 'contact_cement', not 'patchy_cement'"):
        load_scene(scene)


def test_sweeping_a_calibrated_parameter_is_refused(tmp_path):
    """A sweep over a key that the scene's calibration file sets fails at load, naming both."""
    from pathlib import Path

    text = (Path(__file__).parents[1] / "datasets" / "scenes"
            / "carcione2022_sandstone_calibrated.toml").read_text()
    scene = tmp_path / "s.toml"
    scene.write_text(text + '\n[sweep]\n"models.patchy_cement.coordination_number" = [6.0, 8.0]\n')
    with pytest.raises(ValueError, match="set by calibration 'garcia_medina_compacted_patchy'"):
        load_scene(scene)


def test_a_sweep_above_max_members_is_refused_before_any_work(tmp_path, run_cli, monkeypatch):
    """Issue 24: a sweep of 10^6 members started a run of days with no word."""
    from rockcem import runner
    from rockcem.scene import MAX_SWEEP_MEMBERS, sweep_size

    raw = {**SANDSTONE, "outputs": ["porosity"],
           "sweep": {"path.gradient": [20.0, 30.0, 40.0], "sandstone.beta": [0.01, 0.02]}}
    scene = scene_from_dict(raw)
    assert sweep_size(scene) == 6 and MAX_SWEEP_MEMBERS >= 1000

    def never(*args, **kwargs):
        raise AssertionError("the sweep ran")

    monkeypatch.setattr(runner, "run", never)
    with pytest.raises(ValueError, match=r"6 members \(3 gradient x 2 beta\), above "
                                         r"max_members = 5; pass max_members=6"):
        run_scene(scene, max_members=5)
    for bad in (0, 2.5, True, "10"):
        with pytest.raises(ValueError, match="max_members must be an integer >= 1"):
            run_scene(scene, max_members=bad)
    monkeypatch.undo()
    assert run_scene(scene, max_members=6)["porosity"].shape[:2] == (3, 2)
    from rockcem.scene import _to_toml

    (tmp_path / "s.toml").write_text(_to_toml(raw))
    out = run_cli(["run", str(tmp_path / "s.toml"), "-q", "--max-members", "5"], tmp_path)
    assert out.returncode == 2 and out.stderr.count("\n") == 1
    assert "--max-members 6" in out.stderr
    assert sorted(os.listdir(tmp_path)) == ["s.toml"]
