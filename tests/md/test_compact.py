"""Compaction between frozen slabs, and the contact stress (virial) it records."""

import numpy as np
import pytest

from md.contact import QUARTZ, hertz_force
from md.observe import contact_stress
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
    return settle(size=(3, 3, 6), fall_stiffness_factor=1e-3, seed=2, kinetic_tolerance=1e-5)


def test_compaction_to_a_stress(settled):
    c = compact(settled, target_stress=3e6, strain_step=2e-3)
    rec = c.metadata["record"]
    assert c.stage == "compact"
    assert rec["stress_zz"][-1] >= 3e6 and all(s < 3e6 for s in rec["stress_zz"][:-1])
    assert np.all(np.diff(rec["porosity"]) < 0)
    assert np.all(np.diff(rec["stress_zz"]) > 0)
    assert rec["porosity"][-1] < settled.metadata["porosity"]
    assert rec["coordination_number"][-1] >= rec["coordination_number"][0]


def test_compaction_to_a_porosity(settled):
    c = compact(settled, target_porosity=0.387, strain_step=2e-3)
    assert c.metadata["record"]["porosity"][-1] <= 0.387


@pytest.mark.parametrize("kwargs,match", [
    (dict(), "target"),
    (dict(target_porosity=0.6), "not below"),
    (dict(target_stress=-1.0), "target_stress"),
    (dict(target_stress=1e6, strain_step=0.5), "strain_step"),
    (dict(target_stress=1e6, slab=10.0), "slab"),
])
def test_compaction_bad_input(settled, kwargs, match):
    with pytest.raises(ValueError, match=match):
        compact(settled, **kwargs)


def test_unreachable_target_porosity(settled):
    with pytest.raises(ValueError, match="target_porosity"):
        compact(settled, target_porosity=0.1)


def test_blow_up_is_detected():
    """A time step far too large for the stiffness must stop with a clear error, not NaN."""
    import numpy as np

    from md.protocols import _check_overlaps

    x = np.array([[0.0, 0.0, 0.0], [3e-4, 0.0, 0.0]])
    with pytest.raises(RuntimeError, match="settle: the integration blew up"):
        _check_overlaps("settle", x, np.array([2e-4, 2e-4]), np.array([[0, 1]]),
                        Box(2e-3, 2e-3, 0.0, 1e-3))


def test_prepare_pack_resumes_from_saved_stages(tmp_path, monkeypatch):
    import md.protocols as P

    calls = []
    real_settle, real_compact = P.settle, P.compact
    monkeypatch.setattr(P, "settle", lambda **k: calls.append("settle") or real_settle(**k))
    monkeypatch.setattr(P, "compact", lambda p, **k: calls.append("compact") or real_compact(p, **k))
    opts = dict(size=(3, 3, 6), fall_stiffness_factor=1e-3, seed=2, kinetic_tolerance=1e-5)
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
