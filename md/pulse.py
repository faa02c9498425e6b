"""The acoustic pulse test (García & Medina, Sect. III G, eqs. 10–11) on the linearised
operator of :func:`md.acoustic_system`.

SI units. A square-wave displacement of one end slab, the other held; slab-averaged contact
forces as detector signals; arrival times of the first pulse; the velocity by eq. 11 with its
error, and beside it the errors eq. 11 leaves out (the pulse against its static long-wave limit,
and the resolution error where the caller supplies one).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from .static import _prescribed, _wave_axis, static_modulus

if TYPE_CHECKING:
    from .acoustic import AcousticSystem

__all__ = ["pulse_test"]

#: Settings of md.acoustic_system copied into the pulse test's attributes.
_LINEARISATION = ("lattice_rule", "interface", "normal_stiffness", "restitution")


def _first_peak(signal, floor=0.0):
    """Index of the maximum of the first run of samples at or above half the global maximum
    (−1 if that maximum is not above ``floor`` or the run has not ended)."""
    top = np.max(signal)
    if not top > max(floor, 0.0):
        return -1
    above = signal >= 0.5 * top
    start = int(np.argmax(above))
    run = above[start:]
    if run.all():
        if start > 0:
            return -1                                   # still rising at the end of the record
        stop = signal.size
    else:
        stop = start + int(np.argmin(run))
    return start + int(np.argmax(signal[start:stop]))


def pulse_test(system: AcousticSystem, wave="p", *, detectors=None, time_step_factor=0.5,
               pulse_duration=None, max_time=None, record_every=1, resolution_error=None,
               parallel=False, progress=False):
    """Acoustic pulse test (García & Medina, Sect. III G, eqs. 10–11).

    The sample is cut into slabs of ``system.slab_thickness`` along z. The bottom slab is
    displaced by a square wave — :math:`u_z = u_0` (``wave="p"``) or :math:`u_x = u_0`
    (``wave="s"``, the shear-wave variant) for :math:`0 \\le t < \\tau`, then back to 0 — the
    top slab is held fixed, and the linear system is integrated by the central-difference
    scheme. The signal of a slab (eq. 10) is the mean over its particles of the z (or x) force
    of their contacts, each bond's force on its second particle times the z component of its
    normal, halved between the two ends (compression positive): the particle's share of the
    slab's :math:`\\sigma_{zz}` (:math:`\\sigma_{xz}`). This unipolar signal peaks where the
    pulse is; the slab mean of the *net* force on the particles is the difference of the stresses
    on the slab's faces, a bipolar derivative of the pulse whose dispersive tail outgrows its
    first peak within a few slabs. The arrival time at a detector is the time of the maximum of
    the first pulse (the first run of the signal above half its maximum), so a reflection from
    the fixed end is not taken for it. With detectors at slabs :math:`s_1, s_2` a distance
    :math:`L` apart and arrival times :math:`T_1, T_2`, eq. 11 gives

    .. math:: V = \\frac{L}{T_2 - T_1} \\pm \\frac{L\\Delta T + (T_2-T_1)\\Delta L}{(T_2 - T_1)^2}

    with :math:`\\Delta T` the recording interval and :math:`\\Delta L` the mean grain radius
    (the cell width for a pure cement block). The source gives :math:`\\Delta L \\approx R`
    and, in the same sentence, "half the width of the slabs" (:math:`\\approx 2R`); this code
    takes :math:`R` (``velocity_error``) and reports the half-slab choice beside it
    (``velocity_error_half_slab``), which doubles the :math:`\\Delta L` term.

    Eq. 11 covers the reading of arrival times only. The larger biases are reported beside it:
    ``velocity_error_static``, the pulse velocity minus the static long-wave limit of the same
    operator (dispersion of a pulse a few grains long: −2 % on a cement block, −5 to −30 % in
    grain packs), and ``velocity_error_resolution``, the resolution error the caller passes as
    ``resolution_error`` (relative; from a study of :math:`\\Omega` such as
    ``benchmarks/md_omega_convergence.py``), NaN when not given.

    The static modulus of the same operator (:func:`static_modulus`) is returned as a
    cross-check: :math:`\\sqrt{M/\\rho}` is the long-wave limit of the pulse velocity. They agree
    where the sample is homogeneous on the scale of the pulse (a cement block: 2 %); in grain
    packs the pulse, a few grains long, is dispersed and travels 5–30 % slower.

    Parameters
    ----------
    system : AcousticSystem
    wave : {"p", "s"}
    detectors : (int, int), optional
        Detector slabs, default ``(1, n_slabs - 3)`` (``(1, n_slabs - 2)`` for 4 or 5 slabs):
        two slabs are left before the fixed one, where the reflected pulse overlaps the incident
        one.
    time_step_factor : float
        Time step as a fraction of :math:`2/\\omega_{max}` (the stability limit of the scheme,
        :math:`\\omega_{max}` bounded by Gershgorin), in (0, 1]; default 0.5.
    pulse_duration : float, optional
        :math:`\\tau`, s; default twice the time a wave at the static velocity takes to cross
        one slab.
    max_time : float, optional
        Simulated time, s, ``> 0``. By default the run lasts :math:`\\tau` plus 1.5 times the
        static-velocity travel time to the far detector and is extended (up to 20 times) until
        the far detector's first pulse has passed.
    record_every : int
        Record the slab signals every this many steps (:math:`\\Delta T`), ``>= 1``.
    resolution_error : float, optional
        Relative error of the velocity from the lattice resolution (e.g. the distance of this
        :math:`\\Omega` from a Richardson-extrapolated limit), ``>= 0``; reported as
        ``velocity_error_resolution`` (m/s).
    parallel : bool
        Run the time steps (and the static cross-check) on the multi-threaded gather kernels of
        :mod:`md._kernels_parallel` (numba threads, ``numba.set_num_threads``); same result to
        round-off. On a 2-core machine this is about half as fast as the serial default
        (``benchmarks/md_parallel_speed.py``): each bond is evaluated from both ends.
    progress : bool
        Show a progress bar (tqdm).

    Returns
    -------
    xarray.Dataset
        ``signal`` (time, slab), N; ``arrival_time`` (slab), s; ``n_particles`` (slab); scalars
        ``velocity`` and ``velocity_error`` (m/s, eq. 11 with :math:`\\Delta L = R`),
        ``velocity_error_half_slab`` (eq. 11 with half a slab), ``velocity_error_static`` and
        ``velocity_error_resolution`` (m/s, see above), ``velocity_fit`` (m/s, least-squares
        slope of the arrival times of the detector slabs from :math:`s_1` to :math:`s_2`),
        ``velocity_static`` and ``modulus_static`` (the static cross-check), ``density``; the
        wave, time step, pulse duration and detector slabs in attributes.

    Raises
    ------
    ValueError
        For a sample of fewer than 4 slabs, detectors outside the interior slabs, or knobs out
        of range.
    RuntimeError
        When no first pulse is resolved at the detectors (e.g. no load path).
    """
    import xarray as xr
    from tqdm.auto import tqdm

    from ._kernels_acoustic import leapfrog_run

    if parallel and system.rotations:
        raise ValueError("parallel=True runs translations only; build the system with "
                         "rotations=False or use parallel=False")
    if not 0.0 < time_step_factor <= 1.0:
        raise ValueError(f"time_step_factor must lie in (0, 1]; got {time_step_factor}")
    if int(record_every) != record_every or record_every < 1:
        raise ValueError(f"record_every must be an integer >= 1; got {record_every}")
    record_every = int(record_every)
    if resolution_error is not None and not (np.isfinite(resolution_error)
                                             and resolution_error >= 0):
        raise ValueError(f"resolution_error must be a relative error >= 0; got {resolution_error}")
    slab, n_slabs, flag = _prescribed(system)
    if detectors is None:                        # keep the far detector clear of the reflection
        s1, s2 = 1, (n_slabs - 3 if n_slabs >= 6 else n_slabs - 2)
    else:
        s1, s2 = (int(d) for d in detectors)
    if not 0 < s1 < s2 < n_slabs - 1:
        raise ValueError(f"detectors must be two slabs with 0 < s1 < s2 < {n_slabs - 1} "
                         f"(between the source and the fixed slab); got {detectors}")
    ax = _wave_axis(wave)
    static = static_modulus(system, wave, parallel=parallel)
    h = system.slab_thickness
    z0 = system.extent[0]
    centres = z0 + (np.arange(n_slabs) + 0.5) * h
    tau = 2.0 * h / static.velocity if pulse_duration is None else float(pulse_duration)
    if not tau > 0:
        raise ValueError(f"pulse_duration must be > 0 s; got {pulse_duration}")
    if max_time is not None and not float(max_time) > 0:
        raise ValueError(f"max_time must be > 0 s; got {max_time}")
    travel = (centres[s2] - centres[0]) / static.velocity
    t_run = tau + 1.5 * travel if max_time is None else float(max_time)
    t_cap = 20.0 * t_run if max_time is None else t_run
    omega = system.max_frequency()
    dt = time_step_factor * 2.0 / omega
    counts = np.bincount(slab, minlength=n_slabs)
    inv_m = 1.0 / system.masses
    n = system.n_particles
    u = np.zeros((n, system.dof))
    v = np.zeros((n, system.dof))
    amp = 1e-4 * system.slab_thickness
    u[flag == 2, ax] = amp
    if system.rotations:
        from ._kernels_rotation import leapfrog_run_rot as run
        args = (1.0 / system.dof_masses, flag, slab, n_slabs, *system._kernel_args())
    elif parallel:
        from ._kernels_parallel import leapfrog_run_parallel as run
        args = (inv_m, flag, slab, n_slabs, *system.gather_args())
    else:
        run = leapfrog_run
        args = (inv_m, flag, slab, n_slabs, *system._kernel_args())
    chunk = max(1, int(min(2000, math.ceil(t_run / dt))) // record_every) * record_every
    records = []
    t = 0.0
    bar = tqdm(total=t_run, disable=not progress, desc="pulse test", unit="s",
               bar_format="{l_bar}{bar}| {n:.3g}/{total:.3g} s simulated")
    while True:
        left = max(1, math.ceil((t_run - t) / dt / record_every)) * record_every
        steps = min(chunk, left)                 # the last chunk stops at t_run
        rec = np.empty((steps // record_every, n_slabs))
        run(u, v, *args, dt, t, steps, amp, tau, record_every, ax, rec)
        records.append(rec / np.maximum(counts, 1))
        t += steps * dt
        bar.update(min(steps * dt, max(t_run - bar.n, 0.0)))
        if t >= t_run:
            sig = np.concatenate(records)
            if _first_peak(sig[:, s2], 0.1 * sig[:, s1].max()) >= 0 or t >= t_cap:
                break
            t_run = min(t_run * 1.25, t_cap)
    bar.close()
    signal = np.concatenate(records)
    times = np.arange(signal.shape[0]) * dt * record_every
    arrival = np.full(n_slabs, np.nan)
    floor = 0.02 * signal[:, s1].max()
    for s in range(1, n_slabs - 1):
        k = _first_peak(signal[:, s], floor)
        if k >= 0:
            arrival[s] = times[k]
    if not (np.isfinite(arrival[s1]) and np.isfinite(arrival[s2]) and arrival[s2] > arrival[s1]):
        raise RuntimeError(f"no pulse arrival was resolved at detectors {s1} and {s2} within "
                           f"{t:.3g} s; raise max_time")
    L = centres[s2] - centres[s1]
    T = arrival[s2] - arrival[s1]
    dT = dt * record_every
    dL = float(system.metadata["mean_radius"] if system.n_grains else
               system.metadata["cell_width"])
    vel = L / T
    vel_err = (L * dT + T * dL) / T**2
    vel_err_slab = (L * dT + T * 0.5 * system.slab_thickness) / T**2
    res_err = np.nan if resolution_error is None else float(resolution_error) * L / T
    sel = np.arange(s1, s2 + 1)
    ok = np.isfinite(arrival[sel])
    vel_fit = float(1.0 / np.polyfit(centres[sel][ok], arrival[sel][ok], 1)[0]) \
        if ok.sum() >= 2 else np.nan
    name = wave.upper()
    return xr.Dataset(
        {
            "signal": (("time", "slab"), signal,
                       {"long_name": f"mean {'zx'[ax == 0]} contact force per particle of the "
                                     "slab (eq. 10)", "units": "N"}),
            "arrival_time": (("slab",), arrival, {"units": "s"}),
            "n_particles": (("slab",), counts),
            "velocity": ((), vel, {"units": "m s-1", "long_name": f"{name} velocity (eq. 11)"}),
            "velocity_error": ((), vel_err, {"units": "m s-1",
                                             "long_name": "error of velocity (eq. 11)"}),
            "velocity_error_half_slab": ((), vel_err_slab, {
                "units": "m s-1", "long_name": "error of velocity (eq. 11, Delta L half a slab)"}),
            "velocity_error_static": ((), L / T - static.velocity, {
                "units": "m s-1", "long_name": "pulse velocity minus static long-wave limit"}),
            "velocity_error_resolution": ((), res_err, {
                "units": "m s-1", "long_name": "resolution error of velocity (given)"}),
            "velocity_fit": ((), vel_fit, {"units": "m s-1",
                                           "long_name": f"{name} velocity from all detectors"}),
            "velocity_static": ((), static.velocity, {"units": "m s-1"}),
            "modulus_static": ((), static.modulus, {"units": "Pa"}),
            "density": ((), static.density, {"units": "kg m-3"}),
        },
        coords={"time": ("time", times, {"units": "s"}),
                "slab": ("slab", np.arange(n_slabs)),
                "z": ("slab", centres, {"units": "m", "long_name": "slab centre"})},
        attrs={"wave": wave, "time_step_s": dt, "time_step_factor": time_step_factor,
               "pulse_duration_s": tau, "amplitude_m": amp, "detectors": [s1, s2],
               "distance_m": L, "delta_L_m": dL, "delta_T_s": dT,
               "delta_L_choice": "mean grain radius R (cell width for a cement block); "
                                 "velocity_error_half_slab uses half a slab",
               "references": "García & Medina, Sects. III F-G, eqs. 4-11",
               # how the sample was linearised (md.acoustic_system), where it says
               "rotations": int(system.rotations),
               **{key: system.metadata[key] for key in _LINEARISATION
                  if key in system.metadata}},
    )
