"""Compaction between frozen slabs, and the contact stress (virial) it records."""

import numpy as np
import pytest

from md.contact import QUARTZ, hertz_force
from md.observe import contact_stress, group_force, porosity
from md.protocols import compact, settle
from md.space import Box


def test_contact_stress_of_one_vertical_contact():
    """Two grains stacked in z with overlap xi: sigma_zz = F l / V, F the Hertz force, l the
    branch length; no shear or lateral components."""
    R, xi = 2e-4, 1e-7
    x = np.array([[1e-3, 1e-3, 1e-3], [1e-3, 1e-3, 1e-3 + 2 * R - xi]])
    box = Box(2e-3, 2e-3, 0.0, 3e-3)
    s = contact_stress(x, np.array([R, R]), np.array([[0, 1]]), box, QUARTZ,
                       z_range=(0.5e-3, 2e-3))
    F = float(hertz_force(xi, R / 2, QUARTZ.E_f))
    # The overlap is recovered from positions ~1e-3 m apart: ~1e-12 relative round-off in xi.
    assert s[2, 2] == pytest.approx(F * (2 * R - xi) / (2e-3 * 2e-3 * 1.5e-3), rel=1e-9)
    assert abs(s[0, 0]) + abs(s[0, 2]) + abs(s[1, 2]) < 1e-12 * s[2, 2]


@pytest.fixture(scope="module")
def settled():
    return settle(size=(3, 3, 6), fall_stiffness_factor=1e-3, seed=2, kinetic_tolerance=1e-5,
                  protocol="lattice")


@pytest.fixture(scope="module")
def compacted(settled):
    return compact(settled, target_stress=3e6, strain_step=2e-3)


def test_compaction_to_a_stress(settled, compacted):
    c = compacted
    rec = c.metadata["record"]
    assert c.stage == "compact"
    assert rec["stress_zz"][-1] >= 3e6 and all(s < 3e6 for s in rec["stress_zz"][:-1])
    assert np.all(np.diff(rec["porosity"]) < 0)
    assert np.all(np.diff(rec["stress_zz"]) > 0)
    assert rec["porosity"][-1] < settled.metadata["porosity"]
    assert rec["coordination_number"][-1] >= rec["coordination_number"][0]
    assert c.metadata["record_units"]["stress_zz"] == "Pa"
    assert c.metadata["stress_measure"] == "stress_zz"
    # Uniaxial compaction: the lateral stresses are below the vertical one.
    assert 0.4 * rec["stress_zz"][-1] < rec["stress_mean"][-1] < rec["stress_zz"][-1]


def test_porosity_of_a_compacted_pack_is_its_record(settled, compacted):
    """porosity(pack) measures the core window between the frozen slabs, the window of the
    compaction record (not from the original floor)."""
    rec = compacted.metadata["record"]
    assert porosity(compacted) == rec["porosity"][-1] == compacted.metadata["porosity"]
    # No porosity of the settled pack is carried over under a name of the compacted one.
    assert "porosity_from_floor" in settled.metadata
    assert "porosity_from_floor" not in compacted.metadata


def test_virial_equals_the_force_on_the_slabs(compacted):
    """sigma_zz of the core (normal and tangential forces) equals the force on the top slab
    per area, and minus that on the bottom slab, within 1 %; the tangential forces are part
    of that balance."""
    c = compacted
    x, r = c.positions, c.radii
    lo, hi = c.metadata["core_window_m"]
    frozen = np.zeros(c.n_grains, bool)
    frozen[c.metadata["frozen_grains"]] = True
    top, bottom = frozen & (x[:, 2] > hi), frozen & (x[:, 2] < lo)
    area = c.box.lx * c.box.ly
    f_top = group_force(x, r, c.pairs, c.box, c.material, top, c.history)
    f_bottom = group_force(x, r, c.pairs, c.box, c.material, bottom, c.history)
    s = contact_stress(x, r, c.pairs, c.box, c.material, z_range=(lo, hi), history=c.history)
    assert s[2, 2] == pytest.approx(c.metadata["stress_zz"], rel=1e-12)
    assert s[2, 2] == pytest.approx(f_top[2] / area, rel=0.01)
    assert s[2, 2] == pytest.approx(-f_bottom[2] / area, rel=0.01)
    normal_only = contact_stress(x, r, c.pairs, c.box, c.material, z_range=(lo, hi))
    assert abs(normal_only[2, 2] / s[2, 2] - 1) > 1e-3


def test_compaction_to_a_porosity(settled):
    target = settled.metadata["porosity"] - 0.008
    c = compact(settled, target_porosity=target, strain_step=2e-3)
    assert c.metadata["porosity"] <= target < c.metadata["record"]["porosity"][-2]


@pytest.mark.parametrize("kwargs,match", [
    (dict(), "target"),
    (dict(target_stress=1e6, stress_measure="stress_xy"), "stress_measure"),
    (dict(target_porosity=0.6), "not below"),
    (dict(target_stress=-1.0), "target_stress"),
    (dict(target_stress=1e6, strain_step=0.5), "strain_step"),
    (dict(target_stress=1e6, slab=10.0), "slab"),
    (dict(target_stress=1e6, max_increments=0), "max_increments"),
    (dict(target_stress=1e6, rest_tolerance=0.0), "rest_tolerance"),
    (dict(target_stress=1e6, drag=-1.0), "drag"),
])
def test_compaction_bad_input(settled, kwargs, match):
    with pytest.raises(ValueError, match=match):
        compact(settled, **kwargs)


def test_unreachable_target_porosity(settled):
    with pytest.raises(ValueError, match="target_porosity"):
        compact(settled, target_porosity=0.1)


