"""The ``[uncertain]`` section of a scene, read and checked (issue 32): which keys may be
uncertain, their valid ranges (those a fixed value is checked against), the distributions'
parameters, the designs and the rank correlations. Private to the scene loader
(:mod:`rockcem.scene`); the sampling and the members' evaluation are
:mod:`rockcem._uncertain`.
"""

from __future__ import annotations

import json

import numpy as np

from ._uncertain import (DEFAULT_QUANTILES, DESIGNS, DISTRIBUTIONS, MAX_OUTSIDE_MASS, _frozen,
                         _range_text)

__all__ = ["key_range", "validate_uncertain"]


#: Keys that cannot be uncertain, and why.
_NOT_SAMPLED = {
    "path.max_depth": "it sets the depth axis every member shares",
    "path.depth_step": "it sets the depth axis every member shares",
    "models.self_consistent.tol": "it is a numerical tolerance, not an input of the rock",
}


_TOP_KEYS = {"samples": "integer", "seed": "integer", "design": "string",
             "quantiles": "numbers", "members": "boolean", "rank_correlations": "list",
             "sensitivity": "boolean"}


def key_range(dotted, sections):
    """The valid range of an uncertain scene key: ``(low, high, low_open, high_open, unit)``.

    The ranges are those the scene's own evaluation checks a fixed value against (the burial
    functions and the models, whose constants are imported from there), narrowed where a
    fixed key of the scene bounds another: the gradient by the path's largest temperature
    (:data:`burial.path.MAX_TEMPERATURE_C` at ``max_depth``), the sedimentation rate by the age
    of the Earth (:data:`burial.path.MAX_TIME_MYR`), the water density by the sediment's, a
    sandstone's initial porosity and final IGV by each other, Model 4's contact cement limit
    by the critical porosity.

    Raises
    ------
    ValueError
        For a key that cannot be sampled (MD keys, the depth axis, a numerical tolerance).
    """
    from burial.clay import MAX_ACTIVATION_ENERGY, MAX_ORDER
    from burial.path import (MAX_SURFACE_TEMPERATURE_C, MAX_TEMPERATURE_C, MAX_TIME_MYR,
                             MIN_TEMPERATURE_C)
    from burial.quartz import MIN_GRAIN_SIZE_MM

    from .scene import FLUID_RANGES, SCHEMA
    from .validation import MAX_DENSITY

    section, _, key = dotted.rpartition(".")
    if section == "models.md":
        raise ValueError(f"scene key uncertain.{dotted!r}: MD keys are not sampled (an MD "
                         "member takes minutes: 10^3 members would take days); sweep a few "
                         "values in [sweep] instead")
    if dotted in _NOT_SAMPLED:
        raise ValueError(f"scene key uncertain.{dotted!r} cannot be uncertain: "
                         f"{_NOT_SAMPLED[dotted]}")
    unit = SCHEMA[section][key][2]
    inf = np.inf
    path = sections.get("path", {})
    if section == "path":
        if key == "gradient":
            top = (MAX_TEMPERATURE_C - path["surface_temperature"]) * 1000.0 / path["max_depth"]
            return 0.0, top, True, False, unit
        if key == "sedimentation_rate":
            return path["max_depth"] / MAX_TIME_MYR, inf, False, True, unit
        if key == "heating_rate":
            return 0.0, inf, True, True, unit
        if key == "surface_temperature":
            return MIN_TEMPERATURE_C, MAX_SURFACE_TEMPERATURE_C, False, False, unit
    if section == "pressure":
        if key == "sediment_density":
            return sections["pressure"]["water_density"], MAX_DENSITY, False, False, unit
        return 0.0, sections["pressure"]["sediment_density"], True, False, unit
    if section == "sandstone" and key in ("porosity0", "igv_final"):
        # eq. B.7: the IGV falls from porosity0 towards igv_final (burial.intergranular_volume)
        rock = sections["sandstone"]
        return ((rock["igv_final"], 1.0, rock["igv_final"] == 0.0, True, unit)
                if key == "porosity0" else (0.0, rock["porosity0"], False, False, unit))
    if section in ("sandstone", "shale"):
        table = {"porosity0": (0.0, 1.0, True, True), "quartz_fraction": (0.0, 1.0, False, False),
                 "grain_size": (MIN_GRAIN_SIZE_MM, inf, False, True),
                 "clay_coating": (0.0, 1.0, False, False), "igv_final": (0.0, 1.0, False, False),
                 "beta": (0.0, inf, False, True),
                 "start_temperature": (MIN_TEMPERATURE_C, MAX_TEMPERATURE_C, False, False),
                 "r0": (0.0, 1.0, False, False), "order": (1.0, MAX_ORDER, False, False),
                 "activation_energy": (0.0, MAX_ACTIVATION_ENERGY, True, False),
                 "frequency_factor": (0.0, inf, True, True)}
        return (*table[key], unit)
    if section == "fluid":
        low, high, _text = FLUID_RANGES[key]
        return low, high, False, key in ("salinity", "top", "base"), unit
    if section in ("models.hs_gassmann", "models.generalized_gassmann"):
        from .frames import MAX_KRIEF_EXPONENT

        return 0.0, MAX_KRIEF_EXPONENT, True, False, unit
    if section == "models.self_consistent":
        from .inclusions import MAX_ASPECT_RATIO, MIN_ASPECT_RATIO

        return MIN_ASPECT_RATIO, MAX_ASPECT_RATIO, False, False, unit
    if section == "models.patchy_cement":
        from .granular import MAX_COORDINATION_NUMBER, MAX_PRESSURE_MPA

        table = {"coordination_number": (0.0, MAX_COORDINATION_NUMBER, True, False),
                 # at most the critical porosity (rockcem.models.patchy_cement_model)
                 "contact_cement_limit": (0.0, sections["sandstone"]["porosity0"], True, False),
                 "delta": (0.0, MAX_PRESSURE_MPA, False, False),
                 "thickness": (0.0, inf, False, True), "f": (0.0, 1.0, False, False)}
        return (*table[key], unit)
    raise ValueError(f"scene key uncertain.{dotted!r} cannot be uncertain")  # not numeric


