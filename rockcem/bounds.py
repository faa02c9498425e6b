"""Voigt, Reuss, Hill and Hashin–Shtrikman bounds and averages for any number of phases.

All functions take the phase moduli ``K`` and ``G`` (GPa) and the volume ``fractions`` with the
phases on the **last axis**; leading axes broadcast (one row per depth, say). Fractions must lie in
[0, 1] and sum to 1 along the last axis. A phase with zero shear modulus (a fluid) is valid input.
"""

from __future__ import annotations

import functools
from typing import NamedTuple

import numpy as np

from .validation import (as_array, blockwise, broadcast_phases, check_fractions, check_modulus,
                          max_phases, min_phases, stack_phases, sum_phases)
from .elastic import Moduli
from .validation import labelled

__all__ = ["Bounds", "voigt", "reuss", "hill", "hashin_shtrikman", "hashin_shtrikman_average",
           "hashin_shtrikman_upper"]


class Bounds(NamedTuple):
    """Lower and upper bounds of the bulk and shear moduli, GPa."""

    K_lower: np.ndarray
    G_lower: np.ndarray
    K_upper: np.ndarray
    G_upper: np.ndarray

    @property
    def lower(self) -> Moduli:
        """The lower bound as ``Moduli``."""
        return Moduli(self.K_lower, self.G_lower)

    @property
    def upper(self) -> Moduli:
        """The upper bound as ``Moduli``."""
        return Moduli(self.K_upper, self.G_upper)

    @property
    def average(self) -> Moduli:
        """The arithmetic mean of the bounds (eq. C.3 of [Carcione2022]_ for HS)."""
        return Moduli(0.5 * (self.K_lower + self.K_upper), 0.5 * (self.G_lower + self.G_upper))


def _phases(K, G, fractions):
    K = check_modulus("K", as_array("K", K), allow_zero=True)
    G = check_modulus("G", as_array("G", G), allow_zero=True)
    f = check_fractions("fractions", as_array("fractions", fractions))
    f, K, G = broadcast_phases(("fractions", f), K=K, G=G)
    return K, G, f


def _by_blocks(fn, K, G, f):
    """``fn(K, G, f)`` of checked phase arrays (phases on the last axis) in blocks of points
    (:func:`rockcem.validation.blockwise`): each block's phase arrays stay in cache. ``fn``
    works point by point and returns arrays of the points' shape."""
    m = f.shape[-1]
    columns = [a[..., i] for a in (K, G, f) for i in range(m)]

    def kernel(*c):
        return fn(*np.broadcast_arrays(stack_phases(*c[:m]), stack_phases(*c[m:2 * m]),
                                       stack_phases(*c[2 * m:])))

    return blockwise(kernel, *columns)


def _fixed_moduli(K, G):
    """The phase moduli as ``n`` numbers each where they are the same at every point (an
    input of shape ``(n,)``, or repeated along the points by broadcasting: stride 0), else
    ``None``."""
    if K.size and all(a.ndim <= 1 or not any(a.strides[:-1]) for a in (K, G)):
        return K.reshape(-1, K.shape[-1])[0], G.reshape(-1, G.shape[-1])[0]
    return None


def _by_fixed_blocks(fn, K, G, f):
    """``fn(K, G, columns)`` over blocks of points (:func:`rockcem.validation.blockwise`):
    ``K``, ``G`` the ``n`` numbers of the phases (the same at every point), ``columns`` the
    ``n`` fractions of a block, one array each (not stacked); ``fn`` returns arrays of the
    block's shape."""
    return blockwise(lambda *c: fn(K, G, c), *(f[..., i] for i in range(f.shape[-1])))


def _fixed_fast(K, G):
    """Whether :func:`_hs_fixed` applies to the phase moduli ``K``, ``G`` (``n`` numbers):
    every denominator :math:`M_i + z` of the four bounds exceeds 1e-300 (no zero, no overflow
    of ``f / (M_i + z)``), i.e. no phase without shear stiffness."""
    z_lo = np.min(G)
    return (np.min(K) + 4.0 / 3.0 * z_lo > 1e-300
            and np.min(G) + float(_zeta(np.min(K), z_lo)) > 1e-300)


