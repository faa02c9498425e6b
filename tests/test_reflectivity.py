"""rockcem.reflectivity against bruges (a peer library, Apache-2.0) and against physics: energy
conservation of the full Zoeppritz solution, the normal-incidence limit, what holds beyond the
critical angle, the order of the linearisations' error, and AVO classes of textbook interfaces."""

import numpy as np
import pytest

from rockcem import reflectivity as R

bruges_reflection = pytest.importorskip("bruges.reflection.reflection")

# bruges adds 1e-12 km/s to both S velocities ("prevent singular matrix", its @vectorize); its
# inputs are given that much less so that both libraries compute the same interface.
BRUGES_VS_OFFSET = 1e-12


def random_interfaces(rng, n):
    """``n`` interfaces between isotropic solids (vs/vp in [0.3, 0.75]), either medium faster."""
    vp1, vp2 = rng.uniform(1.5, 6.0, n), rng.uniform(1.5, 6.0, n)
    vs1, vs2 = vp1 * rng.uniform(0.3, 0.75, n), vp2 * rng.uniform(0.3, 0.75, n)
    rho1, rho2 = rng.uniform(1.8, 2.8, n), rng.uniform(1.8, 2.8, n)
    return vp1, vs1, rho1, vp2, vs2, rho2


def with_bruges(func, media, angles, **kwargs):
    """``func`` of bruges on ``media`` (its S velocities less its offset), angles last."""
    vp1, vs1, rho1, vp2, vs2, rho2 = media
    out = func(vp1, vs1 - BRUGES_VS_OFFSET, rho1, vp2, vs2 - BRUGES_VS_OFFSET, rho2, angles,
               **kwargs)
    return out.T if isinstance(out, np.ndarray) else type(out)(*(np.transpose(o) for o in out))


def column(media):
    return [m[:, None] for m in media]


ANGLES = np.linspace(0.0, 89.0, 90)


# --- the exact solution against bruges and against the 4x4 solve -------------------------------

def test_zoeppritz_equals_bruges_before_and_conjugate_beyond_the_critical_angle(rng):
    media = random_interfaces(rng, 400)
    vp1, vs1, rho1, vp2, vs2, rho2 = media
    ours = R.zoeppritz_pp(*column(media), ANGLES)
    theirs = with_bruges(bruges_reflection.zoeppritz_rpp, media, ANGLES)
    p = np.sin(np.radians(ANGLES)) / vp1[:, None]
    before = (p * vp2[:, None] < 1.0) & (p * vs2[:, None] < 1.0)
    assert before.sum() > 5000 and (~before).sum() > 5000
    # bruges takes numpy's principal arcsin beyond critical: the exp(+i omega t) convention,
    # whose coefficients are the complex conjugates of those of Aki & Richards' exp(-i omega t)
    np.testing.assert_allclose(ours[before], theirs[before], rtol=0, atol=1e-10)
    np.testing.assert_allclose(ours[~before], np.conj(theirs[~before]), rtol=0, atol=1e-10)
    assert np.all(ours[before].imag == 0.0)


def test_closed_form_equals_the_4x4_solve_of_the_boundary_conditions(rng):
    media = random_interfaces(rng, 300)
    closed = R.zoeppritz_pp(*column(media), ANGLES)
    solved = R.zoeppritz_scattering(*column(media), ANGLES).rpp
    np.testing.assert_allclose(closed, solved, rtol=0, atol=1e-12)


def test_blocks_give_the_values_of_one_unblocked_call(rng, monkeypatch):
    """The blocked evaluation (slices along an inner axis, a long last axis) against a single
    block: the same numbers (to the last bits SIMD may round differently), in the same places."""
    media = [m.reshape(3, 4, 25) for m in random_interfaces(rng, 300)]
    args = [m[..., None] for m in media]
    whole = R.zoeppritz_pp(*args, ANGLES[:40])                # 12000 elements: one block
    monkeypatch.setattr(R, "_BLOCK", 97)                      # 2 rows of 40 per block
    np.testing.assert_allclose(R.zoeppritz_pp(*args, ANGLES[:40]), whole, rtol=0, atol=1e-15)
    monkeypatch.setattr(R, "_BLOCK", 7)                       # the last axis sliced
    np.testing.assert_allclose(R.zoeppritz_pp(*args, ANGLES[:40]), whole, rtol=0, atol=1e-15)
    flat = [m.ravel() for m in media]                         # one long axis, sliced
    np.testing.assert_allclose(R.zoeppritz_pp(*flat, ANGLES[9]), whole[..., 9].ravel(), rtol=0,
                               atol=1e-15)


