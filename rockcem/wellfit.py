r"""Fitting a scene to a well: numeric scene keys by least squares against well logs.

:func:`fit_scene` runs the scene, reduced to what the fitted logs need (the outputs ``vp``,
``vs``, ``density``, ``porosity`` that the well has, and only the one model that ``vp``/``vs``
come from), at trial values of the free keys, takes the model at the log's depths (linear
between scene depths) and fits with :func:`rockcem.calibrate.fit_parameters`. What the free
keys cannot change is computed once and shared by every trial: with only model parameters
free the whole rock state (burial path, kinetics, compaction, density); with compaction keys
(:data:`_COMPACTION_KEYS`) the path and the quartz-cement kinetics; with no path key the
path (a history table is read once). The result gives values, one-sigma uncertainties, their
correlation, the misfit before and after, parameters on a bound, and parameters the logs do not
determine; :meth:`SceneFit.write_calibration` writes a scene calibration file (``model =
"scene"``) that any scene applies with its top-level key ``calibration = "<file>"``.

The residuals are the misfits of :func:`rockcem.wells.well_misfit` (``compare``), from the same
function: relative, :math:`m/o - 1`, for vp, vs and density; absolute, :math:`m - o`, for
porosity, a fraction (:data:`rockcem.wells.MISFIT`: near 0 porosity a ratio blows up); the
misfits reported are their root-mean-square values.

Uncertainties are the linearised ones of :func:`rockcem.calibrate.fit_parameters`,
:math:`s^2 (J^T W J)^{-1}`. With ``errors`` (the logs' standard deviations) they are absolute.
Without, each log is weighted by its own scatter: a first fit on the misfits
:math:`(m - o)/c_v(o)`, with :math:`c_v(o) = o` (relative) or 1 (porosity), gives the model
:math:`m^{(1)}` and the scatter :math:`s_v = \mathrm{rms}((o - m^{(1)})/c_v(m^{(1)}))` of every
log :math:`v` (:math:`\mathrm{rms}(o/m^{(1)} - 1)` of a relative one); the fit is repeated from
there with residuals :math:`(m - o)/(s_v c_v(m^{(1)}))` (two-stage feasible weighted least
squares, [Carroll1988]_ ch. 2). One variance pooled over logs of different scatter (a porosity
log at 15 % beside a sonic log at 2 %) would widen the uncertainties of the parameters that
only the sonic logs constrain by the ratio of the scatters; and weights taken from the noisy
log itself (:math:`m/o - 1`) bias the model low by about :math:`2 s_v^2` (0.1 % of Vp at 2 %
scatter), which hundreds of samples turn into most of a standard error. Weights from the
first model have neither fault. The covariance is then the robust (sandwich) one of
[White1980]_, which stays right where the scatter is not the fixed fraction (for porosity, the
fixed amount) of the log that the weights assume, as for a sonic log noisier at depth, where
:math:`s^2 (J^T W J)^{-1}` was 1.5-fold off (for parameters found unidentifiable the usual one
is kept, whose correlations show it). Either way the
samples are taken as independent: residuals of a real log are correlated over the tool's
vertical resolution and over the depths a model misses, so that the standard errors are then
lower bounds (fitting every n-th sample, or the logs averaged over intervals, tests it).

A parameter is reported *unidentifiable* when its standard error is infinite or wider than its
bounds, or when it is correlated with another by :math:`|r| > 0.999`: the logs then fix at
best a combination of parameters.

By default the fit uses the logs that the free keys can change: with only model parameters
free (``models.*``) that is ``vp`` and ``vs``, since density and porosity do not depend on the
elastic model.

A scene with ``[uncertain]`` is fitted as one scene: its uncertain keys that are not free are
held at their medians (the scene's nominal values). With ``prior=True`` the distributions of
the free keys that are uncertain are their priors, and the fit is a maximum a posteriori (MAP)
estimate (the posterior density is proportional to the likelihood times the priors, and its
maximum minimises minus their logarithm; with Gaussian data errors this is the least-squares
problem of [Tarantola2005]_ sect. 3.2, pp. 62-70, with the normal prior there replaced by
:math:`p_k`): it minimises

.. math:: S(\theta) = \tfrac12 \sum_v \sum_i \left(\frac{m_{vi}(\theta) - o_{vi}}{\sigma_v}
          \right)^2 - \sum_k \ln p_k(\theta_k)

over each prior's range, the data term that of independent Gaussian errors of standard
deviation :math:`\sigma_v` per log (``errors``, required: they weigh the logs against the
priors), :math:`p_k` the density of key :math:`k`'s distribution truncated to its valid range
(the truncation adds a constant), a free key without a prior flat within its bounds. It is
solved as least squares on the residuals of the data and, per prior, the residual
:math:`r_k = \mathrm{sign}(\theta_k - \hat\theta_k)\sqrt{2[\ln p_k(\hat\theta_k) -
\ln p_k(\theta_k)]}` with :math:`\hat\theta_k` the prior's mode, so that
:math:`\tfrac12 r_k^2` is the prior's term up to a constant (for a normal prior,
:math:`r_k = (\theta_k - \mu_k)/s_k`). The bounds of a key with a prior are its prior's
range: the valid range it was truncated to, within the distribution's support, an infinite
end replaced by the truncated prior's :math:`10^{-12}` quantile. The uncertainties are
:math:`(J^T J)^{-1}` of those residuals at the estimate (Gauss-Newton): the posterior
covariance where the model is linear in the parameters and the priors normal
(:math:`(G^T C_D^{-1} G + C_M^{-1})^{-1}`, [Tarantola2005]_ sect. 3.2-3.3); for other priors an approximation that leaves out the second
derivative of the signed root (near the end of a triangular prior it understates how fast the
prior falls, and overstates the error).

References
----------
.. [Tarantola2005] Tarantola, A. (2005). *Inverse Problem Theory and Methods for Model
   Parameter Estimation*. SIAM, ch. 3.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from ._identifiability import CORRELATION_LIMIT as _CORRELATION_LIMIT
from ._identifiability import correlation as _correlation
from ._identifiability import unidentifiable as _shared_unidentifiable
from ._well_misfit import MISFIT, _misfit, _misfit_scale, _relative
from .wells import WELL_VARIABLES

__all__ = ["DEFAULT_BOUNDS", "SceneFit", "fit_scene"]

#: Bounds of keys that may be freed without giving them: the physical or plausible range.
DEFAULT_BOUNDS = {
    "path.gradient": (10.0, 80.0),
    "path.sedimentation_rate": (1.0, 2000.0),
    "path.surface_temperature": (-5.0, 40.0),
    "sandstone.porosity0": (0.2, 0.5),
    "sandstone.grain_size": (0.01, 5.0),
    "sandstone.quartz_fraction": (0.01, 1.0),
    "sandstone.clay_coating": (0.0, 0.99),
    "sandstone.igv_final": (0.05, 0.35),
    "sandstone.beta": (1e-4, 0.1),
    "shale.porosity0": (0.2, 0.8),
    "shale.beta": (1e-4, 0.1),
    "models.patchy_cement.coordination_number": (4.0, 16.0),
    "models.patchy_cement.contact_cement_limit": (0.005, 0.2),
    "models.patchy_cement.delta": (0.0, 500.0),
    "models.patchy_cement.thickness": (0.0, 0.5),
    "models.patchy_cement.f": (0.0, 1.0),
    "models.hs_gassmann.A": (1.0, 8.0),
    "models.generalized_gassmann.A": (1.0, 8.0),
    "models.self_consistent.aspect_ratio": (0.01, 1.0),
}
#: Keys that change compaction but not the quartz-cement kinetics (which depend on the path,
#: porosity0, grain size, quartz fraction, clay coating and start temperature only).
_COMPACTION_KEYS = ("sandstone.beta", "sandstone.igv_final", "pressure.sediment_density",
                    "pressure.water_density")
#: Correlation beyond which two parameters are reported as not separately determined (the rule
#: of :func:`rockcem.calibrate.unidentifiable`, shared with :mod:`md.calibrate`).
CORRELATION_LIMIT = _CORRELATION_LIMIT


@dataclass(frozen=True)
class SceneFit:
    """Outcome of :func:`fit_scene`.

    Attributes
    ----------
    result : rockcem.calibrate.FitResult
        Values, standard errors, covariance, chi2, dof; ``misfit`` (before: ``misfit_initial``),
        the rms misfit of each log as :func:`rockcem.wells.well_misfit` measures it.
    scene, fitted : Scene
        The reduced scene at the starting and at the fitted values.
    model : str or None
        The model ``vp``/``vs`` were fitted with.
    variables : tuple of str
        The logs fitted.
    depth_range : (float, float)
        Depth window of the fit, m.
    points : dict
        Number of log samples fitted per variable.
    correlation : ndarray, shape (p, p)
        Correlation of the parameters (order of ``result.values``).
    unidentifiable : tuple of str
        Parameters the logs do not determine (see the module docstring).
    well_source : str
        The well file.
    weights : str
        How the residuals were weighted.
    priors : dict
        With ``prior=True``: ``{key: the prior, in words}`` of the free keys with a prior (the
        fit is then a maximum a posteriori estimate).
    held : dict
        The scene's uncertain keys that were not free: ``{key: median}``, the value they were
        held at.
    """

    result: object
    scene: object
    fitted: object
    model: str | None
    variables: tuple
    depth_range: tuple
    points: dict
    correlation: np.ndarray = field(repr=False)
    unidentifiable: tuple = ()
    well_source: str = ""
    weights: str = "relative residuals"
    priors: dict = field(default_factory=dict)
    held: dict = field(default_factory=dict)

    @property
    def at_bound(self) -> tuple:
        """Parameters that ended on a bound (their standard error understates the doubt)."""
        return tuple(k for k, v in self.result.at_bound.items() if v)

    def summary(self) -> str:
        """A readable report: values ± errors, flags, correlation and misfit."""
        r = self.result
        lines = [f"fit of {self.scene.name} to {self.well_source or 'the well'}: "
                 f"{', '.join(self.variables)}"
                 + (f" (model {self.model})" if self.model else "")
                 + f", {self.depth_range[0]:g}-{self.depth_range[1]:g} m, "
                 + ", ".join(f"{v} {n}" for v, n in self.points.items()) + " samples"]
        for k, v in r.values.items():
            flags = [f for f, on in (("at bound", k in self.at_bound),
                                     ("UNIDENTIFIABLE", k in self.unidentifiable)) if on]
            lines.append(f"  {k} = {v:.6g} +- {r.stderr[k]:.3g}"
                         + (f"  [{', '.join(flags)}]" if flags else ""))
        names = list(r.values)
        for i in range(len(names)):
            for j in range(i + 1, len(names)):
                lines.append(f"  correlation {names[i]} / {names[j]}: "
                             f"{self.correlation[i, j]:+.3f}")
        how = "relative misfit" if all(map(_relative, r.misfit)) else \
            "misfit (" + "; ".join(f"{v} {MISFIT[v]}" for v in r.misfit) + ")"
        lines.append(f"  rms {how}: " + ", ".join(
            f"{v} {r.misfit_initial[v]:.4f} -> {r.misfit[v]:.4f}" for v in r.misfit))
        if self.priors:
            lines.append("  maximum a posteriori with priors " + "; ".join(
                f"{k} {v}" for k, v in self.priors.items()) + " (chi2 includes their terms)")
        if self.held:
            lines.append("  uncertain keys held at their medians: " + ", ".join(
                f"{k} = {v:.6g}" for k, v in self.held.items()))
        lines.append(f"  chi2 {r.chi2:.4g}, dof {r.dof}, converged {r.success}")
        return "\n".join(lines)

    def write_calibration(self, path, *, name=None, description=""):
        """Write the fitted values as a scene calibration file (``model = "scene"``).

        Returns
        -------
        pathlib.Path
        """
        from .calibrate import write_calibration

        r = self.result
        record = {"scene": self.scene.name, "model": self.model or "", "variables":
                  list(self.variables), "depth_top": float(self.depth_range[0]),
                  "depth_base": float(self.depth_range[1]), "chi2": r.chi2, "dof": r.dof,
                  "success": r.success, "at_bound": list(self.at_bound),
                  "unidentifiable": list(self.unidentifiable),
                  "correlation": [[float(c) for c in row] for row in self.correlation],
                  "initial": [float(self.scene.sections[k.rpartition(".")[0]]
                                    [k.rpartition(".")[2]]) for k in r.values]}
        return write_calibration(
            path, name=name or f"{self.scene.name}_well_fit", model="scene",
            parameters=dict(r.values), uncertainty=dict(r.stderr), misfit=dict(r.misfit),
            description=description or f"scene {self.scene.name} fitted to well logs",
            data=f"well {self.well_source}: {', '.join(self.variables)} at "
                 f"{self.depth_range[0]:g}-{self.depth_range[1]:g} m",
            weights=self.weights, references="", record=record)


def _free(scene, free):
    """``{key: (initial, lower, upper)}`` from keys, ``{key: (lo, hi)}`` or triples."""
    from .histories import KIND_KEYS
    from .scene import SCHEMA

    items = free.items() if isinstance(free, dict) else [(k, None) for k in free]
    out = {}
    for key, given in items:
        section, _, name = key.rpartition(".")
        if section not in scene.sections or name not in scene.sections[section]:
            raise ValueError(f"free parameter {key!r} is not a key of this scene (keys are "
                             "'section.key', e.g. 'sandstone.beta' or "
                             "'models.patchy_cement.delta')")
        if SCHEMA[section][name][1] != "number":
            raise ValueError(f"free parameter {key!r} is not numeric")
        kind = scene.sections["path"]["kind"]
        if section == "path" and name not in KIND_KEYS[kind]:
            raise ValueError(f"free parameter {key!r} does not apply to a path of kind "
                             f"{kind!r}")
        for label, cal in scene.calibrations.items():
            param = key if label == "scene" else name
            if (label == "scene" or section == f"models.{label}") \
                    and param in cal["parameters"]:
                raise ValueError(f"free parameter {key!r} is set by calibration "
                                 f"{cal['name']!r}; remove it from the scene to fit it")
        current = scene.sections[section][name]
        if given is None:
            if key not in DEFAULT_BOUNDS:
                raise ValueError(f"free parameter {key!r} has no default bounds; give them "
                                 f"({key}=LOWER:UPPER)")
            given = DEFAULT_BOUNDS[key]
        given = tuple(float(v) for v in given)
        if len(given) == 2:
            if current is None:
                raise ValueError(f"free parameter {key!r} has no value in the scene; give a "
                                 "start (initial, lower, upper)")
            lo, hi = given
            start = min(max(float(current), lo), hi)
            given = (start, lo, hi)
        if len(given) != 3 or not given[1] <= given[0] <= given[2] or given[1] >= given[2]:
            raise ValueError(f"free parameter {key!r}: need lower < upper and the start "
                             f"within them; got {given}")
        out[key] = given
    if not out:
        raise ValueError("no free parameter given")
    return out


def _reduced(scene, well, variables, model, *, models_only=False):
    """The scene computing only what the fit needs; the variables and the model.

    With ``models_only`` (only model parameters free) the default logs are the model outputs
    (density and porosity do not depend on them)."""
    from .scene import MODEL_OUTPUTS, scene_from_dict

    if scene.sweep:
        raise ValueError("fit a scene without [sweep]")
    can = [v for v in WELL_VARIABLES if v in well.data_vars
           and (v not in MODEL_OUTPUTS or scene.models)]
    if variables is None:
        variables = [v for v in can if v in MODEL_OUTPUTS] if models_only else can
        if not variables and models_only:
            raise ValueError("the free keys are model parameters, but the well has no vp or "
                             "vs log (density and porosity do not depend on them)")
    missing = [v for v in variables if v not in can]
    if missing:
        raise ValueError(f"cannot fit {missing[0]!r}: the well and the scene share "
                         f"{', '.join(can) or 'no log'}")
    if not variables:
        raise ValueError("the well has no log the scene models (vp, vs, density, porosity)")
    raw = scene._raw()
    # One scene is fitted: each uncertain key at its median (the scene's nominal value) until
    # the fit sets it; [uncertain] would refuse a fitted key set beside it.
    for dotted in (scene.uncertain or {}).get("keys", {}):
        section, _, key = dotted.rpartition(".")
        table = raw.setdefault("models", {}).setdefault(section[7:], {}) \
            if section.startswith("models.") else raw.setdefault(section, {})
        table[key] = scene.sections[section][key]
    raw.pop("uncertain", None)
    needs_model = any(v in MODEL_OUTPUTS for v in variables)
    if needs_model:
        if model is None:
            if len(scene.models) != 1:
                raise ValueError(f"the scene has models {', '.join(scene.models)}: name the "
                                 "one to fit vp/vs with (model=...)")
            model = scene.models[0]
        if model not in scene.models:
            raise ValueError(f"model {model!r} is not in the scene ({', '.join(scene.models)})")
        if model == "md":
            raise ValueError("the MD backend takes minutes per evaluation and cannot be fitted; "
                             "fit one of the other models (model=...)")
        raw["models"] = {model: raw.get("models", {}).get(model, {})}
    else:
        model = None
        raw.pop("models", None)
    raw["outputs"] = list(variables)
    raw.pop("sweep", None)
    return scene_from_dict(raw, base_dir=scene.base_dir), tuple(variables), model


#: How far inside an infinite end of a prior's range its bound is put: the truncated prior's
#: quantile at this probability from that end.
_PRIOR_TAIL = 1e-12
#: Largest prior term :math:`\ln p(\hat\theta) - \ln p(\theta)` a residual carries: where the
#: density is 0 (the ends of a triangular prior) the term would be infinite.
_PRIOR_CAP = 700.0


def _prior(entry):
    r"""An uncertain key's distribution (an entry of ``scene.uncertain["keys"]``) as a prior of
    :func:`fit_scene`: ``(residual, (lower, upper), text)``, with ``residual(x)`` the signed
    root :math:`\mathrm{sign}(x - \hat x)\sqrt{2[\ln p(\hat x) - \ln p(x)]}` (module
    docstring), :math:`\hat x` the mode of the truncated distribution (for the uniform, whose
    residual is 0, its lower end), and the bounds its range within the distribution's
    support."""
    from ._uncertain import _frozen

    dist = entry["distribution"]
    frozen = _frozen(dist, entry)
    low, high, low_open, high_open = entry["range"]
    support = frozen.support()
    a, b = max(float(low), float(support[0])), min(float(high), float(support[1]))
    c_lo, c_hi = entry["cdf_range"]
    # An infinite end: the tail quantile; an open one: the next number inside.
    lo = float(frozen.ppf(c_lo + _PRIOR_TAIL * (c_hi - c_lo))) if not np.isfinite(a) else \
        float(np.nextafter(a, np.inf)) if low_open and a == low else a
    hi = float(frozen.isf(1.0 - c_hi + _PRIOR_TAIL * (c_hi - c_lo))) if not np.isfinite(b) else \
        float(np.nextafter(b, -np.inf)) if high_open and b == high else b
    mode = {"normal": lambda: entry.get("mean"),
            "lognormal": lambda: entry["median"] * np.exp(-entry["sigma"] ** 2),
            "triangular": lambda: entry.get("mode"), "uniform": lambda: lo}[dist]()
    mode = min(max(float(mode), lo), hi)
    top = float(frozen.logpdf(mode))
    params = ", ".join(f"{k} {entry[k]:g}" for k in ("mean", "sd", "median", "sigma", "lower",
                                                     "mode", "upper") if k in entry)
    # The bounds as a range: "(0, 80.8]" for an open end, the tail quantile for an infinite one.
    left = f"({a:.6g}" if np.isfinite(a) and lo != a else f"[{lo:.6g}"
    right = f"{b:.6g})" if np.isfinite(b) and hi != b else f"{hi:.6g}]"
    text = f"{dist}({params}) on {left}, {right}"

    def residual(x):
        if dist == "uniform":
            return 0.0
        with np.errstate(divide="ignore"):          # log 0 at a triangle's ends: capped
            drop = min(max(top - float(frozen.logpdf(x)), 0.0), _PRIOR_CAP)
        return float(np.sign(x - mode) * np.sqrt(2.0 * drop))

    return residual, (lo, hi), text


def _with_priors(scene, free, errors):
    """The free keys with the priors of those that are uncertain in ``scene``: the free keys
    as :func:`_free` takes them, each with a prior given its prior's bounds (start at the
    scene's median), and ``{key: (residual, text)}``."""
    spec = (scene.uncertain or {}).get("keys", {})
    items = dict(free) if isinstance(free, dict) else dict.fromkeys(free)
    names = [k for k in items if k in spec]
    if not names:
        raise ValueError(f"prior: none of the free parameters ({', '.join(items) or 'none'}) "
                         "is uncertain in the scene (its [uncertain] keys: "
                         f"{', '.join(spec) or 'none'})")
    if errors is None:
        raise ValueError("prior: give errors, the standard deviation of each fitted log "
                         "(e.g. vp=0.05): they weigh the logs against the priors")
    priors = {}
    for key in names:
        residual, (lo, hi), text = _prior(spec[key])
        if items[key] is not None:
            raise ValueError(f"free parameter {key!r} takes its bounds from its prior "
                             f"({lo:.6g} to {hi:.6g}); give it without bounds")
        section, _, name = key.rpartition(".")
        items[key] = (min(max(float(scene.sections[section][name]), lo), hi), lo, hi)
        priors[key] = (residual, text)
    return items, priors


