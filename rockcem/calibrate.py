"""Least-squares calibration of free model parameters against measured velocities.

The fitting routine is model-agnostic: it takes a function that predicts velocities from named
parameters, the measurements, and the free parameters with their starting values and bounds. It
returns the fitted values, their standard errors (from the Jacobian at the solution) and the
misfit. Residuals are relative (``predicted / observed - 1``) unless measurement errors are
given, in which case they are weighted, ``(predicted - observed) / error``.
:func:`fit_contact_cement` applies it to the contact-cement family (CCT/MCCT), e.g. to the
artificial sandstones of Table 1 of [Xu2023]_; :mod:`md.calibrate` applies it to MD results.

Calibration files carry a fitted parameter set to scenes: :func:`write_calibration` writes one
(TOML, format ``rockcem-calibration/1``, described in ``datasets/calibrations/README.md``),
:func:`load_calibration` reads and checks it, and a scene names it in
``[models.patchy_cement] calibration = "<file or shipped name>"``.
"""

from __future__ import annotations

import datetime
import hashlib
import tomllib
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy.optimize import least_squares

from ._identifiability import (CORRELATION_LIMIT, IDENTIFIABILITY_RULE, correlation,
                               unidentifiable)
from ._toml import toml_value
from .validation import as_array, broadcast, check_positive, check_range
from .elastic import velocities
from .granular import contact_cement
from .materials import Mineral

__all__ = ["FitResult", "fit_parameters", "fit_contact_cement", "correlation", "unidentifiable",
           "CORRELATION_LIMIT", "IDENTIFIABILITY_RULE", "CALIBRATION_FORMAT",
           "CALIBRATION_MODELS", "write_calibration", "load_calibration", "shipped_calibrations",
           "apply_scene_calibration"]

#: Version tag of the calibration file format.
CALIBRATION_FORMAT = "rockcem-calibration/1"
#: What a calibration file may calibrate: the effective-medium models :mod:`md.calibrate` fits,
#: and ``"scene"``, any numeric scene keys named ``"section.key"`` (written by
#: :mod:`rockcem.wellfit` from a fit to a well; a scene names it in its top-level
#: ``calibration`` key).
CALIBRATION_MODELS = ("contact_cement", "patchy_cement", "scene")


@dataclass(frozen=True)
class FitResult:
    r"""Outcome of a least-squares calibration.

    Attributes
    ----------
    values : dict
        Fitted value of each free parameter.
    stderr : dict
        One-standard-deviation uncertainty of each, from :math:`s^2 (J^T J)^{-1}` with
        :math:`s^2` the residual variance (1 with ``absolute_errors``; ``nan``-free: ``inf``
        when not identifiable).
    misfit : dict
        Root-mean-square relative misfit of each observed quantity at the solution.
    misfit_initial : dict
        The same at the starting values, for comparison.
    predicted : dict
        Predicted values of each observed quantity at the solution.
    success : bool
        Whether the optimiser reports convergence.
    chi2 : float
        Sum of the squared residuals at the solution: relative residuals, or weighted ones
        (:math:`\chi^2`) when errors were given.
    dof : int
        Degrees of freedom, number of residuals minus number of free parameters (at least 1).
    covariance : ndarray, shape (p, p)
        Covariance of the free parameters in the order of ``values`` (``inf`` on the diagonal
        when not identifiable).
    at_bound : dict
        Whether each fitted value lies on (within 1e-9 of the range of) a bound, where its
        standard error understates the uncertainty.
    """

    values: dict
    stderr: dict
    misfit: dict
    misfit_initial: dict
    predicted: dict = field(repr=False)
    success: bool = True
    chi2: float = 0.0
    dof: int = 1
    covariance: np.ndarray | None = field(default=None, repr=False)
    at_bound: dict = field(default_factory=dict)


def _rms(pred, obs):
    """Root-mean-square misfit per quantity: relative (predicted / observed - 1) where every
    observation is > 0, else absolute (predicted - observed)."""
    return {k: float(np.sqrt(np.mean((pred[k] / obs[k] - 1.0) ** 2)))
            if np.all(obs[k] > 0.0) else float(np.sqrt(np.mean((pred[k] - obs[k]) ** 2)))
            for k in obs}


