"""The linearised acoustic stage: lattice constants, operator assembly, static moduli and the
pulse test, against closed forms and a second numerical method (García & Medina, III F–G)."""

import math

import numpy as np
import pytest

from md.acoustic import (acoustic_system, cement_block, damping_ratio, pulse_test,
                         static_modulus)
from md.cement import (HARD_CEMENT, LATTICE_OFFSETS, SOFT_CEMENT, CementMaterial,
                       cement_lattice, grow_cement, lattice_constants)
from md.contact import QUARTZ
from md.space import Box
from md.state import Pack

CW = 1e-5


def cubic_pack(n=(3, 3, 24), R=1e-4, overlap=1e-7):
    """Grains on a simple cubic lattice of spacing d = 2R - overlap (periodic in x, y)."""
    nx, ny, nz = n
    d = 2 * R - overlap
    k, j, i = np.meshgrid(np.arange(nz), np.arange(ny), np.arange(nx), indexing="ij")
    x = np.stack([(i.ravel() + 0.5) * d, (j.ravel() + 0.5) * d, R + k.ravel() * d], -1)
    z = np.zeros_like(x)
    return Pack(x, z, z.copy(), np.full(len(x), R), Box(nx * d, ny * d, 0.0, nz * d + R),
                QUARTZ, np.zeros((0, 2), np.int32), np.zeros((0, 3))), d


# --- lattice constants ---------------------------------------------------------------------

@pytest.mark.parametrize("cement", [HARD_CEMENT, SOFT_CEMENT])
@pytest.mark.parametrize("wave,attr", [("p", "vp"), ("s", "vs")])
@pytest.mark.parametrize("rotations,rel", [(False, 1e-8), (True, 3e-5)])
def test_cement_block_static_moduli_give_the_cement_velocities(cement, wave, attr, rotations,
                                                               rel):
    """A sparse solve of a pure cement block gives the cement's P and S velocities (eq. 8; with
    rotations the constants of lattice_constants(rotations=True)). With rotations the end
    slabs, translated rigidly, hold their particles' rotations near zero while the sheared
    interior turns by half the shear: the mismatch layer costs 1e-4 of the S velocity on a
    24-cell block, 2e-5 on 48 cells (P has no rotation and is exact)."""
    nz = 48 if rotations else 24
    st = static_modulus(cement_block((4, 4, nz), CW, cement, rotations=rotations), wave)
    assert st.velocity == pytest.approx(getattr(cement, attr), rel=rel)
    assert st.density == pytest.approx(cement.density, rel=1e-12)


def test_paper_rule_is_off_by_the_predicted_amount():
    """Eq. 9 (C from eq. 8) on this lattice: rho Vp^2 = 3Cn/cw + 3C/cw^3 = 3/4 rho (Vp^2 + Vs^2)
    and rho Vs^2 = rho (7 Vs^2 - Vp^2) / 4."""
    c = HARD_CEMENT
    block = cement_block((4, 4, 24), CW, c, rule="paper", rotations=False)
    vp = static_modulus(block, "p").velocity
    vs = static_modulus(block, "s").velocity
    assert vp == pytest.approx(math.sqrt(0.75 * (c.vp**2 + c.vs**2)), rel=1e-8)
    assert vs == pytest.approx(math.sqrt((7 * c.vs**2 - c.vp**2) / 4), rel=1e-8)
    assert 1.005 < vp / c.vp < 1.02 and 1.02 < vs / c.vs < 1.04


@pytest.mark.parametrize("wave,attr", [("p", "vp"), ("s", "vs")])
@pytest.mark.parametrize("rotations,rel", [(False, 1e-8), (True, 1e-5)])
def test_pulse_on_a_cement_block_gives_the_cement_velocity(wave, attr, rotations, rel):
    """The homogeneous check of the pulse machinery: within 3 % (the peak of the square pulse
    runs 2–2.5 % slow on the lattice, see benchmarks/md_pulse_error_vs_time.py; the
    eq. 11 error of a single pair of detectors misses that bias), with and without rotations."""
    block = cement_block((3, 3, 160), CW, HARD_CEMENT, slab_thickness=8 * CW,
                         rotations=rotations)
    ds = pulse_test(block, wave)
    target = getattr(HARD_CEMENT, attr)
    assert ds.attrs["rotations"] == int(rotations)
    assert abs(float(ds.velocity) / target - 1) < 0.03
    assert abs(float(ds.velocity_fit) / target - 1) < 0.03
    assert float(ds.velocity_static) == pytest.approx(target, rel=rel)
    assert np.all(np.diff(ds.arrival_time.values[1:-3]) > 0)


