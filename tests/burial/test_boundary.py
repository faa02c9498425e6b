"""The public boundary of burial (issue 24): bad input is a ValueError naming the argument,
before any large array is made; extreme but valid input gives a finite, bounded answer with no
warning; a BurialPath made directly is checked like one from path_from_nodes."""

import warnings

import numpy as np
import pytest

from burial import (BurialPath, athy_porosity, horizon_paths, intergranular_volume, linear_path,
                    path_from_nodes, pressures, quartz_cement, sandstone_porosity, shifted_path,
                    smectite_fraction)
from burial.path import MAX_PROFILE_NODES

PATH = linear_path(30.0, 40.0, 15.0, 4000.0, depth_step=1000.0)


# --- the IGV's matrix term (a one-line mutation of it survived the whole suite) ---------------
def test_intergranular_volume_matrix_term_closed_form():
    """Eq. B.7: IGV = IGV_i + (phi0 + m0 - IGV_i) exp(-beta p_e); at p_e = 0 it is phi0 + m0,
    at beta p_e = ln 2 half-way between that and IGV_i."""
    phi0, m0, igv_i, beta = 0.30, 0.08, 0.20, 0.01
    assert intergranular_volume(phi0, 0.0, igv_i, beta, m0) == pytest.approx(0.38, rel=1e-15)
    half = np.log(2.0) / beta
    assert intergranular_volume(phi0, half, igv_i, beta, m0) == pytest.approx(0.29, rel=1e-14)
    far = intergranular_volume(phi0, 1e5, igv_i, beta, m0)
    assert far == pytest.approx(igv_i, rel=1e-12)


def test_intergranular_volume_final_bound_includes_the_matrix(expect_value_error):
    """igv_final may reach porosity0 + matrix0 (no compaction left), not beyond."""
    np.testing.assert_allclose(intergranular_volume(0.3, [0.0, 50.0], 0.38, 0.01, 0.08), 0.38,
                               rtol=1e-15)
    expect_value_error(lambda: intergranular_volume(0.3, 10.0, 0.39, 0.01, 0.08), "igv_final")
    expect_value_error(lambda: intergranular_volume(0.3, 10.0, 0.2, 0.01, 0.8), "matrix0")


# --- kelvin, NaN and infinities -----------------------------------------------------------------
@pytest.mark.parametrize("call, name, match", [
    # 288.15 (kelvin by mistake) ran and filled the pores with cement from 10 m down.
    (lambda: linear_path(30.0, 40.0, 288.15, 3000.0), "surface_temperature", "kelvin"),
    (lambda: linear_path(30.0, 40.0, 101.0, 3000.0), "surface_temperature", "kelvin"),
    (lambda: linear_path(30.0, 40.0, -150.0, 3000.0), "surface_temperature", r"\[-100, 100\]"),
    (lambda: path_from_nodes([0, 10], [0, 100], [288.15, 290.0]), "temperature", "kelvin"),
    (lambda: BurialPath([0.0, 10.0], [0.0, 100.0], [288.15, 290.0]), "temperature", "kelvin"),
    (lambda: shifted_path([0, 10], [0, 100], [288.15, 290.0]), "temperature", "kelvin"),
    (lambda: linear_path(30.0, 40.0, np.nan, 3000.0), "surface_temperature", "NaN"),
    (lambda: linear_path(30.0, 40.0, np.inf, 3000.0), "surface_temperature", ""),
    (lambda: linear_path(np.inf, 40.0, 15.0, 3000.0), "gradient", ""),
    (lambda: linear_path(30.0, 40.0, 15.0, np.inf), "max_depth", ""),
    (lambda: linear_path(30.0, 40.0, 15.0, 3000.0, depth_step=np.nan), "depth_step", "NaN"),
    (lambda: quartz_cement(PATH, 0.36, 0.3, 0.65, start_temperature=np.nan),
     "start_temperature", "NaN"),
    (lambda: quartz_cement(PATH, 0.36, 0.3, 0.65, start_temperature=np.inf),
     "start_temperature", r"\[-100, 500\]"),
    (lambda: quartz_cement(PATH, 0.36, 0.3, 0.65, start_temperature=[50.0, np.nan]),
     "start_temperature", r"\[1\] is NaN"),
    (lambda: quartz_cement(PATH, 0.36, 0.3, 0.65, start_temperature="60"),
     "start_temperature", "text"),
    (lambda: quartz_cement(PATH, 0.36, 0.3, 0.65, rate_exponent=1.0), "rate_exponent",
     r"\(0, 0.1\]"),
    (lambda: smectite_fraction(PATH, 0.9, order=[1.0, 12.0]), "order",
     r"\[1\] must lie in \[1, 10\]"),
    (lambda: smectite_fraction(PATH, 0.9, activation_energy=1e300), "activation_energy", ""),
    (lambda: pressures(PATH, sediment_density=np.nan), "sediment_density", "NaN"),
    (lambda: pressures("path"), "path", ""),
    (lambda: quartz_cement(PATH, 0.36, 1e-300, 0.65), "grain_size", r"\[1e-06, inf\)"),
])
def test_bad_input_names_the_argument(call, name, match):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ValueError, match=rf"\b{name}\b.*{match}"):
            call()


