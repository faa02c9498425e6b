"""Burial paths: time → depth and temperature as piecewise-linear nodes, and the pressures.

Units: time Myr, depth m, temperature °C, pressure MPa, density g/cm³. Time runs forward from
deposition (t = 0). A path may carry leading "package" axes: ``depth`` and ``temperature`` have
shape ``(..., n_nodes)`` against one increasing ``time`` of shape ``(n_nodes,)`` or
``(..., n_nodes)``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from rockcem.validation import as_array, check_positive, check_range
from rockcem.constants import STANDARD_GRAVITY

__all__ = ["BurialPath", "linear_path", "path_from_nodes", "pressures", "Pressures"]

#: Temperatures above this (°C) are rejected: no diagenetic model here holds there, and a path in
#: kelvin would trip it.
MAX_TEMPERATURE_C = 500.0


@dataclass(frozen=True)
class BurialPath:
    """A piecewise-linear burial path.

    Attributes
    ----------
    time : ndarray, shape (n,) or (..., n)
        Time since deposition at the nodes, Myr, strictly increasing along the last axis
        (:func:`burial.horizons.horizon_paths` pads shorter histories with copies of their
        first node: pieces of zero duration, which add nothing to any integral).
    depth : ndarray, shape (..., n)
        Burial depth at the nodes, m, ``>= 0``.
    temperature : ndarray, shape (..., n)
        Temperature at the nodes, °C.
    """

    time: np.ndarray
    depth: np.ndarray
    temperature: np.ndarray

    @property
    def heating_rate(self) -> np.ndarray:
        """Heating rate of each linear piece, °C/Myr, shape ``(..., n - 1)`` (0 on a piece
        of zero duration)."""
        dt = np.diff(self.time, axis=-1)
        dT = np.diff(self.temperature, axis=-1)
        return np.divide(dT, dt, out=np.zeros(np.broadcast_shapes(dT.shape, dt.shape)),
                         where=dt != 0.0)


def _validated(time, depth, temperature) -> BurialPath:
    t = as_array("time", time)
    z = as_array("depth", depth)
    T = as_array("temperature", temperature)
    if t.ndim == 0 or t.shape[-1] < 2:
        raise ValueError("time must hold at least two nodes along its last axis")
    if not np.all(np.isfinite(t)) or not np.all(np.isfinite(z)) or not np.all(np.isfinite(T)):
        raise ValueError("time, depth and temperature must be finite")
    if np.any(np.diff(t, axis=-1) <= 0.0):
        raise ValueError("time must increase strictly from node to node")
    check_positive("depth", z, allow_zero=True)
    check_range("temperature (degC; a path in kelvin would exceed the range)", T, -273.15,
                MAX_TEMPERATURE_C)
    try:
        shape = np.broadcast_shapes(t.shape, z.shape, T.shape)
    except ValueError:
        raise ValueError(f"time {t.shape}, depth {z.shape} and temperature {T.shape} do not "
                         "broadcast together (nodes on the last axis)") from None
    if shape[-1] != t.shape[-1]:
        raise ValueError("depth and temperature must have one value per time node")
    z = np.broadcast_to(z, shape)
    T = np.broadcast_to(T, shape)
    return BurialPath(t, z, T)


def path_from_nodes(time, depth, temperature) -> BurialPath:
    """A burial path from a table of nodes, e.g. exported from a basin model.

    Between nodes depth and temperature vary linearly in time: a hiatus is two nodes at the same
    depth and temperature, uplift and cooling are nodes of decreasing depth and temperature.

    Parameters
    ----------
    time : array_like, shape (n,) or (..., n)
        Time since deposition, Myr, strictly increasing.
    depth : array_like, shape (..., n)
        Burial depth, m, ``>= 0``.
    temperature : array_like, shape (..., n)
        Temperature, °C, in [-273.15, 500].

    Returns
    -------
    BurialPath

    Examples
    --------
    Burial, a 10-Myr hiatus, then uplift and cooling:

    >>> p = path_from_nodes([0, 50, 60, 80], [0, 2000, 2000, 1200], [15, 75, 75, 51])
    >>> p.heating_rate.tolist()
    [1.2, 0.0, -1.2]
    """
    return _validated(time, depth, temperature)


def linear_path(gradient, sedimentation_rate, surface_temperature, max_depth, *,
                depth_step=10.0) -> BurialPath:
    r"""The linear basin model of Carcione et al. (2022), eq. 2.

    .. math:: z = S t, \qquad T = T_0 + G z = T_0 + H t, \qquad H = G S

    A sediment package buried at a constant rate :math:`S` in a constant geothermal gradient
    :math:`G`. Every package follows the same path, so the values at the nodes are at the same time
    the present-day depth profile (a package now at depth :math:`z` has been buried for
    :math:`z/S`).

    Parameters
    ----------
    gradient : float
        Geothermal gradient :math:`G`, °C/km, ``> 0`` (20–40 typical).
    sedimentation_rate : float
        Burial rate :math:`S`, m/Myr, ``> 0`` (20–500 typical; 40 in the worked examples).
    surface_temperature : float
        :math:`T_0`, °C.
    max_depth : float
        Deepest node, m, ``> 0``.
    depth_step : float, keyword-only
        Spacing of the nodes, m, ``> 0``; the kinetics are exact for any spacing, so it only sets
        where values are reported.

    Returns
    -------
    BurialPath

    Examples
    --------
    >>> p = linear_path(30.0, 40.0, 15.0, 3000.0, depth_step=1000.0)
    >>> p.time.tolist(), p.temperature.tolist()
    ([0.0, 25.0, 50.0, 75.0], [15.0, 45.0, 75.0, 105.0])
    """
    G = float(check_positive("gradient", as_array("gradient", gradient)))
    S = float(check_positive("sedimentation_rate", as_array("sedimentation_rate",
                                                            sedimentation_rate)))
    T0 = float(as_array("surface_temperature", surface_temperature))
    zmax = float(check_positive("max_depth", as_array("max_depth", max_depth)))
    dz = float(check_positive("depth_step", as_array("depth_step", depth_step)))
    depth = np.arange(0.0, zmax, dz)
    depth = np.append(depth[zmax - depth > 1e-9 * dz], zmax)
    return _validated(depth / S, depth, T0 + G * depth / 1000.0)


class Pressures(NamedTuple):
    """Pressures at the nodes of a path, MPa."""

    confining: np.ndarray           #: lithostatic, :math:`\bar\rho g z`
    pore: np.ndarray                #: hydrostatic, :math:`\bar\rho_w g z`
    effective: np.ndarray           #: :math:`p_e = p_c - p_H` (eq. 1)
    max_effective: np.ndarray       #: largest effective pressure reached so far along the path


def pressures(path: BurialPath, *, sediment_density=2.5, water_density=1.04) -> Pressures:
    r"""Lithostatic, hydrostatic and effective pressure along a path, eq. 1 of Carcione et al. 2022.

    .. math:: p_c = \bar\rho g z, \qquad p_H = \bar\rho_w g z, \qquad p_e = p_c - p_H

    with :math:`g` = :data:`rockcem.constants.STANDARD_GRAVITY`; densities in g/cm³ are
    converted to kg/m³ (× 1000) and Pa to MPa (× 10⁻⁶), i.e. :math:`p` [MPa] =
    :math:`10^{-3}\,\rho\,g\,z`. The running maximum of :math:`p_e` drives compaction, so that
    uplift does not decompact.

    Parameters
    ----------
    path : BurialPath
    sediment_density, water_density : float, keyword-only
        :math:`\bar\rho` and :math:`\bar\rho_w`, g/cm³ (defaults 2.5 and 1.04 as in the paper),
        with ``sediment_density >= water_density > 0``.

    Returns
    -------
    Pressures

    Examples
    --------
    >>> p = pressures(linear_path(30.0, 40.0, 15.0, 1000.0, depth_step=1000.0))
    >>> [round(float(v), 4) for v in p.effective]
    [0.0, 14.3226]
    """
    rho = float(check_positive("sediment_density", as_array("sediment_density", sediment_density)))
    rho_w = float(check_positive("water_density", as_array("water_density", water_density)))
    if rho_w > rho:
        raise ValueError("water_density must not exceed sediment_density")
    factor = 1e-3 * STANDARD_GRAVITY          # MPa per (g/cm3 * m)
    pc = factor * rho * path.depth
    ph = factor * rho_w * path.depth
    pe = pc - ph
    return Pressures(pc, ph, pe, np.maximum.accumulate(pe, axis=-1))