def test_blocked_long_axis_equals_elementwise_scalars(rng, monkeypatch):
    media = random_interfaces(rng, 50)
    monkeypatch.setattr(R, "_BLOCK", 8)
    blocked = R.zoeppritz_pp(*media, 35.0)
    one_by_one = np.array([R.zoeppritz_pp(*(m[i] for m in media), 35.0) for i in range(50)])
    np.testing.assert_allclose(blocked, one_by_one, rtol=0, atol=1e-15)


# --- physics of the exact solution -------------------------------------------------------------

def test_energy_flux_is_conserved_at_every_angle(rng):
    """Sum of the vertical energy fluxes of the four scattered waves = the incident one, before
    and beyond the critical angles (an evanescent wave carries none)."""
    media = random_interfaces(rng, 300)
    s = R.zoeppritz_scattering(*column(media), ANGLES)
    total = s.rpp_flux + s.rps_flux + s.tpp_flux + s.tps_flux
    np.testing.assert_allclose(total, 1.0, rtol=0, atol=1e-12)
    for f in (s.rpp_flux, s.rps_flux, s.tpp_flux, s.tps_flux):
        assert np.all(f >= 0.0)
    p = np.sin(np.radians(ANGLES)) / media[0][:, None]
    beyond = p * media[3][:, None] > 1.0
    assert beyond.sum() > 1000
    assert np.all(s.tpp_flux[beyond] == 0.0)


def test_normal_incidence_is_the_impedance_contrast(rng):
    vp1, vs1, rho1, vp2, vs2, rho2 = random_interfaces(rng, 1000)
    z1, z2 = rho1 * vp1, rho2 * vp2
    r = R.zoeppritz_pp(vp1, vs1, rho1, vp2, vs2, rho2, 0.0)
    np.testing.assert_allclose(r.real, (z2 - z1) / (z2 + z1), rtol=0, atol=1e-15)
    assert np.all(r.imag == 0.0)


def test_identical_media_reflect_nothing():
    r = R.zoeppritz_pp(3.0, 1.6, 2.4, 3.0, 1.6, 2.4, ANGLES)
    # (near grazing the vertical slownesses, cos/v and sqrt(1/v**2 - p**2), round apart: 2e-13)
    np.testing.assert_allclose(r, 0.0, atol=1e-12)


def test_beyond_the_p_critical_angle_what_holds():
    """Beyond the P critical angle the transmitted P wave carries no energy, so |R_PP|^2 plus the
    fluxes of the converted S waves is 1: |R_PP| < 1 while a converted wave propagates (it is not
    total reflection). Only as the S velocities go to 0 (the acoustic limit) does |R_PP| -> 1, with
    1 - |R_PP| proportional to vs."""
    angles = np.array([45.0, 60.0, 80.0])            # beyond arcsin(2/3) = 41.8 degrees
    s = R.zoeppritz_scattering(2.0, 1.0, 2.2, 3.0, 1.5, 2.3, angles)
    np.testing.assert_allclose(np.abs(s.rpp) ** 2 + s.rps_flux + s.tps_flux, 1.0, atol=1e-13)
    assert np.all(np.abs(s.rpp) < 0.95) and np.all(s.rps_flux > 0.05)
    gaps = [1.0 - np.abs(R.zoeppritz_pp(2.0, 2.0 * k, 2.2, 3.0, 3.0 * k, 2.3, angles))
            for k in (1e-2, 1e-3, 1e-4)]
    assert np.all(gaps[-1] < 1e-6)
    np.testing.assert_allclose(gaps[0] / gaps[1], 10.0, rtol=0.15)
    np.testing.assert_allclose(gaps[1] / gaps[2], 10.0, rtol=0.01)


