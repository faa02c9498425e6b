r"""Numerical solution of Dvorkin's cemented-contact problem, with contact thickness.

Two identical elastic spheres (shear modulus :math:`\mu`, Poisson ratio :math:`\nu`) are bonded
by a thin elastic cement layer of radius :math:`a = \alpha R`. The layer is an elastic foundation
in uniaxial strain (modulus :math:`M_c`) whose thickness at normalised radius :math:`t = r/R` is
:math:`2R(\varepsilon + t^2/2)`; each grain deforms as a half-space (Boussinesq). For a normal
approach the normalised cement stress :math:`\hat\sigma(t)` obeys ([Dvorkin1994]_; the form
with thickness is eq. 1 of [HanGuo]_ and eq. A-2 of [Xu2023]_)

.. math::

    \hat\sigma(t)\Big(\varepsilon + \frac{t^2}{2}\Big)
    + \frac{\Lambda}{2}\int_0^\alpha \hat\sigma(s)\,\frac{4 K(m)}{t + s}\,s\,ds = 1,
    \qquad m = \frac{4ts}{(t+s)^2},

with :math:`K` the complete elliptic integral of the first kind (the ring-load kernel of the
axisymmetric Boussinesq problem), and the normalised stiffness is
:math:`S = \int_0^\alpha \hat\sigma(t)\,t\,dt`. With :math:`\Lambda = \Lambda_n` this is the
:math:`\hat S_n` of the contact cement theory (:func:`rockcem.granular.contact_cement`): its
flat-punch limit :math:`S \to 2\alpha/(\pi^2\Lambda)` matches the handbook's
:math:`B_n = 0.20405\,\Lambda_n^{-0.89}` at :math:`\Lambda_n = 1`, and at
:math:`\varepsilon = 0` it agrees with the handbook polynomial fit within ±4 % for
:math:`0.1 \le \Lambda_n \le 1` (see ``tests/rockcem/test_contact_integral.py``). For the
tangential problem the Cerruti kernel averaged over the contact gives the same equation with
:math:`\Lambda = \Lambda_\tau (1 - \nu/2)`.

The equation is discretised by collocation with piecewise-constant :math:`\hat\sigma` on
``panels`` panels graded toward the axis and the rim (:math:`u_j = \sin^2(\pi j / 2N)`,
:math:`t = \alpha u`), where the stress varies fastest; the panel integrals of the
logarithmically singular kernel are done by adaptive quadrature next to the collocation point
and by Gauss–Legendre elsewhere. The unit-geometry matrix is built once per ``panels`` and
cached, so each point costs one dense ``panels × panels`` solve.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
from scipy.integrate import quad
from scipy.special import ellipkm1

from .validation import as_array, broadcast, check_positive, check_range
from .validation import labelled

__all__ = ["cemented_contact_stiffness"]

_GL_NODES, _GL_WEIGHTS = np.polynomial.legendre.leggauss(16)


def _kernel(u, v):
    """Ring-load kernel 4 K(m) / (u + v) times the ring radius v.

    Evaluated through the complementary parameter 1 - m = ((u - v)/(u + v))^2, exact near the
    singularity where m itself rounds to 1.
    """
    p = ((u - v) / (u + v)) ** 2
    return v * 4.0 * ellipkm1(p) / (u + v)


def _near_panel(u, lo, hi):
    """Panel integral of the kernel near the collocation point u.

    The kernel is logarithmic at v = u; with v = u ± d s² the integrand becomes s log s, smooth
    enough for adaptive quadrature to machine precision.
    """
    total = 0.0
    for end in (lo, hi):
        if end == u:
            continue
        d = end - u
        if lo < u < hi or (u == lo and end == hi) or (u == hi and end == lo):
            # Singular end at u: substitute v = u + d s^2 on s in (0, 1].
            total += abs(quad(lambda s_: _kernel(u, u + d * s_ * s_) * 2.0 * d * s_, 0.0, 1.0,
                              limit=200, epsabs=1e-13, epsrel=1e-10)[0])
    if not lo <= u <= hi:
        total = quad(lambda v: _kernel(u, v), lo, hi, limit=200, epsabs=1e-13, epsrel=1e-10)[0]
    return total


@lru_cache(maxsize=8)
def _unit_matrix(panels: int):
    """Collocation points, panel first moments and the kernel matrix on u in [0, 1]."""
    edges = np.sin(0.5 * np.pi * np.arange(panels + 1) / panels) ** 2
    mid = 0.5 * (edges[:-1] + edges[1:])
    W = np.empty((panels, panels))
    lo, hi = edges[:-1], edges[1:]
    half = 0.5 * (hi - lo)
    nodes = (lo + half)[:, None] + half[:, None] * _GL_NODES          # (panel, node)
    for i, u in enumerate(mid):
        W[i] = np.sum(_GL_WEIGHTS * _kernel(u, nodes), axis=-1) * half
        for j in range(max(0, i - 2), min(panels, i + 3)):
            W[i, j] = _near_panel(u, lo[j], hi[j])
    moment = 0.5 * (hi**2 - lo**2)                                     # ∫ v dv over each panel
    W.setflags(write=False)
    return mid, moment, W


@labelled(units="1")
def cemented_contact_stiffness(alpha, Lambda, thickness=0.0, *, panels=64, chunk=2048):
    r"""Normalised stiffness :math:`S(\alpha, \Lambda, \varepsilon)` of a cemented contact.

    Solves the integral equation of the module docstring at every point.

    Parameters
    ----------
    alpha : float or array_like
        Normalised cement radius :math:`a/R`, in (0, 1].
    Lambda : float or array_like
        Stiffness ratio :math:`\Lambda_n` (normal) or :math:`\Lambda_\tau(1-\nu/2)`
        (tangential), ``> 0``.
    thickness : float or array_like
        Normalised contact thickness :math:`\varepsilon \ge 0` (the cement is
        :math:`2\varepsilon R` thick on the axis).
    panels : int, optional
        Number of collocation panels (the accuracy knob: second-order convergence; at the
        default 64 the relative error is at most :math:`1.1\times10^{-4}` (median
        :math:`4\times10^{-5}`) over cement radii 0.05–0.5, :math:`\Lambda` 0.02–5 and
        thickness 0–0.05, for about 0.1 ms per point; see
        ``benchmarks/contact_integral_error_vs_time.py``).
    chunk : int, optional
        Points solved together (bounds memory at ``chunk * panels**2`` floats).

    Returns
    -------
    ndarray
        :math:`S`, dimensionless, broadcast over the inputs.

    Examples
    --------
    Rigid grains and a thin bond (large :math:`\Lambda`) approach the flat punch,
    :math:`S \to 2\alpha/(\pi^2\Lambda)`:

    >>> S = cemented_contact_stiffness(0.3, 1e3)
    >>> round(float(S / (2 * 0.3 / (np.pi**2 * 1e3))), 2)
    1.0
    """
    alpha = check_range("alpha", as_array("alpha", alpha), 0.0, 1.0, low_open=True)
    Lambda = check_positive("Lambda", as_array("Lambda", Lambda))
    eps = check_positive("thickness", as_array("thickness", thickness), allow_zero=True)
    if int(panels) < 4:
        raise ValueError(f"panels must be >= 4; got {panels}")
    alpha, Lambda, eps = broadcast(alpha=alpha, Lambda=Lambda, thickness=eps)
    mid, moment, W = _unit_matrix(int(panels))
    a, lam, e = alpha.ravel(), Lambda.ravel(), eps.ravel()
    out = np.empty(a.size)
    for start in range(0, a.size, int(chunk)):
        sl = slice(start, start + int(chunk))
        ak, lk_, ek = a[sl, None], lam[sl, None], e[sl, None]
        # The system divided by alpha, so that a tiny cement radius does not underflow it to
        # a singular matrix: A / alpha = Lambda W / 2 + (eps / alpha + alpha t^2 / 2) I, and
        # S = alpha^2 (A^-1 1) . moment = alpha ((A / alpha)^-1 1) . moment.
        with np.errstate(over="ignore"):
            diag = ek / ak + 0.5 * ak * mid ** 2
        thick = ~np.isfinite(diag[:, 0])        # eps / alpha beyond 1e308: no stiffness left
        diag[thick] = 1.0
        B = (0.5 * lk_)[..., None] * W + diag[..., None] * np.eye(mid.size)
        sigma = np.linalg.solve(B, np.ones((B.shape[0], mid.size, 1)))[..., 0]
        out[sl] = np.where(thick, 0.0, ak[:, 0] * (sigma @ moment))
    return out.reshape(alpha.shape)
