"""The burial functions over an ensemble (issue 32): per-member parameters as arrays, broadcast
against the depth nodes. Closed forms per member (T0 + G z, eq. 1's pressures, eq. B.1 and
eq. A.2 for a constant heating rate), the same values as one member at a time, and a bad
member refused by its index."""

import numpy as np
import pytest
from scipy.special import expi

from burial import linear_path, pressures, quartz_cement, smectite_fraction

MYR = 365.25 * 86400 * 1e6          # s per Myr (Julian year)
R_CAL = 1.986                        # cal/(mol K), Carcione et al. 2022 App. A
G0 = 9.80665                         # m/s2


def _members(m, seed=7):
    rng = np.random.default_rng(seed)
    return dict(G=rng.uniform(20.0, 40.0, m), S=rng.uniform(20.0, 200.0, m),
                T0=rng.uniform(0.0, 30.0, m), rho=rng.uniform(2.1, 2.7, m),
                rho_w=rng.uniform(1.0, 1.1, m), D=rng.lognormal(np.log(0.3), 0.3, m),
                C=rng.uniform(0.0, 0.4, m), Ts=rng.uniform(60.0, 90.0, m),
                a=rng.uniform(1e-22, 3e-22, m), b=rng.uniform(0.018, 0.026, m),
                phi0=rng.uniform(0.3, 0.42, m), f=rng.uniform(0.5, 0.9, m),
                n=rng.choice([1.0, 3.0, 5.0], m), E=rng.uniform(30.0, 40.0, m),
                c=rng.uniform(0.5e23, 2e23, m), r0=rng.uniform(0.8, 1.0, m))


def test_temperature_and_pressures_closed_form_per_member():
    """T = T0 + G z (eq. 2) and p = 1e-3 rho g z (eq. 1), member by member, on shared nodes."""
    p = _members(5)
    path = linear_path(p["G"], p["S"], p["T0"], 3000.0, depth_step=250.0)
    z = np.arange(0.0, 3000.0 + 1.0, 250.0)
    assert path.temperature.shape == path.time.shape == (5, z.size)
    np.testing.assert_allclose(path.temperature, p["T0"][:, None] + p["G"][:, None] * z / 1e3,
                               rtol=1e-15)
    np.testing.assert_allclose(path.time, z / p["S"][:, None], rtol=1e-15)
    pr = pressures(path, sediment_density=p["rho"], water_density=p["rho_w"])
    np.testing.assert_allclose(pr.confining, 1e-3 * p["rho"][:, None] * G0 * z, rtol=1e-15)
    np.testing.assert_allclose(pr.effective, 1e-3 * (p["rho"] - p["rho_w"])[:, None] * G0 * z,
                               rtol=1e-14, atol=1e-13)


def test_walderhaug_constant_heating_rate_closed_form_per_member():
    """Eq. B.1 integrated at a constant heating rate H = G S / 1000 from the onset Ts:
    phi_p = phi0 [1 - exp(-k (10^(b T) - 10^(b Ts)) / (b H ln 10))] above Ts, 0 below, with
    k = Mq a A0 / (rho_q phi0), A0 = (1 - C) 6 f / D (Carcione et al. 2022, eqs. B.1-B.6)."""
    p = _members(6)
    path = linear_path(p["G"], p["S"], p["T0"], 5000.0, depth_step=100.0)
    got = quartz_cement(path, p["phi0"], p["D"], p["f"], p["C"], rate_constant=p["a"],
                        rate_exponent=p["b"], start_temperature=p["Ts"])
    col = (lambda v: v[:, None])
    H = col(p["G"] * p["S"] / 1000.0) / MYR                              # degC/s
    k = col(60.09 * p["a"] * (1 - p["C"]) * 6 * p["f"] / (p["D"] / 10.0) / (2.65 * p["phi0"]))
    T = path.temperature
    x = k * (10.0 ** (col(p["b"]) * T) - 10.0 ** (col(p["b"] * p["Ts"]))) \
        / (col(p["b"]) * H * np.log(10.0))
    want = np.where(T > col(p["Ts"]), col(p["phi0"]) * -np.expm1(-x), 0.0)
    assert np.all(want[:, -1] > 0.01)            # the closed form is tested where cement grew
    np.testing.assert_allclose(got, want, rtol=1e-11, atol=1e-15)


