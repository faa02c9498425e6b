"""The MD scene's output file reads as CF and keeps the pulse test's error terms.

The Dataset builder is fed a small hand-made set of pulse results, so the check costs no MD
run (a run of the shipped scene takes minutes).
"""

import numpy as np
import pytest

from md.experiment import _scene_dataset, md_scene_from_dict

xr = pytest.importorskip("xarray")
netCDF4 = pytest.importorskip("netCDF4")


def _scene(**md):
    return md_scene_from_dict({"name": "tiny", "md": {"samples": ["loose", "compacted"],
                                                      "cements": ["hard"],
                                                      "schemes": ["contact", "pendular"],
                                                      "saturations": [0.0, 0.1], **md}})


def _pulses(scene):
    p = scene["md"]
    shape = (len(p["samples"]), len(p["cements"]), len(p["schemes"]), len(p["saturations"]))
    v = np.linspace(1500.0, 3000.0, np.prod(shape)).reshape(shape)     # m/s
    dims = ("sample", "cement", "scheme", "saturation")
    data = {"velocity": v, "velocity_error": 0.05 * v, "velocity_error_half_slab": 0.1 * v,
            "velocity_fit": 1.01 * v, "velocity_static": 1.1 * v,
            "density": np.full(shape, 1650.0)}
    return xr.Dataset({k: (dims, a) for k, a in data.items()},
                      coords={"sample": p["samples"], "cement": p["cements"],
                              "scheme": p["schemes"], "saturation": p["saturations"]})


def test_md_scene_dataset_units_errors_and_cf(tmp_path):
    cf_xarray = pytest.importorskip("cf_xarray.units")
    scene = _scene()
    pulses = _pulses(scene)
    out = _scene_dataset(scene, pulses, {"porosity_uncemented": [0.40, 0.38],
                                         "coordination_number": [4.5, 5.6],
                                         "stress": [0.01, 10.0], "stress_mean": [0.007, 6.8]})
    # SI pulse results become km/s and g/cm3; both eq. 11 errors are kept side by side.
    np.testing.assert_allclose(out.vp.values, pulses.velocity.values / 1e3, rtol=1e-15)
    np.testing.assert_allclose(out.vp_error_half_slab / out.vp_error, 2.0, rtol=1e-12)
    np.testing.assert_allclose(out.density, 1.65, rtol=1e-15)
    np.testing.assert_allclose(out.porosity.sel(sample="compacted"), 0.38 * np.array([1, 0.9]))
    assert out.attrs["interface"] == "facet" and out.attrs["Conventions"].startswith("CF-")
    path = tmp_path / "md.nc"
    out.to_netcdf(path)
    back = xr.load_dataset(path)
    for name, var in back.variables.items():
        assert var.attrs.get("long_name"), name
        if var.dtype.kind not in "OSU":
            cf_xarray.units.Unit(var.attrs["units"])          # UDUNITS-parseable
    with netCDF4.Dataset(path) as nc:
        for name in nc.dimensions:
            assert "_FillValue" not in nc.variables[name].ncattrs(), name


@pytest.mark.parametrize("md, message", [
    ({"interface": "cell"}, r"md.interface must be 'facet', 'patch' or 'paper'"),
    ({"schemes": ["pendulum"]}, r"md.schemes has 'pendulum'; valid: .*pendular"),
    ({"saturations": [0.0, 0.1, 0.1]}, r"md.saturations lists 0.1 more than once"),
    ({"cements": ["hard", "hard"]}, r"md.cements lists 'hard' more than once"),
    ({"seed": -1}, r"md.seed must be an integer >= 0"),
])
def test_md_scene_bad_interface_or_scheme(md, message):
    with pytest.raises(ValueError, match=message):
        _scene(**md)


def test_md_scene_dataset_resolution_error_is_first_order_richardson():
    scene = _scene(resolution=8.0, resolution_check=6.0)
    pulses = _pulses(scene)
    pulses["velocity_check"] = pulses.velocity - 300.0          # m/s below at the coarse Omega
    pulses["wall_time"] = xr.full_like(pulses.velocity, 2.0)
    out = _scene_dataset(scene, pulses, {"porosity_uncemented": [0.40, 0.38],
                                         "coordination_number": [4.5, 5.6],
                                         "stress": [0.01, 10.0], "stress_mean": [0.007, 6.8]},
                         member_seconds=12.0)
    # v(inf) - v(8) = (v(8) - v(6)) / (8/6 - 1) = 3 * 0.3 km/s at order 1.
    np.testing.assert_allclose(out.vp_error_resolution, 0.9, rtol=1e-12)
    np.testing.assert_allclose(out.vp - out.vp_resolution_check, 0.3, rtol=1e-12)
    assert out.wall_time.attrs["units"] == "s" and out.attrs["member_wall_time_s"] == 12.0


