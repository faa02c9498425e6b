"""The state of a grain pack between stages, saved to and loaded from netCDF.

Each MD stage (settle, compact, cement, pulse test) returns a :class:`Pack`; saving it after a
stage lets a long run resume from its last finished stage. SI units throughout (m, kg, s, Pa).
Files are written atomically (temporary file, then rename), so an interrupted save never leaves
a half-written stage behind.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .contact import GrainMaterial
from .space import Box

__all__ = ["Pack", "save_pack", "load_pack"]


@dataclass(frozen=True)
class Pack:
    """A grain pack at the end of a stage.

    Attributes
    ----------
    positions, velocities, angular_velocities : ndarray, shape (N, 3)
        m, m/s, rad/s.
    radii : ndarray, shape (N,)
        m.
    box : Box
    material : GrainMaterial
    pairs : ndarray, shape (M, 2), int32
        Neighbour pairs the tangential histories refer to.
    history : ndarray, shape (M, 3)
        Tangential spring elongations of those pairs, m.
    stage : str
        Name of the stage that produced the pack (``"settle"``, ``"compact"``, …).
    time : float
        Simulated time at the end of the stage, s.
    metadata : dict
        JSON-serialisable extra information (seed, parameters, diagnostics).
    overlap_dissolved : ndarray, shape (M,), optional
        Part of each pair's overlap removed by pressure solution, m (:func:`md.reconstruct`):
        the grains are truncated there and only the rest of the overlap is elastic. None (a
        pack of elastic spheres): every overlap is elastic.
    """

    positions: np.ndarray
    velocities: np.ndarray
    angular_velocities: np.ndarray
    radii: np.ndarray
    box: Box
    material: GrainMaterial
    pairs: np.ndarray
    history: np.ndarray
    stage: str = ""
    time: float = 0.0
    metadata: dict = field(default_factory=dict)
    overlap_dissolved: np.ndarray | None = None

    def __post_init__(self):
        n = self.radii.shape[0] if np.ndim(self.radii) == 1 else -1
        for name in ("positions", "velocities", "angular_velocities"):
            if np.shape(getattr(self, name)) != (n, 3):
                raise ValueError(f"{name} must have shape (N, 3) with N = len(radii)")
        if np.shape(self.pairs)[1:] != (2,) or np.shape(self.history) != (len(self.pairs), 3):
            raise ValueError("pairs must have shape (M, 2) and history (M, 3)")
        if self.overlap_dissolved is not None and (
                np.shape(self.overlap_dissolved) != (len(self.pairs),)
                or not np.all(np.asarray(self.overlap_dissolved) >= 0)):
            raise ValueError("overlap_dissolved must have shape (M,) (one per pair) and be "
                             ">= 0 m")

    @property
    def n_grains(self) -> int:
        """Number of grains."""
        return int(self.radii.shape[0])


def save_pack(pack: Pack, path) -> Path:
    """Write a pack to netCDF atomically (temporary file in the same folder, then rename)."""
    import xarray as xr

    ds = xr.Dataset(
        {
            "positions": (("grain", "xyz"), pack.positions, {"units": "m"}),
            "velocities": (("grain", "xyz"), pack.velocities, {"units": "m s-1"}),
            "angular_velocities": (("grain", "xyz"), pack.angular_velocities,
                                   {"units": "rad s-1"}),
            "radii": (("grain",), pack.radii, {"units": "m"}),
            "pairs": (("pair", "end"), np.asarray(pack.pairs, dtype=np.int32)),
            "history": (("pair", "xyz"), pack.history, {"units": "m"}),
            **({} if pack.overlap_dissolved is None else
               {"overlap_dissolved": (("pair",), np.asarray(pack.overlap_dissolved, float),
                                      {"units": "m"})}),
        },
        attrs={
            "stage": pack.stage,
            "time_s": float(pack.time),
            "box_json": json.dumps(pack.box.__dict__),
            "material_json": json.dumps(pack.material.__dict__),
            "metadata_json": json.dumps(pack.metadata),
            "title": f"rockcem md grain pack after stage {pack.stage!r}",
        },
    )
    return _atomic_netcdf(ds, path)


def _atomic_netcdf(ds, path) -> Path:
    """Write a Dataset to netCDF through a temporary file in the same folder, then rename.

    ``md`` keeps its own writer (it does not import ``rockcem``); ``rockcem._atomic`` is the
    same mechanism for the rest of the project."""
    import os
    import tempfile

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    os.close(fd)
    umask = os.umask(0)                  # mkstemp makes the file private; give it the usual mode
    os.umask(umask)
    os.chmod(tmp, 0o666 & ~umask)
    try:
        ds.to_netcdf(tmp, engine="netcdf4")
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
    return path


def load_pack(path) -> Pack:
    """Read a pack written by :func:`save_pack`."""
    import xarray as xr

    path = Path(path)
    if not path.is_file():
        raise ValueError(f"no pack file {str(path)!r}")
    try:
        with xr.open_dataset(path, engine="netcdf4") as ds:
            ds = ds.load()
    except PermissionError:
        raise ValueError(f"pack file {str(path)!r} cannot be read: permission denied") from None
    except (OSError, ValueError, RuntimeError) as exc:
        # netCDF4 raises OSError ("NetCDF: Unknown file format", "Invalid argument") for an empty,
        # truncated or foreign file, RuntimeError ("NetCDF: HDF error") for a damaged HDF5 one.
        raise ValueError(f"pack file {str(path)!r} cannot be read as netCDF (empty, truncated "
                         f"or not a pack file: {exc}); write it again with md.save_pack"
                         ) from None
    try:
        box = Box(**json.loads(ds.attrs["box_json"]))
        material = GrainMaterial(**json.loads(ds.attrs["material_json"]))
        metadata = json.loads(ds.attrs["metadata_json"])
        stage, time = str(ds.attrs["stage"]), float(ds.attrs["time_s"])
        arrays = {name: ds[name].values for name in ("positions", "velocities",
                                                     "angular_velocities", "radii", "pairs",
                                                     "history")}
        dissolved = ds["overlap_dissolved"].values if "overlap_dissolved" in ds else None
    except (KeyError, TypeError, ValueError, json.JSONDecodeError) as exc:
        raise ValueError(f"{path.name} is not a rockcem pack file (missing or bad "
                         f"{exc}); write it again with md.save_pack") from None
    return Pack(
        positions=np.ascontiguousarray(arrays["positions"]),
        velocities=np.ascontiguousarray(arrays["velocities"]),
        angular_velocities=np.ascontiguousarray(arrays["angular_velocities"]),
        radii=np.ascontiguousarray(arrays["radii"]),
        box=box, material=material,
        pairs=np.ascontiguousarray(arrays["pairs"], dtype=np.int32),
        history=np.ascontiguousarray(arrays["history"]),
        stage=stage, time=time, metadata=metadata,
        overlap_dissolved=None if dissolved is None else np.ascontiguousarray(dissolved),
    )
