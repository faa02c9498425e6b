"""Tests that notice one-line slips in the newest MD modules (issue 30, Build item 6).

Each test pins a value computed by hand at one state, an exact invariant or a documented
threshold, so that a realistic single-line change to md.protocols (the compaction step),
md.along_depth (the finer last tenth of a compaction, the carried cement), md.convergence (the
settled rule), md.static (the solver "auto" picks, the LU-preconditioned iteration count, the
lattice degree, the constants from the loads) or the MD join of rockcem._md_backend
(saturation, total error, trust, warnings) fails a test. The slip each test was checked
against is named in its docstring.
"""

import dataclasses
import math

import numpy as np
import pytest

import md
import md.static as static
from md.acoustic import acoustic_system, cement_block
from md.cement import HARD_CEMENT, cement_lattice, grow_cement
from md.convergence import SAFETY_FALLBACK, SETTLED, resolution_error

# ---------------------------------------------------------------------------------------------
# md.protocols.compact: the recorded increments and where a compaction stops


@pytest.fixture(scope="module")
def loaded(compacted_pack):
    """The stored pack after one increment of 1e-4 strain (about 14 MPa vertical), with a
    record and its stress in the metadata."""
    return md.compact(compacted_pack, target_stress=12e6, strain_step=1e-4)


def _check_record(pack, step, target, unload=False):
    """The invariants of a compaction record: every increment shortens (or lengthens) the
    sample by ``step`` of its height, so 1 - strain_k = (1 -+ step)^k exactly (compounded); the
    run stops at the first increment whose stress reaches ``target`` (all earlier ones short
    of it), so the overshoot is below the last increment's stress change; the metadata's
    stress is the record's last."""
    rec = pack.metadata["record"]
    k = np.arange(1, len(rec["strain"]) + 1)
    factor = 1.0 + step if unload else 1.0 - step
    np.testing.assert_allclose(1.0 - np.asarray(rec["strain"]), factor ** k, rtol=1e-12)
    s = np.asarray(rec["stress_zz"])
    if unload:
        assert s[-1] <= target and np.all(s[:-1] > target)
    else:
        assert s[-1] >= target and np.all(s[:-1] < target)
    if s.size > 1:
        assert abs(s[-1] - target) < abs(s[-1] - s[-2])
    assert pack.metadata["stress_zz"] == s[-1]
    assert pack.metadata["strain_step"] == step


def test_compaction_record_holds_the_strain_step_asked_for(loaded):
    """md.compact to 16 MPa in steps of 1e-4 from about 14 MPa (about ten increments): the
    recorded strains are the compounded step, and the run stops at the first increment past
    the target. Slip checked: ``factor = 1 - 5 * strain_step`` in md/protocols.py (the
    strains are 5e-4 apart, and the stop is reached in two increments)."""
    start = loaded.metadata["stress_zz"]
    assert start < 15e6
    out = md.compact(loaded, target_stress=16e6, strain_step=1e-4)
    _check_record(out, 1e-4, 16e6)
    assert len(out.metadata["record"]["strain"]) >= 4


