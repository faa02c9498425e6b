"""Quartz cement and smectite→illite kinetics against independent solutions (Carcione et al. 2022,
App. A and B) and their stiff and extreme cases."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.special import expi

from burial import (illite_fraction, intergranular_volume, linear_path, path_from_nodes,
                    pressures, quartz_cement, sandstone_porosity, smectite_fraction)

MYR = 365.25 * 86400 * 1e6          # s per Myr (Julian year)
R_CAL = 1.986                        # cal/(mol K), Carcione et al. 2022 App. A
# Sect. 6.2 sandstone: phi0 0.36, D 0.03 cm, a 1.98e-22 mol/(cm2 s), b 0.022/degC, rho 2.65,
# Mq 60.09 g/mol, f 0.65, V 1 cm3.
PHI0, D_MM, F = 0.36, 0.3, 0.65
K_WALDERHAUG = 60.09 * 1.98e-22 * (6 * F / 0.03) / (2.65 * PHI0)     # 1/s


def walderhaug_rhs(T_of_t, k=K_WALDERHAUG, phi0=PHI0, b=0.022):
    return lambda t, y: [k * MYR * (phi0 - y[0]) * 10.0 ** (b * T_of_t(t))]


def test_carcione2022_fig13_cement_radau():
    """Cement along the worked example (G = 30 degC/km, S = 40 m/Myr, T0 = 15 degC) against a
    stiff ODE solver at tight tolerance."""
    p = linear_path(30.0, 40.0, 15.0, 5000.0, depth_step=250.0)
    phip = quartz_cement(p, PHI0, D_MM, F)
    sol = solve_ivp(walderhaug_rhs(lambda t: 15.0 + 1.2 * t), (0, p.time[-1]), [0.0],
                    method="Radau", t_eval=p.time, rtol=1e-12, atol=1e-16)
    np.testing.assert_allclose(phip[1:], sol.y[0][1:], rtol=1e-8)


def test_eq_b1_stepping_is_reproduced():
    """Eq. B.1 stepped at dt = 0.1 Myr (the method of the source) is exact for constant H."""
    H, T0, dt = 1.2, 15.0, 0.1
    t = np.arange(0, 125.0 + dt / 2, dt)
    T = T0 + H * t
    phip = np.zeros_like(t)
    c = K_WALDERHAUG * MYR / (0.022 * H * np.log(10))
    for n in range(len(t) - 1):
        phip[n + 1] = PHI0 - (PHI0 - phip[n]) * np.exp(-c * (10 ** (0.022 * T[n + 1])
                                                            - 10 ** (0.022 * T[n])))
    p = path_from_nodes(t[::50], 40.0 * t[::50], T[::50])
    np.testing.assert_allclose(quartz_cement(p, PHI0, D_MM, F), phip[::50], rtol=1e-10)


@pytest.mark.parametrize("step_m", [0.04, 4.0, 40.0, 400.0])
def test_step_size_invariance(step_m):
    """Time steps 0.001 to 10 Myr (S = 40 m/Myr) give the same cement and illite."""
    coarse = linear_path(30.0, 40.0, 15.0, 4000.0, depth_step=400.0)
    fine = linear_path(30.0, 40.0, 15.0, 4000.0, depth_step=step_m)
    stride = int(round(400.0 / step_m))
    np.testing.assert_allclose(quartz_cement(fine, PHI0, D_MM, F)[::stride],
                               quartz_cement(coarse, PHI0, D_MM, F), rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(smectite_fraction(fine, 0.99)[::stride],
                               smectite_fraction(coarse, 0.99), rtol=1e-11)


def test_one_or_thousand_pieces():
    t = np.linspace(0, 100, 1001)
    T = 15 + 1.2 * t
    many = path_from_nodes(t, 40 * t, T)
    one = path_from_nodes([0, 100], [0, 4000], [15, 135])
    assert quartz_cement(many, PHI0, D_MM, F)[-1] == pytest.approx(
        quartz_cement(one, PHI0, D_MM, F)[-1], rel=1e-12)
    assert smectite_fraction(many, 0.99)[-1] == pytest.approx(smectite_fraction(one, 0.99)[-1],
                                                              rel=1e-11)


def eq_a2(T_c, H, r0=0.99, n=5, E=36000.0, c=1.217e23, T0_c=15.0):
    """Eq. A.2 of Carcione et al. 2022 with Ei from scipy (the constant-heating-rate solution)."""
    T, T0 = T_c + 273.15, T0_c + 273.15
    m = n - 1
    x, x0 = -E / (R_CAL * T), -E / (R_CAL * T0)
    J = (E / R_CAL * (expi(x) - expi(x0)) + T * np.exp(x) - T0 * np.exp(x0)) / H
    return m ** (-1 / m) * (r0 ** -m / m + c * J) ** (-1 / m)


@pytest.mark.parametrize("gradient", [20.0, 30.0, 40.0])
def test_carcione2022_fig8_illite_closed_form(gradient):
    """Fig. 8: illite for three gradients, against the closed form A.2 and a Radau solution."""
    p = linear_path(gradient, 40.0, 15.0, 6000.0, depth_step=500.0)
    r = smectite_fraction(p, 0.99)
    H = gradient * 0.04
    np.testing.assert_allclose(r[1:], eq_a2(p.temperature[1:], H), rtol=1e-9)
    E_R = 36000.0 / R_CAL
    sol = solve_ivp(lambda t, y: [-1.217e23 * y[0] ** 5 * np.exp(-E_R / (288.15 + H * t))],
                    (0, p.time[-1]), [0.99], method="Radau", t_eval=p.time, rtol=1e-12,
                    atol=1e-14)
    np.testing.assert_allclose(r, sol.y[0], rtol=1e-8)


def test_carcione2022_fig8_higher_gradient_more_illite():
    ill = [illite_fraction(linear_path(g, 40.0, 15.0, 5000.0, depth_step=100.0), 0.99)
           for g in (20.0, 30.0, 40.0)]
    assert np.all(ill[0][1:] < ill[1][1:]) and np.all(ill[1][1:] < ill[2][1:])
    assert np.all(np.diff(ill[1]) >= 0)


def test_carcione2022_fig14_quartz_fraction_and_grain_size():
    """Fig. 14: less detrital quartz, less cement; f/D enters only as a ratio (eq. B.2)."""
    p = linear_path(30.0, 40.0, 15.0, 4000.0, depth_step=100.0)
    assert np.all(quartz_cement(p, PHI0, D_MM, 0.4)[1:] < quartz_cement(p, PHI0, D_MM, 1.0)[1:])
    np.testing.assert_allclose(quartz_cement(p, PHI0, 0.6, 1.0), quartz_cement(p, PHI0, 0.3, 0.5),
                               rtol=1e-13)


def test_carcione2022_fig15_heating_rate():
    """Fig. 15: at a given depth the slowest heating (oldest rock) has the most cement."""
    out = []
    for H in (0.4, 1.2, 2.0):
        S = H / 30.0 * 1000.0          # m/Myr at G = 30 degC/km
        out.append(quartz_cement(linear_path(30.0, S, 15.0, 4000.0, depth_step=100.0), PHI0,
                                 D_MM, F))
    assert np.all(out[0][5:] > out[1][5:]) and np.all(out[1][5:] > out[2][5:])


def test_carcione2022_fig13_porosity_zero_near_4450m():
    """With IGV compaction (IGVi 0.2, beta 0.01/MPa) the pores fill near 4.45 km."""
    p = linear_path(30.0, 40.0, 15.0, 5000.0, depth_step=5.0)
    phip = quartz_cement(p, PHI0, D_MM, F)
    igv = intergranular_volume(PHI0, pressures(p).max_effective)
    s = sandstone_porosity(igv, phip)
    assert np.all(s.porosity >= 0.0)
    first = p.depth[np.argmax(s.pore_filled)]
    assert 4350.0 < first < 4550.0
    np.testing.assert_array_equal(s.porosity[s.pore_filled], 0.0)


# --- hiatus, uplift and cooling -------------------------------------------------------------------
def test_hiatus_uplift_cooling_against_radau():
    t = np.array([0.0, 50.0, 60.0, 80.0, 90.0])
    T = np.array([15.0, 95.0, 95.0, 55.0, 140.0])
    z = np.array([0.0, 2500.0, 2500.0, 1500.0, 3500.0])
    p = path_from_nodes(t, z, T)
    T_of = lambda s: np.interp(s, t, T)  # noqa: E731
    sol = solve_ivp(walderhaug_rhs(T_of), (0, 90), [0.0], method="Radau", t_eval=t, rtol=1e-12,
                    atol=1e-16, max_step=0.5)
    np.testing.assert_allclose(quartz_cement(p, PHI0, D_MM, F)[1:], sol.y[0][1:], rtol=1e-7)
    pe = pressures(p)
    assert pe.max_effective[3] == pe.max_effective[2] > pe.effective[3]   # uplift: no decompaction
    r = smectite_fraction(p, 0.99)
    assert np.all(np.diff(r) <= 0)


def test_start_temperature():
    p = linear_path(30.0, 40.0, 15.0, 4000.0, depth_step=100.0)
    a = quartz_cement(p, PHI0, D_MM, F, start_temperature=80.0)
    assert np.all(a[p.temperature <= 80.0] == 0.0)
    assert np.all(a <= quartz_cement(p, PHI0, D_MM, F))
    # Independent: the integral restarts at 80 degC, where the piecewise path crosses it.
    t80 = (80.0 - 15.0) / 1.2
    sol = solve_ivp(walderhaug_rhs(lambda t: 15.0 + 1.2 * t), (t80, p.time[-1]), [0.0],
                    method="Radau", rtol=1e-12, atol=1e-16)
    assert a[-1] == pytest.approx(sol.y[0][-1], rel=1e-8)


# --- stiff and extreme cases ---------------------------------------------------------------------
@pytest.mark.parametrize("H", [0.01, 1.2, 10.0, 100.0])
@pytest.mark.parametrize("D", [0.01, 0.3, 10.0])
@pytest.mark.parametrize("coating", [0.0, 0.5, 1.0])
def test_quartz_bounded_and_monotone(H, D, coating):
    t = np.linspace(0, 235.0 / H, 200)
    p = path_from_nodes(t, 40.0 * t, 15.0 + H * t)            # up to 250 degC
    phip = quartz_cement(p, PHI0, D, F, coating)
    assert np.all(np.isfinite(phip)) and np.all(phip >= 0) and np.all(phip <= PHI0)
    assert np.all(np.diff(phip) >= 0)
    if coating == 1.0:
        assert np.all(phip == 0.0)


@pytest.mark.parametrize("r0", [0.0, 0.3, 1.0])
@pytest.mark.parametrize("H", [0.01, 1.2, 100.0])
@pytest.mark.parametrize("order", [1.0, 2.0, 5.0])
def test_smectite_bounded_and_monotone(r0, H, order):
    t = np.linspace(0, 235.0 / H, 200)
    p = path_from_nodes(t, 40.0 * t, 15.0 + H * t)
    r = smectite_fraction(p, r0, order)
    assert np.all(np.isfinite(r)) and np.all(r >= 0) and np.all(r <= r0)
    assert np.all(np.diff(r) <= 0)


def test_reaction_nearly_complete_no_underflow_trouble():
    t = np.linspace(0, 1000, 50)
    # Held at 250 degC from the first node on: that node lies buried (250 degC at depth 0 would
    # be a surface in kelvin, refused).
    p = path_from_nodes(t, 8000.0 + 40 * t, np.full(50, 250.0))
    r = smectite_fraction(p, 0.99, order=1)
    assert r[-1] < 1e-100 and np.all(np.isfinite(r))


@pytest.mark.parametrize("call,match", [
    (lambda: path_from_nodes([0, 1, 1], [0, 1, 2], [15, 16, 17]), "time"),
    (lambda: path_from_nodes([0, 1, 2], [0, -1, 2], [15, 16, 17]), "depth"),
    (lambda: path_from_nodes([0, 1, 2], [0, 1, 2], [288, 300, 650]), "kelvin"),
    (lambda: path_from_nodes([0, 1, 2], [0, 1, 2], [-300, 16, 17]), "temperature"),
    (lambda: path_from_nodes([0, np.nan, 2], [0, 1, 2], [15, 16, 17]), "time"),
    (lambda: path_from_nodes([0, 1, 2], [0, 1], [15, 16, 17]), "broadcast"),
    (lambda: linear_path(-30.0, 40.0, 15.0, 1000.0), "gradient"),
    (lambda: quartz_cement(linear_path(30, 40, 15, 1000), 0.36, 0.0, 0.65), "grain_size"),
    (lambda: quartz_cement(linear_path(30, 40, 15, 1000), 0.36, 0.3, 1.5), "quartz_fraction"),
    (lambda: quartz_cement(linear_path(30, 40, 15, 1000), 0.36, 0.3, 0.6, 2.0), "clay_coating"),
    (lambda: quartz_cement("path", 0.36, 0.3, 0.65), "path"),
    (lambda: smectite_fraction(linear_path(30, 40, 15, 1000), 1.2), "r0"),
    (lambda: smectite_fraction(linear_path(30, 40, 15, 1000), 0.9, order=0.5), "order"),
])
def test_bad_input(call, match):
    with pytest.raises(ValueError, match=match):
        call()