def _harmonic_fixed(values, columns, shift):
    r""":math:`[\sum_i f_i / (v_i + s)]^{-1} - s`, clipped at 0 (:func:`_harmonic`, the same
    operations in the same order, so the same values) for ``n`` numbers :math:`v_i` and one
    number :math:`s` (every :math:`v_i + s > 10^{-300}`), the fractions :math:`f_i` one array
    each: the denominators are numbers, and no mask is needed."""
    total = columns[0] / (values[0] + shift)
    for v, c in zip(values[1:], columns[1:]):
        total += c / (v + shift)
    total = np.divide(1.0, total, out=total) if total.ndim else 1.0 / total
    total -= shift
    # Clip the cancellation in inv - shift (as _harmonic); rarely anything to clip.
    return np.maximum(total, 0.0) if total.min() < 0.0 else total


def _hs_fixed(K, G, columns, *, lower=True, upper=True, shear=True):
    r"""Hashin–Shtrikman bounds (:func:`hashin_shtrikman`, the same arithmetic and values) of
    phases whose moduli ``K``, ``G`` are ``n`` numbers, the same at every point, for which
    :func:`_fixed_fast` holds; ``columns``: the ``n`` checked fractions, one array each.

    Where every phase is present the extreme moduli are numbers, the shifts :math:`\tfrac43
    G_{\max/\min}` and :math:`\zeta` and the denominators :math:`M_i + z` too, and each
    harmonic sum needs no mask (:func:`_harmonic_fixed`). Points where a phase is absent (a
    zero fraction: the extremes are over the phases present) are computed again by the general
    code (:func:`_hs_lower`, :func:`_hs_upper`), so each point's value never depends on its
    neighbours. Returns ``(K-, G-)``, ``(K+, G+)`` or both, in that order; without ``shear``
    the bulk moduli alone (``K-``, ``K+``)."""
    out = []
    for want, ext in ((lower, np.min), (upper, np.max)):
        if want:
            K_e, G_e = ext(K), ext(G)
            out.append(_harmonic_fixed(K, columns, 4.0 / 3.0 * G_e))
            if shear:
                out.append(_harmonic_fixed(G, columns, _zeta(K_e, G_e)))
    if all(c.min() > 0.0 for c in columns):
        return tuple(out)
    shape = np.broadcast_shapes(*(np.shape(c) for c in columns))
    flat = [np.broadcast_to(c, shape).reshape(-1) for c in columns]
    idx = np.flatnonzero(np.logical_or.reduce([c <= 0.0 for c in flat]))
    f = np.stack([c[idx] for c in flat], -1)
    Kp, Gp = np.broadcast_to(K, f.shape), np.broadcast_to(G, f.shape)
    parts = [bound for want, general in ((lower, _hs_lower), (upper, _hs_upper)) if want
             for bound in general(Kp, Gp, f)[:2 if shear else 1]]
    out = [np.array(np.broadcast_to(o, shape)) for o in out]
    for o, p in zip(out, parts):
        o.reshape(-1)[idx] = p
    return tuple(out)


def _harmonic(values, f, shift=0.0):
    r"""Return :math:`[\sum_i f_i / (v_i + s)]^{-1} - s` along the last axis.

    A phase with ``v_i + s = 0`` and ``f_i > 0`` makes the sum infinite and the result ``-s``
    (the exact limit); phases with ``f_i = 0`` never contribute, even when ``v_i + s = 0``.
    """
    shift = np.asarray(shift, dtype=float)
    denom = values + shift[..., None]
    if denom.size == 0 or denom.min() > 0.0:
        # Common case (no zero modulus meets a zero shift): plain harmonic sum.
        with np.errstate(over="ignore"):
            total = sum_phases(np.divide(f, denom, out=denom) if denom.shape == np.shape(f)
                               else f / denom)
        if total.size and np.isfinite(total.max()):
            inv = np.divide(1.0, total, out=total)
        else:
            inv = np.where(np.isfinite(total), 1.0 / total, 0.0)
        inv = np.subtract(inv, shift, out=inv) if inv.shape == np.broadcast_shapes(
            inv.shape, shift.shape) else inv - shift
        return np.maximum(inv, 0.0, out=inv)
    present = f > 0.0
    zero = present & (denom <= 0.0)
    safe = np.where(present & ~zero, denom, 1.0)
    # Subnormal denominators overflow f/denom to inf; the limit (a zero modulus) is then exact.
    with np.errstate(over="ignore", divide="ignore"):
        total = sum_phases(np.where(present & ~zero, f / safe, 0.0))
        any_zero = np.any(zero, axis=-1)
        inv = np.where(any_zero | ~np.isfinite(total) | (total <= 0.0), 0.0,
                       1.0 / np.where(np.isfinite(total) & (total > 0.0), total, 1.0))
    # Clip the cancellation in inv - shift (a bound that is exactly 0 may round to -1e-15).
    return np.maximum(inv - shift, 0.0)


