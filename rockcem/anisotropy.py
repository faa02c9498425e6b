r"""Transversely isotropic (TI) media: Thomsen's parameters, the bulk modulus under hydrostatic
stress, anisotropic Gassmann fluid substitution and the vertical velocities.

A TI medium with its symmetry axis along z (vertical: a compacted sediment, the MD engine's
pack) has five independent constants in Voigt notation, :math:`C_{11}, C_{13}, C_{33},
C_{44}, C_{66}`, with :math:`C_{12} = C_{11} - 2C_{66}`, :math:`C_{22} = C_{11}`,
:math:`C_{23} = C_{13}`, :math:`C_{55} = C_{44}`. Moduli in GPa, density in g/cm³, velocities
in km/s, porosity as a fraction. Every function takes floats or arrays, broadcasts them and
returns arrays (or a NamedTuple of arrays).

Input is refused, naming the argument and its range, where the constants do not describe a
stable (positive-definite) TI stiffness: :math:`C_{44} > 0`, :math:`C_{66} > 0`,
:math:`C_{11} > C_{66}` (:math:`C_{11} > |C_{12}|`) and
:math:`C_{13}^2 < C_{33}(C_{11} - C_{66})` (:math:`(C_{11} + C_{12})C_{33} > 2C_{13}^2`).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .fluids import _check_common
from .validation import (MAX_MODULUS, as_array, broadcast, check_modulus, check_positive,
                         check_range)
from .validation import labelled

__all__ = ["Thomsen", "TIStiffness", "VerticalVelocities", "thomsen", "ti_bulk_modulus",
           "ti_gassmann", "vertical_velocities"]


class Thomsen(NamedTuple):
    """Thomsen's anisotropy parameters (dimensionless)."""

    epsilon: np.ndarray
    gamma: np.ndarray
    delta: np.ndarray


class TIStiffness(NamedTuple):
    """The five constants of a TI medium, GPa."""

    c11: np.ndarray
    c13: np.ndarray
    c33: np.ndarray
    c44: np.ndarray
    c66: np.ndarray


class VerticalVelocities(NamedTuple):
    """P- and S-wave velocities along the symmetry axis, km/s."""

    vp: np.ndarray
    vs: np.ndarray


def _check_ti(c11, c13, c33, c44=None, c66=None):
    """The TI constants as broadcast arrays, refused unless they are a positive-definite
    stiffness (``c44`` may be omitted where it is not used)."""
    arrays = {"c11": check_modulus("c11", as_array("c11", c11)),
              "c13": check_range("c13", as_array("c13", c13), -MAX_MODULUS, MAX_MODULUS),
              "c33": check_modulus("c33", as_array("c33", c33))}
    if c44 is not None:
        arrays["c44"] = check_modulus("c44", as_array("c44", c44))
    arrays["c66"] = check_modulus("c66", as_array("c66", c66))
    out = dict(zip(arrays, broadcast(**arrays)))
    c11, c13, c33, c66 = out["c11"], out["c13"], out["c33"], out["c66"]
    bad = c11 <= c66
    if np.any(bad):
        raise ValueError("c11 must exceed c66 (c11 > |c12| with c12 = c11 - 2 c66: a "
                         f"positive-definite TI stiffness); got c11 {float(c11[bad].flat[0]):g}"
                         f" <= c66 {float(c66[bad].flat[0]):g}")
    bad = c13**2 >= c33 * (c11 - c66)
    if np.any(bad):
        raise ValueError("c13 must satisfy c13**2 < c33 (c11 - c66) (a positive-definite TI "
                         f"stiffness); got c13 {float(c13[bad].flat[0]):g} with c11 "
                         f"{float(c11[bad].flat[0]):g}, c33 {float(c33[bad].flat[0]):g}, c66 "
                         f"{float(c66[bad].flat[0]):g}")
    return out


