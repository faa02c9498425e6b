r"""Calibrate effective-medium models against MD results, and with the same routine against
measurements.

Layering: this module is the one place where :mod:`md` meets :mod:`rockcem`. md's engine modules
never import rockcem; this one imports it (and xarray) only inside its functions, so
``import md`` stays light. The fit itself is :func:`rockcem.calibrate.fit_parameters` (least
squares on relative or error-weighted residuals, standard errors from the Jacobian); this module
turns a Dataset into the predictor and the observations it needs, one fit per group, and the
results back into a Dataset. Units are those of rockcem's API: moduli GPa, density g/cm³,
velocity km/s, pressure MPa, fractions (the MD results of :func:`md.experiment.run_md_scene` are
already in them; md's SI materials are converted here).

Models (:data:`MODELS` lists each parameter with its default, starting value, bounds and unit):

``contact_cement``
    The contact cement theory (CCT) of Dvorkin & Nur, eq. 15 of [Carcione2022]_ and eq. A1 of
    [GarciaMedina2007]_, with the cement radius of scheme 1 (cement at the contacts, eq. 16 of
    [Carcione2022]_, eq. A3 second line of [GarciaMedina2007]_) or scheme 2 (coating, eq. 18,
    eq. A3 first line), and with a contact thickness :math:`\varepsilon > 0` the MCCT of
    [HanGuo]_ (eq. 7; eq. A-9 of [Xu2023]_): :func:`rockcem.granular.contact_cement`. Free
    parameters: ``coordination_number`` :math:`n`, ``thickness`` :math:`\varepsilon` and
    ``cement_efficiency`` :math:`\eta`, the fraction of the cement volume the theory sees as
    contact cement (the cement radius follows from :math:`\phi_c - \phi_\eta` with
    :math:`\phi_\eta = \phi_c - \eta(\phi_c - \phi)`; the pack term :math:`1 - \phi_c` is
    unchanged). Points without cement are left out of these fits: the theory describes cemented
    contacts only (at zero cement it gives the small stiffness of its :math:`C` terms).
``patchy_cement``
    The dry frame of Model 4 of [Carcione2022]_ (eqs. 15–21, D.1–D.2): cemented patches by CCT,
    uncemented ones by Hertz–Mindlin at the effective pressure plus the bonding pre-stress
    :math:`\delta`, joined by the HS upper bound, then interpolated to the mineral
    (:func:`rockcem.granular.patchy_cement`; the cement fraction is :math:`\phi_c - \phi`).
    Free parameters: ``coordination_number``, ``thickness``, ``delta`` (MPa),
    ``contact_cement_limit`` :math:`\phi_{p0}` and ``f`` (no-slip fraction).

The data: an ``xarray.Dataset`` with the observed quantities, any of ``vp``, ``vs`` (km/s),
``K``, ``G`` (GPa), and the rock state: ``porosity`` (after cementation, fraction) and
``density`` (g/cm³, needed for velocities); optionally ``porosity_uncemented`` (the critical
porosity :math:`\phi_c`; or an attribute ``critical_porosity``), ``coordination_number``
(used where :math:`n` is held), ``stress`` or ``pressure_effective`` (MPa, patchy cement),
``<name>_error`` (one-sigma errors of an observed quantity, e.g. the eq. 11 errors ``vp_error``
of the pulse test, used as weights), and for bonded-contact results a coordinate
``radius_ratio`` (:math:`a/R`, used as the cement radius :math:`\alpha` directly) with an
optional ``thickness_ratio`` (used as :math:`\varepsilon` where it is held). Grain and cement
moduli come from the arguments or from attributes ``grain_K``, ``grain_G``, ``cement_K``,
``cement_G`` (GPa; densities ``grain_rho``, ``cement_rho`` optional).

:func:`calibrate` returns the fits as a Dataset, with each fitted parameter flagged
``unidentifiable`` where the data do not determine it; :func:`calibrate_identified` fits, holds
the flagged parameters it is allowed to hold and fits the rest again; :func:`total_error`
combines the eq. 11 and resolution errors of an MD study into the weights;
:func:`write_calibration` writes one parameter set as a calibration file (TOML, format
``rockcem-calibration/1``, described in ``datasets/calibrations/README.md``) that scenes read
with ``[models.patchy_cement] calibration = "<file or shipped name>"``.
"""