def _harmonic2(a, b, x, shift, x1=None, *, divide=False):
    r""":math:`[x/(a+s) + x_1/(b+s)]^{-1} - s`, clipped at 0: :func:`_harmonic` of two phases
    with fractions ``x`` and :math:`x_1` (``x1``, or ``1 - x`` if not given), without stacking
    them. Where every denominator exceeds 1e-300 (no zero, no overflow: ``x <= 1``) a
    denominator that is one number is inverted once (a product per point instead of a division,
    within an ulp; with ``divide`` a division, the values of that function); other inputs go
    to that function."""
    da = a + shift
    db = b + shift
    if _lowest(da) > 1e-300 and _lowest(db) > 1e-300:
        total = x * (1.0 / da) if np.ndim(da) == 0 and not divide else x / da
        rest = 1.0 - x if x1 is None else x1
        rest = rest * (1.0 / db) if np.ndim(db) == 0 and not divide else rest / db
        total = _inplace(np.add, total, rest)
        total = _inplace(np.divide, 1.0, total, out_arg=1)
        total = _inplace(np.subtract, total, shift)
        # Clip the cancellation in inv - shift (as that function); rarely anything to clip.
        return np.maximum(total, 0.0) if _lowest(total) < 0.0 else total
    a, b, x, x1, shift = np.broadcast_arrays(a, b, x, 1.0 - x if x1 is None else x1, shift)
    return _harmonic(np.stack([a, b], axis=-1), np.stack([x, x1], axis=-1), shift)


def _hs_upper2(K1, G1, K2, G2, f1, f2):
    """Upper HS bound ``(K, G)`` of two phases (:func:`_hs_upper`, the same arithmetic and
    values), each modulus and fraction an array or a number (checked, broadcasting), not
    stacked: the extremes over the phases present, then :func:`_harmonic2`."""
    K_max, G_max = np.maximum(K1, K2), np.maximum(G1, G2)
    if not (_lowest(f1) > 0.0 and _lowest(f2) > 0.0):      # a phase absent somewhere
        K_max = np.where(f1 > 0.0, np.where(f2 > 0.0, K_max, K1), K2)
        G_max = np.where(f1 > 0.0, np.where(f2 > 0.0, G_max, G1), G2)
    return (_harmonic2(K1, K2, f1, 4.0 / 3.0 * G_max, f2, divide=True),
            _harmonic2(G1, G2, f1, _zeta(K_max, G_max), f2, divide=True))


def _hill2(K1, G1, K2, G2, f1, f2):
    """Hill average ``(K, G)`` of two phases (:func:`_hill`, eq. 19 of [Carcione2022]_, the same
    arithmetic and values), each modulus and fraction an array or a number (checked,
    broadcasting), not stacked."""
    return (0.5 * (f1 * K1 + f2 * K2 + _harmonic2(K1, K2, f1, 0.0, f2, divide=True)),
            0.5 * (f1 * G1 + f2 * G2 + _harmonic2(G1, G2, f1, 0.0, f2, divide=True)))


def _inplace(ufunc, a, b, out_arg=0):
    """``ufunc(a, b)``, written over the temporary ``(a, b)[out_arg]`` where it has the result's
    shape (a temporary of the caller, never an input)."""
    tmp, other = (a, b) if out_arg == 0 else (b, a)
    if isinstance(tmp, np.ndarray) and tmp.ndim and (np.ndim(other) == 0
                                                     or np.shape(other) == tmp.shape):
        return ufunc(a, b, out=tmp)
    return ufunc(a, b)


def _lowest(a):
    """The least element of a checked array or number (``min`` without numpy's dispatch)."""
    return a.min() if isinstance(a, np.ndarray) else a


@labelled(units="GPa", phases=("K", "G", "fractions"))
def voigt(K, G, fractions) -> Moduli:
    r"""Voigt (iso-strain) upper bound, :math:`M_V = \sum_i f_i M_i`.

    Parameters
    ----------
    K, G : array_like, shape (..., n)
        Bulk and shear moduli of the phases, GPa (``>= 0``).
    fractions : array_like, shape (..., n)
        Volume fractions of the phases, in [0, 1], summing to 1 along the last axis.

    Returns
    -------
    Moduli
        Arrays of shape ``(...)``, GPa.

    Examples
    --------
    >>> round(float(voigt([40.0, 2.2], [39.0, 0.0], [0.7, 0.3]).K), 2)
    28.66
    """
    K, G, f = _phases(K, G, fractions)
    return Moduli(sum_phases(f * K), sum_phases(f * G))


