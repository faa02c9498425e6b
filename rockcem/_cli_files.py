"""The files the ``rockcem`` commands read and write: :func:`output_file`, the check every
command makes of each file it will write, before any work; :func:`unasked_output`, the check of
a file a run writes without being asked by name (the scene's output); :func:`stage_folder`, the
check of an MD stage folder; :func:`no_such_file`, the message for a file name that does not
exist, with the closest name of its folder."""

from __future__ import annotations

from pathlib import Path

__all__ = ["no_such_file", "output_file", "stage_folder", "unasked_output"]


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


#: The Dataset attribute naming the scene file a run of ``rockcem run`` came from (absolute
#: path): :func:`unasked_output` lets a run replace only its own scene's earlier output.
SCENE_FILE_ATTR = "scene_file"


def unasked_output(out, scene_file):
    """Check the file a run writes by default (the scene's ``output``, else ``<name>.nc``; no
    ``-o``) before the run: it may replace only an earlier output of the same scene file.

    An output never destroys a file it was not asked to write: a copied scene keeps its
    ``name``, and would replace the output of the scene it was copied from.

    Parameters
    ----------
    out : path-like
        The default output file.
    scene_file : path-like
        The scene file being run.

    Raises
    ------
    ValueError
        One line, for an existing ``out`` that is not a rockcem output, or is the output of
        another scene file (its attribute :data:`SCENE_FILE_ATTR`). An output written before
        that attribute existed is replaced, as it always was.
    """
    import xarray as xr

    path = Path(out)
    if not path.is_file():
        return
    try:
        with xr.open_dataset(path, engine="netcdf4") as ds:
            attrs = dict(ds.attrs)
    except Exception:  # noqa: BLE001 (any file netCDF cannot open is not ours to replace)
        attrs = {}
    ours = SCENE_FILE_ATTR in attrs or "scene_toml" in attrs or \
        str(attrs.get("title", "")).startswith("rockcem")
    if not ours:
        raise ValueError(f"output file {out} exists and is not the output of a rockcem run; "
                         f"the run would replace it: give -o FILE, or move it away")
    made_by = attrs.get(SCENE_FILE_ATTR)
    here = str(Path(scene_file).resolve())
    if made_by is not None and str(made_by) != here:
        raise ValueError(f"output file {out} exists and is the output of another scene file, "
                         f"{made_by} (a scene of the same name or output); the run would "
                         f"replace it: give -o FILE, or another name or output in {scene_file}")


def stage_folder(folder, out, *, what):
    """Check the folder of the MD stage files before the run: not an existing file (nor under
    one), not the output file.

    Parameters
    ----------
    folder, out : path-like
        The stage folder and the output file of the run.
    what : str
        The setting that names the folder, as messages say it (``"models.md.workdir"``).

    Raises
    ------
    ValueError
        One line naming ``what``.
    """
    import os

    path = Path(folder)
    if not str(folder).strip():
        raise ValueError(f"{what} must name a folder; got {str(folder)!r}")
    if os.path.realpath(path) == os.path.realpath(out):
        raise ValueError(f"{what} {str(folder)!r} is the output file (-o): the stage files "
                         f"need a folder of their own")
    for parent in (path, *path.parents):
        if parent.exists() and not parent.is_dir():
            kind = "is a file" if parent == path else f"lies under the file {parent}"
            raise ValueError(f"{what} {str(folder)!r} {kind}: it must be a folder (made if "
                             f"missing)")
