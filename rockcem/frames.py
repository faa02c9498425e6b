"""Dry-frame models: Krief's porosity law, single- and multi-mineral.

Moduli in GPa, porosity as a fraction.
"""

from __future__ import annotations

import numpy as np

from .validation import (as_array, broadcast, broadcast_phases, check_fractions,
                          check_modulus, check_range, sum_phases)
from .bounds import hashin_shtrikman_average
from .elastic import Moduli
from .validation import labelled

__all__ = ["krief", "krief_multimineral", "krief_factor", "MAX_KRIEF_EXPONENT"]

#: Largest Krief exponent accepted (published values 2-4; 3 in [Carcione2022]_): far beyond it
#: the frame is gone at any porosity, and A / (1 - phi) overflows.
MAX_KRIEF_EXPONENT = 100.0


@labelled(units="1")
def krief_factor(phi, A=3.0):
    r"""Krief's porosity factor :math:`(1-\phi)^{A/(1-\phi)}` (eq. 3 of [Carcione2022]_).

    Parameters
    ----------
    phi : float or array_like
        Porosity, in [0, 1). At ``phi -> 1`` the factor tends to 0 (returned as 0 at ``phi = 1``).
    A : float or array_like, optional
        Dimensionless Krief exponent, in (0, :data:`MAX_KRIEF_EXPONENT`] (3 in [Carcione2022]_
        and [Krief1990]_).
    """
    phi = check_range("phi", as_array("phi", phi), 0.0, 1.0)
    A = check_range("A", as_array("A", A), 0.0, MAX_KRIEF_EXPONENT, low_open=True)
    phi, A = broadcast(phi=phi, A=A)
    inside = phi < 1.0
    safe_phi = np.where(inside, phi, 0.0)
    # log1p keeps accuracy at small porosity; the limit at phi = 1 is exactly 0.
    return np.where(inside, np.exp(A / (1.0 - safe_phi) * np.log1p(-safe_phi)), 0.0)


@labelled(units="GPa")
def krief(K_min, G_min, phi, A=3.0) -> Moduli:
    r"""Krief dry-frame moduli, eq. 3 of [Carcione2022]_ ([Krief1990]_).

    .. math::

        K_m = K_s (1-\phi)^{A/(1-\phi)}, \qquad \mu_m = \mu_s (1-\phi)^{A/(1-\phi)}

    Parameters
    ----------
    K_min, G_min : float or array_like
        Bulk and shear moduli of the mineral (solid) phase, GPa; ``K_min > 0``, ``G_min >= 0``.
    phi : float or array_like
        Porosity, in [0, 1]. The law is empirical; it holds for any porosity in that range, with
        the frame moduli falling monotonically to 0 at ``phi = 1``.
    A : float, optional
        Krief exponent (dimensionless, in (0, :data:`MAX_KRIEF_EXPONENT`]); default 3.

    Returns
    -------
    Moduli
        Dry-frame ``K`` and ``G``, GPa, broadcast over the inputs.

    Examples
    --------
    >>> m = krief(40.0, 39.0, 0.2)
    >>> round(float(m.K), 3)
    17.324
    """
    K_min = check_modulus("K_min", as_array("K_min", K_min))
    G_min = check_modulus("G_min", as_array("G_min", G_min), allow_zero=True)
    broadcast(K_min=K_min, G_min=G_min, phi=as_array("phi", phi), A=as_array("A", A))
    factor = krief_factor(phi, A)
    K_min, G_min, factor = broadcast(K_min=K_min, G_min=G_min, phi=factor)
    return Moduli(K_min * factor, G_min * factor)


@labelled(units="GPa", phases=("K_solid", "G_solid", "solid_fractions"))
def krief_multimineral(K_solid, G_solid, solid_fractions, phi, A=3.0) -> Moduli:
    r"""Per-mineral Krief frame moduli of a multi-mineral rock, eqs. 13–14 of [Carcione2022]_.

    .. math::

        K_{mi} = \frac{K_s}{V_K}\,\beta_i K_i (1-\phi)^{A/(1-\phi)}, \qquad
        \mu_{mi} = \frac{\mu_s}{V_\mu}\,\beta_i \mu_i (1-\phi)^{A/(1-\phi)}

    with :math:`V_K = \sum_i \beta_i K_i`, :math:`V_\mu = \sum_i \beta_i \mu_i` (Voigt averages) and
    :math:`K_s, \mu_s` the Hashin–Shtrikman average of the minerals (eq. C.3), so that
    :math:`\sum_i K_{mi}` is Krief's law applied to the HS mineral modulus ([Carcione2005]_).

    Parameters
    ----------
    K_solid, G_solid : array_like, shape (..., n)
        Moduli of the ``n`` solid phases, GPa (``K > 0``, ``G >= 0``).
    solid_fractions : array_like, shape (..., n)
        :math:`\beta_i`, the fraction of each solid per unit volume of *solid* (sum to 1).
    phi : float or array_like, shape (...)
        Porosity, in [0, 1].
    A : float, optional
        Krief exponent; default 3.

    Returns
    -------
    Moduli
        Per-mineral frame moduli, shape ``(..., n)``, GPa. Sum over the last axis for the frame.
    """
    K = check_modulus("K_solid", as_array("K_solid", K_solid))
    G = check_modulus("G_solid", as_array("G_solid", G_solid), allow_zero=True)
    beta = check_fractions("solid_fractions", as_array("solid_fractions", solid_fractions))
    beta, K, G, _, _ = broadcast_phases(("solid_fractions", beta), K_solid=K, G_solid=G,
                                        phi=as_array("phi", phi)[..., None],
                                        A=as_array("A", A)[..., None])
    factor = krief_factor(phi, A)[..., None]
    hs = hashin_shtrikman_average(K, G, beta)
    V_K = sum_phases(beta * K)
    V_G = sum_phases(beta * G)
    K_mi = (hs.K / V_K)[..., None] * beta * K * factor
    with np.errstate(invalid="ignore", divide="ignore"):
        G_scale = np.where(V_G > 0.0, hs.G / np.where(V_G > 0.0, V_G, 1.0), 0.0)
    G_mi = G_scale[..., None] * beta * G * factor
    return Moduli(K_mi, G_mi)