@labelled(units="GPa", phases=("K", "G", "fractions"))
def reuss(K, G, fractions) -> Moduli:
    r"""Reuss (iso-stress) lower bound, :math:`1/M_R = \sum_i f_i / M_i`.

    Same parameters as :func:`voigt`. A phase with zero modulus and nonzero fraction gives zero.

    Examples
    --------
    >>> float(reuss([40.0, 2.2], [39.0, 0.0], [0.7, 0.3]).G)
    0.0
    """
    K, G, f = _phases(K, G, fractions)
    zero = np.zeros(K.shape[:-1])
    return Moduli(_harmonic(K, f, zero), _harmonic(G, f, zero))


@labelled(units="GPa", phases=("K", "G", "fractions"))
def hill(K, G, fractions) -> Moduli:
    r"""Voigt–Reuss–Hill average, :math:`M_H = (M_V + M_R)/2` (eq. 19 of [Carcione2022]_).

    Same parameters as :func:`voigt`.
    """
    return Moduli(*_by_blocks(_hill, *_phases(K, G, fractions)))


def _hill(K, G, f):
    """Hill average (K, G) of checked, broadcast phase arrays (:func:`hill`)."""
    zero = np.zeros(K.shape[:-1])
    return (0.5 * (sum_phases(f * K) + _harmonic(K, f, zero)),
            0.5 * (sum_phases(f * G) + _harmonic(G, f, zero)))


def _zeta(K, G):
    r""":math:`\zeta(K, G) = \frac{G}{6}\frac{9K + 8G}{K + 2G}` (zero for a fluid, ``G = 0``)."""
    if np.size(G) and np.min(G) > 0.0:        # then K + 2G > 0 too (K >= 0)
        return G / 6.0 * (9.0 * K + 8.0 * G) / (K + 2.0 * G)
    denom = K + 2.0 * G
    return np.where(G > 0.0, G / 6.0 * (9.0 * K + 8.0 * G) / np.where(denom > 0, denom, 1.0), 0.0)


@labelled(units="GPa", phases=("K", "G", "fractions"))
def hashin_shtrikman(K, G, fractions) -> Bounds:
    r"""Hashin–Shtrikman(–Walpole) bounds for ``n`` isotropic phases.

    The two-phase form is eqs. C.1–C.2 of [Carcione2022]_ ([HashinShtrikman1963]_); for ``n`` phases
    Berryman's form ([Mavko2009]_, Sect. 4.1) is used:

    .. math::

        K^{\pm} = \Lambda(G_{\max/\min}), \qquad
        \Lambda(z) = \Big[\sum_i \frac{f_i}{K_i + \tfrac43 z}\Big]^{-1} - \tfrac43 z,

        G^{\pm} = \Gamma\big(\zeta(K_{\max/\min}, G_{\max/\min})\big), \qquad
        \Gamma(z) = \Big[\sum_i \frac{f_i}{G_i + z}\Big]^{-1} - z,

    with :math:`\zeta(K, G) = \frac{G}{6}\frac{9K+8G}{K+2G}`. The extreme moduli are taken over the
    phases present (nonzero fraction). When the stiffest bulk and shear moduli belong to different
    phases this is Walpole's (1966) generalisation, still a rigorous bound. With a fluid phase
    (``G = 0``) the lower bounds reduce to Reuss's ``K`` and to ``G = 0``.

    Parameters
    ----------
    K, G : array_like, shape (..., n)
        Bulk and shear moduli of the phases, GPa (``>= 0``).
    fractions : array_like, shape (..., n)
        Volume fractions, in [0, 1], summing to 1 along the last axis.

    Returns
    -------
    Bounds
        ``K_lower, G_lower, K_upper, G_upper``, each of shape ``(...)``; ``.average`` gives eq. C.3.

    Examples
    --------
    Quartz and cement of [Carcione2022]_, Table 1, in a 70:30 mixture:

    >>> b = hashin_shtrikman([40.0, 35.0], [39.0, 30.0], [0.7, 0.3])
    >>> round(float(b.K_lower), 4), round(float(b.K_upper), 4)
    (38.4314, 38.4407)
    """
    K, G, f = _phases(K, G, fractions)
    fixed = _fixed_moduli(K, G)
    if fixed is not None and _fixed_fast(*fixed):
        return Bounds(*_by_fixed_blocks(_hs_fixed, *fixed, f))
    return Bounds(*_by_blocks(_hs_both, K, G, f))