def test_critical_angle_against_snell_and_bruges():
    v1 = np.array([2.0, 2.5, 3.0, 3.0, 4.0])
    v2 = np.array([4.0, 3.5, 3.0, 2.0, 4.5])
    ours = R.critical_angle(v1, v2)
    theirs = np.array([bruges_reflection.critical_angles(a, b)[0] for a, b in zip(v1, v2)])
    np.testing.assert_allclose(ours[~np.isnan(theirs)], theirs[~np.isnan(theirs)], atol=1e-12)
    np.testing.assert_array_equal(ours[np.isnan(theirs)], 90.0)     # no critical angle: 90
    assert ours[0] == pytest.approx(30.0, abs=1e-12)
    # just beyond it, the transmitted P wave is evanescent; just before, it carries energy
    s = R.zoeppritz_scattering(2.0, 1.0, 2.2, 4.0, 2.0, 2.3, [29.99, 30.01])
    assert s.tpp_flux[0] > 0.0 and s.tpp_flux[1] == 0.0


# --- the linearisations ------------------------------------------------------------------------

def test_aki_richards_equals_bruges_before_the_critical_angle(rng):
    media = random_interfaces(rng, 300)
    vp1, vp2 = media[0], media[3]
    ours = R.aki_richards_pp(*column(media), ANGLES)
    theirs = with_bruges(bruges_reflection.akirichards, media, ANGLES)
    before = np.sin(np.radians(ANGLES)) * vp2[:, None] / vp1[:, None] < 1.0
    np.testing.assert_allclose(ours[before], theirs[before].real, rtol=0, atol=1e-10)
    assert np.all(np.isfinite(ours)) and ours.dtype == float


def test_aki_richards_error_scales_as_the_contrast_squared():
    """Against the exact coefficient, the linearisation's error falls 100-fold when the
    contrasts fall 10-fold (second order) at oblique incidence; at normal incidence, where A&R
    is A = (Z2 - Z1)/(Z2 + Z1) (1 + (dvp/vp)(drho/rho)/4), it is of third order."""
    angles = np.array([10.0, 20.0, 30.0, 40.0])
    errors = []
    for eps in (1e-2, 1e-3, 1e-4):
        media = (3.0, 1.5, 2.3, 3.0 * (1 + eps), 1.5 * (1 - 2 * eps), 2.3 * (1 + 0.5 * eps))
        errors.append(np.abs(R.aki_richards_pp(*media, angles)
                             - R.zoeppritz_pp(*media, angles).real))
        assert np.all(np.abs(R.zoeppritz_pp(*media, angles).real) > 0.3 * eps)  # not a zero
    np.testing.assert_allclose(errors[0] / errors[1], 100.0, rtol=0.1)
    np.testing.assert_allclose(errors[1] / errors[2], 100.0, rtol=0.01)
    normal = [abs(R.aki_richards_pp(*m, 0.0) - R.zoeppritz_pp(*m, 0.0).real)
              for m in ((3.0, 1.5, 2.3, 3.03, 1.5, 2.323), (3.0, 1.5, 2.3, 3.003, 1.5, 2.3023))]
    np.testing.assert_allclose(normal[0] / normal[1], 1000.0, rtol=0.03)


def test_shuey_equals_bruges_two_and_three_terms(rng):
    media = random_interfaces(rng, 300)
    angles = ANGLES[:60]
    three = with_bruges(bruges_reflection.shuey, media, angles)
    r0, rg, _ = with_bruges(bruges_reflection.shuey, media, angles, terms=True)
    np.testing.assert_allclose(R.shuey_pp(*column(media), angles), three, rtol=0, atol=1e-10)
    np.testing.assert_allclose(R.shuey_pp(*column(media), angles, terms=2), r0 + rg,
                               rtol=0, atol=1e-10)
    a, g = with_bruges(bruges_reflection.shuey, media, angles, return_gradient=True)
    terms = R.intercept_gradient(*media)
    np.testing.assert_allclose(terms.intercept, a, rtol=0, atol=1e-10)
    np.testing.assert_allclose(terms.gradient, g, rtol=0, atol=1e-10)


