"""The MD backend of a burial scene: burial hands each chosen depth's largest effective stress
and cement fraction to :func:`md.along_depth.carry_down`, and the dry moduli it returns are
saturated with the scene's fluid by Gassmann's equation.

Private to the scene runner (:mod:`rockcem.runner`); imported, with numba, only by a scene
with ``[models.md]``. The mapping and its reasoning are in docs/user_guide/md_along_depth.md.
"""

from __future__ import annotations

import math
from pathlib import Path
from types import SimpleNamespace

import numpy as np

__all__ = ["md_depth_indices", "md_model", "md_warnings"]

#: Diagnostic variables of the MD backend, per depth (NaN where MD did not run).
MD_DEPTH_VARIABLES = ("md_stress", "md_stress_present", "md_pack_porosity", "md_porosity",
                      "md_cement_saturation", "md_cement_overflow", "md_coordination_number")
#: Diagnostic variables per MD model member and depth.
MD_MODEL_VARIABLES = ("vp_error_resolution", "vs_error_resolution", "vp_error_sample",
                      "vs_error_sample", "vp_error", "vs_error", "md_trusted",
                      "md_within_bounds", "md_resolution_asymptotic", "md_density",
                      "md_wall_time", "thomsen_epsilon", "thomsen_gamma", "thomsen_delta")
#: Default largest total error of a trusted MD member, relative to its velocity.
TRUST_THRESHOLD = 0.05


def md_labels(params) -> list[str]:
    """Model labels of the MD members: ``md`` for one scheme, ``md_<scheme>`` for several."""
    schemes = params["schemes"]
    return ["md"] if len(schemes) == 1 else [f"md_{s}" for s in schemes]


def md_depth_indices(depth, max_stress, params) -> np.ndarray:
    """Indices of the profile depths MD runs at: the nearest profile depth to each of
    ``depths``, or ``count`` depths spread evenly below the surface (where the effective stress
    is > 0). Raises ValueError for a depth outside the profile or one that loads nothing."""
    depth = np.asarray(depth, dtype=float)
    loaded = np.flatnonzero(np.asarray(max_stress) > 0)
    if loaded.size == 0:
        raise ValueError("no depth of the profile bears an effective stress > 0")
    if params["depths"] is not None:
        if params["count"] is not None:
            raise ValueError("give depths or count, not both")
        want = np.asarray(params["depths"], dtype=float)
        if want.size == 0:
            raise ValueError("depths must list at least one depth")
        lo, hi = depth.min(), depth.max()
        if np.any((want < lo) | (want > hi)):
            raise ValueError(f"depths must lie within the profile, {lo:g}-{hi:g} m; "
                             f"got {want.tolist()}")
        idx = np.argmin(np.abs(depth[None, :] - want[:, None]), axis=1)
        unloaded = np.asarray(max_stress)[idx] <= 0
        if np.any(unloaded):
            k = int(np.flatnonzero(unloaded)[0])
            raise ValueError(f"depth {want[k]:g} m (profile depth {depth[idx[k]]:g} m) bears "
                             "no effective stress: the MD pack needs a load")
        values, first, counts = np.unique(idx, return_index=True, return_counts=True)
        if np.any(counts > 1):
            k = values[counts > 1][0]
            same = want[idx == k].tolist()
            raise ValueError(f"depths {same} fall on the same profile depth {depth[k]:g} m "
                             "(refine path.depth_step or drop one)")
        return values
    count = 3 if params["count"] is None else params["count"]
    if not 1 <= count <= loaded.size:
        raise ValueError(f"count must lie in [1, {loaded.size}] (the loaded profile depths); "
                         f"got {count}")
    pick = loaded[np.round(np.linspace(0, loaded.size - 1, count + 1)[1:]).astype(int)] \
        if count < loaded.size else loaded
    return np.unique(pick)


def _materials(grain, cement):
    import md

    from .elastic import poisson_ratio

    nu = float(poisson_ratio(grain.K, grain.G))
    g = md.GrainMaterial(grain.G * 1e9, nu, grain.rho * 1e3, md.QUARTZ.friction,
                         md.QUARTZ.restitution)
    vp = np.sqrt((cement.K + 4.0 / 3.0 * cement.G) / cement.rho) * 1e3
    vs = np.sqrt(cement.G / cement.rho) * 1e3
    return g, md.CementMaterial(float(vp), float(vs), cement.rho * 1e3)


