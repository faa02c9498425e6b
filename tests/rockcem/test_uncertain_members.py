"""Uncertain members evaluated together (issue 32): the rock states of a chunk of members from
one call of each burial function on per-member parameters equal the scene runner's member by
member, and the quantiles taken per depth slice equal those of all members at once."""

import warnings

import numpy as np
import pytest

from rockcem._uncertain import _evaluate_each, _evaluate_together, sample_inputs
from rockcem.scene import scene_from_dict

UNIFORM = (lambda lo, hi: {"distribution": "uniform", "lower": lo, "upper": hi})

#: Every numeric key of a linear sandstone path and its rock state, and one per model.
SANDSTONE = {
    "name": "members", "lithology": "sandstone",
    "path": {"max_depth": 5000.0, "depth_step": 100.0},
    "models": {"hs_gassmann": {}, "self_consistent": {"aspect_ratio": 0.108},
               "generalized_gassmann": {},
               "patchy_cement": {}},
    "outputs": ["burial_time", "temperature", "pressure_confining", "pressure_pore",
                "pressure_effective", "cement_fraction", "intergranular_volume", "porosity",
                "pore_filled", "density", "vp", "vs"],
    "uncertain": {
        "samples": 9, "seed": 5,
        "path.gradient": UNIFORM(22.0, 40.0), "path.sedimentation_rate": UNIFORM(20.0, 120.0),
        "path.surface_temperature": UNIFORM(2.0, 25.0),
        "pressure.sediment_density": UNIFORM(2.2, 2.6),
        "pressure.water_density": UNIFORM(1.0, 1.1),
        "sandstone.porosity0": UNIFORM(0.34, 0.42), "sandstone.grain_size": UNIFORM(0.1, 0.5),
        "sandstone.quartz_fraction": UNIFORM(0.5, 0.9), "sandstone.clay_coating": UNIFORM(0, 0.4),
        "sandstone.igv_final": UNIFORM(0.15, 0.25), "sandstone.beta": UNIFORM(0.005, 0.02),
        "sandstone.start_temperature": UNIFORM(60.0, 90.0),
        "models.hs_gassmann.A": UNIFORM(2.5, 3.5),
        "models.patchy_cement.delta": UNIFORM(40.0, 100.0)}}

#: A shale with its kinetics uncertain, on a path given by its heating rate.
SHALE = {
    "name": "members_shale", "lithology": "shale",
    "path": {"max_depth": 5000.0, "depth_step": 250.0, "gradient": 30.0},
    "models": {"hs_gassmann": {}, "self_consistent": {"aspect_ratio": 0.17}},
    "outputs": ["temperature", "porosity", "smectite_fraction", "density", "vp", "vs"],
    "uncertain": {
        "samples": 7, "seed": 3,
        "path.heating_rate": UNIFORM(0.6, 2.0),
        "shale.porosity0": UNIFORM(0.3, 0.4), "shale.beta": UNIFORM(0.005, 0.02),
        "shale.r0": UNIFORM(0.6, 0.99), "shale.order": UNIFORM(1.0, 6.0),
        "shale.activation_energy": UNIFORM(30.0, 40.0),
        "shale.frequency_factor": UNIFORM(0.5e23, 2e23)}}


#: Only keys of the rock (no key of the path or the pressures uncertain).
ROCK_ONLY = dict(SANDSTONE, uncertain={"samples": 5, "seed": 2, **{
    k: v for k, v in SANDSTONE["uncertain"].items() if k.startswith("sandstone.")}})


def quietly(call, *args):
    """``call(*args)`` with the validity warnings silenced."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return call(*args)


@pytest.mark.parametrize("raw", [SANDSTONE, SHALE, ROCK_ONLY],
                         ids=["sandstone", "shale", "rock_only"])
def test_members_together_equal_one_at_a_time(raw):
    """The vectorised members (called directly: no fall-back to the member loop) against each
    member through the scene runner, to 1e-12 relative; the validity lines too."""
    s = scene_from_dict(raw)
    values = sample_inputs(s.uncertain)
    m = s.uncertain["samples"]
    together, w1 = quietly(_evaluate_together, s, values, m)
    each, w2 = quietly(_evaluate_each, s, values, m)
    assert together.keys() == each.keys() and len(together) == len(raw["outputs"])
    for name in together:
        assert together[name][0] == each[name][0]
        assert np.shape(together[name][1]) == np.shape(each[name][1]), name
        np.testing.assert_allclose(together[name][1], each[name][1], rtol=1e-12, atol=1e-14,
                                   err_msg=name)
    assert w1 == w2


def test_temperature_of_members_is_the_closed_form():
    """Each member's temperature is T0 + G z (Carcione et al. 2022, eq. 2) of its inputs."""
    s = scene_from_dict(SANDSTONE)
    values = sample_inputs(s.uncertain)
    data = quietly(_evaluate_together, s, values, s.uncertain["samples"])[0]
    z = np.arange(0.0, 5001.0, 100.0)
    want = values["path.surface_temperature"][:, None] \
        + values["path.gradient"][:, None] * z / 1000.0
    np.testing.assert_allclose(data["temperature"][1], want, rtol=1e-14)


