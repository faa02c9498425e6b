"""Which curve of a well log is which variable, in what unit, and which samples are bad.

The part of :mod:`rockcem.wells` that works on curves, whatever the file format: the
mnemonics (:data:`ALIASES`, :data:`DEPTH_NAMES`) and unit spellings (:data:`UNITS`) understood,
the choice of one curve per variable (:func:`_choose`), the null values, the checks that blank a
bad sample or refuse a curve in the wrong unit (:data:`RANGES`, :func:`_check_curve`) and the
labels of an apparent porosity. :mod:`rockcem.wells` documents the rules and re-exports the
public names.
"""

from __future__ import annotations

import re

import numpy as np

from .validation import as_array

#: Variables a well and a scene share, in the order they are read and compared.
WELL_VARIABLES = ("vp", "vs", "density", "porosity")

#: Mnemonics of the depth (index) curve, the first curve of a file.
DEPTH_NAMES = ("DEPT", "DEPTH", "MD", "TVD")

#: Log mnemonics read for each variable, in order of preference. Whether a sonic curve is a
#: slowness or a velocity follows from its unit.
ALIASES = {
    "vp": ("DT", "DTC", "DTCO", "DT4P", "DTP", "AC", "ACTC", "VP", "PVEL"),
    "vs": ("DTS", "DTSM", "DT4S", "DTSH", "VS", "SVEL"),
    "density": ("RHOB", "RHOZ", "ZDEN", "DEN", "DENS", "RHO"),
    "porosity": ("PHIT", "PHI", "POR", "TPOR",                          # total porosity
                 "NPHI", "TNPH", "NPOR", "NPHI_SAN", "NPHS", "NPHI_LIM", "NPHL", "NPHI_DOL",
                 "NPHD", "CN",                                          # neutron (apparent)
                 "DPHI", "DPHI_SAN", "DPHS", "DPHI_LIM", "DPHL", "DPHI_DOL", "DPHD"),  # density
}

#: Understood units (upper case, spaces removed, the micro sign ``µ`` or ``μ`` read as ``u``)
#: of each kind of curve, with the factor to the project's unit. Slownesses map to the factor
#: ``c`` of :math:`v = c/\Delta t` in km/s. ``.1IN`` is the LAS depth unit of a tenth of an
#: inch; ``LPU``, ``SPU``, ``DPU`` are porosity percent in limestone, sandstone, dolomite units;
#: ``DECP`` and ``CFCF`` are fractions.
UNITS = {
    "depth": {"M": 1.0, "METER": 1.0, "METERS": 1.0, "METRE": 1.0, "METRES": 1.0,
              "FT": 0.3048, "F": 0.3048, "FEET": 0.3048, "FOOT": 0.3048,
              ".1IN": 0.00254, "0.1IN": 0.00254, "IN": 0.0254},
    "slowness": {"US/FT": 304.8, "USEC/FT": 304.8, "US/F": 304.8, "USEC/F": 304.8,
                 "US/FOOT": 304.8, "US/M": 1000.0, "USEC/M": 1000.0},
    "velocity": {"KM/S": 1.0, "KM/SEC": 1.0, "M/S": 1e-3, "M/SEC": 1e-3,
                 "FT/S": 0.3048e-3, "F/S": 0.3048e-3, "FT/SEC": 0.3048e-3},
    "density": {"G/CC": 1.0, "G/CM3": 1.0, "G/CM^3": 1.0, "G/CM**3": 1.0, "GM/CC": 1.0,
                "G/C3": 1.0, "GR/CC": 1.0, "GRM/CC": 1.0, "GM/CM3": 1.0,
                "KG/M3": 1e-3, "KG/M^3": 1e-3, "K/M3": 1e-3},
    "porosity": {"V/V": 1.0, "FRAC": 1.0, "FRACTION": 1.0, "DEC": 1.0, "DECP": 1.0,
                 "M3/M3": 1.0, "FT3/FT3": 1.0, "CFCF": 1.0, "VOL/VOL": 1.0, "1": 1.0,
                 "%": 0.01, "PU": 0.01, "P.U.": 0.01, "PERCENT": 0.01, "PCT": 0.01,
                 "PERCNT": 0.01, "LPU": 0.01, "SPU": 0.01, "DPU": 0.01},
}

