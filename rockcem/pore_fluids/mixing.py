"""Fluid mixtures: uniform (Wood), Brie's patchy exponent, and patchy saturation of a rock."""

from __future__ import annotations

import numpy as np

from ..fluids import gassmann
from ..validation import (MAX_DENSITY, as_array, broadcast, broadcast_phases, check_fractions,
                          check_modulus, check_range, sum_phases)
from ._common import FluidProperties
from ..validation import FIELD_UNITS, labelled

__all__ = ["wood", "brie", "patchy_saturation"]


# --- mixing --------------------------------------------------------------------------------------

def _velocity(K, rho):
    if np.any((K > 0.0) & (rho <= 0.0)):
        raise ValueError("a mixture with a modulus but no mass: check rho")
    return np.asarray(np.sqrt(np.divide(K, rho, out=np.zeros(np.shape(K)), where=rho > 0.0)))


@labelled(units=FIELD_UNITS, phases=("fractions", "K", "rho"))
def wood(fractions, K, rho):
    r"""Uniform (fine-scale) mixture of fluids, Wood's equation ([Wood1955]_): the Reuss
    average of the moduli and the volume average of the densities,

    .. math:: \frac{1}{K} = \sum_i \frac{f_i}{K_i}, \qquad \rho = \sum_i f_i\rho_i

    (a phase with ``K_i = 0`` and ``f_i > 0`` gives ``K = 0``). This is the lower bound of a
    fluid mixture's modulus and, put in Gassmann's equation, of the rock's ([Mavko2009]_).

    Parameters
    ----------
    fractions : array_like, shape (..., n)
        Volume fractions (saturations) of the n fluids on the last axis, each in [0, 1],
        summing to 1 (``rockcem.validation.stack_phases(Sw, 1 - Sw)`` builds them).
    K : array_like, shape (..., n)
        Bulk moduli, GPa, ``>= 0``.
    rho : array_like, shape (..., n)
        Densities, g/cm³, in [0, 25].

    Returns
    -------
    FluidProperties
        Arrays of shape (...).

    Examples
    --------
    10 % gas (0.05 GPa) in brine (2.5 GPa) keeps a fifth of the brine's modulus:

    >>> round(float(wood([0.9, 0.1], [2.5, 0.05], [1.05, 0.2]).K), 3)
    0.424
    """
    f = check_fractions("fractions", as_array("fractions", fractions))
    K = check_modulus("K", as_array("K", K), allow_zero=True)
    rho = check_range("rho", as_array("rho", rho), 0.0, MAX_DENSITY)
    f, K, rho = broadcast_phases(("fractions", f), K=K, rho=rho)
    present = f > 0.0
    empty = np.any(present & (K == 0.0), axis=-1)
    compliance = sum_phases(np.where(present, f / np.where(K > 0.0, K, 1.0), 0.0))
    K_mix = np.where(empty, 0.0, 1.0 / np.where(empty, 1.0, compliance))
    rho_mix = sum_phases(f * rho)
    return FluidProperties(np.asarray(K_mix), np.asarray(rho_mix), _velocity(K_mix, rho_mix))


@labelled(units=FIELD_UNITS)
def brie(water_saturation, K_brine, K_hydrocarbon, rho_brine, rho_hydrocarbon, *,
         exponent=3.0):
    r"""Brie's empirical fluid mixing law ([Brie1995]_), from uniform to patchy saturation,

    .. math:: K = (K_{brine} - K_{hc})\,S_w^{\,e} + K_{hc}, \qquad
              \rho = S_w\rho_{brine} + (1 - S_w)\rho_{hc}

    ``exponent = 1`` is the Voigt (arithmetic) average of the fluid moduli — the fluid-level
    patchy upper bound; ``exponent = 3`` is Brie's value for gas sands; large exponents
    (about 40) approach Wood's uniform mixing for a gas.

    Parameters
    ----------
    water_saturation : float or array_like
        :math:`S_w`, in [0, 1].
    K_brine, K_hydrocarbon : float or array_like
        Moduli of the liquid and the hydrocarbon, GPa, ``>= 0``.
    rho_brine, rho_hydrocarbon : float or array_like
        Densities, g/cm³, in [0, 25].
    exponent : float, keyword-only
        :math:`e`, in [1, 100] (below 1 the mixture would be stiffer than the Voigt bound).

    Returns
    -------
    FluidProperties
    """
    Sw = check_range("water_saturation", as_array("water_saturation", water_saturation), 0.0, 1.0)
    Kb = check_modulus("K_brine", as_array("K_brine", K_brine), allow_zero=True)
    Kh = check_modulus("K_hydrocarbon", as_array("K_hydrocarbon", K_hydrocarbon),
                       allow_zero=True)
    rb = check_range("rho_brine", as_array("rho_brine", rho_brine), 0.0, MAX_DENSITY)
    rh = check_range("rho_hydrocarbon", as_array("rho_hydrocarbon", rho_hydrocarbon), 0.0,
                     MAX_DENSITY)
    e = check_range("exponent", as_array("exponent", exponent), 1.0, 100.0)
    Sw, Kb, Kh, rb, rh, e = broadcast(water_saturation=Sw, K_brine=Kb, K_hydrocarbon=Kh,
                                      rho_brine=rb, rho_hydrocarbon=rh, exponent=e)
    K = (Kb - Kh) * Sw**e + Kh
    rho = Sw * rb + (1.0 - Sw) * rh
    return FluidProperties(np.asarray(K), np.asarray(rho), _velocity(K, rho))