def test_compacted_stage_takes_the_last_tenth_in_a_fifth_of_the_step(loaded, tmp_path,
                                                                       monkeypatch):
    """md.along_depth._compacted: below 90 % of the target the pack is compacted in steps of
    ``strain_step`` to 0.9 of it, then in steps of a fifth of it to the target (so the stress
    overshoots by a fifth as much); the stage returned and saved records the fine steps.
    Unloading takes its own step (``unload_step``), not a fifth of it. Slips checked: ``0.2 *
    strain_step`` written ``strain_step`` in md/along_depth.py (the 5x larger step the scene's
    1.05 bound hid), and the 0.9 of the first target written 0.95."""
    import md.protocols
    from md.along_depth import _compacted
    from md.state import load_pack

    calls = []
    real = md.protocols.compact

    def spy(pack, **kw):
        calls.append((kw["target_stress"], kw["strain_step"], kw.get("unload", False)))
        return real(pack, **kw)

    monkeypatch.setattr(md.protocols, "compact", spy)
    target, step = 16e6, 5e-4
    out, key, path = _compacted(loaded, target, tmp_path, "chain", step, False)
    assert [c[:2] for c in calls] == [(pytest.approx(0.9 * target, rel=1e-15), step),
                                      (target, pytest.approx(0.2 * step, rel=1e-15))]
    _check_record(out, 0.2 * step, target)
    again = load_pack(path)
    assert again.metadata["record"]["strain"] == out.metadata["record"]["strain"]
    assert again.metadata["options_key"] == key
    # Already at the stress: nothing is compacted, the pack comes back as it is.
    calls.clear()
    same, same_key, none = _compacted(out, 0.99 * target, tmp_path, key, step, False)
    assert same is out and same_key == key and none is None and calls == []
    # Unloading: one compaction, with unload=True, in steps of unload_step itself.
    un, _, _ = _compacted(out, 0.995 * out.metadata["stress_zz"], tmp_path, key, 2e-5, False,
                          unload=True)
    assert calls == [(0.995 * out.metadata["stress_zz"], 2e-5, True)]
    _check_record(un, 2e-5, 0.995 * out.metadata["stress_zz"], unload=True)


# ---------------------------------------------------------------------------------------------
# md.convergence: the settled rule of "richardson", and that "gci" has none


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_settled_rule_at_its_threshold(sign):
    """Under ``rule="richardson"`` three values whose changes differ in sign (no Richardson
    order) count as converged when every change is at most SETTLED = 1 % of the *finest*
    value: 100, 99, 99.5 (changes 1 and 0.5, the 1 exactly 1 % of the finest 100; 1.0101 % of
    the middle value, 1.005 % of the coarsest) is settled, with the first-order two-point
    error 1 / (6/5 - 1) = 5; 100, 98.9921875, 99.5 (a change of 1.0078 %) is not, with the
    same first-order error. Slips checked: SETTLED 0.02 or 0.005, ``<=`` written ``<``, the
    change relative to the middle or coarsest value (column[1], column[-1]) or to a signed
    finest value (abs dropped; the negative sequence)."""
    assert SETTLED == 0.01
    om = [6.0, 5.0, 4.0]
    x = sign * np.array([[100.0, 100.0], [99.0, 98.9921875], [99.5, 99.5]])
    err, asym = resolution_error(om, x, rule="richardson")
    assert asym.tolist() == [True, False]
    np.testing.assert_allclose(err, [1.0 / 0.2, 1.0078125 / 0.2], rtol=1e-12)


def test_gci_has_no_settled_rule():
    """The same settled sequence under the default ``"gci"``: no credible order, so not
    asymptotic, and three times the larger first-order step, max(1 / 0.2, 0.5 / 0.25) = 5.
    Slip checked: ``not gci and`` dropped from the settled branch (the sequence would be
    called asymptotic under "gci")."""
    x = np.array([[100.0], [99.0], [99.5]])
    err, asym = resolution_error([6.0, 5.0, 4.0], x)
    assert not asym[0]
    assert err[0] == pytest.approx(SAFETY_FALLBACK * 5.0, rel=1e-12)


# ---------------------------------------------------------------------------------------------
# md.static: the preconditioned conjugate gradients, the iteration count, the solver "auto"


def _diag_ops(d, inverse=False):
    def apply_(p, q):
        q[:] = d * p

    def precondition(r, z):
        z[:] = r / d if inverse else r

    return apply_, precondition