def test_lattice_bond_count_of_a_full_block():
    """9 bonds per node; the 5 offsets with a z step lose one layer each (periodic x, y)."""
    nx, ny, nz = 4, 5, 6
    block = cement_block((nx, ny, nz), CW)
    assert block.lattice_i.size == 9 * nx * ny * nz - 5 * nx * ny


# --- the operator ----------------------------------------------------------------------------

@pytest.fixture(scope="module")
def cemented_cubic():
    """A cemented simple cubic pack, linearised with translations only (the source's eqs. 4–6)
    as the fourth item and with rotations as the fifth."""
    pack, d = cubic_pack((3, 3, 10))
    lat = cement_lattice(pack, 3.0)
    cem = grow_cement(lat, 0.1, "contact")
    return (pack, lat, cem,
            acoustic_system(pack, lat, cem, HARD_CEMENT, slab_thickness=2 * d, rotations=False),
            acoustic_system(pack, lat, cem, HARD_CEMENT, slab_thickness=2 * d))


@pytest.mark.parametrize("which", [3, 4], ids=["translations", "rotations"])
def test_kernel_equals_the_assembled_sparse_operator(cemented_cubic, rng, which):
    system = cemented_cubic[which]
    n, dof = system.n_particles, system.dof
    assert dof == (6 if which == 4 else 3)
    u, v = rng.normal(size=(n, dof)), rng.normal(size=(n, dof))
    K, D, M = system.stiffness_matrix(), system.damping_matrix(), system.mass_matrix()
    expected = -(K @ u.ravel() + D @ v.ravel())
    got = system.forces(u, v).ravel()
    assert np.max(np.abs(got - expected)) <= 1e-12 * np.max(np.abs(expected))
    assert abs(K - K.T).max() <= 1e-12 * abs(K).max()
    assert system.stiffness_diagonal().ravel() == pytest.approx(K.diagonal(), rel=1e-12)
    assert M.diagonal() == pytest.approx(system.dof_masses.ravel())
    # Rigid translations are free of force.
    shift = np.zeros((n, dof))
    shift[:, :3] = [1.0, -2.0, 0.5]
    assert np.max(np.abs(K @ shift.ravel())) <= 1e-9 * abs(K).max()


def test_parallel_kernels_equal_the_assembled_operator(cemented_cubic, rng):
    """The multi-threaded gather kernels give -(K u + D v) as the sparse matrices do, and the
    same pulse test as the serial kernels (signals to round-off)."""
    system = cemented_cubic[3]
    n = system.n_particles
    u, v = rng.normal(size=(n, 3)), rng.normal(size=(n, 3))
    expected = -(system.stiffness_matrix() @ u.ravel() + system.damping_matrix() @ v.ravel())
    got = system.forces(u, v, parallel=True).ravel()
    assert np.max(np.abs(got - expected)) <= 1e-12 * np.max(np.abs(expected))
    serial = pulse_test(system, max_time=2e-6)
    threaded = pulse_test(system, max_time=2e-6, parallel=True)
    scale = np.max(np.abs(serial.signal.values))
    assert np.max(np.abs(threaded.signal.values - serial.signal.values)) <= 1e-9 * scale
    assert float(threaded.modulus_static) == pytest.approx(float(serial.modulus_static),
                                                           rel=1e-8)


def test_lattice_bonds_join_cement_particles_one_offset_apart(cemented_cubic):
    pack, lat, cem, system, _ = cemented_cubic
    i, j = system.lattice_i, system.lattice_j
    assert i.size > 0 and i.min() >= system.n_grains and j.min() >= system.n_grains
    d = system.positions[j] - system.positions[i]
    d[:, 0] -= system.box.lx * np.round(d[:, 0] / system.box.lx)
    d[:, 1] -= system.box.ly * np.round(d[:, 1] / system.box.ly)
    expected = LATTICE_OFFSETS[system.lattice_dir] * lat.cell_width
    assert np.allclose(d, expected, atol=1e-9 * lat.cell_width)


def test_grain_cement_bonds_against_brute_force(cemented_cubic):
    pack, lat, cem, system, _ = cemented_cubic
    ng = system.n_grains
    centres = lat.centres()[cem]
    L = np.array([pack.box.lx, pack.box.ly])
    expected = set()
    for g, (xg, rg) in enumerate(zip(pack.positions, pack.radii)):
        dd = centres - xg
        dd[:, :2] -= L * np.round(dd[:, :2] / L)
        q = np.clip(np.zeros(3), dd - lat.cell_width / 2, dd + lat.cell_width / 2)
        expected |= {(g, ng + c) for c in np.flatnonzero(np.sum(q * q, axis=1) < rg * rg)}
    gc = system.bond_j >= ng
    got = set(zip(system.bond_i[gc].tolist(), system.bond_j[gc].tolist()))
    assert got == expected and len(got) > 0
    assert np.allclose(np.linalg.norm(system.bond_normal, axis=1), 1.0)


