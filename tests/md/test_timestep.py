"""The time step from the stiffest linearised contact of the current state."""

import numpy as np
import pytest

from md.contact import QUARTZ, GrainMaterial
from md.integrate import contact_time_step, highest_frequency, run_verlet
from md.space import Box

R = 2e-4
M = 4 / 3 * np.pi * R**3 * QUARTZ.density
BOX = Box(4e-3, 4e-3, 0.0, 4e-3)


def pair(xi):
    x = np.array([[1e-3, 1e-3, 1e-3], [1e-3, 1e-3, 1e-3 + 2 * R - xi]])
    return x, np.array([R, R]), np.array([[0, 1]])


def test_bound_lies_above_the_closed_form_modes_of_a_pair():
    """Two equal grains, overlap xi: the normal mode sqrt(k_n / m_f) with k_n = dF/dxi =
    2 E_f sqrt(R_f xi), and the tangential mode with both grains rolling, k_t (1/m_f +
    2 r^2 / I) = 7 k_t / m (I = 2/5 m r^2). The bound is above both and within a factor 2."""
    xi = 1e-6
    x, r, pairs = pair(xi)
    root = np.sqrt(R / 2 * xi)
    k_n, k_t = 2 * QUARTZ.E_f * root, 8 * QUARTZ.G_f * root
    omega_n = np.sqrt(k_n / (M / 2))
    omega_t = np.sqrt(7 * k_t / M)
    bound = highest_frequency(x, r, pairs, BOX, QUARTZ)
    assert bound >= max(omega_n, omega_t)
    assert bound <= 2 * max(omega_n, omega_t)
    # The normal mode is the Hertz linearisation: check dF/dxi by a finite difference.
    F = lambda s: 4 / 3 * QUARTZ.E_f * np.sqrt(R / 2) * s**1.5    # noqa: E731
    assert k_n == pytest.approx((F(xi * 1.001) - F(xi * 0.999)) / (0.002 * xi), rel=1e-6)


def test_time_step_shrinks_with_the_overlap_as_xi_to_the_minus_quarter():
    x1, r, pairs = pair(1e-7)
    x2, _, _ = pair(1.6e-6)
    dt1 = contact_time_step(x1, r, pairs, BOX, QUARTZ)
    dt2 = contact_time_step(x2, r, pairs, BOX, QUARTZ)
    assert dt1 / dt2 == pytest.approx(16 ** 0.25, rel=1e-9)


def test_impact_resolved_with_the_prescribed_restitution():
    """A head-on impact at 0.1 m/s with the time step of an impact at that speed (8 steps per
    period of the bound) keeps the restitution 0.9 within 0.5 % and spends >= 8 steps in
    contact."""
    v0 = 0.1
    x = np.array([[0.0, 0, 0], [2 * R + 1e-9, 0, 0]])
    v = np.array([[v0 / 2, 0, 0], [-v0 / 2, 0, 0]])
    w = np.zeros((2, 3))
    r = np.array([R, R])
    dt = contact_time_step(x, r, np.zeros((0, 2), int), Box(1.0, 1.0, -1.0, 1.0), QUARTZ,
                           impact_speed=v0)
    hist, in_contact = None, 0
    for _ in range(10_000):
        _, hist = run_verlet(x, v, w, r, np.array([[0, 1]]), QUARTZ, (1.0, 1.0), dt=dt,
                             n_steps=1, v_ref=v0, hist=hist)
        if x[1, 0] - x[0, 0] < 2 * R:
            in_contact += 1
        elif in_contact:
            break
    assert (v[1, 0] - v[0, 0]) / v0 == pytest.approx(0.9, rel=5e-3)
    assert in_contact >= 8


def test_energy_of_a_loaded_chain_is_conserved_at_the_state_time_step():
    """A column of five elastic, frictionless grains pressed between two frozen ones,
    oscillating about its loaded state: at the time step of the state the energy stays within
    1e-3 over 2e4 steps (stable), where a step 2.5 times larger than the Verlet limit 2 /
    omega_bound blows up."""
    elastic = GrainMaterial(44e9, 0.08, 2650.0, 0.0, 1.0)
    n = 7
    xi = 2e-6
    x = np.zeros((n, 3)) + 1e-3
    x[:, 2] = 1e-3 + np.arange(n) * (2 * R - xi)
    x[1:-1, 2] += np.random.default_rng(0).uniform(-2e-7, 2e-7, n - 2)
    r = np.full(n, R)
    pairs = np.array([[i, i + 1] for i in range(n - 1)])
    mobile = np.ones(n, bool)
    mobile[[0, -1]] = False
    dt = contact_time_step(x, r, pairs, BOX, elastic, mobile=mobile)

    def run(step, n_steps):
        from md._kernels_integrate import elastic_energy, verlet_run

        y, v, w = x.copy(), np.zeros_like(x), np.zeros_like(x)
        m = 4 / 3 * np.pi * r**3 * elastic.density
        energies = []
        for _ in range(n_steps // 100):
            verlet_run(y, v, w, r, m, pairs, np.zeros((n - 1, 3)), np.array([BOX.lx, BOX.ly]),
                       elastic.E_f, elastic.G_f, 0.0, 0.1, 0.0, step, 100, 0.0, 0,
                       np.zeros(0), -np.inf, np.zeros((0, 3)), 0.0, ~mobile)
            energies.append(0.5 * np.sum(m[:, None] * v * v)
                            + elastic_energy(y, r, pairs, np.array([BOX.lx, BOX.ly]),
                                             elastic.E_f))
        return np.array(energies)

    e = run(dt, 20_000)
    assert np.max(np.abs(e / e[0] - 1)) < 1e-3
    omega = highest_frequency(x, r, pairs, BOX, elastic, mobile=mobile)
    with np.errstate(all="ignore"):
        bad = run(5.0 / omega, 2_000)
    assert not np.all(np.isfinite(bad)) or bad.max() > 10 * e[0]


@pytest.mark.parametrize("kwargs,match", [
    (dict(steps_per_period=3), "steps_per_period"),
    (dict(impact_speed=-1.0), "impact_speed"),
])
def test_time_step_bad_input(kwargs, match):
    x, r, pairs = pair(1e-7)
    with pytest.raises(ValueError, match=match):
        contact_time_step(x, r, pairs, BOX, QUARTZ, **kwargs)


def test_time_step_needs_a_contact_or_an_impact():
    x, r, pairs = pair(-1e-5)                     # apart
    with pytest.raises(ValueError, match="impact_speed"):
        contact_time_step(x, r, pairs, BOX, QUARTZ)
