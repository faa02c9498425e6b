"""Private helpers of :mod:`md.calibrate`: the model table, the data of one fit group and
its predictor (imports rockcem only inside functions)."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np


#: Parameters of each model: ``{name: (held default, start, lower, upper, unit, description)}``.
#: A held parameter takes the value in ``fixed``, else the data's (``coordination_number``,
#: ``thickness_ratio``), else the default; a free one starts from the data's value or ``start``.
MODELS: dict[str, dict[str, tuple]] = {
    "contact_cement": {
        "coordination_number": (9.0, 9.0, 2.0, 20.0, "1", "coordination number n"),
        "thickness": (0.0, 0.01, 0.0, 0.2, "1",
                      "MCCT contact thickness epsilon (half the axial gap over R)"),
        "cement_efficiency": (1.0, 0.5, 1e-3, 1.0, "1",
                              "fraction of the cement volume that is contact cement"),
    },
    "patchy_cement": {
        "coordination_number": (9.0, 9.0, 2.0, 20.0, "1", "coordination number n"),
        "thickness": (0.0, 0.01, 0.0, 0.2, "1",
                      "MCCT contact thickness epsilon (half the axial gap over R)"),
        "delta": (0.0, 10.0, 0.0, 500.0, "MPa", "bonding pre-stress delta"),
        "contact_cement_limit": (0.05, 0.05, 1e-3, 0.4, "1",
                                 "phi_p0, the most cement that sits at contacts"),
        "f": (1.0, 0.5, 0.0, 1.0, "1", "Hertz-Mindlin no-slip fraction"),
    },
}

_OBSERVABLES = {"vp": "km s-1", "vs": "km s-1", "K": "GPa", "G": "GPa"}
_REFERENCES = {"contact_cement": ["DvorkinNur1996", "Mavko2009", "HanGuo", "Xu2023",
                                  "GarciaMedina2007"],
               "patchy_cement": ["Carcione2022", "Avseth2016", "DvorkinNur1996", "Walton1987",
                                 "GangiCarlson1996", "HanGuo", "GarciaMedina2007"]}


def as_mineral(material, name=""):
    """A :class:`rockcem.materials.Mineral` (GPa, g/cm³) from a Mineral or an md material.

    Parameters
    ----------
    material : Mineral, md.GrainMaterial or md.CementMaterial
        md's materials are in SI (Pa, m/s, kg/m³) and are converted.
    name : str
        Label of the result when converting.

    Returns
    -------
    Mineral
    """
    from rockcem.materials import Mineral

    from .cement import CementMaterial
    from .contact import GrainMaterial

    if isinstance(material, Mineral):
        return material
    if isinstance(material, GrainMaterial):
        return Mineral.from_poisson(material.shear_modulus / 1e9, material.poisson_ratio,
                                    material.density / 1e3, name, "md.GrainMaterial")
    if isinstance(material, CementMaterial):
        return Mineral.from_velocities(material.vp / 1e3, material.vs / 1e3,
                                       material.density / 1e3, name, "md.CementMaterial")
    raise ValueError(f"{name or 'material'} must be a rockcem Mineral, md.GrainMaterial or "
                     f"md.CementMaterial; got {type(material).__name__}")


def _attrs_mineral(data, which):
    from rockcem.materials import Mineral

    keys = [f"{which}_K", f"{which}_G"]
    if not all(k in data.attrs for k in keys):
        raise ValueError(f"{which} is required: give a Mineral or md material, or attributes "
                         f"{keys[0]}, {keys[1]} (GPa) on the data")
    return Mineral(float(data.attrs[keys[0]]), float(data.attrs[keys[1]]),
                   float(data.attrs.get(f"{which}_rho", 2.65)), which, "data attributes")


def _free_spec(model, free):
    table = MODELS[model]
    if free is None:
        return {}
    if isinstance(free, str):
        free = [free]
    items = free.items() if isinstance(free, Mapping) else [(k, None) for k in free]
    spec = {}
    for name, bounds in items:
        if name not in table:
            raise ValueError(f"free parameter {name!r} is not a parameter of model {model!r} "
                             f"(valid: {', '.join(table)})")
        spec[name] = None if bounds is None else tuple(float(b) for b in bounds)
        if bounds is not None and len(spec[name]) != 3:
            raise ValueError(f"free[{name!r}] must be (initial, lower, upper); got {bounds!r}")
    return spec


def _flat(sub, name, ref, point_dims):
    """Variable or coordinate ``name`` of a group, broadcast to the observed grid, flattened."""
    var = sub[name]
    extra = [d for d in var.dims if d not in ref.dims]
    if extra:
        raise ValueError(f"data variable {name!r} has dimensions {extra} that the observed "
                         f"quantities do not have")
    return np.asarray(var.broadcast_like(ref).transpose(*point_dims).values, dtype=float).ravel()


class _Group:
    """The rock state and observations of one fit, flattened over the point dimensions.

    ``valid`` marks points with a complete rock state (the model is evaluated there, NaN
    elsewhere); ``used`` the valid points with usable observations that enter the fit.
    """

    def __init__(self, sub, obs_names, point_dims, model, *, phic, pressure, errors,
                 radius):
        ref = sub[obs_names[0]]
        self.obs = {k: _flat(sub, k, ref, point_dims) for k in obs_names}
        self.err = ({k: _flat(sub, v, ref, point_dims) for k, v in errors.items()}
                    if errors else None)
        porosity = _flat(sub, "porosity", ref, point_dims)
        self.size = porosity.size
        state = {"porosity": porosity,
                 "phic": (_flat(sub, phic, ref, point_dims) if isinstance(phic, str)
                          else np.full(self.size, float(phic)))}
        if {"vp", "vs"} & set(obs_names):
            state["density"] = _flat(sub, "density", ref, point_dims)
        if pressure is not None:
            state["pressure"] = (_flat(sub, pressure, ref, point_dims)
                                 if isinstance(pressure, str) else np.full(self.size, pressure))
        if radius:
            state["alpha"] = _flat(sub, "radius_ratio", ref, point_dims)
        self.data_values = {}
        if "coordination_number" in sub.variables:
            self.data_values["coordination_number"] = _flat(sub, "coordination_number", ref,
                                                            point_dims)
        if radius and "thickness_ratio" in sub.variables:
            self.data_values["thickness"] = _flat(sub, "thickness_ratio", ref, point_dims)
        self.valid = np.ones(self.size, dtype=bool)
        for v in (*state.values(), *self.data_values.values()):
            self.valid &= np.isfinite(v)
        self.state = {k: v[self.valid] for k, v in state.items()}
        ok = self.valid.copy()
        for k in obs_names:
            ok &= np.isfinite(self.obs[k]) & (self.obs[k] > 0)
            if self.err is not None:
                ok &= np.isfinite(self.err[k]) & (self.err[k] > 0)
        if model == "contact_cement":
            with np.errstate(invalid="ignore"):
                cement = state["alpha"] if radius else state["phic"] - state["porosity"]
                ok &= cement > 1e-12
        self.used = ok


def _largest_n(group, thickness):
    """The largest coordination number for which the bonded data's cement radii fit in their
    pore space (porosity >= 0 in eq. 7 of [HanGuo]_ inverted), over the group's used points."""
    st, use = group.state, group.used[group.valid]
    eps = np.asarray(thickness, dtype=float)
    eps = eps[group.valid][use] if eps.ndim else eps
    a, phic = st["alpha"][use], st["phic"][use]
    return float(np.min(phic / ((1.0 - phic) * 0.75 * a**2 * (0.25 * a**2 + eps))))