from __future__ import annotations

import datetime
import itertools
import json

import numpy as np

__all__ = ["MODELS", "calibrate", "calibrate_identified", "total_error", "as_mineral",
           "write_calibration"]

from ._calibrate_groups import (MODELS, _OBSERVABLES, _REFERENCES,  # noqa: E402, F401
                                _fit_group, _Group, _inputs, _largest_n, as_mineral)
from ._calibrate_file import write_calibration  # noqa: E402


def calibrate(data, model="contact_cement", *, free=("coordination_number",), fixed=None,
              grain=None, cement=None, scheme=1, observed=None, errors="auto",
              absolute_errors=False, each=None, critical_porosity=None, pressure=None,
              stiffness="fit"):
    r"""Fit effective-medium parameters to MD results or measurements by least squares.

    One fit per combination of the ``each`` dimensions (e.g. per MD sample, cement and
    cementation scheme), over the remaining (point) dimensions (e.g. cement saturation
    :math:`S_c`), with :func:`rockcem.calibrate.fit_parameters`: relative residuals
    :math:`p/o - 1`, or :math:`(p - o)/\sigma` where errors :math:`\sigma` are used.

    Parameters
    ----------
    data : xarray.Dataset
        Observations and rock state; see the module docstring for the variables it may hold.
    model : {"contact_cement", "patchy_cement"}
        The effective-medium model (see the module docstring and :data:`MODELS`).
    free : sequence of str or mapping, keyword-only
        The parameters to fit: names (start and bounds from :data:`MODELS`; :math:`n` starts
        from the data's coordination number if there is one), or ``{name: (initial, lower,
        upper)}``. Default: the coordination number.
    fixed : mapping, optional, keyword-only
        Values of held parameters (over the data's and the defaults of :data:`MODELS`).
    grain, cement : Mineral, md.GrainMaterial or md.CementMaterial, optional, keyword-only
        Materials; default from the data's attributes (module docstring).
    scheme : {1, 2}, keyword-only
        Cement radius of scheme 1 (at the contacts) or 2 (coating).
    observed : sequence of str, optional, keyword-only
        Quantities to fit among ``vp``, ``vs`` (km/s), ``K``, ``G`` (GPa); default all of
        these the data holds.
    errors : "auto", None or mapping, keyword-only
        ``"auto"``: weight by the data's ``<name>_error`` when there is one for every observed
        quantity (the eq. 11 errors of the pulse test), else relative residuals; ``None``:
        relative residuals; ``{name: variable}``: those error variables (units of the
        observation, ``> 0``).
    absolute_errors : bool, keyword-only
        Take the errors as true standard deviations (see
        :func:`rockcem.calibrate.fit_parameters`); default: scale by the residual variance.
    each : sequence of str, optional, keyword-only
        Dimensions to fit separately. Default: every dimension of the observations but
        ``saturation`` when there is one; otherwise one joint fit over all points.
    critical_porosity : float, optional, keyword-only
        :math:`\phi_c`, in (0, 1); default the data's ``porosity_uncemented``, else its
        attribute ``critical_porosity``, else (bonded-contact data) its ``porosity``.
    pressure : float, optional, keyword-only
        Effective pressure for ``patchy_cement``, MPa, ``>= 0``; default the data's
        ``stress`` or ``pressure_effective``.
    stiffness : {"fit", "integral"}, keyword-only
        Contact stiffnesses of :func:`rockcem.granular.contact_cement` (``contact_cement``
        only; ``patchy_cement`` uses the handbook fit).

    Returns
    -------
    xarray.Dataset
        Over the ``each`` dimensions: ``value`` and ``stderr`` (dimension ``parameter``, every
        parameter of the model, with ``parameter_units``; the error of a held one is 0),
        ``fitted`` (per parameter), ``at_bound``, ``unidentifiable`` (the data do not
        determine the fitted value: :func:`rockcem.calibrate.unidentifiable` with the test
        against the value's magnitude, so an error infinite, wider than the bounds or than
        the value, or a correlation beyond 0.999; false where held), ``covariance`` and
        ``correlation`` (``cov_i`` × ``cov_j``, the free parameters), ``misfit`` and
        ``misfit_initial`` (root-mean-square relative misfit per ``observed`` quantity, at
        the solution and the start), ``chi2``, ``dof``,
        ``n_points``, ``success``; over the data's dimensions each observation, its
        prediction ``<name>_model`` (NaN where the rock state is incomplete), its error
        ``<name>_error`` where used, and ``used`` (points in the fit). Attributes name the
        model, scheme, materials, held values, weights and the data.

    Raises
    ------
    ValueError
        For an unknown model or parameter, bounds that do not hold the start, missing data
        variables, too few points, or rock states out of the model's range.

    Examples
    --------
    Synthetic CCT velocities with :math:`n = 7` are fitted back:

    >>> import numpy as np, xarray as xr
    >>> from rockcem.granular import contact_cement
    >>> from rockcem.materials import mineral
    >>> q, c = mineral("quartz_garcia_medina"), mineral("hard_cement")
    >>> phi = 0.38 * (1 - np.array([0.02, 0.05, 0.1, 0.2]))
    >>> m = contact_cement(q.K, q.G, c.K, c.G, phi, 0.38, 7.0)
    >>> rho = 2.65 * 0.62 + 2.65 * (0.38 - phi)
    >>> ds = xr.Dataset({"vp": ("saturation", np.sqrt((m.K + 4 / 3 * m.G) / rho)),
    ...                  "porosity": ("saturation", phi), "density": ("saturation", rho)},
    ...                 attrs={"critical_porosity": 0.38})
    >>> fit = calibrate(ds, grain=q, cement=c)
    >>> round(float(fit.value.sel(parameter="coordination_number")), 6)
    7.0
    """
    import xarray as xr

    from rockcem.calibrate import correlation, unidentifiable

    inp = _inputs(data, model, free, fixed, grain, cement, scheme, observed, errors,
                  critical_porosity, pressure, stiffness)
    table, obs = MODELS[model], inp["obs"]
    ref = xr.broadcast(*[data[k] for k in obs])[0]
    dims = ref.dims
    if each is None:
        each = tuple(d for d in dims if d != "saturation") if "saturation" in dims else ()
    each = (each,) if isinstance(each, str) else tuple(each)
    if any(d not in dims for d in each):
        raise ValueError(f"each must name dimensions of the observations {dims}; got {each}")
    points = tuple(d for d in dims if d not in each)
    names = list(table)
    free_names = [k for k in names if k in inp["free"]]
    rows, sources = [], {}
    for idx in itertools.product(*(range(data.sizes[d]) for d in each)):
        sub = data.isel(dict(zip(each, idx)))
        g = _Group(sub, obs, points, model, phic=inp["phic"][0], pressure=inp["press"],
                   errors=inp["errors"], radius=inp["radius"])
        where = ", ".join(f"{d}={data[d][i].item()!r}" for d, i in zip(each, idx)) \
            or "all points"
        n_used = int(g.used.sum())
        if n_used == 0 or n_used * len(obs) < len(free_names):
            raise ValueError(f"{where}: {n_used} usable points cannot fit {free_names}")
        held = {}
        for k in names:
            if k in free_names:
                continue
            src = "fixed" if k in inp["fixed"] else "data" if k in g.data_values else "default"
            held[k] = {"fixed": inp["fixed"].get(k), "data": g.data_values.get(k),
                       "default": table[k][0]}[src]
            sources[k] = src
        spec = {}
        for k in free_names:
            lo, hi = table[k][2], table[k][3]
            start = float(np.mean(g.data_values[k][g.used])) if k in g.data_values else \
                table[k][1]
            x0, lo, hi = inp["free"][k] or (min(max(start, lo), hi), lo, hi)
            hi_given = hi
            if k == "coordination_number":
                # The models accept n up to rockcem.granular.MAX_COORDINATION_NUMBER: a wider
                # bound would let the fit step where they refuse.
                from rockcem.granular import MAX_COORDINATION_NUMBER

                hi = min(hi, MAX_COORDINATION_NUMBER)
                if not hi > lo:
                    raise ValueError(f"coordination_number: the lower bound {lo:g} leaves no "
                                     f"room below the models' largest n, "
                                     f"{MAX_COORDINATION_NUMBER:g}")
                if hi < hi_given and hi < x0 <= hi_given:
                    x0 = hi
            if k == "coordination_number" and inp["radius"] and model == "contact_cement" \
                    and scheme == 1 and "thickness" not in free_names:
                # Bonded data give the cement radius: above this n the cement would not fit
                # in the pore space (eq. 7 of [HanGuo]_ gives a negative porosity).
                hi = min(hi, 0.999 * _largest_n(g, held["thickness"]))
                if not hi > lo:
                    raise ValueError(f"{where}: the cement radii of the data leave no "
                                     f"coordination number above {lo:g} with porosity >= 0")
                if hi < hi_given and hi < x0 <= hi_given:
                    x0 = hi
            spec[k] = (x0, lo, hi)
        fit, pred = _fit_group(g, model, spec, held, inp, scheme, stiffness, absolute_errors,
                               where)
        bad = unidentifiable(fit, spec, relative=True)
        rows.append({
            "value": [fit.values[k] if k in fit.values
                      else float(np.mean(np.asarray(held[k])[g.used] if np.ndim(held[k])
                                         else held[k])) for k in names],
            "stderr": [fit.stderr.get(k, 0.0) for k in names],
            "at_bound": [fit.at_bound.get(k, False) for k in names],
            "unidentifiable": [k in bad for k in names],
            "covariance": fit.covariance, "correlation": correlation(fit),
            "misfit": [fit.misfit[k] for k in obs],
            "misfit_initial": [fit.misfit_initial[k] for k in obs],
            "chi2": fit.chi2, "dof": fit.dof, "n_points": n_used, "success": fit.success,
            "used": g.used.reshape([data.sizes[d] for d in points]),
            **{f"{k}_model": pred[k].reshape([data.sizes[d] for d in points]) for k in obs},
        })
    shape = tuple(data.sizes[d] for d in each)

    def stack(key):
        return np.reshape(np.array([r[key] for r in rows]), shape + np.shape(rows[0][key]))

    E = each
    out = xr.Dataset(
        {
            "value": (E + ("parameter",), stack("value"),
                      {"long_name": "parameter value (fitted, or held where fitted is false)"}),
            "stderr": (E + ("parameter",), stack("stderr"),
                       {"long_name": "one-standard-deviation error (0 where held)"}),
            "fitted": (("parameter",), np.array([k in free_names for k in names])),
            "at_bound": (E + ("parameter",), stack("at_bound"),
                         {"long_name": "fitted value on a bound (its error is understated)"}),
            "unidentifiable": (E + ("parameter",), stack("unidentifiable"),
                               {"long_name": "the data do not determine the fitted value "
                                             "(rockcem.calibrate.unidentifiable, relative)"}),
            "covariance": (E + ("cov_i", "cov_j"), stack("covariance")),
            "correlation": (E + ("cov_i", "cov_j"), stack("correlation"),
                            {"units": "1", "long_name": "correlation of the free parameters"}),
            "misfit": (E + ("observed",), stack("misfit"),
                       {"units": "1", "long_name": "root-mean-square relative misfit"}),
            "misfit_initial": (E + ("observed",), stack("misfit_initial"),
                               {"units": "1", "long_name": "the same at the start"}),
            "chi2": (E, stack("chi2"), {"long_name": "sum of squared residuals"}),
            "dof": (E, stack("dof"), {"long_name": "residuals minus free parameters"}),
            "n_points": (E, stack("n_points"), {"long_name": "points in the fit"}),
            "success": (E, stack("success")),
            "used": (E + points, stack("used"), {"long_name": "point entered the fit"}),
            **{f"{k}_model": (E + points, stack(f"{k}_model"),
                              {"units": _OBSERVABLES[k], "long_name": f"{k} of the model"})
               for k in obs},
        },
        coords={**{d: data[d] for d in dims if d in data.coords},
                **{k: c for k, c in data.coords.items() if c.ndim == 0},
                "parameter": names,
                "parameter_units": ("parameter", [table[k][4] for k in names]),
                "cov_i": free_names, "cov_j": free_names, "observed": obs},
    )
    for k in obs:
        out[k] = data[k].broadcast_like(ref)
        if inp["errors"]:
            out[f"{k}_error"] = data[inp["errors"][k]].broadcast_like(ref)
    out = out.transpose(*dims, ...)
    out.attrs.update(_attrs(data, model, scheme, stiffness, inp, free_names, sources,
                            absolute_errors))
    return out


