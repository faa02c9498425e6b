"""Deposition of a grain pack onto a flat floor (García & Medina, Sect. III A). SI units.

Two protocols:

- ``"sequential"`` (the source's): grains are dropped in small waves at random x, y from above
  the growing pile, with the speed they reach falling through the fluid from a fixed height,
  and settle on the grains already deposited while the next wave falls;
- ``"lattice"`` (faster): all grains are released at once from a jittered lattice.

Both end with the whole pack relaxed to rest and return a :class:`md.state.Pack`.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ._dynamics import refresh_neighbors, remap_history, time_step
from .contact import QUARTZ, GrainMaterial, damping_parameter
from .neighbors import build_neighbors
from .observe import coordination_number, core_window, porosity
from .space import Box
from .state import Pack

__all__ = ["settle", "drop_speed", "PROTOCOLS"]

GRAVITY = 9.81
PROTOCOLS = ("sequential", "lattice")


def drop_speed(height, drag, gravity=GRAVITY):
    r"""Speed (m/s) of a grain released at rest after falling ``height`` (m) under gravity with
    the viscous drag ``-drag m v`` (1/s): the root of
    :math:`s(v) = -v/k - (v_t/k)\ln(1 - v/v_t)`, :math:`v_t = g/k`, :math:`k` = ``drag``
    (integral of :math:`v\,dv/(g - k v)`); :math:`\sqrt{2 g s}` without drag."""
    height = float(height)
    if not height >= 0:
        raise ValueError(f"height must be >= 0 m; got {height}")
    if not drag >= 0:
        raise ValueError(f"drag must be >= 0 1/s; got {drag}")
    if drag == 0 or height == 0:
        return float(np.sqrt(2.0 * gravity * height))
    from scipy.optimize import brentq

    v_t = gravity / drag

    def fallen(v):
        return -v / drag - v_t / drag * np.log1p(-v / v_t) - height

    top = v_t * (1.0 - 1e-15)
    if fallen(top) <= 0.0:                  # terminal speed to round-off
        return float(v_t)
    return float(brentq(fallen, 0.0, top, xtol=1e-15, rtol=1e-13))


#: Most grains :func:`settle` drops (it refuses a larger box up front, naming ``size``): memory
#: grows with the count, and a pack of this many grains already settles in hours on one core.
MAX_GRAINS = 100_000


def grain_count(size, radius_range) -> int:
    """Grains :func:`settle` drops to fill a box of ``size`` largest diameters to its target
    height at a porosity of 0.4 (radii uniform in ``radius_range``)."""
    r_min, r_max = map(float, radius_range)
    d = 2.0 * r_max
    volume = size[0] * size[1] * size[2] * d**3
    return max(int(round(0.6 * volume / _mean_volume(r_min, r_max))), 2)


def check_size(size, radius_range=(0.9, 1.0), *, name="size") -> tuple:
    """Check a box ``size`` (three finite numbers of largest diameters, wider than two, at
    least 5 high) and that it holds at most :data:`MAX_GRAINS` grains; returns it as floats.

    Raises ``ValueError`` naming ``name``.
    """
    try:
        size = tuple(float(x) for x in size)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be three numbers of largest diameters; got {size!r}"
                         ) from None
    if len(size) != 3 or not all(np.isfinite(size)) or min(size) <= 0:
        raise ValueError(f"{name} must be three positive finite numbers of largest diameters; "
                         f"got {size!r}")
    if size[0] <= 2 or size[1] <= 2:
        raise ValueError(f"{name}: the box must be wider than two largest diameters; got "
                         f"{size!r}")
    if size[2] < 5:
        raise ValueError(f"{name}: the height must be at least 5 largest diameters (a core "
                         f"between the end slabs); got {size!r}")
    n = grain_count(size, radius_range)
    if n > MAX_GRAINS:
        raise ValueError(f"{name} {list(size)} holds about {n:.3g} grains; at most "
                         f"{MAX_GRAINS} (md.deposit.MAX_GRAINS)")
    return size


def _mean_volume(r_min, r_max):
    if r_max == r_min:
        return 4.0 / 3.0 * np.pi * r_max**3
    return 4.0 / 3.0 * np.pi * (r_max**4 - r_min**4) / (4.0 * (r_max - r_min))


class _Run:
    """Arrays and neighbour list of a deposition that grows by waves of grains."""

    def __init__(self, box, material, drag, skin):
        self.box, self.mat, self.drag, self.skin = box, material, float(drag), skin
        self.x = np.zeros((0, 3))
        self.v = np.zeros((0, 3))
        self.w = np.zeros((0, 3))
        self.r = np.zeros(0)
        self.wall = np.zeros((0, 3))
        self.nl = build_neighbors(self.x, self.r, box, skin)
        self.hist = np.zeros((0, 3))
        self.beta = damping_parameter(material.restitution)
        self.steps = 0
        self.time = 0.0

    def add(self, x, v, r):
        self.x = np.ascontiguousarray(np.vstack([self.x, x]))
        self.v = np.ascontiguousarray(np.vstack([self.v, v]))
        self.w = np.ascontiguousarray(np.vstack([self.w, np.zeros_like(x)]))
        self.r = np.concatenate([self.r, r])
        self.wall = np.ascontiguousarray(np.vstack([self.wall, np.zeros_like(x)]))
        new = build_neighbors(self.x, self.r, self.box, self.skin)
        self.hist = remap_history(self.nl.pairs, self.hist, new.pairs, self.r.size)
        self.nl = new

    def advance(self, mat, v_ref, v_impact, chunk_time):
        """Run one chunk (at most ``chunk_time`` s, grains crossing at most 0.4 skin) with the
        time step of the current state: its contacts and impacts at up to ``v_impact`` or
        twice the fastest grain's speed. ``v_ref``: speed of the restitution calibration."""
        from ._kernels_integrate import verlet_run

        speed = float(np.sqrt((self.v * self.v).sum(axis=1).max()))
        impact = max(2.0 * speed, v_impact)
        dt = time_step(self.x, self.r, self.nl, self.box, mat, z_floor=0.0, impact_speed=impact)
        chunk = int(max(10, min(chunk_time / dt, 0.4 * self.skin / (max(impact, 1e-6) * dt))))
        m = 4.0 / 3.0 * np.pi * self.r**3 * mat.density
        verlet_run(self.x, self.v, self.w, self.r, m, self.nl.pairs, self.hist,
                   np.array([self.box.lx, self.box.ly]), mat.E_f, mat.G_f, self.beta, v_ref,
                   mat.friction, dt, chunk, -GRAVITY, 0, np.zeros(0), 0.0, self.wall, self.drag)
        self.steps += chunk
        self.time += chunk * dt
        self.nl, self.hist = refresh_neighbors("settle", self.nl, self.hist, self.x, self.r,
                                               self.box, self.skin, mat)

    def kinetic_energy_per_grain(self):
        m = 4.0 / 3.0 * np.pi * self.r**3 * self.mat.density
        return 0.5 * np.sum(m[:, None] * self.v * self.v) / self.r.size


