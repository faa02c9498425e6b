"""Small shared pieces of isotropic elasticity: the ``Moduli`` pair, Poisson ratio, velocities.

Units: moduli in GPa, density in g/cm³, so that ``sqrt(GPa / (g/cm³))`` is km/s with no factor.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .validation import (MAX_DENSITY, MIN_DENSITY, as_array, broadcast, check_modulus,
                         check_positive, check_range)
from .validation import labelled

__all__ = ["Moduli", "Velocities", "poisson_ratio", "velocities", "p_wave_modulus"]


class Moduli(NamedTuple):
    """Bulk and shear moduli, GPa (arrays of one shape)."""

    K: np.ndarray
    G: np.ndarray


class Velocities(NamedTuple):
    """P- and S-wave velocities, km/s."""

    vp: np.ndarray
    vs: np.ndarray


@labelled(units="1")
def poisson_ratio(K, G):
    r"""Poisson ratio of an isotropic solid.

    .. math:: \nu = \frac{3K - 2G}{2(3K + G)}

    Parameters
    ----------
    K, G : float or array_like
        Bulk and shear moduli, GPa; ``K > 0``, ``G >= 0``.

    Returns
    -------
    ndarray
        Poisson ratio in (-1, 0.5]; 0.5 for a fluid (``G = 0``).

    Examples
    --------
    >>> float(poisson_ratio(36.0, 45.0))  # doctest: +ELLIPSIS
    0.0588...
    """
    K = check_positive("K", check_modulus("K", as_array("K", K), allow_zero=True))
    G = check_modulus("G", as_array("G", G), allow_zero=True)
    K, G = broadcast(K=K, G=G)
    return (3.0 * K - 2.0 * G) / (2.0 * (3.0 * K + G))


@labelled(units="GPa")
def p_wave_modulus(K, G):
    r"""P-wave modulus :math:`E = K + \tfrac43 G`, GPa (eq. 22 of [Carcione2022]_).

    Parameters
    ----------
    K, G : float or array_like
        Bulk and shear moduli, GPa, ``>= 0``.

    Returns
    -------
    ndarray
        P-wave modulus, GPa, broadcast over the inputs.
    """
    K = check_modulus("K", as_array("K", K), allow_zero=True)
    G = check_modulus("G", as_array("G", G), allow_zero=True)
    K, G = broadcast(K=K, G=G)
    return K + 4.0 / 3.0 * G


@labelled(units="km s-1")
def velocities(K, G, density) -> Velocities:
    r"""P- and S-wave velocities from moduli and density, eqs. 22–25 of [Carcione2022]_.

    .. math:: V_P = \sqrt{(K + \tfrac43 G)/\rho}, \qquad V_S = \sqrt{G/\rho}

    Parameters
    ----------
    K, G : float or array_like
        Bulk and shear moduli, GPa (``K >= 0``, ``G >= 0``).
    density : float or array_like
        Bulk density, g/cm³, in [:data:`rockcem.validation.MIN_DENSITY`,
        :data:`rockcem.validation.MAX_DENSITY`] (a density in kg/m³ is refused).

    Returns
    -------
    Velocities
        ``vp`` and ``vs`` in km/s.

    Examples
    --------
    >>> v = velocities(40.0, 39.0, 2.65)   # quartz of Carcione et al. 2022, Table 1
    >>> round(float(v.vp), 3), round(float(v.vs), 3)
    (5.892, 3.836)
    """
    K = check_modulus("K", as_array("K", K), allow_zero=True)
    G = check_modulus("G", as_array("G", G), allow_zero=True)
    rho = check_range("density", as_array("density", density), MIN_DENSITY, MAX_DENSITY)
    K, G, rho = broadcast(K=K, G=G, density=rho)
    return Velocities(np.sqrt((K + 4.0 / 3.0 * G) / rho), np.sqrt(G / rho))
