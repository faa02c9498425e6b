"""rockcem.synthetics against closed forms: travel time of constant and linear velocity columns,
the Ricker wavelet and its analytic spectrum (and bruges), a two-layer column's synthetic, angle
gathers, and bad input."""

import numpy as np
import pytest

from rockcem import synthetics as S
from rockcem.reflectivity import zoeppritz_pp


def ricker_formula(f, t):
    """w(t) = (1 - 2 pi^2 f^2 t^2) exp(-pi^2 f^2 t^2) (Ricker 1953), written out here."""
    x = (np.pi * f * t) ** 2
    return (1.0 - 2.0 * x) * np.exp(-x)


# --- depth to time ----------------------------------------------------------------------------

def test_twt_of_a_constant_velocity_column_is_2z_over_v():
    z = np.linspace(350.0, 4000.0, 74)
    t = S.depth_to_twt(z, np.full_like(z, 2.7))
    np.testing.assert_allclose(t, 2.0 * z / 2700.0, rtol=1e-14)
    # several columns at once, depth on the last axis
    t2 = S.depth_to_twt(z, np.array([[2.0], [3.0]]) * np.ones_like(z))
    np.testing.assert_allclose(t2, 2.0 * z / np.array([[2000.0], [3000.0]]), rtol=1e-14)


def test_datum_velocity_sets_the_time_to_the_first_depth():
    z = np.array([500.0, 1500.0])
    t = S.depth_to_twt(z, [3.0, 3.0], datum_velocity=1.5)
    np.testing.assert_allclose(t, [2 * 500 / 1500, 2 * 500 / 1500 + 2 * 1000 / 3000], rtol=1e-14)


def test_twt_of_a_linear_velocity_converges_at_second_order():
    """v = v0 + k z: t(z) = (2/k) ln(v(z)/v0) (k per s). The trapezoid on the slowness has an
    error that falls 4-fold when the sampling halves, and is 2.3e-6 s at 10 m over 3 km."""
    v0, k = 1.8, 0.6e-3                              # km/s, km/s per m
    exact = 2.0 / (k * 1000.0) * np.log((v0 + k * 3000.0) / v0)
    errors = []
    for n in (31, 61, 121, 301):
        z = np.linspace(0.0, 3000.0, n)
        errors.append(abs(S.depth_to_twt(z, v0 + k * z)[-1] - exact))
    np.testing.assert_allclose(errors[0] / errors[1], 4.0, rtol=0.01)
    np.testing.assert_allclose(errors[1] / errors[2], 4.0, rtol=0.01)
    assert errors[3] < 3e-6


# --- the wavelet -------------------------------------------------------------------------------

