"""MD protocols: deposition, compaction between frozen slabs, and the two in sequence with every
stage saved (García & Medina, Sect. III A).

SI units. Each protocol returns a :class:`md.state.Pack` that can be saved and resumed.
Deposition lives in :mod:`md.deposit`; porosity, coordination and stress in :mod:`md.observe`.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ._dynamics import refresh_neighbors, remap_history, time_step
from .contact import damping_parameter
from .deposit import settle
from .neighbors import build_neighbors
from .observe import (contact_stress, coordination_number, end_slabs, pack_stress, pair_geometry,
                      porosity, slab_core)
from .space import Box
from .state import Pack

__all__ = ["settle", "compact", "prepare_pack", "porosity", "coordination_number",
           "pack_stress"]

#: Compaction by elastic contacts cannot reach far below random close packing.
MIN_TARGET_POROSITY = 0.30
#: Names of the stresses a compaction records and may stop at (Pa).
STRESS_MEASURES = ("stress_zz", "stress_mean")


def compact(pack: Pack, *, target_stress=None, target_porosity=None, stress_measure=None,
            strain_step=2e-3, slab=1.0, drag=2000.0, rest_tolerance=1e-4, max_increments=400,
            isotropic=False, unload=False, progress=False) -> Pack:
    r"""Compact a settled pack between frozen end slabs to a stress (García & Medina, Sect. III A).

    The grains within ``slab`` largest diameters of the bottom and of the top are frozen. At each
    increment the sample is shortened by ``strain_step`` of its height — an affine step of all
    positions toward the core — and the mobile grains relax (damped with ``-drag m v``, no
    gravity, no floor) until their kinetic energy is below ``rest_tolerance`` times the elastic
    energy of the contacts. The time step follows the stiffest linearised contact of the current
    state (:func:`md.integrate.contact_time_step`). After each increment the porosity and the
    contact stress of the core window between the slabs (:func:`md.observe.contact_stress`,
    normal and tangential forces, equal to the force on a slab per area) and the coordination
    number of the mobile grains (their contacts with frozen grains included) are recorded. The
    run stops at the first increment whose stress reaches ``target_stress`` (Pa; the primary
    control, the source's confining stress) or, as an option, whose porosity reaches
    ``target_porosity``.

    With ``isotropic=True`` each increment also shrinks the periodic lengths in x and y (and
    the x, y positions with them) by ``strain_step``: an isotropic confinement, as Xu 2023
    (Sect. 2.3) prepares its bonded samples.

    With ``unload=True`` each increment instead *lengthens* the sample by ``strain_step`` (the
    grains relax as before, their tangential contact history kept, so friction makes the
    unloading path stiffer than the loading one), and the run stops at the first increment
    whose stress has fallen to ``target_stress`` or below: an uplifted sediment unloaded from
    its largest burial stress. Unloading is stiff (the stress falls by about
    :math:`M\,\Delta\varepsilon` per increment), so give it a small ``strain_step``.

    Parameters
    ----------
    pack : Pack
    target_stress : float, optional
        Pa, ``> 0``.
    target_porosity : float, optional
        In [0.30, current core porosity).
    stress_measure : {"stress_zz", "stress_mean"}, optional
        The stress compared with ``target_stress``: the vertical stress :math:`\sigma_{zz}`
        (default for uniaxial compaction) or the mean stress :math:`\mathrm{tr}\,\sigma/3`
        (default with ``isotropic``).
    strain_step : float
        In (0, 0.05).
    slab : float
        Thickness of the frozen end slabs, largest diameters.
    drag : float
        Relaxation drag rate, 1/s.
    rest_tolerance : float
        Kinetic over elastic energy at rest.
    max_increments : int
    isotropic : bool
    unload : bool
        Unload to ``target_stress`` instead of loading (``target_porosity`` not allowed).
    progress : bool

    Returns
    -------
    Pack
        ``stage="compact"``. ``metadata["record"]`` holds per increment the lists ``strain``,
        ``porosity`` (core), ``coordination_number``, ``stress_zz`` and ``stress_mean`` (Pa;
        ``metadata["record_units"]`` names the units); ``metadata`` also holds the porosity
        reached (``porosity``, equal to :func:`md.observe.porosity` of the returned pack), the
        stresses reached (``stress_zz``, ``stress_mean``, Pa), the core window
        (``core_window_m``), the indices of the frozen slab grains (``frozen_grains``) and the
        controls.
    """
    from ._kernels_integrate import elastic_energy, verlet_run

    if target_porosity is None and target_stress is None:
        raise ValueError("give target_stress (or target_porosity)")
    if unload and (target_stress is None or target_porosity is not None):
        raise ValueError("unload=True takes target_stress and no target_porosity")
    if target_porosity is not None and not MIN_TARGET_POROSITY <= target_porosity < 1:
        raise ValueError(f"target_porosity must lie in [{MIN_TARGET_POROSITY}, 1): elastic "
                         "grains cannot be compacted far below random close packing")
    if target_stress is not None and not target_stress > 0:
        raise ValueError(f"target_stress must be > 0 Pa; got {target_stress}")
    if not 0 < strain_step < 0.05:
        raise ValueError("strain_step must lie in (0, 0.05)")
    if not drag >= 0:
        raise ValueError(f"drag must be >= 0 1/s; got {drag}")
    if not rest_tolerance > 0:
        raise ValueError(f"rest_tolerance must be > 0; got {rest_tolerance}")
    if not (float(max_increments).is_integer() and max_increments >= 1):
        raise ValueError(f"max_increments must be an integer >= 1; got {max_increments}")
    max_increments = int(max_increments)
    if stress_measure is None:
        stress_measure = "stress_mean" if isotropic else "stress_zz"
    if stress_measure not in STRESS_MEASURES:
        raise ValueError(f"stress_measure must be one of {', '.join(STRESS_MEASURES)}; got "
                         f"{stress_measure!r}")
    mat = pack.material
    x = pack.positions.copy()
    v = np.zeros_like(x)
    w = np.zeros_like(x)
    r = pack.radii.copy()
    n = r.size
    m = 4.0 / 3.0 * np.pi * r**3 * mat.density
    box = pack.box
    fixed = end_slabs(x[:, 2], r, slab)
    if fixed.all() or not fixed.any():
        raise ValueError("slab: the frozen slabs must leave mobile grains between them")
    window = slab_core(x[:, 2], r, fixed)
    if target_porosity is not None:
        phi0 = porosity(pack, bottom=window[0], top=window[1])
        if target_porosity >= phi0:
            raise ValueError(f"target_porosity {target_porosity} is not below the current "
                             f"porosity {phi0:.4f}")
    beta = damping_parameter(mat.restitution)
    skin = 0.3 * r.min()
    nl = build_neighbors(x, r, box, skin)
    hist = remap_history(pack.pairs, pack.history, nl.pairs, n)
    v_ref = 0.01
    record = {"strain": [], "porosity": [], "coordination_number": [], "stress_zz": [],
              "stress_mean": []}
    strain = 0.0
    steps = 0
    elapsed = 0.0
    from tqdm.auto import tqdm

    bar = tqdm(total=max_increments, desc="unload" if unload else "compact", unit="step",
               disable=not progress)
    factor = 1.0 + strain_step if unload else 1.0 - strain_step
    for _ in range(max_increments):
        centre = 0.5 * (x[:, 2].min() + x[:, 2].max())
        x[:, 2] = centre + (x[:, 2] - centre) * factor
        strain = 1.0 - (1.0 - strain) * factor                  # 1 - H / H_0, compounded
        if isotropic:                        # periodic images move in with the grains
            x[:, :2] *= factor
            box = Box(box.lx * factor, box.ly * factor, box.lz_min,
                      box.lz_max)
            old_pairs = nl.pairs
            nl = build_neighbors(x, r, box, skin)
            hist = remap_history(old_pairs, hist, nl.pairs, n)
        for _relax in range(2000):
            speed = float(np.sqrt((v * v).sum(axis=1).max()))
            dt = time_step(x, r, nl, box, mat, mobile=~fixed, impact_speed=2.0 * speed)
            verlet_run(x, v, w, r, m, nl.pairs, hist, np.array([box.lx, box.ly]), mat.E_f,
                       mat.G_f, beta, v_ref, mat.friction, dt, 200, 0.0, 0, np.zeros(0),
                       -np.inf, np.zeros((0, 3)), float(drag), fixed)
            steps += 200
            elapsed += 200 * dt
            nl, hist = refresh_neighbors("compact", nl, hist, x, r, box, skin, mat)
            ke = 0.5 * np.sum(m[:, None] * v * v)
            pe = elastic_energy(x, r, nl.pairs, np.array([box.lx, box.ly]), mat.E_f)
            if ke <= rest_tolerance * max(pe, 1e-300):
                break
        else:
            raise RuntimeError("compact: the pack did not come to rest within an increment")
        window = slab_core(x[:, 2], r, fixed)
        cur = Pack(x.copy(), v.copy(), w.copy(), r, box, mat, np.asarray(nl.pairs, np.int32),
                   hist.copy(), stage="compact", time=pack.time + elapsed)
        phi = porosity(cur, bottom=window[0], top=window[1])
        sigma = contact_stress(x, r, nl.pairs, box, mat, z_range=window, history=hist)
        in_contact = nl.pairs[pair_geometry(x, r, nl.pairs, box)[2] > 0.0]
        contacts = np.bincount(in_contact.ravel(), minlength=n)
        record["strain"].append(strain)
        record["porosity"].append(phi)
        record["coordination_number"].append(float(contacts[~fixed].mean()))
        record["stress_zz"].append(float(sigma[2, 2]))
        record["stress_mean"].append(float(np.trace(sigma)) / 3.0)
        bar.update(1)
        if unload:
            if record[stress_measure][-1] <= target_stress:
                break
        elif (target_porosity is not None and phi <= target_porosity) or \
                (target_stress is not None and record[stress_measure][-1] >= target_stress):
            break
    else:
        raise RuntimeError(f"compact: target not reached in {max_increments} increments "
                           f"(porosity {record['porosity'][-1]:.4f}, "
                           f"{stress_measure} {record[stress_measure][-1]:.3g} Pa)")
    bar.close()
    # The settled pack's porosity from the floor does not describe the compacted one.
    inherited = {k: val for k, val in pack.metadata.items() if k != "porosity_from_floor"}
    return dataclasses.replace(cur, metadata={
        **inherited, "record": record,
        "record_units": {"strain": "1", "porosity": "1", "coordination_number": "1",
                         "stress_zz": "Pa", "stress_mean": "Pa"},
        "porosity": record["porosity"][-1], "stress_zz": record["stress_zz"][-1],
        "stress_mean": record["stress_mean"][-1], "core_window_m": list(window),
        "coordination_number": record["coordination_number"][-1],
        "target_stress": target_stress, "target_porosity": target_porosity,
        "stress_measure": stress_measure, "strain_step": strain_step, "slab": slab,
        "isotropic": bool(isotropic), "unload": bool(unload), "compaction_steps": int(steps),
        "frozen_grains": np.flatnonzero(fixed).tolist()})


#: Options of :func:`settle` and :func:`compact` -> the metadata key that records each.
_SETTLE_KEYS = {"size": "size_diameters", "radius_range": "radius_range_m", "seed": "seed",
                "protocol": "protocol", "drag": "drag",
                "fall_stiffness_factor": "fall_stiffness_factor", "wave": "wave",
                "drop_height": "drop_height_m"}
_COMPACT_KEYS = {"target_stress": "target_stress", "target_porosity": "target_porosity",
                 "stress_measure": "stress_measure", "strain_step": "strain_step",
                 "slab": "slab", "isotropic": "isotropic"}


def _stage_matches(path, options, keys):
    """The pack saved at ``path`` if every option given (and recorded) equals its record, else
    None (no file, or made with other options)."""
    from .state import load_pack

    if not path.exists():
        return None
    pack = load_pack(path)
    for name, value in (options or {}).items():
        key = keys.get(name)
        if key is None or value is None or key not in pack.metadata:
            continue
        recorded = pack.metadata[key]
        if isinstance(value, (tuple, list)):
            same = len(value) == len(recorded) and np.allclose(value, recorded, rtol=1e-12)
        elif isinstance(value, (int, float)) and not isinstance(value, bool):
            same = recorded is not None and np.isclose(value, recorded, rtol=1e-12)
        else:
            same = value == recorded
        if not same:
            return None
    return pack


def prepare_pack(workdir, *, settle_options=None, compact_options=None, progress=False) -> Pack:
    """Settle then compact a pack, saving each stage in ``workdir`` and resuming from the last
    saved one: ``settle.nc`` and ``compact.nc``. An interrupted run loses at most the stage it
    was in; a finished stage is not recomputed unless an option given here differs from the one
    recorded in its file (another seed, size, drag, compaction stress, ...), when it is redone
    with the stages after it (delete a file to redo it anyway).

    Parameters
    ----------
    workdir : path
        Folder for the stage files (created if missing).
    settle_options, compact_options : dict, optional
        Keyword arguments of :func:`settle` and :func:`compact`; without ``compact_options`` the
        settled pack is returned.
    progress : bool
        Progress bars.

    Returns
    -------
    Pack
    """
    from pathlib import Path

    from .state import save_pack

    folder = Path(workdir)
    folder.mkdir(parents=True, exist_ok=True)
    settled_file, compacted_file = folder / "settle.nc", folder / "compact.nc"
    settled = _stage_matches(settled_file, settle_options, _SETTLE_KEYS)
    if compact_options is not None and settled is not None:
        compacted = _stage_matches(compacted_file, {**(settle_options or {}),
                                                    **compact_options},
                                   {**_SETTLE_KEYS, **_COMPACT_KEYS})
        if compacted is not None:
            return compacted
    if settled is not None:
        pack = settled
    else:
        pack = settle(**(settle_options or {}), progress=progress)
        save_pack(pack, settled_file)
    if compact_options is None:
        return pack
    pack = compact(pack, **compact_options, progress=progress)
    save_pack(pack, compacted_file)
    return pack
