r"""Private numba kernel of the self-consistent solver; the public wrapper is
:func:`rockcem.inclusions.self_consistent`.

This module imports numba at the top, so it is imported only inside that function, at call time,
and only for inputs large enough to repay the start-up (``import rockcem`` never loads numba).
Its plain-Python twin is the same source run with ``NUMBA_DISABLE_JIT=1``; the numpy path of
``rockcem.inclusions`` (same iteration, Jacobian by complex steps through the direct
transcription of P and Q, no continuation) is the independent cross-check. Both are compared
with this kernel in tests/rockcem/test_inclusions.py.

Per point: Newton's method with the exact Jacobian on eq. 8 of [Carcione2022]_,

.. math::

    r_1 = \sum_i \phi_i (K_i - K) P_i = 0, \qquad r_2 = \sum_i \phi_i (\mu_i - \mu) Q_i = 0,

started at the Hashin–Shtrikman upper bound (or a continuation start, see :func:`solve_points`),
damped and tested for convergence exactly as the numpy path. P, Q of spheres are eq. 9 of
[Carcione2022]_; those of spheroids are [Berryman1980]_'s :math:`F_1 \dots F_9` as polynomials
in :math:`A = \mu_i/\mu - 1`, :math:`B = (K_i/K - \mu_i/\mu)/3`,
:math:`R = 3\mu/(3K + 4\mu)` with coefficients that depend on the aspect ratio alone (``coef``,
one row per distinct aspect ratio, from ``rockcem.inclusions._spheroid_coefficients``), so that
their derivatives in :math:`K, \mu` follow by the chain rule through :math:`A, B, R`.
A pore without shear stiffness (:math:`\mu_i = 0`: a fluid, or empty) has :math:`A = -1` and
:math:`B = K_i/(3K)`, and the terms that vanish there are skipped (:func:`spheroid_pq_fluid`):
the saturated and the dry solve of Model 2 evaluate only such spheroids.
"""

from __future__ import annotations

import numpy as np
from numba import njit, types

__all__ = ["solve_points"]

# Fast-math without "nnan"/"ninf" (the NaN checks must stay), nor "afn".
_FAST = {"nsz", "arcp", "contract", "reassoc"}
_EPS = np.finfo(np.float64).eps
_TINY = np.finfo(np.float64).tiny
_NEAR = 0.05          # largest fraction change for a continuation start
_CONT_ITER = 10       # iterations allowed from a continuation start before falling back
_ASYMPTOTIC = 1e-3    # the collapse ahead: Newton targets below this fraction of the moduli


@njit(cache=True, inline="always", error_model="numpy", fastmath=_FAST)
def _linear(d, A, p, q, w, R, u, dAG, dRK, dRG, duK, duG):
    """``F = d + A (p + q R) + w u`` and its derivatives in K and G (A does not depend on K)."""
    L = p + q * R
    F = d + A * L + w * u
    return F, A * q * dRK + w * duK, dAG * L + A * q * dRG + w * duG


