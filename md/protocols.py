"""MD protocols: ballistic settling of a grain pack (García & Medina, Sect. III A).

SI units. Each protocol returns a :class:`md.state.Pack` that can be saved and resumed.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from .contact import QUARTZ, GrainMaterial, damping_parameter
from .integrate import stable_time_step
from .neighbors import build_neighbors, needs_rebuild
from .space import Box
from .state import Pack

__all__ = ["settle", "compact", "prepare_pack", "porosity", "coordination_number"]

GRAVITY = 9.81
#: Largest overlap, as a fraction of the smaller radius, before a run is declared blown up (a
#: Hertz contact of quartz at 100 MPa overlaps by well under 1 % of the radius).
MAX_OVERLAP = 0.05
#: Compaction by elastic contacts cannot reach far below random close packing.
MIN_TARGET_POROSITY = 0.30


def _check_overlaps(stage, x, r, pairs, box):
    """Raise if any contact overlaps by more than MAX_OVERLAP of the smaller radius."""
    if pairs.shape[0] == 0:
        return
    d = x[pairs[:, 1]] - x[pairs[:, 0]]
    d[:, 0] -= box.lx * np.round(d[:, 0] / box.lx)
    d[:, 1] -= box.ly * np.round(d[:, 1] / box.ly)
    ri, rj = r[pairs[:, 0]], r[pairs[:, 1]]
    worst = np.max((ri + rj - np.linalg.norm(d, axis=1)) / np.minimum(ri, rj))
    if worst > MAX_OVERLAP:
        raise RuntimeError(f"{stage}: the integration blew up (an overlap of {worst:.1%} of a "
                           "radius); the time step or the stiffness is wrong")


def _remap_history(old_pairs, old_hist, new_pairs, n):
    """Carry tangential histories over to a rebuilt neighbour list (pairs matched by (i, j))."""
    hist = np.zeros((new_pairs.shape[0], 3))
    if old_pairs.shape[0] == 0 or new_pairs.shape[0] == 0:
        return hist
    old_key = old_pairs[:, 0].astype(np.int64) * n + old_pairs[:, 1]
    new_key = new_pairs[:, 0].astype(np.int64) * n + new_pairs[:, 1]
    order = np.argsort(old_key)
    pos = np.searchsorted(old_key[order], new_key)
    pos = np.minimum(pos, old_key.size - 1)
    found = old_key[order][pos] == new_key
    hist[found] = old_hist[order][pos[found]]
    return hist


def _refresh_neighbors(stage, nl, hist, x, r, box, skin):
    """Rebuild the neighbour list when a grain has moved more than skin/2 (histories carried
    over) and check for blown-up overlaps; returns the list and histories to use next."""
    if needs_rebuild(nl, x, box):
        new = build_neighbors(x, r, box, skin)
        hist = _remap_history(nl.pairs, hist, new.pairs, r.size)
        nl = new
    _check_overlaps(stage, x, r, nl.pairs, box)
    return nl, hist


def porosity(pack: Pack, *, bottom=None, top=None) -> float:
    """Porosity of the pack between ``bottom`` (default the floor) and ``top`` (default: the
    highest grain top minus one largest diameter, to leave out the rough free surface), from the
    grain volumes inside that slab (spherical caps of grains cut by its planes counted exactly)."""
    z, r = pack.positions[:, 2], pack.radii
    z0 = pack.box.lz_min if bottom is None else float(bottom)
    z1 = float(np.max(z + r) - 2.0 * r.max()) if top is None else float(top)
    if not z1 > z0:
        raise ValueError("the slab for the porosity is empty")

    def below(h):                 # volume of a sphere of radius r below a plane at height h
        s = np.clip(h - (z - r), 0.0, 2.0 * r)
        return np.pi * s * s * (3.0 * r - s) / 3.0

    solid = np.sum(below(z1) - below(z0))
    return float(1.0 - solid / (pack.box.lx * pack.box.ly * (z1 - z0)))


def coordination_number(pack: Pack, *, tolerance=0.0, exclude_rattlers=False) -> float:
    """Mean number of contacts per grain (overlap > ``tolerance`` m); grain–floor contacts are
    not counted. With ``exclude_rattlers`` grains with fewer than two contacts are left out."""
    nl = build_neighbors(pack.positions, pack.radii, pack.box, 0.0)
    p = nl.pairs
    d = pack.positions[p[:, 1]] - pack.positions[p[:, 0]]
    d[:, 0] -= pack.box.lx * np.round(d[:, 0] / pack.box.lx)
    d[:, 1] -= pack.box.ly * np.round(d[:, 1] / pack.box.ly)
    xi = pack.radii[p[:, 0]] + pack.radii[p[:, 1]] - np.linalg.norm(d, axis=1)
    p = p[xi > tolerance]
    counts = np.bincount(p.ravel(), minlength=pack.n_grains)
    if exclude_rattlers:
        counts = counts[counts >= 2]
    return float(counts.mean()) if counts.size else 0.0


def settle(size=(8, 8, 32), radius_range=(1.8e-4, 2.0e-4), *, material: GrainMaterial = QUARTZ,
           seed=0, drag=50.0, fall_stiffness_factor=1.0, kinetic_tolerance=1e-7,
           max_time=1.0, progress=False) -> Pack:
    """Ballistic deposition of a grain pack onto a flat floor.

    Grains with radii uniform in ``radius_range`` start from a jittered lattice above the floor at
    random x, y (periodic in x and y), fall under gravity with viscous drag (``-drag m v``),
    collide with Hertz–Mindlin contacts (:mod:`md.contact`) and come to rest on the floor. The
    run stops when the kinetic energy per grain falls below ``kinetic_tolerance`` times
    :math:`m g d` of the largest grain.

    Accelerated deposition: with ``fall_stiffness_factor < 1`` the contacts are that much
    softer while the grains fall and settle (longer contacts, a larger time step), then the true
    stiffness is restored and the pack relaxed to rest again; the faithful run has the factor 1.
    The time step always follows from the stiffest contact (:func:`md.integrate.stable_time_step`).

    Parameters
    ----------
    size : (float, float, float)
        Box width, depth and target height in largest diameters; the number of grains fills the
        target height at a porosity of 0.4. Default (8, 8, 32), the paper's sample.
    radius_range : (float, float)
        Smallest and largest radius, m; default 0.18–0.20 mm.
    material : GrainMaterial
    seed : int
        Seed of the random generator (reproducible packs).
    drag : float
        Viscous drag rate, 1/s (terminal speed g/drag).
    fall_stiffness_factor : float
        In (0, 1]; see above.
    kinetic_tolerance : float
        Rest criterion (dimensionless).
    max_time : float
        Simulated seconds allowed before ``RuntimeError``.
    progress : bool
        Show a progress bar.

    Returns
    -------
    Pack
        With ``stage="settle"`` and ``metadata`` holding porosity, coordination number, steps,
        seed and parameters.
    """
    r_min, r_max = map(float, radius_range)
    if not 0 < r_min <= r_max:
        raise ValueError("radius_range must satisfy 0 < min <= max")
    if len(size) != 3 or min(size) <= 0:
        raise ValueError("size must be three positive numbers of largest diameters")
    if size[0] <= 2 or size[1] <= 2:
        raise ValueError("size: the box must be wider than two largest diameters")
    if not 0 < fall_stiffness_factor <= 1:
        raise ValueError("fall_stiffness_factor must lie in (0, 1]")
    if not drag >= 0:
        raise ValueError("drag must be >= 0")
    from ._kernels_integrate import verlet_run

    rng = np.random.default_rng(seed)
    d = 2.0 * r_max
    lx, ly, height = size[0] * d, size[1] * d, size[2] * d
    mean_vol = 4.0 / 3.0 * np.pi * (r_max**4 - r_min**4) / (4.0 * (r_max - r_min)) \
        if r_max > r_min else 4.0 / 3.0 * np.pi * r_max**3
    n = max(int(round(0.6 * lx * ly * height / mean_vol)), 2)
    spacing = 1.15 * d
    nx, ny = max(int(lx // spacing), 1), max(int(ly // spacing), 1)
    layers = int(np.ceil(n / (nx * ny)))
    ix, iy, iz = np.meshgrid(np.arange(nx), np.arange(ny), np.arange(layers), indexing="ij")
    sites = np.stack([ix.ravel(), iy.ravel(), iz.ravel()], -1)[:n].astype(float)
    x = np.empty((n, 3))
    x[:, 0] = (sites[:, 0] + 0.5) * lx / nx + rng.uniform(-0.05, 0.05, n) * d
    x[:, 1] = (sites[:, 1] + 0.5) * ly / ny + rng.uniform(-0.05, 0.05, n) * d
    x[:, 2] = (sites[:, 2] + 0.5) * spacing + r_max
    r = rng.uniform(r_min, r_max, n)
    rng.shuffle(r)
    v = np.zeros((n, 3))
    w = np.zeros((n, 3))
    m = 4.0 / 3.0 * np.pi * r**3 * material.density
    box = Box(lx, ly, 0.0, float(x[:, 2].max() + 2 * d))
    beta = damping_parameter(material.restitution)
    v_fall = min(GRAVITY / drag if drag > 0 else np.inf,
                 np.sqrt(2.0 * GRAVITY * box.lz_max))
    skin = 0.3 * r_max
    steps_total = 0
    t_sim = 0.0
    nl = build_neighbors(x, r, box, skin)
    hist = np.zeros((nl.n_pairs, 3))
    wall_hist = np.zeros((n, 3))
    e_scale = m.max() * GRAVITY * d

    def run_stage(mat, v_ref, chunk_time):
        nonlocal nl, hist, steps_total, t_sim
        dt = stable_time_step(mat, r_min, r_max, v_ref)
        from tqdm.auto import tqdm

        bar = tqdm(desc="settle", unit="chunk", disable=not progress)
        while True:
            # No grain may cross more than a fraction of the skin between neighbour checks.
            v_bound = max(float(np.sqrt((v * v).sum(axis=1).max())), v_ref, 1e-6)
            chunk = int(max(10, min(chunk_time / dt, 0.4 * skin / (v_bound * dt))))
            energy = np.zeros(0)
            verlet_run(x, v, w, r, m, nl.pairs, hist, np.array([lx, ly]), mat.E_f, mat.G_f,
                       beta, v_ref, mat.friction, dt, chunk, -GRAVITY, 0, energy, 0.0,
                       wall_hist, float(drag))
            steps_total += chunk
            t_sim += chunk * dt
            bar.update(1)
            if not np.all(np.isfinite(x)):
                raise RuntimeError("settle: the integration blew up (non-finite positions)")
            nl, hist = _refresh_neighbors("settle", nl, hist, x, r, box, skin)
            ke = 0.5 * np.sum(m[:, None] * v * v) / n
            if ke < kinetic_tolerance * e_scale and t_sim > 0.01:
                break
            if t_sim > max_time:
                raise RuntimeError(f"settle: not at rest after {max_time} s of simulated time "
                                   f"(kinetic energy per grain {ke:.3g} J)")
        bar.close()

    soft = dataclasses.replace(material, shear_modulus=material.shear_modulus
                               * fall_stiffness_factor) if fall_stiffness_factor < 1 else material
    run_stage(soft, max(v_fall, 1e-3), 2e-3)
    if fall_stiffness_factor < 1:
        run_stage(material, 0.01, 2e-4)
    # Overlaps beyond a few per cent of a radius mean the time step or stiffness is wrong.
    pack = Pack(x, v, w, r, box, material, np.asarray(nl.pairs, dtype=np.int32), hist,
                stage="settle", time=t_sim,
                metadata={"seed": int(seed), "n_grains": int(n), "steps": int(steps_total),
                          "drag": float(drag), "fall_stiffness_factor":
                          float(fall_stiffness_factor), "size_diameters": list(map(float, size)),
                          "radius_range_m": [r_min, r_max]})
    phi = porosity(pack)
    z = coordination_number(pack)
    return dataclasses.replace(pack, metadata={**pack.metadata, "porosity": phi,
                                               "coordination_number": z})


def compact(pack: Pack, *, target_porosity=None, target_stress=None, strain_step=2e-3,
            slab=1.0, drag=2000.0, rest_tolerance=1e-4, max_increments=400, isotropic=False,
            progress=False) -> Pack:
    r"""Compact a settled pack between frozen end slabs (García & Medina, Sect. III A).

    The grains within ``slab`` largest diameters of the bottom and of the top are frozen. At each
    increment the sample is shortened by ``strain_step`` of its height — an affine step of all
    positions toward the core — and the mobile grains relax (damped with ``-drag m v``, no
    gravity, no floor) until their kinetic energy is below ``rest_tolerance`` times the elastic
    energy of the contacts. After each increment the porosity and coordination number of the core
    (between the slabs) and the vertical contact stress :math:`\sigma_{zz}` (virial of the core,
    :func:`md.observe.contact_stress`) are recorded. The run stops at the first increment that
    reaches ``target_porosity`` or ``target_stress`` (Pa).

    With ``isotropic=True`` each increment also shrinks the periodic lengths in x and y (and
    the x, y positions with them) by ``strain_step``: an isotropic confinement, as Xu 2023
    (Sect. 2.3) prepares its bonded samples. ``target_stress`` then refers to the mean stress
    :math:`\mathrm{tr}\,\sigma/3`, recorded as ``stress_mean``.

    Returns
    -------
    Pack
        ``stage="compact"``; ``metadata["record"]`` holds the lists ``porosity``,
        ``coordination_number``, ``stress_zz`` and ``stress_mean`` (Pa) and ``strain`` per
        increment.
    """
    from ._kernels_integrate import elastic_energy, verlet_run
    from .observe import contact_stress

    if target_porosity is None and target_stress is None:
        raise ValueError("give target_porosity or target_stress")
    if target_porosity is not None and not MIN_TARGET_POROSITY <= target_porosity < 1:
        raise ValueError(f"target_porosity must lie in [{MIN_TARGET_POROSITY}, 1): elastic "
                         "grains cannot be compacted far below random close packing")
    if target_stress is not None and not target_stress > 0:
        raise ValueError("target_stress must be > 0 Pa")
    if not 0 < strain_step < 0.05:
        raise ValueError("strain_step must lie in (0, 0.05)")
    mat = pack.material
    x = pack.positions.copy()
    v = np.zeros_like(x)
    w = np.zeros_like(x)
    r = pack.radii.copy()
    n = r.size
    m = 4.0 / 3.0 * np.pi * r**3 * mat.density
    d = 2.0 * r.max()
    box = pack.box
    z_lo, z_hi = x[:, 2].min(), x[:, 2].max()
    fixed = (x[:, 2] < z_lo + slab * d) | (x[:, 2] > z_hi - slab * d)
    if fixed.all() or not fixed.any():
        raise ValueError("slab: the frozen slabs must leave mobile grains between them")
    if target_porosity is not None:
        phi0 = porosity(pack, bottom=z_lo + slab * d, top=z_hi - slab * d)
        if target_porosity >= phi0:
            raise ValueError(f"target_porosity {target_porosity} is not below the current "
                             f"porosity {phi0:.4f}")
    beta = damping_parameter(mat.restitution)
    skin = 0.3 * r.min()
    nl = build_neighbors(x, r, box, skin)
    hist = _remap_history(pack.pairs, pack.history, nl.pairs, n)
    v_ref = 0.01
    dt = stable_time_step(mat, r.min(), r.max(), v_ref)
    record = {"strain": [], "porosity": [], "coordination_number": [], "stress_zz": [],
              "stress_mean": []}
    strain = 0.0
    from tqdm.auto import tqdm

    bar = tqdm(total=max_increments, desc="compact", unit="step", disable=not progress)
    for _ in range(max_increments):
        centre = 0.5 * (x[:, 2].min() + x[:, 2].max())
        x[:, 2] = centre + (x[:, 2] - centre) * (1.0 - strain_step)
        strain += strain_step
        if isotropic:                        # periodic images move in with the grains
            x[:, :2] *= 1.0 - strain_step
            box = Box(box.lx * (1.0 - strain_step), box.ly * (1.0 - strain_step), box.lz_min,
                      box.lz_max)
            old_pairs = nl.pairs
            nl = build_neighbors(x, r, box, skin)
            hist = _remap_history(old_pairs, hist, nl.pairs, n)
        for _relax in range(2000):
            verlet_run(x, v, w, r, m, nl.pairs, hist, np.array([box.lx, box.ly]), mat.E_f,
                       mat.G_f, beta, v_ref, mat.friction, dt, 200, 0.0, 0, np.zeros(0),
                       -np.inf, np.zeros((0, 3)), float(drag), fixed)
            if not np.all(np.isfinite(x)):
                raise RuntimeError("compact: the integration blew up (non-finite positions)")
            nl, hist = _refresh_neighbors("compact", nl, hist, x, r, box, skin)
            ke = 0.5 * np.sum(m[:, None] * v * v)
            pe = elastic_energy(x, r, nl.pairs, np.array([box.lx, box.ly]), mat.E_f)
            if ke <= rest_tolerance * max(pe, 1e-300):
                break
        else:
            raise RuntimeError("compact: the pack did not come to rest within an increment")
        lo = x[fixed, 2][x[fixed, 2] < centre].max() + r.max()
        hi = x[fixed, 2][x[fixed, 2] > centre].min() - r.max()
        cur = Pack(x.copy(), v.copy(), w.copy(), r, box, mat, np.asarray(nl.pairs, np.int32),
                   hist.copy(), stage="compact")
        phi = porosity(cur, bottom=lo, top=hi)
        sigma = contact_stress(x, r, nl.pairs, box, mat, z_range=(lo, hi))
        mobile = Pack(x[~fixed], v[~fixed], w[~fixed], r[~fixed], box, mat,
                      np.zeros((0, 2), np.int32), np.zeros((0, 3)))
        record["strain"].append(strain)
        record["porosity"].append(phi)
        record["coordination_number"].append(coordination_number(mobile))
        record["stress_zz"].append(float(sigma[2, 2]))
        record["stress_mean"].append(float(np.trace(sigma)) / 3.0)
        bar.update(1)
        measure = record["stress_mean" if isotropic else "stress_zz"][-1]
        if (target_porosity is not None and phi <= target_porosity) or \
                (target_stress is not None and measure >= target_stress):
            break
    else:
        raise RuntimeError(f"compact: target not reached in {max_increments} increments "
                           f"(porosity {record['porosity'][-1]:.4f}, "
                           f"stress {record['stress_zz'][-1]:.3g} Pa)")
    bar.close()
    return dataclasses.replace(cur, metadata={**pack.metadata, "record": record,
                                              "strain_step": strain_step, "slab": slab,
                                              "isotropic": bool(isotropic)})


def prepare_pack(workdir, *, settle_options=None, compact_options=None, progress=False) -> Pack:
    """Settle then compact a pack, saving each stage in ``workdir`` and resuming from the last
    saved one: ``settle.nc`` and ``compact.nc``. An interrupted run loses at most the stage it
    was in; a finished stage is never recomputed (delete its file to redo it).

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

    from .state import load_pack, save_pack

    folder = Path(workdir)
    folder.mkdir(parents=True, exist_ok=True)
    settled_file, compacted_file = folder / "settle.nc", folder / "compact.nc"
    if compact_options is not None and compacted_file.exists():
        return load_pack(compacted_file)
    if settled_file.exists():
        pack = load_pack(settled_file)
    else:
        pack = settle(**(settle_options or {}), progress=progress)
        save_pack(pack, settled_file)
    if compact_options is None:
        return pack
    pack = compact(pack, **compact_options, progress=progress)
    save_pack(pack, compacted_file)
    return pack