def test_pcg_iteration_counts_by_hand():
    """Conjugate gradients end, in exact arithmetic, in as many iterations as the
    preconditioned matrix has distinct eigenvalues (Saad 2003, Prop. 6.13 via the Krylov
    space's dimension): one with the exact inverse as preconditioner, three on diag(1, 1, 2,
    2, 5, 5) without one; none for a zero right-hand side; a cap of two on the latter raises.
    Slips checked: ``range(maxiter)`` for ``range(maxiter + 1)`` (maxiter = 3 then raises) and
    the count off by one."""
    d = np.array([1.0, 1.0, 2.0, 2.0, 5.0, 5.0])
    b = np.array([1.0, 2.0, 3.0, 4.0, 5.0, 6.0])
    y, it = static._pcg(*_diag_ops(d, inverse=True), b, 1e-10, 10)
    assert it == 1
    np.testing.assert_allclose(y, b / d, rtol=1e-14)
    y, it = static._pcg(*_diag_ops(d), b, 1e-10, 3)
    assert it == 3
    np.testing.assert_allclose(y, b / d, rtol=1e-12)
    y, it = static._pcg(*_diag_ops(d), np.zeros(6), 1e-10, 3)
    assert it == 0 and not y.any()
    with pytest.raises(RuntimeError, match="did not converge in 2 CG iterations"):
        static._pcg(*_diag_ops(d), b, 1e-10, 2)


CW = 1e-5
BLOCK = (3, 3, 8)


@pytest.fixture(scope="module")
def systems(compacted_pack):
    """A pure cement block of 3 x 3 x 8 cells (slabs one cell thick), the stored pack bare and
    with a 10 % coating (Omega 3), all with rotations."""
    lat = cement_lattice(compacted_pack, 3.0)
    return {"block": cement_block(BLOCK, CW, HARD_CEMENT, slab_thickness=CW),
            "bare": acoustic_system(compacted_pack),
            "coated": acoustic_system(compacted_pack, lat, grow_cement(lat, 0.1, "coating"))}


def _setup(system, **kw):
    return static._StaticSetup(system, rtol=1e-10, maxiter=None, **{"parallel": False,
                                                                     "solver": "auto", **kw})


def test_lattice_degree_and_free_dof_of_a_cement_block(systems):
    """A full block periodic in x and y has 18 lattice neighbours per cell (6 faces and 12
    edges of the cube) inside and 13 on its top and bottom layers (the 5 across the free end
    missing): mean degree (6 x 18 + 2 x 13) / 8 = 16.75. With one-cell slabs its free degrees
    of freedom are the translations of the 6 interior layers and every rotation:
    6 x 9 x 3 + 72 x 3 = 378. A pack without cement has degree 0. Slips checked: the degree
    without the factor 2 (8.375, below no threshold the same way), and the end slabs'
    translations freed."""
    block = systems["block"]
    assert static._lattice_degree(block) == pytest.approx(16.75, rel=1e-15)
    assert static._lattice_degree(systems["bare"]) == 0.0
    assert _setup(block).free_idx.size == 6 * 9 * 3 + 72 * 3


def test_shipped_thresholds_are_the_documented_cases():
    """md.static's comment: a thin coating of 3e5 free dof (mean lattice degree 2) factorises
    in 7 s, so "auto" takes LU there; well-connected cement of 3e5 (half-filled pores, degree
    6.5: 80 s and 2.2 GB) takes CG (the cap of well-connected cement itself:
    tests/md/test_static_solver.py). Slips checked: FILM_DEGREE moved past 2 or 6.5,
    LU_MAX_DOF raised to 3e5, LU_MAX_DOF_FILM lowered below it."""
    assert 2.0 <= static.FILM_DEGREE < 6.5
    assert static.LU_MAX_DOF < 3e5 <= static.LU_MAX_DOF_FILM


