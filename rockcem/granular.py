r"""Granular-medium (contact) models: Hertz–Mindlin, soft and stiff sand, contact cement
(CCT and its contact-thickness extension MCCT), constant, increasing and patchy cement.

Units: moduli GPa, pressure MPa (converted to GPa through :data:`rockcem.constants.GPA_PER_MPA`
where it meets a modulus), porosity and fractions as fractions, ``n`` the coordination number
(average contacts per grain). Subscript 0 is the grain mineral, c the cement.

Validity (one rule for the package): inputs outside a model's range raise ``ValueError``; nothing
returns NaN. The porosity range of each model is stated in its docstring.
"""

from __future__ import annotations

import numpy as np

from .bounds import _harmonic2, _lowest
from .constants import GPA_PER_MPA
from .elastic import Moduli
from .validation import (
    as_array,
    blockwise,
    broadcast,
    check_modulus,
    check_range,
    stack_phases,
)
from .validation import labelled

__all__ = [
    "MAX_COORDINATION_NUMBER",
    "MAX_PRESSURE_MPA",
    "cement_porosity",
    "cement_radius",
    "constant_cement",
    "contact_cement",
    "hertz_mindlin",
    "increasing_cement",
    "patchy_cement",
    "soft_sand",
    "stiff_sand",
]


#: Largest mean coordination number accepted: 12 is the most contacts equal spheres can have,
#: and a pack of mixed sizes averages well below 20 (the upper bound of md.calibrate's fits).
MAX_COORDINATION_NUMBER = 20.0
#: Largest effective pressure and bonding pre-stress accepted, MPa (1 GPa): grains crush far
#: below it, and the effective pressure at the 20 km of the deepest basins is about 500 MPa.
MAX_PRESSURE_MPA = 1000.0


# ----------------------------------------------------------------------------- input checks
def _poisson(name, K, G):
    """Poisson ratio of a mineral whose moduli :func:`_shapes` has checked; it must lie in
    (-1, 0.5)."""
    nu = (3.0 * K - 2.0 * G) / (2.0 * (3.0 * K + G))
    check_range(f"Poisson ratio of (K{name}, G{name})", nu, -1.0, 0.5, low_open=True,
                high_open=True)
    return nu


def _not_above(name, value, limit_name, limit):
    """Refuse ``value > limit`` (checked arrays; a relative 1e-12 of rounding allowed)."""
    if np.size(limit) == 1:         # one reduction, no temporary of the value's size
        bad = np.size(value) > 0 and np.max(value) > float(np.max(limit)) * (1 + 1e-12)
    else:
        bad = np.any(value > limit * (1 + 1e-12))
    if bad:
        raise ValueError(f"{name} must lie in [0, {limit_name}] for this model")


#: The range of every argument of the public functions below: (low, high, low_open,
#: high_open), or "modulus" (a solid's, rockcem.validation.check_modulus).
_RANGES = {
    "K0": "modulus", "G0": "modulus", "Kc": "modulus", "Gc": "modulus",
    "phi": (0.0, 1.0, False, False), "phic": (0.0, 1.0, True, True),
    "phib": (0.0, 1.0, True, True), "n": (0.0, MAX_COORDINATION_NUMBER, True, False),
    "pressure": (0.0, MAX_PRESSURE_MPA, False, False),
    "delta": (0.0, MAX_PRESSURE_MPA, False, False), "f": (0.0, 1.0, False, False),
    "thickness": (0.0, np.inf, False, True), "alpha": (0.0, 1.0, False, False),
    "cement_fraction": (0.0, 1.0, False, False),
    "contact_cement_limit": (0.0, 1.0, True, False),
}


def _shapes(_labels=None, **arrays):
    """Check every argument against its own range (:data:`_RANGES`), then refuse, by name,
    shapes that do not broadcast together: all before any joint check (phi <= phic, the Poisson
    ratio of a mineral) or arithmetic, so that a bad argument is always the one named, and a
    shape mismatch with the arguments' names rather than numpy's operands. ``_labels`` maps an
    argument to the name a message gives it (a scene key such as ``coordination_number``).

    Returns the checked arrays (float, not broadcast) in the order given."""
    labels = {"n": "n (coordination number)", **(_labels or {})}
    checked = {}
    for name, value in arrays.items():
        label = labels.get(name, name)
        arr = as_array(label, value)
        rule = _RANGES[name]
        if rule == "modulus":
            check_modulus(label, arr)
        else:
            lo, hi, lo_open, hi_open = rule
            check_range(label, arr, lo, hi, low_open=lo_open, high_open=hi_open)
        checked[label.split(" ")[0]] = arr
    broadcast(**checked)
    return tuple(checked.values())


def _zeta(K, G):
    r""":math:`\zeta(K, G) = \frac{G}{6}\frac{9K + 8G}{K + 2G}`, zero where ``G = 0``
    ([Mavko2009]_ Sect. 7.9)."""
    if _lowest(G) > 0.0:            # then K + 2G > 0 too (K >= 0): no guard needed
        return G / 6.0 * (9.0 * K + 8.0 * G) / (K + 2.0 * G)
    denom = K + 2.0 * G
    return np.where(G > 0.0, G / 6.0 * (9.0 * K + 8.0 * G) / np.where(denom > 0, denom, 1.0), 0.0)


