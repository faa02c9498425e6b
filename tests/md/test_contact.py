"""Contact laws of the MD engine against closed forms (García & Medina Sect. III A; Johnson)."""

import numpy as np
import pytest

from md._kernels_contact import pair_force
from md.contact import (QUARTZ, GrainMaterial, contact_time, damping_parameter, hertz_energy,
                        hertz_force, pair_force_reference, restitution)
from md.integrate import run_verlet, stable_time_step

R = 1.9e-4                        # m: grains of 0.018-0.020 cm radius (the paper's sample)
M = 4 / 3 * np.pi * R**3 * QUARTZ.density


def test_quartz_table_i():
    assert QUARTZ.shear_modulus == 44e9 and QUARTZ.poisson_ratio == 0.08
    assert QUARTZ.density == 2650.0 and QUARTZ.friction == 0.3 and QUARTZ.restitution == 0.9
    E = 2 * 44e9 * 1.08
    assert QUARTZ.E_f == pytest.approx(E / (2 * (1 - 0.08**2)), rel=1e-15)
    # kappa_s = 4 a G / (2 - nu) of the paper equals 8 G_f a.
    assert 8 * QUARTZ.G_f == pytest.approx(4 * 44e9 / (2 - 0.08), rel=1e-15)


def test_force_is_minus_energy_gradient():
    R_f = R / 2
    xi = np.geomspace(1e-9, 1e-6, 7)
    h = xi * 1e-6
    dU = (hertz_energy(xi + h, R_f, QUARTZ.E_f) - hertz_energy(xi - h, R_f, QUARTZ.E_f)) / (2 * h)
    np.testing.assert_allclose(dU, hertz_force(xi, R_f, QUARTZ.E_f), rtol=1e-8)
    # The kernel at rest gives the Hertz force along n.
    for x in xi:
        f = pair_force(x, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, R_f, M / 2, QUARTZ.E_f,
                       QUARTZ.G_f, 0.1, 0.1, 0.3, 1e-8)
        assert f[0] == pytest.approx(float(hertz_force(x, R_f, QUARTZ.E_f)), rel=1e-13)
        assert f[6] == pytest.approx(f[0], rel=1e-15)


def test_kernel_matches_python_twin(rng):
    beta = damping_parameter(QUARTZ.restitution)
    for _ in range(50):
        n = rng.normal(size=3)
        n /= np.linalg.norm(n)
        vr = rng.normal(scale=0.05, size=3)
        zeta = rng.normal(scale=1e-8, size=3)
        xi = rng.uniform(1e-9, 1e-6)
        ref_f, ref_z, ref_fn = pair_force_reference(xi, n, vr, zeta, R / 2, M / 2, QUARTZ, 0.1,
                                                    1e-8)
        out = pair_force(xi, *n, *vr, *zeta, R / 2, M / 2, QUARTZ.E_f, QUARTZ.G_f, beta, 0.1,
                         QUARTZ.friction, 1e-8)
        np.testing.assert_allclose(out[:3], ref_f, rtol=1e-12, atol=1e-12 * abs(ref_fn))
        np.testing.assert_allclose(out[3:6], ref_z, rtol=1e-12, atol=1e-20)
        assert out[6] == pytest.approx(ref_fn, rel=1e-12)