def test_intercept_gradient_curvature_by_hand():
    """2.0/1.0/2.2 over 3.0/1.5/2.3: dvp/vp = 0.4, dvs/vs = 0.4, drho/rho = 2/45, (vs/vp)^2 =
    1/4, so A = (0.4 + 2/45)/2 = 2/9, B = 0.2 - (2/45 + 0.8)/2 = -2/9, C = 0.2."""
    t = R.intercept_gradient(2.0, 1.0, 2.2, 3.0, 1.5, 2.3)
    assert t.intercept == pytest.approx(2 / 9, abs=1e-15)
    assert t.gradient == pytest.approx(-2 / 9, abs=1e-15)
    assert t.curvature == pytest.approx(0.2, abs=1e-15)
    assert R.shuey_pp(2.0, 1.0, 2.2, 3.0, 1.5, 2.3, 30.0, terms=2) == pytest.approx(
        2 / 9 - 2 / 9 * 0.25, abs=1e-15)


def test_shuey_intercept_is_the_normal_incidence_coefficient(rng):
    """With arithmetic means, (Z2 - Z1)/(Z2 + Z1) = A / (1 + (dvp/vp)(drho/rho)/4) exactly: A is
    the normal-incidence coefficient to second order, and equal to it without a density
    contrast. Shuey's R(0) is A."""
    vp1, vs1, rho1, vp2, vs2, rho2 = random_interfaces(rng, 500)
    a = R.intercept_gradient(vp1, vs1, rho1, vp2, vs2, rho2).intercept
    r0 = (rho2 * vp2 - rho1 * vp1) / (rho2 * vp2 + rho1 * vp1)
    dvp = (vp2 - vp1) / (0.5 * (vp1 + vp2))
    drho = (rho2 - rho1) / (0.5 * (rho1 + rho2))
    np.testing.assert_allclose(r0, a / (1.0 + dvp * drho / 4.0), rtol=1e-13, atol=1e-15)
    same = R.intercept_gradient(vp1, vs1, rho1, vp2, vs2, rho1).intercept
    np.testing.assert_allclose(same, (vp2 - vp1) / (vp2 + vp1), rtol=1e-13)
    np.testing.assert_allclose(R.shuey_pp(vp1, vs1, rho1, vp2, vs2, rho2, 0.0), a, atol=1e-16)


def test_gradient_is_the_slope_of_the_exact_coefficient_in_sin_squared():
    """dR/d(sin^2 theta) of the exact coefficient at normal incidence -> B, with an error of
    second order in the contrasts."""
    errors = []
    for eps in (1e-2, 1e-3):
        media = (3.0, 1.5, 2.3, 3.0 * (1 + eps), 1.5 * (1 + 2 * eps), 2.3 * (1 - eps))
        s2 = np.array([1e-4, 2e-4])
        r = R.zoeppritz_pp(*media, np.degrees(np.arcsin(np.sqrt(s2)))).real
        r0 = R.zoeppritz_pp(*media, 0.0).real
        # a three-point fit, R = r0 + b s2 + c s2^2
        b = (4 * (r[0] - r0) - (r[1] - r0)) / (2 * s2[0])
        errors.append(abs(b - R.intercept_gradient(*media).gradient))
    assert errors[1] < errors[0] / 50


# --- AVO classes -------------------------------------------------------------------------------

# Shale over gas sand, Vp and Vs in m/s and density in g/cm3: classes I, II, III of Hilterman
# (2001), Seismic Amplitude Interpretation, SEG/EAGE DISC 4, and class IV of Castagna & Swan
# (1997), The Leading Edge 16, 337-342 (as transcribed in A. Amato del Monte's "AVO Explorer"
# notebook, 2016).
TEXTBOOK = {
    "I": ((3094, 1515, 2.40), (4050, 2526, 2.21)),
    "II": ((2643, 1167, 2.29), (2781, 1665, 2.08)),
    "III": ((2192, 818, 2.16), (1542, 901, 1.88)),
    "IV": ((3240, 1620, 2.34), (1650, 1090, 2.07)),
}


def _km(layer):
    vp, vs, rho = layer
    return vp / 1000.0, vs / 1000.0, rho


