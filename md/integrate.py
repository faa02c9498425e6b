"""Time integration of grain packs: time step from the stiffest contact, velocity Verlet runs.

SI units. The numba kernels live in ``md/_kernels_integrate.py``; this module validates inputs
and chooses the time step — never set by hand.
"""

from __future__ import annotations

import numpy as np

from .contact import GrainMaterial, contact_time, damping_parameter

__all__ = ["stable_time_step", "contact_time_step", "highest_frequency", "run_verlet"]

#: Default time steps per period of the highest linearised frequency (:func:`contact_time_step`).
#: Velocity Verlet is stable for omega dt < 2; 2 pi / 8 = 0.79 leaves a margin of 2.5 on a bound
#: that already lies above the true highest frequency.
STEPS_PER_PERIOD = 8


def stable_time_step(material: GrainMaterial, radius_min, radius_max, v_ref, *,
                     steps_per_contact=50):
    r"""Time step resolving the shortest contact: :math:`t_c / N`.

    The shortest Hertz contact of the pack is that of the two smallest grains meeting at the
    highest speed (:math:`t_c \propto (m_f^2 / (E_f^2 R_f v))^{1/5} \propto R`):
    :func:`md.contact.contact_time` for their reduced mass and radius at the reference speed.

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


def _impact_stiffness(material, R_f, m_f, speed):
    r"""Linearised normal and tangential stiffness (N/m) at the deepest overlap of a Hertz impact
    at ``speed``: :math:`\xi^* = (15 m_f v^2 / (16 E_f\sqrt{R_f}))^{2/5}` (Johnson, Contact
    Mechanics, eq. 11.22)."""
    xi = (15.0 * m_f * speed**2 / (16.0 * material.E_f * np.sqrt(R_f))) ** 0.4
    root = np.sqrt(R_f * xi)
    return 2.0 * material.E_f * root, 8.0 * material.G_f * root


def highest_frequency(x, r, pairs, box, material: GrainMaterial, *, mobile=None, z_floor=None,
                      impact_speed=0.0):
    r"""Upper bound of the highest angular frequency of the pack linearised about its state.

    Each contact in the pair list (and, with ``z_floor``, each grain–floor contact) has the
    linearised normal stiffness :math:`k_n = dF_n/d\xi = 2E_f\sqrt{R_f\xi}` (Hertz, García &
    Medina eq. 1) and the tangential stiffness :math:`k_t = 8G_f\sqrt{R_f\xi}` (Mindlin, eq. 2).
    Its energy :math:`k_n\delta_n^2 + k_t|\boldsymbol\delta_t|^2` with
    :math:`\delta_n^2 \le 2(|u_i|^2+|u_j|^2)` and
    :math:`|\boldsymbol\delta_t|^2 \le 4(|u_i|^2+|u_j|^2+r_i^2|\theta_i|^2+r_j^2|\theta_j|^2)`
    bounds the Rayleigh quotient of the translations and rotations, so that

    .. math::

        \omega_{\max}^2 \le \max_g \max\Big(\frac{1}{m_g}\sum_{c\ni g}(2k_n + 4k_t),\;
        \frac{4 r_g^2}{I_g}\sum_{c\ni g} k_t\Big), \qquad I_g = \tfrac25 m_g r_g^2,

    over the mobile grains ``g``. Grains that may still collide add, to every grain, the
    stiffness of a head-on impact at ``impact_speed`` at its deepest overlap, for the smallest
    grains (the stiffest case: :math:`\omega^2 \propto R_f^{2/5} m_f^{-4/5}`).

    Parameters
    ----------
    x : ndarray, shape (N, 3)
        Positions, m.
    r : ndarray, shape (N,)
        Radii, m.
    pairs : ndarray, shape (M, 2), int
        Neighbour pairs (those not overlapping add nothing).
    box : md.space.Box
        Periodic in x and y.
    material : GrainMaterial
    mobile : ndarray, shape (N,), bool, optional
        Grains moved by the dynamics (default all); frozen grains only stiffen their neighbours.
    z_floor : float, optional
        Height of a rigid floor, m.
    impact_speed : float
        Largest relative speed at which two grains may still meet, m/s, ``>= 0``.

    Returns
    -------
    float
        rad/s (0 for a pack with no contact and no impact).
    """
    if not impact_speed >= 0:
        raise ValueError(f"impact_speed must be >= 0 m/s; got {impact_speed}")
    pairs = np.asarray(pairs).reshape(-1, 2)
    n = r.size
    m = 4.0 / 3.0 * np.pi * r**3 * material.density
    from .observe import pair_geometry

    xi = np.maximum(pair_geometry(x, r, pairs, box)[2], 0.0)
    ri, rj = r[pairs[:, 0]], r[pairs[:, 1]]
    root = np.sqrt(ri * rj / (ri + rj) * xi)
    kn, kt = 2.0 * material.E_f * root, 8.0 * material.G_f * root
    sum_n = np.bincount(pairs.ravel(), np.repeat(kn, 2), minlength=n).astype(float)
    sum_t = np.bincount(pairs.ravel(), np.repeat(kt, 2), minlength=n).astype(float)
    if z_floor is not None:
        root_f = np.sqrt(r * np.maximum(r - (x[:, 2] - z_floor), 0.0))
        sum_n += 2.0 * material.E_f * root_f
        sum_t += 8.0 * material.G_f * root_f
    if impact_speed > 0:
        r_min = float(r.min())
        kn_i, kt_i = _impact_stiffness(material, 0.5 * r_min,
                                       2.0 / 3.0 * np.pi * r_min**3 * material.density,
                                       float(impact_speed))
        sum_n = sum_n + kn_i
        sum_t = sum_t + kt_i
    omega2 = np.maximum((2.0 * sum_n + 4.0 * sum_t) / m, 10.0 * sum_t / m)
    if mobile is not None:
        omega2 = omega2[np.asarray(mobile, dtype=bool)]
    return float(np.sqrt(omega2.max())) if omega2.size else 0.0


def contact_time_step(x, r, pairs, box, material: GrainMaterial, *, mobile=None, z_floor=None,
                      impact_speed=0.0, steps_per_period=STEPS_PER_PERIOD):
    r"""Time step from the stiffest linearised contacts of the pack in its current state:
    :math:`\Delta t = 2\pi / (N\,\omega_{\max})`, :math:`\omega_{\max}` the bound of
    :func:`highest_frequency` (arguments as there), :math:`N` = ``steps_per_period``
    (``>= 4``; velocity Verlet is stable for :math:`\omega\Delta t < 2`, i.e. N > π).

    Returns
    -------
    float
        s.

    Raises
    ------
    ValueError
        If the pack has no contact and ``impact_speed`` is 0 (nothing sets a time scale).
    """
    if not steps_per_period >= 4:
        raise ValueError(f"steps_per_period must be >= 4; got {steps_per_period}")
    omega = highest_frequency(x, r, pairs, box, material, mobile=mobile, z_floor=z_floor,
                              impact_speed=impact_speed)
    if not omega > 0:
        raise ValueError("impact_speed: no contact and impact_speed 0, nothing sets the time "
                         "step; give the largest speed at which grains may meet")
    return float(2.0 * np.pi / (steps_per_period * omega))


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