@labelled(units="GPa", phases=("saturations", "K_fluids"))
def patchy_saturation(K_dry, G_dry, K_min, phi, saturations, K_fluids):
    r"""Saturated bulk modulus of a rock with patchy saturation ([Mavko2009]_, after White
    1975 and Mavko & Mukerji 1998): each patch holds one fluid and obeys Gassmann's equation
    (:func:`rockcem.fluids.gassmann`) with the common dry frame; the shear modulus is the same
    in every patch, so the composite follows exactly from Hill's theorem — the volume average of
    the P-wave compliance,

    .. math::

        \frac{1}{K_{sat} + \frac43 G} = \sum_i \frac{S_i}{K_{G}(K_{f,i}) + \frac43 G}

    This is the patchy (coarse-scale, high-frequency) upper limit of a partially saturated rock;
    Gassmann with Wood's fluid (:func:`wood`) is the uniform lower limit. It is preferred to the
    fluid-level Voigt average (:func:`brie` with ``exponent = 1`` in Gassmann's equation), which
    is no bound at all: it overstates the patchy modulus of a soft frame and understates, a
    little, that of a frame nearly as stiff as its mineral.

    Parameters
    ----------
    K_dry, G_dry : float or array_like, shape (...)
        Dry-frame moduli, GPa (``K_dry <= K_min``, ``G_dry >= 0``).
    K_min : float or array_like, shape (...)
        Mineral bulk modulus, GPa.
    phi : float or array_like, shape (...)
        Porosity, in [0, 1].
    saturations : array_like, shape (..., n)
        Volume fraction of the pore space held by each fluid (each patch), summing to 1.
    K_fluids : array_like, shape (..., n)
        Bulk modulus of each fluid, GPa, ``>= 0``.

    Returns
    -------
    ndarray, shape (...)
        Saturated bulk modulus, GPa; ``G_sat = G_dry``. The rock's density takes the fluid
        densities linearly (as :func:`wood`).
    """
    K_dry = check_modulus("K_dry", as_array("K_dry", K_dry), allow_zero=True)
    G = check_modulus("G_dry", as_array("G_dry", G_dry), allow_zero=True)
    K_min = check_modulus("K_min", as_array("K_min", K_min))
    phi = check_range("phi", as_array("phi", phi), 0.0, 1.0)
    S = check_fractions("saturations", as_array("saturations", saturations))
    Kf = check_modulus("K_fluids", as_array("K_fluids", K_fluids), allow_zero=True)
    K_dry, G, K_min, phi = broadcast(K_dry=K_dry, G_dry=G, K_min=K_min, phi=phi)
    S, Kf, K_dry, G, K_min, phi = broadcast_phases(
        ("saturations", S), K_fluids=Kf, K_dry=K_dry[..., None], G_dry=G[..., None],
        K_min=K_min[..., None], phi=phi[..., None])
    M = gassmann(K_dry, K_min, Kf, phi) + 4.0 / 3.0 * G
    present = S > 0.0
    empty = np.any(present & (M == 0.0), axis=-1)
    compliance = sum_phases(np.where(present, S / np.where(M > 0.0, M, 1.0), 0.0))
    M_sat = np.where(empty, 0.0, 1.0 / np.where(empty, 1.0, compliance))
    return np.maximum(M_sat - 4.0 / 3.0 * G[..., 0], 0.0)