@pytest.mark.parametrize("name", ["block", "bare", "coated"])
def test_auto_picks_by_the_thresholds(systems, monkeypatch, name):
    """"auto" takes LU up to LU_MAX_DOF free dof, or LU_MAX_DOF_FILM where the mean lattice
    degree is at most FILM_DEGREE (the bare pack, 0; the coating, about 1.6), else CG; the
    other cap plays no part; the parallel operator always takes CG. Checked with the
    thresholds moved to the system's own free dof and degree. Slips checked: ``<=`` written
    ``<`` on either comparison, the two caps swapped, ``FILM_DEGREE`` compared with ``>=``."""
    system = systems[name]
    n = _setup(system).free_idx.size
    degree = static._lattice_degree(system)
    film = degree <= static.FILM_DEGREE
    assert film == (name != "block")
    own, other = ("LU_MAX_DOF_FILM", "LU_MAX_DOF") if film else ("LU_MAX_DOF", "LU_MAX_DOF_FILM")
    for other_cap in (0, 10 * n):
        monkeypatch.setattr(static, other, other_cap)
        monkeypatch.setattr(static, own, n)
        assert _setup(system).solver == "lu"
        assert _setup(system, parallel=True).solver == "cg"
        monkeypatch.setattr(static, own, n - 1)
        assert _setup(system).solver == "cg"
    # The degree threshold itself: at the system's degree it is film, just below it is not.
    monkeypatch.setattr(static, "LU_MAX_DOF_FILM", n)
    monkeypatch.setattr(static, "LU_MAX_DOF", n - 1)
    monkeypatch.setattr(static, "FILM_DEGREE", degree)
    assert _setup(system).solver == "lu"
    monkeypatch.setattr(static, "FILM_DEGREE", np.nextafter(degree, -np.inf))
    assert _setup(system).solver == "cg"


@pytest.mark.parametrize("name", ["block", "bare", "coated"])
def test_lu_preconditioned_solves_take_two_iterations(systems, name):
    """The LU factor of the scaled K_ff (with its own mechanisms pinned and a shift of 1e-10)
    is nearly exact, so conjugate gradients preconditioned by it reach rtol 1e-10 in two
    iterations on every load (measured: 2 on all five loads of the three systems; 1 would
    need the factor exact to 1e-10); the block-Jacobi solve of the same system takes more (6 on
    the block, about a hundred on the packs) and gives the same P modulus. Slips checked: the shift
    raised to 1e-6, the diagonal scaling dropped from the preconditioner's solve."""
    system = systems[name]
    st = static.static_stiffness(system, solver="lu")
    assert {k: v[2] for k, v in st.loads.items()} == dict.fromkeys(("z", "xz", "x", "y", "xy"),
                                                                    2)
    cg = static.static_modulus(system, "p", solver="cg")
    assert cg.iterations > 2
    assert cg.modulus == pytest.approx(st.c33, rel=1e-6)


def test_ti_constants_are_the_documented_formulas_of_the_loads(systems):
    """static_stiffness's constants from its five loads (the interior strain and the band's
    stress per load, returned in ``loads``), by the formulas of its docstring:
    C13 = (s_xx + s_yy) / 2 / e_zz of "z"; C11 = (s_aa - C13 e_zz) / e_aa and
    C12 = (s_oo - C13 e_zz) / e_aa over the x and y loads, averaged; C31 = (s_zz - C33 e_zz) /
    e_aa; C66 = s_yx / (2 e_xy). On the coated pack the x and y loads' e_zz is not zero (the
    C13 e_zz term moves C11 by 1e-4 to 3e-4, far above the 1e-12 compared), so the correction
    is seen. Slips
    checked: the ``- c13 * e[2, 2]`` term of C11 dropped, C66 without the factor 2."""
    st = static.static_stiffness(systems["coated"])
    e, s, _ = st.loads["z"]
    c13 = 0.5 * (s[0, 0] + s[1, 1]) / e[2, 2]
    assert st.c13 == pytest.approx(c13, rel=1e-12)
    c11, c12, c31, terms = [], [], [], []
    for name, a, o in (("x", 0, 1), ("y", 1, 0)):
        e, s, _ = st.loads[name]
        c11.append((s[a, a] - c13 * e[2, 2]) / e[a, a])
        c12.append((s[o, o] - c13 * e[2, 2]) / e[a, a])
        c31.append((s[2, 2] - st.c33 * e[2, 2]) / e[a, a])
        terms.append(abs(c13 * e[2, 2] / e[a, a]))
    assert min(terms) > 1e-5 * st.c11
    for got, want in ((st.c11, np.mean(c11)), (st.c12, np.mean(c12)), (st.c31, np.mean(c31))):
        assert got == pytest.approx(want, rel=1e-12)
    e, s, _ = st.loads["xy"]
    assert st.c66 == pytest.approx(s[1, 0] / (2 * e[0, 1]), rel=1e-12)


