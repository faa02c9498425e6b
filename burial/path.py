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

from rockcem.constants import STANDARD_GRAVITY
from rockcem.validation import (MAX_DENSITY, as_array, as_scalar, broadcast, check_positive,
                                check_range)

from ._members import element_name, member_values

__all__ = ["BurialPath", "linear_path", "path_from_nodes", "pressures", "Pressures",
           "MAX_TEMPERATURE_C", "MIN_TEMPERATURE_C", "MAX_SURFACE_TEMPERATURE_C", "MAX_DEPTH_M",
           "MAX_TIME_MYR", "MAX_PROFILE_NODES"]

#: Temperatures above this (°C) are rejected: no diagenetic model here holds there.
MAX_TEMPERATURE_C = 500.0
#: Temperatures below this (°C) are rejected: colder than any sediment (and the Arrhenius
#: kinetics lose their meaning towards 0 K).
MIN_TEMPERATURE_C = -100.0
#: Temperature at the sediment surface (depth 0) above this (°C) is refused: water boils at the
#: sea floor's pressure well below it, and a temperature in kelvin (288.15 for 15 °C) trips it.
MAX_SURFACE_TEMPERATURE_C = 100.0
#: Depths below this (m) are refused as implausible for a sedimentary column (the deepest basins
#: hold about 20 km of sediment; a table in feet may trip it).
MAX_DEPTH_M = 20000.0
#: A linear path that takes longer than this (Myr) to reach its deepest node is refused: the age
#: of the Earth (4 567 Myr); a sedimentation rate in m/yr instead of m/Myr trips it.
MAX_TIME_MYR = 4600.0
#: Most depth nodes a generated profile (:func:`linear_path`, ``shifted_path(depth_step=...)``)
#: may have: 1 cm steps over 10 km. Every node is a depth of the rock state and of every model,
#: so more would take gigabytes for no physics (the kinetics are exact for any spacing).
MAX_PROFILE_NODES = 1_000_000


def _kelvin_hint(name, value):
    return (f"{name} is {value:g} degC at the sediment surface (depth 0), above "
            f"{MAX_SURFACE_TEMPERATURE_C:g}; is it in kelvin? (give degC: 288.15 K is 15 degC)")


@dataclass(frozen=True)
class BurialPath:
    """A piecewise-linear burial path, checked when it is made.

    Attributes
    ----------
    time : ndarray, shape (n,) or (..., n)
        Time since deposition at the nodes, Myr, ``>= 0``, non-decreasing along the last axis:
        a piece of zero duration adds nothing to any integral
        (:func:`burial.horizons.horizon_paths` pads shorter histories with copies of their
        first node); :func:`path_from_nodes` asks for strictly increasing time.
    depth : ndarray, shape (..., n)
        Burial depth at the nodes, m, ``>= 0``. (The kinetics do not depend on the depth, so no
        upper bound is set here; :func:`linear_path` and the tables of
        :mod:`burial.horizons` keep depths within :data:`MAX_DEPTH_M`.)
    temperature : ndarray, shape (..., n)
        Temperature at the nodes, °C, in [:data:`MIN_TEMPERATURE_C`,
        :data:`MAX_TEMPERATURE_C`], and at most :data:`MAX_SURFACE_TEMPERATURE_C` where the
        depth is 0 (a path in kelvin trips it).

    Raises
    ------
    ValueError
        Naming ``time``, ``depth`` or ``temperature``: not real (complex, text, None), NaN or
        infinite, out of range, fewer than two nodes, time running backwards, shapes that do
        not broadcast. ``depth`` and ``temperature`` are broadcast to one shape.
    """

    time: np.ndarray
    depth: np.ndarray
    temperature: np.ndarray

    def __post_init__(self):
        t, z, T = (as_array(name, getattr(self, name))
                   for name in ("time", "depth", "temperature"))
        for name, arr in (("time", t), ("depth", z), ("temperature", T)):
            if arr.ndim == 0 or arr.shape[-1] < 2:
                raise ValueError(f"{name} must hold at least two nodes along its last axis; "
                                 f"got shape {arr.shape}")
            if not np.all(np.isfinite(arr)):
                raise ValueError(f"{name} must be finite; got {arr[~np.isfinite(arr)].flat[0]}")
        check_positive("time (Myr since deposition)", t, allow_zero=True)
        check_positive("depth (m)", z, allow_zero=True)
        if np.any(np.diff(t, axis=-1) < 0.0):
            raise ValueError("time must not decrease from node to node")
        broadcast(time=t, depth=z, temperature=T)
        shape = np.broadcast_shapes(z.shape, T.shape)
        if shape[-1] != t.shape[-1]:
            raise ValueError(f"depth and temperature must have one value per time node "
                             f"({t.shape[-1]}); got shapes {z.shape} and {T.shape}")
        z, T = np.broadcast_to(z, shape), np.broadcast_to(T, shape)
        hot = (z == 0.0) & (T > MAX_SURFACE_TEMPERATURE_C)
        if np.any(hot):
            raise ValueError(_kelvin_hint("temperature", float(T[hot].flat[0])))
        check_range("temperature (degC; a path in kelvin would exceed the range)", T,
                    MIN_TEMPERATURE_C, MAX_TEMPERATURE_C)
        for name, arr in (("time", t), ("depth", z), ("temperature", T)):
            object.__setattr__(self, name, arr)

    @property
    def heating_rate(self) -> np.ndarray:
        """Heating rate of each linear piece, °C/Myr, shape ``(..., n - 1)`` (0 on a piece
        of zero duration)."""
        dt = np.diff(self.time, axis=-1)
        dT = np.diff(self.temperature, axis=-1)
        return np.divide(dT, dt, out=np.zeros(np.broadcast_shapes(dT.shape, dt.shape)),
                         where=dt != 0.0)


