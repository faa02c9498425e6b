"""MD along a burial path: one grain pack carried down, cemented and measured at chosen depths.

The MD backend of a burial scene (:mod:`rockcem.runner` calls :func:`carry_down`). ``md`` knows
nothing of burial: it is handed, per depth, the largest effective stress the sediment has borne,
its cement fraction and (for reconstruction) its intergranular volume, and returns the dry
moduli of the cemented pack (SI units).

What happens, in order (the reasoning is in docs/user_guide/md_along_depth.md):

1. One pack is settled (:func:`md.settle`) and never re-settled.
2. Depths are taken in order of their largest effective stress; the pack is compacted
   between frozen end slabs (:func:`md.compact`, uniaxial strain, vertical stress
   :math:`\\sigma_{zz}`: a laterally confined basin loads its sediment vertically) to each
   depth's stress in turn, so the compaction increments are reused down the path. Elastic
   spheres stop near a porosity of 0.37; with ``compaction="reconstruct"`` (the default where
   burial's intergranular volume is given) each depth's Hertzian pack is compacted on to that
   intergranular volume by process-based reconstruction (:mod:`md.reconstruct`: centres moved
   together vertically, the overlap removed as pressure solution, flattened contacts in the
   contact stiffness), so the sample has burial's porosity; uplift keeps it (burial's IGV is
   that of the largest stress).
3. At each depth the pack is cemented by each scheme until the cement in its core window,
   where its porosity is measured, is the depth's cement fraction (:func:`cement_cells`): a
   saturation :math:`S_c = \\phi_{cem}/\\phi_{pack}`. With ``cement_history="grown"`` (the
   default) the cement of the shallower depth is carried with its grains to this depth's pack
   and only the increment is added (:func:`_grown_cement`); ``"fresh"`` cements each depth
   afresh. A depth whose pores burial fills is cemented full; cement that exceeds the pores
   is flagged.
4. The cemented sample is linearised with rotations (:func:`md.acoustic_system`) and its static
   P (uniaxial strain) and S (simple shear) moduli are solved for (:func:`md.static_modulus`),
   the long-wave limit that logs see; ``measure="pulse"`` uses pulse-test velocities instead.
5. With ``resolution_check`` every member is also measured at a coarser :math:`\\Omega`, and
   the first-order Richardson estimate :math:`|X(\\Omega) - X(\\Omega_c)|/(\\Omega/\\Omega_c - 1)`
   is reported as the resolution error of each modulus; with ``resolution_check2`` as well, at
   a third, and the error is the Richardson estimate with the observed order where the three
   are in the asymptotic range (:mod:`md.convergence`), flagged where they are not.

Every compacted (and reconstructed) pack, every grown cement and every measured member is saved
in ``workdir`` (``pack/``, ``cement/``, ``members/``), so an interrupted run resumes; a stage
file made with other options is redone, and so is one that cannot be read (empty, truncated,
missing a variable), with a :class:`StageFileWarning` naming it.
"""

from __future__ import annotations

import hashlib
import json
import time
import warnings
from pathlib import Path

import numpy as np

__all__ = ["carry_down", "SCHEMES", "MEASURES", "COMPACTIONS", "CEMENT_HISTORIES",
           "FULL_SAMPLES", "StageFileWarning"]


class StageFileWarning(UserWarning):
    """A stage file of :func:`carry_down` that could not be read (empty, truncated, missing a
    variable) is redone; the warning names it."""

#: Cementation schemes a depth may use (:func:`md.grow_cement`).
SCHEMES = ("contact", "coating", "pore_body", "pendular")
#: How the moduli are measured.
MEASURES = ("static", "pulse")
#: What the static solve measures: the five constants of the transversely isotropic sample
#: (:func:`md.static.static_stiffness`) or its vertical P and S moduli alone.
ANISOTROPY = ("ti", "isotropic")
#: How a depth whose pores burial fills is measured: voxel finite elements of grain and cement
#: (:mod:`md.voxel`) or the acoustic stage's lattice (:func:`carry_down`'s ``full_sample``).
FULL_SAMPLES = ("voxel", "lattice")
#: The voxel finite elements of a full sample converge much faster in Omega than the lattice
#: (at most 0.1 % per step from Omega 2 on, docs/studies/md_voxel_fe.md): they are run at this
#: fraction of the member's resolutions (the same ratios between them, so the same Richardson
#: error estimate), where the coarsest stays >= 1 cell per radius; else at the resolutions.
VOXEL_RESOLUTION_FACTOR = 0.5
#: Moduli of a member (Pa), each at every resolution: C33 and C44 are ``p_modulus`` and
#: ``shear_modulus``; C11, C13 and C66 are NaN unless ``anisotropy="ti"``.
MODULI = ("p_modulus", "shear_modulus", "c11", "c13", "c66")
#: Suffixes of the moduli at the finest resolution and the two checks.
_RESOLUTION_SUFFIX = ("", "_check", "_check2")
#: How the pack is compacted past the stress's Hertzian state (:func:`carry_down`).
COMPACTIONS = ("reconstruct", "hertz")
#: Whether cement grows with burial or is laid down afresh at each depth.
CEMENT_HISTORIES = ("grown", "fresh")


