"""The calibration file of one fit of :func:`md.calibrate.calibrate` (private module; the
public name is :func:`md.calibrate.write_calibration`)."""

from __future__ import annotations

import json
from pathlib import Path


def write_calibration(fit, path, *, name=None, description="", **selection) -> Path:
    """Write one fitted parameter set of :func:`md.calibrate.calibrate` as a calibration file
    for scenes.

    The file (TOML, format ``rockcem-calibration/1``, :func:`rockcem.calibrate.write_calibration`;
    see ``datasets/calibrations/README.md``) lists in ``[parameters]`` every model parameter
    the fit used, fitted or held, and the cement-radius ``scheme`` (``cement_efficiency`` is
    left out when held at 1, where it does nothing); the errors of the fitted ones, the misfit
    and what the fit was made on (``[fit]``, with the unidentifiable parameters) are kept for
    the record, and for a fit of :func:`md.calibrate.calibrate_identified` the first fit and
    what was held (``[identifiability]``).

    Parameters
    ----------
    fit : xarray.Dataset
        From :func:`md.calibrate.calibrate`.
    path : str or Path
        File to write (``.toml``).
    name : str, optional, keyword-only
        Name of the calibration; default the file's stem.
    description : str, keyword-only
        Free text.
    **selection
        Labels selecting one fit, e.g. ``sample="compacted", cement="hard",
        scheme="contact"``: one for every dimension of ``value`` but ``parameter``.

    Returns
    -------
    Path
    """
    from rockcem.calibrate import IDENTIFIABILITY_RULE
    from rockcem.calibrate import write_calibration as write

    if "calibration_model" not in fit.attrs or "value" not in fit:
        raise ValueError("fit must be a Dataset returned by md.calibrate.calibrate")
    try:
        one = fit.sel(selection) if selection else fit
    except (KeyError, ValueError) as exc:
        raise ValueError(f"selection {selection} does not match the fit's labels: {exc}") \
            from None
    left = [d for d in one["value"].dims if d != "parameter"]
    if left:
        raise ValueError(f"select one fit: give a label for {', '.join(left)} "
                         f"(e.g. {left[0]}={one[left[0]].values[0].item()!r})")
    path = Path(path)
    fitted = {str(k): bool(f) for k, f in zip(one.parameter.values, one.fitted.values)}
    params = {k: float(one.value.sel(parameter=k)) for k in fitted}
    if not fitted.get("cement_efficiency", True) and params["cement_efficiency"] == 1.0:
        del params["cement_efficiency"]
    params["scheme"] = int(fit.attrs["scheme"])
    # The labels of this fit: those selected here, or the data's own scalar coordinates.
    labels = {**{str(k): c.item() for k, c in one.coords.items() if c.ndim == 0},
              **selection}
    where = ", ".join(f"{k} = {v}" for k, v in labels.items())
    ident = json.loads(fit.attrs.get("identifiability_json", "null"))
    held_why = {k: "held: unidentifiable" for k in (ident or {}).get("held", {})}
    record = {
        "grain": fit.attrs["grain"], "grain_K": fit.attrs["grain_K"],
        "grain_G": fit.attrs["grain_G"], "cement": fit.attrs["cement"],
        "cement_K": fit.attrs["cement_K"], "cement_G": fit.attrs["cement_G"],
        "critical_porosity_source": fit.attrs["critical_porosity_source"],
        "held": [f"{k} ({held_why.get(k, v['source'])})"
                 for k, v in json.loads(fit.attrs["held_json"]).items()],
        "points": int(one.n_points), "chi2": float(one.chi2),
        "dof": int(one.dof), "success": bool(one.success),
        "at_bound": [k for k, f in fitted.items() if f and bool(one.at_bound.sel(parameter=k))],
        "unidentifiable": [k for k, f in fitted.items()
                           if f and bool(one.unidentifiable.sel(parameter=k))],
    }
    identifiability = None
    if ident is not None:
        identifiability = {
            "rule": IDENTIFIABILITY_RULE,
            "free": ident["free"], "unidentifiable": ident["unidentifiable"],
            "held": list(ident["held"]), "reason": ident["reason"],
            **{f"first_fit_{k}": v for k, v in ident["values"].items()},
            **{f"first_fit_{k}_err": v for k, v in ident["stderr"].items()},
            **{f"correlation_{k.replace('/', '_')}": v
               for k, v in ident["correlation"].items()},
            "first_fit_chi2": ident["chi2"], "first_fit_dof": ident["dof"]}
    return write(path, name=name or path.stem, model=fit.attrs["calibration_model"],
                 parameters=params,
                 uncertainty={k: float(one.stderr.sel(parameter=k)) for k, f in fitted.items()
                              if f},
                 misfit={str(k): float(v) for k, v in zip(one.observed.values,
                                                           one.misfit.values)},
                 description=description,
                 data=fit.attrs["data"] + (f" ({where})" if where else ""),
                 weights=fit.attrs["weights"],
                 references=fit.attrs["references"].replace("\n", "; "), record=record,
                 identifiability=identifiability)