@pytest.mark.parametrize("name", list(TEXTBOOK))
def test_textbook_gas_sands_get_their_class(name):
    shale, sand = (_km(x) for x in TEXTBOOK[name])
    t = R.intercept_gradient(*shale, *sand)
    code = R.avo_class(t.intercept, t.gradient)
    assert R.AVO_CLASSES[R.AVO_CLASS_CODES.index(int(code))] == name
    # and the exact coefficient behaves as the class says (Castagna & Swan 1997)
    r = R.zoeppritz_pp(*shale, *sand, np.arange(0.0, 31.0, 5.0)).real
    if name == "I":          # positive, decreasing with angle
        assert r[0] > 0.05 and np.all(np.diff(r) < 0)
    elif name == "II":       # near zero at normal incidence, growing negative
        assert abs(r[0]) < 0.03 and np.all(np.diff(r) < 0) and r[-1] < 2 * r[0]
    elif name == "III":      # negative, growing in magnitude
        assert r[0] < -0.1 and np.all(np.diff(r) < 0)
    else:                    # negative, shrinking in magnitude
        assert r[0] < -0.1 and np.all(np.diff(r) > 0)


def test_class_iip_reverses_polarity():
    """A sand just harder than Hilterman's class II shale: small positive A, negative B, and the
    exact coefficient changes sign within 30 degrees (Ross & Kinman 1995's 'p')."""
    shale, sand = _km(TEXTBOOK["II"][0]), (2.75, 1.6, 2.25)
    t = R.intercept_gradient(*shale, *sand)
    assert 0 < t.intercept < R.AVO_THRESHOLD and t.gradient < 0
    assert R.avo_class(t.intercept, t.gradient) == 2
    r = R.zoeppritz_pp(*shale, *sand, [0.0, 30.0]).real
    assert r[0] > 0 > r[1]


def test_avo_class_rule_at_its_edges():
    t = 0.03
    a = np.array([t, t - 1e-12, 0.0, -1e-12, -t + 1e-12, -t, -0.2, 0.0, 0.2, -0.2])
    b = np.array([-0.1, -0.1, -0.1, -0.1, -0.1, -0.1, 0.0, 0.0, 0.1, 1e-9])
    np.testing.assert_array_equal(R.avo_class(a, b, threshold=t),
                                  [1, 2, 2, 3, 3, 4, 5, 0, 0, 5])
    assert R.avo_class(0.05, -0.1, threshold=0.1) == 2
    assert R.avo_class(0.05, -0.1).dtype == np.int8
    assert R.AVO_CLASS_CODES == (1, 2, 3, 4, 5) and R.AVO_CLASSES == ("I", "IIp", "II", "III",
                                                                       "IV")


# --- inputs -----------------------------------------------------------------------------------

GOOD = (2.0, 1.0, 2.2, 3.0, 1.5, 2.3)


@pytest.mark.parametrize("index, value, name", [
    (0, -2.0, "vp1"), (1, 0.0, "vs1"), (2, 0.0, "rho1"), (3, 3000.0, "vp2"), (4, np.nan, "vs2"),
    (5, 2300.0, "rho2"), (1, 1.8, "vs1"), (4, 2.6, "vs2"), (0, np.inf, "vp1"),
])
def test_unphysical_media_are_refused_by_name(expect_value_error, index, value, name):
    args = list(GOOD)
    args[index] = value
    for f in (R.zoeppritz_pp, R.aki_richards_pp, R.shuey_pp, R.zoeppritz_scattering):
        expect_value_error(lambda: f(*args, 10.0), name)
    expect_value_error(lambda: R.intercept_gradient(*args), name)


def test_messages_say_the_range_and_the_likely_unit_slip():
    with pytest.raises(ValueError, match=r"vp2 must lie in \(0, 25\] km/s; got 3000; a velocity "
                                         r"in m/s\? \(give km/s\)"):
        R.zoeppritz_pp(2.0, 1.0, 2.2, 3000.0, 1.5, 2.3, 10.0)
    with pytest.raises(ValueError, match=r"vs1 must be below vp1 \* sqrt\(3\)/2"):
        R.zoeppritz_pp(2.0, 1.8, 2.2, 3.0, 1.5, 2.3, 10.0)


