"""The seismic join of a stack scene ([seismic]; issue 31): each variable against values
computed here from the layers' own profiles by closed forms."""

import subprocess
import sys

import numpy as np
import pytest
from scipy.integrate import cumulative_trapezoid

from rockcem.scene import run_scene, scene_from_dict, write_dataset

pytestmark = pytest.mark.filterwarnings("ignore::UserWarning")


def _raw(seismic=None, thickness=True, fluids=("brine", "gas")):
    raw = {
        "name": "seal_over_sand",
        "path": {"gradient": 30.0, "sedimentation_rate": 40.0, "surface_temperature": 15.0,
                 "max_depth": 4000.0, "depth_step": 50.0},
        "stack": {"fluids": list(fluids), "reservoir": "reservoir"},
        "fluid": {"model": "batzle_wang", "salinity": 0.05, "saturation": 0.8},
        "layers": [
            {"name": "seal", "scene": "carcione2022_shale", "stand_in": "generalized_gassmann"},
            {"name": "reservoir", "scene": "carcione2022_sandstone"},
        ],
    }
    if fluids == ("brine",):
        del raw["fluid"]["saturation"]
    if thickness:
        raw["layers"][0]["thickness"] = 2000.0
    if seismic is not None:
        raw["seismic"] = seismic
    return raw


@pytest.fixture(scope="module")
def ds():
    return run_scene(scene_from_dict(_raw({"max_angle": 30.0, "angle_step": 5.0,
                                           "frequency": 20.0, "dt": 0.002})))


def _side(ds, layer, name, fluid, model):
    """A layer's value of ``name`` with the model pairing of the stack."""
    m = str(ds["model_of_layer"].sel(layer=layer, model=model).values)
    var = ds[name].sel(layer=layer)
    if "fluid" in var.dims:
        var = var.sel(fluid=fluid)
    if "model" in var.dims:
        var = var.sel(model=m)
    return var.values


def test_normal_incidence_is_the_impedance_contrast(ds):
    for fluid in ("brine", "gas"):
        for model in ds["model"].values:
            z1 = _side(ds, "seal", "vp", fluid, model) * _side(ds, "seal", "density", fluid,
                                                                  model)
            z2 = (_side(ds, "reservoir", "vp", fluid, model)
                  * _side(ds, "reservoir", "density", fluid, model))
            r0 = ds["reflectivity_pp"].sel(interface="seal/reservoir", fluid=fluid,
                                           model=model, angle=0.0).values
            ok = np.isfinite(z1) & np.isfinite(z2)
            assert ok.sum() > 10
            np.testing.assert_allclose(r0[ok], ((z2 - z1) / (z2 + z1))[ok], rtol=0,
                                       atol=1e-13)


def test_intercept_gradient_and_class_follow_shuey_by_hand(ds):
    fluid, model = "gas", "patchy_cement"
    vp1, vs1, r1 = (_side(ds, "seal", n, fluid, model) for n in ("vp", "vs", "density"))
    vp2, vs2, r2 = (_side(ds, "reservoir", n, fluid, model) for n in ("vp", "vs", "density"))
    vp, vs, rho = (vp1 + vp2) / 2, (vs1 + vs2) / 2, (r1 + r2) / 2
    dvp, dvs, drho = vp2 - vp1, vs2 - vs1, r2 - r1
    a = 0.5 * (dvp / vp + drho / rho)                                   # Shuey (1985)
    b = 0.5 * dvp / vp - 2 * (vs / vp) ** 2 * (drho / rho + 2 * dvs / vs)
    sel = dict(interface="seal/reservoir", fluid=fluid, model=model)
    np.testing.assert_allclose(ds["avo_intercept"].sel(**sel).values, a, atol=1e-13)
    np.testing.assert_allclose(ds["avo_gradient"].sel(**sel).values, b, atol=1e-13)
    t = ds["avo_class"].attrs["threshold"]
    want = np.select([(b < 0) & (a >= t), (b < 0) & (a >= 0), (b < 0) & (a > -t), b < 0,
                      a < 0], [1, 2, 3, 4, 5], 0)
    np.testing.assert_array_equal(ds["avo_class"].sel(**sel).values, want)
    assert ds["avo_class"].attrs["flag_meanings"] == "I IIp II III IV"
    np.testing.assert_array_equal(ds["avo_class"].attrs["flag_values"], [1, 2, 3, 4, 5])


