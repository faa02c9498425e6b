"""rockcem.anisotropy: Thomsen's parameters, the TI bulk modulus and anisotropic Gassmann,
against independent values (isotropic Gassmann, the 6 x 6 compliance inverted by numpy, the
Biot-Gassmann tensor form evaluated on the full 6 x 6 stiffness)."""

import numpy as np
import pytest

from rockcem.anisotropy import thomsen, ti_bulk_modulus, ti_gassmann, vertical_velocities
from rockcem.fluids import gassmann


def _iso(K, G):
    """TI constants (c11, c13, c33, c44, c66) of an isotropic medium."""
    lam = K - 2.0 * G / 3.0
    return lam + 2 * G, lam, lam + 2 * G, G, G


def _full(c11, c13, c33, c44, c66):
    """The 6 x 6 Voigt stiffness of a TI medium (axis 3)."""
    c12 = c11 - 2 * c66
    C = np.zeros((6, 6))
    C[:3, :3] = [[c11, c12, c13], [c12, c11, c13], [c13, c13, c33]]
    C[3, 3] = C[4, 4] = c44
    C[5, 5] = c66
    return C


# A TI frame (GPa) of a compacted pack: C33 > C11, C44 > C66 (epsilon, gamma < 0).
FRAME = dict(c11=6.0, c13=2.0, c33=9.0, c44=3.5, c66=2.5)


def test_isotropic_medium_has_zero_thomsen_parameters():
    t = thomsen(*_iso(37.0, 44.0))
    assert np.allclose(t, 0.0, atol=1e-15)


def test_thomsen_by_hand():
    """eq. 8a: (12 - 10)/20; 8b: (5 - 4)/8; 17: ((3 + 4)^2 - (10 - 4)^2)/(2 10 (10 - 4))."""
    t = thomsen(12.0, 3.0, 10.0, 4.0, 5.0)
    assert t.epsilon == pytest.approx(0.1, rel=1e-14)
    assert t.gamma == pytest.approx(0.125, rel=1e-14)
    assert t.delta == pytest.approx(13.0 / 120.0, rel=1e-14)


def test_ti_bulk_modulus_is_the_inverse_sum_of_the_compliances():
    """1/K = sum_{i,j<=3} S_ij of the 6 x 6 stiffness inverted by numpy; below the Voigt-type
    C_iijj/9; lambda + 2/3 mu for an isotropic medium."""
    S = np.linalg.inv(_full(**FRAME))
    K = ti_bulk_modulus(FRAME["c11"], FRAME["c13"], FRAME["c33"], FRAME["c66"])
    assert K == pytest.approx(1.0 / S[:3, :3].sum(), rel=1e-13)
    assert K < np.trace(_full(**FRAME)[:3, :3] @ np.ones((3, 3))) / 9.0
    c11, c13, c33, _, c66 = _iso(37.0, 44.0)
    assert ti_bulk_modulus(c11, c13, c33, c66) == pytest.approx(37.0, rel=1e-13)


def test_isotropic_frame_reduces_to_gassmann():
    """An isotropic dry frame: K_sat = C33 - 4/3 C44 = C11 - 4/3 C66 is rockcem.fluids.gassmann,
    the shear moduli stay, and the saturated frame stays isotropic."""
    K, G, K0, Kf, phi = 9.0, 7.0, 36.6, np.array([0.0, 2.4, 0.05]), 0.27
    s = ti_gassmann(*_iso(K, G), K0, Kf, phi)
    want = gassmann(K, K0, Kf, phi)
    assert np.allclose(s.c33 - 4 / 3 * s.c44, want, rtol=1e-13)
    assert np.allclose(s.c11 - 4 / 3 * s.c66, want, rtol=1e-13)
    assert np.allclose(s.c13, want - 2 / 3 * G, rtol=1e-13)
    assert np.all(s.c44 == G) and np.all(s.c66 == G)
    assert np.allclose(thomsen(*s), 0.0, atol=1e-14)


def test_ti_gassmann_against_the_biot_tensor_form():
    """Brown & Korringa's general form on the full 6 x 6 matrices by numpy:
    C_sat = C_dry + M alpha (x) alpha, alpha = (I - C_dry S_0) m, m = (1,1,1,0,0,0),
    1/M = phi/K_f - phi/K_0 + m.S_0.m - m.S_0.C_dry.S_0.m, S_0 the mineral's compliance
    (inverted from its stiffness, not written as 1/3K_0); C44 and C66 unchanged."""
    K0, G0, Kf, phi = 37.0, 44.0, 2.7, 0.22
    C = _full(**FRAME)
    S0 = np.linalg.inv(_full(*_iso(K0, G0)))
    m = np.array([1.0, 1, 1, 0, 0, 0])
    alpha = m - C @ S0 @ m
    M = 1.0 / (phi / Kf - phi / K0 + m @ S0 @ m - m @ S0 @ C @ S0 @ m)
    want = C + M * np.outer(alpha, alpha)
    s = ti_gassmann(**FRAME, K_min=K0, K_fluid=Kf, phi=phi)
    got = _full(*s)
    np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-12)
    assert s.c44 == FRAME["c44"] and s.c66 == FRAME["c66"]
    assert s.c33 > FRAME["c33"] and s.c11 > FRAME["c11"]


def test_empty_pore_returns_the_dry_frame():
    s = ti_gassmann(**FRAME, K_min=37.0, K_fluid=0.0, phi=[0.0, 0.3])
    for got, key in zip(s, ("c11", "c13", "c33", "c44", "c66")):
        assert np.all(got == FRAME[key])


def test_vertical_velocities():
    v = vertical_velocities([36.0, 9.0], 16.0, 2.25)
    np.testing.assert_allclose(v.vp, [4.0, 2.0], rtol=1e-15)
    np.testing.assert_allclose(v.vs, 8.0 / 3.0, rtol=1e-15)


@pytest.mark.parametrize("kwargs,match", [
    (dict(FRAME, c66=6.0), "c11 must exceed c66"),
    (dict(FRAME, c13=7.0), "c13 must satisfy"),
    (dict(FRAME, c44=0.0), r"c44 must lie in"),
    (dict(FRAME, c33=np.nan), "c33 contains NaN"),
    (dict(FRAME, c11=6e9), "a modulus in Pa"),
])
def test_bad_constants_are_named(kwargs, match):
    with pytest.raises(ValueError, match=match):
        thomsen(**kwargs)
    with pytest.raises(ValueError, match=match):
        ti_gassmann(**kwargs, K_min=37.0, K_fluid=2.2, phi=0.2)


@pytest.mark.parametrize("kwargs,match", [
    (dict(K_min=3.0, K_fluid=2.2, phi=0.2), "K_min must be at least"),
    (dict(K_min=37.0, K_fluid=-1.0, phi=0.2), "K_fluid must lie in"),
    (dict(K_min=37.0, K_fluid=2.2, phi=1.2), r"phi must lie in \[0, 1\]"),
])
def test_bad_fluid_inputs_are_named(kwargs, match):
    with pytest.raises(ValueError, match=match):
        ti_gassmann(**FRAME, **kwargs)


def test_thomsen_delta_needs_c33_above_c44():
    with pytest.raises(ValueError, match="c33 must exceed c44"):
        thomsen(10.0, 1.0, 3.0, 4.0, 3.0)