def _rock_state(scene):
    """The cached rock state of a scene's pipeline (everything but the models)."""
    from .runner import _Pipeline

    pipe = _Pipeline(scene)
    for name in ("path", "pressures", "materials", "porosity", "solid_fractions", "density"):
        getattr(pipe, name)                          # cached_property: computed and kept
    return {k: v for k, v in pipe.__dict__.items() if k not in ("scene", "sec", "lith")}


def _sandwich_covariance(predict, observed, errors, values, params):
    r"""Heteroscedasticity-consistent covariance of least-squares parameters, [White1980]_
    (HC1): :math:`C = \frac{N}{N-p} B^{-1} (J^T \mathrm{diag}(r^2) J) B^{-1}`,
    :math:`B = J^T J`, with :math:`r` the weighted residuals :math:`(m - o)/\sigma` at the
    solution and :math:`J` their Jacobian (central differences, one-sided at a bound). It
    holds whatever the true scatter of each sample, where :math:`s^2 B^{-1}` holds only if the
    weights :math:`1/\sigma` are right up to one factor.

    Returns
    -------
    ndarray, shape (p, p)
        ``inf`` on the diagonal where :math:`B` is singular.
    """
    names = list(values)
    x = np.array([values[k] for k in names], dtype=float)

    def weighted(xv):
        pred = predict(**dict(zip(names, xv)))
        return np.concatenate([(np.asarray(pred[v]) - observed[v]) / errors[v]
                               for v in observed])

    r = weighted(x)
    J = np.empty((r.size, x.size))
    for j, k in enumerate(names):
        lo, hi = params[k][1], params[k][2]
        h = 1e-6 * max(abs(x[j]), 1e-3 * (hi - lo))
        up, down = x.copy(), x.copy()
        up[j], down[j] = min(x[j] + h, hi), max(x[j] - h, lo)
        J[:, j] = (weighted(up) - weighted(down)) / (up[j] - down[j])
    n, p = J.shape
    try:
        bread = np.linalg.inv(J.T @ J)
    except np.linalg.LinAlgError:
        return np.diag(np.full(p, np.inf))
    return bread @ ((J * r[:, None] ** 2).T @ J) @ bread * n / max(n - p, 1)