#: Plausible range of a single sample of each variable, in the project's units. The lower bound
#: of vp is the speed of sound in water at 0 °C (1.40 km/s): a rock logged slower is a bad
#: sample (a gas sand can be slower, a sonic log rarely reads it right). A sample outside is
#: blanked; a curve whose median lies outside has the wrong unit.
RANGES = {"vp": (1.40, 7.5), "vs": (0.05, 4.5), "density": (1.0, 3.5), "porosity": (-0.15, 1.0)}

#: Null values written without being declared (blanked with a hint to pass ``null=``).
_SENTINELS = (-999.25, -999.0, -999.99, -9999.0, -9999.25, -9999.99, -99999.0, -32767.0,
              -2147483647.0)

_UNIT_TEXT = {"vp": "km/s", "vs": "km/s", "density": "g/cm3", "porosity": ""}
_MATRIX_UNITS = {"LPU": "limestone", "SPU": "sandstone", "DPU": "dolomite"}
_MATRIX_NAMES = {"_LIM": "limestone", "_SAN": "sandstone", "_DOL": "dolomite",
                 "NPHL": "limestone", "NPHS": "sandstone", "NPHD": "dolomite",
                 "DPHL": "limestone", "DPHS": "sandstone", "DPHD": "dolomite"}


# ----------------------------------------------------------------------------- units, curves
def _unit_key(unit) -> str:
    # The micro sign (U+00B5) and the Greek mu (U+03BC) both upper-case to U+039C: read as u.
    key = re.sub(r"\s+", "", str(unit or ""))
    return key.replace("\u00b5", "u").replace("\u03bc", "u").upper()


def _kinds(variable):
    return {"vp": ("slowness", "velocity"), "vs": ("slowness", "velocity"),
            "density": ("density",), "porosity": ("porosity",)}[variable]


def _unit_kind(variable, unit):
    """``(kind, factor)`` of a curve of ``variable`` in ``unit``, or None if not understood."""
    key = _unit_key(unit)
    for kind in _kinds(variable):
        if key in UNITS[kind]:
            return kind, UNITS[kind][key]
    return None


def _known_units(variable):
    return ", ".join(u for kind in _kinds(variable) for u in UNITS[kind])


def _base(mnemonic) -> str:
    """A mnemonic without lasio's ``:1``, ``:2`` of a repeated one."""
    return re.sub(r":\d+$", "", str(mnemonic)).upper()


def _apparent(mnemonic, unit):
    """``("neutron" | "density" | None, matrix or None)`` of a porosity curve."""
    name, key = _base(mnemonic), _unit_key(unit)
    source = "neutron" if (name.startswith(("NPH", "TNPH", "NPOR", "CN"))
                           or key in _MATRIX_UNITS) else \
        "density" if name.startswith("DPH") else None
    matrix = _MATRIX_UNITS.get(key) or next(
        (m for k, m in _MATRIX_NAMES.items() if name.endswith(k)), None)
    return source, (matrix if source else None)


