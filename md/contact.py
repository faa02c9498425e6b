"""Contact mechanics of the MD engine: Hertz normal force with viscous damping, Mindlin tangential
spring with history and a Coulomb cap (García & Medina, Sect. III A, eqs. 1–3). SI units.

For a pair of spheres with radii :math:`R_i, R_j` and masses :math:`m_i, m_j` of one material
(shear modulus :math:`G`, Poisson ratio :math:`\\nu`):

.. math::

    R_f = \\frac{R_i R_j}{R_i + R_j}, \\quad m_f = \\frac{m_i m_j}{m_i + m_j}, \\quad
    E_f = \\frac{E}{2(1-\\nu^2)}, \\quad G_f = \\frac{G}{2(2-\\nu)}, \\quad E = 2G(1+\\nu),

    F_n = \\kappa_n \\xi + \\gamma_n \\dot\\xi \\ge 0, \\qquad
    \\kappa_n = \\tfrac43 \\sqrt{\\xi R_f}\\,E_f, \\qquad \\gamma_n = c\\sqrt{\\xi},

    \\mathbf F_t = -\\kappa_s \\boldsymbol\\zeta - \\gamma_s \\mathbf v_t, \\quad
    \\kappa_s = 8 G_f \\sqrt{R_f \\xi}, \\quad |\\mathbf F_t| \\le \\mu F_n,

with :math:`\\xi` the overlap and :math:`\\boldsymbol\\zeta` the tangential elongation (history).
The damping :math:`\\gamma_n \\propto \\sqrt\\xi` (the paper's
:math:`\\tilde\\gamma_n\\sqrt{\\xi R_f}`) gives a restitution coefficient that depends on the impact
speed; the constant is set so that a head-on impact at the reference speed ``v_ref`` has the
prescribed restitution :math:`e_n` (0.9 in the paper) — see :func:`damping_parameter`. The
tangential spring :math:`8 G_f a` with contact radius :math:`a = \\sqrt{R_f\\xi}` is the paper's
:math:`\\kappa_s = 4 a G/(2-\\nu)` for identical spheres.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

__all__ = ["GrainMaterial", "QUARTZ", "damping_parameter", "restitution", "hertz_force",
           "hertz_energy", "contact_time", "pair_force_reference"]


@dataclass(frozen=True)
class GrainMaterial:
    """Grain material of the MD engine (SI units).

    Parameters
    ----------
    shear_modulus : float
        Pa, ``> 0``.
    poisson_ratio : float
        In (-1, 0.5).
    density : float
        kg/m³, ``> 0``.
    friction : float
        Coulomb coefficient :math:`\\mu`, ``>= 0``.
    restitution : float
        Normal restitution :math:`e_n` at the reference impact speed, in (0, 1].
    """

    shear_modulus: float
    poisson_ratio: float
    density: float
    friction: float = 0.3
    restitution: float = 0.9

    def __post_init__(self):
        if not self.shear_modulus > 0:
            raise ValueError(f"shear_modulus must be > 0 Pa; got {self.shear_modulus}")
        if not -1.0 < self.poisson_ratio < 0.5:
            raise ValueError(f"poisson_ratio must lie in (-1, 0.5); got {self.poisson_ratio}")
        if not self.density > 0:
            raise ValueError(f"density must be > 0 kg/m3; got {self.density}")
        if not self.friction >= 0:
            raise ValueError(f"friction must be >= 0; got {self.friction}")
        if not 0.0 < self.restitution <= 1.0:
            raise ValueError(f"restitution must lie in (0, 1]; got {self.restitution}")

    @property
    def young_modulus(self) -> float:
        """:math:`E = 2G(1+\\nu)`, Pa."""
        return 2.0 * self.shear_modulus * (1.0 + self.poisson_ratio)

    @property
    def bulk_modulus(self) -> float:
        """:math:`K = 2G(1+\\nu)/(3(1-2\\nu))`, Pa."""
        return self.young_modulus / (3.0 * (1.0 - 2.0 * self.poisson_ratio))

    @property
    def E_f(self) -> float:
        """Effective contact modulus :math:`E/(2(1-\\nu^2))`, Pa."""
        return self.young_modulus / (2.0 * (1.0 - self.poisson_ratio**2))

    @property
    def G_f(self) -> float:
        """Effective tangential modulus :math:`G/(2(2-\\nu))`, Pa."""
        return self.shear_modulus / (2.0 * (2.0 - self.poisson_ratio))


#: Quartz grains of García & Medina, Table I: G = 44 GPa, nu = 0.08, rho = 2.65 g/cm3, mu = 0.3,
#: e_n = 0.9.
QUARTZ = GrainMaterial(44.0e9, 0.08, 2650.0, 0.3, 0.9)


def _rhs(beta):
    def f(t, y):
        X, V = y
        Xp = max(X, 0.0)
        acc = -(Xp**1.5 + beta * np.sqrt(Xp) * V)
        return [V, min(acc, 0.0)]                 # no cohesion: the force never attracts
    return f


def restitution(beta: float) -> float:
    """Normal restitution of the damped Hertz contact for the dimensionless damping ``beta``.

    Integrates :math:`X'' = -\\max(X^{3/2} + \\beta X^{1/2} X', 0)` from :math:`X = 0`,
    :math:`X' = 1` until the spheres separate (scipy's DOP853 at rtol 1e-12) and returns
    :math:`-X'` there. In physical units :math:`\\xi = \\xi^* X`, :math:`t = (\\xi^*/v) \\tau` with
    :math:`\\xi^* = (m_f v^2 / k)^{2/5}`, :math:`k = \\tfrac43 E_f\\sqrt{R_f}`, and the damping
    constant :math:`c = \\beta\\, m_f^{2/5} v^{-1/5} k^{3/5}`.
    """
    from scipy.integrate import solve_ivp

    if beta < 0:
        raise ValueError(f"beta must be >= 0; got {beta}")

    def separated(t, y):
        return y[0]
    separated.terminal = True
    separated.direction = -1
    sol = solve_ivp(_rhs(beta), (0.0, 50.0), [0.0, 1.0], method="DOP853", rtol=1e-11,
                    atol=1e-13, events=separated, first_step=1e-6)
    if not sol.t_events[0].size:
        return 0.0                                     # overdamped: the spheres stick
    return float(-sol.y_events[0][0][1])


@lru_cache(maxsize=64)
def damping_parameter(e_n: float) -> float:
    """Dimensionless damping :math:`\\beta` with :func:`restitution` ``(beta) = e_n`` (brentq)."""
    from scipy.optimize import brentq

    if not 0.0 < e_n <= 1.0:
        raise ValueError(f"restitution must lie in (0, 1]; got {e_n}")
    if e_n == 1.0:
        return 0.0
    # e(beta) falls monotonically from 1; bracket the root before refining it.
    hi = 0.05
    while restitution(hi) > e_n:
        hi *= 2.0
    return float(brentq(lambda b: restitution(b) - e_n, hi / 2.0 if hi > 0.05 else 0.0, hi,
                        xtol=1e-12, rtol=1e-11))


def hertz_force(xi, R_f, E_f):
    """Elastic Hertz force :math:`\\tfrac43 E_f \\sqrt{R_f}\\,\\xi^{3/2}` (N) for overlap ``xi``
    (m)."""
    xi = np.asarray(xi, dtype=float)
    return 4.0 / 3.0 * E_f * np.sqrt(R_f) * np.maximum(xi, 0.0) ** 1.5


def hertz_energy(xi, R_f, E_f):
    """Elastic energy :math:`\\tfrac{8}{15} E_f \\sqrt{R_f}\\,\\xi^{5/2}` (J) of a Hertz contact."""
    xi = np.asarray(xi, dtype=float)
    return 8.0 / 15.0 * E_f * np.sqrt(R_f) * np.maximum(xi, 0.0) ** 2.5


def contact_time(v, R_f, m_f, E_f):
    """Duration of an elastic Hertz impact at relative speed ``v`` (Johnson, Contact Mechanics,
    eq. 11.24): :math:`t_c = 2.8683\\,(m_f^2 / (R_f E_f^2 v))^{1/5}`, with the constant
    :math:`\\tfrac45\\sqrt\\pi\\,\\Gamma(2/5)/\\Gamma(9/10)\\,(15/16)^{2/5}` (from
    :math:`2\\int_0^1 (1 - x^{5/2})^{-1/2}\\,dx`)."""
    from scipy.special import gamma

    const = 0.8 * np.sqrt(np.pi) * gamma(0.4) / gamma(0.9) * (15.0 / 16.0) ** 0.4
    return const * (m_f**2 / (R_f * E_f**2 * v)) ** 0.2


def pair_force_reference(xi_n, n, v_rel, zeta, R_f, m_f, material: GrainMaterial, v_ref, dt):
    """Plain-Python twin of the numba kernel ``md._kernels_contact.pair_force`` (for tests).

    Returns ``(force_on_j, new_zeta, fn)``.
    """
    n = np.asarray(n, dtype=float)
    v_rel = np.asarray(v_rel, dtype=float)
    zeta = np.asarray(zeta, dtype=float)
    beta = damping_parameter(material.restitution)
    k = 4.0 / 3.0 * material.E_f * np.sqrt(R_f)
    c = beta * m_f**0.4 * v_ref**-0.2 * k**0.6
    v_n = float(v_rel @ n)
    fn = max(k * xi_n**1.5 - c * np.sqrt(xi_n) * v_n, 0.0)
    v_t = v_rel - v_n * n
    zeta = zeta - (zeta @ n) * n + v_t * dt
    kappa_s = 8.0 * material.G_f * np.sqrt(R_f * xi_n)
    gamma_s = 2.0 / 3.0 * c * np.sqrt(xi_n)
    f_t = -kappa_s * zeta - gamma_s * v_t
    cap = material.friction * fn
    norm = float(np.linalg.norm(f_t))
    if norm > cap:
        f_t = f_t * (cap / norm) if norm > 0 else f_t
        zeta = -(f_t + gamma_s * v_t) / kappa_s
    return fn * n + f_t, zeta, fn
