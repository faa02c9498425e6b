"""Uncertain inputs in a stack of layers (issue 32, item 5): the quantiles of the layers and of
the interface's reflectivity, and the probability of each AVO class along depth.

The checks are independent of the uncertain machinery: a class boundary crossed at a fraction
of the members known in closed form (the uniform input's CDF at the crossing, found by a root
solve of the deterministic stack), the deterministic run's class where the only uncertain
input does not touch the model, and a layer's quantiles against the same layer run as a plain
uncertain scene.
"""

import copy
import warnings

import numpy as np
import pytest
from scipy.optimize import brentq

from rockcem.reflectivity import AVO_CLASSES, AVO_CLASS_CODES
from rockcem.scene import read_scene_toml, run_scene, scene_from_dict

DEPTH_STEP = 100.0
PATH = {"gradient": 30.0, "sedimentation_rate": 40.0, "surface_temperature": 15.0,
        "max_depth": 4000.0, "depth_step": DEPTH_STEP}
PRESSURE = {"sediment_density": 2.5, "water_density": 1.04}


def _stack(uncertain=None, *, reservoir_models=None, path=None):
    """The Carcione et al. (2022) shale over their sandstone, brine (the catalogue water), one
    path; Model 1 in both layers unless the reservoir's models are given (the seal's Model 1
    then stands in for the others)."""
    seal = {"name": "seal", "scene": "carcione2022_shale", "models": {"hs_gassmann": {"A": 3.0}}}
    reservoir = {"name": "reservoir", "scene": "carcione2022_sandstone",
                 "models": reservoir_models or {"hs_gassmann": {"A": 3.0}}}
    if reservoir_models and set(reservoir_models) != {"hs_gassmann"}:
        seal["stand_in"] = "hs_gassmann"
    sampled = [k.partition(".")[2] for k in (uncertain or {}) if k.startswith("path.")]
    raw = {"name": "uncertain_stack",
           "path": {k: v for k, v in (path or PATH).items() if k not in sampled},
           "pressure": dict(PRESSURE),
           "stack": {"fluids": ["brine"], "reservoir": "reservoir"},
           "seismic": {"max_angle": 30.0, "angle_step": 10.0},
           "layers": [seal, reservoir]}
    if uncertain is not None:
        raw["uncertain"] = uncertain
    return raw


