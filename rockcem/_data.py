"""Locate the data files of ``datasets/`` whether installed (wheel) or in a source checkout."""

from __future__ import annotations

import tomllib
from functools import lru_cache
from pathlib import Path

__all__ = ["data_path", "find_file", "read_toml"]


@lru_cache(maxsize=1)
def _root() -> Path:
    here = Path(__file__).resolve().parent
    installed = here / "_datasets"            # the wheel maps datasets/ to rockcem/_datasets
    if (installed / "materials").is_dir():
        return installed
    checkout = here.parent / "datasets"
    if checkout.is_dir():
        return checkout
    raise FileNotFoundError("the rockcem datasets folder is missing from this installation")


def data_path(*parts: str) -> Path:
    """Path of a file under ``datasets/``, e.g. ``data_path("materials", "minerals.toml")``."""
    path = _root().joinpath(*parts)
    if not path.exists():
        raise FileNotFoundError(f"no dataset file {'/'.join(parts)} under {_root()}")
    return path


@lru_cache(maxsize=None)
def read_toml(*parts: str) -> dict:
    """Parsed TOML file under ``datasets/`` (cached; treat the result as read-only)."""
    with open(data_path(*parts), "rb") as fh:
        return tomllib.load(fh)


def find_file(name, base_dir=None, shipped=None) -> tuple[Path | None, str]:
    """A file a scene names: ``name`` if absolute; else relative to ``base_dir`` (the scene
    file's folder), then to the working directory, then ``shipped`` (a path in ``datasets/``,
    for a bare name that is a shipped file's).

    Returns the first of them that is a file (``None`` if none is) and the places looked at,
    each once (the scene's folder may be the working directory), absolute and saying what
    each is relative to, for the message of a missing file.
    """
    given = Path(str(name))
    places = [("", given)] if given.is_absolute() else (
        ([("the scene file's folder", Path(base_dir) / given)] if base_dir is not None else [])
        + [("the working directory", Path.cwd() / given)])
    if shipped is not None and not given.is_absolute():
        places.append(("the shipped data", Path(shipped)))
    unique = []
    for where, p in places:
        same = next((k for k, (_, q) in enumerate(unique) if q.resolve() == p.resolve()), None)
        if same is None:
            unique.append((where, p))
        else:
            unique[same] = (f"{unique[same][0]} and {where}", unique[same][1])
    found = next((p for _, p in unique if p.is_file()), None)
    looked = "; ".join(f"{p.resolve()} ({where})" if where else str(p) for where, p in unique)
    return found, looked
