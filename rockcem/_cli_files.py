"""The files the ``rockcem`` commands read and write: :func:`output_file`, the check every
command makes of each file it will write, before any work; :func:`no_such_file`, the message
for a file name that does not exist, with the closest name of its folder."""

from __future__ import annotations

from pathlib import Path

__all__ = ["no_such_file", "output_file"]


def no_such_file(source) -> str:
    """``no such file: SOURCE``, with the closest name in its folder when one is close
    ("did you mean ...?"), as scene names and keys get."""
    import difflib

    path = Path(source)
    folder = path.parent if str(path.parent) else Path(".")
    try:
        names = [p.name for p in folder.iterdir() if p.is_file()]
    except OSError:
        names = []
    close = difflib.get_close_matches(path.name, names, n=1, cutoff=0.7)
    hint = f"; did you mean {str(folder / close[0]) if str(path.parent) != '.' else close[0]}?" \
        if close else ""
    return f"no such file: {source}{hint}"


def output_file(given, default, *, what="-o", figure=False):
    """The file a command will write, checked before any work.

    Parameters
    ----------
    given : str or None
        The option's value; ``""`` is refused, never taken for "not given".
    default : str or os.PathLike
        The file written when the option is not given.
    what : str, keyword-only
        The option, as messages name it (``"-o"``, ``"--figure"``); a default is named
        "output file".
    figure : bool, keyword-only
        Check a figure (:func:`rockcem.plots.figure_path`: suffix ``.png``, ``.pdf`` or
        ``.svg`` and an existing folder) instead of a data file
        (:func:`rockcem._atomic.output_path`).

    Returns
    -------
    str or os.PathLike
        ``given``, else ``default``, as given (for the "wrote ..." line).

    Raises
    ------
    ValueError
        One line, unless the file is a regular file that may be written or a new name in a
        writable folder (a symbolic link is written through to its target and kept).
    """
    if figure:
        from .plots import figure_path as check
    else:
        from ._atomic import output_path as check

    out = default if given is None else given
    check(out, what=what if given is not None else "output file")
    return out
