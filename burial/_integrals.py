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

# 6-point Gauss–Legendre: on a piece where a/T changes by less than 1/2 its relative error is
# about (1/4)^12 / 12! ~ 1e-16.
_GL_X, _GL_W = np.polynomial.legendre.leggauss(6)


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
    (the piece is cut where T crosses it).
    """
    t = np.asarray(time, dtype=float)
    T = np.asarray(temperature, dtype=float)
    dt = np.diff(t, axis=-1)
    T1, T2 = T[..., :-1], T[..., 1:]
    if start_temperature is not None:
        Ts = float(start_temperature)
        dT = T2 - T1
        # Fraction of the piece above Ts, and the temperatures at the ends of that part.
        with np.errstate(divide="ignore", invalid="ignore"):
            s_cross = np.where(dT != 0.0, (Ts - T1) / np.where(dT != 0.0, dT, 1.0), 0.0)
        s_cross = np.clip(s_cross, 0.0, 1.0)
        lo = np.where(T1 >= Ts, 0.0, s_cross)           # start of the hot part
        hi = np.where(T2 >= Ts, 1.0, s_cross)           # end of the hot part
        hot = (T1 >= Ts) | (T2 >= Ts)
        frac = np.where(hot, hi - lo, 0.0)
        T1, T2 = T1 + lo * dT, T1 + hi * dT
        dt = dt * frac
    dT = T2 - T1
    pieces = dt * 10.0 ** (b * T1) * exprel(b * dT * LN10)
    return _cumulate(pieces)


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
    :math:`|a/T_2 - a/T_1| < 1/2` the difference would cancel, and a 6-point Gauss–Legendre rule
    on the piece (exact to round-off for an integrand that changes by less than :math:`e^{1/2}`)
    is used instead. ``start_temperature`` is not supported (the Arrhenius factor already
    vanishes at low temperature).
    """
    if start_temperature is not None:
        raise ValueError("start_temperature is not used by the Arrhenius kinetics")
    t = np.asarray(time, dtype=float)
    TK = np.asarray(temperature, dtype=float) + ZERO_CELSIUS_IN_KELVIN
    dt = np.diff(t, axis=-1)
    T1, T2 = TK[..., :-1], TK[..., 1:]
    T1, T2, dt = np.broadcast_arrays(T1, T2, dt)
    near = np.abs(activation / T2 - activation / T1) < 0.5
    pieces = np.empty(T1.shape)
    if np.any(near):
        t1, t2, d = T1[near], T2[near], dt[near]
        mid, half = 0.5 * (t1 + t2), 0.5 * (t2 - t1)
        acc = np.zeros(t1.shape)
        for x, w in zip(_GL_X, _GL_W):
            acc += w * np.exp(-activation / (mid + half * x))
        pieces[near] = 0.5 * d * acc
    far = ~near
    if np.any(far):
        t1, t2 = T1[far], T2[far]
        pieces[far] = dt[far] * (_arrhenius_antiderivative(t2, activation)
                                 - _arrhenius_antiderivative(t1, activation)) / (t2 - t1)
    return _cumulate(pieces)
