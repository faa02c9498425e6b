"""Least-squares calibration of free model parameters against measured velocities.

The fitting routine is model-agnostic: it takes a function that predicts velocities from named
parameters, the measurements, and the free parameters with their starting values and bounds. It
returns the fitted values, their standard errors (from the Jacobian at the solution) and the
misfit. :func:`fit_contact_cement` applies it to the contact-cement family (CCT/MCCT), e.g. to
the artificial sandstones of Table 1 of [Xu2023]_.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import least_squares

from ._validation import as_array, broadcast, check_positive, check_range
from .elastic import velocities
from .granular import contact_cement
from .materials import Mineral

__all__ = ["FitResult", "fit_parameters", "fit_contact_cement"]


@dataclass(frozen=True)
class FitResult:
    """Outcome of a least-squares calibration.

    Attributes
    ----------
    values : dict
        Fitted value of each free parameter.
    stderr : dict
        One-standard-deviation uncertainty of each, from :math:`s^2 (J^T J)^{-1}` with
        :math:`s^2` the residual variance (``nan``-free: ``inf`` when not identifiable).
    misfit : dict
        Root-mean-square relative misfit of each observed quantity at the solution.
    misfit_initial : dict
        The same at the starting values, for comparison.
    predicted : dict
        Predicted values of each observed quantity at the solution.
    success : bool
        Whether the optimiser reports convergence.
    """

    values: dict
    stderr: dict
    misfit: dict
    misfit_initial: dict
    predicted: dict = field(repr=False)
    success: bool = True


def _rms(pred, obs):
    return {k: float(np.sqrt(np.mean((pred[k] / obs[k] - 1.0) ** 2))) for k in obs}


def fit_parameters(predict: Callable[..., Mapping[str, np.ndarray]],
                   observed: Mapping[str, np.ndarray],
                   parameters: Mapping[str, tuple[float, float, float]]) -> FitResult:
    """Fit free parameters by least squares on relative residuals.

    Parameters
    ----------
    predict : callable
        ``predict(**params)`` returns a mapping with the same keys as ``observed`` (e.g.
        ``{"vp": ..., "vs": ...}``), arrays of the observed shape.
    observed : mapping
        Measured values (e.g. velocities in km/s), each array ``> 0``.
    parameters : mapping
        ``{name: (initial, lower, upper)}`` for each free parameter, with
        ``lower <= initial <= upper``.

    Returns
    -------
    FitResult
    """
    obs = {k: check_positive(k, as_array(k, v)) for k, v in observed.items()}
    if not obs:
        raise ValueError("observed must name at least one measured quantity")
    if not parameters:
        raise ValueError("parameters must name at least one free parameter")
    names = list(parameters)
    x0, lo, hi = (np.array([float(parameters[n][i]) for n in names]) for i in range(3))
    if np.any(lo > x0) or np.any(x0 > hi) or np.any(lo >= hi):
        bad = [n for n, a, b, c in zip(names, lo, x0, hi) if not a <= b <= c or a >= c]
        raise ValueError(f"parameters {bad}: need lower < upper and lower <= initial <= upper")

    def residuals(x):
        pred = predict(**dict(zip(names, x)))
        missing = set(obs) - set(pred)
        if missing:
            raise ValueError(f"predict returned no {sorted(missing)}")
        return np.concatenate([np.ravel(np.asarray(pred[k]) / obs[k] - 1.0) for k in obs])

    initial = predict(**dict(zip(names, x0)))
    sol = least_squares(residuals, x0, bounds=(lo, hi), x_scale="jac")
    pred = predict(**dict(zip(names, sol.x)))
    dof = max(sol.fun.size - len(names), 1)
    s2 = float(np.sum(sol.fun**2)) / dof
    JtJ = sol.jac.T @ sol.jac
    try:
        cov = np.linalg.inv(JtJ) * s2
        err = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    except np.linalg.LinAlgError:
        err = np.full(len(names), np.inf)
    return FitResult(
        values=dict(zip(names, map(float, sol.x))),
        stderr=dict(zip(names, map(float, err))),
        misfit=_rms(pred, obs),
        misfit_initial=_rms(initial, obs),
        predicted={k: np.asarray(pred[k]) for k in obs},
        success=bool(sol.success),
    )


def fit_contact_cement(grain: Mineral, cement: Mineral, porosity, density, vp, vs, *,
                       critical_porosity=0.4, scheme=2, stiffness="fit",
                       free=None) -> FitResult:
    r"""Fit contact-cement (CCT/MCCT) parameters to measured dry velocities.

    Predicts :math:`V_P, V_S` with :func:`rockcem.granular.contact_cement` (cement volume
    :math:`\phi_c - \phi`) and the measured bulk density, and fits the free parameters.

    Parameters
    ----------
    grain, cement : Mineral
        Grain and cement materials.
    porosity, density, vp, vs : array_like
        Measured porosity (fraction), dry bulk density (g/cm³) and velocities (km/s).
    critical_porosity : float
        :math:`\phi_c` of the uncemented pack; default 0.4 (the value of [Xu2023]_).
    scheme : {1, 2}
        Cement at contacts or coating the grains.
    stiffness : {"fit", "integral"}
        As in :func:`rockcem.granular.contact_cement`.
    free : mapping, optional
        ``{name: (initial, lower, upper)}`` over ``thickness`` and ``n``; default
        ``{"thickness": (0.01, 0.0, 0.2)}`` with ``n = 8.5`` fixed. A name not given is held at
        its default (thickness 0, n 8.5).

    Returns
    -------
    FitResult
    """
    phi = check_range("porosity", as_array("porosity", porosity), 0.0, 1.0)
    rho = check_positive("density", as_array("density", density))
    vp = check_positive("vp", as_array("vp", vp))
    vs = check_positive("vs", as_array("vs", vs))
    phi, rho, vp, vs = broadcast(porosity=phi, density=rho, vp=vp, vs=vs)
    free = dict(free) if free is not None else {"thickness": (0.01, 0.0, 0.2)}
    unknown = set(free) - {"thickness", "n"}
    if unknown:
        raise ValueError(f"free may contain 'thickness' and 'n' only; got {sorted(unknown)}")
    fixed = {"thickness": 0.0, "n": 8.5}

    def predict(**params):
        p = {**fixed, **params}
        m = contact_cement(grain.K, grain.G, cement.K, cement.G, phi, critical_porosity, p["n"],
                           scheme, p["thickness"], stiffness=stiffness)
        v = velocities(m.K, m.G, rho)
        return {"vp": v.vp, "vs": v.vs}

    return fit_parameters(predict, {"vp": vp, "vs": vs}, free)