def _choose(source, curves, override):
    """The curve of each variable: ``{variable: (index, mnemonic, unit, kind, factor)}`` and
    the notes on variables left out, from the header ``curves = [(mnemonic, unit), ...]``."""
    if override is None:
        override = {}
    if not hasattr(override, "items"):
        raise ValueError("curves must be a mapping {variable: mnemonic}, e.g. {'vp': 'DTCO'}")
    unknown = [k for k in override if k not in WELL_VARIABLES]
    if unknown:
        raise ValueError(f"curves: {unknown[0]!r} is not a variable; use "
                         f"{', '.join(WELL_VARIABLES)}")
    names = [str(m).upper() for m, _ in curves]
    chosen, notes = {}, []
    for var in WELL_VARIABLES:
        if var in override:
            wanted = override[var]
            if wanted is None or str(wanted).strip().lower() in ("", "none"):
                notes.append({"variable": var, "status": "left out", "note": "curves= says so"})
                continue
            wanted = str(wanted).strip().upper()
            hits = [i for i, n in enumerate(names) if n == wanted and i > 0] or \
                [i for i, n in enumerate(names) if _base(n) == wanted and i > 0]
            if not hits:
                raise ValueError(f"{source}: no curve {wanted!r} for {var} (curves= or --curve);"
                                 f" the file has {', '.join(names[1:]) or 'none'}")
            if len(hits) > 1:
                raise ValueError(f"{source}: curve {wanted} appears {len(hits)} times "
                                 f"({', '.join(names[i] for i in hits)}); name one of them")
            i = hits[0]
            other = _sonic_of_other_wave(var, _base(names[i]))
            if other:
                raise ValueError(f"{source}: curve {names[i]!r} for {var}: {_base(names[i])} is "
                                 f"a {other} mnemonic ({', '.join(ALIASES[_OTHER_WAVE[var]])}"
                                 f"); name a {'shear' if var == 'vs' else 'compressional'} "
                                 f"sonic for {var}")
            unit = curves[i][1]
            hit = _unit_kind(var, unit)
            if hit is None:
                what = f"unit {unit!r} is not understood" if _unit_key(unit) else "no unit given"
                raise ValueError(f"{source}: curve {names[i]!r} for {var}: {what}; use one of "
                                 f"{_known_units(var)}")
            chosen[var] = (i, names[i], str(unit), *hit)
            continue
        passed = []
        for alias in ALIASES[var]:
            hits = [i for i, n in enumerate(names) if _base(n) == alias and i > 0]
            if not hits:
                continue
            if len(hits) > 1:
                passed.append(f"{alias} appears {len(hits)} times "
                              f"({', '.join(names[i] for i in hits)}): name one with "
                              f"curves={{'{var}': '{names[hits[-1]]}'}}")
                continue
            i = hits[0]
            unit = curves[i][1]
            hit = _unit_kind(var, unit)
            if hit is None:
                what = f"unit {unit!r} not understood" if _unit_key(unit) else "no unit"
                passed.append(f"{names[i]}: {what} for {var}")
                continue
            chosen[var] = (i, names[i], str(unit), *hit)
            break
        if passed:
            notes.append({"variable": var, "status": "passed over" if var in chosen else
                          "left out", "note": "; ".join(passed)})
    # One curve is one variable: --curve vs=DTS with DTS also vp's is a slip, never two logs.
    users = {}
    for var, entry in chosen.items():
        users.setdefault(entry[0], []).append(var)
    for i, shared in users.items():
        if len(shared) > 1:
            named = [v for v in shared if v in override]
            raise ValueError(f"{source}: curve {names[i]} would be read as both "
                             f"{' and '.join(shared)}" + (
                                 f" ({', '.join(f'--curve {v}={names[i]}' for v in named)} "
                                 f"names it; the other chose it by its mnemonic)"
                                 if len(named) < len(shared) else "") +
                             f"; name another curve for one of them, or leave one out "
                             f"(--curve {shared[-1]}=none)")
    return chosen, notes


#: The other wave of a sonic variable (whose mnemonics :func:`_choose` refuses for it).
_OTHER_WAVE = {"vp": "vs", "vs": "vp"}


def _sonic_of_other_wave(var, name) -> str:
    """``"compressional sonic"`` when ``name`` is one of vp's mnemonics and ``var`` is vs (and
    ``"shear sonic"`` the other way round), else ``""``: the curve's own name says it is the
    other wave's log."""
    if var not in _OTHER_WAVE or name not in ALIASES[_OTHER_WAVE[var]]:
        return ""
    return "compressional sonic" if var == "vs" else "shear sonic"


# ----------------------------------------------------------------------------- checks
def _null_values(null):
    if null is None:
        return []
    values = as_array("null", null).ravel()
    if not np.all(np.isfinite(values)):
        raise ValueError(f"null must be finite numbers; got {values.tolist()}")
    return [float(v) for v in values]


def _fmt(value):
    return f"{value:.4g}"