def fit_scene(scene, well, free, *, model=None, variables=None, depth=None, errors=None,
              prior=False):
    """Fit numeric scene keys to well logs by least squares, or with the scene's
    distributions as priors by a maximum a posteriori estimate (module docstring).

    Parameters
    ----------
    scene : Scene or str
        A scene (or a scene file / shipped name), without a sweep.
    well : xarray.Dataset or str
        Logs from :func:`rockcem.wells.read_well`, or a file for it.
    free : sequence of str or mapping
        Keys ``"section.key"`` to fit: a list (bounds from :data:`DEFAULT_BOUNDS`, start at
        the scene's value), or ``{key: (lower, upper)}`` or ``{key: (initial, lower, upper)}``.
    model : str, optional, keyword-only
        The model ``vp``/``vs`` come from; needed when the scene has several.
    variables : sequence of str, optional, keyword-only
        Logs to fit; default every one of ``vp``, ``vs``, ``density``, ``porosity`` both have
        that the free keys can change (``vp`` and ``vs`` only when all are ``models.*``).
    depth : (float, float), optional, keyword-only
        Depth window, m; default the depths both cover.
    errors : mapping, optional, keyword-only
        ``{variable: standard deviation}`` of the logs in their units (km/s, g/cm³, fraction):
        residuals weighted by them and uncertainties taken as absolute. Default: the misfits
        of :func:`rockcem.wells.well_misfit` (relative; absolute for porosity), each log
        weighted by its own scatter (module docstring).
    prior : bool, optional, keyword-only
        Take the distributions of the scene's ``[uncertain]`` keys that are free as their
        priors and their ranges as their bounds (such keys are given without bounds); needs
        ``errors`` (the noise model: independent Gaussian errors of those standard deviations)
        and at least one free key that is uncertain. The fit is then the maximum a posteriori
        estimate, its uncertainties those of the Gauss-Newton approximation (module docstring).

    Returns
    -------
    SceneFit

    Examples
    --------
    A porosity log made from the sandstone at an initial porosity of 0.36, fitted with the
    prior normal(0.40, 0.002), as tight as the log's constraint, lands about half way:

    >>> import numpy as np
    >>> from rockcem.scene import load_scene, run_scene, scene_from_dict
    >>> from rockcem.synthetic_well import synthetic_well
    >>> scene = load_scene("carcione2022_sandstone").replace(**{"path.depth_step": 100.0})
    >>> truth = run_scene(scene)
    >>> well = synthetic_well(truth, np.arange(300.0, 1500.0, 100.0),
    ...                       sigma={"porosity": 0.005})
    >>> raw = scene._raw()
    >>> del raw["sandstone"]["porosity0"]
    >>> raw["uncertain"] = {"samples": 10, "sandstone.porosity0": {
    ...     "distribution": "normal", "mean": 0.40, "sd": 0.002}}
    >>> fit = fit_scene(scene_from_dict(raw), well, ["sandstone.porosity0"],
    ...                 variables=["porosity"], errors={"porosity": 0.005}, prior=True)
    >>> 0.37 < fit.result.values["sandstone.porosity0"] < 0.39
    True
    """
    from .calibrate import fit_parameters
    from .runner import _Pipeline
    from .scene import MODEL_OUTPUTS, Scene, load_scene
    from .wells import read_well

    if not isinstance(scene, Scene):
        scene = load_scene(scene)
    source = str(well.attrs.get("source_file", "")) if hasattr(well, "data_vars") else str(well)
    if not hasattr(well, "data_vars"):
        well = read_well(well)
    priors = {}
    if prior:
        free, priors = _with_priors(scene, free, errors)
    params = _free(scene, free)
    held = {k: scene.sections[k.rpartition(".")[0]][k.rpartition(".")[2]]
            for k in (scene.uncertain or {}).get("keys", {}) if k not in params}
    models_only = all(k.startswith("models.") for k in params)
    reduced, variables, model = _reduced(scene, well, variables, model,
                                         models_only=models_only)
    for key in params:
        if key.rpartition(".")[0] not in reduced.sections:
            raise ValueError(f"free parameter {key!r} belongs to a model the fitted logs "
                             f"({', '.join(variables)}) do not use")
    # With model parameters only free, the rock state (burial path, kinetics, compaction,
    # density) is the same for every trial: computed once and handed to each trial's pipeline;
    # with no path key free, the burial path (a history table read once) is.
    start = _Pipeline(reduced)
    scene_depth = start.now(start.path.depth)
    if models_only:
        rock = _rock_state(reduced)
    elif not any(k.startswith("path.") for k in params):
        shared = ("path", "history")
        if all(k in _COMPACTION_KEYS or k.startswith("models.") for k in params) \
                and reduced.lithology == "sandstone":
            start.quartz                                  # the kinetics, computed once
            shared += ("quartz",)
        rock = {k: v for k, v in start.__dict__.items() if k in shared}
    else:
        rock = {}
    lo = max(float(scene_depth.min()), float(well.depth.min()))
    hi = min(float(scene_depth.max()), float(well.depth.max()))
    if depth is not None:
        top, bottom = (float(d) for d in depth)
        if not top < bottom:
            raise ValueError(f"depth window must be TOP < BASE; got {top:g} {bottom:g}")
        lo, hi = max(lo, top), min(hi, bottom)
    if not lo < hi:
        raise ValueError("the well, the scene and the depth window share no depth range")
    z = well.depth.values
    inside = (z >= lo) & (z <= hi)
    masks = {v: inside & np.isfinite(well[v].values) for v in variables}
    points = {v: int(m.sum()) for v, m in masks.items()}
    short = [v for v, n in points.items() if n < 2]
    if short:
        raise ValueError(f"log {short[0]} has {points[short[0]]} samples in {lo:g}-{hi:g} m")
    observed = {v: well[v].values[masks[v]] for v in variables}
    for v, values in observed.items():        # porosity's misfit is absolute: any value
        if _relative(v) and np.any(values <= 0.0):
            at = float(z[masks[v]][np.flatnonzero(values <= 0.0)[0]])
            raise ValueError(f"log {v} is {values[values <= 0.0][0]:g} at {at:g} m; the fit "
                             "needs positive values (its misfit is relative): narrow the "
                             "depth window or leave that log out")

    def trial(values):
        """The reduced scene at trial values, set without validating the whole scene again
        (which would re-read a history table at every trial): the scene schema checks only
        that a value is a finite number, and the burial and model functions check their own
        ranges. The fitted scene is validated (``reduced.replace``)."""
        sections = dict(reduced.sections)
        for key, value in values.items():
            section, _, name = key.rpartition(".")
            sections[section] = {**sections[section], name: float(value)}
        return dataclasses.replace(reduced, sections=sections)

    def predict(**values):
        pipe = _Pipeline(trial(values))
        pipe.__dict__.update(rock)
        depth = pipe.now(pipe.path.depth)
        out = {}
        for v in variables:
            arr = getattr(pipe.model(model), v) if v in MODEL_OUTPUTS else \
                pipe.state_variable(v)
            out[v] = np.interp(z[masks[v]], depth, arr)
        return out

    sigma = None if errors is None else {v: errors[v] for v in variables if v in errors}
    if sigma is not None and set(sigma) != set(variables):
        raise ValueError(f"errors must give a standard deviation for each fitted log: "
                         f"{', '.join(variables)}")
    x0 = {k: p[0] for k, p in params.items()}
    initial = predict(**x0)                 # computed once, for the misfit before

    def predict_from_start(**values):
        return initial if values == x0 else predict(**values)

    how = "relative" if all(map(_relative, variables)) else \
        "misfits " + ", ".join(f"{v} {MISFIT[v]}" for v in variables)
    # Without errors the residuals are well_misfit's, (m - o)/scale, their variance fitted.
    scale = sigma or {v: _misfit_scale(v, observed[v]) for v in variables}
    if priors:
        result = _posterior_fit(predict_from_start, observed, params, sigma, priors)
    else:
        result = fit_parameters(predict_from_start, observed, params, errors=scale,
                                absolute_errors=sigma is not None)
    weights = ("relative residuals" if how == "relative" else how) if sigma is None else \
        "absolute errors " + ", ".join(f"{k} {v:g}" for k, v in sigma.items())
    if priors:
        weights += ("; maximum a posteriori with priors " + "; ".join(
            f"{k} {text}" for k, (_, text) in priors.items()))
    if sigma is None:
        # Second stage (module docstring): errors s_v c_v(m_v) from the first solution m_v.
        first = result
        model_at = {v: np.asarray(first.predicted[v], dtype=float) for v in variables}
        scale = {v: _misfit_scale(v, model_at[v]) for v in variables}
        scatter = _rms_misfit(observed, model_at)         # of the logs about the first fit
        if all(scatter[v] > 0.0 and np.all(scale[v] > 0.0) for v in variables):
            again = {k: (min(max(first.values[k], lo), hi), lo, hi)
                     for k, (_, lo, hi) in params.items()}
            errors = {v: scatter[v] * scale[v] for v in variables}
            result = fit_parameters(predict, observed, again, errors=errors)
            weights = (how + ": each log weighted by its own scatter about the first fit ("
                       + ", ".join(f"{v} {scatter[v]:.3%}" if _relative(v) else
                                   f"{v} {scatter[v]:.3g}" for v in variables) + ")")
            if not _unidentifiable(result, params):       # else: the usual diagnostics
                cov = _sandwich_covariance(predict, observed, errors, result.values, params)
                result = dataclasses.replace(result, covariance=cov, stderr={
                    k: float(np.sqrt(max(cov[i, i], 0.0))) for i, k in enumerate(result.values)})
                weights += "; robust (sandwich) covariance"
    # The misfits as well_misfit gives them (fit_parameters reports relative ones).
    result = dataclasses.replace(result, misfit=_rms_misfit(result.predicted, observed),
                                 misfit_initial=_rms_misfit(initial, observed))
    bad = _unidentifiable(result, params)
    return SceneFit(result, reduced, reduced.replace(**result.values), model, variables,
                    (lo, hi), points, _correlation(result), bad, source, weights,
                    {k: text for k, (_, text) in priors.items()}, held)