# ---------------------------------------------------------------------------------------------
# md.along_depth: cement grown during burial, carried to the next depth


def _window_cells(pack, lat):
    lo, hi = md.observe.core_window(pack)
    z = lat.centres()[:, 2]
    inside = (z >= lo) & (z < hi)
    return inside, pack.box.lx * pack.box.ly * (hi - lo)


def test_grown_cement_adds_exactly_the_increment(compacted_pack):
    """cement_cells with carried cement: the carried cells stay and the window then holds
    exactly round(f V / w^3) cemented cells (the increment is counted from the carried cells
    inside the window, skipping them in the growth order); a fraction the carried cement
    already exceeds returns it unchanged. Slips checked: the carried count taken over the
    whole lattice (``cells`` for ``cells & inside``), the carried cells not skipped in the
    order, the cut one cell late."""
    from md.along_depth import cement_cells

    lat = cement_lattice(compacted_pack, 2.0)
    inside, volume = _window_cells(compacted_pack, lat)
    first, _ = cement_cells(compacted_pack, lat, 0.05, "coating")
    assert (first & ~inside).any()              # carried cells outside the window too
    for fraction in (0.08, 0.12):
        grown, over = cement_cells(compacted_pack, lat, fraction, "pore_body", carried=first)
        assert not over and np.all(grown[first])
        want = round(fraction * volume / lat.cell_width**3)
        assert np.count_nonzero(grown & inside) == want
    same, over = cement_cells(compacted_pack, lat, 0.02, "pore_body", carried=first)
    assert np.array_equal(same, first) and not over


def test_grown_cement_stage_carries_the_shallower_cement(compacted_pack, tmp_path):
    """md.along_depth._grown_cement, twice on one pack: the second depth's cells hold the
    first's (carried with the grains, here unmoved) plus the increment, its stage file holds
    them, and the window fraction it reports is the cells' own count over the window, within
    half a cell of the fraction asked for. Slip checked: ``previous`` not passed on to
    carried_cells (the second depth's cement grown afresh by its own scheme)."""
    import xarray as xr
    from md.along_depth import _grown_cement

    state, path1, w1, _ = _grown_cement(compacted_pack, "k", 0.05, "coating", 2.0, 0, None,
                                        tmp_path, False)
    state2, path2, w2, over = _grown_cement(compacted_pack, "k", 0.12, "pore_body", 2.0, 0,
                                            state, tmp_path, False)
    with xr.open_dataset(path1) as a, xr.open_dataset(path2) as b:
        first, second = a["cells"].values.astype(bool), b["cells"].values.astype(bool)
    assert not over and np.all(second[first]) and second.sum() > first.sum()
    lat = cement_lattice(compacted_pack, 2.0)
    inside, volume = _window_cells(compacted_pack, lat)
    cell = lat.cell_width**3 / volume
    assert w2 == pytest.approx(np.count_nonzero(second & inside) * cell, rel=1e-12)
    assert abs(w2 - 0.12) <= 0.5 * cell
    assert state2[1].size == second.sum()           # one attached point per cemented cell


# ---------------------------------------------------------------------------------------------
# rockcem._md_backend: the MD join