def test_surface_temperature_up_to_100_degC_is_accepted():
    p = linear_path(30.0, 40.0, 100.0, 1000.0, depth_step=500.0)
    np.testing.assert_allclose(p.temperature, [100.0, 115.0, 130.0])


# --- a BurialPath made directly is checked ------------------------------------------------------
@pytest.mark.parametrize("time, depth, temperature, name", [
    ([0.0, 1.0], [-5.0, -3.0], [15.0, 20.0], "depth"),
    ([0.0, 1.0], [0.0, 3.0 + 1j], [15.0, 20.0], "depth"),
    ([0.0, 1.0 + 0j], [0.0, 3.0], [15.0, 20.0], "time"),
    ([0.0, 1.0], [0.0, 3.0], [15.0, np.nan], "temperature"),
    ([0.0, 1.0], [0.0, np.inf], [15.0, 20.0], "depth"),
    ([0.0, -1.0], [0.0, 3.0], [15.0, 20.0], "time"),
    ([0.0, 2.0, 1.0], [0.0, 3.0, 4.0], [15.0, 16.0, 17.0], "time"),
    ([0.0], [0.0], [15.0], "time"),
    ([0.0, 1.0], [0.0, 3.0], [15.0, 600.0], "temperature"),
    ([0.0, 1.0], [[0.0, 3.0]] * 2, [15.0, 16.0, 17.0], "temperature"),
    ([0.0, 1.0], [0.0, 3.0], "hot", "temperature"),
    ([0.0, 1.0], None, [15.0, 16.0], "depth"),
])
def test_burial_path_made_directly_is_checked(time, depth, temperature, name,
                                              expect_value_error):
    expect_value_error(lambda: BurialPath(time, depth, temperature), name)


def test_burial_path_made_directly_allows_zero_length_pieces_and_broadcasts():
    """Zero-duration pieces (the padding of horizon_paths) are allowed; depth and temperature
    are broadcast to one shape; the values are those given."""
    p = BurialPath([0.0, 0.0, 10.0], [[0.0, 0.0, 100.0], [0.0, 0.0, 200.0]], [15.0, 15.0, 18.0])
    assert p.depth.shape == p.temperature.shape == (2, 3)
    np.testing.assert_array_equal(p.heating_rate, [[0.0, 0.3], [0.0, 0.3]])
    h = horizon_paths(["A"] * 3 + ["B"] * 2, [20, 10, 0, 10, 0], [0, 100, 200, 0, 50],
                      [15, 18, 21, 15, 16.5])
    assert isinstance(h.path, BurialPath)


# --- sizes are bounded before any array is made ---------------------------------------------------
@pytest.mark.parametrize("kwargs, name", [
    (dict(max_depth=1e300), "max_depth"),
    (dict(max_depth=1e8), "max_depth"),
    (dict(max_depth=20001.0), "max_depth"),
    (dict(depth_step=1e-6), "depth_step"),
    (dict(max_depth=20000.0, depth_step=0.01), "depth_step"),
    (dict(gradient=1e300), "gradient"),
    (dict(sedimentation_rate=1e-300), "sedimentation_rate"),
    (dict(sedimentation_rate=0.04), "sedimentation_rate"),      # m/yr instead of m/Myr
])
def test_linear_path_sizes_bounded_up_front(kwargs, name, monkeypatch):
    def refuse(*args, **kw):
        raise AssertionError("an array was made before the sizes were checked")

    args = dict(gradient=20.0, sedimentation_rate=40.0, surface_temperature=15.0,
                max_depth=5000.0) | kwargs
    monkeypatch.setattr(np, "arange", refuse)
    with pytest.raises(ValueError, match=rf"\b{name}\b"):
        linear_path(**args)