@njit(cache=True, inline="always", error_model="numpy", fastmath=_FAST)
def spheroid_pq(K, G, Ki, Gi, c, row):
    r"""P, Q of a spheroid in a matrix ``K, G`` and their derivatives in ``K`` and ``G``.

    [Berryman1980]_, Appendix ([Mavko2009]_ p. 189), with :math:`F_j` in the polynomial form of
    ``rockcem.inclusions._spheroid_coefficients`` (coefficients ``c[row]``):

    .. math::

        P = \frac{F_1}{F_2}, \qquad
        Q = \frac15\Big(\frac{2}{F_3} + \frac{1}{F_4}
            + \frac{F_4F_5 + F_6F_7 - F_8F_9}{F_2F_4}\Big),

    differentiated through :math:`\partial_K R = -9G/(3K+4G)^2`,
    :math:`\partial_G R = 9K/(3K+4G)^2`, :math:`\partial_G A = -G_i/G^2`,
    :math:`\partial_K B = -K_i/(3K^2)`, :math:`\partial_G B = G_i/(3G^2)`.

    Returns ``(P, dP/dK, dP/dG, Q, dQ/dK, dQ/dG)``.
    """
    iK = 1.0 / K
    iG = 1.0 / G
    iD = 1.0 / (3.0 * K + 4.0 * G)
    R = 3.0 * G * iD
    dRK = -9.0 * G * iD * iD
    dRG = 9.0 * K * iD * iD
    A = Gi * iG - 1.0
    dAG = -Gi * iG * iG
    B = (Ki * iK - Gi * iG) / 3.0
    dBK = -Ki * iK * iK / 3.0
    dBG = Gi * iG * iG / 3.0
    cc = 3.0 - 4.0 * R
    dcK = -4.0 * dRK
    dcG = -4.0 * dRG
    u = B * cc
    duK = dBK * cc + B * dcK
    duG = dBG * cc + B * dcG
    th = c[row, 20]
    F1, F1K, F1G = _linear(1.0, A, c[row, 0], c[row, 1], 0.0, R, u, dAG, dRK, dRG, duK, duG)
    # F2 = 1 + A L2 + u + W cc M / 2 with W = A (A + 3B), M = s2 + t2 R.
    F2, F2K, F2G = _linear(1.0, A, c[row, 2], c[row, 3], 1.0, R, u, dAG, dRK, dRG, duK, duG)
    M = c[row, 4] + c[row, 5] * R
    W = A * (A + 3.0 * B)
    WK = 3.0 * A * dBK
    WG = (2.0 * A + 3.0 * B) * dAG + 3.0 * A * dBG
    F2 += 0.5 * W * cc * M
    F2K += 0.5 * (WK * cc * M + W * dcK * M + W * cc * c[row, 5] * dRK)
    F2G += 0.5 * (WG * cc * M + W * dcG * M + W * cc * c[row, 5] * dRG)
    F3, F3K, F3G = _linear(1.0, A, c[row, 6], c[row, 7], 0.0, R, u, dAG, dRK, dRG, duK, duG)
    F4, F4K, F4G = _linear(1.0, A, c[row, 8], c[row, 9], 0.0, R, u, dAG, dRK, dRG, duK, duG)
    F5, F5K, F5G = _linear(0.0, A, c[row, 10], c[row, 11], th, R, u, dAG, dRK, dRG, duK, duG)
    F6, F6K, F6G = _linear(1.0, A, c[row, 12], c[row, 13], 1.0 - th, R, u, dAG, dRK, dRG, duK, duG)
    F7, F7K, F7G = _linear(2.0, A, c[row, 14], c[row, 15], th, R, u, dAG, dRK, dRG, duK, duG)
    F8, F8K, F8G = _linear(0.0, A, c[row, 16], c[row, 17], 1.0 - th, R, u, dAG, dRK, dRG, duK, duG)
    F9, F9K, F9G = _linear(0.0, A, c[row, 18], c[row, 19], th, R, u, dAG, dRK, dRG, duK, duG)
    return _pq_from_f(F1, F1K, F1G, F2, F2K, F2G, F3, F3K, F3G, F4, F4K, F4G, F5, F5K, F5G,
                      F6, F6K, F6G, F7, F7K, F7G, F8, F8K, F8G, F9, F9K, F9G)


@njit(cache=True, inline="always", error_model="numpy", fastmath=_FAST)
def _linear_fluid(d, p, q, w, R, u, dRK, dRG, duK, duG):
    """``F = d - (p + q R) + w u`` and its derivatives in K and G: :func:`_linear` at A = -1."""
    return d - p - q * R + w * u, w * duK - q * dRK, w * duG - q * dRG