def md_model(depth, present_stress, max_stress, cement_fraction, grain, cement, fluids,
             grain_size, params, *, intergranular_volume=None, workdir, scheduler=None, jobs=1,
             progress=False):
    """Run the MD members of a scene and saturate them.

    Parameters
    ----------
    depth, present_stress, max_stress, cement_fraction : ndarray, shape (n,)
        The profile: depth (m), present and largest effective stress (MPa), cement fraction.
    grain, cement : rockcem.materials.Mineral
    fluids : sequence of rockcem.materials.Fluid
        The pore fluids to saturate the MD members with, one saturated rock each (numbers, or
        one value per profile depth): the scene's fluid, or the patches of patchy saturation;
        the MD members run once for all of them.
    grain_size : float
        Grain diameter, mm.
    params : dict
        The scene's ``[models.md]`` table.
    intergranular_volume : ndarray, shape (n,), optional
        Burial's intergranular volume (porosity + cement fraction): the MD pack is compacted
        to it where ``params["compaction"]`` is ``"reconstruct"`` (the default; needs it).
    workdir : path
        Default folder of the stage files (the table's ``workdir`` wins).
    scheduler, jobs
        Where the MD members run (:func:`md.along_depth.carry_down`).

    Returns
    -------
    (list of dict, dict, list of dict)
        Per fluid, per model label a namespace of ``K_dry, G_dry, K_sat, G_sat, vp, vs,
        density`` (GPa, km/s, g/cm³; NaN off the MD depths); the per-depth diagnostics; per
        fluid, per label the per-model diagnostics (:data:`MD_DEPTH_VARIABLES`,
        :data:`MD_MODEL_VARIABLES`).
    """
    from md.convergence import resolution_error

    from .bounds import hashin_shtrikman_average, hashin_shtrikman_upper

    n = depth.size
    idx = md_depth_indices(depth, max_stress, params)
    if np.any(present_stress[idx] <= 0):
        k = idx[present_stress[idx] <= 0][0]
        raise ValueError(f"depth {depth[k]:g} m bears no effective stress today "
                         f"({present_stress[k]:.4g} MPa): the MD pack cannot be unloaded to it")
    compaction = params.get("compaction", "reconstruct")
    igv = None
    if compaction == "reconstruct":
        if intergranular_volume is None:
            raise ValueError('compaction = "reconstruct" needs burial\'s intergranular volume')
        # Never below the cement (burial's IGV holds its cement).
        igv = np.maximum(np.asarray(intergranular_volume, dtype=float)[idx], cement_fraction[idx])
    # Every key is checked here, before the pack is settled (minutes) or a lattice allocated.
    params = check_md_table(params, cemented=bool(np.any(cement_fraction[idx] > 0)),
                            intergranular_volume=None if igv is None else float(igv.min()))
    r_max = grain_size / 2.0 * 1e-3
    g_mat, c_mat = _materials(grain, cement)
    work = Path(params["workdir"]) if params["workdir"] else Path(workdir)
    for parent in (work, *work.parents):
        if parent.exists() and not parent.is_dir():
            raise ValueError(f"workdir {str(work)!r} "
                             + ("is a file" if parent == work else f"lies under the file "
                                f"{parent}") + ": it must be a folder (made if missing)")
    samples = params["samples"]
    parallel = scheduler is None and jobs > 1 and samples > 1
    width = min(jobs, samples) if parallel else 1
    common = dict(present_stress=np.minimum(present_stress[idx], max_stress[idx]),
                  intergranular_volume=igv, compaction=compaction,
                  cement_history=params.get("cement_history", "grown"),
                  schemes=params["schemes"], size=params["size"],
                  radius_range=((1.0 - params["radius_spread"]) * r_max, r_max),
                  material=g_mat, cement=c_mat,
                  fall_stiffness_factor=params["fall_stiffness_factor"],
                  resolution=params["resolution"],
                  resolution_check=params["resolution_check"],
                  resolution_check2=params["resolution_check2"],
                  interface=params["interface"], measure=params["measure"],
                  anisotropy=params.get("anisotropy", "ti"),
                  full_sample=params.get("full_sample", "voxel"),
                  slab=params["slab"], workdir=work, scheduler=scheduler,
                  jobs=max(1, jobs // width), progress=progress and not parallel)
    tasks = [(max_stress[idx], cement_fraction[idx], {**common, "seed": params["seed"] + k})
             for k in range(samples)]
    if parallel:
        # Local processes and several packs: the packs are carried down side by side (each
        # pack's compaction stages are sequential; the members of one pack are few), the
        # processes shared among them.
        from md._tasks import run_tasks

        done = {task[2]["seed"]: ds for task, ds in run_tasks(
            _carry_down_task, tasks, jobs=width, progress=progress, desc="MD packs")}
        runs = [done[task[2]["seed"]] for task in tasks]
    else:
        runs = [_carry_down_task(*task) for task in tasks]

    def full(values):
        out = np.full(n, np.nan)
        out[idx] = values
        return out

    def stack(name, scheme=None):
        """A variable of every sample, shape (samples, depths)."""
        return np.stack([(r[name] if scheme is None else r[name].sel(scheme=scheme)).values
                         for r in runs])

    scheme0 = params["schemes"][0]              # porosity and S_c do not depend on the scheme
    phi_pack, phi = stack("porosity_pack"), stack("porosity", scheme0)
    per_depth = {"md_stress": full(stack("stress_reached").mean(0) / 1e6),
                 "md_stress_present": full(stack("stress_present").mean(0) / 1e6),
                 "md_pack_porosity": full(phi_pack.mean(0)), "md_porosity": full(phi.mean(0)),
                 "md_cement_saturation": full(stack("saturation", scheme0).mean(0)),
                 "md_cement_overflow": full(stack("cement_overflow", scheme0).max(0)),
                 "md_coordination_number": full(stack("coordination_number").mean(0))}
    # Each sample's solid: grain and cement at its own fractions (the cement its core holds).
    beta_c = (phi_pack - phi) / (1.0 - phi)
    mineral = hashin_shtrikman_average([grain.K, cement.K], [grain.G, cement.G],
                                       np.stack([1.0 - beta_c, beta_c], axis=-1))
    # The upper Hashin-Shtrikman bound of each sample's dry frame: grain, cement, empty pores.
    upper = hashin_shtrikman_upper(
        [grain.K, cement.K, 0.0], [grain.G, cement.G, 0.0],
        np.stack([(1.0 - phi) * (1.0 - beta_c), (1.0 - phi) * beta_c, phi], axis=-1))
    ti = params.get("anisotropy", "ti") == "ti"

    def saturate(fluid):
        """The MD members saturated with ``fluid``: (models, per-model diagnostics)."""
        # Saturated bulk density of the core window (eq. 24 of Carcione et al. 2022) with the
        # porosity Gassmann is given (the engine's sample density also counts the end layers).
        # The fluid at the MD depths (a number, or one value per profile depth).
        K_fluid, rho_fluid = (np.asarray(v)[idx] if np.ndim(v) else v for v in (fluid.K, fluid.rho))
        rho = (1.0 - phi) * (grain.rho * (1.0 - beta_c) + cement.rho * beta_c) + phi * rho_fluid

        def velocities(scheme, suffix=""):
            """``(K_dry, G_dry, K_sat, vp, vs, epsilon, gamma, delta, sound)`` of every
            sample at one resolution (GPa, km/s; shape (samples, depths))."""
            c = {name: stack(f"{name}{suffix}", scheme) / 1e9 for name in MD_MODULI}
            return saturated_moduli(c, mineral.K, K_fluid, phi, rho, ti=ti)

        count = len(runs)
        models, per_model = {}, {}
        for label, scheme in zip(md_labels(params), params["schemes"]):
            K_dry, G_dry, K_sat, vp, vs, eps, gam, dlt, sound = velocities(scheme)
            omegas = [w for w in (params["resolution"], params["resolution_check"],
                                  params["resolution_check2"]) if w]
            if len(omegas) > 1:
                # Richardson estimates on the velocities themselves (the P and S moduli of one
                # resolution change together; md.convergence): first order from two resolutions,
                # the observed order from three where they are in the asymptotic range; averaged
                # over the samples, asymptotic where every sample is.
                coarse = [velocities(scheme, f"_{c}")[3:5]
                          for c in ("check", "check2")[:len(omegas) - 1]]
                vp_res, vp_asym = resolution_error(omegas, np.stack([vp] + [c[0] for c in coarse]))
                vs_res, vs_asym = resolution_error(omegas, np.stack([vs] + [c[1] for c in coarse]))
                vp_res, vs_res = vp_res.mean(0), vs_res.mean(0)
                asym = (vp_asym & vs_asym).all(0).astype(float) if len(omegas) == 3 \
                    else np.full(idx.size, np.nan)          # no three-point check made
            else:                                   # no coarser resolution: no error estimate
                vp_res = vs_res = asym = np.full(idx.size, np.nan)
            # A frame stiffer than the Hashin-Shtrikman upper bound of its solid and empty
            # pores by more than its own resolution error is not a rock (a resolution artefact
            # of a nearly filled lattice). Within that error it is consistent with the bound:
            # the voxel finite elements of a full sample (md.voxel) approach it from above, as
            # a displacement method does (0.01-0.2 %; docs/studies/md_voxel_fe.md). The
            # moduli's relative error is twice the velocities'.
            with np.errstate(invalid="ignore", divide="ignore"):
                slack = 1e-9 + 2.0 * np.nan_to_num(np.fmax(vp_res / np.abs(vp.mean(0)),
                                                           vs_res / np.abs(vs.mean(0))))
                sound &= (K_dry <= upper.K * (1 + slack)) & (G_dry <= upper.G * (1 + slack))
            # Sample-size error: standard error of the mean over the independent packs.
            vp_smp, vs_smp = ((v.std(0, ddof=1) / np.sqrt(count)) if count > 1 else
                              np.full(idx.size, np.nan) for v in (vp, vs))
            vp_tot, vs_tot = total_error(vp_res, vp_smp), total_error(vs_res, vs_smp)
            sound = sound.all(0)
            trusted = sound & trusted_members(vp.mean(0), vp_tot, vs.mean(0), vs_tot,
                                              params.get("trust_threshold", TRUST_THRESHOLD))
            models[label] = SimpleNamespace(K_dry=full(K_dry.mean(0)), G_dry=full(G_dry.mean(0)),
                                            K_sat=full(K_sat.mean(0)), G_sat=full(G_dry.mean(0)),
                                            vp=full(vp.mean(0)), vs=full(vs.mean(0)),
                                            density=full(rho.mean(0)))
            per_model[label] = {"vp_error_resolution": full(vp_res),
                                "vs_error_resolution": full(vs_res),
                                "vp_error_sample": full(vp_smp), "vs_error_sample": full(vs_smp),
                                "vp_error": full(vp_tot), "vs_error": full(vs_tot),
                                "md_trusted": full(trusted.astype(float)),
                                "md_within_bounds": full(sound.astype(float)),
                                "thomsen_epsilon": full(eps.mean(0)),
                                "thomsen_gamma": full(gam.mean(0)),
                                "thomsen_delta": full(dlt.mean(0)),
                                "md_resolution_asymptotic": full(asym),
                                "md_density": full(rho.mean(0)),
                                "md_wall_time": full(stack("wall_time", scheme).sum(0))}
        return models, per_model

    saturated = [saturate(f) for f in fluids]
    return [m for m, _ in saturated], per_depth, [d for _, d in saturated]


#: The dry moduli of an MD member in its stage files (Pa; md.along_depth.MODULI).
MD_MODULI = ("p_modulus", "shear_modulus", "c11", "c13", "c66")


def saturated_moduli(c, K_min, K_fluid, phi, rho, *, ti=True):
    r"""Dry and saturated moduli and vertical velocities of MD samples.

    Parameters
    ----------
    c : dict of ndarray
        The dry moduli, GPa: ``p_modulus`` (C33), ``shear_modulus`` (C44) and, for ``ti``,
        ``c11``, ``c13``, ``c66``.
    K_min, K_fluid, phi, rho
        Mineral and fluid bulk moduli (GPa), porosity and saturated density (g/cm³),
        broadcastable to the moduli.
    ti : bool
        ``True``: the sample is transversely isotropic (axis z): its dry bulk modulus is the
        one under hydrostatic stress (:func:`rockcem.anisotropy.ti_bulk_modulus`), it is
        saturated by anisotropic Gassmann (:func:`rockcem.anisotropy.ti_gassmann`; Gassmann
        1951, Brown & Korringa 1975), the velocities are the vertical ones,
        :math:`\sqrt{C^{sat}_{33}/\rho}` and :math:`\sqrt{C_{44}/\rho}` (Thomsen 1986,
        eq. 9), and Thomsen's parameters are the saturated rock's
        (:func:`rockcem.anisotropy.thomsen`). Where a sample's constants are not a
        positive-definite stiffness no stiffer than its mineral (the noise of a small pack),
        it falls back to the isotropic reading and is not ``sound``. ``False``: the isotropic
        approximation :math:`K_{dry} = C_{33} - \tfrac43 C_{44}` with isotropic Gassmann
        (Thomsen's parameters NaN).

    Returns
    -------
    tuple of ndarray
        ``(K_dry, G_dry, K_sat, vp, vs, epsilon, gamma, delta, sound)``; ``G_dry`` is C44
        (the fluid carries no shear), ``sound`` where the TI reading holds (all True for the
        isotropic one).
    """
    from .anisotropy import thomsen, ti_bulk_modulus, ti_gassmann
    from .fluids import gassmann

    c33, c44 = c["p_modulus"], c["shear_modulus"]
    K_min, K_fluid, phi, rho = np.broadcast_arrays(K_min, K_fluid, phi, rho, c33)[:4]
    K_dry = c33 - 4.0 / 3.0 * c44
    # Without pores (burial's pores full) there is no fluid to substitute: the saturated rock is
    # the dry one. Gassmann's bound K_dry <= K_min is then not asked of it either: its frame is
    # the mineral, measured (a voxel sample, md.voxel, is 0.01-0.2 % above its Hashin-Shtrikman
    # average from above, as a displacement method is); the bounds check is the caller's.
    full = phi <= 0
    K_sat = K_dry.copy()
    if np.any(~full):
        K_sat[~full] = gassmann(K_dry[~full], K_min[~full], K_fluid[~full], phi[~full])
    vp, vs = np.sqrt((K_sat + 4.0 / 3.0 * c44) / rho), np.sqrt(c44 / rho)
    nan = np.full(c33.shape, np.nan)
    eps, gam, dlt = nan.copy(), nan.copy(), nan.copy()
    sound = np.ones(c33.shape, bool)
    if not ti:
        return K_dry, c44, K_sat, vp, vs, eps, gam, dlt, sound
    c11, c13, c66 = c["c11"], c["c13"], c["c66"]
    c12 = c11 - 2.0 * c66
    with np.errstate(invalid="ignore"):
        sound = (np.isfinite(c11) & np.isfinite(c13) & np.isfinite(c66) & (c11 > c66)
                 & (c13**2 < c33 * (c11 - c66)) & (c44 > 0)
                 & (((2.0 * c11 + c33 + 2.0 * c12 + 4.0 * c13) / 9.0 <= K_min) | full))
    if np.any(sound):
        K_dry[sound] = ti_bulk_modulus(c11[sound], c13[sound], c33[sound], c66[sound])
        K_sat[sound & full] = K_dry[sound & full]
        vp[sound & full] = np.sqrt(c33[sound & full] / rho[sound & full])
        t = thomsen(c11[sound & full], c13[sound & full], c33[sound & full],
                    c44[sound & full], c66[sound & full])
        eps[sound & full], gam[sound & full], dlt[sound & full] = t.epsilon, t.gamma, t.delta
    k = sound & ~full
    if np.any(k):
        sat = ti_gassmann(c11[k], c13[k], c33[k], c44[k], c66[k], K_min[k], K_fluid[k], phi[k])
        K_sat[k] = ti_bulk_modulus(sat.c11, sat.c13, sat.c33, sat.c66)
        vp[k] = np.sqrt(sat.c33 / rho[k])
        t = thomsen(sat.c11, sat.c13, sat.c33, sat.c44, sat.c66)
        eps[k], gam[k], dlt[k] = t.epsilon, t.gamma, t.delta
    return K_dry, c44, K_sat, vp, vs, eps, gam, dlt, sound


def _carry_down_task(max_stress, cement_fraction, options):
    """One pack carried down (:func:`md.along_depth.carry_down`; a task of
    :func:`md._tasks.run_tasks`, so module level)."""
    from md.along_depth import carry_down

    return carry_down(max_stress, cement_fraction, **options)


def total_error(resolution, sample) -> np.ndarray:
    """Total error of an MD velocity: the resolution and sample-size errors in quadrature
    (independent sources: the lattice and the pack). NaN where either was not measured (no
    coarser resolution; one pack): an error that was not measured is not zero."""
    return np.hypot(np.asarray(resolution, dtype=float), np.asarray(sample, dtype=float))


def trusted_members(vp, vp_error, vs, vs_error, threshold) -> np.ndarray:
    """Where an MD member is trusted: both total errors measured (finite) and at most
    ``threshold`` of their velocities. Everything else is flagged."""
    if not 0 < threshold < 1:
        raise ValueError(f"trust_threshold must lie in (0, 1); got {threshold}")
    with np.errstate(invalid="ignore"):
        return ((vp_error <= threshold * vp) & (vs_error <= threshold * vs)
                & np.isfinite(vp_error) & np.isfinite(vs_error))


#: Most cement-lattice cells of one MD member (at its finest resolution; :func:`lattice_cells`):
#: about 3.5 GB and 17 minutes of one core per member (:data:`LATTICE_BYTES_PER_CELL`,
#: :data:`LATTICE_SECONDS_PER_CELL`), Omega 17.7 on the default box of 4 x 4 x 12 diameters
#: (Omega 6, the default resolution, is 3.9e5 cells). A larger lattice is refused before any
#: work, with its estimate; ``resolution = 40`` (1.1e8 cells, about 40 GB) ran past 400 s and
#: 0.85 GB before anything refused it.
MAX_LATTICE_CELLS = 1.0e7
#: Peak memory of one member per lattice cell, bytes: the lattice, the linearised system and
#: the sparse LU factors of the static TI solve, measured (``ru_maxrss`` above the loaded pack,
#: one process per resolution) on a 3 x 3 x 8 pack of 96 grains compacted to 20 MPa with 8 %
#: contact cement: 195 MB at Omega 9 (5.0e5 cells, 390 bytes per cell) and 358 MB at Omega 12
#: (1.1e6 cells, 313 bytes per cell); 350 is their mean. At Omega 6 (1.5e5 cells) the same
#: measure gave 346 MB, more than at Omega 9, unexplained (a cost that does not scale with the
#: cells): an estimate to within a factor of a few, meant for lattices far above these.
LATTICE_BYTES_PER_CELL = 350.0
#: Time of one member per lattice cell, s (one core of the shared 2-core test machine, the same
#: runs: 47 s and 108 s, 9.4e-5 and 9.5e-5 s per cell).
LATTICE_SECONDS_PER_CELL = 1.0e-4


def lattice_cells(size, resolution, radius_spread) -> float:
    """Cells of the cement lattice of a pack of ``size`` largest diameters at ``resolution``
    cells per mean radius (:func:`md.cement.cement_lattice`: the cell width is the mean radius
    over :math:`\\Omega`; the mean radius of radii uniform in :math:`[(1-s)R, R]` is
    :math:`(1 - s/2)R`): :math:`l_x l_y l_z / w^3 = s_x s_y s_z\\,(2\\Omega/(1 - s/2))^3`."""
    return float(np.prod(size)) * (2.0 * resolution / (1.0 - radius_spread / 2.0)) ** 3


def check_md_table(params, *, cemented=True, intergranular_volume=None) -> dict:
    """Check every key of a ``[models.md]`` table before anything runs, and fill in the
    default coarser resolutions (:func:`resolve_checks`).

    Parameters
    ----------
    params : dict
        The table, defaults filled in (:data:`rockcem.scene.SCHEMA`).
    cemented : bool, keyword-only
        Whether a member has cement (the cement lattice is built).
    intergranular_volume : float, optional, keyword-only
        The smallest intergranular volume the pack is compacted to (reconstruction), for the
        height of the sample; None: Hertzian compaction (porosity near 0.37).

    Returns
    -------
    dict
        ``params`` with ``resolution_check`` and ``resolution_check2`` resolved.

    Raises
    ------
    ValueError
        Naming the key and its valid range: ``seed`` not an integer >= 0; ``samples`` outside
        [1, 50]; ``radius_spread`` outside [0, 1); ``resolution`` not > 1, or a lattice of
        more than :data:`MAX_LATTICE_CELLS` cells (with the memory and time it would take);
        ``slab`` not > 0, or too thick for 4 slabs in the compacted sample; ``size`` (md's
        :func:`md.deposit.check_size`, and a width in y that is not a whole multiple of that in
        x where there is cement); ``interface``, ``measure``, ``anisotropy``, ``compaction``,
        ``cement_history`` or ``schemes`` not one of their names; ``trust_threshold`` outside
        (0, 1); ``fall_stiffness_factor`` outside (0, 1].
    """
    from md.along_depth import CEMENT_HISTORIES, COMPACTIONS, FULL_SAMPLES, MEASURES, SCHEMES
    from md.deposit import check_size
    from md.interface import INTERFACES

    seed = params["seed"]
    if not (isinstance(seed, (int, np.integer)) and not isinstance(seed, bool) and seed >= 0):
        raise ValueError(f"seed must be an integer >= 0 (numpy's random seeds); got {seed!r}")
    if not 1 <= params["samples"] <= 50:
        raise ValueError(f"samples must lie in [1, 50]; got {params['samples']}")
    spread = params["radius_spread"]
    if not 0 <= spread < 1:
        raise ValueError(f"radius_spread must lie in [0, 1); got {spread}")
    for key, names in (("interface", INTERFACES), ("measure", MEASURES),
                       ("compaction", COMPACTIONS), ("cement_history", CEMENT_HISTORIES),
                       ("anisotropy", ("ti", "isotropic")), ("full_sample", FULL_SAMPLES)):
        value = params.get(key)
        if key in params and value not in names:
            raise ValueError(f"{key} must be one of {', '.join(names)}; got {value!r}")
    if params.get("anisotropy", "ti") == "ti" and params["measure"] != "static":
        raise ValueError(f"measure = {params['measure']!r} needs anisotropy = 'isotropic' (the "
                         "pulse test gives the vertical velocities only; 'ti' needs 'static')")
    if params.get("full_sample", "voxel") == "voxel" and params["measure"] != "static":
        raise ValueError(f"full_sample = 'voxel' is a static solve; measure = "
                         f"{params['measure']!r} needs full_sample = 'lattice'")
    schemes = list(params["schemes"])
    if not schemes or len(set(schemes)) != len(schemes) or any(s not in SCHEMES
                                                               for s in schemes):
        raise ValueError(f"schemes must be distinct names from {', '.join(SCHEMES)}; got "
                         f"{schemes}")
    threshold = params.get("trust_threshold", TRUST_THRESHOLD)
    if not 0 < threshold < 1:
        raise ValueError(f"trust_threshold must lie in (0, 1); got {threshold}")
    if not 0 < params["fall_stiffness_factor"] <= 1:
        raise ValueError(f"fall_stiffness_factor must lie in (0, 1]; got "
                         f"{params['fall_stiffness_factor']}")
    if not params["resolution"] > 1:
        raise ValueError(f"resolution must be > 1; got {params['resolution']}")
    size = check_size(params["size"], (1.0 - spread, 1.0), name="size")
    slab = params["slab"]
    if not slab > 0:
        raise ValueError(f"slab must be > 0 grain diameters; got {slab}")
    # The settled pack fills size[2] at a porosity of 0.4 (md.deposit.grain_count); compacted to
    # an intergranular volume v its height is size[2] (1 - 0.4) / (1 - v); Hertzian compaction
    # stops near 0.37. The static solve and the pulse test need 4 slabs (md.static).
    v = 0.37 if intergranular_volume is None else float(intergranular_volume)
    height = size[2] * 0.6 / (1.0 - v)
    if height / slab < 4:
        raise ValueError(f"slab = {slab:g} grain diameters is too thick: the compacted sample, "
                         f"about {height:.3g} diameters tall (size[2] = {size[2]:g} at an "
                         f"intergranular volume of {v:.3g}), holds {int(height // slab)} "
                         f"slab(s); the moduli need at least 4 (8 or more advised): give slab "
                         f"<= {height / 4:.3g} or a taller size")
    if cemented:
        ratio = size[1] / size[0]
        if abs(ratio - round(ratio)) > 1e-9 or round(ratio) < 1:
            raise ValueError(f"size {list(size)}: the cement lattice needs the box's width in y "
                             f"a whole multiple of its width in x (size[1] / size[0] = "
                             f"{ratio:.4g}); give size[1] = size[0] (or 2, 3, ... times it)")
    cells = lattice_cells(size, params["resolution"], spread)
    if cells > MAX_LATTICE_CELLS:
        most = (MAX_LATTICE_CELLS / lattice_cells(size, 1.0, spread)) ** (1.0 / 3.0)
        raise ValueError(
            f"resolution = {params['resolution']:g} on a box of {list(size)} diameters is a "
            f"cement lattice of about {cells:.3g} cells per member, above "
            f"rockcem._md_backend.MAX_LATTICE_CELLS = {MAX_LATTICE_CELLS:.3g}: about "
            f"{cells * LATTICE_BYTES_PER_CELL / 1e9:.3g} GB and "
            f"{cells * LATTICE_SECONDS_PER_CELL / 3600:.3g} h per member on one core; give "
            f"resolution <= {math.floor(most * 10) / 10:g} or a smaller size")
    out = resolve_checks(params)
    for key, lo, hi in (("resolution_check", 1.0, out["resolution"]),
                        ("resolution_check2", 1.0, out["resolution_check"])):
        value = out[key]
        if value != 0 and not (hi and lo <= value < hi):
            raise ValueError(f"{key} must be 0 or lie in [1, {hi:g}); got {value}")
    return out


def resolve_checks(params) -> dict:
    """``params`` with the default coarser resolutions filled in: ``resolution_check`` the
    resolution over :data:`md.convergence.MIN_RATIO` (1.5; none below 1) and
    ``resolution_check2`` that over 1.5 again (none below 1, and none without a first check).
    Resolutions closer than 1.5 apart let the lattice's noise decide the observed order
    (``benchmarks/md_error_coverage.py``)."""
    ratio = 1.5             # md.convergence.MIN_RATIO (md is not imported for the defaults)
    out = dict(params)
    if out["resolution_check"] is None:
        c = out["resolution"] / ratio
        out["resolution_check"] = c if c >= 1 else 0.0
    if out["resolution_check2"] is None:
        c = out["resolution_check"] / ratio if out["resolution_check"] else 0.0
        out["resolution_check2"] = c if c >= 1 else 0.0
    return out


def md_warnings(depth, porosity, per_depth, per_model=None) -> list[str]:
    """Lines for the Dataset's ``validity_warnings``: where the MD sample's porosity differs from
    burial's by more than 0.01 (Hertzian compaction stops near 0.37; reconstruction reaches
    burial's intergranular volume unless the Hertzian pack is already denser), where burial's cement overfilled the pack's pores, and (with ``per_model`` from a
    three-resolution run) where the resolution error is not an asymptotic estimate."""
    ran = np.isfinite(per_depth["md_porosity"])
    lines = []
    gap = per_depth["md_porosity"] - np.asarray(porosity)
    off = ran & (np.abs(np.nan_to_num(gap)) > 0.01)
    if np.any(off):
        lines.append(f"MD model at {', '.join(f'{d:g}' for d in depth[off])} m: the MD sample's "
                     f"porosity differs from burial's by {gap[off].min():+.3f} to "
                     f"{gap[off].max():+.3f} (Hertzian compaction stops near 0.37, and "
                     "reconstruction only compacts); its velocities are those of the rock it "
                     "has (md_porosity)")
    over = ran & (np.nan_to_num(per_depth["md_cement_overflow"]) > 0)
    if np.any(over):
        lines.append(f"MD model at {', '.join(f'{d:g}' for d in depth[over])} m: burial's cement "
                     "exceeds the MD pack's pores; the pores were filled (md_cement_overflow)")
    for label, diag in (per_model or {}).items():
        flagged = np.isfinite(diag["md_trusted"]) & (diag["md_trusted"] == 0)
        if np.any(flagged):
            unmeasured = flagged & ~(np.isfinite(diag["vp_error"]) & np.isfinite(diag["vs_error"]))
            why = ("its total error (resolution and sample size in quadrature) exceeds the trust "
                   "threshold of its velocity" if not np.any(unmeasured) else
                   "its total error exceeds the trust threshold of its velocity or was not "
                   "measured (a sample-size error needs samples >= 2, a resolution error a "
                   "resolution_check)")
            lines.append(f"MD model {label} at {', '.join(f'{d:g}' for d in depth[flagged])} m "
                         f"is not trusted: {why} (md_trusted = 0)")
        outside = np.isfinite(diag["md_within_bounds"]) & (diag["md_within_bounds"] == 0)
        if np.any(outside):
            lines.append(f"MD model {label} at {', '.join(f'{d:g}' for d in depth[outside])} m: "
                         "its dry frame is stiffer than the Hashin-Shtrikman upper bound of its "
                         "grains, cement and empty pores, or its five constants are not a "
                         "positive-definite stiffness within its mineral's (the noise of a "
                         "small pack; the isotropic reading is used there): not trusted "
                         "(md_within_bounds = 0)")
        asym = diag["md_resolution_asymptotic"]
        off = np.isfinite(asym) & (asym == 0)
        if np.any(off):
            lines.append(f"MD model {label} at {', '.join(f'{d:g}' for d in depth[off])} m: "
                         "the three lattice resolutions are not in the asymptotic range of vp, "
                         "vs or both (no credible order): the resolution error of a velocity "
                         "without one is three times the larger first-order step, of a velocity "
                         "with one the grid convergence index of its order (md.convergence)")
    return lines