def test_linear_path_at_the_node_bound_and_a_step_larger_than_the_path():
    p = linear_path(20.0, 40.0, 15.0, 10000.0, depth_step=10000.0 / (MAX_PROFILE_NODES - 1))
    assert p.depth.size == MAX_PROFILE_NODES and p.depth[-1] == 10000.0
    np.testing.assert_array_equal(linear_path(20.0, 40.0, 15.0, 1000.0,
                                              depth_step=1e300).depth, [0.0, 1000.0])
    np.testing.assert_array_equal(linear_path(20.0, 40.0, 15.0, 1e-3).depth, [0.0, 1e-3])


def test_shifted_path_depth_step_bounded(expect_value_error):
    expect_value_error(lambda: shifted_path([0, 10], [0, 1000], [15, 45], depth_step=1e-6),
                       "depth_step")
    expect_value_error(lambda: shifted_path([0, 10], [0, 1000], [15, 45], depth_step="10"),
                       "depth_step")
    expect_value_error(lambda: shifted_path([0, 10], [0, 1000], [15, 45], depth_step=-1.0),
                       "depth_step")


# --- extreme but valid input: finite, bounded, no warning ---------------------------------------
@pytest.mark.parametrize("kwargs", [
    dict(rate_constant=1e300),                      # overflowed k with a warning
    dict(grain_size=1e-6),                          # the smallest accepted (1 nm)
    dict(porosity0=1e-300),
    dict(rate_exponent=0.1),
    dict(quartz_fraction=0.0, rate_constant=1e300),  # k = 0 with an infinite integral
])
def test_quartz_cement_extremes_are_finite_and_silent(kwargs):
    args = dict(porosity0=0.36, grain_size=0.3, quartz_fraction=0.65) | kwargs
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        phip = quartz_cement(PATH, **args)
    assert np.all(np.isfinite(phip))
    assert np.all(phip >= 0.0) and np.all(phip <= args["porosity0"])
    assert np.all(np.diff(phip) >= 0.0)
    assert phip[0] == 0.0                       # no time, no cement


def test_kinetics_on_a_path_of_1e300_myr_complete_without_nan():
    """Walderhaug: the pores fill (phi_p = phi0) unless there is no quartz; Pytte-Reynolds: the
    smectite is gone (r = 0) unless there was none to begin with."""
    p = path_from_nodes([0.0, 1e300, 1.7e308], [0.0, 10.0, 20.0], [15.0, 200.0, 200.0])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        np.testing.assert_array_equal(quartz_cement(p, 0.3, 0.3, 0.6), [0.0, 0.3, 0.3])
        np.testing.assert_array_equal(quartz_cement(p, 0.3, 0.3, 0.0), [0.0, 0.0, 0.0])
        for order in (1.0, 5.0, 10.0):
            # r = r0 (1 + m c J r0^m)^(-1/m): 1e-77 for n = 5 and J ~ 1e298 Myr.
            np.testing.assert_allclose(smectite_fraction(p, 0.99, order), [0.99, 0.0, 0.0],
                                       rtol=0.0, atol=1e-30)
            np.testing.assert_array_equal(smectite_fraction(p, 0.0, order), [0.0, 0.0, 0.0])
        np.testing.assert_allclose(smectite_fraction(p, 0.99, 5.0, frequency_factor=1e308),
                                   [0.99, 0.0, 0.0], rtol=0.0, atol=1e-30)


def test_start_temperature_at_the_bounds():
    """At the hottest allowed temperature nothing counts; at the coldest, everything does."""
    np.testing.assert_array_equal(quartz_cement(PATH, 0.36, 0.3, 0.65, start_temperature=500.0),
                                  0.0)
    np.testing.assert_array_equal(quartz_cement(PATH, 0.36, 0.3, 0.65, start_temperature=-100.0),
                                  quartz_cement(PATH, 0.36, 0.3, 0.65))


@pytest.mark.parametrize("call, names", [
    (lambda: quartz_cement(PATH, [0.3] * 3, 0.3, [0.6] * 2), ("porosity0", "quartz_fraction")),
    (lambda: athy_porosity([0.3] * 3, [1.0, 2.0]), ("porosity0", "effective_pressure")),
    (lambda: intergranular_volume(0.3, [1.0, 2.0], [0.2] * 3), ("effective_pressure",
                                                                "igv_final")),
    (lambda: sandstone_porosity([0.3, 0.2], [0.0] * 3), ("intergranular_volume",
                                                         "cement_fraction")),
    (lambda: smectite_fraction(path_from_nodes([0, 1], [[0, 1]] * 2, [15, 16]), [0.9] * 3),
     ("r0", "path")),
])
def test_shape_mismatch_names_both_arguments(call, names):
    with pytest.raises(ValueError, match="do not broadcast") as info:
        call()
    for name in names:
        assert name in str(info.value)
    assert "operands" not in str(info.value)