def _check_entry(dotted, entry, rng):
    """One ``[uncertain."section.key"]`` table, checked: ``{"distribution", params...,
    "truncate", "range", "cdf_range", "outside"}``."""
    where = f"scene key uncertain.{json.dumps(dotted)}"
    if not isinstance(entry, dict):
        raise ValueError(f"{where} must be a table: distribution = \"normal\", mean = ..., "
                         "sd = ...")
    dist = entry.get("distribution")
    if dist not in DISTRIBUTIONS:
        raise ValueError(f"{where}.distribution must be one of {', '.join(DISTRIBUTIONS)}; "
                         f"got {dist!r}")
    names = DISTRIBUTIONS[dist]
    stray = [k for k in entry if k not in (*names, "distribution", "truncate")]
    if stray:
        raise ValueError(f"{where}: {stray[0]!r} is not a parameter of a {dist} distribution "
                         f"(its parameters: {', '.join(names)}; and truncate)")
    from .scene import _float, _is_number

    params = {}
    for name in names:
        if name not in entry:
            raise ValueError(f"{where}: a {dist} distribution needs {', '.join(names)}; "
                             f"{name} is missing")
        value = entry[name]
        if not _is_number(value) or not np.isfinite(_float(value)):
            raise ValueError(f"{where}.{name} must be a finite number; got {value!r}")
        params[name] = _float(value)
    for name in ("sd", "sigma", "median"):
        if name in params and not params[name] > 0.0:
            raise ValueError(f"{where}.{name} must be > 0; got {params[name]:g}")
    if "lower" in params and not params["lower"] < params["upper"]:
        raise ValueError(f"{where}: lower ({params['lower']:g}) must be below upper "
                         f"({params['upper']:g})")
    if "mode" in params and not params["lower"] <= params["mode"] <= params["upper"]:
        raise ValueError(f"{where}.mode ({params['mode']:g}) must lie in [lower, upper] = "
                         f"[{params['lower']:g}, {params['upper']:g}]")
    truncate = entry.get("truncate", False)
    if not isinstance(truncate, bool):
        raise ValueError(f"{where}.truncate must be true or false; got {truncate!r}")
    low, high, low_open, high_open, _unit = rng
    if not low < high:
        raise ValueError(f"{where}: the scene's fixed keys leave it no valid range "
                         f"({_range_text(rng)})")
    frozen = _frozen(dist, params)
    cdf_low, cdf_high = float(frozen.cdf(low)), float(frozen.cdf(high))
    outside = cdf_low + (1.0 - cdf_high)
    text = f"{dist}({', '.join(f'{k} {v:g}' for k, v in params.items())})"
    if not cdf_high - cdf_low > 0.0:
        raise ValueError(f"{where}: {text} lies wholly outside the valid range "
                         f"{_range_text(rng)} of {dotted}")
    if outside > MAX_OUTSIDE_MASS and not truncate:
        raise ValueError(f"{where}: {text} puts {outside:.3g} of its probability outside the "
                         f"valid range {_range_text(rng)} of {dotted}; narrow it, or set "
                         "truncate = true to truncate it to that range")
    return {"distribution": dist, **params, "truncate": truncate, "range": list(rng[:4]),
            "cdf_range": [cdf_low, cdf_high], "outside": outside}