def _wave_positions(rng, run, radii, z_insert, tries=200):
    """x, y of a wave at height ``z_insert``: uniform at random, redrawn while a grain would
    touch another of the wave or a grain already there (periodic in x and y)."""
    placed = np.zeros((0, 3))
    placed_r = np.zeros(0)
    near = np.abs(run.x[:, 2] - z_insert) < 2.0 * radii.max() + run.r.max(initial=0.0)
    others, others_r = run.x[near], run.r[near]
    for ri in radii:
        for _ in range(tries):
            p = np.array([rng.uniform(0, run.box.lx), rng.uniform(0, run.box.ly), z_insert])
            q = np.vstack([placed, others])
            if q.size:
                d = q - p
                d[:, 0] -= run.box.lx * np.round(d[:, 0] / run.box.lx)
                d[:, 1] -= run.box.ly * np.round(d[:, 1] / run.box.ly)
                gap = np.linalg.norm(d, axis=1) - np.concatenate([placed_r, others_r]) - ri
                if gap.min() < 0.05 * ri:
                    continue
            placed = np.vstack([placed, p])
            placed_r = np.append(placed_r, ri)
            break
        else:
            raise RuntimeError("settle: no room for a wave; use a smaller wave")
    return placed


def _sequential(run, rng, radii, mat, wave, drop_height, d, v_ref, bar=None):
    """Drop ``radii`` in waves of ``wave`` grains; each wave starts one largest radius above
    the highest grain with the speed of a fall from ``drop_height`` and the next is released
    once every grain of the previous one is a diameter below where it started or has landed
    (slower than a tenth of the largest fall speed). ``v_ref``: speed of the restitution
    calibration, m/s. ``bar``: a progress bar advanced by one per wave released."""
    v_terminal = GRAVITY / run.drag if run.drag > 0 else np.inf
    v_bound = min(v_terminal, np.sqrt(2.0 * GRAVITY * max(drop_height, d)))
    start, waves = 0, 0
    last, z_last = np.zeros(0, dtype=int), 0.0
    while start < radii.size:
        landed = np.sqrt((run.v[last] ** 2).sum(axis=1)) < 0.1 * v_bound
        if np.all((run.x[last, 2] < z_last - d) | landed):
            top = float(np.max(run.x[:, 2] + run.r)) if run.r.size else 0.0
            z_insert = top + 0.5 * d + 0.05 * d
            wave_r = radii[start:start + wave]
            pos = _wave_positions(rng, run, wave_r, z_insert)
            speed = drop_speed(max(drop_height - z_insert, 0.0), run.drag)
            vel = np.zeros_like(pos)
            vel[:, 2] = -speed
            last = np.arange(run.r.size, run.r.size + wave_r.size)
            z_last = z_insert
            run.add(pos, vel, wave_r)
            start += wave_r.size
            waves += 1
            if bar is not None:
                bar.update(1)
        run.advance(mat, v_ref, v_bound, 2e-3)
    return waves, v_bound