def test_cubic_pack_static_moduli_match_the_contact_chain():
    """Simple cubic pack: M = k_n / d and G = k_t / d with the linearised Hertz–Mindlin
    stiffnesses k_n = 2 E_f a, k_t = 8 G_f a, a = sqrt(R_f xi)."""
    R, xi = 1e-4, 1e-7
    pack, d = cubic_pack((3, 3, 12), R, xi)
    system = acoustic_system(pack, rotations=False)
    a = math.sqrt(R / 2 * xi)
    assert static_modulus(system, "p").modulus == pytest.approx(2 * QUARTZ.E_f * a / d, rel=1e-8)
    assert static_modulus(system, "s").modulus == pytest.approx(8 * QUARTZ.G_f * a / d, rel=1e-8)


def test_secant_normal_stiffness_is_the_force_over_the_overlap():
    """``normal_stiffness="secant"`` (the source's eq. 4 with eq. 1's kappa_n): on the simple
    cubic pack M = F_n(xi) / (xi d), the Hertz force over the overlap (md.contact.hertz_force,
    the force law of the settling and compaction stages), and the shear modulus is unchanged."""
    from md.contact import hertz_force

    R, xi = 1e-4, 1e-7
    pack, d = cubic_pack((3, 3, 12), R, xi)
    secant = acoustic_system(pack, normal_stiffness="secant", rotations=False)
    tangent = acoustic_system(pack, rotations=False)
    force = float(hertz_force(xi, R / 2, QUARTZ.E_f))
    assert static_modulus(secant, "p").modulus == pytest.approx(force / xi / d, rel=1e-8)
    assert static_modulus(secant, "s").modulus == pytest.approx(
        static_modulus(tangent, "s").modulus, rel=1e-8)
    # the tangent is the derivative of the same force law (central difference)
    h = 1e-4 * xi
    dfdxi = (float(hertz_force(xi + h, R / 2, QUARTZ.E_f))
             - float(hertz_force(xi - h, R / 2, QUARTZ.E_f))) / (2 * h)
    assert static_modulus(tangent, "p").modulus == pytest.approx(dfdxi / d, rel=1e-7)


@pytest.mark.parametrize("interface,factor", [("paper", 2.0 / 3.0), ("facet", 1.0)])
def test_secant_scales_the_per_cell_interface_only(cemented_cubic, interface, factor):
    """The source's per-cell grain–cement bond is eq. 4 too, so the secant reading takes two
    thirds of its normal stiffness; the facet rule (a punch on a half-space, linear elastic)
    does not depend on it. Tangential stiffnesses never change."""
    pack, lat, cem, *_ = cemented_cubic
    tangent = acoustic_system(pack, lat, cem, interface=interface)
    secant = acoustic_system(pack, lat, cem, interface=interface, normal_stiffness="secant")
    n_g = pack.n_grains
    gc = tangent.bond_j >= n_g                        # grain–cement bonds
    assert gc.any() and np.array_equal(tangent.bond_j, secant.bond_j)
    np.testing.assert_allclose(secant.bond_kn[gc], factor * tangent.bond_kn[gc], rtol=1e-12)
    np.testing.assert_allclose(secant.bond_kn[~gc], 2.0 / 3.0 * tangent.bond_kn[~gc],
                               rtol=1e-12)
    np.testing.assert_array_equal(secant.bond_kt, tangent.bond_kt)
    assert secant.metadata["normal_stiffness"] == "secant"
    with pytest.raises(ValueError, match="normal_stiffness"):
        acoustic_system(pack, normal_stiffness="chord")


def test_cubic_pack_pulse_velocity_near_the_long_wave_limit():
    pack, d = cubic_pack((3, 3, 48))
    system = acoustic_system(pack, slab_thickness=4 * d)
    ds = pulse_test(system)
    assert ds.attrs["normal_stiffness"] == "tangent" and ds.attrs["interface"] == "facet"
    ratio = float(ds.velocity) / float(ds.velocity_static)
    assert 0.9 < ratio <= 1.0 + float(ds.velocity_error) / float(ds.velocity_static)