def _hs_interpolate(K_a, G_a, K_b, G_b, frac_a, K_ref, G_ref) -> Moduli:
    r"""Modified Hashin–Shtrikman interpolation between end members a and b.

    .. math::

        K = \Big[\frac{x}{K_a + \tfrac43 G_r} + \frac{1-x}{K_b + \tfrac43 G_r}\Big]^{-1}
            - \tfrac43 G_r, \qquad
        G = \Big[\frac{x}{G_a + z} + \frac{1-x}{G_b + z}\Big]^{-1} - z,
        \quad z = \zeta(K_r, G_r)

    with ``x = frac_a``; the reference (r) is the softer end member for the "soft" (lower-bound)
    form and the stiffer one for the "stiff" (upper-bound) form ([Mavko2009]_ Sect. 7.9).
    Checked arrays; the results broadcast to the inputs' shape.
    """
    frac_b = 1.0 - frac_a
    K = _harmonic2(K_a, K_b, frac_a, 4.0 / 3.0 * G_ref, frac_b)
    G = _harmonic2(G_a, G_b, frac_a, _zeta(K_ref, G_ref), frac_b)
    return Moduli(K, G)


def _hm(K0, G0, phic, n, pressure, f, delta, nu):
    r"""Hertz–Mindlin ``(K, G)`` of checked arrays (``nu``: the grain's Poisson ratio), eqs.
    D.1–D.2 of [Carcione2022]_: :math:`K^3 = c\,p` with
    :math:`c = n^2(1-\phi_c)^2\mu_0^2 / (18\pi^2(1-\nu_0)^2)`, :math:`p` in GPa, and
    :math:`\mu = g K`, :math:`g = 3\,\frac{2 + 3f - \nu_0(1+3f)}{5(2-\nu_0)}` (the cube root of
    :math:`18 \cdot 3/2 = 27`)."""
    c = (n * (1.0 - phic) * G0) ** 2 * GPA_PER_MPA / (18.0 * np.pi**2 * (1.0 - nu) ** 2)
    g = 3.0 * (2.0 + 3.0 * f - nu * (1.0 + 3.0 * f)) / (5.0 * (2.0 - nu))
    K = (pressure + delta) * c
    K = np.cbrt(K, out=K) if isinstance(K, np.ndarray) else np.cbrt(K)
    return K, K * g


# ----------------------------------------------------------------------------- Hertz–Mindlin
@labelled(units="GPa")
def hertz_mindlin(K0, G0, phic, n, pressure, f=1.0, delta=0.0) -> Moduli:
    r"""Hertz–Mindlin moduli of a dense random pack of identical spheres at critical porosity.

    Eqs. D.1–D.2 of [Carcione2022]_ ([Mavko2009]_ Sect. 5.4, [Walton1987]_), with the effective
    pressure augmented by the bonding pre-stress :math:`\delta` of [GangiCarlson1996]_ and the
    shear-reduction (slip) factor ``f`` of [Mavko2009]_:

    .. math::

        K_{HM} = \Big[\frac{n^2 (1-\phi_c)^2 \mu_0^2\, p}{18\pi^2 (1-\nu_0)^2}\Big]^{1/3},
        \qquad
        \mu_{HM} = \frac{2 + 3f - \nu_0(1 + 3f)}{5(2-\nu_0)}
                   \Big[\frac{3 n^2 (1-\phi_c)^2 \mu_0^2\, p}{2\pi^2 (1-\nu_0)^2}\Big]^{1/3},

    with :math:`p = (p_e + \delta)` converted from MPa to GPa. For ``f = 1`` (no slip)
    :math:`\mu_{HM} = \frac{3(5-4\nu_0)}{5(2-\nu_0)}K_{HM}` (eq. D.2); ``f = 0`` is frictionless.

    Parameters
    ----------
    K0, G0 : float or array_like
        Grain bulk and shear moduli, GPa (``> 0``).
    phic : float or array_like
        Critical porosity of the pack, in (0, 1).
    n : float or array_like
        Coordination number, in (0, :data:`MAX_COORDINATION_NUMBER`] (about 9 for a dense
        random pack).
    pressure : float or array_like
        Effective pressure :math:`p_e`, MPa, in [0, :data:`MAX_PRESSURE_MPA`].
    f : float or array_like, optional
        Fraction of grain contacts with no slip, in [0, 1]; default 1.
    delta : float or array_like, optional
        Bonding pre-stress :math:`\delta`, MPa, in [0, :data:`MAX_PRESSURE_MPA`]; default 0
        (classical Hertz–Mindlin).

    Returns
    -------
    Moduli
        Dry-pack ``K`` and ``G`` at ``phic``, GPa.

    Examples
    --------
    >>> m = hertz_mindlin(36.6, 45.0, 0.4, 8.6, 20.0)
    >>> round(float(m.K), 4), round(float(m.G), 4)
    (1.9063, 2.8028)
    """
    K0, G0, phic, n, pressure, f, delta = _shapes(K0=K0, G0=G0, phic=phic, n=n,
                                                  pressure=pressure, f=f, delta=delta)
    nu = _poisson("0", K0, G0)
    return Moduli(*blockwise(_hm, K0, G0, phic, n, pressure, f, delta, nu))