@njit(cache=True, inline="always", error_model="numpy", fastmath=_FAST)
def spheroid_pq_fluid(K, G, Ki, c, row):
    r""":func:`spheroid_pq` of a spheroid without shear stiffness (:math:`\mu_i = 0`: a fluid,
    or an empty pore with :math:`K_i = 0` too).

    The same equations ([Berryman1980]_, Appendix; [Mavko2009]_ p. 189) at
    :math:`A = \mu_i/\mu - 1 = -1` and :math:`B = K_i/(3K)`: :math:`\partial_G A = 0`,
    :math:`\partial_G B = 0`, :math:`W = A(A + 3B) = 1 - 3B`, :math:`\partial_K W =
    -3\,\partial_K B`, :math:`\partial_G W = 0`; the terms of :func:`spheroid_pq` that these
    zeros cancel are not evaluated.

    Returns ``(P, dP/dK, dP/dG, Q, dQ/dK, dQ/dG)``.
    """
    iK = 1.0 / K
    iD = 1.0 / (3.0 * K + 4.0 * G)
    R = 3.0 * G * iD
    dRK = -9.0 * G * iD * iD
    dRG = 9.0 * K * iD * iD
    B = Ki * iK / 3.0
    dBK = -B * iK
    cc = 3.0 - 4.0 * R
    dcK = -4.0 * dRK
    dcG = -4.0 * dRG
    u = B * cc
    duK = dBK * cc + B * dcK
    duG = B * dcG
    th = c[row, 20]
    F1, F1K, F1G = _linear_fluid(1.0, c[row, 0], c[row, 1], 0.0, R, u, dRK, dRG, duK, duG)
    F2, F2K, F2G = _linear_fluid(1.0, c[row, 2], c[row, 3], 1.0, R, u, dRK, dRG, duK, duG)
    M = c[row, 4] + c[row, 5] * R
    W = 1.0 - 3.0 * B
    WK = -3.0 * dBK
    F2 += 0.5 * W * cc * M
    F2K += 0.5 * (WK * cc * M + W * dcK * M + W * cc * c[row, 5] * dRK)
    F2G += 0.5 * (W * dcG * M + W * cc * c[row, 5] * dRG)
    F3, F3K, F3G = _linear_fluid(1.0, c[row, 6], c[row, 7], 0.0, R, u, dRK, dRG, duK, duG)
    F4, F4K, F4G = _linear_fluid(1.0, c[row, 8], c[row, 9], 0.0, R, u, dRK, dRG, duK, duG)
    F5, F5K, F5G = _linear_fluid(0.0, c[row, 10], c[row, 11], th, R, u, dRK, dRG, duK, duG)
    F6, F6K, F6G = _linear_fluid(1.0, c[row, 12], c[row, 13], 1.0 - th, R, u, dRK, dRG, duK,
                                 duG)
    F7, F7K, F7G = _linear_fluid(2.0, c[row, 14], c[row, 15], th, R, u, dRK, dRG, duK, duG)
    F8, F8K, F8G = _linear_fluid(0.0, c[row, 16], c[row, 17], 1.0 - th, R, u, dRK, dRG, duK,
                                 duG)
    F9, F9K, F9G = _linear_fluid(0.0, c[row, 18], c[row, 19], th, R, u, dRK, dRG, duK, duG)
    return _pq_from_f(F1, F1K, F1G, F2, F2K, F2G, F3, F3K, F3G, F4, F4K, F4G, F5, F5K, F5G,
                      F6, F6K, F6G, F7, F7K, F7G, F8, F8K, F8G, F9, F9K, F9G)


@njit(cache=True, inline="always", error_model="numpy", fastmath=_FAST)
def _pq_from_f(F1, F1K, F1G, F2, F2K, F2G, F3, F3K, F3G, F4, F4K, F4G, F5, F5K, F5G,
               F6, F6K, F6G, F7, F7K, F7G, F8, F8K, F8G, F9, F9K, F9G):
    r"""P, Q of :func:`spheroid_pq` and their derivatives from :math:`F_1 \dots F_9` and theirs."""
    i2 = 1.0 / F2
    i3 = 1.0 / F3
    i4 = 1.0 / F4
    P = F1 * i2
    PK = (F1K - P * F2K) * i2
    PG = (F1G - P * F2G) * i2
    N = F4 * F5 + F6 * F7 - F8 * F9
    NK = F4K * F5 + F4 * F5K + F6K * F7 + F6 * F7K - F8K * F9 - F8 * F9K
    NG = F4G * F5 + F4 * F5G + F6G * F7 + F6 * F7G - F8G * F9 - F8 * F9G
    iS = i2 * i4
    NS = N * iS
    Q = 0.2 * (2.0 * i3 + i4 + NS)
    QK = 0.2 * (-2.0 * F3K * i3 * i3 - F4K * i4 * i4 + (NK - NS * (F2K * F4 + F2 * F4K)) * iS)
    QG = 0.2 * (-2.0 * F3G * i3 * i3 - F4G * i4 * i4 + (NG - NS * (F2G * F4 + F2 * F4G)) * iS)
    return P, PK, PG, Q, QK, QG


_CONVERGED, _COLLAPSED, _FAILED = 0, 1, 2