def _source_hash() -> str:
    """Fingerprint of the md sources: a stage made by another engine is redone."""
    h = hashlib.sha1()
    for path in sorted(Path(__file__).parent.glob("*.py")):
        h.update(path.read_bytes())
    return h.hexdigest()[:16]


def _key(options: dict) -> str:
    return hashlib.sha1(json.dumps(options, sort_keys=True).encode()).hexdigest()[:16]


def _no_folder(path: Path):
    """Refuse a folder where a stage file goes (the redone stage could not replace it)."""
    if path.is_dir():
        raise ValueError(f"MD stage file {path} is a folder: remove it (the stage folder holds "
                         "the stage files of carry_down only)")


def _redo(path: Path, why: str):
    warnings.warn(f"MD stage file {path} cannot be read ({why}): that stage is redone",
                  StageFileWarning, stacklevel=3)


def _saved(path: Path, key: str, variables=(), attrs=()):
    """The Dataset saved at ``path`` if it was made with the options fingerprinted by ``key``;
    None if there is none, if it was made with other options, or if it cannot be read or lacks
    one of ``variables`` or ``attrs`` (then with a :class:`StageFileWarning`: the stage is
    redone and the file replaced). A folder at ``path`` is refused (ValueError)."""
    import xarray as xr

    _no_folder(path)
    if not path.exists():
        return None
    try:
        with xr.open_dataset(path, engine="netcdf4") as ds:
            if ds.attrs.get("options_key") != key:
                return None
            missing = [v for v in variables if v not in ds.variables] + \
                [a for a in attrs if a not in ds.attrs]
            if missing:
                _redo(path, f"no {missing[0]}")
                return None
            return ds.load()
    except (OSError, ValueError, RuntimeError) as exc:
        # netCDF4: OSError for an empty, truncated or foreign file, RuntimeError (HDF error)
        # for a damaged one.
        _redo(path, " ".join(str(exc).split())[:120] or type(exc).__name__)
        return None


def _saved_pack(path: Path, key: str):
    """The pack saved at ``path`` if made with the options of ``key`` (as :func:`_saved`)."""
    from .state import load_pack

    _no_folder(path)
    if not path.exists():
        return None
    try:
        done = load_pack(path)
    except ValueError as exc:
        _redo(path, str(exc))
        return None
    return done if done.metadata.get("options_key") == key else None


def _compacted(pack, stress, folder, chain_key, strain_step, progress, *, unload=False):
    """The pack compacted (or with ``unload`` unloaded) to ``stress`` (Pa, vertical), saved as
    a stage file; returns it, the key of the chain of stages that made it and its file (None
    when ``pack`` already bears ``stress``: it is returned as it is)."""
    from .protocols import compact
    from .state import save_pack

    if not unload and pack.metadata.get("stress_zz", -np.inf) >= stress:
        return pack, chain_key, None    # already there (a depth of the same stress)
    key = _key({"previous": chain_key, "stress": float(stress), "strain_step": strain_step,
                "unload": unload})
    path = folder / f"{'unload' if unload else 'compact'}_{stress / 1e6:.6g}MPa_{key[:6]}.nc"
    done = _saved_pack(path, key)
    if done is not None:
        return done, key, path
    out = pack
    if not unload and pack.metadata.get("stress_zz", 0.0) < 0.9 * stress:
        out = compact(out, target_stress=0.9 * float(stress), stress_measure="stress_zz",
                      strain_step=strain_step, progress=progress)
    # The last tenth in steps a fifth as large: the stress overshoots by a fifth as much.
    out = compact(out, target_stress=float(stress), stress_measure="stress_zz",
                  strain_step=strain_step if unload else 0.2 * strain_step, unload=unload,
                  progress=progress)
    out.metadata["options_key"] = key
    save_pack(out, path)
    return out, key, path


def _reconstructed(pack, intergranular_volume, folder, chain_key, pack_file):
    """The pack compacted on to ``intergranular_volume`` by process-based reconstruction
    (:func:`md.reconstruct.reconstruct`), saved as a stage file; returns it, its key and its
    file."""
    from .reconstruct import reconstruct
    from .state import save_pack

    key = _key({"previous": chain_key, "reconstruct": float(intergranular_volume)})
    path = folder / f"reconstruct_{intergranular_volume:.6g}_{key[:6]}.nc"
    done = _saved_pack(path, key)
    if done is not None:
        return done, key, path
    out = reconstruct(pack, float(intergranular_volume))
    out.metadata["options_key"] = key
    save_pack(out, path)
    return out, key, path