def _check_correlations(pairs, keys):
    """``rank_correlations`` as a target rank-correlation matrix over ``keys`` (positive
    definite), or None."""
    if pairs is None or pairs == []:
        return None
    where = "scene key uncertain.rank_correlations"
    if not isinstance(pairs, list):
        raise ValueError(f"{where} must be a list of [\"section.key\", \"section.key\", rho]")
    C = np.eye(len(keys))
    seen = set()
    for item in pairs:
        if not (isinstance(item, list) and len(item) == 3 and all(isinstance(k, str)
                                                                   for k in item[:2])
                and isinstance(item[2], (int, float)) and not isinstance(item[2], bool)):
            raise ValueError(f"{where}: each entry must be [\"section.key\", \"section.key\", "
                             f"rho]; got {item!r}")
        a, b, rho = item
        for k in (a, b):
            if k not in keys:
                raise ValueError(f"{where}: {k!r} is not an uncertain key (uncertain: "
                                 f"{', '.join(keys)})")
        if a == b or frozenset((a, b)) in seen:
            raise ValueError(f"{where}: the pair {a!r}, {b!r} is given twice or pairs a key "
                             "with itself")
        if not -1.0 < rho < 1.0:
            raise ValueError(f"{where}: rank correlation of {a} and {b} must lie in (-1, 1); "
                             f"got {rho:g}")
        seen.add(frozenset((a, b)))
        i, j = keys.index(a), keys.index(b)
        C[i, j] = C[j, i] = float(rho)
    if np.linalg.eigvalsh(C).min() <= 1e-10:
        raise ValueError(f"{where}: the rank correlations given are not a valid correlation "
                         "matrix (not positive definite); loosen them")
    return C


