"""One TOML value writer for the files rockcem writes (scene texts, calibration files)."""

from __future__ import annotations

import json

import numpy as np


def toml_value(v) -> str:
    """``v`` as a TOML value: booleans, integers, floats (``inf``, ``nan`` included), strings and
    lists or tuples of them; numpy scalars are written as the Python scalars they hold.

    Raises
    ------
    ValueError
        For any other type.
    """
    if isinstance(v, (bool, np.bool_)):
        return "true" if v else "false"
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    if isinstance(v, (float, np.floating)):
        return repr(float(v))                  # inf, -inf and nan are TOML's spellings too
    if isinstance(v, str):
        return json.dumps(v, ensure_ascii=False)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    raise ValueError(f"cannot write {v!r} as TOML")
