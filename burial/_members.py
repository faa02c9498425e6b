"""Checks of per-path parameters given as arrays (one value per member of an ensemble): a bad
element is refused by the argument's name and its index, ``gradient[3]``."""

from __future__ import annotations

import numpy as np

from rockcem.validation import as_array, check_range

__all__ = ["member_values", "element_name"]


def element_name(name, mask):
    """``name`` for a scalar, ``name[i]`` (``name[i, j]``) for the first True element of
    ``mask``, an array of the argument's shape."""
    mask = np.asarray(mask)
    if mask.ndim == 0:
        return name
    index = tuple(int(i) for i in np.argwhere(mask)[0])
    return f"{name}[{', '.join(map(str, index))}]"


def member_values(name, value, low, high, *, low_open=False, high_open=False):
    """``value`` as a float array with every element in the range ``low``–``high``.

    As :func:`rockcem.validation.as_array` and :func:`rockcem.validation.check_range`, and an
    array's NaN or out-of-range element is named with its index (``gradient[3] must lie in
    (0, inf); got -1``), so that the member it belongs to can be found.

    Raises
    ------
    ValueError
        Naming ``name`` (with the index of the first bad element of an array).
    """
    raw = None
    if isinstance(value, (list, tuple, np.ndarray)) and not isinstance(value, np.ma.MaskedArray):
        try:
            raw = np.asarray(value)
        except (TypeError, ValueError):      # ragged: as_array names it
            raw = None
    if raw is not None and raw.dtype.kind == "f" and raw.ndim and raw.size \
            and np.isnan(raw.min()):
        raise ValueError(f"{element_name(name, np.isnan(raw))} is NaN")
    arr = as_array(name, value)
    if arr.ndim == 0:
        return check_range(name, arr, low, high, low_open=low_open, high_open=high_open)
    bad = (arr <= low if low_open else arr < low) | (arr >= high if high_open else arr > high)
    if np.any(bad):
        lo, hi = "(" if low_open else "[", ")" if high_open else "]"
        raise ValueError(f"{element_name(name, bad)} must lie in {lo}{low:g}, {high:g}{hi}; "
                         f"got {arr[bad].flat[0]:g}")
    return arr