@labelled(units="GPa")
def soft_sand(K0, G0, phi, phic, n, pressure, f=1.0, delta=0.0) -> Moduli:
    r"""Soft-sand (friable, unconsolidated) model: modified HS lower bound.

    Connects the Hertz–Mindlin point at :math:`\phi_c` to the mineral at zero porosity
    ([Mavko2009]_ Sect. 7.9; [rockphypy]):

    .. math::

        K = \Big[\frac{\phi/\phi_c}{K_{HM} + \tfrac43 \mu_{HM}}
                 + \frac{1-\phi/\phi_c}{K_0 + \tfrac43 \mu_{HM}}\Big]^{-1} - \tfrac43 \mu_{HM},
        \qquad
        \mu = \Big[\frac{\phi/\phi_c}{\mu_{HM} + z} + \frac{1-\phi/\phi_c}{\mu_0 + z}\Big]^{-1} - z,

    :math:`z = \zeta(K_{HM}, \mu_{HM})`. Valid for :math:`0 \le \phi \le \phi_c`.

    Parameters
    ----------
    K0, G0 : float or array_like
        Grain moduli, GPa.
    phi : float or array_like
        Porosity, in [0, ``phic``].
    phic, n, pressure, f, delta
        As in :func:`hertz_mindlin`.

    Returns
    -------
    Moduli
        Dry-rock ``K``, ``G``, GPa.
    """
    return _sand(K0, G0, phi, phic, n, pressure, f, delta, stiff=False)


@labelled(units="GPa")
def stiff_sand(K0, G0, phi, phic, n, pressure, f=1.0, delta=0.0) -> Moduli:
    r"""Stiff-sand model: modified HS upper bound between Hertz–Mindlin and the mineral.

    Same end members as :func:`soft_sand`, joined with the mineral as the reference
    ([Mavko2009]_ Sect. 7.9):

    .. math::

        K = \Big[\frac{\phi/\phi_c}{K_{HM} + \tfrac43 \mu_0}
                 + \frac{1-\phi/\phi_c}{K_0 + \tfrac43 \mu_0}\Big]^{-1} - \tfrac43 \mu_0,
        \qquad z = \zeta(K_0, \mu_0).

    Parameters and returns as in :func:`soft_sand`; valid for :math:`0 \le \phi \le \phi_c`.
    """
    return _sand(K0, G0, phi, phic, n, pressure, f, delta, stiff=True)


def _sand(K0, G0, phi, phic, n, pressure, f, delta, *, stiff):
    """Soft (``stiff=False``) or stiff sand: the inputs checked once, then Hertz–Mindlin and the
    interpolation in blocks (:func:`rockcem.validation.blockwise`)."""
    K0, G0, phi, phic, n, pressure, f, delta = _shapes(
        K0=K0, G0=G0, phi=phi, phic=phic, n=n, pressure=pressure, f=f, delta=delta)
    _not_above("phi", phi, "phic", phic)
    nu = _poisson("0", K0, G0)

    def kernel(K0, G0, phi, phic, n, pressure, f, delta, nu):
        K_hm, G_hm = _hm(K0, G0, phic, n, pressure, f, delta, nu)
        ref = (K0, G0) if stiff else (K_hm, G_hm)
        return _hs_interpolate(K_hm, G_hm, K0, G0, phi / phic, *ref)

    return Moduli(*blockwise(kernel, K0, G0, phi, phic, n, pressure, f, delta, nu))


# ----------------------------------------------------------------------------- contact cement
@labelled(units="1")
def cement_radius(phi, phic, n, scheme=1, thickness=0.0):
    r"""Normalised radius :math:`\alpha = a/R` of the cement at a grain contact.

    Scheme 1 (cement at the contacts), eq. 7 of [HanGuo]_ (eq. A-9 of [Xu2023]_), for a contact
    of normalised thickness :math:`\varepsilon = h/R`:

    .. math::

        \alpha = \sqrt{-2\varepsilon + 2\sqrt{\varepsilon^2 + \frac{4}{3n}
                 \frac{\phi_c-\phi}{1-\phi_c}}}
               = \sqrt{\frac{2y}{\varepsilon + \sqrt{\varepsilon^2 + y}}},
        \qquad y = \frac{4}{3n}\frac{\phi_c-\phi}{1-\phi_c},

    evaluated in the second (cancellation-free) form. At :math:`\varepsilon = 0` it is exactly
    eq. 16 of [Carcione2022]_, :math:`\alpha = 2[(\phi_c-\phi)/(3n(1-\phi_c))]^{1/4}`, the factor
    2 of [DvorkinNur1996]_.

    Scheme 2 (cement coating the grains), eq. 18 of [Carcione2022]_ and eq. 10 of [HanGuo]_:

    .. math:: \alpha = \sqrt{\frac{2(\phi_c-\phi)}{3(1-\phi_c)}},

    independent of :math:`\varepsilon` and of ``n``. [Xu2023]_ (eq. A-6) prints an extra
    :math:`1/n` under the root; [DvorkinNur1996]_, [Mavko2009]_ and [HanGuo]_ have none, and
    the geometry (a shell of thickness :math:`\alpha^2 R/2` on every grain) has none, so it is
    left out here.

    Parameters
    ----------
    phi : float or array_like
        Porosity after cementation, in [0, ``phic``]; :math:`\phi_c - \phi` is the cement volume.
    phic : float or array_like
        Critical (uncemented) porosity, in (0, 1).
    n : float or array_like
        Coordination number, in (0, :data:`MAX_COORDINATION_NUMBER`].
    scheme : {1, 2}
        Cement at the contacts (1) or coating the grains (2).
    thickness : float or array_like
        Normalised contact thickness :math:`\varepsilon`, half the axial gap over :math:`R`
        (what Han & Guo's eqs. 1 and 6 count; their text calls it h/R), ``>= 0``.

    Returns
    -------
    ndarray
        :math:`\alpha`, dimensionless, ``>= 0``.
    """
    phi, phic, n, eps = _shapes(phi=phi, phic=phic, n=n, thickness=thickness)
    _not_above("phi", phi, "phic", phic)
    _check_scheme(scheme)
    return _cement_radius(phi, phic, n, scheme, eps)