def test_arrhenius_constant_heating_rate_closed_form_per_member():
    """Eq. A.2 of Carcione et al. 2022 (the integral of n-th order Arrhenius kinetics at a
    constant heating rate, with Ei) for members of other gradients, orders, energies."""
    m = 5
    p = _members(m)
    n = np.array([2.0, 3.0, 5.0, 5.0, 6.0])
    path = linear_path(p["G"][:m], 40.0, 15.0, 6000.0, depth_step=500.0)
    r = smectite_fraction(path, p["r0"], n, p["E"], p["c"])
    col = (lambda v: v[:, None])
    T, T0 = path.temperature[:, 1:] + 273.15, 15.0 + 273.15
    H = col(p["G"] * 0.04)                                            # degC/Myr
    E_R = col(p["E"] * 1000.0 / R_CAL)
    J = (E_R * (expi(-E_R / T) - expi(-E_R / T0)) + T * np.exp(-E_R / T)
         - T0 * np.exp(-E_R / T0)) / H
    mm = col(n - 1.0)
    want = (col(p["r0"]) ** -mm + mm * col(p["c"]) * J) ** (-1.0 / mm)
    np.testing.assert_allclose(r[:, 1:], want, rtol=1e-9)


def test_members_together_equal_one_at_a_time():
    """Forty random members in one call give each member's one-member result to 1e-12."""
    m = 40
    p = _members(m, seed=11)
    path = linear_path(p["G"], p["S"], p["T0"], 6000.0, depth_step=10.0)
    pr = pressures(path, sediment_density=p["rho"], water_density=p["rho_w"])
    phip = quartz_cement(path, p["phi0"], p["D"], p["f"], p["C"], rate_constant=p["a"],
                         rate_exponent=p["b"], start_temperature=p["Ts"])
    r = smectite_fraction(path, p["r0"], p["n"], p["E"], p["c"])
    for i in range(m):
        one = linear_path(p["G"][i], p["S"][i], p["T0"][i], 6000.0, depth_step=10.0)
        np.testing.assert_allclose(path.temperature[i], one.temperature, rtol=1e-12)
        np.testing.assert_allclose(path.time[i], one.time, rtol=1e-12)
        one_pr = pressures(one, sediment_density=p["rho"][i], water_density=p["rho_w"][i])
        for a, b in zip(pr, one_pr):
            np.testing.assert_allclose(a[i], b, rtol=1e-12)
        np.testing.assert_allclose(
            phip[i], quartz_cement(one, p["phi0"][i], p["D"][i], p["f"][i], p["C"][i],
                                   rate_constant=p["a"][i], rate_exponent=p["b"][i],
                                   start_temperature=p["Ts"][i]), rtol=1e-12, atol=1e-300)
        np.testing.assert_allclose(r[i], smectite_fraction(one, p["r0"][i], p["n"][i], p["E"][i],
                                                           p["c"][i]), rtol=1e-12)


@pytest.mark.parametrize("call, match", [
    (lambda: linear_path([30.0, np.nan, 25.0], 40.0, 15.0, 3000.0), r"gradient\[1\] is NaN"),
    (lambda: linear_path([30.0, 25.0, 300.0], 40.0, 15.0, 3000.0),
     r"gradient\[2\] 300 degC/km .* 915 degC"),
    (lambda: linear_path(30.0, [40.0, -1.0], 15.0, 3000.0),
     r"sedimentation_rate\[1\] must lie in \(0, inf\); got -1"),
    (lambda: linear_path(30.0, 40.0, [15.0, 288.15], 3000.0),
     r"surface_temperature\[1\] .*kelvin"),
    (lambda: pressures(linear_path([30.0, 31.0], 40.0, 15.0, 3000.0),
                       sediment_density=[2.5, 1.0]),
     r"water_density\[1\] must not exceed sediment_density\[1\]"),
    (lambda: pressures(linear_path([30.0, 31.0], 40.0, 15.0, 3000.0),
                       sediment_density=[2.5, 2.4, 2.3]), "do not broadcast"),
    (lambda: quartz_cement(linear_path([30.0, 31.0], 40.0, 15.0, 3000.0), 0.36, 0.3, 0.65,
                           start_temperature=[70.0, 800.0]),
     r"start_temperature\[1\] must lie in \[-100, 500\]; got 800"),
    (lambda: smectite_fraction(linear_path([30.0, 31.0], 40.0, 15.0, 3000.0), 0.9,
                               activation_energy=[36.0, -1.0]), r"activation_energy\[1\]"),
])
def test_bad_member_named_with_its_index(call, match):
    with pytest.raises(ValueError, match=match):
        call()
