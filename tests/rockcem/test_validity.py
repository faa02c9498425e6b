"""Validity warnings: where they apply, and that a scene carries them without computing more."""

import numpy as np
import pytest

from rockcem.frames import krief_factor
from rockcem.scene import run_scene, scene_from_dict
from rockcem.validity import (ASSUMPTION_SHEAR_FRACTION, KRIEF_LOOSE_FRACTION,
                              RockcemValidityWarning, validity_warnings)

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
    assert lines[1].startswith("Model 4 (patchy cement) at 0–")
    assert lines[2].startswith(f"quartz cement at {filled.min():g}–6000 m")


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


# ----------------------------------------------------------------------------- Models 2 and 4
Z4 = np.array([0.0, 100.0, 200.0, 300.0])


def test_models_2_and_4_flagged_where_the_assumption_carries_most_of_the_shear_modulus():
    """Hand values: G = 4 GPa, the supported part 0, 1.9, 2.0 and 2.1 GPa: flagged where it is
    below half (0 and 100 m); exactly half is not flagged."""
    G = np.full(4, 4.0)
    supported = np.array([0.0, 1.9, 2.0, 2.1])
    lines = validity_warnings(Z4, np.full(4, 0.2), porosity0=0.36,
                              models=["self_consistent", "patchy_cement"],
                              shear_moduli={"patchy_cement": (G, supported),
                                            "self_consistent": (G, supported[::-1])})
    assert ASSUMPTION_SHEAR_FRACTION == 0.5
    assert lines == [
        "Model 2 (self-consistent) at 200–300 m: more than half of the saturated shear modulus "
        "is the pore fluid's, held in isolated pores (a high-frequency limit); the rock's "
        "connected pores at seismic frequencies leave it the dry frame's (Gassmann), less than "
        "half (Vs too high, Vp/Vs too low)",
        "Model 4 (patchy cement) at 0–100 m: more than half of the dry frame's shear modulus "
        "comes from the bonding pre-stress delta, not from cement or the effective pressure; an "
        "uncemented sand there is a Hertz-Mindlin pack at its effective pressure, far softer "
        "(velocities too high)"]
    # nothing flagged where the supported part is at least half, or for other labels
    assert validity_warnings(Z4, np.full(4, 0.2), porosity0=0.36, shear_moduli={
        "patchy_cement": (G, G / 2), "hs_gassmann": (G, 0 * G)}) == []


def test_shear_moduli_of_another_shape_refused():
    with pytest.raises(ValueError, match=r"shear_moduli\['patchy_cement'\]"):
        validity_warnings(Z4, np.full(4, 0.2), porosity0=0.36,
                          shear_moduli={"patchy_cement": (np.ones(3), np.ones(3))})


MODELS_2_4 = dict(SANDSTONE, models={"self_consistent": {"aspect_ratio": 0.108},
                                     "patchy_cement": {}})


def test_model_4_surface_is_a_pack_held_by_delta_alone():
    """At the surface (effective pressure 0, no cement, porosity = critical) Model 4's frame is
    Hertz-Mindlin at p = delta (Carcione et al. 2022, eq. D.2, by hand below), and Avseth's
    (delta = 0) has no stiffness: flagged from 0 m, to where the cement and the effective
    pressure carry half the frame; there it is still stiffer than any uncemented pack at the
    depth's pressure (the stiff-sand model, Mavko et al. 2009, Sect. 7.9)."""
    from rockcem.granular import stiff_sand
    from rockcem.materials import mineral

    ds = run_scene(scene_from_dict(MODELS_2_4))
    q = mineral("quartz")
    nu = (3 * q.K - 2 * q.G) / (2 * (3 * q.K + q.G))
    delta, n, phic = 100e-3, 9.0, 0.36                      # GPa
    hm = (5 - 4 * nu) / (5 * (2 - nu)) * (3 * n ** 2 * (1 - phic) ** 2 * q.G ** 2 * delta
                                         / (2 * np.pi ** 2 * (1 - nu) ** 2)) ** (1 / 3)
    g4 = ds.G_dry.sel(model="patchy_cement").values
    assert g4[0] == pytest.approx(hm, rel=1e-12)
    line = next(x for x in ds.attrs["validity_warnings"].split("\n") if x.startswith("Model 4"))
    base = float(line.split(" at 0–")[1].split(" m:")[0])
    assert 400.0 <= base <= 800.0                            # 595 m at a 100 m step: 500 m
    flagged = ds.depth.values <= base
    pe = np.maximum(ds.pressure_effective.values, 1e-3)
    pack = stiff_sand(q.K, q.G, ds.porosity.values, phic, n, pe)
    assert np.all(g4[flagged] / pack.G[flagged] > 1.9)


def test_model_2_flagged_where_its_dry_frame_holds_less_than_half():
    """Model 2's dry self-consistent frame has no shear modulus at the surface (porosity 0.36
    is above the scheme's percolation for pores of aspect ratio 0.108) while the saturated one
    has ~2.7 GPa: flagged from 0 m down to the last depth where G_dry < G_sat / 2."""
    ds = run_scene(scene_from_dict(MODELS_2_4))
    m2 = ds.sel(model="self_consistent")
    assert float(m2.G_dry[0]) < 1e-6 and float(m2.G_sat[0]) > 2.5
    deepest = ds.depth.values[m2.G_dry.values < 0.5 * m2.G_sat.values].max()
    assert f"Model 2 (self-consistent) at 0–{deepest:g} m:" in ds.attrs["validity_warnings"]
    assert 2500.0 <= deepest <= 3500.0
    # Gassmann's low-frequency limit: with the dry frame's shear modulus, Vs at the surface
    # would be 0, not the model's 1.1 km/s
    assert float(m2.vs[0]) > 1.0


def test_no_model_4_flag_without_bonding_pre_stress():
    raw = dict(SANDSTONE, models={"patchy_cement": {"delta": 0.0}})
    assert "Model 4" not in run_scene(scene_from_dict(raw)).attrs.get("validity_warnings", "")


# ----------------------------------------------------------------------------- Python warnings
def test_run_scene_issues_each_line_once_as_a_python_warning():
    """A sweep of two members with the same lines: each line issued once, as a
    RockcemValidityWarning attributed to the caller's line (this file), not rockcem's."""
    import warnings

    raw = dict(SANDSTONE, sweep={"sandstone.grain_size": [0.3, 0.31]})
    with warnings.catch_warnings(record=True) as record:
        warnings.simplefilter("always")
        ds = run_scene(scene_from_dict(raw))
    ours = [w for w in record if issubclass(w.category, RockcemValidityWarning)]
    lines = ds.attrs["validity_warnings"].split("\n")
    assert [str(w.message) for w in ours] == [f"scene t: {line}" for line in lines]
    assert {w.filename for w in ours} == {__file__}
    assert issubclass(RockcemValidityWarning, UserWarning)


def test_validity_warnings_can_be_filtered_or_made_errors():
    import warnings

    import rockcem

    assert rockcem.RockcemValidityWarning is RockcemValidityWarning
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        warnings.simplefilter("ignore", rockcem.RockcemValidityWarning)
        run_scene(scene_from_dict(SANDSTONE))               # no warning escapes
    with warnings.catch_warnings():
        warnings.simplefilter("error", rockcem.RockcemValidityWarning)
        with pytest.raises(RockcemValidityWarning, match="scene t: Model 1 \\(Krief"):
            run_scene(scene_from_dict(SANDSTONE))


def test_no_python_warning_without_lines():
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error", RockcemValidityWarning)
        run_scene(scene_from_dict(dict(SANDSTONE, outputs=["temperature"])))