def total_error(data, name="vp"):
    r"""The error of an MD velocity for weighting a fit: the eq. 11 error of the pulse test
    combined in quadrature with the resolution error where the study has one.

    :math:`\sigma = \sqrt{\sigma_{11}^2 + \sigma_\Omega^2}`, with :math:`\sigma_{11}` the
    variable ``<name>_error`` (eq. 11 of [GarciaMedina2007]_, the arrival-time error for
    :math:`\Delta L = R`) and :math:`\sigma_\Omega` the variable ``<name>_error_resolution``
    (first-order Richardson estimate of the distance to the :math:`\Omega \to \infty` limit,
    written by :func:`md.experiment.run_md_scene` with ``resolution_check``; 0 for the
    uncemented pack, which has no cement lattice). The two are taken as independent: the
    first is the timing of one pulse, the second the discretisation of the cement. A NaN in
    either gives a NaN, which leaves the point out of a fit (:func:`calibrate` uses only
    points with a finite positive error). Without ``<name>_error_resolution``, the eq. 11
    error alone.

    Parameters
    ----------
    data : xarray.Dataset
        An MD scene's output (:func:`md.experiment.run_md_scene`).
    name : str
        The velocity, ``"vp"`` or ``"vs"`` (km/s).

    Returns
    -------
    xarray.DataArray
        km/s, the dimensions of ``<name>_error``.
    """
    if f"{name}_error" not in data.variables:
        raise ValueError(f"data needs a variable {name}_error (the eq. 11 error) for "
                         f"name={name!r}")
    err = data[f"{name}_error"]
    res = data.get(f"{name}_error_resolution")
    total = err if res is None else np.hypot(err, res)
    how = "eq. 11" if res is None else "eq. 11 and resolution errors in quadrature"
    return total.rename(f"{name}_error_total").assign_attrs(
        units=err.attrs.get("units", "km s-1"), long_name=f"error of {name}: {how}")