def validate_uncertain(raw, sections, sweep, *, models, lithology):
    """Check a scene's ``[uncertain]`` section against its validated ``sections``.

    Parameters
    ----------
    raw : dict
        The parsed ``[uncertain]`` table.
    sections : dict
        The scene's sections (defaults filled in) without the uncertain keys' values.
    sweep : dict
        The scene's validated sweep (a key may not be both swept and uncertain).
    models : tuple of str
        The scene's models (a model's key is uncertain only if the model runs).
    lithology : str

    Returns
    -------
    dict
        ``{"samples", "seed", "design", "quantiles", "members", "keys": {dotted: entry},
        "correlation": matrix as nested lists or None}``.

    Raises
    ------
    ValueError
        Naming the key: unknown, not numeric, swept too, an MD key, bad parameters, a
        distribution leaving the key's range without ``truncate = true``, a bad design or
        sample count, bad quantiles or rank correlations.
    """
    from .scene import SCHEMA, _suggest

    if not isinstance(raw, dict):
        raise ValueError("scene section [uncertain] must be a table")
    if "md" in models:
        raise ValueError("scene section [uncertain] does not apply to a scene with [models.md]: "
                         "an MD member takes minutes, 10^3 members days; sweep a few values "
                         "in [sweep] instead")
    keys = {k: v for k, v in raw.items() if isinstance(v, dict)}
    top = {k: v for k, v in raw.items() if not isinstance(v, dict)}
    for k in top:
        if k not in _TOP_KEYS:
            valid = [f"{s}.{n}" for s in sections for n in sections[s]]
            hint = _suggest(k, valid) if "." in k else _suggest(k, _TOP_KEYS)
            raise ValueError(f"unknown scene key uncertain.{k}{hint}")
    if not keys:
        raise ValueError("scene section [uncertain] names no key: add a table such as "
                         "[uncertain.\"path.gradient\"] distribution = \"normal\", mean = 30, "
                         "sd = 2")
    samples = top.get("samples")
    if not (isinstance(samples, int) and not isinstance(samples, bool) and samples >= 2):
        raise ValueError(f"scene key uncertain.samples must be an integer >= 2 (the members "
                         f"to draw); got {samples!r}")
    seed = top.get("seed", 0)
    if not (isinstance(seed, int) and not isinstance(seed, bool) and seed >= 0):
        raise ValueError(f"scene key uncertain.seed must be an integer >= 0; got {seed!r}")
    design = top.get("design", "lhs")
    if design not in DESIGNS:
        raise ValueError(f"scene key uncertain.design must be one of {', '.join(DESIGNS)}; "
                         f"got {design!r}")
    if design == "sobol" and samples & (samples - 1):
        low = 1 << (samples.bit_length() - 1)
        raise ValueError(f"scene key uncertain.samples = {samples} with design = 'sobol': "
                         "Sobol' points keep their balance only in powers of two; use "
                         f"{low} or {2 * low}")
    quantiles = top.get("quantiles", list(DEFAULT_QUANTILES))
    if not (isinstance(quantiles, list) and quantiles
            and all(isinstance(q, (int, float)) and not isinstance(q, bool) for q in quantiles)
            and all(0.0 < q < 1.0 for q in quantiles)
            and all(a < b for a, b in zip(quantiles, quantiles[1:]))):
        raise ValueError(f"scene key uncertain.quantiles must be a list of increasing numbers "
                         f"in (0, 1); got {quantiles!r}")
    members = top.get("members", False)
    if not isinstance(members, bool):
        raise ValueError(f"scene key uncertain.members must be true or false; got {members!r}")
    if members and sweep:
        raise ValueError("scene key uncertain.members = true does not apply beside a [sweep] "
                         "(each swept combination draws its own members); run the swept "
                         "values as scenes of their own to keep their members")
    sensitivity = _check_sensitivity(top, samples, members, sweep)
    out = {}
    for dotted, entry in keys.items():
        section, _, key = dotted.rpartition(".")
        if "distribution" not in entry and entry and all(isinstance(v, dict)
                                                         for v in entry.values()):
            inner = next(iter(entry))
            raise ValueError(f"scene section [uncertain.{dotted}.{inner}...]: quote the key, "
                             f"[uncertain.\"{dotted}.{inner}\"] (a dotted key unquoted is a "
                             "table in a table)")
        if section == "models.md":
            key_range(dotted, sections)                     # refuses MD keys by name
        if section not in SCHEMA or key not in SCHEMA[section]:
            valid = [f"{s}.{n}" for s in sections for n in sections[s]]
            raise ValueError(f"unknown uncertain key {dotted!r}{_suggest(dotted, valid)}")
        if section not in sections:
            what = (f"model {section.removeprefix('models.')!r} is not in the scene's "
                    "[models]" if section.startswith("models.") else
                    f"section [{section}] does not apply to lithology {lithology!r}")
            raise ValueError(f"uncertain key {dotted!r}: {what}")
        if SCHEMA[section][key][1] != "number":
            raise ValueError(f"uncertain key {dotted!r} is not a number (it is a "
                             f"{SCHEMA[section][key][1]}): sweep its values in [sweep] instead")
        if dotted in sweep:
            raise ValueError(f"scene key {dotted} is both swept and uncertain; remove it from "
                             "[sweep] or from [uncertain]")
        out[dotted] = _check_entry(dotted, entry, key_range(dotted, sections))
        out[dotted]["unit"], out[dotted]["doc"] = SCHEMA[section][key][2], SCHEMA[section][key][3]
    names = list(out)
    C = _check_correlations(top.get("rank_correlations"), names)
    if C is not None and samples <= len(names) + 1:
        raise ValueError(f"scene key uncertain.samples = {samples}: rank correlations between "
                         f"{len(names)} inputs need more than {len(names) + 1} members")
    return {"samples": samples, "seed": seed, "design": "sobol" if sensitivity else design,
            "quantiles": [float(q) for q in quantiles], "members": members, "keys": out,
            "correlation": None if C is None else C.tolist(), "sensitivity": sensitivity}


def _check_sensitivity(top, samples, members, sweep):
    """``sensitivity = true`` checked against the section's other keys: ``samples`` the base
    N of the Saltelli design (a power of two), no rank correlations (Sobol' indices assume
    independent inputs), no ``design`` other than Sobol', no kept members, no sweep."""
    sensitivity = top.get("sensitivity", False)
    where = "scene key uncertain.sensitivity"
    if not isinstance(sensitivity, bool):
        raise ValueError(f"{where} must be true or false; got {sensitivity!r}")
    if not sensitivity:
        return False
    if samples & (samples - 1):
        low = 1 << (samples.bit_length() - 1)
        raise ValueError(f"scene key uncertain.samples = {samples} with sensitivity = true: "
                         "the base N of the Saltelli design must be a power of two (Sobol' "
                         f"points keep their balance only then); use {low} or {2 * low}")
    if top.get("rank_correlations") not in (None, []):
        raise ValueError(f"{where} = true does not apply with uncertain.rank_correlations: "
                         "Sobol' indices assume independent inputs; remove the correlations "
                         "(or the sensitivity)")
    if top.get("design", "sobol") != "sobol":
        raise ValueError(f"{where} = true draws its own design (Saltelli's, on scrambled "
                         f"Sobol' points); uncertain.design = {top['design']!r} does not apply: "
                         "remove it")
    if members:
        raise ValueError(f"{where} = true does not apply with uncertain.members = true (the "
                         "members are those of the Saltelli design); remove one of them")
    if sweep:
        raise ValueError(f"{where} = true does not apply beside a [sweep]; run the swept "
                         "values as scenes of their own")
    return True
