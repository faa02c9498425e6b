"""Input checking shared by every package (the shared base: imports numpy only).

One rule for the whole project: bad input raises ``ValueError`` naming the argument and the
valid range; nothing returns NaN or a complex number silently. With :mod:`rockcem.constants`
and :mod:`rockcem.variables` this is the floor that ``burial``, the ``rockcem`` models and ``md``
build on; it imports none of them, nor the scene layer.

:func:`labelled` is the one place that handles pandas and xarray inputs: it aligns them by label,
calls the numpy function below it and puts the labels back (pandas and xarray are imported only
when a labelled input arrives, never for numpy ones).
"""

from __future__ import annotations

import contextlib
import functools
import inspect
from collections.abc import Callable, Mapping

import numpy as np

__all__ = ["MAX_DENSITY", "MIN_DENSITY", "MAX_MODULUS", "MIN_MODULUS", "as_array", "as_scalar",
           "prefixed_errors", "labelled", "FIELD_UNITS", "INPUT_UNITS", "UNIT_SPELLINGS",
           "NOT_QUANTITIES",
           "check_range", "check_positive", "check_modulus", "check_fractions", "broadcast",
           "broadcast_phases", "stack_phases", "sum_phases", "max_phases", "min_phases",
           "blockwise", "BLOCK"]

#: Largest density accepted anywhere, g/cm³: above that of osmium (22.6), the densest element.
MAX_DENSITY = 25.0
#: Smallest density a velocity is computed from, g/cm³ (a thousandth of air's at the surface).
MIN_DENSITY = 1e-6
#: Largest elastic modulus accepted anywhere, GPa: a million times diamond's, far beyond any
#: stiffness contrast a model is asked for, and below a modulus given in Pa by mistake (quartz:
#: 3.7e10 Pa). Products and ratios of a few moduli stay finite in float64.
MAX_MODULUS = 1e9
#: Smallest modulus accepted where a modulus must be positive (a solid's), GPa: 1 Pa.
MIN_MODULUS = 1e-9


