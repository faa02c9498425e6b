"""Input checking shared by every package (the shared base: imports numpy only).

One rule for the whole project: bad input raises ``ValueError`` naming the argument and the
valid range; nothing returns NaN or a complex number silently. With :mod:`rockcem.constants`
and :mod:`rockcem.variables` this is the floor that ``burial``, the ``rockcem`` models and ``md``
build on; it imports none of them, nor the scene layer.
"""

from __future__ import annotations

import contextlib

import numpy as np

__all__ = ["MAX_DENSITY", "MIN_DENSITY", "MAX_MODULUS", "MIN_MODULUS", "as_array", "as_scalar",
           "prefixed_errors",
           "check_range", "check_positive", "check_modulus", "check_fractions", "broadcast",
           "broadcast_phases", "stack_phases", "sum_phases", "max_phases", "min_phases"]

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
    text is a mistake upstream), complex values and NaN. Infinities pass here; the range
    checks below refuse them.
    """
    if value is None:
        raise ValueError(f"{name} must be a real number, got None")
    if isinstance(value, (str, bytes)):
        raise ValueError(f"{name} must be a real number, got text {value!r}")
    try:
        raw = np.asarray(value)
    except (TypeError, ValueError):          # ragged nested sequences
        raise ValueError(f"{name} must be a real number or a rectangular array of real "
                         "numbers") from None
    if raw.dtype.kind in "USO" and any(isinstance(v, (str, bytes)) for v in raw.flat):
        raise ValueError(f"{name} must be a real number, got text {value!r}")
    if raw.dtype.kind == "c" or (raw.dtype.kind == "O"
                                 and any(isinstance(v, complex) for v in raw.flat)):
        raise ValueError(f"{name} must be real, got a complex value")
    try:
        arr = np.asarray(raw, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a real number or an array of real numbers") from None
    if np.isnan(arr).any():
        raise ValueError(f"{name} contains NaN")
    return arr


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
    if np.any(np.abs(total - 1.0) > atol):
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


@contextlib.contextmanager
def prefixed_errors(prefix: str):
    """Prefix a ``ValueError`` raised inside the block with ``prefix`` and ``": "`` (the scene
    section or key that chose what failed), without the traceback of the original."""
    try:
        yield
    except ValueError as exc:
        raise ValueError(f"{prefix}: {exc}") from None
