"""TOML for rockcem: one value writer for the files it writes (scene texts, calibration
files) and one reader of the text of a TOML file it reads (:func:`toml_text`)."""

from __future__ import annotations

import json

import numpy as np


def toml_value(v) -> str:
    """``v`` as a TOML value: booleans, integers, floats (``inf``, ``nan`` included), strings and
    lists or tuples of them; numpy scalars are written as the Python scalars they hold (a
    numpy float as the decimal it prints as: ``np.float32(0.05)`` as ``0.05``).

    Raises
    ------
    ValueError
        For any other type.
    """
    if isinstance(v, (bool, np.bool_)):
        return "true" if v else "false"
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    if isinstance(v, np.floating):             # np.float32(0.05) as the 0.05 it prints as
        return repr(float(str(v)))
    if isinstance(v, float):
        return repr(v)                         # inf, -inf and nan are TOML's spellings too
    if isinstance(v, str):
        return json.dumps(v, ensure_ascii=False)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    raise ValueError(f"cannot write {v!r} as TOML")


def toml_text(path, what) -> str:
    """The text of a TOML file: UTF-8 (TOML 1.0, "a TOML file must be a valid UTF-8 encoded
    Unicode document"), a leading byte-order mark dropped (Windows editors write one; the
    parser would take it for the start of a key).

    Parameters
    ----------
    path : path-like
        The file.
    what : str
        The file as messages name it, e.g. ``"scene file scene.toml"``.

    Raises
    ------
    ValueError
        One line naming the file, the line and the byte, for a file that is not UTF-8 (such as
        a latin-1 ``é``).
    """
    data = open(path, "rb").read()
    if data.startswith(b"\xef\xbb\xbf"):
        data = data[3:]
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data[:exc.start].count(b"\n") + 1
        raise ValueError(f"{what} is not UTF-8, as TOML must be: line {line} has the byte "
                         f"0x{data[exc.start]:02x}; save the file as UTF-8") from None