def test_seismic_sources_in_the_references(ds):
    refs = ds.attrs["references"]
    for key in ("[Zoeppritz1919]", "[Shuey1985]", "[Ricker1953]", "[Carcione2022]"):
        assert key in refs


def test_angles_and_magnitude(ds):
    np.testing.assert_array_equal(ds["angle"].values, [0, 5, 10, 15, 20, 25, 30])
    r = ds["reflectivity_pp"]
    np.testing.assert_array_less(np.abs(r.values) - 1e-15, ds["reflectivity_pp_magnitude"])
    assert np.isfinite(ds["reflectivity_pp_magnitude"].values).all()


def test_twt_is_twice_the_integral_of_the_slowness(ds):
    depth = ds["depth"].values
    vp = ds["column_vp"].sel(fluid="brine", model="hs_gassmann").values
    want = 2 * cumulative_trapezoid(1.0 / (1000.0 * vp), depth, initial=0.0)
    np.testing.assert_allclose(ds["twt_of_depth"].sel(fluid="brine", model="hs_gassmann"),
                               want, rtol=1e-12, atol=1e-15)


def test_synthetic_peaks_at_the_seal_base(ds):
    """The column's one step (the seal's base at 2000 m) is by far its largest contrast: the
    trace's largest excursion lies within one sample of its time, with the step's sign."""
    sel = dict(fluid="brine", model="hs_gassmann")
    depth = ds["depth"].values
    k = np.searchsorted(depth, 2000.0)                  # first reservoir sample
    twt = ds["twt_of_depth"].sel(**sel).values
    t_step = 0.5 * (twt[k - 1] + twt[k])
    vp, rho = (ds[f"column_{n}"].sel(**sel).values for n in ("vp", "density"))
    r = (vp[k] * rho[k] - vp[k - 1] * rho[k - 1]) / (vp[k] * rho[k] + vp[k - 1] * rho[k - 1])
    trace = ds["synthetic"].sel(**sel)
    peak = int(np.argmax(np.abs(trace.values)))
    assert abs(float(ds["twt"][peak]) - t_step) <= 0.002 + 1e-12
    assert np.sign(trace.values[peak]) == np.sign(r)
    gather = ds["angle_gather"].sel(**sel)
    assert gather.attrs["gather_depth"] == 2000.0
    assert float(ds["gather_twt"].min()) < t_step < float(ds["gather_twt"].max())


def test_file_round_trip(ds, tmp_path):
    import xarray as xr

    path = write_dataset(ds, tmp_path / "stack.nc")
    with xr.open_dataset(path) as back:
        np.testing.assert_array_equal(back["avo_class"].values, ds["avo_class"].values)
        assert back["avo_class"].attrs["flag_meanings"] == "I IIp II III IV"


def test_no_seismic_section_computes_and_imports_none():
    code = ("import sys, warnings; warnings.simplefilter('ignore')\n"
            "from rockcem.scene import run_scene, scene_from_dict\n"
            "import tests.test_stack_seismic as t\n"
            "ds = run_scene(scene_from_dict(t._raw()))\n"
            "assert 'reflectivity_pp' not in ds and 'synthetic' not in ds\n"
            "assert 'rockcem.reflectivity' not in sys.modules\n"
            "assert 'rockcem.synthetics' not in sys.modules\n")
    import pathlib
    root = pathlib.Path(__file__).resolve().parents[1]
    subprocess.run([sys.executable, "-c", code], check=True, cwd=root)


def test_without_column_no_synthetics():
    ds = run_scene(scene_from_dict(_raw({"max_angle": 10.0}, thickness=False,
                                        fluids=("brine",))))
    assert "avo_class" in ds and "synthetic" not in ds and "twt" not in ds.coords


