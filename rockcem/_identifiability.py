"""Identifiability of fitted parameters: their correlation, and which ones the data do not
determine (one rule for :mod:`rockcem.wellfit` and :mod:`md.calibrate`; public through
:mod:`rockcem.calibrate`)."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

#: Correlation beyond which two fitted parameters are reported as not separately determined.
CORRELATION_LIMIT = 0.999
#: The rule of :func:`unidentifiable` in words, as calibration files record it.
IDENTIFIABILITY_RULE = (f"standard error infinite, wider than the bounds or than the value, or "
                        f"|correlation| > {CORRELATION_LIMIT:g} (linearised at the solution; "
                        f"rockcem.calibrate.unidentifiable)")


def correlation(result) -> np.ndarray:
    r"""Correlation matrix of the fitted parameters of ``result``.

    Parameters
    ----------
    result : rockcem.calibrate.FitResult

    Returns
    -------
    ndarray, shape (p, p)
        :math:`C_{ij}/\sqrt{C_{ii} C_{jj}}` of the covariance :math:`C`, in the order of
        ``result.values``; NaN where not defined (an infinite or zero variance), 1 on the
        diagonal.
    """
    cov = np.asarray(result.covariance, dtype=float)
    with np.errstate(invalid="ignore", divide="ignore"):
        d = np.sqrt(np.diag(cov))
        corr = cov / np.outer(d, d)
    defined = np.isfinite(d) & (d > 0)
    corr = np.where(np.isfinite(corr) & np.outer(defined, defined), corr, np.nan)
    np.fill_diagonal(corr, 1.0)
    return corr


def unidentifiable(result, bounds: Mapping[str, tuple], *, relative=False,
                   correlation_limit=CORRELATION_LIMIT) -> tuple:
    r"""The fitted parameters the data do not determine.

    A parameter is unidentifiable when its standard error :math:`\sigma` is not finite, or
    wider than the range of its bounds, :math:`\sigma > u - l` (the data do not narrow the
    range it was allowed), or when it correlates with another fitted parameter by
    :math:`|r| > r_{max}`, or not definably (NaN) with one whose error is finite: the data fix
    at best a combination of the two. (Beside a parameter without leverage, whose error is
    infinite, the others are judged by their errors with it held; see
    :func:`rockcem.calibrate.fit_parameters`.) With ``relative``, also when
    :math:`\sigma > |x|` at a value :math:`x \neq 0`: the one-sigma interval reaches past
    zero, so the data do not fix the value's magnitude (a value of exactly 0, which lies on a
    bound, is judged by the other tests only). This is the linearised (Jacobian) picture at
    the solution, the same as the standard errors.

    Parameters
    ----------
    result : rockcem.calibrate.FitResult
        From :func:`rockcem.calibrate.fit_parameters`.
    bounds : mapping
        ``{name: (initial, lower, upper)}`` (as passed to
        :func:`rockcem.calibrate.fit_parameters`) or ``{name: (lower, upper)}`` for every
        fitted parameter, in its units.
    relative : bool, keyword-only
        Add the test against the value's magnitude. Default: off.
    correlation_limit : float, keyword-only
        :math:`r_{max}`, in (0, 1]; default :data:`CORRELATION_LIMIT`.

    Returns
    -------
    tuple of str
        Names, in the order of ``result.values``.
    """
    if not 0.0 < correlation_limit <= 1.0:
        raise ValueError(f"correlation_limit must lie in (0, 1]; got {correlation_limit!r}")
    missing = [k for k in result.values if k not in bounds]
    if missing:
        raise ValueError(f"bounds must give (lower, upper) for every fitted parameter; "
                         f"missing {missing}")
    corr = correlation(result)
    errors = np.array([result.stderr[k] for k in result.values], dtype=float)
    bad = []
    for i, k in enumerate(result.values):
        lo, hi = bounds[k][-2:]
        err, value = result.stderr[k], result.values[k]
        others = np.abs(np.delete(corr[i], i))
        # An undefined correlation counts against the parameter unless the other one has no
        # finite error (no leverage: flagged itself; this one's error is then conditional).
        finite = np.isfinite(np.delete(errors, i))
        if not np.isfinite(err) or err > hi - lo or np.any(others > correlation_limit) \
                or np.any(np.isnan(others) & finite) \
                or (relative and value != 0.0 and err > abs(value)):
            bad.append(k)
    return tuple(bad)