def _validated(time, depth, temperature) -> BurialPath:
    path = BurialPath(time, depth, temperature)
    if np.any(np.diff(path.time, axis=-1) <= 0.0):
        raise ValueError("time must increase strictly from node to node")
    return path


def path_from_nodes(time, depth, temperature) -> BurialPath:
    """A burial path from a table of nodes, e.g. exported from a basin model.

    Between nodes depth and temperature vary linearly in time: a hiatus is two nodes at the same
    depth and temperature, uplift and cooling are nodes of decreasing depth and temperature.

    Parameters
    ----------
    time : array_like, shape (n,) or (..., n)
        Time since deposition, Myr, ``>= 0``, strictly increasing.
    depth : array_like, shape (..., n)
        Burial depth, m, ``>= 0``.
    temperature : array_like, shape (..., n)
        Temperature, °C, in [:data:`MIN_TEMPERATURE_C`, :data:`MAX_TEMPERATURE_C`]; at most
        :data:`MAX_SURFACE_TEMPERATURE_C` at depth 0.

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

    ``gradient``, ``sedimentation_rate`` and ``surface_temperature`` may be arrays (one value
    per member of an ensemble, shapes broadcast together to the members' shape ``M``): the
    path then has leading axes ``M`` in ``time`` and ``temperature``, one path per member on
    the shared depth nodes, and the burial functions take per-member parameters of shape ``M``
    against it (:func:`pressures`, :func:`burial.quartz_cement`).

    Parameters
    ----------
    gradient : float or array_like
        Geothermal gradient :math:`G`, °C/km, ``> 0`` (20–40 typical); the path must stay at
        or below :data:`MAX_TEMPERATURE_C` down to ``max_depth``.
    sedimentation_rate : float or array_like
        Burial rate :math:`S`, m/Myr, ``> 0`` (20–500 typical; 40 in the worked examples); the
        deepest node must be buried within :data:`MAX_TIME_MYR`.
    surface_temperature : float or array_like
        :math:`T_0`, °C, in [:data:`MIN_TEMPERATURE_C`, :data:`MAX_SURFACE_TEMPERATURE_C`]
        (288.15, a surface temperature in kelvin, is refused).
    max_depth : float
        Deepest node, m, in (0, :data:`MAX_DEPTH_M`].
    depth_step : float, keyword-only
        Spacing of the nodes, m, ``> 0``, with at most :data:`MAX_PROFILE_NODES` nodes down to
        ``max_depth``; the kinetics are exact for any spacing, so it only sets where values
        are reported.

    Returns
    -------
    BurialPath

    Raises
    ------
    ValueError
        Naming the argument, before any array is made: a value that is not a finite real
        number (``max_depth`` and ``depth_step``: one number, the depth nodes every member
        shares), out of its range, or shapes that do not broadcast; the element of an array is
        named by its index (``gradient[3]``).

    Examples
    --------
    >>> p = linear_path(30.0, 40.0, 15.0, 3000.0, depth_step=1000.0)
    >>> p.time.tolist(), p.temperature.tolist()
    ([0.0, 25.0, 50.0, 75.0], [15.0, 45.0, 75.0, 105.0])

    Two members, gradients 20 and 40 °C/km:

    >>> linear_path([20.0, 40.0], 40.0, 15.0, 2000.0, depth_step=1000.0).temperature.tolist()
    [[15.0, 35.0, 55.0], [15.0, 55.0, 95.0]]
    """
    G = member_values("gradient", gradient, 0.0, np.inf, low_open=True, high_open=True)
    S = member_values("sedimentation_rate", sedimentation_rate, 0.0, np.inf, low_open=True,
                      high_open=True)
    T0 = member_values("surface_temperature", surface_temperature, -np.inf, np.inf)
    kelvin = (T0 > MAX_SURFACE_TEMPERATURE_C) & (T0 <= MAX_TEMPERATURE_C + 273.15)
    if np.any(kelvin):
        raise ValueError(_kelvin_hint(element_name("surface_temperature", kelvin),
                                      float(T0[kelvin].flat[0])))
    T0 = member_values("surface_temperature", T0, MIN_TEMPERATURE_C, MAX_SURFACE_TEMPERATURE_C)
    zmax = check_range("max_depth", as_scalar("max_depth", max_depth), 0.0, MAX_DEPTH_M,
                       low_open=True)
    dz = check_positive("depth_step", as_scalar("depth_step", depth_step))
    G, S, T0 = broadcast(gradient=G, sedimentation_rate=S, surface_temperature=T0)
    T_bottom = T0 + G * zmax / 1000.0
    hot = T_bottom > MAX_TEMPERATURE_C
    if np.any(hot):
        i = np.argwhere(hot)[0] if hot.ndim else ()
        raise ValueError(f"{element_name('gradient', hot)} {G[tuple(i)]:g} degC/km takes the "
                         f"path from {T0[tuple(i)]:g} degC to {T_bottom[tuple(i)]:.4g} degC at "
                         f"max_depth {zmax:g} m, above the {MAX_TEMPERATURE_C:g} degC the "
                         "kinetics hold to; lower the gradient or max_depth")
    old = S < zmax / MAX_TIME_MYR            # zmax / S > MAX_TIME_MYR, without overflow
    if np.any(old):
        s_bad = float(S[old].flat[0])
        with np.errstate(over="ignore"):
            years = np.float64(zmax) / np.float64(s_bad)
        raise ValueError(f"{element_name('sedimentation_rate', old)} {s_bad:g} m/Myr takes "
                         f"{years:.4g} Myr to bury max_depth {zmax:g} m, longer than the "
                         f"age of the Earth ({MAX_TIME_MYR:g} Myr); is it in m/Myr?")
    if zmax / dz > MAX_PROFILE_NODES - 1:
        raise ValueError(f"depth_step {dz:g} m gives {zmax / dz + 1:.3g} nodes down to max_depth "
                         f"{zmax:g} m; at most {MAX_PROFILE_NODES} (depth_step >= "
                         f"{zmax / (MAX_PROFILE_NODES - 1):.3g} m)")
    depth = np.arange(0.0, zmax, dz)
    depth = np.append(depth[zmax - depth > 1e-9 * min(dz, zmax)], zmax)
    time = depth / S[..., None]
    still = np.any(np.diff(time, axis=-1) <= 0.0, axis=-1)
    if np.any(still):
        raise ValueError(f"{element_name('sedimentation_rate', still)} "
                         f"{float(S[still].flat[0]):g} m/Myr buries the {depth[1]:g} m between "
                         "the first nodes in no time that a float can hold; lower it or raise "
                         "depth_step")
    return _validated(time, depth, T0[..., None] + G[..., None] * depth / 1000.0)


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
    sediment_density, water_density : float or array_like, keyword-only
        :math:`\bar\rho` and :math:`\bar\rho_w`, g/cm³ (defaults 2.5 and 1.04 as in the paper),
        with ``sediment_density >= water_density > 0``, at most
        :data:`rockcem.validation.MAX_DENSITY`; arrays are one value per path (their shape
        broadcasts against the path's leading axes; an element refused is named by its index).

    Returns
    -------
    Pressures

    Examples
    --------
    >>> p = pressures(linear_path(30.0, 40.0, 15.0, 1000.0, depth_step=1000.0))
    >>> [round(float(v), 4) for v in p.effective]
    [0.0, 14.3177]
    """
    if not isinstance(path, BurialPath):
        raise ValueError("path must be a burial.BurialPath (see linear_path, path_from_nodes)")
    rho = member_values("sediment_density", sediment_density, 0.0, MAX_DENSITY, low_open=True)
    rho_w = member_values("water_density", water_density, 0.0, MAX_DENSITY, low_open=True)
    rho, rho_w = broadcast(sediment_density=rho, water_density=rho_w)
    heavy = rho_w > rho
    if np.any(heavy):
        raise ValueError(f"{element_name('water_density', heavy)} must not exceed "
                         f"{element_name('sediment_density', heavy)}")
    broadcast(sediment_density=rho, **{"path (leading axes)": path.depth[..., 0]})
    factor = 1e-3 * STANDARD_GRAVITY          # MPa per (g/cm3 * m)
    pc = factor * rho[..., None] * path.depth
    ph = factor * rho_w[..., None] * path.depth
    pe = pc - ph
    return Pressures(pc, ph, pe, np.maximum.accumulate(pe, axis=-1))