def _predictor(model, group, grain, cement, scheme, stiffness, held, obs_names):
    """``predict(**free) -> {name: array over all points}`` (NaN where the state is not valid).

    ``held`` values are scalars or arrays over all points."""
    from rockcem.elastic import velocities
    from rockcem.granular import cement_porosity, contact_cement, patchy_cement

    g, st = group, group.state
    held = {k: (v[g.valid] if np.ndim(v) else v) for k, v in held.items()}

    def predict(**free):
        p = {**held, **free}
        n, eps, phic = p["coordination_number"], p["thickness"], st["phic"]
        if model == "contact_cement":
            if "alpha" in st:
                phi = cement_porosity(st["alpha"], phic, n, scheme, eps)
            else:
                phi = phic - p["cement_efficiency"] * (phic - st["porosity"])
            m = contact_cement(grain.K, grain.G, cement.K, cement.G, phi, phic, n, scheme, eps,
                               stiffness=stiffness)
        else:
            m = patchy_cement(grain.K, grain.G, cement.K, cement.G, st["porosity"], phic, n,
                              st["pressure"], phic - st["porosity"], p["contact_cement_limit"],
                              scheme, eps, p["f"], p["delta"])
        out = {"K": m.K, "G": m.G}
        if "density" in st:
            v = velocities(m.K, m.G, st["density"])
            out.update(vp=v.vp, vs=v.vs)
        result = {}
        for k in obs_names:
            full = np.full(g.size, np.nan)
            full[g.valid] = np.broadcast_to(out[k], (int(g.valid.sum()),))
            result[k] = full
        return result

    return predict


