"""Atomic saving of figures."""

from __future__ import annotations

from pathlib import Path

from .._atomic import atomic_write


from ._style import (_SUFFIX_FORMATS)

__all__ = ["save_figure"]


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
        Destination, ending in ``.png``, ``.pdf`` or ``.svg``; its folder must exist.
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
        fmt = _SUFFIX_FORMATS.get(path.suffix.lower())
        if fmt is None:
            raise ValueError(f"path must end in {', '.join(_SUFFIX_FORMATS)}; got {str(path)!r}")
        if not dpi > 0:
            raise ValueError(f"dpi must be > 0; got {dpi!r}")
        folder = path.parent
        if not folder.is_dir():
            raise ValueError(f"folder {str(folder)!r} does not exist")
        atomic_write(path, lambda tmp: fig.savefig(tmp, format=fmt, dpi=dpi,
                                                   bbox_inches="tight"))
    finally:
        plt.close(fig)
    return path
