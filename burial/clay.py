"""Smectite → illite conversion along any burial path (Pytte & Reynolds 1989; Carcione et al.
2022, App. A)."""

from __future__ import annotations

import numpy as np

from rockcem.constants import GAS_CONSTANT_CAL
from rockcem.validation import as_array, broadcast, check_range

from ._integrals import cumulative_arrhenius
from ._members import member_values
from .path import BurialPath

__all__ = ["smectite_fraction", "illite_fraction", "MAX_ORDER", "MAX_ACTIVATION_ENERGY"]

#: Largest reaction order accepted (Pytte & Reynolds fit 5; published fits lie between 1 and 6).
MAX_ORDER = 10.0
#: Largest activation energy accepted, kcal/mol (published values 20–60; 36 in the worked
#: example); with temperatures above -100 °C it keeps :math:`e^{E/RT}` finite.
MAX_ACTIVATION_ENERGY = 100.0


def smectite_fraction(path: BurialPath, r0, order=5, activation_energy=36.0,
                      frequency_factor=1.217e23):
    r"""Smectite fraction :math:`r` of the smectite/illite mixture at every node of a path.

    The n-th order Arrhenius kinetics of eq. A.1 of Carcione et al. (2022),
    :math:`dr/dt = -c\,r^n e^{-E/RT}`, integrate to

    .. math::

        r(t) = \big[r_0^{-m} + m\,c\,J(t)\big]^{-1/m}, \quad m = n - 1, \qquad
        r(t) = r_0\,e^{-c J(t)} \ (n = 1), \qquad J(t) = \int_0^t e^{-E/RT(t')}\,dt',

    with T in kelvin and :math:`R` = :data:`rockcem.constants.GAS_CONSTANT_CAL`. :math:`J` is
    carried exactly over each linear piece of T(t) (``burial._integrals.cumulative_arrhenius``),
    which for a constant heating rate is eq. A.2. The result is evaluated as
    :math:`r_0\,[1 + m c J r_0^m]^{-1/m}` so that :math:`r_0 = 0` gives 0 and nothing overflows.

    Parameters
    ----------
    path : BurialPath
        Temperatures in °C.
    r0 : float or array_like
        Initial smectite fraction, in [0, 1] (0.99 in the worked example).
    order : float or array_like
        Reaction order :math:`n`, in [1, :data:`MAX_ORDER`]; default 5.
    activation_energy : float or array_like
        :math:`E`, kcal/mol, in (0, :data:`MAX_ACTIVATION_ENERGY`]; default 36.
    frequency_factor : float or array_like
        :math:`c`, 1/Myr, ``> 0``; default 1.217e23.

    Every parameter may be an array with one value per path (its shape broadcasts against the
    path's leading axes; an element refused is named by its index, ``order[2]``).

    Returns
    -------
    ndarray
        :math:`r` at every node, in :math:`[0, r_0]`, non-increasing in time.

    Examples
    --------
    >>> from burial.path import linear_path
    >>> p = linear_path(30.0, 40.0, 15.0, 4000.0, depth_step=1000.0)
    >>> smectite_fraction(p, 0.99).round(4).tolist()
    [0.99, 0.9137, 0.3523, 0.1209, 0.0483]
    """
    if not isinstance(path, BurialPath):
        raise ValueError("path must be a burial.BurialPath (see linear_path, path_from_nodes)")
    r0 = check_range("r0", as_array("r0", r0), 0.0, 1.0)
    n = member_values("order", order, 1.0, MAX_ORDER)
    E = member_values("activation_energy", activation_energy, 0.0, MAX_ACTIVATION_ENERGY,
                      low_open=True)
    c = member_values("frequency_factor", frequency_factor, 0.0, np.inf, low_open=True,
                      high_open=True)
    broadcast(r0=r0, order=n, activation_energy=E, frequency_factor=c,
              **{"path (leading axes)": path.temperature[..., 0]})
    r0 = np.asarray(r0)[..., None]
    # J or c J may overflow to inf for a huge frequency factor or a path of 10^300 Myr: the
    # limit of a reaction run to completion (r = 0), which the forms below reach; where J = 0
    # or r0 = 0 nothing has reacted (the products are set to 0 rather than inf * 0).
    with np.errstate(over="ignore", invalid="ignore"):
        J = cumulative_arrhenius(path.time, path.temperature, E * 1000.0 / GAS_CONSTANT_CAL)
        c = c[..., None]
        first = n[..., None] == 1.0
        if np.all(first):
            return r0 * np.exp(-np.where(J > 0.0, c * J, 0.0))
        m = np.where(first, 1.0, n[..., None] - 1.0)
        z = np.where((J > 0.0) & (r0 > 0.0), m * c * J * r0**m, 0.0)
        r = r0 * (1.0 + z) ** (-1.0 / m)
        if np.any(first):
            r = np.where(first, r0 * np.exp(-np.where(J > 0.0, c * J, 0.0)), r)
        return r


def illite_fraction(path: BurialPath, r0, order=5, activation_energy=36.0,
                    frequency_factor=1.217e23):
    """Illite fraction :math:`1 - r` of the clay (the illite/smectite ratio of App. A is
    :math:`100(1 - r)` %); parameters as :func:`smectite_fraction`."""
    return 1.0 - smectite_fraction(path, r0, order, activation_energy, frequency_factor)