def calibrate_identified(data, model="patchy_cement", *, free, hold, reason="", **options):
    r"""One fit by :func:`calibrate`, then the parameters the data do not determine held and
    the rest fitted again.

    The first fit frees every parameter of ``free``. Those it flags ``unidentifiable`` (see
    :func:`calibrate`: an infinite standard error, one wider than the bounds or than the
    value, or a correlation beyond 0.999) that ``hold`` names are held at the values ``hold``
    gives, and the others are fitted again; a flagged parameter ``hold`` does not name stays
    free and stays flagged. The first fit is kept for the record in the attribute
    ``identifiability_json`` (free parameters, values, errors, correlation, chi2, the flagged
    and the held ones, ``reason``), which :func:`write_calibration` writes as the table
    ``[identifiability]``.

    Parameters
    ----------
    data : xarray.Dataset
        As for :func:`calibrate`, reduced to one fit (select one label of each dimension but
        the point dimension, e.g. ``ds.sel(sample="compacted", cement="hard",
        scheme="contact")``).
    model : {"contact_cement", "patchy_cement"}
    free : sequence of str or mapping, keyword-only
        As for :func:`calibrate`, at least two parameters.
    hold : mapping, keyword-only
        ``{name: value}``: the free parameters that may be held if unidentifiable, and their
        values, within the bounds of :data:`MODELS` (units of :data:`MODELS`).
    reason : str, keyword-only
        Why those values (recorded).
    **options
        Passed to :func:`calibrate` (``fixed`` among them: merged with the held values).

    Returns
    -------
    xarray.Dataset
        The final fit, as :func:`calibrate` returns it, with ``identifiability_json``.

    Raises
    ------
    ValueError
        If the data give more than one fit, ``hold`` names a parameter that is not free or a
        value out of bounds, or every free parameter would be held.
    """
    first = calibrate(data, model, free=free, **options)
    if first["value"].dims != ("parameter",):
        raise ValueError("calibrate_identified needs data of one fit: select one label of "
                         f"{', '.join(d for d in first['value'].dims if d != 'parameter')}")
    free_names = [str(k) for k in first.cov_i.values]
    table = MODELS[model]
    for k, v in hold.items():
        if k not in free_names:
            raise ValueError(f"hold names {k!r}, which is not free (free: {free_names})")
        if not isinstance(v, (int, float, np.integer, np.floating)) \
                or not table[k][2] <= v <= table[k][3]:
            raise ValueError(f"hold[{k!r}] must be a number in [{table[k][2]:g}, "
                             f"{table[k][3]:g}]; got {v!r}")
    flagged = [k for k in free_names if bool(first.unidentifiable.sel(parameter=k))]
    held = {k: float(hold[k]) for k in flagged if k in hold}
    rest = [k for k in free_names if k not in held]
    if held and not rest:
        raise ValueError(f"every free parameter {free_names} is unidentifiable and held: "
                         "nothing is left to fit")
    final = first
    if held:
        spec = ({k: free[k] for k in rest} if isinstance(free, dict) else rest)
        final = calibrate(data, model, free=spec,
                          **{**options, "fixed": {**(options.get("fixed") or {}), **held}})
    corr = first.correlation.values
    final.attrs["identifiability_json"] = json.dumps({
        "free": free_names, "unidentifiable": flagged, "held": held, "reason": reason,
        "values": {k: float(first.value.sel(parameter=k)) for k in free_names},
        "stderr": {k: float(first.stderr.sel(parameter=k)) for k in free_names},
        "correlation": {f"{a}/{b}": float(corr[i, j]) for i, a in enumerate(free_names)
                        for j, b in enumerate(free_names) if j > i},
        "chi2": float(first.chi2), "dof": int(first.dof)})
    return final