def test_force_loop_matches_the_python_twin_pair_by_pair(rng):
    """``accumulate_forces`` with the per-pair damping of ``pair_damping`` (computed once per
    list) equals the plain-Python twin summed over the pairs: forces (j gets f, i gets -f) and
    torques -r (n x f_t) on both grains, with spins in the contact-point velocity."""
    from md._kernels_contact import accumulate_forces, pair_damping

    beta, v_ref, dt = damping_parameter(QUARTZ.restitution), 0.1, 1e-8
    n_grains = 12
    r = rng.uniform(1.8e-4, 2.0e-4, n_grains)
    x = rng.uniform(0.0, 6e-4, (n_grains, 3))                  # a dense clump: many overlaps
    v = rng.normal(scale=0.05, size=(n_grains, 3))
    w = rng.normal(scale=50.0, size=(n_grains, 3))
    m = 4 / 3 * np.pi * r**3 * QUARTZ.density
    pairs = np.array([(i, j) for i in range(n_grains) for j in range(i + 1, n_grains)], np.int32)
    hist = rng.normal(scale=1e-8, size=(len(pairs), 3))
    box_l = np.array([1.0, 1.0])                                # wide: no periodic images
    damping = pair_damping(r, m, pairs, QUARTZ.E_f, beta, v_ref)
    force, torque = np.zeros((n_grains, 3)), np.zeros((n_grains, 3))
    new_hist = hist.copy()
    accumulate_forces(x, v, w, r, pairs, new_hist, box_l, QUARTZ.E_f, QUARTZ.G_f, damping,
                      QUARTZ.friction, dt, force, torque)
    f_ref, t_ref, touching = np.zeros_like(force), np.zeros_like(torque), 0
    for p, (i, j) in enumerate(pairs):
        d = x[j] - x[i]
        xi = r[i] + r[j] - np.linalg.norm(d)
        R_f, m_f = r[i] * r[j] / (r[i] + r[j]), m[i] * m[j] / (m[i] + m[j])
        k = 4 / 3 * QUARTZ.E_f * np.sqrt(R_f)
        assert damping[p] == pytest.approx(beta * m_f**0.4 * v_ref**-0.2 * k**0.6, rel=1e-14)
        if xi <= 0:
            assert np.all(new_hist[p] == 0.0)
            continue
        touching += 1
        n = d / np.linalg.norm(d)
        vr = v[j] - v[i] - np.cross(r[i] * w[i] + r[j] * w[j], n)
        f, z, fn = pair_force_reference(xi, n, vr, hist[p], R_f, m_f, QUARTZ, v_ref, dt)
        np.testing.assert_allclose(new_hist[p], z, rtol=1e-12, atol=1e-20)
        f_ref[j] += f
        f_ref[i] -= f
        c = np.cross(n, f - fn * n)
        t_ref[j] -= r[j] * c
        t_ref[i] -= r[i] * c
    assert touching >= 10
    scale = np.abs(f_ref).max()
    np.testing.assert_allclose(force, f_ref, rtol=1e-12, atol=1e-12 * scale)
    np.testing.assert_allclose(torque, t_ref, rtol=1e-12, atol=1e-12 * scale * r.max())


def head_on(material, v0, steps_per_contact=50, v_ref=None):
    """Two equal spheres approaching head-on; returns (restitution, contact time)."""
    x = np.array([[0.0, 0, 0], [2 * R + 1e-9, 0, 0]])
    v = np.array([[v0 / 2, 0, 0], [-v0 / 2, 0, 0]])
    w = np.zeros((2, 3))
    r = np.array([R, R])
    dt = stable_time_step(material, R, R, v0, steps_per_contact=steps_per_contact)
    pairs = np.array([[0, 1]])
    steps_in_contact = 0
    hist = None
    for _ in range(100 * steps_per_contact):
        _, hist = run_verlet(x, v, w, r, pairs, material, (1.0, 1.0), dt=dt, n_steps=1,
                             v_ref=v_ref or v0, hist=hist)
        gap = x[1, 0] - x[0, 0] - 2 * R
        if gap < 0:
            steps_in_contact += 1
        elif steps_in_contact:
            break
    return (v[1, 0] - v[0, 0]) / v0, steps_in_contact * dt


def test_head_on_restitution_within_one_percent():
    e, _ = head_on(QUARTZ, 0.1)
    assert e == pytest.approx(0.9, rel=0.01)
    # Viscoelastic (Kuwabara-Kono) damping: faster impacts dissipate more.
    e_fast, _ = head_on(QUARTZ, 1.0, v_ref=0.1)
    assert e_fast < e