def _posterior_fit(predict, observed, params, sigma, priors):
    r"""The maximum a posteriori estimate of the module docstring: least squares on the data's
    residuals :math:`(m - o)/\sigma` and one residual per prior (:func:`_prior`), its
    covariance :math:`(J^T J)^{-1}` of them all (absolute errors). ``chi2`` is twice the
    objective (the priors' terms counted from their modes); ``misfit`` and ``predicted`` are
    the logs'."""
    from .calibrate import fit_parameters

    labels = {f"prior {k}": k for k in priors}

    def augmented(**values):
        out = dict(predict(**values))
        for label, key in labels.items():
            out[label] = np.array([priors[key][0](values[key])])
        return out

    result = fit_parameters(augmented, {**observed, **dict.fromkeys(labels, np.zeros(1))},
                            params, errors={**sigma, **dict.fromkeys(labels, 1.0)},
                            absolute_errors=True)
    return dataclasses.replace(
        result, predicted={v: result.predicted[v] for v in observed},
        misfit={v: result.misfit[v] for v in observed},
        misfit_initial={v: result.misfit_initial[v] for v in observed})


def _rms_misfit(model, log):
    """Root-mean-square misfit of ``model`` to ``log``, ``{variable: array}``, as
    :func:`rockcem.wells.well_misfit` measures it."""
    return {v: float(np.sqrt(np.mean(_misfit(np.asarray(model[v], dtype=float), o, v) ** 2)))
            for v, o in log.items()}


def _unidentifiable(result, params):
    """Parameters whose standard error is not finite or wider than their bounds, or that
    correlate with another beyond :data:`CORRELATION_LIMIT`
    (:func:`rockcem.calibrate.unidentifiable`)."""
    return _shared_unidentifiable(result, params, correlation_limit=CORRELATION_LIMIT)