def _check_curve(source, var, mnemonic, unit, kind, factor, raw, text, nulls, zraw, zunit):
    """Blank the bad samples of one curve; refuse it if its bulk says the unit is wrong.

    Returns ``(values in the project's unit, report entry)``; ``values`` is None when the
    curve has no valid sample."""
    lo, hi = RANGES[var]
    shown = _UNIT_TEXT[var] or "(fraction)"
    null = np.isnan(raw) & ~text
    for v in nulls:
        null |= raw == v
    sentinel = np.zeros(raw.shape, dtype=bool)
    for v in _SENTINELS:
        if v not in nulls:
            sentinel |= raw == v
    usable = ~(null | text | sentinel)
    positive = kind in ("slowness", "velocity", "density")
    not_positive = usable & (raw <= 0.0) if positive else np.zeros(raw.shape, dtype=bool)
    valid = usable & ~not_positive
    with np.errstate(divide="ignore", invalid="ignore"):
        value = np.where(valid, factor / raw if kind == "slowness" else factor * raw, np.nan)
    entry = {"variable": var, "mnemonic": mnemonic, "unit": str(unit), "kind": kind,
             "samples": int(raw.size), "null": int(null.sum())}
    if not valid.any():
        entry.update(status="left out", kept=0, blanked=_reasons(
            raw, zraw, zunit, unit, ((text, "not a number"), (sentinel, "undeclared null"),
                                     (not_positive, "not positive"))),
            note="no valid sample")
        return None, entry
    median = float(np.median(value[valid]))
    if not lo <= median <= hi:
        raise ValueError(_wrong_unit(source, var, mnemonic, unit, kind, factor, median))
    if kind == "porosity" and factor == 0.01:
        p95 = float(np.percentile(raw[valid], 95.0))
        if p95 < 0.5:
            raise ValueError(f"{source}: curve {mnemonic} ({unit}): 95 % of its samples are "
                             f"below {p95:.3g} {unit}, porosity {p95 * factor:.3g}: the values "
                             f"look like a fraction, not percent; correct the unit, or leave "
                             f"the curve out (curves={{'{var}': None}}, --curve {var}=none)")
    below = valid & (value < lo)
    above = valid & (value > hi)
    value[below | above] = np.nan
    units = f" {_UNIT_TEXT[var]}" if _UNIT_TEXT[var] else ""
    entry["blanked"] = _reasons(raw, zraw, zunit, unit, (
        (text, "not a number"), (sentinel, "undeclared null"), (not_positive, "not positive"),
        (below, f"slower than water (< {lo:g}{units})" if var == "vp" else
         f"below {lo:g}{units}"),
        (above, f"above {hi:g}{units}")))
    entry.update(status="read", kept=int(np.isfinite(value).sum()))
    entry["median"] = f"{_fmt(median)} {shown}"
    if sentinel.any():
        found = sorted({float(v) for v in raw[sentinel]})
        entry["note"] = ("values " + ", ".join(f"{v:g}" for v in found) + " look like nulls "
                         "the header does not declare: pass null=" +
                         (f"{found[0]:g}" if len(found) == 1 else
                          "[" + ", ".join(f"{v:g}" for v in found) + "]") +
                         f" (--null {found[0]:g})")
    return value, entry


def _reasons(raw, zraw, zunit, unit, masks):
    """``{reason: {"count": n, "first": "value unit at depth"}}`` of the non-empty masks."""
    out = {}
    for mask, reason in masks:
        n = int(mask.sum())
        if n:
            k = int(np.flatnonzero(mask)[0])
            value = raw[k]
            out[reason] = {"count": n, "first": (f"{value:g} {unit}".strip() if
                                                 np.isfinite(value) else "text") +
                           f" at {zraw[k]:g} {zunit}".rstrip()}
    return out


def _wrong_unit(source, var, mnemonic, unit, kind, factor, median):
    """The message refusing a curve whose median lies outside its variable's range."""
    lo, hi = RANGES[var]
    what = f"{var} {_fmt(median)} {_UNIT_TEXT[var]}".rstrip()
    if var == "vp" and median < lo:
        why = f"slower than water ({lo:g} km/s)"
    else:
        why = f"outside [{lo:g}, {hi:g}] {_UNIT_TEXT[var]}".rstrip()
    raw_median = factor / median if kind == "slowness" else median / factor
    others = []
    for k in _kinds(var):
        for u, f in UNITS[k].items():
            if u == _unit_key(unit) or f == factor and k == kind:
                continue
            v = f / raw_median if k == "slowness" else f * raw_median
            if lo <= v <= hi and not any(f"{_fmt(v)}" in o for o in others):
                others.append(f"in {u} it would be {_fmt(v)} {_UNIT_TEXT[var]}".rstrip())
    hint = f" ({'; '.join(others[:2])})" if others else ""
    return (f"{source}: curve {mnemonic} ({unit}): its median, {_fmt(raw_median)} {unit}, "
            f"gives {what}, {why}: the unit is wrong{hint}; correct the unit in the file, or "
            f"choose another curve or none (curves={{'{var}': ...}}, "
            f"--curve {var}=MNEMONIC or {var}=none)")


def _label(var, mnemonic, unit):
    """``(long_name, log_label, comment)`` of a well variable."""
    if var != "porosity":
        return None, mnemonic, None
    source, matrix = _apparent(mnemonic, unit)
    if source is None:
        return f"log porosity ({mnemonic})", mnemonic, None
    units = f" ({matrix} units)" if matrix else ""
    comment = (f"a {source} porosity, apparent: in the units of the tool's calibration "
               f"matrix{units}, not the total porosity of the rock")
    return f"log porosity (apparent, from {mnemonic})", f"{mnemonic}, apparent", comment
