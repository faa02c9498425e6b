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
    "path": {"max_depth": 3000.0, "depth_step": 100.0},
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


@pytest.mark.parametrize("raw", [SANDSTONE, SHALE], ids=["sandstone", "shale"])
def test_members_together_equal_one_at_a_time(raw):
    """The vectorised members (called directly: no fall-back to the member loop) against each
    member through the scene runner, to 1e-12 relative; the validity lines too."""
    s = scene_from_dict(raw)
    values = sample_inputs(s.uncertain)
    m = s.uncertain["samples"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        together, w1 = _evaluate_together(s, values, m)
        each, w2 = _evaluate_each(s, values, m)
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
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        data, _ = _evaluate_together(s, values, s.uncertain["samples"])
    z = np.arange(0.0, 3001.0, 100.0)
    want = values["path.surface_temperature"][:, None] \
        + values["path.gradient"][:, None] * z / 1000.0
    np.testing.assert_allclose(data["temperature"][1], want, rtol=1e-14)
