"""Fluid substitution: Gassmann's equation, the generalized multi-mineral Gassmann modulus and
their inverses.

Moduli in GPa, porosity and fractions as fractions. The shear modulus is unaffected by the fluid
in all of these (it is returned by no function here: ``G_sat = G_dry``).
"""

from __future__ import annotations

import numpy as np

from .validation import (as_array, broadcast, broadcast_phases, check_fractions,
                          check_modulus, check_positive, check_range, sum_phases)
from .validation import labelled

__all__ = ["gassmann", "gassmann_dry", "generalized_gassmann", "generalized_gassmann_dry"]


def _check_common(K_min, K_fluid, phi, *, phi_open_low=False):
    K_min = check_modulus("K_min", as_array("K_min", K_min))
    K_fluid = check_modulus("K_fluid", as_array("K_fluid", K_fluid), allow_zero=True)
    phi = check_range("phi", as_array("phi", phi), 0.0, 1.0, low_open=phi_open_low)
    return K_min, K_fluid, phi


@labelled(units="GPa")
def gassmann(K_dry, K_min, K_fluid, phi):
    r"""Saturated bulk modulus by Gassmann's equation, eqs. 4–6 of [Carcione2022]_.

    .. math::

        K_G = K_m + \alpha^2 M, \qquad
        M = \Big(\frac{\alpha - \phi}{K_s} + \frac{\phi}{K_f}\Big)^{-1}, \qquad
        \alpha = 1 - \frac{K_m}{K_s}

    evaluated as :math:`M = K_s K_f / [(\alpha-\phi) K_f + \phi K_s]` so that an empty pore
    (``K_fluid = 0``) gives ``K_dry`` exactly and ``phi = 0`` gives ``K_min`` ([Gassmann1951]_).

    Parameters
    ----------
    K_dry : float or array_like
        Dry-frame bulk modulus :math:`K_m`, GPa, in [0, ``K_min``].
    K_min : float or array_like
        Mineral (solid) bulk modulus :math:`K_s`, GPa, ``> 0``.
    K_fluid : float or array_like
        Pore-fluid bulk modulus :math:`K_f`, GPa, ``>= 0``.
    phi : float or array_like
        Porosity, in [0, 1].

    Returns
    -------
    ndarray
        Saturated bulk modulus, GPa, in [``K_dry``, ``K_min``] for ``K_fluid <= K_min``.

    Examples
    --------
    >>> round(float(gassmann(10.0, 40.0, 2.2, 0.2)), 4)
    15.3746
    """
    K_min, K_fluid, phi = _check_common(K_min, K_fluid, phi)
    K_dry = check_modulus("K_dry", as_array("K_dry", K_dry), allow_zero=True)
    K_dry, K_min, K_fluid, phi = broadcast(K_dry=K_dry, K_min=K_min, K_fluid=K_fluid, phi=phi)
    if np.any(K_dry > K_min * (1.0 + 1e-12)):
        raise ValueError("K_dry must not exceed K_min (the frame cannot be stiffer than its "
                         "mineral)")
    return _gassmann(K_dry, K_min, K_fluid, phi)


def _gassmann(K_dry, K_min, K_fluid, phi):
    """Eqs. 4–6 of [Carcione2022]_ (:func:`gassmann`, the same arithmetic) of checked inputs
    that broadcast, ``K_dry <= K_min``."""
    alpha = 1.0 - K_dry / K_min
    denom = (alpha - phi) * K_fluid + phi * K_min
    # alpha^2 M as alpha (alpha M): where alpha and phi are both tiny, M alone overflows while
    # alpha M stays below K_min K_fluid / ((alpha - phi) K_fluid + phi K_min) * alpha, finite.
    if np.size(denom) == 0 or np.min(denom) > 0.0:     # the common case: no guard needed
        alpha_M = alpha * K_min * K_fluid / denom
    else:
        ok = denom > 0.0
        alpha_M = np.where(ok, alpha * K_min * K_fluid / np.where(ok, denom, 1.0), 0.0)
    # Where denom = 0 (K_f = 0 and phi = 0, or phi = 0 and K_dry = K_min) there is nothing to add.
    return K_dry + alpha * alpha_M