@pytest.mark.parametrize("seismic, match", [
    ({"max_angle": 90.0}, r"seismic.max_angle must be in \(0, 90\)"),
    ({"angle_step": 0.0}, r"seismic.angle_step must be > 0"),
    ({"angle_step": 50.0}, r"seismic.angle_step \(50\) must not exceed"),
    ({"frequency": -5.0}, r"seismic.frequency must be > 0"),
    ({"dt": 0.5}, r"seismic.dt must lie in"),
    ({"class_threshold": 1.5}, r"seismic.class_threshold must lie in \(0, 1\)"),
    ({"max_angel": 30.0}, r"max_angel"),
])
def test_bad_keys_named(seismic, match):
    with pytest.raises(ValueError, match=match):
        scene_from_dict(_raw(seismic))


def test_gather_depth_needs_the_column():
    with pytest.raises(ValueError, match="gather_depth needs the synthetic column"):
        scene_from_dict(_raw({"gather_depth": 1000.0}, thickness=False))


def _step_well(tmp_path, z_step=2000.0):
    z = np.arange(1800.0, 2200.0 + 1e-9, 5.0)
    above = z < z_step
    vp = np.where(above, 2.8, 3.2)
    vs = np.where(above, 1.3, 1.9)
    rho = np.where(above, 2.35, 2.2)
    path = tmp_path / "step.csv"
    lines = ["DEPT (m),VP (km/s),VS (km/s),RHOB (g/cm3)"]
    lines += [f"{a},{b},{c},{d}" for a, b, c, d in zip(z, vp, vs, rho)]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_well_interface_by_hand(tmp_path):
    from rockcem._well_avo import well_interface_avo
    from rockcem.wells import read_well

    well = read_well(_step_well(tmp_path))
    w = well_interface_avo(well, 2000.0, window=50.0)
    np.testing.assert_allclose([w.vp1, w.vs1, w.rho1, w.vp2, w.vs2, w.rho2],
                               [2.8, 1.3, 2.35, 3.2, 1.9, 2.2], rtol=1e-12)
    assert (w.n_above, w.n_below) == (10, 10)               # 1950-1995 and 2005-2050
    vp, vs, rho = 3.0, 1.6, 2.275
    a = 0.5 * (0.4 / vp - 0.15 / rho)
    b = 0.5 * 0.4 / vp - 2 * (vs / vp) ** 2 * (-0.15 / rho + 2 * 0.6 / vs)
    assert w.intercept == pytest.approx(a, abs=1e-14)
    assert w.gradient == pytest.approx(b, abs=1e-14)
    assert a > 0.03 and b < 0 and w.avo_class == "I"      # A 0.034, B -0.66: class I
    with pytest.raises(ValueError, match="window below the interface at 2200 m"):
        well_interface_avo(well, 2200.0, window=50.0)
    with pytest.raises(ValueError, match="window must be > 0"):
        well_interface_avo(well, 2000.0, window=0.0)


def test_compare_interface_cli(tmp_path, ds, capsys):
    from rockcem.cli import main

    nc = write_dataset(ds, tmp_path / "stack.nc")
    well = _step_well(tmp_path)
    assert main(["compare", str(nc), "--well", str(well), "--interface", "2000",
                 "--window", "50", "-q"]) == 0
    out = capsys.readouterr().out
    assert "AVO of the interface at 2000 m" in out and "class" in out
    assert out.count("patchy_cement") == 2              # one row per fluid
    assert main(["compare", str(nc), "--well", str(well), "--interface", "2000",
                 "--intervals", "1900", "2100"]) == 2
    assert "do not go together" in capsys.readouterr().err