def test_prepare_pack_resumes_from_saved_stages(tmp_path, monkeypatch):
    import md.protocols as P

    calls = []
    real_settle, real_compact = P.settle, P.compact
    monkeypatch.setattr(P, "settle", lambda **k: calls.append("settle") or real_settle(**k))
    monkeypatch.setattr(P, "compact",
                        lambda p, **k: calls.append("compact") or real_compact(p, **k))
    opts = dict(size=(3, 3, 6), fall_stiffness_factor=1e-3, seed=2, kinetic_tolerance=1e-5,
                protocol="lattice")
    first = P.prepare_pack(tmp_path, settle_options=opts,
                           compact_options=dict(target_stress=1e6))
    assert calls == ["settle", "compact"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["compact.nc", "settle.nc"]
    (tmp_path / "compact.nc").unlink()           # as if interrupted during compaction
    again = P.prepare_pack(tmp_path, settle_options=opts,
                           compact_options=dict(target_stress=1e6))
    assert calls == ["settle", "compact", "compact"]     # the settled stage was not redone
    np.testing.assert_allclose(again.positions, first.positions, rtol=1e-12)
    done = P.prepare_pack(tmp_path, settle_options=opts, compact_options=dict(target_stress=1e6))
    assert calls == ["settle", "compact", "compact"] and done.stage == "compact"
    # Another compaction stress redoes the compaction only; another seed redoes both. The new
    # target lies above the stress the first run stopped at (a strain step can overshoot 1 MPa
    # by a pack-dependent amount, and packs differ between CPUs in their last bits).
    target = 1.5 * done.metadata["stress_zz"]
    harder = P.prepare_pack(tmp_path, settle_options=opts,
                            compact_options=dict(target_stress=target))
    assert calls[3:] == ["compact"] and harder.metadata["target_stress"] == target
    assert harder.metadata["stress_zz"] >= target > done.metadata["stress_zz"]
    other = P.prepare_pack(tmp_path, settle_options={**opts, "seed": 3},
                           compact_options=dict(target_stress=target))
    assert calls[4:] == ["settle", "compact"] and other.metadata["seed"] == 3
    # The settled stage alone is reused when only compaction options change.
    P.prepare_pack(tmp_path, settle_options={**opts, "seed": 3}, compact_options=None)
    assert calls[6:] == []


def test_isotropic_compaction_shrinks_the_periodic_box(settled):
    """isotropic=True: every increment shortens x, y (box and positions) and z alike; the mean
    stress is recorded and stops the run."""
    c = compact(settled, target_stress=1e6, strain_step=5e-4, isotropic=True)
    rec = c.metadata["record"]
    k = len(rec["strain"])
    assert c.box.lx == pytest.approx(settled.box.lx * (1 - 5e-4) ** k, rel=1e-12)
    assert c.box.ly == pytest.approx(settled.box.ly * (1 - 5e-4) ** k, rel=1e-12)
    assert rec["stress_mean"][-1] >= 1e6 and all(s < 1e6 for s in rec["stress_mean"][:-1])
    assert rec["porosity"][-1] < settled.metadata["porosity"]
    assert c.metadata["isotropic"] is True


def test_recorded_strain_is_the_height_change(settled, compacted):
    """The frozen slabs hold the lowest and highest grains and move only with the affine
    steps, so the recorded strain is 1 - H/H_0 of the span of the grain centres (the
    increments compound: k steps of s give 1 - (1 - s)^k, not k s)."""
    rec = compacted.metadata["record"]
    h0 = np.ptp(settled.positions[:, 2])
    h = np.ptp(compacted.positions[:, 2])
    assert len(rec["strain"]) >= 2
    assert rec["strain"][-1] == pytest.approx(1.0 - h / h0, rel=1e-9)


def test_recorded_coordination_counts_contacts_with_the_slabs(compacted):
    """The coordination number of the mobile grains, counted here over all pairs by brute
    force (minimum image in x and y), includes their contacts with frozen slab grains."""
    c = compacted
    x, r = c.positions, c.radii
    d = x[None, :, :] - x[:, None, :]
    d[..., 0] -= c.box.lx * np.round(d[..., 0] / c.box.lx)
    d[..., 1] -= c.box.ly * np.round(d[..., 1] / c.box.ly)
    touch = np.linalg.norm(d, axis=2) < r[:, None] + r[None, :]
    np.fill_diagonal(touch, False)
    mobile = np.ones(c.n_grains, bool)
    mobile[c.metadata["frozen_grains"]] = False
    assert touch[mobile][:, ~mobile].any()          # some mobile grains touch a slab
    expected = touch[mobile].sum(axis=1).mean()
    assert c.metadata["coordination_number"] == pytest.approx(expected, rel=1e-12)


def test_compacted_pack_time_adds_the_compaction(settled, compacted):
    """Pack.time is the simulated time at the end of the stage: the settling time plus the
    compaction steps, each no longer than the time step of the settled state's stiffest
    contact with no impact (contacts only stiffen under compaction); it was left at 0."""
    from md.integrate import contact_time_step
    from md.neighbors import build_neighbors

    x, r = settled.positions, settled.radii
    mobile = np.ones(settled.n_grains, bool)
    mobile[compacted.metadata["frozen_grains"]] = False
    pairs = build_neighbors(x, r, settled.box, 0.0).pairs
    dt0 = contact_time_step(x, r, pairs, settled.box, settled.material, mobile=mobile)
    elapsed = compacted.time - settled.time
    assert 0 < elapsed <= compacted.metadata["compaction_steps"] * dt0
