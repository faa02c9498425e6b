"""Resolution error of a quantity computed at two or three cement-lattice resolutions.

A value :math:`X(\\Omega)` computed on a lattice of :math:`\\Omega` cells per grain radius tends
to its limit as :math:`X(\\Omega) = X_\\infty + C\\,\\Omega^{-p}` once :math:`\\Omega` is fine
enough (the asymptotic range). Richardson extrapolation (Richardson 1911; Roache 1998,
*Verification and Validation in Computational Science and Engineering*, ch. 5) estimates the
error of the finest value from coarser ones:

* two resolutions :math:`\\Omega > \\Omega_1`, an assumed first order:
  :math:`|X(\\Omega) - X(\\Omega_1)| / (\\Omega/\\Omega_1 - 1)`;
* three resolutions :math:`\\Omega > \\Omega_1 > \\Omega_2`: the observed order :math:`p` solves
  :math:`(\\Omega_1^{-p} - \\Omega^{-p}) / (\\Omega_2^{-p} - \\Omega_1^{-p}) = d_1 / d_2` with
  :math:`d_1 = X(\\Omega) - X(\\Omega_1)`, :math:`d_2 = X(\\Omega_1) - X(\\Omega_2)`, and the
  error is
  :math:`|X(\\Omega) - X_\\infty| = |d_1|\\,\\Omega^{-p} / (\\Omega_1^{-p} - \\Omega^{-p})`.
  The three are taken to be in the asymptotic range when the two changes have one sign and
  :math:`p` lies in :data:`ORDER_RANGE`. Where they are not, but both changes are below
  :data:`SETTLED` of the finest value, the sequence has settled to the lattice's noise: the
  error is then the first-order two-point estimate, the size of that noise (at half-filled
  pores the Ω 10 value lies 1.4 times that estimate from the Ω 6 one: the noise can pass for
  convergence). Elsewhere the estimate falls back to the same first-order one and is
  flagged: it is then an indication, not a bound (a coating thinner than a lattice cell
  gains 3 to 10 % per step of :math:`\\Omega` up to 10: the benchmark
  ``md_scene_error_vs_time``).
"""

from __future__ import annotations

import numpy as np

__all__ = ["ORDER_RANGE", "SETTLED", "richardson", "resolution_error"]

#: Observed orders accepted as asymptotic (the lattice's own order is 1 to 2; the benchmark
#: ``md_omega_convergence`` uses the same range).
ORDER_RANGE = (0.5, 3.0)
#: Largest change between resolutions, relative to the finest value, of a settled sequence.
SETTLED = 0.01


def richardson(omegas, values, *, order_range=ORDER_RANGE):
    """Limit and observed order of three values at three resolutions.

    Parameters
    ----------
    omegas : sequence of 3 float
        Distinct resolutions, any order.
    values : sequence of 3 float
        The quantity at each.
    order_range : (float, float)
        Orders accepted, default :data:`ORDER_RANGE`.

    Returns
    -------
    (float, float)
        :math:`X_\\infty` and :math:`p`; NaN, NaN where the three are not in the asymptotic
        range (the changes differ in sign, one is zero, or the order falls outside
        ``order_range``).
    """
    from scipy.optimize import brentq

    o = np.asarray(omegas, dtype=float)
    v = np.asarray(values, dtype=float)
    if o.shape != (3,) or v.shape != (3,):
        raise ValueError(f"richardson needs three resolutions and three values; got shapes "
                         f"{o.shape} and {v.shape}")
    if not (np.all(np.isfinite(o)) and np.all(o > 0) and np.unique(o).size == 3):
        raise ValueError(f"omegas must be three distinct positive numbers; got {o.tolist()}")
    order = np.argsort(o)[::-1]                     # finest first
    o, v = o[order], v[order]
    if not np.all(np.isfinite(v)):
        return np.nan, np.nan
    d1, d2 = v[0] - v[1], v[1] - v[2]
    if not d1 * d2 > 0:
        return np.nan, np.nan
    ratio = d1 / d2

    def f(q):
        return (o[1] ** -q - o[0] ** -q) / (o[2] ** -q - o[1] ** -q) - ratio

    lo, hi = order_range
    if f(lo) * f(hi) > 0:                           # f falls with q: no root in the range
        return np.nan, np.nan
    p = brentq(f, lo, hi, xtol=1e-12)
    c = d1 / (o[0] ** -p - o[1] ** -p)
    return float(v[0] - c * o[0] ** -p), float(p)


def resolution_error(omegas, values):
    """Resolution error of the finest of two or three values, and whether it is asymptotic.

    Parameters
    ----------
    omegas : sequence of float
        Two or three distinct resolutions; the first is the finest (the result's).
    values : array_like, shape (len(omegas), ...)
        The quantity at each resolution (along the first axis).

    Returns
    -------
    (numpy.ndarray, numpy.ndarray)
        The absolute error of ``values[0]`` (shape ``values.shape[1:]``), and a bool array:
        True where three resolutions are in the asymptotic range (the error is the Richardson
        estimate with the observed order), have settled outside it (both changes below
        :data:`SETTLED` of the finest value; the first-order estimate) or give one value (the
        error is zero: an uncemented sample does not see the lattice); False where the error
        is the first-order two-point estimate of an unsettled sequence, and always with two
        resolutions (no three-point check was made: callers report that as missing, not as
        failed).
    """
    o = np.asarray(omegas, dtype=float)
    v = np.asarray(values, dtype=float)
    if o.ndim != 1 or o.size not in (2, 3) or v.shape[:1] != o.shape:
        raise ValueError(f"resolution_error needs 2 or 3 resolutions and values along the "
                         f"first axis; got {o.size} resolutions and values of shape {v.shape}")
    if not (np.all(o[1:] < o[0]) and np.all(o >= 1) and np.unique(o).size == o.size):
        raise ValueError(f"omegas must be distinct, >= 1, the first the finest; got "
                         f"{o.tolist()}")
    first = np.abs(v[0] - v[1]) / (o[0] / o[1] - 1.0)
    asymptotic = np.zeros(v.shape[1:], dtype=bool)
    if o.size == 2:
        return first, asymptotic
    error = np.array(first, dtype=float)
    for k in np.ndindex(v.shape[1:]):
        column = v[(slice(None), *k)]
        if np.all(column == column[0]):
            error[k], asymptotic[k] = 0.0, True
            continue
        limit, _ = richardson(o, column)
        if np.isfinite(limit):
            error[k] = abs(v[(0, *k)] - limit)
            asymptotic[k] = True
        elif np.all(np.abs(np.diff(column)) <= SETTLED * abs(column[0])):
            asymptotic[k] = True            # settled: the first-order estimate stands
    return error, asymptotic