def as_array(name: str, value) -> np.ndarray:
    """Return ``value`` as a float64 array (a copy is never needed: inputs are never mutated).

    Refuses, naming ``name``: ``None``, text (``"9"`` is not read as 9: a number given as
    text is a mistake upstream), booleans (``True`` is not 1 °C), numpy masked arrays (their
    masked values would be computed as valid ones), complex values and NaN. Infinities pass
    here; the range checks below refuse them.
    """
    if value is None:
        raise ValueError(f"{name} must be a real number, got None")
    if isinstance(value, (str, bytes)):
        raise ValueError(f"{name} must be a real number, got text {value!r}")
    if isinstance(value, np.ma.MaskedArray):
        raise ValueError(f"{name} is a numpy masked array: its masked values would be computed "
                         "as valid ones; give the valid values only (value.compressed() or "
                         "value[~value.mask])")
    try:
        raw = np.asarray(value)
    except (TypeError, ValueError):          # ragged nested sequences
        raise ValueError(f"{name} must be a real number or a rectangular array of real "
                         "numbers") from None
    if raw.dtype.kind in "USO" and any(isinstance(v, (str, bytes)) for v in raw.flat):
        raise ValueError(f"{name} must be a real number, got text {value!r}")
    if raw.dtype.kind == "b" or (isinstance(value, (list, tuple)) and _holds_bool(value)) or (
            raw.dtype.kind == "O" and any(isinstance(v, (bool, np.bool_)) for v in raw.flat)):
        raise ValueError(f"{name} must be a real number, got a boolean (True/False is not 1/0 "
                         "here)")
    if raw.dtype.kind == "c" or (raw.dtype.kind == "O"
                                 and any(isinstance(v, complex) for v in raw.flat)):
        raise ValueError(f"{name} must be real, got a complex value")
    try:
        arr = np.asarray(raw, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a real number or an array of real numbers") from None
    # min() propagates NaN: one reduction, no boolean temporary of the input's size.
    if arr.size and np.isnan(_repeats_dropped(arr).min()):
        raise ValueError(f"{name} contains NaN")
    return arr


def _repeats_dropped(a: np.ndarray) -> np.ndarray:
    """A view of ``a`` without the axes along which ``np.broadcast_to`` repeats it (stride 0):
    the same set of values, so the same min and max, read once each."""
    if a.ndim and a.size > 1 and 0 in a.strides:
        return a[tuple(0 if st == 0 else slice(None) for st in a.strides)]
    return a


def _holds_bool(seq) -> bool:
    """Whether a (nested) list or tuple holds a ``bool`` (numpy reads ``[True, 2.0]`` as
    ``[1.0, 2.0]``)."""
    for v in seq:
        if isinstance(v, (bool, np.bool_)) or (isinstance(v, (list, tuple)) and _holds_bool(v)):
            return True
    return False


def as_scalar(name: str, value) -> float:
    """Return ``value`` as one float (a 0-d or one-element input), refusing arrays by name."""
    arr = as_array(name, value)
    if arr.size != 1:
        raise ValueError(f"{name} must be a single number; got an array of shape {arr.shape}")
    return float(arr.reshape(()))


def check_range(name: str, arr: np.ndarray, low: float, high: float, *,
                low_open: bool = False, high_open: bool = False) -> np.ndarray:
    """Raise ``ValueError`` unless every element lies between ``low`` and ``high``.

    Each end is closed unless ``low_open`` or ``high_open`` says it is open.
    """
    arr_ = np.asarray(arr)
    if arr_.size == 0:
        return arr
    # Two reductions, no temporaries of the input's size; the element-wise masks below only on
    # the way to an error (or when a NaN makes min/max inconclusive: NaN passes, as it always
    # has here; as_array refuses it before).
    distinct = _repeats_dropped(arr_)
    lo_v, hi_v = distinct.min(), distinct.max()
    if (lo_v > low if low_open else lo_v >= low) and (hi_v < high if high_open else hi_v <= high):
        return arr
    bad_low = arr <= low if low_open else arr < low
    bad_high = arr >= high if high_open else arr > high
    if np.any(bad_low | bad_high):
        lo = "(" if low_open else "["
        hi = ")" if high_open else "]"
        worst = np.asarray(arr)[bad_low | bad_high].flat[0]
        raise ValueError(f"{name} must lie in {lo}{low:g}, {high:g}{hi}; got {worst:g}")
    return arr


def check_positive(name: str, arr: np.ndarray, *, allow_zero: bool = False) -> np.ndarray:
    """Raise ``ValueError`` unless ``arr > 0`` (or ``>= 0`` with ``allow_zero``) and finite."""
    return check_range(name, arr, 0.0, np.inf, low_open=not allow_zero, high_open=True)


def check_modulus(name: str, arr: np.ndarray, *, allow_zero: bool = False) -> np.ndarray:
    """Raise ``ValueError`` unless every modulus lies in [:data:`MIN_MODULUS`,
    :data:`MAX_MODULUS`] GPa; with ``allow_zero`` 0 and anything below is accepted too (a
    fluid's shear modulus, a frame at porosity 1)."""
    arr_ = np.asarray(arr)
    if arr_.size == 0:
        return arr
    distinct = _repeats_dropped(arr_)
    if distinct.min() >= (0.0 if allow_zero else MIN_MODULUS) and distinct.max() <= MAX_MODULUS:
        return arr                       # no NaN either (NaN fails both comparisons)
    low = (arr_ < 0.0) if allow_zero else (arr_ < MIN_MODULUS)
    bad = low | ~(arr_ <= MAX_MODULUS)
    if np.any(bad):
        worst = arr_[bad].flat[0]
        hint = "; a modulus in Pa? (give GPa)" if worst > MAX_MODULUS else ""
        lo = "[0" if allow_zero else f"[{MIN_MODULUS:g}"
        raise ValueError(f"{name} must lie in {lo}, {MAX_MODULUS:g}] GPa; got {worst:g}{hint}")
    return arr


def check_fractions(name: str, fractions: np.ndarray, *, atol: float = 1e-6) -> np.ndarray:
    """Check volume fractions along the last axis: each in [0, 1] and summing to 1."""
    if fractions.ndim == 0 or fractions.shape[-1] == 0:
        raise ValueError(f"{name} must have the phases on its last axis (at least one)")
    check_range(name, fractions, 0.0, 1.0)
    total = sum_phases(fractions)
    # |total - 1| > atol somewhere, by two reductions (no boolean temporaries).
    off = np.subtract(total, 1.0)
    if off.size and (off.min() < -atol or off.max() > atol):
        worst = total.flat[np.argmax(np.abs(total - 1.0))]
        raise ValueError(f"{name} must sum to 1 along the last axis (phases); "
                         f"got a sum of {worst:g}")
    return fractions


def broadcast(**arrays: np.ndarray) -> list[np.ndarray]:
    """Broadcast arrays together, naming them if their shapes do not match."""
    try:
        return list(np.broadcast_arrays(*arrays.values()))
    except ValueError:
        shapes = ", ".join(f"{k} {np.shape(v)}" for k, v in arrays.items())
        raise ValueError(f"shapes do not broadcast together: {shapes}") from None


def broadcast_phases(fractions: tuple[str, np.ndarray], **arrays: np.ndarray) -> list[np.ndarray]:
    """Broadcast phase arrays (phases on the last axis) with their ``fractions``.

    As :func:`broadcast`, and the fractions keep their own number of phases: a fraction array
    with one phase never stretches over the phases of the others (``[1.0]`` against two
    minerals would count the one fraction twice and no longer sum to 1).

    Parameters
    ----------
    fractions : (str, ndarray)
        Name and value of the fractions, checked by :func:`check_fractions`.
    **arrays
        The other phase arrays, by name.

    Returns
    -------
    list of ndarray
        The fractions first, then ``arrays`` in order, all of one shape.
    """
    fname, f = fractions
    out = broadcast(**{fname: f}, **arrays)
    if out[0].shape[-1] != f.shape[-1]:
        other = next(k for k, v in arrays.items() if np.ndim(v) and np.shape(v)[-1] > 1)
        raise ValueError(f"{fname} has {f.shape[-1]} phase(s) on its last axis but {other} has "
                         f"{np.shape(arrays[other])[-1]}: give one fraction per phase")
    return out


def stack_phases(*arrays) -> np.ndarray:
    """Broadcast ``arrays`` together and stack them as phases on a new last axis."""
    return np.stack(np.broadcast_arrays(*[np.asarray(a, dtype=float) for a in arrays]), axis=-1)


def sum_phases(a: np.ndarray) -> np.ndarray:
    """Sum over the (short) phase axis, the last one.

    A column-by-column loop: for a handful of phases numpy's reduction along a short last axis
    costs a per-row overhead that is several times the arithmetic (docs/studies/bench_models.md).
    """
    out = a[..., 0].copy()
    for i in range(1, a.shape[-1]):
        out += a[..., i]
    return out


def max_phases(a: np.ndarray) -> np.ndarray:
    """Maximum over the (short) last axis, column by column (see :func:`sum_phases`)."""
    out = a[..., 0].copy()
    for i in range(1, a.shape[-1]):
        np.maximum(out, a[..., i], out=out)
    return out


def min_phases(a: np.ndarray) -> np.ndarray:
    """Minimum over the (short) last axis, column by column (see :func:`sum_phases`)."""
    out = a[..., 0].copy()
    for i in range(1, a.shape[-1]):
        np.minimum(out, a[..., i], out=out)
    return out


#: Points per block of :func:`blockwise`: a block's temporaries (8 bytes a point each) stay in
#: the cores' L2 cache (docs/studies/bench_models.md: about 2x faster than passes over 10^6
#: points, which are bound by memory bandwidth).
BLOCK = 32768


def blockwise(kernel: Callable, *args, block: int = BLOCK) -> tuple[np.ndarray, ...]:
    """``kernel(*args)`` over blocks of ``block`` points of the broadcast inputs.

    For an element-wise ``kernel`` (each element of its results depends on the same element of
    its broadcast inputs only) the values are those of ``kernel(*args)``: every element goes
    through the same operations, only fewer at a time, so that the temporaries stay in cache.
    An input of one element, or of one value repeated by broadcasting (``np.broadcast_to``),
    goes in as a 0-d array (its arithmetic stays scalar); a larger one is broadcast to the common
    shape and cut into blocks (copied once if it was not of that shape already).

    Parameters
    ----------
    kernel : callable
        Takes the arrays and returns a tuple of arrays, each broadcasting to the inputs' shape.
    *args : array_like
        Checked float inputs.
    block : int
        Points per block.

    Returns
    -------
    tuple of ndarray
        The kernel's results, each of the inputs' broadcast shape.
    """
    arrays = [np.asarray(a, dtype=float) for a in args]
    shape = np.broadcast_shapes(*(a.shape for a in arrays))
    size = 1
    for d in shape:
        size *= d
    if size <= 2 * block:
        return tuple(np.asarray(o) if np.shape(o) == shape else np.array(np.broadcast_to(o, shape))
                     for o in kernel(*arrays))
    # One element, or one value repeated by broadcasting (all strides 0): a scalar.
    flat = [a.reshape(-1)[:1].reshape(()) if a.size == 1 or not any(a.strides)
            else np.broadcast_to(a, shape).reshape(-1) for a in arrays]
    outs = None
    for i in range(0, size, block):
        part = kernel(*[a if a.ndim == 0 else a[i:i + block] for a in flat])
        if outs is None:
            outs = [np.empty(size) for _ in part]
        for o, p in zip(outs, part):
            o[i:i + block] = p
    return tuple(o.reshape(shape) for o in outs)


@contextlib.contextmanager
def prefixed_errors(prefix: str):
    """Prefix a ``ValueError`` raised inside the block with ``prefix`` and ``": "`` (the scene
    section or key that chose what failed), without the traceback of the original."""
    try:
        yield
    except ValueError as exc:
        raise ValueError(f"{prefix}: {exc}") from None


# --- labelled inputs -------------------------------------------------------------------------

_LABELLED_MODULES = ("pandas", "xarray")     # a prefix of __module__ ("pandas" in pandas 3)

#: Units of the results, as the functions' docstrings state them, written in the spelling of the
#: variable registry (``datasets/variables.toml``, UDUNITS): by NamedTuple field name, for
#: ``labelled(units=FIELD_UNITS)``.
FIELD_UNITS = {
    **dict.fromkeys(("K", "G", "K_dry", "G_dry", "K_sat", "G_sat", "K_lower", "G_lower",
                     "K_upper", "G_upper", "c11", "c13", "c33", "c44", "c66"), "GPa"),
    **dict.fromkeys(("rho", "density"), "g cm-3"),
    **dict.fromkeys(("vp", "vs"), "km s-1"),
    **dict.fromkeys(("epsilon", "gamma", "delta", "P", "Q"), "1"),
}


#: The spellings accepted for each unit an argument takes, by the unit in the spelling of the
#: variable registry (``datasets/variables.toml``, UDUNITS) first. Matched exactly (``mPa`` is
#: a millipascal, not a megapascal), after surrounding spaces are dropped.
UNIT_SPELLINGS = {
    "degC": ("degC", "degree_Celsius", "degrees_Celsius", "degree_C", "deg_C", "degreeC",
             "celsius", "Celsius", "°C", "℃"),
    "MPa": ("MPa", "megapascal", "megapascals"),
    "GPa": ("GPa", "gigapascal", "gigapascals"),
    "g cm-3": ("g cm-3", "g/cm3", "g/cm^3", "g/cm³", "g cm^-3", "g cm**-3", "g.cm-3", "g cm⁻³",
               "g/cc", "gram/centimeter^3", "g/mL", "g/ml"),
    "km s-1": ("km s-1", "km/s", "km s^-1", "km s**-1", "km.s-1", "km s⁻¹", "kilometer/second"),
    "m": ("m", "meter", "metre", "meters", "metres"),
    "degree": ("degree", "degrees", "deg", "°", "arc_degree"),
    "1": ("1", "fraction", "dimensionless", ""),
    "L/L": ("L/L", "l/l", "L L-1", "m3/m3", "m3 m-3", "1", "dimensionless", ""),
    "degAPI": ("degAPI", "API", "°API", "deg_API", "degree_API", "degrees_API"),
}

#: The unit of each argument of the labelled functions, by argument name (the names mean one
#: thing across the modules; their docstrings state these units). An argument whose labelled
#: value carries ``attrs["units"]`` must carry a spelling of its unit (:data:`UNIT_SPELLINGS`).
#: A function where a name means something else says so with ``labelled(input_units=...)``.
#: The names that are also variables of ``datasets/variables.toml`` have its units there
#: (tests/test_labelled.py checks both that and the docstrings).
INPUT_UNITS = {
    **dict.fromkeys(("K", "G", "K0", "G0", "Kc", "Gc", "K_m", "G_m", "K_i", "G_i", "K_min",
                     "G_min", "K_dry", "G_dry", "K_sat", "K_fluid", "K_fluids", "K_frame",
                     "K_solid", "G_solid", "K_brine", "K_hydrocarbon", "c11", "c13", "c33",
                     "c44", "c66"), "GPa"),
    **dict.fromkeys(("vp1", "vs1", "vp2", "vs2", "v1", "v2"), "km s-1"),
    "angle": "degree",
    "intercept": "1",
    **dict.fromkeys(("rho", "rho1", "rho2", "density", "mineral_density", "fluid_density", "rho_brine",
                     "rho_hydrocarbon", "reference_density"), "g cm-3"),
    **dict.fromkeys(("pressure", "delta"), "MPa"),
    "temperature": "degC",
    **dict.fromkeys(("phi", "phic", "phib", "porosity", "critical_porosity", "cement_fraction",
                     "contact_cement_limit", "fractions", "solid_fractions", "saturations",
                     "water_saturation", "salinity", "aspect_ratio", "n", "coordination_number",
                     "alpha", "thickness", "Lambda", "A", "f", "exponent", "gravity",
                     "gas_gravity"), "1"),
    "gas_oil_ratio": "L/L",
    "api": "degAPI",
}

#: Arguments of the labelled functions that are not physical quantities (materials, choices,
#: solver settings): never given as labelled arrays, so no unit is checked.
NOT_QUANTITIES = frozenset(("minerals", "grain", "cement", "fluid", "scheme", "stiffness",
                            "panels", "chunk", "tol", "max_iter", "full_output", "engine",
                            "terms", "threshold"))

_SPELLING_OF = {unit: frozenset(spellings) for unit, spellings in UNIT_SPELLINGS.items()}


def _check_input_units(func, bound, names, expected):
    """Refuse a labelled argument whose ``attrs["units"]`` is not a spelling of its unit."""
    for name in names:
        attrs = getattr(bound.arguments[name], "attrs", None)
        if not isinstance(attrs, Mapping) or attrs.get("units") is None:
            continue
        unit = expected.get(name)
        if unit is None:
            continue
        given = attrs["units"]
        if not isinstance(given, str) or given.strip() not in _SPELLING_OF[unit]:
            shown = ", ".join(repr(s) for s in UNIT_SPELLINGS[unit][:4])
            raise ValueError(f"{func.__name__}: {name} has units {given!r} but takes {unit} "
                             f"(spelled {shown}, ...); convert the values to {unit} first "
                             "or, if they are already in that unit, set "
                             f"attrs['units'] to {unit!r}")


def labelled(func: Callable | None = None, *, units: str | Mapping[str, str] | None = None,
             phases: tuple[str, ...] = (), input_units: Mapping[str, str] | None = None):
    """Let a numpy function take pandas and xarray inputs and return the type it was given.

    The one mechanism for labels in the project (as MetPy's and xclim's decorators): the function
    below it sees numpy arrays only. With no pandas or xarray argument the call goes straight
    through after a check of each argument's type (1–2 µs a call, against 80 µs and more for the
    smallest call it wraps, measured on the same loaded machine).

    - **pandas**: ``Series`` are aligned by index label, not position (two Series with the same
      labels in different orders are paired by label); the result is a ``Series`` on the first
      one's index (a NamedTuple of ``Series`` for a NamedTuple result).
    - **xarray**: ``DataArray`` are broadcast by dimension name, and aligned by coordinate label
      along a dimension they share; the result is a ``DataArray`` over the union of their
      dimensions (in the order the arguments bring them), with their coordinates (a NamedTuple
      of ``DataArray`` for a NamedTuple result).
    - **Phases** (the arguments named in ``phases``, phases on the last axis in numpy): a pandas
      ``DataFrame`` has one row per sample and one column per phase, a ``Series`` one entry per
      phase; a ``DataArray`` has its phases along its last dimension. Phase labels are aligned
      like the others. A result per phase (as :func:`rockcem.frames.krief_multimineral`'s) is a
      ``DataFrame`` with those columns, or a ``DataArray`` with that last dimension (named
      ``phase`` when no phase input was a ``DataArray``).

    Labels that differ (a label in one input and not in another, a repeated label that cannot be
    paired) are refused by name, never filled with NaN or dropped. A numpy array given alongside
    labelled inputs broadcasts by position, as it does in pandas and xarray; one that would add
    dimensions to the result is refused. pandas and xarray inputs cannot be mixed in one call.

    Parameters
    ----------
    func : callable
        The numpy function (the decorator may be used bare or with keywords).
    units : str or mapping, optional
        The unit of the result as its documentation states it: one string for every array of the
        result, or a mapping from a NamedTuple field to its unit. Written to the result's
        ``attrs["units"]`` when an input carried ``attrs["units"]``.
    phases : tuple of str
        The arguments with phases on their last axis.
    input_units : mapping, optional
        The unit of an argument where it differs from :data:`INPUT_UNITS` for its name (a key
        of :data:`UNIT_SPELLINGS`).

    Notes
    -----
    **Units of the inputs.** A labelled argument that carries ``attrs["units"]`` (a
    ``DataArray``, or a pandas object with ``.attrs``) must carry a spelling of the unit the
    function takes for it (:data:`INPUT_UNITS`, :data:`UNIT_SPELLINGS`: ``degree_Celsius``,
    ``°C`` or ``celsius`` for a temperature; ``MPa`` for a pressure; ``g/cm3`` or ``g/cc`` for
    a density); another unit (``K``, ``kPa``, ``kg m-3``) is refused by name, never taken as
    the function's. Inputs without ``attrs["units"]`` are taken in the documented units.
    """
    if func is None:
        return functools.partial(labelled, units=units, phases=phases, input_units=input_units)
    signature = inspect.signature(func)
    phases = frozenset(phases)
    unknown = phases.difference(signature.parameters)
    if input_units:
        unknown |= set(input_units).difference(signature.parameters)
        bad = {v for v in input_units.values() if v not in UNIT_SPELLINGS}
        if bad:
            raise TypeError(f"labelled({func.__name__}): input_units {sorted(bad)} are not "
                            f"units of UNIT_SPELLINGS ({', '.join(UNIT_SPELLINGS)})")
    if unknown:
        raise TypeError(f"labelled({func.__name__}): no argument named {sorted(unknown)}")
    expected = {name: (input_units or {}).get(name, INPUT_UNITS.get(name))
                for name in signature.parameters}
    expected = {k: v for k, v in expected.items() if v is not None}

    @functools.wraps(func)
    def wrapper(*args, **kwargs):
        for v in args:
            if type(v).__module__.startswith(_LABELLED_MODULES):
                break
        else:
            for v in kwargs.values():
                if type(v).__module__.startswith(_LABELLED_MODULES):
                    break
            else:
                return func(*args, **kwargs)
        bound = signature.bind(*args, **kwargs)
        return _call_labelled(func, bound, units, phases, expected)

    wrapper.input_units = expected       # what the decorator checks, by argument (read-only use)
    return wrapper


def _call_labelled(func, bound, units, phases, expected):
    """Unwrap the labelled arguments of ``bound``, call ``func`` on numpy and re-wrap."""
    kinds = {}
    for name, v in bound.arguments.items():
        package = type(v).__module__.partition(".")[0]
        if package in _LABELLED_MODULES:
            kinds[name] = package
    if not kinds:            # a package whose name merely starts alike
        return func(*bound.args, **bound.kwargs)
    if len(set(kinds.values())) > 1:
        pd_names = [k for k, v in kinds.items() if v == "pandas"]
        xr_names = [k for k, v in kinds.items() if v == "xarray"]
        raise ValueError(f"{func.__name__}: {', '.join(pd_names)} given as pandas and "
                         f"{', '.join(xr_names)} as xarray; give all labelled inputs as one kind "
                         "(e.g. xarray.DataArray.from_series, or DataArray.to_series())")
    _check_input_units(func, bound, kinds, expected)
    has_units = any(_has_units(bound.arguments[k]) for k in kinds)
    if "pandas" in kinds.values():
        return _call_pandas(func, bound, list(kinds), phases, units if has_units else None)
    return _call_xarray(func, bound, list(kinds), phases, units if has_units else None)


def _has_units(v) -> bool:
    attrs = getattr(v, "attrs", None)
    return isinstance(attrs, Mapping) and bool(attrs.get("units"))


def _pairing(what: str, named):
    """Positions that put each labelled index of ``named`` [(argument, pandas.Index)] in the
    order of the first one (``None`` where it is already), refusing labels that differ."""
    ref_name, ref = named[0]
    out = [None]
    for name, idx in named[1:]:
        if idx.equals(ref):
            out.append(None)
            continue
        if ref.has_duplicates or idx.has_duplicates:
            raise ValueError(f"{name} and {ref_name} are labelled differently along {what} and "
                             "one of them repeats a label, so they cannot be paired by label; "
                             "give them the same index")
        perm = idx.get_indexer(ref)
        if len(idx) != len(ref) or (perm < 0).any():
            extra = idx[~idx.isin(ref)]
            where, other, only = (name, ref_name, extra) if len(extra) else \
                (ref_name, name, ref[~ref.isin(idx)])
            raise ValueError(f"{name} and {ref_name} do not have the same labels along {what}: "
                             f"{len(only)} label(s) of {where} are not in {other} (e.g. "
                             f"{only[0]!r}); select the common labels first (e.g. "
                             "a, b = a.align(b, join='inner'))")
        out.append(perm)
    return out


def _check_result_shape(func, out_shape, shape, what):
    if out_shape != shape:
        raise ValueError(f"{func.__name__}: the labelled inputs span {what} but the result has "
                         f"shape {out_shape}: a numpy array given with them added dimensions; give "
                         "it labelled too")


def _rewrap(out, wrap, units, field=None):
    """Apply ``wrap(array, field, unit)`` to every array in ``out`` (nested tuples kept, a
    NamedTuple as its own type)."""
    if isinstance(out, tuple):
        fields = getattr(out, "_fields", None)
        items = [_rewrap(v, wrap, units, fields[i] if fields else None)
                 for i, v in enumerate(out)]
        return type(out)._make(items) if fields else tuple(items)
    if isinstance(out, (np.ndarray, np.generic, float, int)):
        if units is None:
            unit = None
        elif isinstance(units, str):
            unit = units
        else:
            unit = units.get(field)
        return wrap(np.asarray(out), field, unit)
    return out


def _call_pandas(func, bound, names, phases, units):
    import pandas as pd

    samples, phase_labels = [], []
    for name in names:
        v = bound.arguments[name]
        if isinstance(v, pd.DataFrame):
            if name not in phases:
                raise ValueError(f"{name} is a DataFrame but takes one value per sample: give a "
                                 "Series (one column of the DataFrame)")
            samples.append((name, v.index))
            phase_labels.append((name, v.columns))
        elif isinstance(v, pd.Series):
            (phase_labels if name in phases else samples).append((name, v.index))
        else:
            raise ValueError(f"{name} is a pandas {type(v).__name__}: give a Series (or, for "
                             "phases, a DataFrame with one column per phase)")
    values = {name: bound.arguments[name].to_numpy() for name in names}
    if samples:
        for (name, _), perm in zip(samples, _pairing("the index", samples)):
            if perm is not None:
                values[name] = values[name][perm]
    if phase_labels:
        for (name, _), perm in zip(phase_labels, _pairing("the phases", phase_labels)):
            if perm is not None:
                values[name] = values[name][..., perm]
    bound.arguments.update(values)
    out = func(*bound.args, **bound.kwargs)
    if not samples:          # phases only: the phase axis is summed away, nothing to label
        return out
    index = samples[0][1]
    columns = phase_labels[0][1] if phase_labels else None

    def wrap(a, field, unit):
        if a.shape == ():
            a = np.full(len(index), a[()])
        if phases and a.ndim == 2 and a.shape[0] == len(index):     # per phase, as K_frame
            s = pd.DataFrame(a, index=index, columns=columns if columns is not None
                             and len(columns) == a.shape[1] else None)
        else:
            _check_result_shape(func, a.shape, (len(index),), f"an index of {len(index)} labels")
            s = pd.Series(a, index=index, name=field)
        if unit:
            s.attrs["units"] = unit
        return s

    return _rewrap(out, wrap, units)


def _call_xarray(func, bound, names, phases, units):
    import xarray as xr

    arrays = {}
    for name in names:
        v = bound.arguments[name]
        if isinstance(v, xr.Dataset):
            raise ValueError(f"{name} is an xarray Dataset: give one of its variables "
                             f"(ds[{name!r}] or the like)")
        if not isinstance(v, xr.DataArray):
            raise ValueError(f"{name} is an xarray {type(v).__name__}: give a DataArray")
        arrays[name] = v
    phase_dim, phase_from = None, None
    for name, da in arrays.items():
        if name in phases:
            if da.ndim == 0:
                raise ValueError(f"{name} has its phases along its last dimension; got a "
                                 "DataArray with no dimension")
            if phase_dim is None:
                phase_dim, phase_from = da.dims[-1], name
            elif da.dims[-1] != phase_dim:
                raise ValueError(f"{name} has its phases along its last dimension "
                                 f"{da.dims[-1]!r} but {phase_from} along {phase_dim!r}: name "
                                 "the phase dimension alike and put it last")
    for name, da in arrays.items():
        if name not in phases and phase_dim is not None and phase_dim in da.dims:
            raise ValueError(f"{name} takes one value per sample but has the phase dimension "
                             f"{phase_dim!r} (of {phase_from})")
    # align by label along each dimension with an index; sizes must agree along the others
    sizes: dict = {}
    for name, da in arrays.items():
        for d, n in da.sizes.items():
            if d in sizes and sizes[d][1] != n:
                raise ValueError(f"{name} and {sizes[d][0]} have {n} and {sizes[d][1]} entries "
                                 f"along dimension {d!r}")
            sizes.setdefault(d, (name, n))
    for d in sizes:
        named = [(name, da.indexes[d]) for name, da in arrays.items() if d in da.indexes]
        if len(named) > 1:
            for (name, _), perm in zip(named, _pairing(f"dimension {d!r}", named)):
                if perm is not None:
                    arrays[name] = arrays[name].isel({d: perm})
    dims = tuple(d for d in sizes if d != phase_dim)
    shape = tuple(sizes[d][1] for d in dims)
    values = {}
    for name, da in arrays.items():
        own = [d for d in dims if d in da.dims]
        tail = [phase_dim] if name in phases else []
        data = da.transpose(*own, *tail).values
        values[name] = data.reshape([sizes[d][1] if d in da.dims else 1 for d in dims]
                                    + ([data.shape[-1]] if tail else []))
    coords, phase_coords = {}, {}
    for da in arrays.values():
        for c, var in da.coords.items():
            if phase_dim is not None and phase_dim in var.dims:
                if var.dims == (phase_dim,):
                    phase_coords.setdefault(c, var)
            elif c not in coords:
                coords[c] = var
    bound.arguments.update(values)
    out = func(*bound.args, **bound.kwargs)
    if not dims and all(name in phases for name in arrays):
        return out           # phases only: the phase axis is summed away, nothing to label

    def wrap(a, field, unit):
        if a.shape == ():
            a = np.full(shape, a[()])
        if phases and a.ndim == len(shape) + 1 and a.shape[:-1] == shape:  # per phase: K_frame
            labelled_phases = phase_dim is not None and sizes[phase_dim][1] == a.shape[-1]
            return xr.DataArray(a, dims=(*dims, phase_dim if labelled_phases else "phase"),
                                coords={**coords, **phase_coords} if labelled_phases else coords,
                                name=field, attrs={"units": unit} if unit else {})
        _check_result_shape(func, a.shape, shape, f"dimensions {dims} of shape {shape}")
        return xr.DataArray(a, dims=dims, coords=coords, name=field,
                            attrs={"units": unit} if unit else {})

    return _rewrap(out, wrap, units)