@njit(cache=True, inline="always", error_model="numpy", fastmath=_FAST)
def _weights(chain, a2, b2, dot):
    """Weights of the solutions at ``p-1, p-2, p-3`` in the start value at point ``p``.

    Lagrange extrapolation of degree ``min(chain, 3) - 1`` along the path of the fractions:
    point ``p-1`` at 0, ``p-2`` at ``-a`` and ``p-3`` at ``-a-b`` (``a, b`` the lengths of the
    steps between them in fraction space, ``a2 = a**2``, ``b2 = b**2``), point ``p`` at the
    projection of its step on the last one (``dot / a``), clipped to [0, 2a].
    """
    if chain < 2 or a2 == 0.0:
        return 1.0, 0.0, 0.0
    a = np.sqrt(a2)
    t = min(max(dot / a, 0.0), 2.0 * a)
    if chain < 3 or b2 == 0.0:
        return 1.0 + t / a, -t / a, 0.0
    b = np.sqrt(b2)
    return ((t + a) * (t + a + b) / (a * (a + b)), -t * (t + a + b) / (a * b),
            t * (t + a) / ((a + b) * b))


_IN = types.Array(types.float64, 2, "A", readonly=True)     # any layout, read-only or not
_SIGNATURE = types.void(_IN, _IN, _IN, types.Array(types.int64, 2, "A", readonly=True), _IN,
                        types.float64, types.int64, types.boolean, types.float64[:],
                        types.float64[:], types.int64[:], types.float64[:], types.boolean[:])