#: The constants a TI solve adds to the vertical P and S moduli (NaN when isotropic).
_TI_ONLY = ("c11", "c13", "c66")


def _stiffness_moduli(st, ti=True):
    """The dict of :func:`_moduli` from a five-constant solve ``st`` (``c11`` … ``c66``,
    ``density``: :func:`md.static.static_stiffness`, :func:`md.voxel.sample_stiffness`); the
    vertical P and S moduli are C33 and C44, the other three NaN unless ``ti``."""
    return {"p_modulus": st.c33, "shear_modulus": st.c44,
            **{k: getattr(st, k) if ti else np.nan for k in _TI_ONLY}, "density": st.density}


def _moduli(system, measure, anisotropy="isotropic"):
    """Dry moduli of a linearised sample (Pa, :data:`MODULI`; the TI constants NaN unless
    ``anisotropy="ti"``) and its density (kg/m³), as a dict."""
    from .acoustic import pulse_test
    from .static import static_moduli, static_stiffness

    if measure == "static" and anisotropy == "ti":
        return _stiffness_moduli(static_stiffness(system))  # five loads, one factorisation
    nan = dict.fromkeys(_TI_ONLY, np.nan)
    if measure == "static":
        st = static_moduli(system, ("p", "s"))      # one factorisation for both
        return {"p_modulus": st["p"].modulus, "shear_modulus": st["s"].modulus, **nan,
                "density": st["p"].density}
    p, s = pulse_test(system, "p"), pulse_test(system, "s")
    rho = float(p.density)
    return {"p_modulus": rho * float(p.velocity) ** 2,
            "shear_modulus": rho * float(s.velocity) ** 2, **nan, "density": rho}


def _member_task(pack_file, fraction, scheme, omegas, cement, options, path, key,
                 cells_files=None, fill=False):
    """One member (a depth's pack, cement fraction, scheme) at every resolution: its moduli
    saved to the stage file ``path`` and returned (a dict of floats; one task of
    :func:`md._tasks.run_tasks`). ``cells_files`` (one per resolution) hold cement grown
    during burial (:func:`_grown_cement`); without them the pack is cemented afresh. ``fill``:
    burial's pores are full (the sample is measured as ``options["full_sample"]`` says)."""
    import xarray as xr

    from .state import _atomic_netcdf, load_pack

    t0 = time.perf_counter()
    pack = load_pack(pack_file)
    cells = [None] * len(omegas) if cells_files is None else \
        [_load_cells(f) for f in cells_files]
    if fraction > 0 or (cells[0] is not None and cells[0].any()):
        res = [_member(pack, fraction, scheme, om, cement, options, c, fill=fill)
               for om, c in zip(omegas, cells)]
    else:                       # no cement, no lattice: one solve stands for every resolution
        res = [_member(pack, 0.0, scheme, omegas[0], cement, options)] * len(omegas)
    values = {f"{name}{suffix}": res[k][name] if k < len(res) else np.nan
              for k, suffix in enumerate(_RESOLUTION_SUFFIX) for name in MODULI}
    values.update(density=res[0]["density"], wall_time=time.perf_counter() - t0)
    _atomic_netcdf(xr.Dataset({k: ((), v) for k, v in values.items()},
                              attrs={"options_key": key}), path)
    return values


def cement_cells(pack, lat, fraction, scheme, *, seed=0, carried=None, fill=False):
    """Pore cells of ``lat`` cemented by ``scheme`` until the cement in the pack's core window
    (:func:`md.observe.core_window`, where its porosity is measured) fills ``fraction`` of the
    window's volume (to the nearest cell): the growth order of :func:`md.growth.cement_order`
    over the whole lattice, cut where its cells inside the window reach that count. (A
    saturation of all the lattice's pore cells would put a different share in the window, whose
    porosity differs from the end layers'.) ``carried`` (bool, one per pore cell): cement
    already in place (grown at a shallower depth and carried with the grains,
    :func:`md.reconstruct.carried_cells`); it stays, and only the increment is added, in the
    scheme's order, skipping it. ``fill``: cement every pore cell (burial's pores are full).
    Returns the cemented cells (bool, one per pore cell) and whether the window's pores were
    too few (then all of them are cemented)."""
    from .growth import cement_order
    from .observe import core_window

    lo, hi = core_window(pack)
    z = lat.centres()[:, 2]
    inside = (z >= lo) & (z < hi)
    want = int(round(fraction * pack.box.lx * pack.box.ly * (hi - lo) / lat.cell_width**3))
    cells = np.zeros(lat.index.size, dtype=bool) if carried is None else \
        np.array(carried, dtype=bool)
    if cells.shape != (lat.index.size,):
        raise ValueError("carried must have one entry per pore cell of lat")
    if fill:
        return np.ones(lat.index.size, dtype=bool), bool(want > inside.sum())
    have = int(np.count_nonzero(cells & inside))
    if want <= have:
        return cells, False
    order = cement_order(lat, 1.0, scheme, seed=seed)
    order = order[~cells[order]]
    count = have + np.cumsum(inside[order])
    if count.size == 0:
        return cells, True
    overflow = want > count[-1]
    cells[order[:int(np.searchsorted(count, min(want, count[-1]))) + 1]] = True
    return cells, bool(overflow)