def _check_scheme(scheme):
    if scheme not in (1, 2):
        raise ValueError(f"scheme must be 1 (contact cement) or 2 (coating cement); got {scheme!r}")


def _cement_radius(phi, phic, n, scheme, eps):
    """:func:`cement_radius` of checked arrays (``phi <= phic``, ``scheme`` 1 or 2), in the
    inputs' broadcast shape; in blocks for large inputs."""
    if scheme == 2:
        return blockwise(lambda phi, phic, n, eps: (np.sqrt(2.0 * ((phic - phi) / (1.0 - phic))
                                                            / 3.0),), phi, phic, n, eps)[0]
    den = 3.0 * n * (1.0 - phic)
    if np.size(eps) == 1 and float(np.max(eps)) == 0.0 and np.min(den) > 1e-290:
        # eps = 0 (CCT), eq. 16: alpha = 2 [(phic - phi) / (3 n (1 - phic))]^(1/4), as the
        # fourth root of 16 (phic - phi) / (3 n (1 - phic)) (finite: the denominator is not
        # tiny; otherwise the overflow-free form below).
        return blockwise(_radius_cct, phi, phic, 16.0 / den, eps)[0]
    return blockwise(_radius_mcct, phi, phic, n, eps)[0]


def _radius_cct(phi, phic, coef, eps):
    a = (phic - phi) * coef
    if isinstance(a, np.ndarray):
        return (np.sqrt(np.sqrt(a, out=a), out=a),)
    return (np.sqrt(np.sqrt(a)),)


def _radius_mcct(phi, phic, n, eps):
    # alpha^2 = 2y / (eps + sqrt(eps^2 + y)) = 2s / (r + sqrt(r^2 + 1)), s = sqrt(y), r = eps/s:
    # no overflow for a tiny n (huge y) or a huge eps.
    s = np.sqrt(4.0 * ((phic - phi) / (1.0 - phic)) / 3.0) / np.sqrt(n)
    pos = s > 0.0
    with np.errstate(over="ignore"):        # eps / s beyond 1e308: alpha^2 -> 2s / inf = 0
        r = np.where(pos, eps / np.where(pos, s, 1.0), 0.0)
        return (np.sqrt(np.where(pos, 2.0 * s / (r + np.hypot(r, 1.0)), 0.0)),)


@labelled(units="1")
def cement_porosity(alpha, phic, n, scheme=1, thickness=0.0):
    r"""Porosity whose cement radius (:func:`cement_radius`) is ``alpha``: its inverse.

    Scheme 1 inverts eq. 7 of [HanGuo]_: with :math:`y = \frac{4}{3n}\frac{\phi_c -
    \phi}{1-\phi_c}`, :math:`\alpha^2 = 2y/(\varepsilon + \sqrt{\varepsilon^2 + y})` gives
    :math:`y = \alpha^2(\alpha^2/4 + \varepsilon)` (their eq. 6:
    :math:`\frac{3n}{16}\alpha^4 + \frac{3n\varepsilon}{4}\alpha^2 =
    \frac{\phi_c-\phi}{1-\phi_c}`); scheme 2 inverts eq. 18 of [Carcione2022]_:
    :math:`(\phi_c - \phi)/(1-\phi_c) = 3\alpha^2/2`.

    Parameters
    ----------
    alpha : float or array_like
        Normalised cement radius :math:`a/R`, in [0, 1].
    phic, n, scheme, thickness
        As in :func:`cement_radius`.

    Returns
    -------
    ndarray
        Porosity :math:`\phi`; a value below 0 means the cement radius needs more cement than
        the pore space holds (raises ``ValueError``).
    """
    alpha, phic, n, eps = _shapes(alpha=alpha, phic=phic, n=n, thickness=thickness)
    _check_scheme(scheme)
    x = 1.5 * alpha**2 if scheme == 2 else 0.75 * n * alpha**2 * (0.25 * alpha**2 + eps)
    phi = phic - x * (1.0 - phic)
    if np.any(phi < 0.0):
        raise ValueError("alpha (cement radius a/R) needs more cement than the pore space holds "
                         f"(porosity {float(np.min(phi)):.4g} < 0) for these phic, n, thickness")
    phi, _, _, _ = broadcast(phi=phi, n=n, thickness=eps, alpha=alpha)
    return phi


#: Range of the stiffness parameters Lambda_n, Lambda_tau over which the polynomial fits of
#: Dvorkin & Nur (1996) are used; outside it they extrapolate to unphysical values.
LAMBDA_RANGE = (1e-3, 1e3)


def _cct_stiffness(alpha, Lambda_n, Lambda_t, nu0):
    r"""Dvorkin's normalised contact stiffnesses :math:`\hat S_n, \hat S_\tau` (fits).

    Coefficients of the Rock Physics Handbook ([Mavko2009]_ Sect. 7.9, [DvorkinNur1996]_):
    :math:`C_n` exponent -1.9864, :math:`B_n` exponent -0.89008, :math:`A_\tau` exponent
    :math:`0.079\nu^2+0.1754\nu-1.342`, :math:`C_\tau` exponent
    :math:`0.01867\nu^2+0.4011\nu-1.8186` and :math:`C_\tau > 0`. [Xu2023]_ (eq. A-8) prints
    -1.9846, -0.8908 and a negative :math:`C_\tau`; those are transcription variants of the
    same fit.
    """
    An, Bn, Cn, At, Bt, Ct = _cct_coefficients(Lambda_n, Lambda_t, nu0)
    Sn = An * alpha**2 + Bn * alpha + Cn
    St = At * alpha**2 + Bt * alpha + Ct
    return Sn, St