@njit(_SIGNATURE, cache=True, error_model="numpy", fastmath=_FAST)
def solve_points(K_i, G_i, frac, kind, coef, tol, max_iter, continuation, K_out, G_out,
                 iterations, residual, done):
    """Solve eq. 8 at every point (row); results into the five output arrays.

    ``kind[p, i]`` is -1 for a sphere and otherwise the row of ``coef`` for phase ``i`` at point
    ``p``. Every point's Newton iteration starts at its Hashin–Shtrikman upper bound, except with
    ``continuation``: a point with the phases (moduli, shapes) of the point before it and
    fractions within ``_NEAR`` of them first starts from the solutions of up to three converged
    points before it, extrapolated along the path of the fractions (``_weights``), for at most
    ``_CONT_ITER`` iterations; if that does not converge, or ends in shear collapse (accepted
    from the bound only), the point is solved from the bound as usual. Either way a point counts
    as converged by the same test. ``done[p]`` is False where the point did not converge in
    ``max_iter`` iterations (or the iteration produced a non-finite value); the caller raises.

    The collapse ahead. Where no shear stiffness percolates (empty pores past the
    percolation porosity) the iteration goes to :math:`(K, \\mu) \\to 0`, a tenth per step,
    until :math:`\\mu < 10^{-12} \\max_i K_i`: 10–13 steps of damping. Near 0 the residual of
    eq. 8 along a ray :math:`x = s\\hat x` is :math:`F = sF_1(\\hat x) + s^2F_2(\\hat x) + O(s^3)`
    (for :math:`K, \\mu \\ll K_i, \\mu_i` a solid sphere contributes
    :math:`(K_i - K)P_i \\to K + \\tfrac43\\mu` and an empty pore :math:`-KP(\\mu/K)`:
    homogeneous of degree 1), so by Euler's relation :math:`J_1x = F_1`,
    :math:`J_2x = 2F_2` the Newton target is
    :math:`x - J^{-1}F = \\tfrac{s^2}{2}J_1^{-1}J_2\\hat x + O(s^3)`: a fraction :math:`\\propto s`
    of :math:`x`, which the damping cuts to :math:`x/10`, keeping :math:`\\hat x`; the next
    fraction is a tenth of this one, and so on. Once both targets are below
    ``_ASYMPTOTIC`` (1e-3) of the moduli and a tenth (±1 %) of the previous step's, and
    :math:`\\mu < 10^{-3}\\max_i K_i`, the kernel counts the steps left (the same products
    ``0.1 * g`` the iteration would form, within ``max_iter``) and sets the collapse: the same
    result and iteration count as the full iteration (tests/rockcem/test_model2_speed_paths.py;
    about half the iterations of Model 2's dry solve).

    One function on purpose: helpers taking the arrays, even inlined, cost atomic reference
    counts at every call (about 0.2 µs per point, as much as a Newton iteration).
    """
    npts, n = K_i.shape
    k1 = k2 = k3 = g1 = g2 = g3 = 0.0
    chain = 0           # converged points before p, each a near neighbour of the one before it
    # The phases' constants of the bounds, kept while the phases present and their moduli are
    # those of the point before (an ordered profile): their reciprocals are not recomputed.
    inv_K = np.zeros(n)
    inv_Ks = np.zeros(n)
    inv_Gz = np.zeros(n)
    scale = K_max = G_max = shift = zeta = 0.0
    zero_K = False
    for p in range(npts):
        same = p > 0
        if same:
            for i in range(n):
                if (K_i[p, i] != K_i[p - 1, i] or G_i[p, i] != G_i[p - 1, i]
                        or (frac[p, i] > 0.0) != (frac[p - 1, i] > 0.0)):
                    same = False
                    break
        if not same:
            # Largest phase K; extremes over the phases present (as
            # rockcem.bounds.hashin_shtrikman); reciprocals of the Reuss and HS terms.
            K_max = -np.inf
            G_max = -np.inf
            scale = -np.inf
            zero_K = False
            for i in range(n):
                scale = max(scale, K_i[p, i])
                if frac[p, i] > 0.0:
                    K_max = max(K_max, K_i[p, i])
                    G_max = max(G_max, G_i[p, i])
                    if K_i[p, i] > 0.0:
                        inv_K[i] = 1.0 / K_i[p, i]
                    else:
                        inv_K[i] = 0.0
                        zero_K = True
            if G_max > 0.0:
                shift = 4.0 / 3.0 * G_max
                zeta = G_max / 6.0 * (9.0 * K_max + 8.0 * G_max) / (K_max + 2.0 * G_max)
                for i in range(n):
                    inv_Ks[i] = 1.0 / (K_i[p, i] + shift)
                    inv_Gz[i] = 1.0 / (G_i[p, i] + zeta)
        # Reuss K and the Hashin–Shtrikman upper bound (Berryman's n-phase form).
        s_reuss = 0.0
        for i in range(n):
            if frac[p, i] > 0.0:
                s_reuss += frac[p, i] * inv_K[i]
        K_reuss = 0.0 if (zero_K or not s_reuss < np.inf) else 1.0 / s_reuss
        K_up = 0.0
        G_up = 0.0
        if G_max > 0.0:
            sk = 0.0
            sg = 0.0
            for i in range(n):
                if frac[p, i] > 0.0:
                    sk += frac[p, i] * inv_Ks[i]
                    sg += frac[p, i] * inv_Gz[i]
            K_up = max(1.0 / sk - shift, 0.0)
            G_up = max(1.0 / sg - zeta, 0.0)
        if not G_up > 0.0:
            # No shear stiffness at all (a fluid suspension): G = 0 and K = Reuss exactly.
            K_out[p], G_out[p], residual[p], iterations[p], done[p] = K_reuss, 0.0, 0.0, 0, True
            chain = 0
            continue

        # Continuation start: same phases as point p - 1, fractions within _NEAR.
        near = continuation and chain > 0
        if near:
            for i in range(n):
                if (K_i[p, i] != K_i[p - 1, i] or G_i[p, i] != G_i[p - 1, i]
                        or kind[p, i] != kind[p - 1, i]
                        or abs(frac[p, i] - frac[p - 1, i]) > _NEAR):
                    near = False
        k0 = K_up
        g0 = G_up
        if near:
            a2 = 0.0
            b2 = 0.0
            dot = 0.0
            for i in range(n):
                if chain >= 2:
                    d = frac[p - 1, i] - frac[p - 2, i]
                    a2 += d * d
                    dot += (frac[p, i] - frac[p - 1, i]) * d
                if chain >= 3:
                    d = frac[p - 2, i] - frac[p - 3, i]
                    b2 += d * d
            w1, w2, w3 = _weights(chain, a2, b2, dot)
            k0 = w1 * k1 + w2 * k2 + w3 * k3
            g0 = w1 * g1 + w2 * g2 + w3 * g3
            if not (k0 > 0.0 and g0 > 0.0):
                k0 = k1
                g0 = g1
            k0 = min(k0, K_up)
            g0 = min(g0, G_up)

        # Newton's method: from the continuation start (if any), then from the bound.
        its = 0
        status = _FAILED
        rel = np.inf
        k = k0
        g = g0
        for attempt in range(2):
            if attempt == 0:
                if not near:
                    continue
                limit = min(max_iter, _CONT_ITER)
            else:
                if status == _CONVERGED:
                    break
                k = K_up
                g = G_up
                limit = max_iter
            status = _FAILED
            rel = np.inf
            tk_prev = np.inf
            tg_prev = np.inf
            it = 0
            while it < limit:
                it += 1
                r1 = 0.0
                r2 = 0.0
                j11 = 0.0
                j12 = 0.0
                j21 = 0.0
                j22 = 0.0
                # Sphere phases share zeta(k, g) and its derivatives (eq. 9 of [Carcione2022]_).
                h = 4.0 / 3.0 * g
                e = 1.0 / (k + 2.0 * g)
                z = g / 6.0 * (9.0 * k + 8.0 * g) * e
                zK = 5.0 / 3.0 * g * g * e * e
                zG = (9.0 * k * k + 16.0 * k * g + 16.0 * g * g) / 6.0 * e * e
                for i in range(n):
                    fi = frac[p, i]
                    if fi == 0.0:
                        continue
                    Ki = K_i[p, i]
                    Gi = G_i[p, i]
                    dK = Ki - k
                    dG = Gi - g
                    if kind[p, i] < 0:
                        ib = 1.0 / (Ki + h)
                        P = (k + h) * ib
                        PK = ib
                        PG = 4.0 / 3.0 * dK * ib * ib
                        iz = 1.0 / (Gi + z)
                        Q = (g + z) * iz
                        QK = zK * dG * iz * iz
                        QG = ((Gi + z) + zG * dG) * iz * iz
                    elif Gi == 0.0:
                        P, PK, PG, Q, QK, QG = spheroid_pq_fluid(k, g, Ki, coef, kind[p, i])
                    else:
                        P, PK, PG, Q, QK, QG = spheroid_pq(k, g, Ki, Gi, coef, kind[p, i])
                    r1 += fi * dK * P
                    r2 += fi * dG * Q
                    j11 += fi * (dK * PK - P)
                    j12 += fi * dK * PG
                    j21 += fi * dG * QK
                    j22 += fi * (dG * QG - Q)
                rel = abs(r1) / k + abs(r2) / g
                det = j11 * j22 - j12 * j21
                if det == 0.0:
                    det = _TINY
                # Damping: both moduli positive (at most a tenfold drop per step) and below the
                # Hashin–Shtrikman upper bounds, between which the self-consistent moduli lie.
                k_target = k - (r1 * j22 - r2 * j12) / det
                g_target = g - (j11 * r2 - j21 * r1) / det
                k_new = min(max(k_target, 0.1 * k), K_up)
                g_new = min(max(g_target, 0.1 * g), G_up)
                if not (np.isfinite(k_new) and np.isfinite(g_new) and np.isfinite(rel)):
                    break
                step = abs(k_new - k) / k + abs(g_new - g) / g
                collapse = g_new < 1e-12 * scale
                # The collapse ahead (see the docstring): both Newton targets a small fraction
                # of the moduli, a tenth of the previous step's, G far below the phases' moduli.
                tk = np.inf
                tg = np.inf
                if 0.0 < k_target < 0.01 * k and 0.0 < g_target < 0.01 * g:
                    tk = k_target / k
                    tg = g_target / g
                    if (not collapse and tk < _ASYMPTOTIC and tg < _ASYMPTOTIC
                            and abs(tk - 0.1 * tk_prev) < 0.01 * tk_prev
                            and abs(tg - 0.1 * tg_prev) < 0.01 * tg_prev
                            and g_new < _ASYMPTOTIC * scale):
                        # The steps the iteration would take, each G a tenth of the one before.
                        ahead = 0
                        g_next = g_new
                        while not g_next < 1e-12 * scale:
                            g_next = 0.1 * g_next
                            ahead += 1
                        if it + ahead <= limit:
                            it += ahead
                            collapse = True
                tk_prev = tk
                tg_prev = tg
                if collapse:
                    # Shear collapse: the exact limit is G = 0 with K the Reuss average.
                    k = K_reuss
                    g = 0.0
                    rel = 0.0
                    status = _COLLAPSED
                    break
                k = k_new
                g = g_new
                if (step < tol and rel < tol) or rel < 64.0 * _EPS:
                    status = _CONVERGED
                    break
            its += it

        K_out[p] = k
        G_out[p] = g
        residual[p] = rel
        iterations[p] = its
        done[p] = status != _FAILED
        if status == _CONVERGED:
            chain = chain + 1 if near else 1
            k1, k2, k3 = k, k1, k2
            g1, g2, g3 = g, g1, g2
        else:
            chain = 0