def _load_cells(path):
    """The cemented cells of a cement stage file (written, or checked by :func:`_saved`, by
    this run); a file that cannot be read now is named."""
    import xarray as xr

    try:
        with xr.open_dataset(path, engine="netcdf4") as ds:
            return ds["cells"].values.astype(bool)
    except (OSError, ValueError, RuntimeError, KeyError) as exc:
        raise ValueError(f"MD stage file {path} cannot be read ({exc}); remove it and run "
                         "again (the cement stage is then redone)") from None


def _grown_cement(pack, pack_key, fraction, scheme, omega, seed, previous, folder, fill):
    """Cement grown during burial on ``pack`` at resolution ``omega``: the cement of the
    shallower depth (``previous``: ``(key, grain, offset)`` or None) carried with the grains
    (:func:`md.reconstruct.carried_cells`) plus the increment to ``fraction``
    (:func:`cement_cells`). Saved as a stage file; returns ``(key, grain, offset)`` for the
    next depth, the file, the cells' cement fraction in the core window and the overflow
    flag."""
    import xarray as xr

    from .cement import cement_lattice
    from .observe import core_window
    from .reconstruct import attach_cement, carried_cells
    from .state import _atomic_netcdf

    key = _key({"pack": pack_key, "previous": None if previous is None else previous[0],
                "fraction": float(fraction), "scheme": scheme, "omega": float(omega),
                "seed": int(seed), "fill": bool(fill)})
    path = folder / f"{scheme}_w{omega:g}_c{fraction:.6g}_{key[:6]}.nc"
    done = _saved(path, key, ("cells", "grain", "offset"), ("cement_window", "overflow"))
    if done is not None:
        return ((key, done["grain"].values.astype(np.int64), done["offset"].values), path,
                float(done.attrs["cement_window"]), bool(done.attrs["overflow"]))
    lat = cement_lattice(pack, omega)
    carried = None if previous is None else carried_cells(pack, lat, previous[1], previous[2])
    cells, overflow = cement_cells(pack, lat, fraction, scheme, seed=seed, carried=carried,
                                   fill=fill)
    lo, hi = core_window(pack)
    z = lat.centres()[:, 2]
    inside = (z >= lo) & (z < hi)
    window = float(np.count_nonzero(cells & inside) * lat.cell_width**3
                   / (pack.box.lx * pack.box.ly * (hi - lo)))
    grain, offset = attach_cement(pack, lat, cells)
    _atomic_netcdf(xr.Dataset({"cells": (("cell",), cells.astype(np.int8)),
                               "grain": (("point",), grain), "offset": (("point", "xyz"), offset)},
                              attrs={"options_key": key, "cement_window": window,
                                     "overflow": int(overflow)}), path)
    return (key, grain, offset), path, window, overflow


def _member(pack, fraction, scheme, omega, cement, options, cells=None, fill=False):
    """Moduli of the pack cemented to the cement ``fraction`` (volume per bulk volume of its
    core window) by ``scheme`` at resolution ``omega`` (fill fractions of
    :func:`md.growth.cement_fill`: the volume exactly, a thin coating as a film), or with the
    given ``cells`` (whole cells grown during burial). With ``fill`` (burial's pores full) and
    ``options["full_sample"] == "voxel"`` every pore cell is cement and the sample is measured
    by voxel finite elements (:func:`md.voxel.sample_stiffness`) at ``omega`` times
    ``options["voxel_factor"]`` (:data:`VOXEL_RESOLUTION_FACTOR`)."""
    from .acoustic import acoustic_system
    from .cement import cement_lattice
    from .growth import cement_fill

    if fill and options.get("full_sample", "lattice") == "voxel":
        from .voxel import sample_stiffness

        lat = cement_lattice(pack, omega * options.get("voxel_factor", 1.0))
        st = sample_stiffness(pack, lat, np.ones(lat.index.size, bool), cement,
                              slab_thickness=options["slab"] * 2 * pack.radii.max())
        return _stiffness_moduli(st, options.get("anisotropy", "isotropic") == "ti")

    if cells is not None and cells.any() or cells is None and fraction > 0:
        lat = cement_lattice(pack, omega)
        if cells is None:
            cells, _ = cement_fill(pack, lat, fraction, scheme, seed=options["seed"])
        system = acoustic_system(pack, lat, cells, cement, interface=options["interface"],
                                 slab_thickness=options["slab"] * 2 * pack.radii.max())
    else:
        system = acoustic_system(pack, slab_thickness=options["slab"] * 2 * pack.radii.max())
    return _moduli(system, options["measure"], options.get("anisotropy", "isotropic"))