def _cct_coefficients(Lambda_n, Lambda_t, nu0):
    """The coefficients :math:`A_n, B_n, C_n, A_\\tau, B_\\tau, C_\\tau` of
    :func:`_cct_stiffness`."""
    An = -0.024153 * Lambda_n**-1.3646
    Bn = 0.20405 * Lambda_n**-0.89008
    Cn = 0.00024649 * Lambda_n**-1.9864
    nu2 = nu0 * nu0
    At = -1e-2 * (2.26 * nu2 + 2.07 * nu0 + 2.3) * Lambda_t ** (0.079 * nu2 + 0.1754 * nu0 - 1.342)
    Bt = (0.0573 * nu2 + 0.0937 * nu0 + 0.202) * Lambda_t ** (0.0274 * nu2 + 0.0529 * nu0 - 0.8765)
    Ct = 1e-4 * (9.654 * nu2 + 4.945 * nu0 + 3.1) \
        * Lambda_t ** (0.01867 * nu2 + 0.4011 * nu0 - 1.8186)
    return An, Bn, Cn, At, Bt, Ct


@labelled(units="GPa")
def contact_cement(K0, G0, Kc, Gc, phi, phic, n, scheme=1, thickness=0.0, *, stiffness="fit",
                   panels=64) -> Moduli:
    r"""Contact cement theory (CCT) of Dvorkin & Nur, with the contact thickness of Han & Guo.

    Eq. 15 of [Carcione2022]_ ([Dvorkin1994]_, [DvorkinNur1996]_, [Mavko2009]_ Sect. 7.9):

    .. math::

        K = \tfrac16 n (1-\phi_c) M_c \hat S_n, \qquad
        \mu = \tfrac35 K + \tfrac{3}{20} n (1-\phi_c) \mu_c \hat S_\tau, \qquad
        M_c = K_c + \tfrac43 \mu_c,

        \hat S_n = A_n\alpha^2 + B_n\alpha + C_n, \qquad
        \hat S_\tau = A_\tau\alpha^2 + B_\tau\alpha + C_\tau,

        \Lambda_n = \frac{2\mu_c}{\pi\mu_0}\frac{(1-\nu_0)(1-\nu_c)}{1-2\nu_c}, \qquad
        \Lambda_\tau = \frac{\mu_c}{\pi\mu_0},

    with the coefficient set of the Rock Physics Handbook (see ``_cct_stiffness``) and
    :math:`\alpha` from :func:`cement_radius`. :math:`\Lambda_n` is evaluated as
    :math:`2(1-\nu_0)(1-\nu_c)(3K_c+\mu_c)/(3\pi\mu_0)`, the same quantity without the division
    by :math:`1-2\nu_c`.

    ``thickness`` :math:`\varepsilon > 0` is the modified CCT (MCCT) of [HanGuo]_ for grains
    that do not touch: the cement radius follows their eq. 7 (eq. A-9 of [Xu2023]_), and the
    stiffnesses their eq. 1, in which the cement between the grains is
    :math:`2R(\varepsilon + t^2/2)` thick (so :math:`\varepsilon` is half the axial gap over
    :math:`R`, the quantity their eq. 6 counts). The refit of :math:`\hat S_n(\varepsilon)` printed
    as eq. A-12 of [Xu2023]_ is not used: it is negative at small :math:`\alpha` and
    :math:`\Lambda_n`, misses the CCT values at :math:`\varepsilon = 0` by a factor up to 2.5,
    and *stiffens* the contact as the gap grows. Instead the integral equation is solved
    (:mod:`rockcem.contact_integral`) and, with ``stiffness="fit"``, its relative change
    :math:`S(\alpha, \Lambda, \varepsilon)/S(\alpha, \Lambda, 0)` multiplies the handbook fit, so
    ``thickness = 0`` is exactly CCT and the thickness effect is that of the theory. With
    ``stiffness="integral"`` the solved stiffnesses are used directly at every thickness; they
    differ from the fit by less than 5 % for :math:`0.1 \le \Lambda \le 1` and are the better
    choice for soft cements (:math:`\Lambda < 0.05`, e.g. epoxy or clay on quartz), where the
    fit's :math:`C` terms grow without bound.

    The fits hold for small cement amounts (:math:`\alpha` up to about 0.5, a few per cent of
    cement) and no pressure dependence; at zero cement they give the small stiffness of the
    :math:`C` terms, *below* the Hertz–Mindlin moduli of the uncemented pack at any pressure
    (use :func:`patchy_cement` to join the two).

    Parameters
    ----------
    K0, G0 : float or array_like
        Grain moduli, GPa (``> 0``).
    Kc, Gc : float or array_like
        Cement moduli, GPa (``> 0``).
    phi : float or array_like
        Porosity, in [0, ``phic``].
    phic : float or array_like
        Critical porosity, in (0, 1).
    n : float or array_like
        Coordination number, in (0, :data:`MAX_COORDINATION_NUMBER`].
    scheme : {1, 2}
        1: cement at grain contacts; 2: cement coating the grains.
    thickness : float or array_like
        Normalised contact thickness :math:`\varepsilon`, ``>= 0``.
    stiffness : {"fit", "integral"}
        Contact stiffnesses from the handbook polynomial fits (default; thickness through the
        solved ratio) or from the solved integral equation throughout.
    panels : int
        Discretisation of the integral equation when it is used (accuracy knob, see
        :func:`rockcem.contact_integral.cemented_contact_stiffness`).

    Returns
    -------
    Moduli
        Dry-rock ``K`` and ``G``, GPa.

    Raises
    ------
    ValueError
        For inputs out of range, or stiffness ratios :math:`\Lambda_n, \Lambda_\tau` outside
        :data:`LAMBDA_RANGE` where the fits do not hold.

    Examples
    --------
    The example parameter set of the rockphypy documentation (quartz grains and cement):

    >>> m = contact_cement(36.6, 45.0, 36.6, 45.0, 0.3, 0.4, 8.6, scheme=2)
    >>> round(float(m.K), 3), round(float(m.G), 3)
    (8.05, 11.058)
    """
    K0, G0, Kc, Gc, phi, phic, n, eps = _shapes(K0=K0, G0=G0, Kc=Kc, Gc=Gc, phi=phi, phic=phic,
                                                n=n, thickness=thickness)
    return _contact_cement(K0, G0, Kc, Gc, phi, phic, n, scheme, eps, stiffness, panels)