def test_ricker_formula_symmetry_and_bruges():
    w = S.ricker(30.0, 0.001)
    np.testing.assert_allclose(w.amplitude, ricker_formula(30.0, w.time), rtol=0, atol=1e-15)
    assert w.time.size % 2 == 1 and w.time[w.time.size // 2] == 0.0
    assert w.amplitude[w.time.size // 2] == 1.0
    np.testing.assert_array_equal(w.amplitude, w.amplitude[::-1])
    assert abs(w.amplitude[0]) < 1e-13                       # the tails are negligible
    filters = pytest.importorskip("bruges.filters")
    theirs = filters.ricker(None, None, 30.0, t=w.time)
    np.testing.assert_allclose(w.amplitude, theirs.amplitude, rtol=0, atol=1e-15)


def test_ricker_spectrum_is_the_analytic_one_and_peaks_at_the_frequency():
    """|W(nu)| = 2 nu^2 / (sqrt(pi) f^3) exp(-nu^2/f^2) (its Fourier transform), whose maximum
    is at nu = f."""
    f, dt = 25.0, 0.0005
    w = S.ricker(f, dt)
    n = 1 << 16                                             # zero-padded: 0.03 Hz resolution
    nu = np.fft.rfftfreq(n, dt)
    spectrum = np.abs(np.fft.rfft(w.amplitude, n)) * dt
    analytic = 2.0 * nu**2 / (np.sqrt(np.pi) * f**3) * np.exp(-(nu / f) ** 2)
    np.testing.assert_allclose(spectrum, analytic, rtol=0, atol=1e-12)
    assert abs(nu[np.argmax(spectrum)] - f) <= nu[1]


def test_ricker_length_and_wavelet_forms():
    w = S.ricker(25.0, 0.004, length=0.1)
    np.testing.assert_allclose(w.time, np.arange(-12, 13) * 0.004, atol=1e-15)
    depth, vp, rho = [0.0, 1000.0], [2.0, 2.5], [2.0, 2.0]
    by_frequency = S.synthetic_trace(depth, vp, None, rho, dt=0.002, wavelet=25.0)
    by_pair = S.synthetic_trace(depth, vp, None, rho, dt=0.002, wavelet=S.ricker(25.0, 0.002))
    by_array = S.synthetic_trace(depth, vp, None, rho, dt=0.002,
                                 wavelet=S.ricker(25.0, 0.002).amplitude)
    np.testing.assert_array_equal(by_pair.trace, by_frequency.trace)
    np.testing.assert_array_equal(by_array.trace, by_frequency.trace)


# --- reflectivity series and synthetics -------------------------------------------------------

def two_layers(step=10.0):
    """2.0 km/s to 1000 m, 2.5 km/s below, density 2.2: one interface between the samples at
    1000 and 1000 + step m, R = (2.5 - 2.0)/(2.5 + 2.0) = 1/9."""
    z = np.arange(0.0, 2000.0 + step / 2, step)
    vp = np.where(z <= 1000.0, 2.0, 2.5)
    return z, vp, 0.55 * vp, np.full_like(z, 2.2)


def test_two_layer_column_gives_one_scaled_wavelet_at_the_interface_time():
    z, vp, vs, rho = two_layers()
    # the interface lies at the mean of t(1000) = 1.0 s and t(1010) = 1.0 + 10 (1/2 + 1/2.5)/1000
    tau = 0.5 * (1.0 + 1.009)
    dt = 0.0005                                              # tau = 2009 dt: on the grid
    s = S.synthetic_trace(z, vp, vs, rho, dt=dt, wavelet=30.0)
    assert s.twt[0] == 0.0 and s.twt[-1] == pytest.approx(1.009 + 2.0 * 990 / 2500, abs=1e-12)
    np.testing.assert_allclose(s.twt, np.arange(s.twt.size) * dt, atol=1e-12)
    np.testing.assert_allclose(s.trace, ricker_formula(30.0, s.twt - tau) / 9.0, rtol=0,
                               atol=1e-12)
    assert np.count_nonzero(np.abs(s.reflectivity) > 1e-12) == 1   # (rounding splits 1e-13)


def test_linear_placement_keeps_the_sum_and_the_time_of_the_coefficient():
    z, vp, vs, rho = two_layers()
    tau = 0.5 * (1.0 + 1.009)
    for dt in (0.002, 0.0015, 0.004):                        # tau between grid samples
        twt, r = S.reflectivity_series(vp, rho, z, dt=dt)
        assert r.sum() == pytest.approx(1.0 / 9.0, abs=1e-15)
        assert (r * twt).sum() / r.sum() == pytest.approx(tau, abs=1e-12)
        assert np.count_nonzero(r) == 2
        twt, r = S.reflectivity_series(vp, rho, z, dt=dt, placement="nearest")
        assert np.count_nonzero(r) == 1 and r.sum() == pytest.approx(1.0 / 9.0, abs=1e-15)
        assert abs(twt[np.argmax(r)] - tau) <= dt / 2 + 1e-12


def test_leading_axes_are_columns_of_their_own():
    z, vp, vs, rho = two_layers()
    vps = np.stack([vp, 1.1 * vp])
    both = S.synthetic_trace(z, vps, None, rho, dt=0.001, wavelet=25.0)
    for i in range(2):
        one = S.synthetic_trace(z, vps[i], None, rho, dt=0.001, wavelet=25.0)
        j = int(round(one.twt[0] / 0.001))
        n = one.twt.size
        np.testing.assert_allclose(both.trace[i, j:j + n], one.trace, atol=1e-14)


def test_a_profile_within_one_sample_and_a_liquid_at_normal_incidence():
    """Two samples 1 m apart on a 4 ms grid: a grid of two samples holding R; a water layer
    (vs = 0) reflects at normal incidence and is refused at an angle."""
    twt, r = S.reflectivity_series([1.5, 2.0], [1.0, 2.0], [100.0, 101.0], dt=0.004)
    assert twt.size == 2 and r.sum() == pytest.approx(2.5 / 5.5, abs=1e-15)
    s = S.synthetic_trace([0.0, 100.0], [1.5, 2.0], [0.0, 1.0], [1.0, 2.0], dt=0.001,
                          wavelet=30.0)
    assert s.reflectivity.sum() == pytest.approx(2.5 / 5.5, abs=1e-15)
    with pytest.raises(ValueError, match="vs1"):
        S.synthetic_trace([0.0, 100.0], [1.5, 2.0], [0.0, 1.0], [1.0, 2.0], dt=0.001,
                          wavelet=30.0, angle=10.0)


def test_synthetic_at_an_angle_uses_the_exact_coefficient():
    z, vp, vs, rho = two_layers()
    tau = 0.5 * (1.0 + 1.009)
    s = S.synthetic_trace(z, vp, vs, rho, dt=0.0005, wavelet=30.0, angle=25.0)
    r = zoeppritz_pp(2.0, 1.1, 2.2, 2.5, 1.375, 2.2, 25.0).real
    np.testing.assert_allclose(s.trace, r * ricker_formula(30.0, s.twt - tau), atol=1e-12)


def test_angle_gather_around_a_depth():
    z, vp, vs, rho = two_layers()
    angles = np.array([0.0, 10.0, 20.0, 30.0])
    g = S.angle_gather(z, vp, vs, rho, at=1005.0, angles=angles, dt=0.0005, wavelet=30.0,
                       window=0.05)
    tau = 0.5 * (1.0 + 1.009)
    assert g.twt_at == pytest.approx(tau, abs=1e-12)        # 1005 m: half-way in time too
    assert g.gather.shape == (4, g.twt.size)
    assert g.twt[0] >= tau - 0.05 - 1e-12 and g.twt[-1] <= tau + 0.05 + 1e-12
    r = zoeppritz_pp(2.0, 1.1, 2.2, 2.5, 1.375, 2.2, angles).real
    np.testing.assert_allclose(g.gather, r[:, None] * ricker_formula(30.0, g.twt - tau),
                               atol=1e-12)
    normal = S.synthetic_trace(z, vp, vs, rho, dt=0.0005, wavelet=30.0)
    keep = np.isin(np.round(normal.twt / 0.0005), np.round(g.twt / 0.0005))
    np.testing.assert_allclose(g.gather[0], normal.trace[keep], atol=1e-14)


# --- inputs -----------------------------------------------------------------------------------

def test_bad_profiles_are_refused_by_name(expect_value_error):
    z, vp, vs, rho = two_layers()
    expect_value_error(lambda: S.depth_to_twt(z[::-1], vp), "depth")
    expect_value_error(lambda: S.depth_to_twt(z - 500.0, vp), "depth")
    expect_value_error(lambda: S.depth_to_twt([100.0], [2.0]), "depth")
    expect_value_error(lambda: S.depth_to_twt(z, vp * 1000.0), "vp")
    expect_value_error(lambda: S.depth_to_twt(z, vp[:-1]), "vp")
    expect_value_error(lambda: S.depth_to_twt(z, vp, datum_velocity=0.0), "datum_velocity")
    expect_value_error(lambda: S.reflectivity_series(vp, -rho, z, dt=0.001), "rho")
    expect_value_error(lambda: S.reflectivity_series(vp, rho, z, dt=0.0), "dt")
    expect_value_error(lambda: S.reflectivity_series(vp, rho, z, dt=1e-9), "dt")
    expect_value_error(lambda: S.reflectivity_series(vp, rho, z, dt=0.001, placement="x"),
                       "placement")
    expect_value_error(lambda: S.synthetic_trace(z, vp, None, rho, dt=0.001, wavelet=25.0,
                                                 angle=10.0), "vs")
    expect_value_error(lambda: S.synthetic_trace(z, vp, vs, rho, dt=0.001, wavelet=25.0,
                                                 angle=90.0), "angle")
    expect_value_error(lambda: S.synthetic_trace(z, vp, vs, rho, dt=0.001, wavelet=[1.0, 2.0]),
                       "wavelet")
    expect_value_error(lambda: S.angle_gather(z, vp, vs, rho, at=5000.0, angles=[0.0],
                                              dt=0.001, wavelet=25.0), "at")
    expect_value_error(lambda: S.angle_gather(z, vp, vs, rho, at=1000.0, angles=[0.0],
                                              dt=0.001, wavelet=25.0, window=-1.0), "window")


def test_bad_wavelets_are_refused_by_name(expect_value_error):
    expect_value_error(lambda: S.ricker(300.0, 0.002), "frequency")
    expect_value_error(lambda: S.ricker(0.0, 0.002), "frequency")
    expect_value_error(lambda: S.ricker(25.0, -0.002), "dt")
    expect_value_error(lambda: S.ricker(25.0, 0.002, length=0.001), "length")
    expect_value_error(lambda: S.ricker(1e-3, 1e-6), "dt")


def test_labelled_inputs_are_refused_with_the_way_out():
    pd = pytest.importorskip("pandas")
    z, vp, _, _ = two_layers()
    with pytest.raises(ValueError, match=r"vp is a pandas object.*to_numpy"):
        S.depth_to_twt(z, pd.Series(vp))