def test_isotropic_saturation_by_hand():
    """anisotropy = "isotropic" at one state: C33 = 9, C44 = 3 GPa, K_min 37, K_fl 2.4,
    porosity 0.25, density 2.2: K_dry = 9 - 4 = 5; Gassmann (1951; Mavko et al. 2009,
    eq. 6.3.1) K_sat = K_dry + (1 - K_dry/K_min)^2 / (phi/K_fl + (1 - phi)/K_min
    - K_dry/K_min^2); Vp = sqrt((K_sat + 4/3 G)/rho), Vs = sqrt(G/rho). Slips checked: the
    4/3 dropped from K_dry or from Vp, phi for 1 - phi in Gassmann."""
    from rockcem._md_backend import saturated_moduli

    c = {"p_modulus": np.array([9.0]), "shear_modulus": np.array([3.0])}
    K_dry, G, K_sat, vp, vs, *_, sound = saturated_moduli(c, 37.0, 2.4, 0.25, 2.2, ti=False)
    k_sat = 5.0 + (1 - 5.0 / 37.0) ** 2 / (0.25 / 2.4 + 0.75 / 37.0 - 5.0 / 37.0**2)
    assert K_dry[0] == pytest.approx(5.0, rel=1e-15) and G[0] == 3.0
    assert K_sat[0] == pytest.approx(k_sat, rel=1e-12)
    assert vp[0] == pytest.approx(math.sqrt((k_sat + 4.0) / 2.2), rel=1e-12)
    assert vs[0] == pytest.approx(math.sqrt(3.0 / 2.2), rel=1e-12) and sound.all()


@pytest.mark.parametrize("change,K_min,ok", [
    ({}, 3.3, True),                        # Voigt-type bulk (2C11 + C33 + 2C12 + 4C13)/9
    ({}, 3.2, False),                       # = 29.4/9 = 3.2667 with C12 = C11 - 2C66 = 1.2
    # (C33 - 4/3 C44 = 1.8, the isotropic fallback, stays below K_min)
    ({"c11": 2.0}, 37.0, False),            # C11 <= C66
    ({"shear_modulus": 0.0}, 37.0, False),  # C44 = 0
    ({"c13": 5.6}, 37.0, True),             # C13^2 = 31.36 < C33 (C11 - C66) = 32.4
    ({"c13": 5.8}, 37.0, False)])           # C13^2 = 33.64 > 32.4
def test_ti_frame_soundness_at_each_condition(change, K_min, ok):
    """The TI reading holds (``sound``) only for five constants of a positive-definite
    stiffness no stiffer than the mineral: C11 > C66, C13^2 < C33 (C11 - C66), C44 > 0 and the
    Voigt-type bulk modulus (2 C11 + C33 + 2 C12 + 4 C13)/9 <= K_min, with C12 = C11 - 2 C66.
    With C11 6, C13 1.5, C33 9, C44 5.4, C66 2.4 that bulk is 29.4/9 = 3.267: sound for K_min
    3.3, not for 3.2; C13 5.6 is positive definite, 5.8 is not. Slips checked: C12 = C11 - C66
    (bulk 3.8: K_min 3.3 unsound), the K_min condition dropped, C13 not squared. (Dropping
    ``c11 > c66`` changes nothing: with C33 > 0, which the isotropic fallback's Gassmann
    requires, C13^2 < C33 (C11 - C66) implies it.)"""
    from rockcem._md_backend import saturated_moduli

    base = {"c11": 6.0, "c13": 1.5, "p_modulus": 9.0, "shear_modulus": 5.4, "c66": 2.4}
    base.update(change)
    c = {k: np.array([v]) for k, v in base.items()}
    sound = saturated_moduli(c, K_min, 2.4, 0.25, 2.2)[-1]
    assert sound.tolist() == [ok]


def test_total_error_and_trust_by_hand():
    """total_error is the two errors in quadrature (3, 4 -> 5), NaN where either is; a member
    is trusted where both errors are at most the threshold of their velocity (0.5 of 2.0 at
    0.25: on the boundary, trusted) and measured. Slips checked: the errors added, ``<=``
    written ``<``, the S velocity's test dropped. (Dropping the ``isfinite`` terms changes
    nothing: a comparison with NaN is already False.)"""
    from rockcem._md_backend import total_error, trusted_members

    np.testing.assert_allclose(total_error([3.0, 0.0], [4.0, 2.0]), [5.0, 2.0], rtol=1e-15)
    assert np.isnan(total_error([np.nan, 1.0], [1.0, np.nan])).all()
    vp, vs = np.full(5, 2.0), np.full(5, 1.0)
    vp_err = np.array([0.5, 0.5000001, 0.1, np.nan, 0.1])
    vs_err = np.array([0.25, 0.1, 0.2500001, 0.1, np.nan])
    assert trusted_members(vp, vp_err, vs, vs_err, 0.25).tolist() == [True, False, False, False,
                                                                      False]
    with pytest.raises(ValueError, match="trust_threshold"):
        trusted_members(vp, vp_err, vs, vs_err, 1.0)