@pytest.mark.parametrize("md, message", [
    ({"resolution": 8.0, "resolution_check": 8.0}, r"md.resolution_check must be 0 \(none\) or "
                                                   r"lie in \[1, resolution = 8\)"),
    ({"resolution_check": 0.5}, r"md.resolution_check"),
])
def test_md_scene_bad_resolution_check(md, message):
    with pytest.raises(ValueError, match=message):
        _scene(**md)


def _stage(path, member, params, pack_id):
    from md.experiment import _PULSE_VARIABLES

    values = {v: ((), 2000.0) for v in (*_PULSE_VARIABLES.values(), "wall_time")}
    path.parent.mkdir(parents=True, exist_ok=True)
    xr.Dataset(values, attrs=member.attrs(params, pack_id)).to_netcdf(path)


@pytest.mark.parametrize("change", [{}, {"resolution": 6.0}, {"wave": "s"},
                                    {"time_step_factor": 0.25}, {"seed": 1},
                                    {"interface": "paper"}, {"pack": "other"}])
def test_pulse_stage_file_redone_when_the_scene_changes(tmp_path, change):
    from md.experiment import _load_member, _Member

    p = _scene()["md"]
    cemented = _Member.of("loose", "hard", "contact", 0.1, p["resolution"])
    bare = _Member.of("loose", "hard", "contact", 0.0, p["resolution"])
    for m in (cemented, bare):
        _stage(m.file(tmp_path), m, p, "pack-a")
    change = dict(change)
    pack = "pack-b" if change.pop("pack", None) else "pack-a"
    now = {**p, **change}
    again = _Member.of("loose", "hard", "contact", 0.1, now["resolution"])
    done = _load_member(again.file(tmp_path), again.attrs(now, pack))
    if not change and pack == "pack-a":          # the same scene resumes from the file
        assert done["velocity"] == 2000.0
    else:                                        # another Omega, wave, ..., pack: redone
        assert done is None
    # The uncemented member is shared by every cement, scheme and resolution: only the wave,
    # the time step and the pack make it stale.
    bare_now = _Member.of("loose", "soft", "pendular", 0.0, now["resolution"])
    assert bare_now == bare and bare_now.file(tmp_path) == bare.file(tmp_path)
    stale = pack != "pack-a" or "wave" in change or "time_step_factor" in change
    assert (_load_member(bare_now.file(tmp_path), bare_now.attrs(now, pack)) is None) == stale


def test_committed_full_study_has_the_scene_schema_and_its_scene():
    """benchmarks/results/garcia_medina_full.nc (the full-size study, an hour of MD) is the
    output of the shipped scene as it is now: same keys in its attributes, CF units and long
    names on every variable, the four output dimensions, finite velocities and errors."""
    import json
    from pathlib import Path

    from cf_xarray.units import units as udunits

    from rockcem.scene import read_scene_toml

    path = Path(__file__).resolve().parents[2] / "benchmarks" / "results" / "garcia_medina_full.nc"
    if not path.exists():
        pytest.skip("no committed study file in this checkout")
    ds = xr.load_dataset(path)
    scene = md_scene_from_dict(read_scene_toml("garcia_medina_full")[0])
    assert json.loads(ds.attrs["scene_json"])["md"] == scene["md"]
    assert ds.vp.dims == ("sample", "cement", "scheme", "saturation")
    assert list(ds.saturation.values) == scene["md"]["saturations"]
    for name, var in ds.variables.items():
        assert var.attrs.get("long_name"), name
        if var.dtype.kind not in "OSU":
            udunits.Unit(var.attrs["units"])
    for name in ("vp", "vp_error", "vp_static", "vp_error_resolution", "vp_resolution_check"):
        assert np.all(np.isfinite(ds[name])) and np.all(ds[name] >= 0), name
    # The uncemented pack is one pulse test per sample, shared by every cement and scheme,
    # with no resolution error (it has no cement lattice).
    bare = ds.vp.sel(saturation=0.0)
    assert np.all(bare == bare.isel(cement=0, scheme=0))
    assert np.all(ds.vp_error_resolution.sel(saturation=0.0) == 0)
    assert 25 < float(ds.stress.sel(sample="compacted")) < 40           # MPa, target 30