def _contact_cement(K0, G0, Kc, Gc, phi, phic, n, scheme, eps, stiffness="fit",
                    panels=64, *, alpha=None) -> Moduli:
    """:func:`contact_cement` of arguments :func:`_shapes` has checked (the joint checks here).
    ``alpha``: the cement radius of ``phi`` (:func:`_cement_radius`) where the caller has
    computed it from the same arguments (``phi`` is then not read)."""
    nu0, nuc = _poisson("0", K0, G0), _poisson("c", Kc, Gc)
    _check_scheme(scheme)
    if alpha is None:
        _not_above("phi", phi, "phic", phic)
        alpha = _cement_radius(phi, phic, n, scheme, eps)
    if alpha.size and np.max(alpha) > 1.0:
        raise ValueError(f"phi lies too far below phic for contact cement: the cement radius "
                         f"a/R reaches {float(np.max(alpha)):.3g} > 1 (the theory holds for a/R "
                         "up to about 0.5, a few per cent of cement)")
    Lambda_n = 2.0 * (1.0 - nu0) * (1.0 - nuc) * (3.0 * Kc + Gc) / (3.0 * np.pi * G0)
    Lambda_t = Gc / (np.pi * G0)
    if stiffness not in ("fit", "integral"):
        raise ValueError(f"stiffness must be 'fit' or 'integral'; got {stiffness!r}")
    Mc = Kc + 4.0 / 3.0 * Gc
    if stiffness == "fit":
        lo, hi = LAMBDA_RANGE
        for name, lam in (("Lambda_n", Lambda_n), ("Lambda_tau", Lambda_t)):
            check_range(f"{name}, the stiffness ratio of Kc, Gc to G0 in the CCT fit "
                        "(stiffness='integral' holds beyond it),", lam, lo, hi)
        if not np.any(eps > 0.0):
            # CCT (eq. 15) in blocks: K = k Sn, G = 3/5 K + g St, the quadratics in Horner form.
            lowest = []

            def kernel(alpha, k, g, An, Bn, Cn, At, Bt, Ct):
                Sn = (An * alpha + Bn) * alpha + Cn
                St = (At * alpha + Bt) * alpha + Ct
                lowest.append(min(np.min(Sn), np.min(St)))
                K = k * Sn
                return K, 0.6 * K + g * St

            K, G = blockwise(kernel, alpha, n * (1.0 - phic) * Mc / 6.0,
                             0.15 * n * (1.0 - phic) * Gc,
                             *_cct_coefficients(Lambda_n, Lambda_t, nu0))
            _refuse_negative_fit(min(lowest, default=0.0), alpha)
            return Moduli(K, G)
        Sn, St = _cct_stiffness(alpha, Lambda_n, Lambda_t, nu0)
        _refuse_negative_fit(min(np.min(Sn), np.min(St)), alpha)
    if stiffness == "integral" or np.any(eps > 0.0):
        from .contact_integral import cemented_contact_stiffness

        Lambda_s = Lambda_t * (1.0 - 0.5 * nu0)
        # Zero cement radius: no bond, zero stiffness (the integral vanishes with alpha).
        a_pos = np.where(alpha > 0.0, alpha, 1.0)
        Sn_e = np.where(alpha > 0.0, cemented_contact_stiffness(a_pos, Lambda_n, eps,
                                                                panels=panels), 0.0)
        St_e = np.where(alpha > 0.0, cemented_contact_stiffness(a_pos, Lambda_s, eps,
                                                                panels=panels), 0.0)
        if stiffness == "integral":
            Sn, St = Sn_e, St_e
        else:
            thick = np.broadcast_to(eps > 0.0, np.broadcast_shapes(eps.shape, alpha.shape))
            Sn0 = cemented_contact_stiffness(a_pos, Lambda_n, 0.0, panels=panels)
            St0 = cemented_contact_stiffness(a_pos, Lambda_s, 0.0, panels=panels)
            # With a gap and no cement the grains do not touch: the ratio (and S) is 0 there.
            Sn = np.where(thick, Sn * Sn_e / Sn0, Sn)
            St = np.where(thick, St * St_e / St0, St)
    K = n * (1.0 - phic) * Mc * Sn / 6.0
    G = 0.6 * K + 0.15 * n * (1.0 - phic) * Gc * St
    K, G = broadcast(K=K, G=G)
    return Moduli(K, G)


def _refuse_negative_fit(lowest, alpha):
    """Refuse a negative contact stiffness of the CCT fit (``lowest``: the least of S_n, S_tau)."""
    if lowest < 0.0:
        raise ValueError(f"phi lies too far below phic for the CCT fit at these Kc, Gc, "
                         f"G0: the cement radius a/R reaches {float(np.max(alpha)):.3g}, "
                         "where the fit's contact stiffness turns negative (it holds for "
                         "a/R up to about 0.5; stiffness='integral' holds beyond it)")