def _lattice(run, rng, radii, d, lx, ly):
    """Place all grains on a jittered lattice above the floor (released at once)."""
    n = radii.size
    spacing = 1.15 * d
    nx, ny = max(int(lx // spacing), 1), max(int(ly // spacing), 1)
    layers = int(np.ceil(n / (nx * ny)))
    ix, iy, iz = np.meshgrid(np.arange(nx), np.arange(ny), np.arange(layers), indexing="ij")
    sites = np.stack([ix.ravel(), iy.ravel(), iz.ravel()], -1)[:n].astype(float)
    x = np.empty((n, 3))
    x[:, 0] = (sites[:, 0] + 0.5) * lx / nx + rng.uniform(-0.05, 0.05, n) * d
    x[:, 1] = (sites[:, 1] + 0.5) * ly / ny + rng.uniform(-0.05, 0.05, n) * d
    x[:, 2] = (sites[:, 2] + 0.5) * spacing + 0.5 * d
    run.add(x, np.zeros_like(x), radii)
    return float(np.sqrt(2.0 * GRAVITY * x[:, 2].max()))


def settle(size=(8, 8, 32), radius_range=(1.8e-4, 2.0e-4), *, material: GrainMaterial = QUARTZ,
           seed=0, protocol="sequential", wave=None, drop_height=None, drag=50.0,
           fall_stiffness_factor=1.0, kinetic_tolerance=1e-7, max_time=5.0,
           progress=False) -> Pack:
    """Ballistic deposition of a grain pack onto a flat floor (García & Medina, Sect. III A).

    Grains with radii uniform in ``radius_range`` fall under gravity with viscous drag
    (``-drag m v``) through a box periodic in x and y, collide with Hertz–Mindlin contacts
    (:mod:`md.contact`) and come to rest on the floor and on each other. The run stops when
    the kinetic energy per grain is below ``kinetic_tolerance`` times :math:`m g d` of the
    largest grain. The time step follows the stiffest linearised contact of the current state
    and the fastest possible impact (:func:`md.integrate.contact_time_step`).

    ``protocol="sequential"`` (default, the source's) drops the grains in waves of ``wave``
    grains at random x, y (by default a wave covers a fifth of the floor in projection; the
    source drops them one at a time), each wave with the speed of a fall from ``drop_height``
    (:func:`drop_speed`); ``"lattice"`` releases all grains at once from a jittered lattice.

    Accelerated deposition: with ``fall_stiffness_factor < 1`` the contacts are that much
    softer while the grains fall and settle, then the true stiffness is restored and the pack
    relaxed to rest again; the faithful run has the factor 1.

    Parameters
    ----------
    size : (float, float, float)
        Box width, depth and target height in largest diameters; the number of grains fills the
        target height at a porosity of 0.4. Default (8, 8, 32), the source's sample. The height
        must leave a core between the end slabs (at least 5); at most :data:`MAX_GRAINS` grains.
    radius_range : (float, float)
        Smallest and largest radius, m; default 0.18–0.20 mm (the source's).
    material : GrainMaterial
    seed : int
        Seed of the random generator (reproducible packs).
    protocol : {"sequential", "lattice"}
    wave : int, optional
        Grains per wave (sequential); default a fifth of a monolayer, at least 1.
    drop_height : float, optional
        Height above the floor from which the grains fall, m (sequential); default 1.5 times
        the target height.
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
        ``stage="settle"``; ``metadata`` holds the core porosity (``porosity``, in the window
        ``core_window_m`` between the slabs a compaction freezes), the porosity from the floor
        to one diameter below the top (``porosity_from_floor``), coordination number, steps,
        seed and parameters.
    """
    r_min, r_max = map(float, radius_range)
    if not 0 < r_min <= r_max < np.inf:
        raise ValueError(f"radius_range must satisfy 0 < min <= max (finite, m); got "
                         f"{radius_range!r}")
    size = check_size(size, (r_min, r_max))
    if protocol not in PROTOCOLS:
        raise ValueError(f"protocol must be one of {', '.join(PROTOCOLS)}; got {protocol!r}")
    if not 0 < fall_stiffness_factor <= 1:
        raise ValueError("fall_stiffness_factor must lie in (0, 1]")
    if not drag >= 0:
        raise ValueError("drag must be >= 0")
    if not kinetic_tolerance > 0:
        raise ValueError(f"kinetic_tolerance must be > 0; got {kinetic_tolerance}")
    if not max_time > 0:
        raise ValueError(f"max_time must be > 0 s; got {max_time}")
    d = 2.0 * r_max
    lx, ly, height = size[0] * d, size[1] * d, size[2] * d
    drop_height = 1.5 * height if drop_height is None else float(drop_height)
    if not drop_height > 0:
        raise ValueError(f"drop_height must be > 0 m; got {drop_height}")
    monolayer = lx * ly / (np.pi * r_max**2)
    wave = max(int(0.2 * monolayer), 1) if wave is None else int(wave)
    if not 1 <= wave <= 0.5 * monolayer:
        raise ValueError(f"wave must lie in [1, {int(0.5 * monolayer)}] (half a monolayer)")

    rng = np.random.default_rng(seed)
    n = grain_count(size, (r_min, r_max))
    radii = rng.uniform(r_min, r_max, n)
    box = Box(lx, ly, 0.0, max(drop_height, 1.2 * height) + 2.0 * d)
    run = _Run(box, material, drag, 0.3 * r_max)
    soft = dataclasses.replace(material, shear_modulus=material.shear_modulus
                               * fall_stiffness_factor) if fall_stiffness_factor < 1 else material
    from tqdm.auto import tqdm

    extra = {}
    # The restitution e_n holds at the terminal speed (the same contact law whatever the drop
    # height), without drag at the free fall from the drop height or the top of the lattice.
    v_terminal = GRAVITY / drag if drag > 0 else np.inf
    if protocol == "sequential":
        v_ref = min(v_terminal, np.sqrt(2.0 * GRAVITY * drop_height)) if drag == 0 \
            else v_terminal
        with tqdm(desc="settle: deposition", unit="wave", total=-(-n // wave),
                  disable=not progress) as bar:
            waves, v_bound = _sequential(run, rng, radii, soft, wave, drop_height, d, v_ref,
                                         bar)
        extra = {"wave": wave, "waves": waves, "drop_height_m": drop_height}
    else:
        v_fall = _lattice(run, rng, radii, d, lx, ly)
        v_bound = min(v_fall, v_terminal)
        v_ref = v_terminal if drag > 0 else v_fall
    extra["restitution_speed_m_s"] = float(v_ref)
    e_scale = 4.0 / 3.0 * np.pi * r_max**3 * material.density * GRAVITY * d
    # Falling and settling (impacts up to v_bound), then, after softer falling, at rest again
    # with the true stiffness (the time step from the contacts and the grains' own speeds).
    bar = tqdm(desc="settle: to rest", unit="chunk", disable=not progress)
    stages = [(soft, v_bound, 2e-3, 0.01)]
    if soft is not material:
        stages.append((material, 0.0, 2e-4, 0.0))
    for mat, v_impact, chunk_time, t_min in stages:
        t0 = run.time
        while True:
            run.advance(mat, v_ref, v_impact, chunk_time)
            bar.update(1)
            ke = run.kinetic_energy_per_grain()
            if ke < kinetic_tolerance * e_scale and run.time - t0 > t_min:
                break
            if run.time > max_time:
                raise RuntimeError(f"settle: not at rest after {max_time} s of simulated time "
                                   f"(kinetic energy per grain {ke:.3g} J)")
    bar.close()
    pack = Pack(run.x, run.v, run.w, run.r, box, material,
                np.asarray(run.nl.pairs, dtype=np.int32), run.hist, stage="settle",
                time=run.time,
                metadata={"seed": int(seed), "n_grains": int(n), "steps": int(run.steps),
                          "protocol": protocol, "drag": float(drag),
                          "fall_stiffness_factor": float(fall_stiffness_factor),
                          "size_diameters": list(map(float, size)),
                          "radius_range_m": [r_min, r_max], **extra})
    window = core_window(pack)
    z = pack.positions[:, 2]
    from_floor = porosity(pack, bottom=0.0, top=float(np.max(z + pack.radii) - d))
    return dataclasses.replace(pack, metadata={
        **pack.metadata, "core_window_m": list(window), "porosity": porosity(pack),
        "porosity_from_floor": from_floor, "coordination_number": coordination_number(pack)})