def test_run_summary_of_a_stack(tmp_path, capsys):
    """The summary names the layers and fluids and tabulates the class at whole kilometres,
    each cell the class name of the Dataset's code there."""
    import tomllib

    from rockcem.cli import main

    raw = _raw({"max_angle": 20.0})
    scene = tmp_path / "stack.toml"
    from rockcem.scene import scene_from_dict as load

    text = load(raw).text
    scene.write_text(text)
    out_nc = tmp_path / "stack.nc"
    assert main(["run", str(scene), "-o", str(out_nc)]) == 0
    out = capsys.readouterr().out
    assert "layers: seal (shale), reservoir (sandstone)" in out
    assert "AVO class of seal/reservoir at 1000, 2000, 3000, 4000 m:" in out
    import xarray as xr

    with xr.open_dataset(out_nc) as ds:
        names = ds["avo_class"].attrs["flag_meanings"].split()
        codes = ds["avo_class"].sel(interface="seal/reservoir", fluid="gas",
                                    model="patchy_cement", depth=[1000, 2000, 3000, 4000])
        want = [names[c - 1] if c else "-" for c in codes.values]
    row = next(line for line in out.splitlines() if line.strip().startswith("gas")
               and "patchy_cement" in line)
    assert row.split()[2:] == want
    assert tomllib.loads(text)["seismic"]["max_angle"] == 20.0


def test_plot_of_a_stack_file_draws_the_avo_charts_by_default(ds, tmp_path):
    from rockcem.cli import main

    nc = write_dataset(ds, tmp_path / "stack.nc")
    assert main(["plot", str(nc)]) == 0
    for part in ("class", "crossplot", "angle"):
        assert (tmp_path / f"stack_avo_{part}.png").is_file()


def test_plot_synthetic_window_and_scale(ds, tmp_path, capsys):
    from rockcem.cli import main

    nc = write_dataset(ds, tmp_path / "stack.nc")
    out = tmp_path / "syn.png"
    assert main(["plot", str(nc), "--kind", "synthetic", "--twt", "1.5", "2.5",
                 "--trace-scale", "-o", str(out)]) == 0
    assert out.is_file()
    assert main(["plot", str(nc), "--kind", "synthetic", "--twt", "2.5", "1.5"]) == 2
    assert "--twt 2.5 1.5: give a window" in capsys.readouterr().err
    assert main(["plot", str(nc), "--kind", "avo", "--twt", "1", "2"]) == 2
    assert "--twt applies to --kind synthetic" in capsys.readouterr().err


def test_synthetic_section_window_draws_only_it(ds):
    from rockcem.plots import synthetic_section

    fig = synthetic_section(ds.sel(twt=slice(1.5, 2.5)), scale="trace")
    lines = [ln for ln in fig.axes[0].get_lines() if str(ln.get_gid()).startswith("trace:")]
    assert lines and all(1.5 - 1e-9 <= ln.get_ydata().min() and ln.get_ydata().max()
                         <= 2.5 + 1e-9 for ln in lines)


MD_KEYS = {"depths": [2500.0], "schemes": ["coating"], "size": [3.0, 3.0, 6.0],
           "resolution": 3.0, "samples": 1}