@labelled(units="GPa")
def gassmann_dry(K_sat, K_min, K_fluid, phi):
    r"""Dry-frame bulk modulus from the saturated one: Gassmann's equation inverted.

    .. math::

        K_m = \frac{K_G\,(\phi K_s + (1-\phi) K_f) - K_s K_f}
                   {\phi K_s + K_f (K_G/K_s - 1 - \phi)}

    ([Mavko2009]_, Sect. 6.3), the exact inverse of :func:`gassmann`.

    Parameters
    ----------
    K_sat : float or array_like
        Saturated bulk modulus, GPa, in (0, ``K_min``].
    K_min, K_fluid : float or array_like
        Mineral and fluid bulk moduli, GPa.
    phi : float or array_like
        Porosity, in (0, 1]. At zero porosity every frame saturates to ``K_min``, so the inverse
        is undefined there.

    Returns
    -------
    ndarray
        Dry-frame bulk modulus, GPa.

    Raises
    ------
    ValueError
        If ``K_sat`` is softer than any dry frame allows (the implied ``K_dry`` would be negative).

    Examples
    --------
    >>> round(float(gassmann_dry(gassmann(10.0, 40.0, 2.2, 0.2), 40.0, 2.2, 0.2)), 12)
    10.0
    """
    K_min, K_fluid, phi = _check_common(K_min, K_fluid, phi, phi_open_low=True)
    K_sat = check_positive("K_sat", check_modulus("K_sat", as_array("K_sat", K_sat),
                                                  allow_zero=True))
    K_sat, K_min, K_fluid, phi = broadcast(K_sat=K_sat, K_min=K_min, K_fluid=K_fluid, phi=phi)
    if np.any(K_sat > K_min * (1.0 + 1e-12)):
        raise ValueError("K_sat must not exceed K_min")
    num = K_sat * (phi * K_min + (1.0 - phi) * K_fluid) - K_min * K_fluid
    den = phi * K_min + K_fluid * (K_sat / K_min - 1.0 - phi)
    if np.any(den <= 0.0) or np.any(num < -1e-12 * K_min * np.maximum(K_fluid, 1.0)):
        raise ValueError(
            "K_sat is below the fluid-saturated suspension (Reuss) value for this K_fluid and phi; "
            "no non-negative dry modulus reproduces it")
    return np.maximum(num / den, 0.0)


_ABSENT = object()


def _generalized_inputs(K_solid, solid_fractions, K_fluid, phi, *, K_frame=_ABSENT,
                        K_sat=_ABSENT):
    """Checked inputs of the generalized Gassmann pair, broadcast by name: the phase arrays
    (fractions, ``K_solid``, ``K_frame``) to ``(..., n)``, the others (``K_fluid``, ``phi``,
    ``K_sat``) to ``(...)``. The fractions and the frame moduli keep their own number of phases
    ``n``: ``[1.0]`` is not stretched over two solids, nor one frame modulus counted once per
    solid. Returns ``beta, K_i[, K_mi], K_fluid, phi[, K_sat]``."""
    K_i = check_modulus("K_solid", as_array("K_solid", K_solid))
    beta = check_fractions("solid_fractions", as_array("solid_fractions", solid_fractions))
    per_depth = {"K_fluid": check_modulus("K_fluid", as_array("K_fluid", K_fluid),
                                           allow_zero=True),
                 "phi": check_range("phi", as_array("phi", phi), 0.0, 1.0, high_open=True)}
    phases = {"K_solid": K_i}
    if K_frame is not _ABSENT:
        phases["K_frame"] = check_modulus("K_frame", as_array("K_frame", K_frame),
                                           allow_zero=True)
    if K_sat is not _ABSENT:
        per_depth["K_sat"] = check_positive(
            "K_sat", check_modulus("K_sat", as_array("K_sat", K_sat), allow_zero=True))
    broadcast(**per_depth)            # a mismatch among these is named with their own shapes
    out = broadcast_phases(("solid_fractions", beta), **phases,
                           **{k: v[..., None] for k, v in per_depth.items()})
    if K_frame is not _ABSENT and (phases["K_frame"].ndim == 0
                                or phases["K_frame"].shape[-1] != beta.shape[-1]):
        raise ValueError(f"K_frame must hold one frame modulus per solid on its last axis "
                         f"({beta.shape[-1]}, as solid_fractions); got shape "
                         f"{phases['K_frame'].shape}")
    if K_frame is not _ABSENT and np.any(out[2] > out[0] * out[1] * (1.0 + 1e-12)):
        raise ValueError("K_frame must not exceed solid_fractions * K_solid, solid by solid "
                         "(each Biot coefficient alpha_i = beta_i - K_frame_i / K_solid_i is "
                         ">= 0; eq. 13 of Carcione et al. 2022 gives K_frame_i <= beta_i K_i)")
    n = 1 + len(phases)
    return (*out[:n], *(a[..., 0] for a in out[n:]))