def _hs_both(K, G, f):
    """Lower and upper HS bounds (K-, G-, K+, G+) of checked, broadcast phase arrays."""
    return (*_hs_lower(K, G, f), *_hs_upper(K, G, f))


def _hs_upper(K, G, f):
    """Upper HS bound (K, G) of checked, broadcast phase arrays."""
    if f.size and f.min() > 0.0:           # every phase present at every point
        K_max, G_max = max_phases(K), max_phases(G)
    else:
        present = f > 0.0
        K_max = max_phases(np.where(present, K, -np.inf))
        G_max = max_phases(np.where(present, G, -np.inf))
    return _harmonic(K, f, 4.0 / 3.0 * G_max), _harmonic(G, f, _zeta(K_max, G_max))


def _hs_lower(K, G, f):
    """Lower HS bound (K, G) of checked, broadcast phase arrays."""
    if f.size and f.min() > 0.0:           # every phase present at every point
        K_min, G_min = min_phases(K), min_phases(G)
    else:
        present = f > 0.0
        K_min = min_phases(np.where(present, K, np.inf))
        G_min = min_phases(np.where(present, G, np.inf))
    return _harmonic(K, f, 4.0 / 3.0 * G_min), _harmonic(G, f, _zeta(K_min, G_min))


@labelled(units="GPa", phases=("K", "G", "fractions"))
def hashin_shtrikman_upper(K, G, fractions) -> Moduli:
    """The upper Hashin–Shtrikman bound alone (same parameters as :func:`hashin_shtrikman`)."""
    K, G, f = _phases(K, G, fractions)
    fixed = _fixed_moduli(K, G)
    if fixed is not None and _fixed_fast(*fixed):
        return Moduli(*_by_fixed_blocks(functools.partial(_hs_fixed, lower=False), *fixed, f))
    return Moduli(*_by_blocks(_hs_upper, K, G, f))


@labelled(units="GPa", phases=("K", "G", "fractions"))
def hashin_shtrikman_average(K, G, fractions) -> Moduli:
    r"""Mean of the Hashin–Shtrikman bounds, eq. C.3 of [Carcione2022]_.

    .. math::

        K_s = \tfrac12 (K^+_{HS} + K^-_{HS}), \qquad \mu_s = \tfrac12 (\mu^+_{HS} + \mu^-_{HS})

    Same parameters as :func:`hashin_shtrikman`; returns ``Moduli`` of shape ``(...)``.
    """
    K, G, f = _phases(K, G, fractions)
    fixed = _fixed_moduli(K, G)
    if fixed is not None and _fixed_fast(*fixed):
        return Moduli(*_by_fixed_blocks(_hs_average_fixed, *fixed, f))
    return Bounds(*_by_blocks(_hs_both, K, G, f)).average


def _hs_average(K, G, columns, *, shear=True):
    """Eq. C.3 of [Carcione2022]_ (:func:`hashin_shtrikman_average`) of checked fractions, one
    array per phase (``columns``), and phase moduli ``K``, ``G`` that are ``n`` checked
    numbers each, the same at every point; no blocks (for a caller that works in blocks).
    Returns ``(K, G)``, or ``(K,)`` without ``shear``."""
    if _fixed_fast(K, G):
        return _hs_average_fixed(K, G, columns, shear=shear)
    f = np.stack(np.broadcast_arrays(*columns), axis=-1)
    K, G = np.broadcast_to(K, f.shape), np.broadcast_to(G, f.shape)
    return tuple(Bounds(*_hs_both(K, G, f)).average)[:2 if shear else 1]


def _hs_average_fixed(K, G, columns, *, shear=True):
    """Eq. C.3 of [Carcione2022]_ (:func:`hashin_shtrikman_average`) by :func:`_hs_fixed`:
    ``(K, G)`` (``(K,)`` without ``shear``), each the mean of its two bounds."""
    bounds = _hs_fixed(K, G, columns, shear=shear)
    m = len(bounds) // 2
    out = []
    for lo, hi in zip(bounds[:m], bounds[m:]):
        lo += hi
        out.append(lo * 0.5)
    return tuple(out)
