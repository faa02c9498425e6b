"""Materials: ``Mineral`` and ``Fluid`` dataclasses and the catalogue shipped in ``datasets/``.

Units: moduli GPa, density g/cm³. The catalogue holds Table 1 of [Carcione2022]_, Tables I–II of
[GarciaMedina2007]_ and the materials of [HanGuo]_ and [Xu2023]_; each entry records its source.
"""

from __future__ import annotations

import difflib
from dataclasses import dataclass

import numpy as np

from ._data import read_toml

__all__ = ["Mineral", "Fluid", "mineral", "fluid", "minerals", "fluids"]


@dataclass(frozen=True)
class Mineral:
    """An isotropic solid.

    Parameters
    ----------
    K : float
        Bulk modulus, GPa, ``> 0``.
    G : float
        Shear modulus, GPa, ``>= 0``, with Poisson ratio in (-1, 0.5].
    rho : float
        Density, g/cm³, ``> 0``.
    name : str
        Label.
    source : str
        Where the values come from.
    """

    K: float
    G: float
    rho: float
    name: str = ""
    source: str = ""

    def __post_init__(self):
        for attr in ("K", "G", "rho"):
            value = getattr(self, attr)
            if not np.isfinite(value):
                raise ValueError(f"Mineral {self.name!r}: {attr} must be finite; got {value}")
        if self.K <= 0.0:
            raise ValueError(f"Mineral {self.name!r}: K must be > 0 GPa; got {self.K:g}")
        if self.G < 0.0:
            raise ValueError(f"Mineral {self.name!r}: G must be >= 0 GPa; got {self.G:g}")
        if self.rho <= 0.0:
            raise ValueError(f"Mineral {self.name!r}: rho must be > 0 g/cm3; got {self.rho:g}")
        if self.poisson_ratio <= -1.0:
            raise ValueError(f"Mineral {self.name!r}: Poisson ratio must be > -1")

    @property
    def poisson_ratio(self) -> float:
        """Poisson ratio, :math:`(3K - 2G) / (2(3K + G))`."""
        return (3.0 * self.K - 2.0 * self.G) / (2.0 * (3.0 * self.K + self.G))

    @property
    def vp(self) -> float:
        """P-wave velocity, km/s."""
        return float(np.sqrt((self.K + 4.0 / 3.0 * self.G) / self.rho))

    @property
    def vs(self) -> float:
        """S-wave velocity, km/s."""
        return float(np.sqrt(self.G / self.rho))

    @classmethod
    def from_velocities(cls, vp, vs, rho, name="", source=""):
        r"""Mineral from velocities (km/s) and density: :math:`G = \rho V_S^2`,
        :math:`K = \rho (V_P^2 - \tfrac43 V_S^2)`."""
        if vs < 0 or vp <= 0 or vp * vp <= 4.0 / 3.0 * vs * vs:
            raise ValueError(f"Mineral {name!r}: need vp > 0, vs >= 0 and vp^2 > 4/3 vs^2")
        return cls(rho * (vp * vp - 4.0 / 3.0 * vs * vs), rho * vs * vs, rho, name, source)

    @classmethod
    def from_poisson(cls, G, poisson_ratio, rho, name="", source=""):
        r"""Mineral from shear modulus (GPa) and Poisson ratio:
        :math:`K = 2G(1+\nu)/(3(1-2\nu))`."""
        if not -1.0 < poisson_ratio < 0.5:
            raise ValueError(f"Mineral {name!r}: poisson_ratio must lie in (-1, 0.5)")
        return cls(2.0 * G * (1.0 + poisson_ratio) / (3.0 * (1.0 - 2.0 * poisson_ratio)), G, rho,
                   name, source)


@dataclass(frozen=True, eq=False)
class Fluid:
    """A pore fluid: bulk modulus ``K`` (GPa, ``>= 0``) and density ``rho`` (g/cm³, ``>= 0``).

    ``K`` and ``rho`` are numbers (a catalogue fluid) or arrays over depth (a fluid that follows
    the burial path's temperature and pore pressure, :mod:`rockcem.pore_fluids`); the models
    broadcast them against their other inputs.
    """

    K: float | np.ndarray
    rho: float | np.ndarray
    name: str = ""
    source: str = ""

    def __post_init__(self):
        for key, unit in (("K", "GPa"), ("rho", "g/cm3")):
            value = getattr(self, key)
            if type(value).__module__.split(".")[0] in ("pandas", "xarray"):
                # Kept as plain values they would be paired by position with the models'
                # labelled inputs (rockcem.validation.labelled aligns only direct arguments).
                raise ValueError(f"Fluid {self.name!r}: {key} is a {type(value).__name__}; a "
                                 "Fluid holds numbers or numpy arrays over depth, paired by "
                                 "position with the model's other inputs: align it with them "
                                 f"and pass {key}.to_numpy()")
            try:
                arr = np.asarray(value, dtype=float)
            except (TypeError, ValueError):
                raise ValueError(f"Fluid {self.name!r}: {key} must be a number or an array of "
                                 f"numbers >= 0 {unit}; got {value!r}") from None
            if not np.all(np.isfinite(arr) & (arr >= 0.0)):
                worst = arr[~(np.isfinite(arr) & (arr >= 0.0))].ravel()[0]
                raise ValueError(f"Fluid {self.name!r}: {key} must be >= 0 {unit} (finite); "
                                 f"got {worst}")
            object.__setattr__(self, key, float(arr) if arr.ndim == 0 else arr)


def _mineral_from_entry(name: str, e: dict) -> Mineral:
    src = e.get("source", "")
    if "vp" in e:
        return Mineral.from_velocities(e["vp"], e["vs"], e["rho"], name, src)
    if "poisson_ratio" in e:
        return Mineral.from_poisson(e["G"], e["poisson_ratio"], e["rho"], name, src)
    return Mineral(float(e["K"]), float(e["G"]), float(e["rho"]), name, src)


def minerals() -> dict[str, Mineral]:
    """The mineral catalogue, ``{name: Mineral}``."""
    table = read_toml("materials", "minerals.toml")
    return {k: _mineral_from_entry(k, v) for k, v in table.items()}


def fluids() -> dict[str, Fluid]:
    """The fluid catalogue, ``{name: Fluid}``."""
    table = read_toml("materials", "fluids.toml")
    return {k: Fluid(float(v["K"]), float(v["rho"]), k, v.get("source", ""))
            for k, v in table.items()}


def _lookup(kind: str, catalogue: dict, name: str):
    if name not in catalogue:
        close = difflib.get_close_matches(name, catalogue, n=1)
        hint = f"; did you mean {close[0]!r}?" if close else ""
        raise ValueError(f"unknown {kind} {name!r}{hint} (known: {', '.join(sorted(catalogue))})")
    return catalogue[name]


def mineral(name: str) -> Mineral:
    """A mineral of the catalogue by name.

    Examples
    --------
    >>> q = mineral("quartz")
    >>> q.K, q.G, q.rho
    (40.0, 39.0, 2.65)
    """
    return _lookup("mineral", minerals(), name)


def fluid(name: str) -> Fluid:
    """A fluid of the catalogue by name (``"water"``, ``"vacuum"``)."""
    return _lookup("fluid", fluids(), name)