def _run(raw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")          # the shallow validity warnings
        return run_scene(scene_from_dict(copy.deepcopy(raw)))


def _labels(ds):
    """Class code -> label of a deterministic stack's ``avo_class``."""
    attrs = ds["avo_class"].attrs
    return {0: "none", **dict(zip(attrs["flag_values"].tolist(),
                                   attrs["flag_meanings"].split()))}


def test_class_probabilities_sum_to_one_over_chunks():
    """300 members (two chunks of 256 and 44): at every interface, fluid, model and depth the
    fractions are multiples of 1/300 in [0, 1] that add up to one; somewhere a depth holds
    members of more than one class."""
    n = 300
    ds = _run(_stack({"samples": n, "seed": 5,
                      "path.gradient": {"distribution": "normal", "mean": 30.0, "sd": 3.0},
                      "layers.reservoir.sandstone.grain_size": {
                          "distribution": "lognormal", "median": 0.3, "sigma": 0.4}}))
    p = ds["avo_class_probability"]
    assert p.dims == ("avo_class", "interface", "fluid", "model", "depth")
    assert [str(c) for c in p["avo_class"].values] == list(AVO_CLASSES) + ["none"]
    np.testing.assert_allclose(p.sum("avo_class"), 1.0, rtol=0, atol=1e-12)
    counts = p.values * n
    np.testing.assert_allclose(counts, np.round(counts), rtol=0, atol=1e-9)
    assert (p.values >= 0).all() and (p.values <= 1).all()
    assert ((p > 0).sum("avo_class") > 1).any()


def test_an_input_that_does_not_touch_a_model_leaves_its_class_certain():
    """The reservoir's bonding pre-stress (Model 4's delta) moves Model 4 only: Model 1's class
    has probability 1 at the deterministic run's class, at every depth."""
    models = {"hs_gassmann": {"A": 3.0}, "patchy_cement": {}}
    fixed = _run(_stack(reservoir_models={"hs_gassmann": {"A": 3.0},
                                          "patchy_cement": {"delta": 100.0}}))
    ds = _run(_stack({"samples": 40, "seed": 1,
                      "layers.reservoir.models.patchy_cement.delta": {
                          "distribution": "uniform", "lower": 20.0, "upper": 180.0}},
                     reservoir_models=models))
    labels = _labels(fixed)
    codes = fixed["avo_class"].sel(model="hs_gassmann").isel(interface=0, fluid=0).values
    p = ds["avo_class_probability"].sel(model="hs_gassmann").isel(interface=0, fluid=0)
    for k, code in enumerate(codes):
        assert p.sel(avo_class=labels[int(code)]).values[k] == 1.0, ds["depth"].values[k]
    # Model 4 does move: the input is live
    p4 = ds["avo_class_probability"].sel(model="patchy_cement").isel(interface=0, fluid=0)
    assert ds["avo_intercept"].sel(model="patchy_cement", quantile=0.9).isel(
        interface=0, fluid=0).values[20] > ds["avo_intercept"].sel(
        model="patchy_cement", quantile=0.1).isel(interface=0, fluid=0).values[20]
    assert (p4 < 1).any()


def test_class_boundary_crossed_at_the_cdf_of_the_root():
    """The reservoir's Krief exponent uniform on [a, b]: the sand's frame, Vp and so the
    interface's intercept A fall as it grows, so class I (A >= t, B < 0) holds for the members
    below the root x* of A(x*) = t, found by a root solve of the deterministic stack. The
    fraction of class I members is then the uniform CDF (x* - a) / (b - a), within 1/N for
    a Latin hypercube (one member in each of N equal strata)."""
    a, b, n, depth = 2.5, 4.0, 64, 2000.0
    t = 0.03

    def deterministic(x):
        raw = _stack()
        raw["layers"][1]["models"]["hs_gassmann"]["A"] = float(x)
        ds = _run(raw).sel(depth=depth).isel(interface=0, fluid=0, model=0)
        return float(ds["avo_intercept"]), float(ds["avo_gradient"])

    assert deterministic(a)[0] > t > deterministic(b)[0]
    root = brentq(lambda x: deterministic(x)[0] - t, a, b, xtol=1e-10)
    assert deterministic(root)[1] < 0 and deterministic(a)[1] < 0       # B < 0: class I
    expected = (root - a) / (b - a)
    assert 0.2 < expected < 0.8
    ds = _run(_stack({"samples": n, "seed": 11,
                      "layers.reservoir.models.hs_gassmann.A": {
                          "distribution": "uniform", "lower": a, "upper": b}},
                     reservoir_models={"hs_gassmann": {}}))
    p = ds["avo_class_probability"].sel(depth=depth).isel(interface=0, fluid=0, model=0)
    assert abs(float(p.sel(avo_class="I")) - expected) <= 1.0 / n + 1e-12
    # the intercept's quantiles are the deterministic intercepts at the exponent's quantiles
    # (A falls with x: quantile q of A is A at the (1 - q) quantile of x), to the LHS's 1/N
    # in probability
    q = ds["avo_intercept"].sel(depth=depth).isel(interface=0, fluid=0, model=0)
    for level in (0.1, 0.9):
        low = deterministic(a + (1 - level + 1.0 / n) * (b - a))[0]
        high = deterministic(a + (1 - level - 1.0 / n) * (b - a))[0]
        assert low <= float(q.sel(quantile=level)) <= high


def test_layer_quantiles_equal_the_plain_uncertain_scene():
    """The reservoir's quantiles in the stack equal those of carcione2022_sandstone (Model 1)
    run as a plain uncertain scene with the same keys, distributions and seed."""
    gradient = {"distribution": "normal", "mean": 30.0, "sd": 2.5}
    grain = {"distribution": "lognormal", "median": 0.3, "sigma": 0.3}
    common = {"samples": 50, "seed": 7, "quantiles": [0.1, 0.5, 0.9]}
    stack = _run(_stack({**common, "path.gradient": gradient,
                         "layers.reservoir.sandstone.grain_size": grain}))
    raw, _ = read_scene_toml("carcione2022_sandstone")
    path = {k: v for k, v in PATH.items() if k != "gradient"}
    plain = {**raw, "path": path, "pressure": dict(PRESSURE),
             "models": {"hs_gassmann": {"A": 3.0}},
             "uncertain": {**common, "path.gradient": gradient,
                           "sandstone.grain_size": grain}}
    plain["sandstone"] = {k: v for k, v in raw["sandstone"].items() if k != "grain_size"}
    single = _run(plain)
    res = stack.sel(layer="reservoir")
    for name in ("temperature", "porosity", "cement_fraction"):
        np.testing.assert_allclose(res[name].values, single[name].values, rtol=1e-12,
                                   err_msg=name)
    np.testing.assert_allclose(res["density"].sel(fluid="brine").values,
                               single["density"].values, rtol=1e-12)
    for name in ("vp", "vs"):
        np.testing.assert_allclose(res[name].sel(fluid="brine", model="hs_gassmann").values,
                                   single[name].sel(model="hs_gassmann").values, rtol=1e-12,
                                   err_msg=name)
    assert (single["porosity"].sel(quantile=0.9) > single["porosity"].sel(quantile=0.1)).any()


@pytest.mark.parametrize("change, match", [
    (lambda r: r["layers"][1]["models"].update(md={"count": 1}),
     "layer 'reservoir' runs the MD backend"),
    (lambda r: r["uncertain"].update({"layers.reservor.sandstone.grain_size": r[
        "uncertain"].pop("layers.reservoir.sandstone.grain_size")}),
     "no layer 'reservor'; did you mean 'reservoir'"),
    (lambda r: r["uncertain"].update({"layers.seal.sandstone.grain_size": r["uncertain"].pop(
        "layers.reservoir.sandstone.grain_size")}),
     "layer 'seal'.*section \\[sandstone\\] does not apply to lithology 'shale'"),
    (lambda r: r["uncertain"].update(layers={"reservoir": {"sandstone": {"grain_size": {}}}}),
     "quote the key"),
    (lambda r: r["path"].update(sedimentation_rate=40.0) or r["uncertain"].update(
        {"path.sedimentation_rate": {"distribution": "uniform", "lower": 30.0,
                                     "upper": 50.0}}),
     "path.sedimentation_rate is both set"),
    (lambda r: r["layers"][1].update(sandstone={"grain_size": 0.3}),
     "layer 'reservoir'.*sandstone.grain_size is both set"),
    (lambda r: r["uncertain"].update({"fluid.salinity": {"distribution": "uniform",
                                                         "lower": 0.0, "upper": 0.1}}),
     "fluid.salinity does not apply to fluid.model = 'constant'"),
    (lambda r: r["uncertain"].update({"fluid.gas_gravity": {"distribution": "uniform",
                                                            "lower": 0.6, "upper": 0.8}}),
     "fluid.gas_gravity does not apply to stack.fluids = \\['brine'\\]"),
    (lambda r: r["uncertain"].update({"sandstone.grain_size": r["uncertain"].pop(
        "layers.reservoir.sandstone.grain_size")}),
     "as layers.<layer>.<section>.<key>"),
    (lambda r: r["uncertain"].update(sensitivity=True), "uncertain.sensitivity does not apply"),
    (lambda r: r["uncertain"].update(samples=1), "layer 'seal'.*uncertain.samples must be"),
])
def test_refused_by_name(change, match):
    raw = _stack({"samples": 8, "path.gradient": {"distribution": "normal", "mean": 30.0,
                                                  "sd": 2.0},
                  "layers.reservoir.sandstone.grain_size": {"distribution": "uniform",
                                                            "lower": 0.2, "upper": 0.4}})
    change(raw)
    with pytest.raises(ValueError, match=match):
        scene_from_dict(raw)


def test_shipped_scene_loads_with_its_keys():
    from rockcem.scene import load_scene

    scene = load_scene("carcione2022_avo_uncertain")
    assert scene.uncertain["samples"] == 200
    assert all(k.startswith(("path.", "pressure.", "layers.")) for k in scene.uncertain["keys"])
    assert AVO_CLASS_CODES == (1, 2, 3, 4, 5)


def test_members_on_dask_equal_the_serial_run(monkeypatch):
    """The chunks of an uncertain stack on a local dask cluster give the serial run's values
    (CHUNK_MEMBERS lowered so that its 12 members are three chunks, three tasks)."""
    pytest.importorskip("dask.distributed")
    from rockcem import _uncertain

    raw = _stack({"samples": 12, "seed": 4,
                  "path.gradient": {"distribution": "normal", "mean": 30.0, "sd": 2.0},
                  "layers.reservoir.sandstone.grain_size": {"distribution": "uniform",
                                                            "lower": 0.2, "upper": 0.4}})
    scene = scene_from_dict(raw)
    monkeypatch.setattr(_uncertain, "CHUNK_MEMBERS", 5)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        serial = run_scene(scene)
        on_dask = run_scene(scene, scheduler="local")
    for name in ("vp", "porosity", "avo_intercept", "reflectivity_pp", "avo_class_probability"):
        np.testing.assert_array_equal(serial[name].values, on_dask[name].values, err_msg=name)


def test_an_uncertain_saturation_moves_the_gas_sand_only():
    """fluid.saturation goes to the reservoir's gas member only: the seal and the brine sand
    are one value at every quantile (their runs are the deterministic ones), the gas sand's vp
    spreads; the gas interface's classes take more than one value somewhere, the brine's do
    not."""
    raw = _stack({"samples": 30, "seed": 2,
                  "fluid.saturation": {"distribution": "uniform", "lower": 0.05,
                                       "upper": 0.95}})
    raw["stack"]["fluids"] = ["brine", "gas"]
    raw["fluid"] = {"model": "batzle_wang", "salinity": 0.05, "gas_gravity": 0.6}
    fixed = _run({k: v for k, v in raw.items() if k != "uncertain"} | {
        "fluid": {**raw["fluid"], "saturation": 0.5}})
    ds = _run(raw)
    assert ds.attrs["pore_fluid"].count("saturation 0.5") == 1          # the median
    vp = ds["vp"].sel(model="hs_gassmann")
    for layer, fluid in (("seal", "brine"), ("seal", "gas"), ("reservoir", "brine")):
        one = vp.sel(layer=layer, fluid=fluid).values
        np.testing.assert_array_equal(one, np.broadcast_to(one[0], one.shape))
        np.testing.assert_array_equal(
            one[0], fixed["vp"].sel(model="hs_gassmann", layer=layer, fluid=fluid).values)
    gas = vp.sel(layer="reservoir", fluid="gas")
    assert (gas.sel(quantile=0.9) - gas.sel(quantile=0.1)).max() > 0.01     # km/s
    p = ds["avo_class_probability"].isel(interface=0, model=0)
    assert ((p.sel(fluid="brine") == 1.0).sum("avo_class") == 1).all()
    assert ((p.sel(fluid="gas") > 0) & (p.sel(fluid="gas") < 1)).any()


def test_a_table_of_horizons_keeps_its_horizon_names():
    """On a table of horizon histories the uncertain stack keeps the depth axis and the
    horizons' names of the deterministic stack."""
    from rockcem._data import data_path

    raw = _stack({"samples": 6, "layers.reservoir.sandstone.grain_size": {
        "distribution": "uniform", "lower": 0.2, "upper": 0.4}})
    raw["path"] = {"kind": "horizons",
                   "table": str(data_path() / "wells" / "synthetic_basin_history.csv")}
    fixed = _run({k: v for k, v in raw.items() if k != "uncertain"})
    ds = _run(raw)
    np.testing.assert_array_equal(ds["depth"].values, fixed["depth"].values)
    assert ds["horizon"].values.tolist() == fixed["horizon"].values.tolist()


def test_kept_members_are_the_deterministic_stacks_of_their_inputs():
    """members = true: member i's layers and reflectivity are those of the deterministic stack
    run with member i's sampled inputs (its member coordinates); the seal's and the
    reservoir's Krief exponents share a name, told apart by layer."""
    a = {"distribution": "uniform", "lower": 2.5, "upper": 3.5}
    raw = _stack({"samples": 5, "seed": 9, "members": True, "path.gradient": {
        "distribution": "normal", "mean": 30.0, "sd": 2.0},
        "layers.seal.models.hs_gassmann.A": a, "layers.reservoir.models.hs_gassmann.A": a},
        reservoir_models={"hs_gassmann": {}})
    raw["layers"][0]["models"]["hs_gassmann"] = {}
    ds = _run(raw)
    assert ds["vp_members"].dims == ("member", "layer", "fluid", "model", "depth")
    assert ds["avo_class_members"].attrs["flag_meanings"] == " ".join(AVO_CLASSES)
    for i in (0, 3):
        one = copy.deepcopy({k: v for k, v in raw.items() if k != "uncertain"})
        one["path"]["gradient"] = float(ds["gradient"][i])
        one["layers"][0]["models"]["hs_gassmann"]["A"] = float(ds["seal_hs_gassmann_A"][i])
        one["layers"][1]["models"]["hs_gassmann"]["A"] = float(
            ds["reservoir_hs_gassmann_A"][i])
        fixed = _run(one)
        member = ds.isel(member=i)
        for name in ("vp", "vs", "porosity", "avo_intercept", "avo_gradient",
                     "reflectivity_pp", "avo_class"):
            np.testing.assert_allclose(member[f"{name}_members"].values, fixed[name].values,
                                       rtol=1e-12, err_msg=name)


def test_cli_summary_and_plot_of_an_uncertain_stack(tmp_path, capsys):
    """``rockcem run`` prints the most probable class and its share at whole kilometres (read
    back from the Dataset's fractions), ``rockcem plot`` draws the class probabilities by
    default, and the kinds of a single answer (avo, band) are refused in one line."""

    from rockcem import cli
    from rockcem.scene import write_dataset

    raw = _stack({"samples": 40, "seed": 2,
                  "path.gradient": {"distribution": "normal", "mean": 30.0, "sd": 3.0}})
    ds = _run(raw)
    nc = tmp_path / "u.nc"
    write_dataset(ds, nc)
    lines = cli._stack_summary(ds).splitlines()
    assert lines[3].startswith("uncertain: 40 members")
    row = next(line for line in lines if line.strip().startswith("brine"))
    p = ds["avo_class_probability"].sel(interface=ds.interface.values[0], fluid="brine",
                                        model="hs_gassmann")
    at = [float(d) for d in lines[4].split(" at ")[1].rstrip(" m:").split(", ")]
    cells = row.split()[2:]
    for k, depth in enumerate(at):
        col = p.sel(depth=depth).values
        assert cells[2 * k] == str(p.avo_class.values[col.argmax()])
        assert float(cells[2 * k + 1]) == pytest.approx(col.max(), abs=0.005)
    assert cli.main(["plot", str(nc), "-q"]) == 0
    assert (tmp_path / "u_avo-probability.png").stat().st_size > 0
    for kind in ("avo", "band"):
        assert cli.main(["plot", str(nc), "--kind", kind]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "--kind avo-probability" in err, err