def _member_variables():
    """Names of the per-member values a member task returns (and its stage file holds)."""
    return [f"{name}{suffix}" for suffix in _RESOLUTION_SUFFIX for name in MODULI] + \
        ["density", "wall_time"]


def _store(out, i, k, values):
    for var in _member_variables():
        out[var][i, k] = values.get(var, np.nan)


def carry_down(max_stress, cement_fraction, *, present_stress=None, intergranular_volume=None,
               compaction=None, cement_history="grown", schemes=("coating",),
               size=(4.0, 4.0, 12.0),
               radius_range=(1.35e-4, 1.5e-4), material=None, cement=None, seed=0,
               fall_stiffness_factor=1e-3, resolution=3.0, resolution_check=0.0,
               resolution_check2=0.0, interface="facet", measure="static", anisotropy=None,
               slab=1.0, strain_step=5e-4, unload_step=1e-4, full_sample="voxel", workdir,
               scheduler=None, jobs=1, progress=False):
    """Moduli of one MD pack carried down a burial path and cemented at each depth.

    Parameters
    ----------
    max_stress : array_like, shape (n,)
        Largest vertical effective stress each depth has borne, MPa, ``> 0``.
    cement_fraction : array_like, shape (n,)
        Cement volume per bulk volume at each depth, in [0, 1).
    present_stress : array_like, shape (n,), optional
        Present vertical effective stress, MPa, in (0, ``max_stress``]; default
        ``max_stress``. Where it is lower (uplift), the pack compacted to ``max_stress`` is
        unloaded to it (:func:`md.compact` with ``unload=True``) before it is cemented; the
        carried pack itself stays at ``max_stress`` for the deeper depths.
    intergranular_volume : array_like, shape (n,), optional
        Burial's intergranular volume at each depth (porosity + cement fraction), in (0, 1):
        the porosity the uncemented pack is compacted to by ``compaction="reconstruct"``.
    compaction : {"reconstruct", "hertz"}, optional
        ``"reconstruct"`` (the default where ``intergranular_volume`` is given): the pack
        compacted by Hertzian MD to the stress is compacted on to ``intergranular_volume`` by
        process-based reconstruction (:func:`md.reconstruct.reconstruct`: grain centres moved
        together vertically, the overlap removed as pressure solution, flattened contacts in
        the contact stiffness). ``"hertz"`` (the default without it): Hertzian compaction only,
        the pack stays at the porosity elastic spheres reach (0.36–0.38).
    cement_history : {"grown", "fresh"}
        ``"grown"`` (default): cement is laid down in increments as the pack is carried down
        (:func:`_grown_cement`): the cells cemented at a shallower depth stay cemented,
        carried with their grains to the deeper depth's pack (:func:`md.reconstruct.
        carried_cells`; cement that a compaction pushes into a grain is lost), and the depth
        adds the increment to its cement fraction. ``"fresh"``: each depth's pack is
        cemented afresh (the cement never props the pack; the former behaviour).
    schemes : sequence of str
        Cementation schemes (:data:`SCHEMES`); default coating (quartz overgrowths).
    size : (float, float, float)
        Box of the pack, largest grain diameters (:func:`md.settle`); the static moduli need at
        least 4 slabs of two diameters along z after compaction.
    radius_range : (float, float)
        Smallest and largest grain radius, m.
    material : md.GrainMaterial, optional
        Grain material, default :data:`md.QUARTZ`.
    cement : md.CementMaterial, optional
        Default :data:`md.HARD_CEMENT`.
    seed : int
        Settling and pore-body growth seed.
    fall_stiffness_factor : float
        Contact softening while grains fall (:func:`md.settle`).
    resolution, resolution_check, resolution_check2 : float
        Cement lattice resolution :math:`\\Omega` (``>= 1``), a coarser one for the resolution
        error (0: none) and a third, coarser still, for the three-point estimate (0: none;
        needs ``resolution_check``).
    interface : str
        Grain–cement interface rule (:mod:`md.interface`).
    measure : {"static", "pulse"}
    anisotropy : {"ti", "isotropic"}, optional
        ``"ti"`` (default with ``measure="static"``): the five constants of the transversely
        isotropic sample, C11, C13, C33, C44, C66 (:func:`md.static.static_stiffness`, five
        loads on one factorisation); ``"isotropic"`` (the only one with ``"pulse"``): the
        vertical P and S moduli C33 and C44 alone.
    slab : float
        Thickness of the slabs the sample is cut into along z for the moduli, largest grain
        diameters (``> 0``); the interior strain is fitted through the slabs between the two
        end slabs, so a sample needs at least 4 and should have 8 or more: on 4 slabs the two
        interior points give noise, not a strain.
    strain_step, unload_step : float
        Strain of each compaction and unloading increment (:func:`md.compact`); the stress
        overshoots its target by up to about the P modulus times the step
        (``stress_reached``).
    full_sample : {"voxel", "lattice"}
        How a depth whose pores burial fills is measured (:data:`FULL_SAMPLES`): ``"voxel"``
        (default), every cell of its lattice a trilinear finite element of grain or cement
        (:func:`md.voxel.sample_stiffness`; a static solve, the moduli within 0.1 % of their
        resolution limit from Omega 2 on and at the Hashin–Shtrikman bound of the solid:
        docs/studies/md_voxel_fe.md; run at :data:`VOXEL_RESOLUTION_FACTOR` of the
        resolutions); ``"lattice"``, the acoustic stage's rigid grains on
        spring beds and cement lattice, as at every other depth (first order in Omega towards
        a limit under the bound, without the solid's Poisson coupling:
        docs/studies/md_full_cement.md). Other depths always take the acoustic stage: voxels
        would weld every grain contact a cell wide.
    workdir : path
        Folder of the stage files.
    scheduler : str, optional
        Where the members (depth, scheme) run once the pack has been carried down: None (this
        process, or ``jobs`` local processes), ``"local"`` (a local dask cluster of ``jobs``
        workers, at least 2) or a dask scheduler address (:mod:`md._tasks`; the workers must see
        ``workdir``).
    jobs : int
        Local processes or local dask workers.
    progress : bool

    Returns
    -------
    xarray.Dataset
        Dimensions ``point`` (the depths, in the order given) and ``scheme``: ``p_modulus``,
        ``shear_modulus`` (Pa; C33 and C44), with ``anisotropy="ti"`` also ``c11``, ``c13``,
        ``c66`` (Pa; NaN otherwise; each of the five also at the checks, ``c11_check``,
        ``c11_check2``, ...), the same at the coarser resolution (``p_modulus_check``,
        ``shear_modulus_check``), ``density`` (kg/m³, dry sample), their resolution errors
        ``p_modulus_error``, ``shear_modulus_error`` (NaN without ``resolution_check``), the
        moduli at ``resolution_check2`` (``p_modulus_check2``, ``shear_modulus_check2``) and
        whether the error is the asymptotic or settled three-point one
        (``p_modulus_asymptotic``, ``shear_modulus_asymptotic``: 1, else 0; NaN with fewer
        than three resolutions),
        ``saturation`` (S_c = cement fraction / pack porosity, at most 1),
        ``cement_overflow`` (1 where the cement exceeds the pores of the core window by more
        than 0.01: then they are all cemented),
        ``porosity_pack`` and ``porosity`` (the uncemented pack's and the cemented sample's,
        core window; the union volume of the grains, :func:`md.observe.porosity`),
        ``cement_window`` (the cement fraction the cells of the sample's core window hold at
        ``resolution``, with grown cement; within a cell of ``cement_fraction`` unless the
        carried cement exceeds it; NaN with fresh cement), ``compaction_factor`` (the
        reconstruction's :math:`\\lambda`, 0 with Hertzian compaction), ``stress_reached``
        (Pa, vertical stress of the compacted pack; the first increment past the target),
        ``stress_present`` (Pa, after unloading; the first increment at or below the present
        stress), ``coordination_number``, ``wall_time`` (s).
    """
    import xarray as xr
    from tqdm.auto import tqdm

    from .cement import HARD_CEMENT
    from .contact import QUARTZ
    from .observe import coordination_number, porosity
    from .protocols import prepare_pack
    from ._tasks import run_tasks
    from .cement import lattice_constants
    from .growth import coating_is_film

    stress = np.atleast_1d(np.asarray(max_stress, dtype=float))
    frac = np.atleast_1d(np.asarray(cement_fraction, dtype=float))
    if stress.ndim != 1 or stress.shape != frac.shape or stress.size == 0:
        raise ValueError("max_stress and cement_fraction must be 1-d arrays of one length; got "
                         f"shapes {stress.shape} and {frac.shape}")
    if not np.all(np.isfinite(stress) & (stress > 0)):
        raise ValueError(f"max_stress must be finite and > 0 MPa; got {stress.min():g} MPa")
    if not np.all(np.isfinite(frac) & (frac >= 0) & (frac < 1)):
        raise ValueError("cement_fraction must lie in [0, 1)")
    if compaction is None:
        compaction = "hertz" if intergranular_volume is None else "reconstruct"
    if compaction not in COMPACTIONS:
        raise ValueError(f"compaction must be one of {COMPACTIONS}; got {compaction!r}")
    if cement_history not in CEMENT_HISTORIES:
        raise ValueError(f"cement_history must be one of {CEMENT_HISTORIES}; "
                         f"got {cement_history!r}")
    igv = None
    if intergranular_volume is not None:
        igv = np.atleast_1d(np.asarray(intergranular_volume, dtype=float))
        if igv.shape != stress.shape or not np.all(np.isfinite(igv) & (igv > 0) & (igv < 1)):
            raise ValueError("intergranular_volume must have max_stress's shape and lie in "
                             "(0, 1)")
        if np.any(frac > igv + 1e-9):
            raise ValueError("cement_fraction must not exceed intergranular_volume")
    elif compaction == "reconstruct":
        raise ValueError('compaction="reconstruct" needs intergranular_volume (burial\'s '
                         'porosity + cement fraction per depth)')
    now = stress if present_stress is None else \
        np.atleast_1d(np.asarray(present_stress, dtype=float))
    if now.shape != stress.shape or not np.all((now > 0) & (now <= stress * (1 + 1e-12))):
        raise ValueError("present_stress must have max_stress's shape and lie in "
                         "(0, max_stress] MPa")
    for name, step in (("strain_step", strain_step), ("unload_step", unload_step)):
        if not 0 < step < 0.05:
            raise ValueError(f"{name} must lie in (0, 0.05); got {step}")
    schemes = tuple(schemes)
    bad = [s for s in schemes if s not in SCHEMES]
    if bad or not schemes or len(set(schemes)) != len(schemes):
        raise ValueError(f"schemes must be distinct names from {SCHEMES}; got {schemes}")
    if measure not in MEASURES:
        raise ValueError(f"measure must be one of {MEASURES}; got {measure!r}")
    if anisotropy is None:
        anisotropy = "ti" if measure == "static" else "isotropic"
    if anisotropy not in ANISOTROPY:
        raise ValueError(f"anisotropy must be one of {ANISOTROPY}; got {anisotropy!r}")
    if anisotropy == "ti" and measure != "static":
        raise ValueError("anisotropy 'ti' needs measure 'static' (the pulse test gives the "
                         "vertical velocities only)")
    if not resolution >= 1:
        raise ValueError(f"resolution must be >= 1; got {resolution}")
    if resolution_check != 0 and not 1 <= resolution_check < resolution:
        raise ValueError(f"resolution_check must be 0 or lie in [1, {resolution:g}); "
                         f"got {resolution_check}")
    if resolution_check2 != 0 and not (resolution_check
                                       and 1 <= resolution_check2 < resolution_check):
        raise ValueError(f"resolution_check2 must be 0 or lie in [1, resolution_check = "
                         f"{resolution_check:g}); got {resolution_check2}")
    material = QUARTZ if material is None else material
    cement = HARD_CEMENT if cement is None else cement
    folder = Path(workdir)
    settle_options = {"size": tuple(float(s) for s in size),
                      "radius_range": tuple(float(r) for r in radius_range),
                      "material": material, "seed": int(seed),
                      "fall_stiffness_factor": float(fall_stiffness_factor)}
    chain = _key({k: (v if k != "material" else repr(v)) for k, v in settle_options.items()})
    folder = folder / chain             # another pack (size, seed, material, ...): new folder
    pack = prepare_pack(folder / "pack", settle_options=settle_options, progress=progress)
    if not slab > 0:
        raise ValueError(f"slab must be > 0 diameters; got {slab}")
    if full_sample not in FULL_SAMPLES:
        raise ValueError(f"full_sample must be one of {FULL_SAMPLES}; got {full_sample!r}")
    if full_sample == "voxel" and measure != "static":
        raise ValueError("full_sample 'voxel' is a static solve: use measure 'static', or "
                         "full_sample 'lattice' with the pulse test")
    lattice_constants(cement, 1.0, rotations=True)     # the rotating lattice takes this cement
    options = {"seed": int(seed), "interface": interface, "measure": measure, "slab": float(slab),
               "cement": [cement.vp, cement.vs, cement.density], "md_source": _source_hash(),
               "compaction": compaction, "cement_history": cement_history,
               "anisotropy": anisotropy, "full_sample": full_sample}
    omegas = [float(w) for w in (resolution, resolution_check, resolution_check2) if w]
    if full_sample == "voxel":
        options["voxel_factor"] = (VOXEL_RESOLUTION_FACTOR
                                   if min(omegas) * VOXEL_RESOLUTION_FACTOR >= 1 else 1.0)
    n, m = stress.size, len(schemes)
    shape = (n, m)
    out = {k: np.full(shape, np.nan) for k in (*_member_variables(), "saturation", "porosity",
                                               "cement_window")}
    overflow = np.zeros(shape, np.int8)
    per_depth = {k: np.full(n, np.nan) for k in ("porosity_pack", "stress_reached",
                                                 "stress_present", "coordination_number",
                                                 "compaction_factor")}
    grown = {}                  # (scheme, omega) -> (key, grain, offset) of the last depth
    order = np.argsort(stress, kind="stable")
    # 1. Carry the pack down, depth after depth (sequential: each stage starts from the last).
    pack_file = folder / "pack" / "settle.nc"
    todo, where = [], {}
    for i in tqdm(order, disable=not progress, desc="MD packs", unit="depth"):
        pack, chain, made = _compacted(pack, stress[i] * 1e6, folder / "pack", chain,
                                       strain_step, progress)
        pack_file = made or pack_file
        per_depth["stress_reached"][i] = pack.metadata["stress_zz"]
        here, here_key, here_file = pack, chain, pack_file
        if now[i] < stress[i] * (1 - 1e-9):        # uplift: unload a copy, carry the pack on
            here, here_key, here_file = _compacted(pack, now[i] * 1e6, folder / "pack", chain,
                                                   unload_step, progress, unload=True)
        per_depth["stress_present"][i] = here.metadata["stress_zz"]
        per_depth["compaction_factor"][i] = 0.0
        if compaction == "reconstruct":
            here, here_key, here_file = _reconstructed(here, igv[i], folder / "pack",
                                                       here_key, here_file)
            per_depth["compaction_factor"][i] = here.metadata["compaction_factor"]
        phi = porosity(here)
        per_depth["porosity_pack"][i] = phi
        per_depth["coordination_number"][i] = coordination_number(here)
        # Burial's pores full (its porosity below half a percent): the sample's too.
        fill = compaction == "reconstruct" and igv[i] - frac[i] < 0.005
        for k, scheme in enumerate(schemes):
            overflow[i, k] = frac[i] > phi + 0.01
            out["saturation"][i, k] = 1.0 if fill else min(frac[i] / phi, 1.0)
            out["porosity"][i, k] = 0.0 if fill else max(phi - frac[i], 0.0)
            cement_keys, cells_files = None, None
            if cement_history == "grown" and not (scheme == "coating"
                                                  and coating_is_film(here, frac[i])):
                cement_keys, cells_files = [], []
                for w in omegas:
                    state, cfile, window, over = _grown_cement(
                        here, here_key, frac[i], scheme, w, seed, grown.get((scheme, w)),
                        folder / "cement", fill)
                    grown[(scheme, w)] = state
                    cement_keys.append(state[0])
                    cells_files.append(str(cfile))
                    if w == omegas[0]:          # the cells' own (porosity: burial's cement)
                        out["cement_window"][i, k] = window
            else:                   # cement_fill holds the fraction exactly (or fills the pores)
                out["cement_window"][i, k] = phi if fill else min(frac[i], phi)
            key = _key({"pack": here_key, "fraction": float(frac[i]), "scheme": scheme,
                        "omegas": omegas, "cement_keys": cement_keys, **options})
            path = folder / "members" / f"{now[i]:.6g}MPa_{scheme}_c{frac[i]:.6g}_{key[:6]}.nc"
            done = _saved(path, key, _member_variables())
            if done is None:
                task = (str(here_file), 0.999 if fill else float(frac[i]), scheme, omegas,
                        cement, options, str(path), key, cells_files, fill)
                todo.append(task)
                where[path.name] = (i, k)
            else:
                _store(out, i, k, {v: float(done[v]) for v in done.data_vars})
    # 2. The members are independent: serially, on local processes or on dask.
    for task, values in run_tasks(_member_task, todo, scheduler=scheduler, jobs=jobs,
                                  progress=progress, desc="MD members"):
        _store(out, *where[Path(task[6]).name], values)
    from .convergence import resolution_error

    dims = ("point", "scheme")
    data = {k: (dims, v) for k, v in out.items()}
    for k in ("p_modulus", "shear_modulus"):
        if len(omegas) > 1:
            err, asym = resolution_error(omegas, np.stack(
                [out[k], out[f"{k}_check"], out[f"{k}_check2"]][:len(omegas)]))
        else:
            err, asym = np.full(shape, np.nan), np.zeros(shape, bool)
        data[f"{k}_error"] = (dims, err)
        # 1 or 0 from a three-resolution check; NaN without one (no check, not a failed one).
        data[f"{k}_asymptotic"] = (dims, asym.astype(float) if len(omegas) == 3
                                   else np.full(shape, np.nan))
    data["cement_overflow"] = (dims, overflow)
    data.update({k: (("point",), v) for k, v in per_depth.items()})
    return xr.Dataset(data, coords={"scheme": list(schemes)},
                      attrs={"resolution": float(resolution), "compaction": compaction,
                             "cement_history": cement_history, "anisotropy": anisotropy,
                             "resolution_check": float(resolution_check),
                             "resolution_check2": float(resolution_check2),
                             "interface": interface, "measure": measure, "rotations": 1,
                             "n_grains": int(pack.n_grains)})
