"""Validity warnings: where they apply, and that a scene carries them without computing more."""

import numpy as np
import pytest

from rockcem.frames import krief_factor
from rockcem.scene import run_scene, scene_from_dict
from rockcem.validity import KRIEF_LOOSE_FRACTION, validity_warnings

DEPTH = np.arange(0.0, 1001.0, 100.0)
POROSITY = np.linspace(0.36, 0.26, 11)           # 0.01 per 100 m


def test_krief_rule_flags_the_loose_interval_only():
    lines = validity_warnings(DEPTH, POROSITY, porosity0=0.36,
                              models=["hs_gassmann", "self_consistent", "generalized_gassmann"])
    # 0.9 * 0.36 = 0.324: porosity 0.36 ... 0.33 at 0 ... 300 m is above it, 0.32 at 400 m not
    assert lines == [
        "Models 1 and 3 (Krief frame) at 0–300 m: porosity above 0.324 (0.9 of the depositional "
        "0.36); Krief's relation is a fit to consolidated rocks with no pressure dependence and "
        "gives a loose sediment the stiffness of a rock (velocities too high, Vp/Vs too low)"]
    only2 = validity_warnings(DEPTH, POROSITY, porosity0=0.36, models=["generalized_gassmann"])
    assert only2[0].startswith("Model 3 (Krief frame) at 0–300 m")


def test_no_line_for_models_without_krief_or_rock_that_is_not_loose():
    assert validity_warnings(DEPTH, POROSITY, porosity0=0.36,
                             models=["self_consistent", "patchy_cement"]) == []
    assert validity_warnings(DEPTH, POROSITY * 0.5, porosity0=0.36,
                             models=["hs_gassmann"]) == []


def test_krief_frame_at_the_depositional_porosity_is_12_percent_of_the_mineral():
    # the figure quoted in rockcem.validity and docs/disagreements.md: (1 - 0.36)^(3 / 0.64)
    assert float(krief_factor(0.36)) == pytest.approx(0.64 ** (3.0 / 0.64), rel=1e-14)
    assert 0.12 < float(krief_factor(0.36)) < 0.13
    assert KRIEF_LOOSE_FRACTION == 0.9


def test_pore_filled_interval():
    filled = DEPTH >= 700.0
    (line,) = validity_warnings(DEPTH, POROSITY, porosity0=0.36, pore_filled=filled)
    assert line.startswith("quartz cement at 700–1000 m: Walderhaug's kinetics would overfill")
    (line,) = validity_warnings(DEPTH, POROSITY, porosity0=0.36, pore_filled=DEPTH == 1000.0)
    assert line.startswith("quartz cement at 1000 m:")


def test_bad_input():
    with pytest.raises(ValueError, match="porosity0"):
        validity_warnings(DEPTH, POROSITY, porosity0=1.2)
    with pytest.raises(ValueError, match="one shape"):
        validity_warnings(DEPTH, POROSITY[:-1], porosity0=0.36)


SANDSTONE = {"name": "t", "lithology": "sandstone",
             "path": {"max_depth": 6000.0, "depth_step": 100.0},
             "models": {"hs_gassmann": {}, "patchy_cement": {}}}


def test_scene_dataset_carries_the_lines():
    ds = run_scene(scene_from_dict(SANDSTONE))
    lines = ds.attrs["validity_warnings"].split("\n")
    loose = ds.depth.values[ds.porosity.values > 0.9 * 0.36]
    filled = ds.depth.values[ds.pore_filled.values == 1]
    assert lines[0].startswith(f"Model 1 (Krief frame) at 0–{loose.max():g} m")
    assert lines[1].startswith(f"quartz cement at {filled.min():g}–6000 m")


def test_scene_computes_nothing_more_for_the_warnings():
    ds = run_scene(scene_from_dict(dict(SANDSTONE, outputs=["temperature"])))
    assert "validity_warnings" not in ds.attrs             # no porosity, no models computed
    ds = run_scene(scene_from_dict(dict(SANDSTONE, outputs=["porosity"])))
    assert ds.attrs["validity_warnings"].startswith("quartz cement at")   # models not run


def test_sweep_lines_name_their_members():
    raw = dict(SANDSTONE, outputs=["porosity"], sweep={"path.gradient": [20.0, 30.0]})
    ds = run_scene(scene_from_dict(raw))
    lines = ds.attrs["validity_warnings"].split("\n")
    assert len(lines) == 1 and lines[0].startswith("[gradient = 30] quartz cement at")
    raw = dict(SANDSTONE, sweep={"sandstone.grain_size": [0.3, 0.31]})
    lines = run_scene(scene_from_dict(raw)).attrs["validity_warnings"].split("\n")
    assert lines[0].startswith("Model 1 (Krief frame)")    # the same for both: said once


def test_flagged_krief_interval_is_stiffer_than_any_uncemented_pack():
    """What the 0.9 threshold flags is out of Krief's depth by an independent measure: there
    the sand is as good as uncemented, yet Krief's dry frame is stiffer in shear than the
    stiff-sand model (the stiffest uncemented pack at the depth's effective pressure,
    Mavko et al. 2009, Sect. 7.9) — 1.4 times at the deepest flagged depth of the sandstone
    example, 3.8 times at 100 m; below the interval the cement takes over."""
    from rockcem.granular import stiff_sand
    from rockcem.materials import mineral

    ds = run_scene(scene_from_dict(SANDSTONE))
    loose = ds.porosity.values > KRIEF_LOOSE_FRACTION * 0.36
    quartz = mineral("quartz")
    pe = np.maximum(ds.pressure_effective.values, 1e-3)
    pack = stiff_sand(quartz.K, quartz.G, ds.porosity.values, 0.36, 9.0, pe)
    ratio = ds.G_dry.sel(model="hs_gassmann").values / pack.G
    assert loose[0] and np.all(ratio[loose] > 1.35)
    assert ratio[1] > 3.5                                    # 100 m
    assert np.all(ds.cement_fraction.values[loose] < 0.006)  # below 0.6 % cement
    assert ds.cement_fraction.values[~loose][0] > 0.005      # the cement grows on from there