def _inputs(data, model, free, fixed, grain, cement, scheme, observed, errors,
            critical_porosity, pressure, stiffness):
    """Check the arguments of :func:`calibrate` against the data; resolve the defaults."""
    import xarray as xr

    if model not in MODELS:
        raise ValueError(f"model must be one of {', '.join(MODELS)}; got {model!r}")
    if scheme not in (1, 2):
        raise ValueError(f"scheme must be 1 (contact cement) or 2 (coating); got {scheme!r}")
    if stiffness not in ("fit", "integral"):
        raise ValueError(f"stiffness must be 'fit' or 'integral'; got {stiffness!r}")
    if not isinstance(data, xr.Dataset):
        raise ValueError(f"data must be an xarray.Dataset; got {type(data).__name__}")
    free = _free_spec(model, free)
    if not free:
        raise ValueError("free must name at least one parameter to fit")
    fixed = dict(fixed or {})
    for k, v in fixed.items():
        if not isinstance(v, (int, float, np.integer, np.floating)) or not np.isfinite(v):
            raise ValueError(f"fixed[{k!r}] must be a finite number; got {v!r}")
        if k not in MODELS[model] or k in free:
            raise ValueError(f"fixed parameter {k!r} is free or not a parameter of model "
                             f"{model!r} (valid: {', '.join(MODELS[model])})")
    radius = "radius_ratio" in data.variables
    if radius and (model != "contact_cement" or "cement_efficiency" in free):
        raise ValueError("bonded-contact data (radius_ratio: the cement radius is given) can be "
                         "fitted with model 'contact_cement' and no cement_efficiency only")
    obs = list(observed) if observed is not None else [k for k in _OBSERVABLES
                                                        if k in data.data_vars]
    if not obs or any(k not in _OBSERVABLES or k not in data.data_vars for k in obs):
        raise ValueError(f"observed must name variables of the data among "
                         f"{', '.join(_OBSERVABLES)}; got {obs or 'none'}")
    for k in ("porosity",) + (("density",) if {"vp", "vs"} & set(obs) else ()):
        if k not in data.variables:
            raise ValueError(f"data needs a variable {k!r}")
    if errors == "auto":
        errors = {k: f"{k}_error" for k in obs}
        errors = errors if all(v in data.variables for v in errors.values()) else None
    elif isinstance(errors, Mapping):
        errors = dict(errors)
        if set(errors) != set(obs) or any(v not in data.variables for v in errors.values()):
            raise ValueError(f"errors must map each observed quantity {obs} to an error "
                             f"variable of the data; got {errors}")
    elif errors is not None:
        raise ValueError(f"errors must be 'auto', None or a mapping; got {errors!r}")
    number = (int, float, np.integer, np.floating)
    for name, v in (("critical_porosity", critical_porosity), ("pressure", pressure)):
        if v is not None and (not isinstance(v, number) or not np.isfinite(v)):
            raise ValueError(f"{name} must be a finite number; got {v!r}")
    if critical_porosity is not None:
        if not 0.0 < float(critical_porosity) < 1.0:
            raise ValueError(f"critical_porosity must lie in (0, 1); got {critical_porosity!r}")
        phic = (float(critical_porosity), "argument critical_porosity")
    elif "porosity_uncemented" in data.variables:
        phic = ("porosity_uncemented", "data variable porosity_uncemented")
    elif "critical_porosity" in data.attrs:
        phic = (float(data.attrs["critical_porosity"]), "data attribute critical_porosity")
    elif radius:
        phic = ("porosity", "data variable porosity (bonded contacts: the pack's)")
    else:
        raise ValueError("critical_porosity is required: give it, or a data variable "
                         "porosity_uncemented, or a data attribute critical_porosity")
    press = None
    if model == "patchy_cement":
        press = pressure if pressure is not None else next(
            (k for k in ("stress", "pressure_effective") if k in data.variables), None)
        if press is None:
            raise ValueError("pressure is required for patchy_cement: give it (MPa) or a data "
                             "variable stress or pressure_effective")
        if not isinstance(press, str) and not press >= 0:
            raise ValueError(f"pressure must be >= 0 MPa; got {pressure!r}")
    grain = as_mineral(grain, "grain") if grain is not None else _attrs_mineral(data, "grain")
    cement = (as_mineral(cement, "cement") if cement is not None
              else _attrs_mineral(data, "cement"))
    return dict(free=free, fixed=fixed, radius=radius, obs=obs, errors=errors, phic=phic,
                press=press, grain=grain, cement=cement)


def _fit_group(g, model, spec, held, inp, scheme, stiffness, absolute_errors, where):
    """Fit one group; the FitResult and the prediction at every point."""
    from rockcem.calibrate import fit_parameters

    predict_all = _predictor(model, g, inp["grain"], inp["cement"], scheme, stiffness, held,
                             inp["obs"])

    def predict(**p):
        return {k: v[g.used] for k, v in predict_all(**p).items()}

    try:
        fit = fit_parameters(
            predict, {k: v[g.used] for k, v in g.obs.items()}, spec,
            errors=None if g.err is None else {k: v[g.used] for k, v in g.err.items()},
            absolute_errors=absolute_errors)
    except ValueError as exc:
        raise ValueError(f"{where}: {exc}") from None
    return fit, predict_all(**fit.values)