@labelled(units="GPa", phases=("K_frame", "K_solid", "solid_fractions"))
def generalized_gassmann(K_frame, K_solid, solid_fractions, K_fluid, phi):
    r"""Generalized Gassmann modulus of a multi-mineral porous rock, eqs. 10–12 of [Carcione2022]_.

    .. math::

        K_G = \sum_i K_{mi} + \Big(\sum_i \alpha_i\Big)^2 M, \qquad
        M = \Big(\sum_i \frac{\phi'_i}{K_i} + \frac{\phi}{K_f}\Big)^{-1},

        \phi'_i = \alpha_i - \beta_i\phi, \qquad \alpha_i = \beta_i - \frac{K_{mi}}{K_i}

    ([Carcione2005]_). Eq. 10 as printed in [Carcione2022]_ raises the sum of the
    :math:`\alpha_i` to the power ``n`` (the number of solids); the derivation of [Carcione2005]_
    gives the square, which the printed form equals for the ``n = 2`` of that paper. The square is
    used here, so that one solid recovers :func:`gassmann` for any ``n``.

    Parameters
    ----------
    K_frame : array_like, shape (..., n)
        Frame moduli :math:`K_{mi}` of the solids (e.g. from
        :func:`rockcem.frames.krief_multimineral`), GPa, in [0, :math:`\beta_i K_i`] (each
        solid's Biot coefficient :math:`\alpha_i` non-negative).
    K_solid : array_like, shape (..., n)
        Bulk moduli :math:`K_i` of the solids, GPa, ``> 0``.
    solid_fractions : array_like, shape (..., n)
        :math:`\beta_i`, fraction of each solid per unit volume of solid (sum to 1).
    K_fluid : float or array_like, shape (...)
        Fluid bulk modulus, GPa, ``>= 0``.
    phi : float or array_like, shape (...)
        Porosity, in [0, 1).

    Returns
    -------
    ndarray, shape (...)
        Saturated bulk modulus, GPa.
    """
    beta, K_i, K_mi, K_fluid, phi = _generalized_inputs(K_solid, solid_fractions, K_fluid, phi,
                                                        K_frame=K_frame)
    return _generalized_gassmann(K_mi, K_i, beta, K_fluid, phi)


def _generalized_gassmann(K_mi, K_i, beta, K_fluid, phi):
    """Eqs. 10–12 of [Carcione2022]_ (:func:`generalized_gassmann`) of checked inputs that
    broadcast (the phase arrays ``K_mi``, ``K_i``, ``beta`` with the phases last, ``K_fluid``
    and ``phi`` without), phase by phase: the sums over the phases are those of
    :func:`rockcem.validation.sum_phases` (the same additions in the same order), without a
    temporary with a short last axis (a per-row cost in numpy)."""
    alpha = compliance = K_m = None
    for i in range(beta.shape[-1]):
        b, k, k_m = beta[..., i], K_i[..., i], K_mi[..., i]
        alpha_i = b - k_m / k
        term = (alpha_i - b * phi) / k
        if alpha is None:
            alpha, compliance, K_m = alpha_i, term, k_m
        else:
            alpha = alpha + alpha_i
            compliance = compliance + term
            K_m = K_m + k_m
    # M = 1/(compliance + phi/K_f) = K_f / (K_f compliance + phi), finite for K_f = 0.
    denom = K_fluid * compliance + phi
    if np.size(denom) == 0 or np.min(denom) > 0.0:     # the common case: no guard needed
        alpha_M = alpha * K_fluid / denom
    else:
        ok = denom > 0.0
        alpha_M = np.where(ok, alpha * K_fluid / np.where(ok, denom, 1.0), 0.0)  # as gassmann
    # denom = 0 only when phi = 0 and sum(alpha_i/K_i) = 0, i.e. the frame is the mineral.
    return K_m + alpha * alpha_M


