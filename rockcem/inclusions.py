"""Inclusion models: Berryman's self-consistent scheme with spheroidal inclusions.

Moduli in GPa, volume fractions as fractions with the phases on the last axis. Aspect ratio is the
ratio of the spheroid's symmetry semi-axis to its equatorial semi-axis: < 1 oblate (cracks, flat
pores), 1 sphere, > 1 prolate (needles).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .validation import (as_array, broadcast, broadcast_phases, check_fractions, check_modulus,
                         check_range, max_phases)
from .bounds import hashin_shtrikman, reuss
from .elastic import Moduli
from .validation import FIELD_UNITS, labelled

__all__ = ["berryman_pq", "self_consistent", "SolverInfo", "MIN_ASPECT_RATIO",
           "MAX_ASPECT_RATIO"]

#: Thinnest and most elongated spheroids accepted: a crack of 10^-8 (far thinner than the
#: 10^-4 to 10^-2 of rock cracks) and a needle of 10^8; beyond them the shape factors overflow.
MIN_ASPECT_RATIO, MAX_ASPECT_RATIO = 1e-8, 1e8

# Gauss–Legendre nodes on [0, 1] for the smooth integral forms of theta and f near aspect ratio 1.
_GL_X, _GL_W = np.polynomial.legendre.leggauss(24)
_GL_S = 0.5 * (_GL_X + 1.0)
_GL_W = 0.5 * _GL_W
_NEAR_SPHERE = 0.1
_BLOCK = 4096
_H = 1e-30            # relative complex step of the numpy path's Jacobian
# From this many points on, self_consistent solves with the numba kernel of rockcem._sc_kernels
# (imported then, at call time: about 1 s to import and start numba once per process); fewer
# points take the numpy path.
_NUMBA_MIN_POINTS = 50_000


class SolverInfo(NamedTuple):
    """Convergence record of an iterative solve (``full_output=True``)."""

    iterations: np.ndarray     #: Newton iterations taken, per point (both starts, if two)
    residual: np.ndarray       #: final relative residual, per point
    converged: np.ndarray      #: bool, per point


def _theta_f(aspect):
    r"""Berryman's :math:`\theta` and :math:`f` for spheroids of aspect ratio ``aspect``.

    Closed forms ([Berryman1980]_; [Mavko2009]_ Sect. 4.8) away from the sphere. Near
    ``aspect = 1`` they cancel catastrophically (0/0), so there the exact integral forms

    .. math::

        \theta = 2a\int_0^1 \frac{s^2\,ds}{w}, \qquad
        f = -6a^2 \int_0^1 \frac{s^2(1-s^2)\,ds}{w\,(a + w)}, \qquad w = \sqrt{1 - (1-a^2)s^2}

    (derived from :math:`\arccos a - a\sqrt{1-a^2} = 2\int_0^{e} x^2/\sqrt{1-x^2}\,dx`,
    :math:`e^2 = 1 - a^2`) are used, integrated by 24-point Gauss–Legendre to machine precision.
    """
    a = np.asarray(aspect, dtype=float)
    theta = np.empty_like(a)
    f = np.empty_like(a)
    near = np.abs(a - 1.0) <= _NEAR_SPHERE
    oblate = (a < 1.0) & ~near
    prolate = (a > 1.0) & ~near
    if np.any(near):
        an = a[near][..., None]
        w = np.sqrt(1.0 - (1.0 - an * an) * _GL_S * _GL_S)
        theta[near] = 2.0 * an[..., 0] * np.sum(_GL_W * _GL_S**2 / w, axis=-1)
        f[near] = -6.0 * an[..., 0] ** 2 * np.sum(
            _GL_W * _GL_S**2 * (1.0 - _GL_S**2) / (w * (an + w)), axis=-1)
    if np.any(oblate):
        ao = a[oblate]
        e2 = 1.0 - ao * ao
        theta[oblate] = ao / e2**1.5 * (np.arccos(ao) - ao * np.sqrt(e2))
        f[oblate] = ao * ao / e2 * (3.0 * theta[oblate] - 2.0)
    if np.any(prolate):
        ap = a[prolate]
        e2 = ap * ap - 1.0
        theta[prolate] = ap / e2**1.5 * (ap * np.sqrt(e2) - np.arccosh(ap))
        f[prolate] = ap * ap / (1.0 - ap * ap) * (3.0 * theta[prolate] - 2.0)
    return theta, f


def _pq_sphere(K_m, G_m, K_i, G_i):
    """P, Q of spheres, eq. 9 of [Carcione2022]_ (``G_m > 0``)."""
    zeta = G_m / 6.0 * (9.0 * K_m + 8.0 * G_m) / (K_m + 2.0 * G_m)
    return (K_m + 4.0 / 3.0 * G_m) / (K_i + 4.0 / 3.0 * G_m), (G_m + zeta) / (G_i + zeta)


def _pq_spheroid(K_m, G_m, K_i, G_i, theta, f):
    """P, Q of spheroids: Berryman (1980), Appendix; Mavko et al. (2009) p. 189."""
    R = 3.0 * G_m / (3.0 * K_m + 4.0 * G_m)
    A = G_i / G_m - 1.0
    B = (K_i / K_m - G_i / G_m) / 3.0
    c = 3.0 - 4.0 * R
    ft = f + theta
    F1 = 1.0 + A * (1.5 * ft - R * (1.5 * f + 2.5 * theta - 4.0 / 3.0))
    F2 = (1.0 + A * (1.0 + 1.5 * ft - 0.5 * R * (3.0 * f + 5.0 * theta)) + B * c
          + 0.5 * A * (A + 3.0 * B) * c * (ft - R * (f - theta + 2.0 * theta**2)))
    F3 = 1.0 + A * (1.0 - (f + 1.5 * theta) + R * ft)
    F4 = 1.0 + 0.25 * A * (f + 3.0 * theta - R * (f - theta))
    F5 = A * (-f + R * (ft - 4.0 / 3.0)) + B * theta * c
    F6 = 1.0 + A * (1.0 + f - R * ft) + B * (1.0 - theta) * c
    F7 = 2.0 + 0.25 * A * (3.0 * f + 9.0 * theta - R * (3.0 * f + 5.0 * theta)) + B * theta * c
    F8 = (A * (1.0 - 2.0 * R + 0.5 * f * (R - 1.0) + 0.5 * theta * (5.0 * R - 3.0))
          + B * (1.0 - theta) * c)
    F9 = A * ((R - 1.0) * f - R * theta) + B * theta * c
    P = F1 / F2                                   # T_iijj / 3, T_iijj = 3 F1 / F2
    Q = (2.0 / F3 + 1.0 / F4 + (F4 * F5 + F6 * F7 - F8 * F9) / (F2 * F4)) / 5.0
    return P, Q


def _spheroid_coefficients(theta, f):
    r"""Berryman's :math:`F_1 \dots F_9` as polynomials in :math:`A, B, R`: their coefficients.

    With :math:`c = 3 - 4R` and :math:`u = Bc`, the functions of :func:`_pq_spheroid`
    ([Berryman1980]_, Appendix; [Mavko2009]_ p. 189) are

    .. math::

        F_j = d_j + A\,(p_j + q_j R) + w_j u \quad (j \ne 2), \qquad
        F_2 = 1 + A\,(p_2 + q_2 R) + u + \tfrac12 A (A + 3B)\, c\, (s_2 + t_2 R),

    with :math:`d_j = 1` (:math:`F_1, F_3, F_4, F_6`), 2 (:math:`F_7`) or 0 (:math:`F_5, F_8,
    F_9`), :math:`w_j = 0` (:math:`F_1, F_3, F_4`), :math:`\theta` (:math:`F_5, F_7, F_9`) or
    :math:`1 - \theta` (:math:`F_6, F_8`), and :math:`p_j, q_j, s_2, t_2` depending on the
    aspect ratio alone (through :math:`\theta, f`). The numba kernel of
    :func:`self_consistent` evaluates P, Q and their exact derivatives in this form.

    Returns
    -------
    ndarray, shape (..., 21)
        ``p1, q1, p2, q2, s2, t2, p3, q3, p4, q4, ..., p9, q9, theta``.
    """
    th = np.asarray(theta, dtype=float)
    f = np.asarray(f, dtype=float)
    ft = f + th
    cols = [1.5 * ft, 4.0 / 3.0 - 1.5 * f - 2.5 * th,              # F1
            1.0 + 1.5 * ft, -0.5 * (3.0 * f + 5.0 * th),           # F2
            ft, th - f - 2.0 * th**2,                              # F2: s2, t2
            1.0 - f - 1.5 * th, ft,                                # F3
            0.25 * (f + 3.0 * th), 0.25 * (th - f),                # F4
            -f, ft - 4.0 / 3.0,                                    # F5
            1.0 + f, -ft,                                          # F6
            0.25 * (3.0 * f + 9.0 * th), -0.25 * (3.0 * f + 5.0 * th),  # F7
            1.0 - 0.5 * f - 1.5 * th, 0.5 * f + 2.5 * th - 2.0,    # F8
            -f, f - th,                                            # F9
            th]
    return np.stack(np.broadcast_arrays(*cols), axis=-1)


def _pq(K_m, G_m, K_i, G_i, theta, f, sphere):
    """P and Q without input checks; all arrays broadcast; ``G_m > 0``."""
    Ps, Qs = _pq_sphere(K_m, G_m, K_i, G_i)
    if np.all(sphere):
        return Ps, Qs
    P, Q = _pq_spheroid(K_m, G_m, K_i, G_i, theta, f)
    return np.where(sphere, Ps, P), np.where(sphere, Qs, Q)


@labelled(units="1")
def berryman_pq(K_m, G_m, K_i, G_i, aspect_ratio=1.0):
    r"""Berryman's shape factors P and Q of a spheroidal inclusion in a matrix.

    For spheres (eq. 9 of [Carcione2022]_):

    .. math::

        P = \frac{K_m + \tfrac43 G_m}{K_i + \tfrac43 G_m}, \qquad
        Q = \frac{G_m + \zeta_m}{G_i + \zeta_m}, \qquad
        \zeta_m = \frac{G_m}{6}\frac{9K_m + 8G_m}{K_m + 2G_m}

    and for spheroids :math:`P = T_{iijj}/3`, :math:`Q = (T_{ijij} - T_{iijj}/3)/5` with the
    tensor :math:`T` of [Berryman1980]_ (Appendix; [Mavko2009]_ Sect. 4.8), valid for oblate
    (aspect ratio < 1) and prolate (> 1) spheroids alike. Near the sphere the closed forms of
    :math:`\theta, f` are replaced by exact integrals (see ``_theta_f``), so P and Q are smooth
    through aspect ratio 1.

    Parameters
    ----------
    K_m, G_m : float or array_like
        Matrix (background) moduli, GPa; ``K_m > 0``, ``G_m > 0``.
    K_i, G_i : float or array_like
        Inclusion moduli, GPa, ``>= 0`` (``G_i = 0`` for a fluid, ``K_i = G_i = 0`` for a vacuum).
    aspect_ratio : float or array_like
        Spheroid aspect ratio, in [:data:`MIN_ASPECT_RATIO`, :data:`MAX_ASPECT_RATIO`].

    Returns
    -------
    P, Q : ndarray
        Dimensionless shape factors, broadcast over the inputs.

    Examples
    --------
    A spheroid of aspect ratio 1 is a sphere:

    >>> P, Q = berryman_pq(40.0, 39.0, 2.2, 0.0, 1.0 + 1e-9)
    >>> P_s, Q_s = berryman_pq(40.0, 39.0, 2.2, 0.0, 1.0)
    >>> bool(abs(P / P_s - 1) < 1e-8 and abs(Q / Q_s - 1) < 1e-8)
    True
    """
    K_m = check_modulus("K_m", as_array("K_m", K_m))
    G_m = check_modulus("G_m", as_array("G_m", G_m))
    K_i = check_modulus("K_i", as_array("K_i", K_i), allow_zero=True)
    G_i = check_modulus("G_i", as_array("G_i", G_i), allow_zero=True)
    a = check_aspect_ratio(as_array("aspect_ratio", aspect_ratio))
    K_m, G_m, K_i, G_i, a = broadcast(K_m=K_m, G_m=G_m, K_i=K_i, G_i=G_i, aspect_ratio=a)
    # A matrix whose K_m / G_m rounds its Poisson ratio to 0.5 (a ratio of ~1e17) is
    # incompressible to float64, and the spheroid's factors divide by 1 - 2 nu.
    check_range("Poisson ratio of the matrix (K_m, G_m)",
                (3.0 * K_m - 2.0 * G_m) / (2.0 * (3.0 * K_m + G_m)), -1.0, 0.5, low_open=True,
                high_open=True)
    theta, f = _theta_f(a)
    return _pq(K_m, G_m, K_i, G_i, theta, f, a == 1.0)


def _residual(K, G, K_i, G_i, frac, theta, f, sphere, columns):
    """Residuals of eq. 8 of [Carcione2022]_ (rows: points; last axis: phases).

    ``columns`` is ``(sphere_columns, spheroid_columns)`` when every row has the same phases
    spherical, so each formula is evaluated only where it applies.
    """
    Km, Gm = K[:, None], G[:, None]
    if columns is None:
        P, Q = _pq(Km, Gm, K_i, G_i, theta, f, sphere)
        return (np.sum(frac * (K_i - Km) * P, axis=-1), np.sum(frac * (G_i - Gm) * Q, axis=-1))
    r1 = np.zeros(K.shape, dtype=np.result_type(K, G))     # complex for complex steps
    r2 = np.zeros(K.shape, dtype=r1.dtype)
    for cols, spheres in zip(columns, (True, False)):
        if cols.size == 0:
            continue
        Ki, Gi, fr = K_i[:, cols], G_i[:, cols], frac[:, cols]
        P, Q = (_pq_sphere(Km, Gm, Ki, Gi) if spheres
                else _pq_spheroid(Km, Gm, Ki, Gi, theta[:, cols], f[:, cols]))
        r1 += np.sum(fr * (Ki - Km) * P, axis=-1)
        r2 += np.sum(fr * (Gi - Gm) * Q, axis=-1)
    return r1, r2


def _solve(K_i, G_i, fr, theta, f, sphere, columns, tol, max_iter):
    r"""Solve eq. 8 at the points (rows) of one block; returns K, G, iterations, residual, done.

    The numpy path: Newton's method on all points of the block at once, with the Jacobian by
    complex steps ([SquireTrapp1998]_: for a function analytic in ``x``,
    :math:`\partial_x r = \operatorname{Im} r(x + ih)/h` with no cancellation, here
    :math:`h = 10^{-30} x`) through the P, Q of :func:`_pq`; the same start, damping and tests as
    the numba kernel (``rockcem._sc_kernels``), which differs in its form of P, Q and their
    derivatives and in its continuation starts.
    """
    hs = hashin_shtrikman(K_i, G_i, fr)
    Kr = reuss(K_i, G_i, fr).K
    npts = K_i.shape[0]
    Ke = np.array(hs.K_upper, dtype=float).reshape(npts)
    Ge = np.array(hs.G_upper, dtype=float).reshape(npts)
    iterations = np.zeros(npts, dtype=int)
    residual = np.full(npts, np.inf)
    done = np.zeros(npts, dtype=bool)
    # A composite whose HS upper shear bound is 0 has no shear stiffness at all.
    fluid = Ge <= 0.0
    Ke[fluid], Ge[fluid], residual[fluid], done[fluid] = Kr[fluid], 0.0, 0.0, True

    # Working set: the unconverged points, compacted as points converge (gathers from the full
    # arrays at every step would cost more than the physics).
    idx = np.flatnonzero(~done)
    k, g = Ke[idx], Ge[idx]
    K_up, G_up, K_reuss = Ke[idx], Ge[idx], Kr[idx]
    inputs = [K_i[idx], G_i[idx], fr[idx], theta[idx], f[idx], sphere[idx]]
    scale = max_phases(inputs[0])
    for it in range(1, int(max_iter) + 1):
        if idx.size == 0:
            break
        # Residual and Jacobian by complex steps (P, Q are rational in K, G): the real parts
        # are the residuals, the imaginary parts / h the derivatives, exact to round-off.
        a1, a2 = _residual(k + 1j * _H * k, g, *inputs, columns)
        b1, b2 = _residual(k, g + 1j * _H * g, *inputs, columns)
        r1, r2 = a1.real, a2.real
        j11, j21 = a1.imag / (_H * k), a2.imag / (_H * k)
        j12, j22 = b1.imag / (_H * g), b2.imag / (_H * g)
        rel = np.abs(r1) / k + np.abs(r2) / g
        det = j11 * j22 - j12 * j21
        det = np.where(det == 0.0, np.finfo(float).tiny, det)
        # Damping: keep both moduli positive (at most a tenfold drop per step) and below the
        # Hashin–Shtrikman upper bounds, between which the self-consistent moduli lie.
        k_new = np.minimum(np.maximum(k - (r1 * j22 - r2 * j12) / det, 0.1 * k), K_up)
        g_new = np.minimum(np.maximum(g - (j11 * r2 - j21 * r1) / det, 0.1 * g), G_up)
        step = np.abs(k_new - k) / k + np.abs(g_new - g) / g
        # Converged: step and residual below tol, or the residual at round-off level (where the
        # Jacobian cannot shrink the step any further). Shear collapse: the exact limit is
        # mu = 0 with K the Reuss average.
        conv = ((step < tol) & (rel < tol)) | (rel < 64.0 * np.finfo(float).eps)
        collapse = g_new < 1e-12 * scale
        k = np.where(collapse, K_reuss, k_new)
        g = np.where(collapse, 0.0, g_new)
        rel = np.where(collapse, 0.0, rel)
        finished = conv | collapse
        if np.any(finished) or it == int(max_iter):
            out = finished if it < int(max_iter) else slice(None)
            Ke[idx[out]], Ge[idx[out]], residual[idx[out]] = k[out], g[out], rel[out]
            iterations[idx[out]] = it
            done[idx[finished]] = True
            keep = ~finished
            idx, k, g, K_up, G_up, K_reuss, scale = (a[keep] for a in (idx, k, g, K_up, G_up,
                                                                         K_reuss, scale))
            inputs = [a[keep] for a in inputs]
    return Ke, Ge, iterations, residual, done


def _solve_numba(K_i, G_i, fr, kind, coef, tol, max_iter):
    """Solve eq. 8 with the compiled kernel; None where numba cannot be imported."""
    try:
        from . import _sc_kernels
    except ImportError:
        return None
    npts = K_i.shape[0]
    out = (np.empty(npts), np.empty(npts), np.empty(npts, dtype=np.int64), np.empty(npts),
           np.empty(npts, dtype=np.bool_))
    _sc_kernels.solve_points(*map(_read_only, (K_i, G_i, fr, kind, coef)), float(tol),
                             int(max_iter), True, *out)
    return out


def _read_only(a):
    """A read-only view (as the kernel's signature wants; views of ``np.broadcast_arrays``
    results would otherwise warn when numba asks whether they are writeable)."""
    v = a.view()
    v.flags.writeable = False
    return v


ENGINES = ("auto", "numpy", "numba")


def check_aspect_ratio(a, name="aspect_ratio"):
    """Aspect ratios in [:data:`MIN_ASPECT_RATIO`, :data:`MAX_ASPECT_RATIO`]."""
    return check_range(name, a, MIN_ASPECT_RATIO, MAX_ASPECT_RATIO)


def _check_engine(engine):
    if engine not in ENGINES:
        raise ValueError(f"engine must be one of {', '.join(map(repr, ENGINES))}; got {engine!r}")
    return engine


@labelled(units=FIELD_UNITS, phases=("K", "G", "fractions", "aspect_ratio"))
def self_consistent(K, G, fractions, aspect_ratio=1.0, *, tol=1e-12, max_iter=200,
                    full_output=False, engine="auto"):
    r"""Berryman's self-consistent moduli of an ``n``-phase composite, eqs. 8–9 of [Carcione2022]_.

    Solves, at every point at once,

    .. math::

        \sum_{i=1}^n \phi_i (K_i - K) P_i = 0, \qquad \sum_{i=1}^n \phi_i (\mu_i - \mu) Q_i = 0

    for the effective :math:`(K, \mu)`, with P and Q of :func:`berryman_pq` evaluated in the
    effective medium ([Berryman1980]_). Every point is solved by Newton's method with the exact
    Jacobian, started from the Hashin–Shtrikman upper bound and damped so that :math:`\mu` never
    drops by more than a factor 10 per step and neither modulus exceeds its upper bound. Where
    the shear modulus of the composite vanishes (fluid-supported suspensions, crack densities
    beyond percolation) the iteration drives :math:`\mu \to 0`; below
    :math:`10^{-12} \max_i K_i` the point is set to its exact limit (:math:`\mu = 0`, :math:`K`
    = Reuss average, since any inclusion in a fluid is under hydrostatic stress).

    Two implementations of that iteration, with the same start, damping and tests:

    * below 5·10^4 points, numpy: all points of a block together, the Jacobian by complex steps
      ([SquireTrapp1998]_) through the P, Q of :func:`berryman_pq`;
    * from 5·10^4 points on, a numba kernel (``rockcem._sc_kernels``; numba is imported at the
      first such call of a process, which costs about 1 s): P, Q of each spheroid as rational
      functions of :math:`(K, \mu)` whose coefficients depend on its aspect ratio alone
      (``_spheroid_coefficients``), differentiated exactly, and continuation: a point with the
      phases of the point before it and fractions within 0.05 of them starts from the solutions
      at up to three points before it, extrapolated along the fractions, and falls back to the
      bound if that has not converged in 10 iterations or ends in shear collapse. Along an
      ordered depth profile most points then converge in one iteration. A shear collapse is
      set once the damped iteration is in its asymptotic regime (each step a tenth), with the
      steps left counted: the full iteration's result and iteration count
      (``rockcem._sc_kernels.solve_points``).

    The results of the two, and of any order of the points, agree to about ``tol``.

    Parameters
    ----------
    K, G : array_like, shape (..., n)
        Phase moduli, GPa (``>= 0``; at least one phase must have ``G > 0`` for a solid result).
    fractions : array_like, shape (..., n)
        Volume fractions, in [0, 1], summing to 1 along the last axis.
    aspect_ratio : float or array_like, shape (..., n)
        Aspect ratio of each phase's spheroids (1 for spheres, the default), in
        [:data:`MIN_ASPECT_RATIO`, :data:`MAX_ASPECT_RATIO`].
    tol : float, optional
        Convergence tolerance: a point has converged when both the relative Newton step and the
        relative residual are below ``tol``, or when the residual is at round-off level
        (:math:`64\,\epsilon`); default 1e-12.
    max_iter : int, optional
        Iterations allowed from the bound before :class:`RuntimeError`; default 200. Typical
        rock states converge in 5–8 from the bound (1–2 from a continuation start); shear
        collapse and compositions near the shear-percolation threshold take 10–30 as the shear
        modulus decays to zero.
    full_output : bool, optional
        Also return a :class:`SolverInfo` with iterations and residuals per point.
    engine : {"auto", "numpy", "numba"}, optional
        ``"auto"`` (default) uses the numba kernel from 5·10^4 points on and numpy below;
        ``"numpy"`` never imports numba (slower for large inputs); ``"numba"`` always uses the
        kernel (numpy if numba cannot be imported). Same results to round-off.

    Returns
    -------
    Moduli
        Effective ``K`` and ``G``, shape ``(...)``, GPa.
    info : SolverInfo
        Only with ``full_output=True``.

    Raises
    ------
    RuntimeError
        If any point has not converged after ``max_iter`` iterations (never the starting guess).

    Examples
    --------
    Quartz and cement spheres (Table 1 of [Carcione2022]_):

    >>> m = self_consistent([40.0, 35.0], [39.0, 30.0], [0.6, 0.4])
    >>> round(float(m.K), 4), round(float(m.G), 4)
    (37.9284, 35.111)
    """
    K = check_modulus("K", as_array("K", K), allow_zero=True)
    G = check_modulus("G", as_array("G", G), allow_zero=True)
    frac = check_fractions("fractions", as_array("fractions", fractions))
    a = check_aspect_ratio(as_array("aspect_ratio", aspect_ratio))
    broadcast_phases(("fractions", frac), K=K, G=G, aspect_ratio=a)   # names a mismatch
    if tol <= 0.0:
        raise ValueError(f"tol must be > 0; got {tol:g}")
    if int(max_iter) < 1:
        raise ValueError(f"max_iter must be >= 1; got {max_iter}")
    return _self_consistent(K, G, frac, a, tol, int(max_iter), full_output,
                            _check_engine(engine))


def _self_consistent(K, G, frac, a, tol=1e-12, max_iter=200, full_output=False,
                     engine="auto"):
    """:func:`self_consistent` on checked float arrays (not yet broadcast)."""
    a_given = a
    K, G, frac, a = broadcast(K=K, G=G, fractions=frac, aspect_ratio=a)
    shape = K.shape[:-1]
    n = K.shape[-1]
    K_i = K.reshape(-1, n)
    G_i = G.reshape(-1, n)
    fr = frac.reshape(-1, n)
    npts = K_i.shape[0]
    # Shape factors depend on the aspect ratio alone: evaluate them once per distinct value, found
    # among the aspect ratios as given (before broadcasting, usually one per phase).
    uniq, inverse = np.unique(a_given, return_inverse=True)
    th_u, f_u = _theta_f(uniq)
    # kind: -1 for a sphere (closed-form P, Q), else the index of the aspect ratio in uniq.
    kind_given = np.where(uniq == 1.0, -1, np.arange(uniq.size, dtype=np.int64))[inverse]
    kind_given = kind_given.reshape(a_given.shape)
    kind = np.broadcast_to(kind_given, a.shape).reshape(-1, n)

    solved = None
    if engine == "numba" or (engine == "auto" and npts >= _NUMBA_MIN_POINTS):
        solved = _solve_numba(K_i, G_i, fr, kind, _spheroid_coefficients(th_u, f_u), tol,
                              max_iter)
    if solved is None:
        pick = np.maximum(kind, 0)
        theta, f = th_u[pick], f_u[pick]
        sphere = kind < 0
        columns = None
        if np.all(sphere == sphere[:1]):
            columns = (np.flatnonzero(sphere[0]), np.flatnonzero(~sphere[0]))
        # Solve in blocks of a few thousand points: the temporaries of the Newton step then
        # stay in cache (about twice as fast as whole-array passes for 10^5 points and more).
        parts = [_solve(K_i[b:b + _BLOCK], G_i[b:b + _BLOCK], fr[b:b + _BLOCK],
                        theta[b:b + _BLOCK], f[b:b + _BLOCK], sphere[b:b + _BLOCK], columns, tol,
                        max_iter)
                 for b in range(0, npts, _BLOCK)]
        solved = (np.concatenate([p[k] for p in parts]) for k in range(5))
    Ke, Ge, iterations, residual, done = solved
    if not np.all(done):
        bad = np.flatnonzero(~done)
        raise RuntimeError(
            f"self_consistent did not converge at {bad.size} of {npts} points after {max_iter} "
            f"Newton iterations (worst relative residual {np.max(residual[bad]):.3g}); "
            "raise max_iter or check the inputs")
    out = Moduli(Ke.reshape(shape), Ge.reshape(shape))
    if full_output:
        return out, SolverInfo(iterations.reshape(shape), residual.reshape(shape),
                               done.reshape(shape))
    return out
