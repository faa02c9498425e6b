"""The rock state per depth that the petro-elastic models take, as an ``xarray.Dataset``.

``sandstone_state`` and ``shale_state`` run the diagenetic processes of one lithology along a burial
path and return porosity, cement or clay fractions and pressures per present-day depth, with the
names and units of the variable registry (``datasets/variables.toml``).

Which depths: for the linear basin model (:func:`burial.linear_path`) every package follows the
same path, so the path's nodes are the present-day depth profile. For a table of paths with
packages on the leading axis (:func:`burial.path_from_nodes`) the present-day state of each package
is its last node, and the packages become the depth dimension (sorted by present depth).
"""

from __future__ import annotations

import numpy as np

from rockcem.validation import as_scalar
from rockcem.variables import build_dataset

from .clay import smectite_fraction
from .compaction import athy_porosity, intergranular_volume, sandstone_porosity
from .path import BurialPath, pressures
from .quartz import quartz_cement

__all__ = ["sandstone_state", "shale_state"]


def _present(path: BurialPath, fields: dict):
    """Select the present-day values: every node of a single 1-D path (the linear basin model),
    or the last node of each package of a 2-D table, sorted by present depth."""
    if path.depth.ndim == 1:
        return path.depth, fields, {"burial_time": path.time}
    if path.depth.ndim != 2:
        raise ValueError("a path table must have one package axis: depth of shape "
                         "(packages, nodes)")
    depth = path.depth[:, -1]
    order = np.argsort(depth, kind="stable")
    end = {k: np.asarray(v)[..., -1][order] for k, v in fields.items()}
    t = np.broadcast_to(path.time, path.depth.shape)[:, -1][order]
    return depth[order], end, {"burial_time": t}


def _densities(sediment_density, water_density):
    """The two densities as numbers: a path table's leading axis here is its packages, not
    members, so one density each (per-path densities: :func:`burial.pressures`)."""
    return {"sediment_density": as_scalar("sediment_density", sediment_density),
            "water_density": as_scalar("water_density", water_density)}


def _dataset(path, fields, attrs):
    depth, values, extra = _present(path, fields)
    if np.any(np.diff(depth) < 0):
        raise ValueError("present-day depths must not decrease along the path")
    data = {k: (("depth",), v) for k, v in {**extra, **values}.items()}
    return build_dataset(data, {"depth": (("depth",), depth)}, attrs)


def sandstone_state(path: BurialPath, *, porosity0=0.36, grain_size=0.3, quartz_fraction=0.65,
                    clay_coating=0.0, igv_final=0.2, beta=0.01, start_temperature=None,
                    sediment_density=2.5, water_density=1.04):
    r"""Sandstone rock state: Walderhaug cement, IGV compaction, porosity (App. B of Carcione 2022).

    Cement by :func:`burial.quartz_cement`; intergranular volume by eq. B.7 at the maximum
    effective pressure reached (no decompaction on uplift); porosity by eq. B.8, clipped at 0 and
    flagged (:func:`burial.sandstone_porosity`); grain fraction :math:`1 - \mathrm{IGV}`.
    Defaults are the worked example of Sect. 6.2.

    Parameters
    ----------
    path : BurialPath
    porosity0, grain_size, quartz_fraction, clay_coating, start_temperature
        As in :func:`burial.quartz_cement` (grain size in mm).
    igv_final, beta
        As in :func:`burial.intergranular_volume`.
    sediment_density, water_density
        As in :func:`burial.pressures`, g/cm³, one number each.

    Returns
    -------
    xarray.Dataset
        Dimension ``depth``; variables ``burial_time`` (Myr since
        deposition), ``temperature``, ``pressure_confining``,
        ``pressure_pore``, ``pressure_effective``, ``pressure_effective_max``,
        ``cement_fraction``, ``intergranular_volume``, ``porosity``, ``grain_fraction``,
        ``pore_filled``.
    """
    p = pressures(path, **_densities(sediment_density, water_density))
    phip = quartz_cement(path, porosity0, grain_size, quartz_fraction, clay_coating,
                         start_temperature=start_temperature)
    igv = intergranular_volume(porosity0, p.max_effective, igv_final, beta)
    s = sandstone_porosity(igv, phip)
    fields = {
        "temperature": path.temperature, "pressure_confining": p.confining,
        "pressure_pore": p.pore, "pressure_effective": p.effective,
        "pressure_effective_max": p.max_effective, "cement_fraction": s.cement_fraction,
        "intergranular_volume": s.intergranular_volume, "porosity": s.porosity,
        "grain_fraction": 1.0 - s.intergranular_volume, "pore_filled": s.pore_filled,
    }
    attrs = {"lithology": "sandstone", "porosity0": float(porosity0),
             "grain_size_mm": float(grain_size), "quartz_fraction": float(quartz_fraction),
             "clay_coating": float(clay_coating), "igv_final": float(igv_final),
             "beta_per_MPa": float(beta)}
    return _dataset(path, fields, attrs)


def shale_state(path: BurialPath, *, porosity0=0.35, beta=0.01, r0=0.99, order=5,
                activation_energy=36.0, frequency_factor=1.217e23, sediment_density=2.5,
                water_density=1.04):
    r"""Shale rock state: Athy porosity and smectite→illite conversion (Carcione 2022, Sect. 6.1).

    Porosity by Athy's law (eq. 7) at the maximum effective pressure reached; smectite and
    illite fractions of the clay by :func:`burial.smectite_fraction`. Defaults are the worked
    example (φ0 = 0.35, β = 0.01/MPa, r0 = 0.99, n = 5, E = 36 kcal/mol, c = 1.217e23/Myr).

    Returns
    -------
    xarray.Dataset
        Dimension ``depth``; variables ``burial_time`` (Myr since
        deposition), ``temperature``, the pressures, ``porosity``,
        ``smectite_fraction``, ``illite_fraction``.
    """
    p = pressures(path, **_densities(sediment_density, water_density))
    r = smectite_fraction(path, r0, order, activation_energy, frequency_factor)
    fields = {
        "temperature": path.temperature, "pressure_confining": p.confining,
        "pressure_pore": p.pore, "pressure_effective": p.effective,
        "pressure_effective_max": p.max_effective,
        "porosity": athy_porosity(porosity0, p.max_effective, beta),
        "smectite_fraction": r, "illite_fraction": 1.0 - r,
    }
    attrs = {"lithology": "shale", "porosity0": float(porosity0), "beta_per_MPa": float(beta),
             "r0": float(r0), "reaction_order": float(order),
             "activation_energy_kcal_per_mol": float(activation_energy),
             "frequency_factor_per_Myr": float(frequency_factor)}
    return _dataset(path, fields, attrs)