@pytest.mark.parametrize("angle", [90.0, -1.0, 120.0, np.nan, "30"])
def test_angles_outside_0_90_are_refused(expect_value_error, angle):
    for f in (R.zoeppritz_pp, R.aki_richards_pp, R.shuey_pp):
        expect_value_error(lambda: f(*GOOD, angle), "angle")


def test_other_arguments_are_checked(expect_value_error):
    expect_value_error(lambda: R.shuey_pp(*GOOD, 10.0, terms=4), "terms")
    expect_value_error(lambda: R.shuey_pp(*GOOD, 10.0, terms=True), "terms")
    expect_value_error(lambda: R.avo_class(0.1, -0.1, threshold=0.0), "threshold")
    expect_value_error(lambda: R.avo_class(np.nan, -0.1), "intercept")
    expect_value_error(lambda: R.avo_class(0.1, np.inf), "gradient")
    expect_value_error(lambda: R.critical_angle(-1.0, 2.0), "v1")
    expect_value_error(lambda: R.zoeppritz_pp(*GOOD[:5], [2.3, 2.4], [10.0, 20.0, 30.0]),
                       "angle")


def test_never_nan_up_to_grazing(rng):
    """Up to the largest float below 90 degrees (where 1/vp1**2 - p**2 rounds below 0 for about
    a quarter of the velocities: the incident vertical slowness is cos(angle)/vp1), with no
    warning (pytest makes RuntimeWarning an error); and R_PP -> -1 at grazing incidence."""
    media = random_interfaces(rng, 2000)
    angles = np.concatenate([ANGLES, [89.9, 89.999999, np.nextafter(90.0, 0.0)]])
    for f in (R.zoeppritz_pp, R.aki_richards_pp, R.shuey_pp, R.zoeppritz_scattering):
        out = f(*column(media), angles)
        for a in (out if isinstance(out, tuple) else (out,)):
            assert np.all(np.isfinite(a))
    grazing = R.zoeppritz_pp(*media, np.nextafter(90.0, 0.0))
    np.testing.assert_allclose(grazing, -1.0, atol=1e-6)


# --- labelled inputs --------------------------------------------------------------------------

def test_xarray_inputs_give_a_dataarray_with_the_angle_last():
    xr = pytest.importorskip("xarray")
    depth = [1000.0, 2000.0, 3000.0]
    vp2 = xr.DataArray([2.8, 3.0, 3.4], dims="depth", coords={"depth": depth},
                       attrs={"units": "km s-1"})
    angle = xr.DataArray([0.0, 15.0, 30.0], dims="angle", coords={"angle": [0.0, 15.0, 30.0]})
    r = R.zoeppritz_pp(2.5, 1.2, 2.3, vp2, 1.5, 2.25, angle)
    assert r.dims == ("depth", "angle") and r.attrs["units"] == "1"
    expected = R.zoeppritz_pp(2.5, 1.2, 2.3, vp2.values[:, None], 1.5, 2.25, angle.values)
    np.testing.assert_array_equal(r.values, expected)
    terms = R.intercept_gradient(2.5, 1.2, 2.3, vp2, 1.5, 2.25)
    assert terms.gradient.dims == ("depth",)
    assert R.avo_class(terms.intercept, terms.gradient).dtype == np.int8


def test_pandas_inputs_are_paired_by_label():
    pd = pytest.importorskip("pandas")
    vp2 = pd.Series([2.8, 3.0, 3.4], index=[1000.0, 2000.0, 3000.0])
    rho2 = pd.Series([2.25, 2.2, 2.3], index=[1000.0, 2000.0, 3000.0])
    shuffled = rho2.iloc[[2, 0, 1]]
    r = R.shuey_pp(2.5, 1.2, 2.3, vp2, 1.5, shuffled, 20.0)
    assert list(r.index) == [1000.0, 2000.0, 3000.0]
    np.testing.assert_array_equal(r.to_numpy(), R.shuey_pp(2.5, 1.2, 2.3, vp2.to_numpy(), 1.5,
                                                            rho2.to_numpy(), 20.0))
