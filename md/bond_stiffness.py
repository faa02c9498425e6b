r"""Stiffness of a cement bond between two grains (the bond law of :mod:`md.bonded`).

Bond stiffness (this project's lumped model; the sources give the bond only as springs whose
constants PFC calibrates). Each bond mode — normal, shear, bending, twisting — is a bed of
local springs over the disc :math:`r \le a`: at radius :math:`r` a cement column of height
:math:`t(r) = h + 2\left(\bar R - \sqrt{\bar R^2 - r^2}\right)` (the gap between two spheres
of radius :math:`\bar R` whose surfaces are :math:`h` apart on the axis) in series with the two
grains. The thickness is given as :math:`\varepsilon = h/(2\bar R)`, half the axial gap over
the radius: the :math:`\varepsilon` of Dvorkin's layer :math:`\varepsilon + t^2/2` and of
Han & Guo's eqs. 1 and 6 (and of :func:`rockcem.granular.contact_cement`), so that MD and MCCT
are compared at the same :math:`\varepsilon`. The cement column responds as a thin layer, in
uniaxial strain: stiffness per area
:math:`M_c/t` normal and :math:`G_c/t` in shear (Dvorkin et al. 1994's layer, the one CCT
integrates; :math:`M_c = K_c + \tfrac43 G_c`). Each grain is an elastic half-space loaded over
the disc, taken as a bed of uniform stiffness per area chosen so that a disc of rigid cement
(a welded contact) gets the exact rigid-punch stiffness of the pair (Johnson, *Contact
Mechanics*, 1985: normal :math:`2aE/(1-\nu^2)`, tangential :math:`8Ga/(2-\nu)`, tilting
:math:`\tfrac43 E a^3/(1-\nu^2)`, torsion :math:`\tfrac{16}{3} G a^3` per half-space). The
grain bed acts as an extra cement height :math:`t_g = 2 C / s_g` (:math:`C` the cement modulus of
the mode, :math:`s_g` the grain bed per area), so

.. math::

    k_n = 2\pi M_c \int_0^a \frac{r\,dr}{t(r) + t_{g,n}}, \quad
    k_s = 2\pi G_c \int_0^a \frac{r\,dr}{t(r) + t_{g,s}}, \quad
    k_b = \pi M_c \int_0^a \frac{r^3\,dr}{t(r) + t_{g,b}}, \quad
    k_w = 2\pi G_c \int_0^a \frac{r^3\,dr}{t(r) + t_{g,w}},

in closed form (:func:`bond_stiffness`). Both limits are exact for this geometry: rigid cement
gives the welded contact of radius :math:`a`, rigid grains give the thin-layer integral. At
:math:`h = 0` the layer alone would be infinitely stiff (log-divergent at the axis); the grains
keep the bond finite, as in CCT.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = ["BondStiffness", "bond_stiffness", "bond_cement_volume"]


class BondStiffness(NamedTuple):
    """Stiffnesses of a cement bond: ``normal`` and ``shear`` (N/m), ``bending`` and
    ``twisting`` (N m/rad)."""

    normal: np.ndarray
    shear: np.ndarray
    bending: np.ndarray
    twisting: np.ndarray


def _check_moduli(name, bulk, shear):
    bulk, shear = float(bulk), float(shear)
    if not (np.isfinite(bulk) and bulk > 0):
        raise ValueError(f"{name}_bulk must be a finite modulus > 0 Pa; got {bulk}")
    if not (np.isfinite(shear) and shear > 0):
        raise ValueError(f"{name}_shear must be a finite modulus > 0 Pa; got {shear}")
    nu = (3 * bulk - 2 * shear) / (2 * (3 * bulk + shear))
    if not -1.0 < nu < 0.5:
        raise ValueError(f"{name} moduli give a Poisson ratio {nu:.3f} outside (-1, 0.5)")
    return bulk, shear, nu


def _f_moments(x, kmax=3, terms=60):
    r""":math:`F_k(x) = \int_0^x t^k/(1+t)\,dt` for :math:`k = 0 \dots k_{max}`, without
    cancellation: the power series :math:`\sum_m (-1)^m x^{k+m+1}/(k+m+1)` below
    :math:`x = 1/2`, the recursion :math:`F_0 = \ln(1+x)`, :math:`F_k = x^k/k - F_{k-1}` above."""
    x = np.asarray(x, dtype=float)
    small = x < 0.5
    xs = np.where(small, x, 0.0)
    out = []
    f_prev = np.log1p(x)
    for k in range(kmax + 1):
        m = np.arange(terms)
        series = np.sum((-1.0) ** m * xs[..., None] ** (k + m + 1) / (k + m + 1), axis=-1)
        direct = f_prev if k == 0 else x**k / k - f_prev
        f_k = np.where(small, series, direct)
        out.append(f_k)
        f_prev = np.where(small, np.log1p(x) if k == 0 else x**k / k - f_prev, f_k)
    return out


def _layer_integrals(R, a, w0):
    r""":math:`\int_0^a r\,dr/(w_0 + g)` and :math:`\int_0^a r^3 dr/(w_0 + g)` with
    :math:`g = 2(R - \sqrt{R^2 - r^2})`, in closed form.

    In the variable :math:`g` (:math:`r\,dr = (R - g/2)\,dg/2`,
    :math:`r^2 = g(R - g/4)`) both become :math:`\tfrac12\int_0^{g_a} P(g)/(w_0+g)\,dg` with
    :math:`P = R - g/2` and :math:`P = R^2 g - \tfrac34 R g^2 + \tfrac18 g^3`;
    with :math:`g = w_0 t` and :math:`x = g_a/w_0` they are sums of
    :math:`w_0^k F_k(x)` (:func:`_f_moments`), accurate from :math:`w_0 \ll g_a` (thin
    layer, contact bonding) to :math:`w_0 \gg R` (stiff cement). ``w0 > 0``.
    """
    s_a = np.sqrt(np.maximum(R * R - a * a, 0.0))
    g_a = 2.0 * (R - s_a)
    F0, F1, F2, F3 = _f_moments(g_a / w0)
    j0 = 0.5 * (R * F0 - 0.5 * w0 * F1)
    j2 = 0.5 * (R * R * w0 * F1 - 0.75 * R * w0**2 * F2 + 0.125 * w0**3 * F3)
    return j0, j2


def bond_stiffness(radius, radius_ratio, thickness_ratio, grain_bulk, grain_shear,
                   cement_bulk, cement_shear) -> BondStiffness:
    r"""Normal, shear, bending and twisting stiffness of a cement bond (lumped model of the
    module docstring).

    Parameters
    ----------
    radius : array_like
        Grain radius :math:`\bar R`, m (for unequal grains the harmonic mean
        :math:`2R_iR_j/(R_i+R_j)`), ``> 0``.
    radius_ratio : array_like
        :math:`\alpha = a/\bar R`, the bond radius over the grain radius, in (0, 1].
    thickness_ratio : array_like
        :math:`\varepsilon = h/(2\bar R)`, half the cement thickness on the axis over the
        radius, ``>= 0`` (0: contact bonding).
    grain_bulk, grain_shear, cement_bulk, cement_shear : float
        Moduli, Pa, ``> 0``.

    Returns
    -------
    BondStiffness
        Arrays of the broadcast shape.
    """
    R = np.asarray(radius, dtype=float)
    alpha = np.asarray(radius_ratio, dtype=float)
    eps = np.asarray(thickness_ratio, dtype=float)
    if not np.all(np.isfinite(R) & (R > 0)):
        raise ValueError("radius must be finite and > 0 m")
    if not np.all((alpha > 0) & (alpha <= 1)):
        raise ValueError("radius_ratio (a/R) must lie in (0, 1]")
    if not np.all(np.isfinite(eps) & (eps >= 0)):
        raise ValueError("thickness_ratio (h/2R) must be finite and >= 0")
    Kg, Gg, nug = _check_moduli("grain", grain_bulk, grain_shear)
    Kc, Gc, _ = _check_moduli("cement", cement_bulk, cement_shear)
    R, alpha, eps = np.broadcast_arrays(R, alpha, eps)
    a = alpha * R
    h = 2.0 * eps * R                                     # the axial gap
    Mc = Kc + 4.0 * Gc / 3.0
    Eg_star = 2.0 * Gg * (1.0 + nug) / (1.0 - nug**2)     # E/(1 - nu^2) of the grain
    area, polar = np.pi * a * a, 0.5 * np.pi * a**4
    # Grain bed per area and half-space, matched to the rigid-punch stiffnesses (Johnson 1985).
    bed_n = 2.0 * a * Eg_star / area
    bed_s = 8.0 * Gg * a / (2.0 - nug) / area
    bed_b = (4.0 / 3.0) * Eg_star * a**3 / (0.5 * polar)
    bed_w = (16.0 / 3.0) * Gg * a**3 / polar
    out = []
    # (cement modulus, grain bed, which integral, angular factor): normal and shear integrate
    # r dr over the disc (2 pi), bending r^3 cos^2 phi (pi), twisting r^3 (2 pi).
    for modulus, bed, moment, factor in ((Mc, bed_n, 0, 2.0 * np.pi), (Gc, bed_s, 0, 2.0 * np.pi),
                                         (Mc, bed_b, 1, np.pi), (Gc, bed_w, 1, 2.0 * np.pi)):
        w0 = h + 2.0 * modulus / bed                      # two grains in series: t_g = 2C/bed
        out.append(factor * modulus * _layer_integrals(R, a, w0)[moment])
    return BondStiffness(*out)


def bond_cement_volume(radius, radius_ratio, thickness_ratio):
    r"""Volume of the cement of one bond: the disc :math:`r \le a` between two spheres of
    radius :math:`\bar R` whose surfaces are :math:`h = 2\varepsilon\bar R` apart,
    :math:`\pi a^2 h + 2[\pi \bar R a^2 - \tfrac{2\pi}{3}(\bar R^3 - (\bar R^2 - a^2)^{3/2})]`,
    m³."""
    R = np.asarray(radius, dtype=float)
    a = np.asarray(radius_ratio, dtype=float) * R
    h = 2.0 * np.asarray(thickness_ratio, dtype=float) * R
    s3 = np.maximum(R * R - a * a, 0.0) ** 1.5
    cap = np.pi * R * a * a - 2.0 * np.pi / 3.0 * (R**3 - s3)
    return np.pi * a * a * h + 2.0 * cap
