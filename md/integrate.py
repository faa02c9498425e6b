"""Time integration of grain packs: time step from the stiffest contact, velocity Verlet runs.

SI units. The numba kernels live in ``md/_kernels_integrate.py``; this module validates inputs
and chooses the time step — never set by hand.
"""

from __future__ import annotations

import numpy as np

from .contact import GrainMaterial, contact_time, damping_parameter

__all__ = ["stable_time_step", "run_verlet"]


def stable_time_step(material: GrainMaterial, radius_min, radius_max, v_ref, *,
                     steps_per_contact=50):
    """Time step resolving the shortest contact: :math:`t_c / N`.

    The shortest Hertz contact of the pack is that of the two smallest grains (smallest mass)
    meeting the largest grain at the highest speed; it is bounded below by
    :func:`md.contact.contact_time` for the smallest reduced mass and the reference speed.

    Parameters
    ----------
    material : GrainMaterial
    radius_min, radius_max : float
        Smallest and largest grain radius, m, ``0 < radius_min <= radius_max``.
    v_ref : float
        Largest expected impact speed, m/s, ``> 0``.
    steps_per_contact : int, keyword-only
        :math:`N`, time steps per contact duration (``>= 10``); default 50.

    Returns
    -------
    float
        Time step, s.
    """
    if not 0 < radius_min <= radius_max:
        raise ValueError("radii must satisfy 0 < radius_min <= radius_max")
    if not v_ref > 0:
        raise ValueError(f"v_ref must be > 0 m/s; got {v_ref}")
    if int(steps_per_contact) < 10:
        raise ValueError(f"steps_per_contact must be >= 10; got {steps_per_contact}")
    m_min = 4.0 / 3.0 * np.pi * radius_min**3 * material.density
    m_f = 0.5 * m_min                                   # two smallest grains
    R_f = 0.5 * radius_min
    return float(contact_time(v_ref, R_f, m_f, material.E_f) / int(steps_per_contact))


def run_verlet(x, v, w, r, pairs, material: GrainMaterial, box_length, *, dt, n_steps, v_ref,
               gravity=0.0, record_every=0, hist=None):
    """Integrate a pack for ``n_steps`` with a fixed pair list (positions etc. updated in place).

    Parameters
    ----------
    x, v, w : ndarray, shape (N, 3)
        Positions (m), velocities (m/s), angular velocities (rad/s); modified in place.
    r : ndarray, shape (N,)
        Radii, m.
    pairs : ndarray, shape (M, 2), int
        Candidate contacts (i < j).
    material : GrainMaterial
    box_length : (float, float)
        Periodic lengths in x and y, m.
    dt : float
        Time step, s (see :func:`stable_time_step`).
    n_steps : int
    v_ref : float
        Reference speed of the restitution calibration, m/s.
    gravity : float
        Acceleration along z, m/s² (negative points down).
    record_every : int
        Record the total energy every so many steps (0: never).
    hist : ndarray, shape (M, 3), optional
        Tangential histories, carried across calls (zeros if not given).

    Returns
    -------
    energy : ndarray
        Total energy at each record, J.
    hist : ndarray, shape (M, 3)
    """
    from ._kernels_integrate import verlet_run

    x = _f64(x, "x", (None, 3))
    n = x.shape[0]
    for name, arr in (("v", v), ("w", w)):
        _f64(arr, name, (n, 3))
    r = _f64(r, "r", (n,))
    if np.any(r <= 0):
        raise ValueError("r must be > 0")
    pairs = np.ascontiguousarray(pairs, dtype=np.int32).reshape(-1, 2)
    if pairs.size and (pairs.min() < 0 or pairs.max() >= n):
        raise ValueError("pairs must index particles 0 .. N-1")
    if not dt > 0:
        raise ValueError(f"dt must be > 0 s; got {dt}")
    hist = np.zeros((pairs.shape[0], 3)) if hist is None else _f64(hist, "hist",
                                                                     (pairs.shape[0], 3))
    m = 4.0 / 3.0 * np.pi * r**3 * material.density
    records = n_steps // record_every + 1 if record_every > 0 else 0
    energy = np.zeros(records)
    k = verlet_run(x, v, w, r, m, pairs, hist, np.asarray(box_length, dtype=float),
                   material.E_f, material.G_f, damping_parameter(material.restitution),
                   float(v_ref), material.friction, float(dt), int(n_steps), float(gravity),
                   int(record_every), energy)
    return energy[:k], hist


def _f64(arr, name, shape):
    if not isinstance(arr, np.ndarray) or arr.dtype != np.float64 or not arr.flags.c_contiguous:
        raise ValueError(f"{name} must be a C-contiguous float64 array (it is updated in place)")
    if len(shape) != arr.ndim or any(s is not None and s != t for s, t in zip(shape, arr.shape)):
        raise ValueError(f"{name} must have shape {shape}; got {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite")
    return arr