def test_md_warnings_name_the_depths_of_each_condition():
    """One line per condition, naming its depths (MD ran at 1000, 2000 and 4000 m, not 3000):
    a porosity gap above 0.01 (0.01171875 at 2000 and -0.01171875 at 4000; 0.0078125 at 1000
    is not), cement overflow (2000), a member not trusted (2000 with measured errors, 4000
    with one unmeasured: the second wording), outside the bounds (4000) and not asymptotic
    (2000; NaN, no check made, is not named). Slips checked: the gap threshold 0.005 or 0.02,
    the abs of the gap dropped, NaN asymptotic taken as failed, the unmeasured wording lost."""
    from rockcem._md_backend import md_warnings

    depth = np.array([1000.0, 2000.0, 3000.0, 4000.0])
    burial = np.array([0.5, 0.5, 0.5, 0.5])
    per_depth = {"md_porosity": np.array([0.5078125, 0.51171875, np.nan, 0.48828125]),
                 "md_cement_overflow": np.array([0.0, 1.0, np.nan, 0.0])}
    per_model = {"md": {"md_trusted": np.array([1.0, 0.0, np.nan, 0.0]),
                        "vp_error": np.array([0.1, 0.9, np.nan, np.nan]),
                        "vs_error": np.array([0.1, 0.9, np.nan, 0.1]),
                        "md_within_bounds": np.array([1.0, 1.0, np.nan, 0.0]),
                        "md_resolution_asymptotic": np.array([np.nan, 0.0, np.nan, 1.0])}}
    lines = md_warnings(depth, burial, per_depth, per_model)
    assert len(lines) == 5
    gap, over, trust, bounds, asym = lines
    assert gap.startswith("MD model at 2000, 4000 m: the MD sample's porosity differs")
    assert "by -0.012 to +0.012" in gap
    assert over.startswith("MD model at 2000 m: burial's cement exceeds")
    assert trust.startswith("MD model md at 2000, 4000 m is not trusted")
    assert "or was not measured" in trust
    assert bounds.startswith("MD model md at 4000 m: its dry frame is stiffer")
    assert asym.startswith("MD model md at 2000 m: the three lattice resolutions")
    measured = {"md": {**per_model["md"], "vp_error": np.array([0.1, 0.9, np.nan, 0.9])}}
    trust = md_warnings(depth, burial, per_depth, measured)[2]
    assert "not trusted: its total error (resolution and sample size" in trust
    assert md_warnings(depth, burial, {**per_depth, "md_porosity": burial + 0.0078125,
                                       "md_cement_overflow": np.zeros(4)}) == []


@pytest.fixture(scope="module")
def long_block():
    """The cement block of the pulse checks of tests/md/test_acoustic.py: 3 x 3 x 160 cells,
    slabs of 8, with rotations."""
    return cement_block((3, 3, 160), CW, HARD_CEMENT, slab_thickness=8 * CW)


@pytest.mark.parametrize("measure,anisotropy,rel", [("static", "ti", 2e-5),
                                                    ("static", "isotropic", 2e-5),
                                                    ("pulse", "isotropic", 0.06)])