def _attrs(data, model, scheme, stiffness, inp, free_names, sources, absolute_errors):
    import rockcem
    from rockcem.references import REFERENCES

    now = datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds")
    described = data.attrs.get("title") or data.attrs.get("scene_name") or "data"
    err = inp["errors"]
    weights = ("error-weighted residuals (p - o)/sigma, sigma = " + ", ".join(err.values())
               + (" (absolute)" if absolute_errors else " (scaled by the residual variance)")
               if err else "relative residuals p/o - 1")
    grain, cement = inp["grain"], inp["cement"]
    return {
        "Conventions": "CF-1.10",
        "title": f"calibration of {model} (scheme {scheme}) against {described}",
        "calibration_model": model, "scheme": int(scheme), "stiffness": stiffness,
        "free_parameters": " ".join(free_names),
        "held_json": json.dumps({k: {"source": s, **({"value": inp["fixed"][k]}
                                                    if s == "fixed" else {})}
                                 for k, s in sources.items()}),
        "weights": weights, "critical_porosity_source": inp["phic"][1],
        "grain": grain.name, "grain_K": grain.K, "grain_G": grain.G, "grain_rho": grain.rho,
        "cement": cement.name, "cement_K": cement.K, "cement_G": cement.G,
        "cement_rho": cement.rho,
        "data": str(described),
        "source": f"md.calibrate (rockcem {rockcem.__version__})",
        "history": f"{now} created by md.calibrate.calibrate",
        "references": "\n".join(f"[{k}] {REFERENCES[k]}" for k in _REFERENCES[model]),
    }
