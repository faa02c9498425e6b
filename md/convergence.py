"""Resolution error of a quantity computed at two or three cement-lattice resolutions.

A value :math:`X(\\Omega)` computed on a lattice of :math:`\\Omega` cells per grain radius tends
to its limit as :math:`X(\\Omega) = X_\\infty + C\\,\\Omega^{-p}` once :math:`\\Omega` is fine
enough (the asymptotic range). Richardson extrapolation (Richardson 1911; Roache 1998,
*Verification and Validation in Computational Science and Engineering*, ch. 5) estimates the
error of the finest value from coarser ones; the three-point observed order :math:`p` solves
:math:`(\\Omega_1^{-p} - \\Omega^{-p}) / (\\Omega_2^{-p} - \\Omega_1^{-p}) = d_1 / d_2` with
:math:`d_1 = X(\\Omega) - X(\\Omega_1)`, :math:`d_2 = X(\\Omega_1) - X(\\Omega_2)`
(:func:`richardson`).

The lattice adds a noise of about 1 % to every value (where its cells fall against the grains),
so a Richardson estimate from resolutions close together fits the noise: with
:math:`\\Omega` 6, 5, 4 and 0.5 % noise on a first-order sequence with a 3 % error, a third
of the estimates called asymptotic understate the error more than twice. The default rule,
``"gci"``, is Roache's grid convergence index (Roache 1998, ch. 5.6, eqs. 5.6.1-5.6.3; the
procedure of Celik et al. 2008, J. Fluids Eng. 130, 078001, eqs. 1-5), which puts a safety
factor on the Richardson estimate:

* three resolutions whose two changes have one sign and whose observed order lies in
  :data:`ORDER_RANGE`: :math:`F_s |d_1| / (r^{p} - 1)` with :math:`r = \\Omega/\\Omega_1`,
  :math:`F_s` = :data:`SAFETY_OBSERVED` (1.25) and :math:`p` clipped to :data:`ORDER_CLIP`
  (0.5 to 1: a lattice cutting the grain surfaces converges at first order, and a higher
  observed order on three noisy values is mostly the noise's);
* three resolutions out of that range (the changes differ in sign or the order is not
  credible: noise or a sequence not yet asymptotic): :data:`SAFETY_FALLBACK` (3) times the
  larger first-order estimate of the two steps, :math:`|d_k| / (r_k - 1)`;
* two resolutions: :data:`SAFETY_FALLBACK` times the first-order estimate
  :math:`|d_1| / (r - 1)` (Roache's factor for two grids).

The resolutions should be spaced by at least :data:`MIN_RATIO` (1.5): closer ones let the noise
decide the order. ``benchmarks/md_error_coverage.py`` measures how often each rule bounds the
difference to a finer reference (synthetic sequences with noise, and MD members). The former
rule, ``"richardson"`` (the Richardson estimate with the observed order where it is in range,
the first-order estimate elsewhere, no safety factor, and a sequence whose changes are below
:data:`SETTLED` counted as converged), is kept to reproduce earlier results.
"""

from __future__ import annotations

import numpy as np

__all__ = ["ORDER_RANGE", "ORDER_CLIP", "SETTLED", "MIN_RATIO", "SAFETY_OBSERVED",
           "SAFETY_FALLBACK", "RULES", "richardson", "resolution_error"]

#: Observed orders accepted as asymptotic (the lattice's own order is 1 to 2; the benchmark
#: ``md_omega_convergence`` uses the same range).
ORDER_RANGE = (0.5, 3.0)
#: Orders the ``"gci"`` rule computes its error with (the observed order clipped to them): a
#: lattice that cuts the grain surfaces converges at first order, and on three values with 1 %
#: noise a higher observed order is mostly the noise's (it would shrink the error threefold).
ORDER_CLIP = (0.5, 1.0)
#: Largest change between resolutions, relative to the finest value, of a settled sequence
#: (the ``"richardson"`` rule only).
SETTLED = 0.01
#: Smallest ratio of consecutive resolutions recommended for an order estimate.
MIN_RATIO = 1.5
#: Safety factor of the grid convergence index with an observed order (Roache 1998, ch. 5.6).
SAFETY_OBSERVED = 1.25
#: Safety factor of the grid convergence index without one (two grids, or no credible order).
SAFETY_FALLBACK = 3.0
#: Rules of :func:`resolution_error`.
RULES = ("gci", "richardson")


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


def resolution_error(omegas, values, *, rule="gci"):
    """Resolution error of the finest of two or three values, and whether it has an order.

    Parameters
    ----------
    omegas : sequence of float
        Two or three distinct resolutions; the first is the finest (the result's).
    values : array_like, shape (len(omegas), ...)
        The quantity at each resolution (along the first axis).
    rule : {"gci", "richardson"}
        ``"gci"`` (default): the grid convergence index of the module docstring;
        ``"richardson"``: the former rule, without safety factors.

    Returns
    -------
    (numpy.ndarray, numpy.ndarray)
        The absolute error of ``values[0]`` (shape ``values.shape[1:]``), and a bool array:
        True where three resolutions are in the asymptotic range (one sign, an observed order
        in :data:`ORDER_RANGE`) or give one value (the error is zero: an uncemented sample does
        not see the lattice) — and, under ``"richardson"``, where they have settled within
        :data:`SETTLED`; False elsewhere, and always with two resolutions (no three-point
        check was made: callers report that as missing, not as failed).
    """
    if rule not in RULES:
        raise ValueError(f"rule must be one of {RULES}; got {rule!r}")
    o = np.asarray(omegas, dtype=float)
    v = np.asarray(values, dtype=float)
    if o.ndim != 1 or o.size not in (2, 3) or v.shape[:1] != o.shape:
        raise ValueError(f"resolution_error needs 2 or 3 resolutions and values along the "
                         f"first axis; got {o.size} resolutions and values of shape {v.shape}")
    if not (np.all(np.diff(o) < 0) and o[-1] >= 1):
        raise ValueError(f"omegas must be >= 1 and decreasing, the first the finest; got "
                         f"{o.tolist()}")
    gci = rule == "gci"
    steps = [np.abs(v[k] - v[k + 1]) / (o[k] / o[k + 1] - 1.0) for k in range(o.size - 1)]
    asymptotic = np.zeros(v.shape[1:], dtype=bool)
    if o.size == 2:
        return (SAFETY_FALLBACK if gci else 1.0) * steps[0], asymptotic
    # an array even for one value per resolution (0-d), so that error[k] can be set
    error = np.array(SAFETY_FALLBACK * np.maximum(*steps) if gci else steps[0], dtype=float)
    for k in np.ndindex(v.shape[1:]):
        column = v[(slice(None), *k)]
        if np.all(column == column[0]):
            error[k], asymptotic[k] = 0.0, True
            continue
        limit, p = richardson(o, column)
        if np.isfinite(limit):
            asymptotic[k] = True
            if gci:
                q = min(max(p, ORDER_CLIP[0]), ORDER_CLIP[1])
                error[k] = (SAFETY_OBSERVED * abs(column[0] - column[1])
                            / ((o[0] / o[1]) ** q - 1.0))
            else:
                error[k] = abs(column[0] - limit)
        elif not gci and np.all(np.abs(np.diff(column)) <= SETTLED * abs(column[0])):
            asymptotic[k] = True            # settled: the first-order estimate stands
    return error, asymptotic
