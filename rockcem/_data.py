"""Locate the data files of ``datasets/`` whether installed (wheel) or in a source checkout."""

from __future__ import annotations

import tomllib
from functools import lru_cache
from pathlib import Path

__all__ = ["data_path", "read_toml"]


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