@pytest.mark.slow
def test_md_gives_the_reservoir_side_at_its_depths(tmp_path):
    """A sandstone layer with the MD backend: at its depth the reservoir's side of the
    interface is the MD member of the same scene run alone (a plain run, its own stage
    folder), the seal's its stand_in; the two fluids share one stage folder (the MD runs
    once)."""
    from rockcem.scene import load_scene

    raw = _raw({"max_angle": 20.0, "angle_step": 10.0})
    raw["path"]["depth_step"] = 500.0
    raw["pressure"] = {"sediment_density": 2.5, "water_density": 1.04}
    raw["layers"][1] = {"name": "reservoir", "scene": "carcione2022_sandstone_md",
                        "stand_in": "patchy_cement",
                        "models": {"patchy_cement": {}, "md": dict(MD_KEYS)}}
    scene = scene_from_dict(raw)
    import dataclasses

    scene = dataclasses.replace(scene, output=str(tmp_path / "stack.nc"))
    ds = run_scene(scene)
    work = sorted(p.name for p in tmp_path.iterdir())
    assert work == ["stack_reservoir_md_work"]
    assert len(list((tmp_path / "stack_reservoir_md_work").iterdir())) == 1

    same = {f"path.{k}": v for k, v in raw["path"].items()}
    same.update({f"fluid.{k}": v for k, v in raw["fluid"].items() if k != "saturation"})
    same.update({"pressure.sediment_density": 2.5, "pressure.water_density": 1.04})
    alone = load_scene("carcione2022_sandstone_md").replace(
        **{f"models.md.{k}": v for k, v in MD_KEYS.items()}, **same)
    alone = dataclasses.replace(alone, output=str(tmp_path / "alone" / "alone.nc"))
    (tmp_path / "alone").mkdir()
    plain = run_scene(alone)
    vp_md = float(plain["vp"].sel(model="md", depth=2500.0))
    sides = ds["reflectivity_pp"].sel(interface="seal/reservoir", fluid="brine", model="md",
                                      depth=2500.0, angle=0.0)
    z1 = float(ds["vp"].sel(layer="seal", fluid="brine", model="generalized_gassmann",
                            depth=2500.0) * ds["density"].sel(layer="seal", fluid="brine",
                                                              depth=2500.0))
    rho2 = float(ds["density"].sel(layer="reservoir", fluid="brine", depth=2500.0))
    z2 = vp_md * rho2
    assert float(ds["vp"].sel(layer="reservoir", fluid="brine", model="md",
                              depth=2500.0)) == pytest.approx(vp_md, rel=1e-12)
    assert float(sides) == pytest.approx((z2 - z1) / (z2 + z1), abs=1e-12)
    assert np.isnan(ds["reflectivity_pp"].sel(model="md", depth=1000.0)).all()


def _ricker_csv(path, f, dt, header=True):
    """A Ricker wavelet written out by hand: (1 - 2 (pi f t)^2) exp(-(pi f t)^2) (Ricker 1953)."""
    n = int(round(6.0 / (np.pi * f) / dt))
    t = np.arange(-n, n + 1) * dt
    a = (1 - 2 * (np.pi * f * t) ** 2) * np.exp(-(np.pi * f * t) ** 2)
    lines = (["time (s),amplitude"] if header else []) + [f"{float(x)!r},{float(y)!r}" for x, y in zip(t, a)]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_a_users_wavelet_from_a_file(tmp_path, ds):
    """A Ricker of 20 Hz given as the user's wavelet (a file) gives the synthetic that the
    built-in 20 Hz Ricker gives."""
    _ricker_csv(tmp_path / "w.csv", 20.0, 0.002)
    raw = _raw({"max_angle": 30.0, "angle_step": 5.0, "dt": 0.002, "wavelet": "w.csv"})
    user = run_scene(scene_from_dict(raw, base_dir=tmp_path))
    np.testing.assert_allclose(user["synthetic"].values, ds["synthetic"].values, rtol=0,
                               atol=1e-9 * float(np.abs(ds["synthetic"]).max()))
    assert "the wavelet of w.csv" in user["synthetic"].attrs["long_name"]


@pytest.mark.parametrize("content, match", [
    (None, "no such file"),
    ("time,amplitude\n0,1\n0.002,0.5\n", "at least 3 rows"),
    ("-0.004,0\n-0.001,1\n0.002,0\n", "sampled at seismic.dt = 0.002 s"),
    ("0.001,0\n0.003,1\n0.005,0\n", "one sample at time 0"),
    ("-0.002,0\n0,x\n0.002,0\n", "not a CSV file of two numeric columns"),
    ("-0.002,0\n0,0\n0.002,0\n", "all zero"),
])
def test_a_bad_wavelet_file_is_refused_by_name(tmp_path, content, match):
    if content is not None:
        (tmp_path / "w.csv").write_text(content)
    raw = _raw({"dt": 0.002, "wavelet": "w.csv"})
    with pytest.raises(ValueError, match=rf"seismic.wavelet = 'w.csv'.*{match}"):
        scene_from_dict(raw, base_dir=tmp_path)


def test_wavelet_and_frequency_together_refused(tmp_path):
    _ricker_csv(tmp_path / "w.csv", 20.0, 0.002)
    with pytest.raises(ValueError, match="seismic.wavelet and seismic.frequency: give one"):
        scene_from_dict(_raw({"wavelet": "w.csv", "frequency": 20.0}), base_dir=tmp_path)