@labelled(units="GPa")
def constant_cement(K0, G0, Kc, Gc, phi, phic, n, phib, scheme=1, thickness=0.0) -> Moduli:
    r"""Constant-cement model of [Avseth2000]_: contact cement at :math:`\phi_b`, then sorting.

    All sands carry the cement of the contact-cement model at porosity :math:`\phi_b`
    (:math:`K_b, \mu_b` from :func:`contact_cement`); lower porosity comes from pore-filling
    non-contact material, interpolated to the mineral with the modified HS lower bound
    ([Mavko2009]_ Sect. 7.9):

    .. math::

        K = \Big[\frac{\phi/\phi_b}{K_b + \tfrac43 \mu_b}
                 + \frac{1-\phi/\phi_b}{K_0 + \tfrac43 \mu_b}\Big]^{-1} - \tfrac43 \mu_b,
        \qquad
        \mu = \Big[\frac{\phi/\phi_b}{\mu_b + z} + \frac{1-\phi/\phi_b}{\mu_0 + z}\Big]^{-1} - z,
        \quad z = \zeta(K_b, \mu_b).

    Parameters
    ----------
    K0, G0, Kc, Gc, phic, n, scheme, thickness
        As in :func:`contact_cement`.
    phi : float or array_like
        Porosity, in [0, ``phib``].
    phib : float or array_like
        Porosity at which the cement is fixed, in (0, ``phic``].

    Returns
    -------
    Moduli
        Dry-rock ``K``, ``G``, GPa.
    """
    return _bounding(K0, G0, Kc, Gc, phi, phic, n, phib, scheme, thickness, stiff=False)


def _bounding(K0, G0, Kc, Gc, phi, phic, n, phib, scheme, thickness, *, stiff):
    """Constant (``stiff=False``) or increasing cement: the arguments checked once (phi <= phib
    <= phic), contact cement at phib, then the interpolation to the mineral in blocks."""
    K0, G0, Kc, Gc, phi, phic, n, phib, eps = _shapes(
        K0=K0, G0=G0, Kc=Kc, Gc=Gc, phi=phi, phic=phic, n=n, phib=phib, thickness=thickness)
    _not_above("phib", phib, "phic", phic)
    _not_above("phi", phi, "phib", phib)
    b = _contact_cement(K0, G0, Kc, Gc, phib, phic, n, scheme, eps)
    K_r, G_r = (K0, G0) if stiff else (b.K, b.G)
    s, z = 4.0 / 3.0 * G_r, _zeta(K_r, G_r)
    ends = (b.K + s, K0 + s, b.G + z, G0 + z)
    if all(np.size(v) == 1 for v in (*ends, s, z)) and min(np.min(v) for v in ends) > 1e-300:
        # End members and reference one number each (phib one number): the reciprocals of the
        # four denominators once, the points in blocks (the operations of _harmonic2).
        rK_b, rK_0, rG_b, rG_0 = (1.0 / np.reshape(v, ()) for v in ends)
        s, z = np.reshape(s, ()), np.reshape(z, ())

        def mix(x, x1, r_b, r_0, shift):
            total = x * r_b
            total += x1 * r_0
            np.divide(1.0, total, out=total)
            total -= shift
            return np.maximum(total, 0.0) if total.min() < 0.0 else total

        def kernel(phi, phib):
            x = phi / phib
            x1 = 1.0 - x
            if not isinstance(x, np.ndarray) or x.ndim == 0:
                return (_harmonic2(np.reshape(b.K, ()), np.reshape(K0, ()), x, s, x1),
                        _harmonic2(np.reshape(b.G, ()), np.reshape(G0, ()), x, z, x1))
            return mix(x, x1, rK_b, rK_0, s), mix(x, x1, rG_b, rG_0, z)

        shape = np.broadcast_shapes(*(np.shape(v) for v in (K0, G0, Kc, Gc, phi, phic, n,
                                                             phib, eps)))
        return Moduli(*(v.reshape(shape) for v in blockwise(kernel, phi, phib)))

    def kernel(K_b, G_b, K0, G0, phi, phib):
        ref = (K0, G0) if stiff else (K_b, G_b)
        return _hs_interpolate(K_b, G_b, K0, G0, phi / phib, *ref)

    return Moduli(*blockwise(kernel, b.K, b.G, K0, G0, phi, phib))


@labelled(units="GPa")
def increasing_cement(K0, G0, Kc, Gc, phi, phic, n, phib, scheme=1, thickness=0.0) -> Moduli:
    r"""Increasing-cement model: modified HS upper bound from contact cement to the mineral.

    The contact-cement model holds for the first few per cent of cement, down to porosity
    :math:`\phi_b`; below it, cement fills the pores and the moduli follow the modified upper
    Hashin–Shtrikman bound between :math:`(K_b, \mu_b)` at :math:`\phi_b` and the mineral
    ([Mavko2009]_ Sect. 7.9; [Avseth2000]_):

    .. math::

        K = \Big[\frac{\phi/\phi_b}{K_b + \tfrac43 \mu_0}
                 + \frac{1-\phi/\phi_b}{K_0 + \tfrac43 \mu_0}\Big]^{-1} - \tfrac43 \mu_0,
        \qquad z = \zeta(K_0, \mu_0).

    Parameters and returns as in :func:`constant_cement`; valid for :math:`0 \le \phi \le \phi_b`.
    """
    return _bounding(K0, G0, Kc, Gc, phi, phic, n, phib, scheme, thickness, stiff=True)


