"""Exact cumulative integrals of the kinetic rate factors along piecewise-linear T(t).

Both kinetics depend on the path only through a cumulative integral of a function of
temperature: Walderhaug's :math:`\\int 10^{bT} dt` and the Arrhenius :math:`\\int e^{-E/RT} dt`.
Over each linear piece of T(t) both have closed forms, evaluated here without the cancellation
of their textbook forms, so results do not depend on the time step.
"""

from __future__ import annotations

import numpy as np
from scipy.special import exp1, exprel

from rockcem.constants import LN10, ZERO_CELSIUS_IN_KELVIN

__all__ = ["cumulative_power10", "cumulative_arrhenius"]

# Gauss–Legendre rules by the change dx of a/T over a piece: the n-point error for an exponential
# e^{c s} on [-1, 1] is about 2^(2n+1) (n!)^4 / ((2n+1) ((2n)!)^3) c^(2n) with c = dx/2:
# n = 3 for dx < 0.01 (1e-18), n = 4 for dx < 0.1 (1e-17), n = 6 for dx < 1 (4e-16).
_GL_TIERS = [(0.01, np.polynomial.legendre.leggauss(3)),
             (0.1, np.polynomial.legendre.leggauss(4)),
             (1.0, np.polynomial.legendre.leggauss(6))]


def _blocked(fn, *arrays, block=1 << 15):
    """Apply ``fn(*arrays)`` (1-D arrays of pieces, broadcast to one shape) in cache-sized
    blocks.

    The per-piece formulas make several temporaries; on blocks of a few ten thousand pieces
    they stay in cache, which is 2–3 times faster than whole-array passes over 10^7 pieces.
    """
    arrays = np.broadcast_arrays(*arrays)
    shape = arrays[0].shape
    flat = [np.ascontiguousarray(a).reshape(-1) for a in arrays]
    out = np.empty(flat[0].size)
    for i in range(0, out.size, block):
        sl = slice(i, i + block)
        out[sl] = fn(*(a[sl] for a in flat))
    return out.reshape(shape)


def _per_path(value):
    """A per-path parameter (a number, or an array over the path's leading axes) against the
    pieces (last axis)."""
    return np.asarray(value, dtype=float)[..., None]


def _cumulate(pieces):
    """Cumulative sum along the last axis with a leading zero (value at the first node)."""
    out = np.zeros(pieces.shape[:-1] + (pieces.shape[-1] + 1,))
    np.cumsum(pieces, axis=-1, out=out[..., 1:])
    return out


def cumulative_power10(time, temperature, b, *, start_temperature=None):
    r""":math:`\int_0^t 10^{b T(s)}\,ds` at every node (time units of ``time``).

    On a piece from :math:`T_1` to :math:`T_2` over :math:`\Delta t`:

    .. math::

        \int 10^{bT} dt = \Delta t\, 10^{bT_1}\,\mathrm{exprel}(b\,\Delta T \ln 10),
        \qquad \mathrm{exprel}(x) = (e^x - 1)/x,

    exact for heating, cooling and constant temperature alike (no division by
    :math:`\Delta T`). With ``start_temperature`` only the part of each piece above it counts
    (the piece is cut where T crosses it). ``b`` and ``start_temperature`` are numbers or
    arrays over the path's leading axes (one per path).
    """
    t = np.asarray(time, dtype=float)
    T = np.asarray(temperature, dtype=float)
    cut = start_temperature is not None

    def pieces(T1, T2, dt, b, Ts):
        if cut:
            dT = T2 - T1
            # Fraction of the piece above Ts, and the temperatures at the ends of that part.
            with np.errstate(divide="ignore", invalid="ignore"):
                s_cross = np.where(dT != 0.0, (Ts - T1) / np.where(dT != 0.0, dT, 1.0), 0.0)
            s_cross = np.clip(s_cross, 0.0, 1.0)
            lo = np.where(T1 >= Ts, 0.0, s_cross)           # start of the hot part
            hi = np.where(T2 >= Ts, 1.0, s_cross)           # end of the hot part
            frac = np.where((T1 >= Ts) | (T2 >= Ts), hi - lo, 0.0)
            T1, T2, dt = T1 + lo * dT, T1 + hi * dT, dt * frac
        return dt * 10.0 ** (b * T1) * exprel(b * (T2 - T1) * LN10)

    return _cumulate(_blocked(pieces, T[..., :-1], T[..., 1:], np.diff(t, axis=-1), _per_path(b),
                              _per_path(start_temperature if cut else 0.0)))


def _arrhenius_antiderivative(T, a):
    r""":math:`F(T) = T e^{-a/T}\,[1 - x e^{x} E_1(x)]`, :math:`x = a/T`: an antiderivative of
    :math:`e^{-a/T}` (it is :math:`T e^{-a/T} + a\,\mathrm{Ei}(-a/T)` of eq. A.2, rearranged so
    the two terms do not cancel)."""
    x = a / T
    return T * np.exp(-x) * (1.0 - x * np.exp(x) * exp1(x))


def cumulative_arrhenius(time, temperature, activation, *, start_temperature=None):
    r""":math:`\int_0^t e^{-a/T(s)}\,ds` at every node, ``temperature`` in °C, :math:`a = E/R` in K.

    On a piece with a large change of :math:`a/T` the closed form
    :math:`\Delta t\,[F(T_2) - F(T_1)]/\Delta T` (eq. A.2 of Carcione et al. 2022) is used; where
    :math:`|a/T_2 - a/T_1| < 1` the difference would cancel, and a Gauss–Legendre rule of 3, 4
    or 6 points on the piece (chosen by the size of that change; exact to round-off) is used
    instead. ``activation`` is a number or an array over the path's leading axes (one per
    path). ``start_temperature`` is not supported (the Arrhenius factor already vanishes at
    low temperature).
    """
    if start_temperature is not None:
        raise ValueError("start_temperature is not used by the Arrhenius kinetics")
    t = np.asarray(time, dtype=float)
    TK = np.asarray(temperature, dtype=float) + ZERO_CELSIUS_IN_KELVIN

    def pieces(T1, T2, dt, a):
        dx = np.abs(a / T2 - a / T1)
        out = np.empty(T1.shape)
        lower = 0.0
        for upper, (nodes, weights) in _GL_TIERS:
            sel = (dx >= lower) & (dx < upper)
            lower = upper
            if not np.any(sel):
                continue
            every = bool(np.all(sel))      # the common case: no copies through a mask
            t1, t2, d, ai = (T1, T2, dt, a) if every else (T1[sel], T2[sel], dt[sel], a[sel])
            mid, half = 0.5 * (t1 + t2), 0.5 * (t2 - t1)
            acc = np.zeros(t1.shape)
            for xg, w in zip(nodes, weights):
                acc += w * np.exp(-ai / (mid + half * xg))
            if every:
                return 0.5 * d * acc
            out[sel] = 0.5 * d * acc
        far = dx >= lower
        if np.any(far):
            t1, t2, af = T1[far], T2[far], a[far]
            out[far] = dt[far] * (_arrhenius_antiderivative(t2, af)
                                  - _arrhenius_antiderivative(t1, af)) / (t2 - t1)
        return out

    return _cumulate(_blocked(pieces, TK[..., :-1], TK[..., 1:], np.diff(t, axis=-1),
                              _per_path(activation)))