def test_member_moduli_of_a_cement_block_in_every_reading(long_block, measure, anisotropy,
                                                          rel):
    """md.along_depth._moduli, the member's moduli in each of its three readings, on a pure
    cement block whose constants are the cement's: C33 = rho Vp^2, C44 = rho Vs^2 and (TI)
    C11 = C33, C13 = rho (Vp^2 - 2 Vs^2), C66 = C44 (the isotropic lattice with rotations,
    tests/md/test_static_stiffness.py); NaN for C11, C13, C66 in the isotropic readings; the
    density the cement's. The pulse reading (not run by any scene test) within 6 % in the
    modulus (3 % in the velocity, the square pulse's bias). Slips checked: the pulse's shear
    modulus from the P velocity, its P modulus without the square, a TI member's C13 read
    from C66 (``"c13": st.c66``). (C13 read from C12 or C31 is not seen here: the block's
    three are equal.)"""
    from md.along_depth import _moduli

    c = HARD_CEMENT
    M, G = c.density * c.vp**2, c.density * c.vs**2
    got = _moduli(long_block, measure, anisotropy)
    assert got["p_modulus"] == pytest.approx(M, rel=rel)
    assert got["shear_modulus"] == pytest.approx(G, rel=rel)
    assert got["density"] == pytest.approx(c.density, rel=1e-12)
    if anisotropy == "ti":
        assert got["c11"] == pytest.approx(M, rel=rel)
        assert got["c13"] == pytest.approx(M - 2 * G, rel=rel)
        assert got["c66"] == pytest.approx(G, rel=rel)
    else:
        assert np.isnan([got["c11"], got["c13"], got["c66"]]).all()


def test_carry_down_grows_the_second_depths_cement_on_the_first(compacted_pack, tmp_path,
                                                               monkeypatch):
    """carry_down with grown cement over two depths (pore-body cement 0.05, then 0.12): the
    second depth's cement stage holds every cell the first depth's cement is carried to on the
    second pack (md.reconstruct.carried_cells of the first stage's attached points), and its
    window holds 0.12 to within half a cell. The MD compaction is replaced by an affine
    vertical shortening of the stored pack (0.3 % per 15 MPa) so the test stays fast; the
    cement, the carry and the moduli are carry_down's own. Slip checked: ``grown[(scheme, w)]
    = state`` dropped in md/along_depth.py (each depth cemented afresh)."""
    import xarray as xr

    import md.along_depth as ad
    import md.protocols
    from md.reconstruct import carried_cells
    from md.state import load_pack, save_pack

    def prepare(folder, **_):
        return compacted_pack

    def compacted(pack, stress, folder, chain_key, strain_step, progress, *, unload=False):
        x = compacted_pack.positions.copy()
        centre = 0.5 * (x[:, 2].min() + x[:, 2].max())
        x[:, 2] = centre + (x[:, 2] - centre) * (1.0 - 0.003 * stress / 15e6)
        out = dataclasses.replace(compacted_pack, positions=x,
                                  metadata={"stress_zz": float(stress)})
        folder.mkdir(parents=True, exist_ok=True)
        key = ad._key({"previous": chain_key, "stress": float(stress)})
        path = folder / f"fake_{stress / 1e6:g}.nc"
        save_pack(out, path)
        return out, key, path

    monkeypatch.setattr(md.protocols, "prepare_pack", prepare)
    monkeypatch.setattr(ad, "_compacted", compacted)
    ds = ad.carry_down([15.0, 30.0], [0.05, 0.12], schemes=("pore_body",), compaction="hertz",
                       resolution=2.0, anisotropy="isotropic", workdir=tmp_path)
    [first_file] = tmp_path.glob("*/cement/pore_body_w2_c0.05_*.nc")
    [second_file] = tmp_path.glob("*/cement/pore_body_w2_c0.12_*.nc")
    with xr.open_dataset(first_file) as a, xr.open_dataset(second_file) as b:
        grain, offset = a["grain"].values, a["offset"].values
        second = b["cells"].values.astype(bool)
    pack2 = load_pack(next(tmp_path.glob("*/pack/fake_30.nc")))
    lat2 = cement_lattice(pack2, 2.0)
    carried = carried_cells(pack2, lat2, grain, offset)
    assert carried.sum() > 0.5 * grain.size
    assert np.all(second[carried])
    inside, volume = _window_cells(pack2, lat2)
    assert abs(np.count_nonzero(second & inside) * lat2.cell_width**3 / volume - 0.12) \
        <= 0.5 * lat2.cell_width**3 / volume
    assert np.isfinite(ds.p_modulus.values).all()