def fit_parameters(predict: Callable[..., Mapping[str, np.ndarray]],
                   observed: Mapping[str, np.ndarray],
                   parameters: Mapping[str, tuple[float, float, float]], *,
                   errors: Mapping[str, np.ndarray] | None = None,
                   absolute_errors: bool = False) -> FitResult:
    r"""Fit free parameters by least squares, on relative or error-weighted residuals.

    Minimises :math:`\sum_i r_i^2` with :math:`r_i = p_i/o_i - 1` (relative residuals, the
    default) or :math:`r_i = (p_i - o_i)/\sigma_i` (weighted by the measurement errors
    :math:`\sigma_i`), within the bounds of each parameter (``scipy.optimize.least_squares``,
    trust-region reflective). The covariance of the parameters is
    :math:`s^2 (J^T J)^{-1}` with :math:`J` the Jacobian of the residuals at the solution and
    :math:`s^2 = \chi^2/(N - p)` the residual variance, as ``scipy.optimize.curve_fit`` with
    ``absolute_sigma=False``; with ``absolute_errors=True`` the errors are taken as true
    standard deviations and :math:`s^2 = 1`. A parameter whose column of :math:`J` is zero
    (it does not move the prediction at the solution) gets an infinite error and no
    covariance with the others, whose covariance is then that of the fit with it held; where
    :math:`J^T J` of the others is singular, every error is infinite.

    Parameters
    ----------
    predict : callable
        ``predict(**params)`` returns a mapping with the same keys as ``observed`` (e.g.
        ``{"vp": ..., "vs": ...}``), arrays of the observed shape.
    observed : mapping
        Measured values (e.g. velocities in km/s), each array finite, and ``> 0`` for relative
        residuals (no ``errors``); with ``errors`` a value may be 0 or below (a log porosity).
    parameters : mapping
        ``{name: (initial, lower, upper)}`` for each free parameter, with
        ``lower <= initial <= upper``.
    errors : mapping, optional, keyword-only
        One-standard-deviation errors of the measurements, ``{name: array}`` for every key of
        ``observed``, in its units and broadcastable to its shape, each ``> 0``. Default: none
        (relative residuals, every point weighted by ``1/observed``).
    absolute_errors : bool, optional, keyword-only
        Take ``errors`` as absolute standard deviations (covariance not rescaled by the
        residual variance). Needs ``errors``.

    Returns
    -------
    FitResult
        ``misfit`` is the root-mean-square relative misfit either way, for a quantity whose
        observations are all ``> 0``; else its absolute misfit (predicted - observed).
    """
    obs = {k: check_positive(k, as_array(k, v)) if errors is None else
           check_range(k, as_array(k, v), -np.inf, np.inf, low_open=True, high_open=True)
           for k, v in observed.items()}
    if not obs:
        raise ValueError("observed must name at least one measured quantity")
    if not parameters:
        raise ValueError("parameters must name at least one free parameter")
    if errors is not None:
        missing = sorted(set(obs) - set(errors))
        extra = sorted(set(errors) - set(obs))
        if missing or extra:
            raise ValueError(f"errors must give one array per observed quantity "
                             f"{sorted(obs)}; missing {missing}, not observed {extra}")
        sigma = {k: broadcast(**{k: obs[k], f"errors[{k!r}]": check_positive(
            f"errors[{k!r}]", as_array(f"errors[{k!r}]", errors[k]))})[1] for k in obs}
    elif absolute_errors:
        raise ValueError("absolute_errors=True needs errors")
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
        if errors is None:
            return np.concatenate([np.ravel(np.asarray(pred[k]) / obs[k] - 1.0) for k in obs])
        return np.concatenate([np.ravel((np.asarray(pred[k]) - obs[k]) / sigma[k])
                               for k in obs])

    initial = predict(**dict(zip(names, x0)))
    sol = least_squares(residuals, x0, bounds=(lo, hi), x_scale="jac")
    pred = predict(**dict(zip(names, sol.x)))
    dof = max(sol.fun.size - len(names), 1)
    chi2 = float(np.sum(sol.fun**2))
    s2 = 1.0 if absolute_errors else chi2 / dof
    jac = np.asarray(sol.jac, dtype=float)
    live = np.flatnonzero(np.any(jac != 0.0, axis=0))   # parameters that move the residuals
    cov = np.diag(np.full(len(names), np.inf))
    try:
        if live.size:
            sub = np.linalg.inv(jac[:, live].T @ jac[:, live]) * s2
            cov[np.ix_(live, live)] = sub
    except np.linalg.LinAlgError:
        cov = np.diag(np.full(len(names), np.inf))
    err = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    tol = 1e-9 * (hi - lo)
    at_bound = (sol.x - lo <= tol) | (hi - sol.x <= tol)
    return FitResult(
        values=dict(zip(names, map(float, sol.x))),
        stderr=dict(zip(names, map(float, err))),
        misfit=_rms(pred, obs),
        misfit_initial=_rms(initial, obs),
        predicted={k: np.asarray(pred[k]) for k in obs},
        success=bool(sol.success),
        chi2=chi2,
        dof=int(dof),
        covariance=cov,
        at_bound=dict(zip(names, map(bool, at_bound))),
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


# ----------------------------------------------------------------------------- calibration files
def write_calibration(path, *, name, model, parameters, uncertainty=None, misfit=None,
                      description="", data="", weights="", references="", record=None,
                      identifiability=None) -> Path:
    """Write a calibration file (TOML, format ``rockcem-calibration/1``) atomically.

    The file has top-level keys ``format``, ``name``, ``description``, ``model``, ``data``,
    ``weights``, ``created``, ``software``, ``references`` and the tables ``[parameters]`` (the
    values a scene applies: model parameters and the cement-radius ``scheme``),
    ``[uncertainty]`` (one-sigma errors of the fitted ones), ``[misfit]`` (root-mean-square
    relative misfit per observed quantity), ``[fit]`` (what the fit was made on, for the
    record only) and, where given, ``[identifiability]`` (which parameters the data could not
    determine and what was done about it, for the record only). :func:`load_calibration` reads
    it back.

    Parameters
    ----------
    path : str or Path
        File to write.
    name, model : str
        Name of the calibration; fitted model, one of :data:`CALIBRATION_MODELS`.
    parameters : mapping
        ``{parameter: value}``, numbers (``scheme`` an integer 1 or 2).
    uncertainty, misfit : mapping, optional
        ``{parameter: standard error}`` and ``{quantity: misfit}``.
    description, data, weights, references : str
        Free text: what the calibration is for, the data it was fitted to, the residual weights
        and the sources.
    record : mapping, optional
        Scalars, strings or lists of them describing the fit (the ``[fit]`` table).
    identifiability : mapping, optional
        Scalars, strings or lists of them (the ``[identifiability]`` table); its key
        ``unidentifiable``, if given, a list of parameter names.

    Returns
    -------
    Path
    """
    from . import __version__
    from ._atomic import atomic_write

    head = {"format": CALIBRATION_FORMAT, "name": name, "description": description,
            "model": model, "data": data, "weights": weights,
            "created": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
            "software": f"rockcem {__version__}", "references": references}
    lines = [f"# rockcem calibration file ({CALIBRATION_FORMAT}). Scenes apply [parameters]; the "
             "other tables record the fit.", ""]
    lines += [f"{k} = {toml_value(v)}" for k, v in head.items()]
    for table, values in (("parameters", parameters), ("uncertainty", uncertainty or {}),
                          ("misfit", misfit or {}), ("fit", record or {}),
                          ("identifiability", identifiability)):
        if values is None:
            continue
        lines += ["", f"[{table}]"] + [f"{_toml_key(k)} = {toml_value(v)}"
                                       for k, v in values.items()]
    text = "\n".join(lines) + "\n"
    _check_calibration(tomllib.loads(text), str(path))

    def write(tmp):
        with open(tmp, "w", encoding="utf-8") as fh:
            fh.write(text)

    return atomic_write(path, write)


def _toml_key(key) -> str:
    """A TOML key: bare where it can be, quoted otherwise (``"sandstone.beta"``)."""
    import json
    import re

    return key if re.fullmatch(r"[A-Za-z0-9_-]+", key) else json.dumps(key)


def shipped_calibrations() -> dict[str, Path]:
    """The calibration files shipped in ``datasets/calibrations/``: ``{name: path}``."""
    from ._data import data_path

    try:
        folder = data_path("calibrations")
    except FileNotFoundError:
        return {}
    return {p.stem: p for p in sorted(folder.glob("*.toml"))}


def _check_calibration(raw, where):
    def bad(msg):
        return ValueError(f"calibration file {where}: {msg}")

    if raw.get("format") != CALIBRATION_FORMAT:
        raise bad(f"format must be {CALIBRATION_FORMAT!r}; got {raw.get('format')!r}")
    if raw.get("model") not in CALIBRATION_MODELS:
        raise bad(f"model must be one of {', '.join(CALIBRATION_MODELS)}; got "
                  f"{raw.get('model')!r}")
    params = raw.get("parameters")
    if not isinstance(params, dict) or not params:
        raise bad("needs a non-empty table [parameters]")
    for k, v in params.items():
        number = isinstance(v, (int, float)) and not isinstance(v, bool)
        if not number or not np.isfinite(v):
            raise bad(f"parameter {k} must be a finite number; got {v!r}")
    if "scheme" in params and (not isinstance(params["scheme"], int)
                               or params["scheme"] not in (1, 2)):
        raise bad(f"parameter scheme must be the integer 1 or 2; got {params['scheme']!r}")
    for table in ("uncertainty", "misfit"):
        values = raw.get(table, {})
        if not isinstance(values, dict) or not all(
                isinstance(v, (int, float)) and not isinstance(v, bool) and v >= 0
                for v in values.values()):
            raise bad(f"[{table}] must map names to numbers >= 0")
    unknown = sorted(set(raw.get("uncertainty", {})) - set(params))
    if unknown:
        raise bad(f"[uncertainty] names {unknown}, which are not in [parameters]")
    ident = raw.get("identifiability", {})
    names = ident.get("unidentifiable", []) if isinstance(ident, dict) else None
    if not isinstance(names, list) or not all(isinstance(k, str) for k in names):
        raise bad("[identifiability] must be a table whose key unidentifiable, if present, is "
                  "a list of parameter names")


def load_calibration(source, *, base_dir=None) -> dict:
    """Read and check a calibration file written by :func:`write_calibration`.

    Parameters
    ----------
    source : str or Path
        A file path — absolute, or relative to ``base_dir`` (the folder of the scene that
        names it) and then to the working directory — or the name of a shipped calibration
        (:func:`shipped_calibrations`).
    base_dir : str or Path, optional, keyword-only
        Folder relative paths are looked up in first.

    Returns
    -------
    dict
        ``name``, ``model``, ``description``, ``data``, ``parameters``, ``uncertainty``,
        ``misfit``, ``identifiability`` (as in the file; empty where absent), ``path``
        (resolved, str) and ``sha256`` (of the file).

    Raises
    ------
    ValueError
        If the file is missing, not TOML, or not a valid calibration file.
    """
    from ._data import find_file

    given = Path(str(source))
    shipped = shipped_calibrations()
    bare = not given.suffix and len(given.parts) == 1 and str(source) in shipped
    path, looked = find_file(source, base_dir, shipped[str(source)] if bare else None)
    if path is None:
        names = f"; shipped calibrations: {', '.join(shipped)}" if shipped else ""
        raise ValueError(f"calibration file {str(source)!r} not found (looked for {looked})"
                         f"{names}")
    from ._toml import toml_text

    data = path.read_bytes()
    text = toml_text(path, f"calibration file {path}")      # UTF-8, a byte-order mark dropped
    try:
        raw = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"calibration file {path} is not valid TOML: {exc}") from None
    _check_calibration(raw, str(path))
    return {"name": str(raw.get("name", path.stem)), "model": raw["model"],
            "description": str(raw.get("description", "")), "data": str(raw.get("data", "")),
            "parameters": dict(raw["parameters"]),
            "uncertainty": dict(raw.get("uncertainty", {})),
            "misfit": dict(raw.get("misfit", {})),
            "identifiability": dict(raw.get("identifiability", {})),
            "path": str(path.resolve()), "sha256": hashlib.sha256(data).hexdigest()}


