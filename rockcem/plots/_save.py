"""Atomic saving of figures."""

from __future__ import annotations

from pathlib import Path

from .._atomic import atomic_write, output_path
from ._style import _SUFFIX_FORMATS

__all__ = ["figure_path", "save_figure"]


def figure_path(path, *, what="path") -> Path:
    """Check a figure file to write, before the figure is drawn.

    Parameters
    ----------
    path : str or os.PathLike
        Destination, ending in ``.png``, ``.pdf`` or ``.svg``: a regular file that may be
        written or a new name in an existing writable folder (a symbolic link is written
        through to its target; :func:`rockcem._atomic.output_path`).
    what : str, keyword-only
        How the messages name it, e.g. ``"--figure"``.

    Returns
    -------
    pathlib.Path
        The absolute path of the file that will be written.

    Raises
    ------
    ValueError
        One line naming ``what``: another suffix, a missing or read-only folder, a folder, FIFO
        or device node in the way, an empty name.

    Examples
    --------
    >>> figure_path("x.xyz", what="--figure")
    Traceback (most recent call last):
    ...
    ValueError: --figure must end in .png, .pdf, .svg; got 'x.xyz'
    """
    real = output_path(path, what=what, folder_must_exist=True)
    if Path(path).suffix.lower() not in _SUFFIX_FORMATS:
        raise ValueError(f"{what} must end in {', '.join(_SUFFIX_FORMATS)}; got {str(path)!r}")
    return real


def save_figure(fig, path, *, dpi=150):
    """Write a figure to PNG, PDF or SVG (by the suffix) atomically, then close it.

    The figure is written to a temporary file in the destination folder and moved into place
    with :func:`os.replace`, so ``path`` is either the old file or the complete new one, never
    a partial file; on failure the temporary file is removed and the error re-raised. The
    figure is closed in every case.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure.
    path : str or os.PathLike
        Destination, ending in ``.png``, ``.pdf`` or ``.svg``; its folder must exist
        (:func:`figure_path`; a symbolic link is written through to its target).
    dpi : float, optional
        Resolution of raster output, dots per inch; default 150.

    Returns
    -------
    pathlib.Path
        ``path``.

    Examples
    --------
    >>> import os, tempfile
    >>> import matplotlib.pyplot as plt
    >>> fig, ax = plt.subplots()
    >>> _ = ax.plot([0, 1], [0, 1])
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     out = save_figure(fig, os.path.join(folder, "line.png"))
    ...     sorted(os.listdir(folder))
    ['line.png']
    """
    import matplotlib.pyplot as plt

    path = Path(path)
    try:
        figure_path(path)
        fmt = _SUFFIX_FORMATS[path.suffix.lower()]
        if not dpi > 0:
            raise ValueError(f"dpi must be > 0; got {dpi!r}")
        atomic_write(path, lambda tmp: fig.savefig(tmp, format=fmt, dpi=dpi,
                                                   bbox_inches="tight"))
    finally:
        plt.close(fig)
    return path
