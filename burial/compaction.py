"""Mechanical compaction: Athy's law and the intergranular volume (IGV) of Lander & Walderhaug,
and how cement and compaction share the pore space (Carcione et al. 2022, eqs. 7, B.7–B.8)."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from rockcem.validation import as_array, broadcast, check_positive, check_range

__all__ = ["athy_porosity", "intergranular_volume", "sandstone_porosity", "SandstonePorosity"]


def athy_porosity(porosity0, effective_pressure, beta=0.01):
    r"""Athy's law, eq. 7 of Carcione et al. (2022): :math:`\phi = \phi_0 e^{-\beta p_e}`.

    Parameters
    ----------
    porosity0 : float or array_like
        Porosity at zero effective pressure, in [0, 1).
    effective_pressure : float or array_like
        MPa, ``>= 0``. Pass the *maximum* effective pressure reached so far
        (``pressures(path).max_effective``) so that uplift does not decompact.
    beta : float or array_like
        Compaction coefficient, 1/MPa, ``>= 0``; default 0.01.

    Returns
    -------
    ndarray
        Porosity, in (0, ``porosity0``].

    Examples
    --------
    >>> round(float(athy_porosity(0.35, 50.0)), 6)
    0.212286
    """
    phi0 = check_range("porosity0", as_array("porosity0", porosity0), 0.0, 1.0, high_open=True)
    pe = check_positive("effective_pressure", as_array("effective_pressure", effective_pressure),
                        allow_zero=True)
    beta = check_positive("beta", as_array("beta", beta), allow_zero=True)
    phi0, pe, beta = broadcast(porosity0=phi0, effective_pressure=pe, beta=beta)
    with np.errstate(over="ignore"):        # beta p_e beyond 1e308: exp(-inf) = 0, the limit
        return phi0 * np.exp(-beta * pe)


def intergranular_volume(porosity0, effective_pressure, igv_final=0.2, beta=0.01,
                         matrix0=0.0):
    r"""Intergranular volume, eq. B.7 (Lander & Walderhaug 1999).

    .. math:: \mathrm{IGV} = \mathrm{IGV}_i + (\phi_0 + m_0 - \mathrm{IGV}_i)\,e^{-\beta p_e}

    Parameters
    ----------
    porosity0 : float or array_like
        Initial porosity :math:`\phi_0`, in (0, 1).
    effective_pressure : float or array_like
        Maximum effective pressure reached, MPa, ``>= 0``.
    igv_final : float or array_like
        :math:`\mathrm{IGV}_i` at infinite effective pressure, in [0, :math:`\phi_0 + m_0`];
        default 0.2.
    beta : float or array_like
        1/MPa, ``>= 0``; default 0.01.
    matrix0 : float or array_like
        Initial matrix fraction in the pore space :math:`m_0`, in [0, 1], with
        :math:`\phi_0 + m_0 \le 1`; default 0.

    Returns
    -------
    ndarray
        IGV, between ``igv_final`` and :math:`\phi_0 + m_0` (at zero effective pressure).

    Examples
    --------
    At zero effective pressure the IGV is the initial pore space and matrix:

    >>> float(intergranular_volume(0.3, 0.0, 0.2, 0.01, 0.1))
    0.4
    """
    phi0 = check_range("porosity0", as_array("porosity0", porosity0), 0.0, 1.0, low_open=True,
                       high_open=True)
    m0 = check_range("matrix0", as_array("matrix0", matrix0), 0.0, 1.0)
    igv_i = check_range("igv_final", as_array("igv_final", igv_final), 0.0, 1.0)
    pe = check_positive("effective_pressure", as_array("effective_pressure", effective_pressure),
                        allow_zero=True)
    beta = check_positive("beta", as_array("beta", beta), allow_zero=True)
    phi0, pe, igv_i, beta, m0 = broadcast(porosity0=phi0, effective_pressure=pe,
                                          igv_final=igv_i, beta=beta, matrix0=m0)
    if np.any(phi0 + m0 > 1.0):
        raise ValueError("porosity0 + matrix0 must not exceed 1 (the initial IGV is a fraction)")
    if np.any(igv_i > phi0 + m0):
        raise ValueError("igv_final must not exceed porosity0 + matrix0 (the IGV only falls "
                         "from its initial value)")
    with np.errstate(over="ignore"):        # beta p_e beyond 1e308: exp(-inf) = 0, the limit
        return igv_i + (phi0 + m0 - igv_i) * np.exp(-beta * pe)


class SandstonePorosity(NamedTuple):
    """Porosity and cement of a compacting, cementing sandstone (fractions)."""

    porosity: np.ndarray            #: :math:`\max(\mathrm{IGV} - \phi_p, 0)`
    #: cement that fits in the IGV, :math:`\min(\phi_p, \mathrm{IGV})` (never decreasing)
    cement_fraction: np.ndarray
    intergranular_volume: np.ndarray
    pore_filled: np.ndarray         #: bool: the cement kinetics would overfill the pores here


def sandstone_porosity(intergranular_volume, cement_fraction) -> SandstonePorosity:
    r"""Porosity of a sandstone from its IGV and quartz cement, eq. B.8: :math:`\phi = \mathrm{IGV}
    - \phi_p`, along a burial path (time on the last axis).

    The cement of eq. B.1 is computed as if the pores were never lost to compaction; once it
    reaches the intergranular volume (near 4.45 km in the worked example of Carcione et al.
    2022, Sect. 6.2, where they note the porosity "becomes negative") there is no pore space
    left. Here, from that node on, the porosity is 0, the cement is what filled the pores, and
    the point is flagged in ``pore_filled``; a cemented framework does not compact further, so
    the intergranular volume stays at the cement volume (it never falls below the cement already
    in place, and cement never dissolves). Porosity is never negative and cement never decreases
    along the path.

    Parameters
    ----------
    intergranular_volume : array_like, shape (..., n_nodes)
        IGV along the path, fraction in [0, 1] (from :func:`intergranular_volume`).
    cement_fraction : array_like, shape (..., n_nodes)
        Quartz cement :math:`\phi_p` along the path from :func:`burial.quartz_cement`, ``>= 0``.

    Returns
    -------
    SandstonePorosity
    """
    igv = check_range("intergranular_volume", as_array("intergranular_volume",
                                                        intergranular_volume), 0.0, 1.0)
    phip = check_range("cement_fraction", as_array("cement_fraction", cement_fraction), 0.0, 1.0)
    igv, phip = broadcast(intergranular_volume=igv, cement_fraction=phip)
    if igv.ndim == 0:
        cement = np.minimum(phip, igv)
    else:
        cement = np.maximum.accumulate(np.minimum(phip, igv), axis=-1)
    igv_eff = np.maximum(igv, cement)
    return SandstonePorosity(igv_eff - cement, cement, igv_eff, phip >= igv_eff)