def apply_scene_calibration(raw: dict, base_dir, schema) -> tuple[dict, dict]:
    """A scene dict with the values of its scene calibration file applied.

    The scene names the file in its top-level key ``calibration``; the file's ``model`` must be
    ``"scene"`` and each key of its ``[parameters]`` a numeric scene key ``"section.key"``
    (``"sandstone.beta"``, ``"models.patchy_cement.delta"``) of ``schema`` whose section the
    scene has (a model section only if the scene uses that model). A key the scene sets as
    well is an error: remove one of them.

    Returns
    -------
    (dict, dict)
        The scene dict with the values set, and the calibration record
        (:func:`load_calibration`).
    """
    name = raw["calibration"]
    if not isinstance(name, str):
        raise ValueError(f"scene key calibration must be a string (a file); got {name!r}")
    try:
        cal = load_calibration(name, base_dir=base_dir)
    except ValueError as exc:
        raise ValueError(f"scene key calibration: {exc}") from None
    if cal["model"] != "scene":
        raise ValueError(f"scene key calibration: {cal['name']!r} calibrates model "
                         f"{cal['model']!r}; name it in [models.{cal['model']}] calibration")
    out = {k: (dict(v) if isinstance(v, dict) else v) for k, v in raw.items()}
    models = raw.get("models", {})
    out["models"] = {k: dict(v) if isinstance(v, dict) else v for k, v in models.items()} \
        if isinstance(models, dict) else models
    for dotted, value in cal["parameters"].items():
        section, _, key = dotted.rpartition(".")
        if section not in schema or key not in schema[section] \
                or schema[section][key][1] != "number":
            raise ValueError(f"scene key calibration: parameter {dotted!r} of {cal['name']!r} "
                             "is not a numeric scene key 'section.key'")
        if section.startswith("models."):
            label = section.removeprefix("models.")
            if label not in out["models"]:
                raise ValueError(f"scene key calibration: parameter {dotted!r} of "
                                 f"{cal['name']!r}: the scene has no model {label!r}")
            table = out["models"][label]
        else:
            table = out.setdefault(section, {})
        if key in table:
            raise ValueError(f"scene key {dotted} is also set by calibration {cal['name']!r}; "
                             "remove one of them")
        table[key] = value
    out.pop("calibration")
    return out, cal