@pytest.mark.parametrize("rotations,tol", [(False, 1e-9), (True, 1e-5)])
def test_cement_only_stiffens(cemented_cubic, rotations, tol):
    """Rayleigh monotonicity: nested cement (more springs) never lowers the static reaction.
    Strict for fixed springs; the facet rule spreads a patch's punch stiffness over its cells,
    so a cell joining a patch moves some of it to another lever arm, which with rotations may
    cost a millionth of the reaction (1.1e-6 here from S_c 0.05 to 0.1)."""
    pack, lat, *_ = cemented_cubic
    d = 2 * pack.radii[0]
    stresses = [static_modulus(acoustic_system(pack, lat, grow_cement(lat, s, "contact"),
                                               slab_thickness=d, rotations=rotations)).stress
                for s in (0.0, 0.02, 0.05, 0.1, 0.2)]
    assert np.all(np.diff(stresses) >= -tol * stresses[-1]) and stresses[-1] > stresses[0]


def test_time_step_is_stable_and_converges(cemented_cubic):
    system = cemented_cubic[3]
    a = pulse_test(system, time_step_factor=1.0)
    b = pulse_test(system, time_step_factor=0.25)
    assert np.all(np.isfinite(a.signal.values))
    assert float(a.velocity) == pytest.approx(float(b.velocity), rel=0.1)


# --- damping and inputs --------------------------------------------------------------------

@pytest.mark.parametrize("e", [0.1, 0.5, 0.9, 1.0])
def test_damping_ratio_reproduces_the_restitution(e):
    """A linear oscillator with this damping ratio rebounds with velocity ratio e: integrate it
    (scipy, tight tolerances) through half a damped period."""
    from scipy.integrate import solve_ivp

    zeta = damping_ratio(e)
    wd = math.sqrt(1 - zeta**2)
    sol = solve_ivp(lambda t, y: [y[1], -y[0] - 2 * zeta * y[1]], (0, math.pi / wd), [0, 1],
                    rtol=1e-12, atol=1e-14)
    assert -sol.y[1, -1] == pytest.approx(e, rel=1e-8)


@pytest.mark.parametrize("vp,vs", [(3000.0, 1500.0), (1000.0, 900.0), (-1.0, 1.0),
                                   (float("nan"), 1.0)])
def test_cement_outside_the_lattice_range(vp, vs):
    with pytest.raises(ValueError, match="cement"):
        CementMaterial(vp, vs, 2650.0)


def test_bad_knobs(cemented_cubic):
    system = cemented_cubic[3]
    for kwargs, match in [(dict(time_step_factor=1.5), "time_step_factor"),
                          (dict(record_every=0), "record_every"),
                          (dict(detectors=(0, 2)), "detectors"),
                          (dict(pulse_duration=-1.0), "pulse_duration"),
                          (dict(max_time=-1e-6), "max_time"), (dict(max_time=0.0), "max_time"),
                          (dict(max_time=float("nan")), "max_time")]:
        with pytest.raises(ValueError, match=match):
            pulse_test(system, **kwargs)
    with pytest.raises(ValueError, match="wave"):
        static_modulus(system, "q")
    for kwargs, match in [(dict(rtol=0.0), "rtol"), (dict(rtol=float("nan")), "rtol"),
                          (dict(maxiter=0), "maxiter"), (dict(maxiter=2.5), "maxiter")]:
        with pytest.raises(ValueError, match=match):
            static_modulus(system, **kwargs)
    with pytest.raises(ValueError, match="rule"):
        lattice_constants(HARD_CEMENT, CW, "exact")
    with pytest.raises(ValueError, match="4"):
        pulse_test(cement_block((3, 3, 8), CW))
    with pytest.raises(ValueError, match="both"):
        acoustic_system(cemented_cubic[0], cemented_cubic[1])


def test_pulse_reports_the_errors_eq11_leaves_out():
    """Beside the eq. 11 error (Delta L = R, the cell width for a block): the same with half a
    slab, the pulse minus its static limit, and a given relative resolution error."""
    block = cement_block((3, 3, 48), CW, HARD_CEMENT, slab_thickness=6 * CW)
    ds = pulse_test(block, resolution_error=0.02)
    L, dT = ds.attrs["distance_m"], ds.attrs["delta_T_s"]
    T = L / float(ds.velocity)
    assert ds.attrs["delta_L_m"] == pytest.approx(CW)
    assert float(ds.velocity_error) == pytest.approx((L * dT + T * CW) / T**2, rel=1e-9)
    assert float(ds.velocity_error_half_slab) == pytest.approx((L * dT + T * 3 * CW) / T**2,
                                                               rel=1e-9)
    assert float(ds.velocity_error_static) == pytest.approx(
        float(ds.velocity) - HARD_CEMENT.vp, rel=1e-6)
    assert float(ds.velocity_error_resolution) == pytest.approx(0.02 * float(ds.velocity))
    assert "R" in ds.attrs["delta_L_choice"]
    assert np.isnan(float(pulse_test(block).velocity_error_resolution))
    with pytest.raises(ValueError, match="resolution_error"):
        pulse_test(block, resolution_error=-0.1)