def test_validity_masks_give_each_members_lines():
    """The validity rules kept as one bit per (member, depth) and split into depth slices give
    every member the lines its own values give (all four rules hold somewhere here)."""
    from rockcem._uncertain import _chunk_arrays, _masked, _member_lines, _unmasked

    s = scene_from_dict(SANDSTONE)
    values = sample_inputs(s.uncertain)
    m = s.uncertain["samples"]
    checks = quietly(_chunk_arrays, s, values, m)[1]
    parts = [_masked(quietly(_chunk_arrays, s, values, m, sl)[1])
             for sl in (slice(0, 7), slice(7, 8), slice(8, 51))]
    want = _member_lines(checks)
    assert {line.split(" at ")[0] for lines in want for line in lines} >= {
        "Models 1 and 3 (Krief frame)", "Model 2 (self-consistent)", "Model 4 (patchy cement)",
        "quartz cement"}
    assert _member_lines(_unmasked(parts)) == want


def test_depth_slices_give_the_quantiles_of_all_members():
    """The quantiles of each depth slice's members, side by side, equal those of all members
    at once (bit for bit; the first slice's members on paths down to it only, 4 at a time),
    and a slice returns quantiles only."""
    from rockcem._uncertain import _slice_quantiles

    s = scene_from_dict(SANDSTONE)
    values = sample_inputs(s.uncertain)
    q = np.array([0.1, 0.5, 0.9])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        whole, _ = _evaluate_together(s, values, s.uncertain["samples"])
        parts = [_slice_quantiles(s, values, slice(0, 12), q, 4, 1100.0)[0],   # path to 1.1 km
                 _slice_quantiles(s, values, slice(12, 51), q)[0]]
    for name, (dims, a) in whole.items():
        got = np.concatenate([p[name][1] for p in parts], axis=-1)
        assert got.shape == (3,) + a.shape[1:], name
        np.testing.assert_array_equal(got, np.quantile(np.asarray(a, dtype=float), q, axis=0),
                                      err_msg=name)


def test_dask_depth_slices_equal_the_serial_run():
    """On two dask processes (depth slices, quantiles only back) the Dataset and its validity
    lines are those of the serial run."""
    pytest.importorskip("dask.distributed")
    xr = pytest.importorskip("xarray")
    from rockcem.scene import run_scene

    raw = dict(SANDSTONE, uncertain=dict(SANDSTONE["uncertain"], samples=300))
    s = scene_from_dict(raw)                                       # two chunks of members
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        serial, on_dask = run_scene(s), run_scene(s, scheduler="local")
    xr.testing.assert_identical(serial.drop_attrs(), on_dask.drop_attrs())
    assert serial.attrs["validity_warnings"] == on_dask.attrs["validity_warnings"]
    for rule in ("Krief frame", "Model 2", "Model 4", "quartz cement at"):
        assert rule in serial.attrs["validity_warnings"], rule


def test_patchy_cement_at_critical_porosity_plus_rounding_is_the_loose_pack():
    """A member whose IGV at the surface comes out one rounding above its critical porosity
    (phi0 = 0.41837...) with no pressure and delta = 0 (the validity rule's frame): Model 4's
    frame there is the Hertz-Mindlin pack at zero pressure, K = G = 0 (eq. D.1), not -4e-15."""
    from rockcem import materials
    from rockcem.models import patchy_cement_model

    phic = 0.4183700857363322
    r = patchy_cement_model(materials.mineral("quartz"), materials.mineral("quartz_cement"),
                            np.nextafter(phic, 1.0), 0.0, 0.0, materials.fluid("water"),
                            critical_porosity=phic, delta=0.0)
    assert float(r.K_dry) == 0.0 and float(r.G_dry) == 0.0