@labelled(units="1")
def thomsen(c11, c13, c33, c44, c66) -> Thomsen:
    r"""Thomsen's anisotropy parameters of a TI medium (symmetry axis vertical).

    .. math::

        \epsilon = \frac{C_{11} - C_{33}}{2C_{33}}, \qquad
        \gamma = \frac{C_{66} - C_{44}}{2C_{44}}, \qquad
        \delta = \frac{(C_{13} + C_{44})^2 - (C_{33} - C_{44})^2}{2C_{33}(C_{33} - C_{44})}

    eqs. 8a, 8b and 17 of [Thomsen1986]_ (eq. 17's :math:`\delta`, which fixes the P-wave
    velocity near the vertical exactly to first order, rather than eq. 8c's
    :math:`\delta^*`). Valid for any anisotropy as definitions; Thomsen's weak-anisotropy
    velocities use them where they are small (:math:`\ll 1`).

    Parameters
    ----------
    c11, c13, c33, c44, c66 : float or array_like
        TI stiffness constants, GPa (any one unit: only ratios enter); a positive-definite
        stiffness with :math:`C_{33} > C_{44}` (else :math:`\delta` is undefined).

    Returns
    -------
    Thomsen
        ``(epsilon, gamma, delta)``, dimensionless; all zero for an isotropic medium.

    Examples
    --------
    :math:`\epsilon = 2/20`, :math:`\gamma = 1/8`,
    :math:`\delta = (7^2 - 6^2)/(2\cdot10\cdot6) = 13/120`:

    >>> t = thomsen(c11=12.0, c13=3.0, c33=10.0, c44=4.0, c66=5.0)
    >>> [round(float(v), 4) for v in t]
    [0.1, 0.125, 0.1083]
    """
    ti = _check_ti(c11, c13, c33, c44, c66)
    c11, c13, c33, c44, c66 = (ti[k] for k in ("c11", "c13", "c33", "c44", "c66"))
    if np.any(c33 <= c44):
        bad = c33 <= c44
        raise ValueError("c33 must exceed c44 for Thomsen's delta (eq. 17 divides by "
                         f"c33 - c44); got c33 {float(c33[bad].flat[0]):g} <= c44 "
                         f"{float(c44[bad].flat[0]):g}")
    epsilon = (c11 - c33) / (2.0 * c33)
    gamma = (c66 - c44) / (2.0 * c44)
    delta = ((c13 + c44)**2 - (c33 - c44)**2) / (2.0 * c33 * (c33 - c44))
    return Thomsen(epsilon, gamma, delta)


@labelled(units="GPa")
def ti_bulk_modulus(c11, c13, c33, c66):
    r"""Bulk modulus of a TI medium under hydrostatic stress (the Reuss-type modulus):
    :math:`1/K = \sum_{i,j=1}^{3} S_{ij}`, :math:`S = C^{-1}` the compliance (Voigt
    notation), i.e. the volumetric strain per unit confining or pore pressure. In closed form

    .. math::

        K = \frac{C_{33}(C_{11} + C_{12}) - 2C_{13}^2}{C_{11} + C_{12} + 2C_{33} - 4C_{13}},
        \qquad C_{12} = C_{11} - 2C_{66},

    from the inverse of the normal block of the stiffness (its compliances
    :math:`S_{11} + S_{12} = C_{33}/D`, :math:`S_{13} = -C_{13}/D`,
    :math:`S_{33} = (C_{11} + C_{12})/D`, :math:`D = C_{33}(C_{11} + C_{12}) - 2C_{13}^2`;
    [Mavko2009]_, Sect. 2.2 for the TI compliances). It is at most the Voigt-type
    :math:`C_{iijj}/9 = (2C_{11} + C_{33} + 2C_{12} + 4C_{13})/9` (the mean stress over the
    volumetric strain under a hydrostatic *strain*), with equality for an isotropic medium,
    where both are :math:`\lambda + \tfrac23\mu`. This, not :math:`C_{33} - \tfrac43 C_{44}`
    (the isotropic reading of the vertical P and S moduli), is the modulus that a
    fluid-substitution or a bulk-modulus comparison needs.

    Parameters
    ----------
    c11, c13, c33, c66 : float or array_like
        TI stiffness constants, GPa; positive definite.

    Returns
    -------
    ndarray
        Bulk modulus, GPa, > 0.

    Examples
    --------
    An isotropic medium, :math:`\lambda = 10`, :math:`\mu = 15` GPa (:math:`C_{11} = C_{33} =
    40`, :math:`C_{13} = 10`, :math:`C_{66} = 15`): :math:`K = \lambda + 2\mu/3 = 20` GPa.

    >>> float(ti_bulk_modulus(40.0, 10.0, 40.0, 15.0))
    20.0
    """
    ti = _check_ti(c11, c13, c33, None, c66)
    c11, c13, c33, c66 = (ti[k] for k in ("c11", "c13", "c33", "c66"))
    s = 2.0 * (c11 - c66)                   # c11 + c12
    return (c33 * s - 2.0 * c13**2) / (s + 2.0 * c33 - 4.0 * c13)