@labelled(units="GPa", phases=("K_solid", "solid_fractions"))
def generalized_gassmann_dry(K_sat, K_solid, solid_fractions, K_fluid, phi):
    r"""Invert :func:`generalized_gassmann` for the total frame modulus :math:`K_m = \sum K_{mi}`.

    The partition of the frame among the solids is that of eq. 13 of [Carcione2022]_,
    :math:`K_{mi} = w_i K_m` with :math:`w_i = \beta_i K_i / \sum_j \beta_j K_j`. Then
    eq. 10 becomes :math:`(K_G - K_m)(a - b K_m) = (1 - K_m/V_K)^2` with
    :math:`a = (1-\phi)\sum_i \beta_i/K_i + \phi/K_f`, :math:`b = \sum_i \beta_i/(V_K K_i)`,
    :math:`V_K = \sum_i \beta_i K_i`: a quadratic in :math:`K_m` whose root in
    :math:`[0, K_G]` is returned. For one solid it is the inverse of Gassmann's equation.

    Parameters
    ----------
    K_sat : float or array_like, shape (...)
        Saturated bulk modulus, GPa, ``> 0``.
    K_solid, solid_fractions : array_like, shape (..., n)
        As in :func:`generalized_gassmann`.
    K_fluid : float or array_like, shape (...)
        Fluid bulk modulus, GPa, in [:data:`rockcem.validation.MIN_MODULUS`,
        :data:`rockcem.validation.MAX_MODULUS`] (an empty pore hides the frame).
    phi : float or array_like, shape (...)
        Porosity, in (0, 1).

    Returns
    -------
    ndarray, shape (...)
        Total frame bulk modulus :math:`K_m`, GPa. Multiply by :math:`w_i` for the per-solid values.
    """
    beta, K_i, K_fluid, phi, K_sat = _generalized_inputs(K_solid, solid_fractions, K_fluid, phi,
                                                         K_sat=K_sat)
    check_modulus("K_fluid", K_fluid)           # > 0: an empty pore hides the frame
    check_range("phi", phi, 0.0, 1.0, low_open=True, high_open=True)
    if np.any(K_sat > sum_phases(beta * K_i) * (1.0 + 1e-12)):
        raise ValueError("K_sat must not exceed the Voigt average of the solids, "
                         "sum(solid_fractions * K_solid): no porous rock is stiffer")
    if np.any(K_fluid >= np.min(K_i, axis=-1)):
        raise ValueError("K_fluid must be below the bulk moduli of all solids for the inverse: a "
                         "fluid as stiff as the solid hides the frame")
    V_K = np.sum(beta * K_i, axis=-1)
    a = (1.0 - phi) * np.sum(beta / K_i, axis=-1) + phi / K_fluid
    b = np.sum(beta / K_i, axis=-1) / V_K
    q2 = b - 1.0 / V_K**2          # >= 0 by Cauchy–Schwarz; 0 for one solid
    q1 = -(K_sat * b + a) + 2.0 / V_K
    q0 = K_sat * a - 1.0
    # Stable root of q2 x^2 + q1 x + q0 = 0 on the branch continuous with the linear (q2 = 0) case.
    disc = q1 * q1 - 4.0 * q2 * q0
    if np.any(disc < 0.0):
        raise ValueError("K_sat admits no real frame modulus for these solids, fluid and porosity")
    den = -q1 + np.sqrt(disc)
    if np.any(den <= 0.0):
        raise ValueError("K_sat does not determine a frame modulus at this phi: at a porosity "
                         "this close to 0 every frame saturates to the mineral")
    root = 2.0 * q0 / den
    # Round-off allowance: the inverse loses digits as K_fluid approaches the solid moduli
    # (relative conditioning ~ K_sat / (K_sat - Reuss(K_solid, K_fluid))).
    slack = 1e-9 * K_sat
    if np.any(root < -slack) or np.any(root > K_sat + slack):
        raise ValueError(
            "K_sat is outside the range a dry frame in [0, K_sat] can produce for these inputs")
    return np.clip(root, 0.0, K_sat)