@labelled(units="GPa")
def patchy_cement(K0, G0, Kc, Gc, phi, phic, n, pressure, cement_fraction,
                  contact_cement_limit=0.05, scheme=1, thickness=0.0, f=1.0, delta=0.0) -> Moduli:
    r"""Patchy-cement model in the form of Model 4 of [Carcione2022]_ (after [Avseth2016]_).

    1. The cement bonded at grain contacts is capped, eq. 17:
       :math:`\bar\phi_p = \min(\phi_p, \phi_{p0})`; the rest fills pores.
    2. Cemented patches: contact cement theory (eq. 15, :func:`contact_cement`) with the cement
       radius of eq. 16 (``scheme=1``) or 18 (``scheme=2``) for :math:`\bar\phi_p`, optionally
       with contact thickness.
    3. Uncemented patches: Hertz–Mindlin (eqs. D.1–D.2) at the augmented pressure
       :math:`p_e + \delta`.
    4. The high-porosity end member :math:`(K_b, \mu_b)` mixes the two with the HS upper bound,
       cemented fraction :math:`f = \phi_p/\phi_c` (clipped to [0, 1]).
    5. The zero-porosity end member :math:`(K_s, \mu_s)` is the self-consistent mixture of grain
       and cement spheres in proportions :math:`1-\phi_c` and :math:`\phi_c`.
    6. Voigt–Reuss–Hill interpolation in :math:`\phi/\phi_c` between them, eqs. 19–21.

    At zero cement this is the Hill interpolation of Hertz–Mindlin and the mineral; cement only
    stiffens it (the HS upper mix is at least as stiff as its stiffer member's share), so zero
    cement never falls below the uncemented limit.

    Parameters
    ----------
    K0, G0, Kc, Gc : float or array_like
        Grain and cement moduli, GPa.
    phi : float or array_like
        Porosity, in [0, ``phic``].
    phic : float or array_like
        Critical porosity :math:`\phi_0`, in (0, 1) (0.36 in [Carcione2022]_).
    n : float or array_like
        Coordination number (9 in [Carcione2022]_).
    pressure : float or array_like
        Effective pressure, MPa, ``>= 0``.
    cement_fraction : float or array_like
        Total cement volume fraction :math:`\phi_p`, in [0, ``phic``].
    contact_cement_limit : float, optional
        :math:`\phi_{p0}`, the most cement that sits at contacts, in (0, ``phic``]; default 0.05.
    scheme : {1, 2}
        Contact (eq. 16) or coating (eq. 18) cement radius.
    thickness : float or array_like
        Normalised contact thickness of the MCCT, ``>= 0``; default 0.
    f, delta
        Slip factor and bonding pre-stress (MPa) of :func:`hertz_mindlin`.

    Returns
    -------
    Moduli
        Dry-rock ``K``, ``G``, GPa.
    """
    K0, G0, Kc, Gc, phi, phic_arr, n, pressure, phip, limit, eps, f, delta = _shapes(
        K0=K0, G0=G0, Kc=Kc, Gc=Gc, phi=phi, phic=phic, n=n, pressure=pressure,
        cement_fraction=cement_fraction, contact_cement_limit=contact_cement_limit,
        thickness=thickness, f=f, delta=delta)
    _not_above("phi", phi, "phic", phic_arr)
    _not_above("cement_fraction", phip, "phic", phic_arr)
    return _patchy_cement(K0, G0, Kc, Gc, phi, phic_arr, n, pressure, phip, limit, scheme, eps,
                          f, delta)


def _patchy_cement(K0, G0, Kc, Gc, phi, phic_arr, n, pressure, phip, limit, scheme, eps, f,
                   delta, *, alpha=None) -> Moduli:
    """:func:`patchy_cement` of arguments checked by :func:`_shapes` (phi and phip <= phic).
    ``alpha``: the contact cement's radius (:func:`_cement_radius` of ``phic - min(phip,
    limit)``) where the caller has computed it."""
    from .bounds import _hill2, _hs_upper2
    from .inclusions import self_consistent

    # The building blocks below take the arguments checked by the caller (their own checks
    # skipped).
    phi_cct = None if alpha is not None else phic_arr - np.minimum(phip, limit)
    cct = _contact_cement(K0, G0, Kc, Gc, phi_cct, phic_arr, n, scheme, eps, alpha=alpha)
    nu = _poisson("0", K0, G0)
    # The zero-porosity end member depends on the minerals and phic only: one solve per
    # distinct set (one for scalar arguments), not one per point.
    end_s = self_consistent(stack_phases(K0, Kc), stack_phases(G0, Gc),
                            stack_phases(1.0 - phic_arr, phic_arr), engine="numpy")

    def kernel(K0, G0, phic, n, pressure, f, delta, nu, cct_K, cct_G, phip, phi, s_K, s_G):
        hm_K, hm_G = _hm(K0, G0, phic, n, pressure, f, delta, nu)
        frac = np.clip(phip / phic, 0.0, 1.0)
        b_K, b_G = _hs_upper2(cct_K, cct_G, hm_K, hm_G, frac, 1.0 - frac)
        x = phi / phic
        return _hill2(s_K, s_G, b_K, b_G, 1.0 - x, x)

    return Moduli(*blockwise(kernel, K0, G0, phic_arr, n, pressure, f, delta, nu, cct.K, cct.G,
                             phip, phi, end_s.K, end_s.G))