def test_hertz_contact_time():
    elastic = GrainMaterial(44e9, 0.08, 2650.0, 0.3, 1.0)
    e, t = head_on(elastic, 0.1, steps_per_contact=200)
    assert e == pytest.approx(1.0, abs=1e-5)
    t_c = contact_time(0.1, R / 2, M / 2, elastic.E_f)
    assert t == pytest.approx(t_c, rel=0.02)


def test_dimensionless_restitution():
    assert restitution(0.0) == pytest.approx(1.0, abs=1e-9)
    b = damping_parameter(0.9)
    assert restitution(b) == pytest.approx(0.9, abs=1e-9)
    assert restitution(2 * b) < 0.9


def test_tangential_spring_then_coulomb_slip():
    """Below mu F_n the Mindlin spring holds (F_t = kappa_s zeta); above, the contact slides with
    the force capped at mu F_n."""
    xi, R_f, dt = 2e-7, R / 2, 1e-8
    fn = float(hertz_force(xi, R_f, QUARTZ.E_f))
    kappa_s = 8 * QUARTZ.G_f * np.sqrt(R_f * xi)
    zeta = np.zeros(3)
    vt = 1e-2                                  # m/s tangential, no normal motion, no damping
    beta = 0.0
    ft_history = []
    for k in range(1, 1000):
        out = pair_force(xi, 0.0, 0.0, 1.0, vt, 0.0, 0.0, *zeta, R_f, M / 2, QUARTZ.E_f,
                         QUARTZ.G_f, beta, 0.1, QUARTZ.friction, dt)
        zeta = np.array(out[3:6])
        ft_history.append(-out[0])
        if k * vt * dt * kappa_s < 0.99 * QUARTZ.friction * fn:
            assert -out[0] == pytest.approx(kappa_s * k * vt * dt, rel=1e-12)
    assert max(ft_history) == pytest.approx(QUARTZ.friction * fn, rel=1e-12)
    assert ft_history[-1] == pytest.approx(QUARTZ.friction * fn, rel=1e-12)


def test_energy_conserved_without_damping():
    """No damping, no friction: a pair bouncing in a periodic box for 1e5 steps keeps its energy
    (velocity Verlet: bounded oscillation, no drift)."""
    elastic = GrainMaterial(44e9, 0.08, 2650.0, 0.0, 1.0)
    L = 2.5 * 2 * R
    x = np.array([[0.0, 0.0, 0.0], [L / 2, 0.0, 0.0]])
    v = np.array([[0.05, 0.01, 0.0], [-0.05, -0.01, 0.0]])
    w = np.zeros((2, 3))
    r = np.array([R, R])
    dt = stable_time_step(elastic, R, R, 0.2)
    energy, _ = run_verlet(x, v, w, r, np.array([[0, 1]]), elastic, (L, L), dt=dt,
                           n_steps=100_000, v_ref=0.1, record_every=100)
    assert energy.size == 1000
    # Stated bound: relative energy error below 2e-4 at 50 steps per (fastest) contact.
    assert np.max(np.abs(energy / energy[0] - 1)) < 2e-4


@pytest.mark.parametrize("kwargs,match", [
    (dict(shear_modulus=0.0), "shear_modulus"),
    (dict(poisson_ratio=0.5), "poisson_ratio"),
    (dict(density=-1.0), "density"),
    (dict(friction=-0.1), "friction"),
    (dict(restitution=1.5), "restitution"),
])
def test_material_bad_input(kwargs, match):
    args = dict(shear_modulus=44e9, poisson_ratio=0.08, density=2650.0)
    args.update(kwargs)
    with pytest.raises(ValueError, match=match):
        GrainMaterial(**args)


def test_time_step_bad_input():
    with pytest.raises(ValueError, match="radius"):
        stable_time_step(QUARTZ, 2e-4, 1e-4, 0.1)
    with pytest.raises(ValueError, match="v_ref"):
        stable_time_step(QUARTZ, 1e-4, 2e-4, 0.0)