@labelled(units="GPa")
def ti_gassmann(c11, c13, c33, c44, c66, K_min, K_fluid, phi) -> TIStiffness:
    r"""Saturated stiffness of a TI dry frame of one isotropic mineral: the anisotropic form of
    Gassmann's equation ([Gassmann1951]_; [BrownKorringa1975]_ for any anisotropy, here their
    case of a homogeneous isotropic mineral), as written out in [Mavko2009]_, Sect. 6.3:

    .. math::

        C^{sat}_{ij} = C^{dry}_{ij} + M\alpha_i\alpha_j, \qquad
        \alpha_i = 1 - \frac{\sum_{k=1}^{3} C^{dry}_{ik}}{3K_0}, \qquad
        \frac1M = \frac{\phi}{K_f} + \frac{1 - \phi - K^*/K_0}{K_0}, \qquad
        K^* = \frac19\sum_{k,l=1}^{3} C^{dry}_{kl}

    (:math:`i, j \le 3`; the Handbook's form
    :math:`C^{sat}_{ij} = C^{dry}_{ij} + K_0^2\alpha_i\alpha_j /
    [(K_0/K_f)\phi(K_0 - K_f) + K_0 - K^*]` is the same after dividing by :math:`K_0^2`;
    :math:`M` is Biot's modulus and :math:`\alpha_i` the Biot coefficients). For TI,
    :math:`\alpha_1 = \alpha_2 = 1 - (C_{11} + C_{12} + C_{13})/3K_0`,
    :math:`\alpha_3 = 1 - (2C_{13} + C_{33})/3K_0`, so :math:`C_{11}`, :math:`C_{12}`,
    :math:`C_{13}`, :math:`C_{33}` stiffen, :math:`C_{66} = (C_{11} - C_{12})/2` and
    :math:`C_{44}` do not (the fluid carries no shear). An isotropic frame gives
    :func:`rockcem.fluids.gassmann`'s bulk modulus. :math:`M` is evaluated as
    :math:`K_0K_f/[\phi K_0 + (1 - \phi - K^*/K_0)K_f]`, so an empty pore (:math:`K_f = 0`)
    returns the dry frame exactly, as :func:`rockcem.fluids.gassmann` does.

    Parameters
    ----------
    c11, c13, c33, c44, c66 : float or array_like
        Dry-frame TI constants, GPa (symmetry axis z); positive definite, with
        :math:`K^* \le K_0`.
    K_min : float or array_like
        Mineral bulk modulus :math:`K_0`, GPa, ``> 0``.
    K_fluid : float or array_like
        Pore-fluid bulk modulus :math:`K_f`, GPa, ``>= 0``.
    phi : float or array_like
        Porosity, in [0, 1].

    Returns
    -------
    TIStiffness
        The saturated ``(c11, c13, c33, c44, c66)``, GPa.

    Examples
    --------
    An isotropic frame (:math:`K = 10`, :math:`G = 6` GPa) in quartz with brine at 20 %
    porosity: :math:`C_{33} - \tfrac43 C_{44}` is Gassmann's :math:`K_{sat}`
    (``gassmann(10, 40, 2.2, 0.2)`` is 15.3746).

    >>> s = ti_gassmann(18.0, 6.0, 18.0, 6.0, 6.0, 40.0, 2.2, 0.2)
    >>> round(float(s.c33 - 4.0 / 3.0 * s.c44), 4), float(s.c44)
    (15.3746, 6.0)
    """
    ti = _check_ti(c11, c13, c33, c44, c66)
    K0, Kf, phi = _check_common(K_min, K_fluid, phi)       # as rockcem.fluids.gassmann
    c11, c13, c33, c44, c66, K0, Kf, phi = broadcast(**ti, K_min=K0, K_fluid=Kf, phi=phi)
    c12 = c11 - 2.0 * c66
    k_star = (2.0 * c11 + c33 + 2.0 * c12 + 4.0 * c13) / 9.0
    if np.any(k_star > K0 * (1.0 + 1e-12)):
        raise ValueError("K_min must be at least the dry frame's (2 c11 + c33 + 2 c12 + 4 c13)/9 "
                         "(the frame cannot be stiffer than its mineral); got K_min "
                         f"{float(K0[k_star > K0].flat[0]):g} below "
                         f"{float(k_star[k_star > K0].flat[0]):g}")
    a1 = 1.0 - (c11 + c12 + c13) / (3.0 * K0)
    a3 = 1.0 - (2.0 * c13 + c33) / (3.0 * K0)
    denom = phi * K0 + (1.0 - phi - k_star / K0) * Kf
    ok = denom > 0.0
    # Where denom <= 0 (K_f = 0 and phi = 0, or phi = 0 and a frame as stiff as its mineral)
    # there is nothing to add, as in rockcem.fluids.gassmann.
    M = np.where(ok, K0 * Kf / np.where(ok, denom, 1.0), 0.0)
    return TIStiffness(c11 + M * a1**2, c13 + M * a1 * a3, c33 + M * a3**2, c44 + 0.0,
                       c66 + 0.0)


@labelled(units="km s-1")
def vertical_velocities(c33, c44, rho) -> VerticalVelocities:
    r"""P- and S-wave velocities along the symmetry axis of a TI medium,
    :math:`V_{P0} = \sqrt{C_{33}/\rho}`, :math:`V_{S0} = \sqrt{C_{44}/\rho}` (eqs. 9a–b of
    [Thomsen1986]_).

    Parameters
    ----------
    c33, c44 : float or array_like
        GPa, > 0.
    rho : float or array_like
        Density, g/cm³, > 0 (the saturated rock's for saturated constants).

    Returns
    -------
    VerticalVelocities
        ``(vp, vs)``, km/s.

    Examples
    --------
    >>> v = vertical_velocities(36.0, 16.0, 2.25)
    >>> float(v.vp), float(v.vs)
    (4.0, 2.6666666666666665)
    """
    c33 = check_modulus("c33", as_array("c33", c33))
    c44 = check_modulus("c44", as_array("c44", c44))
    rho = check_positive("rho", as_array("rho", rho))
    c33, c44, rho = broadcast(c33=c33, c44=c44, rho=rho)
    return VerticalVelocities(np.sqrt(c33 / rho), np.sqrt(c44 / rho))
