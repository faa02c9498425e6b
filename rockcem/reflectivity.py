"""Plane-wave reflection of P waves at a welded interface between two isotropic solids, and AVO.

The exact PP reflection coefficient ([Zoeppritz1919]_, in the explicit form of
[AkiRichards1980]_), its linearisations ([AkiRichards1980]_; [Shuey1985]_), the intercept,
gradient and curvature, the AVO class of an interface ([RutherfordWilliams1989]_;
[RossKinman1995]_; [CastagnaSwan1997]_) and the critical angle.

Medium 1 lies above the interface, medium 2 below; a plane P wave is incident from medium 1 at
``angle`` degrees from the vertical. Units: velocities in km/s, densities in g/cm³, angles in
degrees; coefficients are dimensionless. Every function broadcasts over all its arguments (give
the angles on a trailing axis, e.g. ``vp1[:, None]`` with ``angle`` of shape ``(n,)``), and takes
pandas and xarray inputs through :func:`rockcem.validation.labelled` (an ``angle`` DataArray on
its own ``angle`` dimension, given last, makes the angle the last dimension of the result).

Conventions of the exact solution. Displacements vary as
:math:`\\exp[i\\omega(px + \\eta z - t)]` with :math:`z` down (Aki & Richards 1980, section 5.2):
:math:`p = \\sin\\theta_1 / V_{P1}` is the horizontal slowness and
:math:`\\eta = \\sqrt{1/V^2 - p^2}` the vertical slowness of a wave of velocity :math:`V`.
Beyond a critical angle (:math:`p > 1/V`) the root is taken with a positive imaginary part, so
that the wave decays away from the interface for positive frequencies; the coefficient is then
complex (its modulus the amplitude, its argument the phase shift). With the opposite time
convention :math:`\\exp(+i\\omega t)` (bruges, from numpy's principal ``arcsin``) the coefficients
are the complex conjugates of these. The polarity follows Aki & Richards: at normal incidence
:math:`R_{PP} = (Z_2 - Z_1)/(Z_2 + Z_1)`, :math:`Z = \\rho V_P`.

Inputs must describe isotropic solids: ``0 < vs < vp * sqrt(3)/2`` (a positive shear and a
positive bulk modulus, ``K = rho (vp**2 - 4/3 vs**2)``); a liquid layer (``vs = 0``) is outside
these functions.

The literature cited in the docstrings below, by author and year (the keys of
:data:`rockcem.references.REFERENCES`: [AkiRichards1980]_, [CastagnaSwan1997]_,
[Castagna1998]_, [Hilterman2001]_, [RossKinman1995]_, [RutherfordWilliams1989]_,
[Shuey1985]_, [Zoeppritz1919]_):

- Aki, K., and Richards, P. G., 1980. Quantitative Seismology, vol. 1. Freeman, San Francisco.
- Castagna, J. P., and Swan, H. W., 1997. Principles of AVO crossplotting. The Leading Edge 16,
  337-342.
- Castagna, J. P., Swan, H. W., and Foster, D. J., 1998. Framework for AVO gradient and intercept
  interpretation. Geophysics 63, 948-956.
- Hilterman, F. J., 2001. Seismic Amplitude Interpretation. SEG/EAGE Distinguished Instructor
  Short Course 4.
- Ross, C. P., and Kinman, D. L., 1995. Nonbright-spot AVO: two examples. Geophysics 60,
  1398-1408.
- Rutherford, S. R., and Williams, R. H., 1989. Amplitude-versus-offset variations in gas sands.
  Geophysics 54, 680-688.
- Shuey, R. T., 1985. A simplification of the Zoeppritz equations. Geophysics 50, 609-614.
- Zoeppritz, K., 1919. Erdbebenwellen VII. VIIb. Über Reflexion und Durchgang seismischer Wellen
  durch Unstetigkeitsflächen. Nachrichten der Königlichen Gesellschaft der Wissenschaften zu
  Göttingen, Mathematisch-physikalische Klasse, 66-84.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .validation import (MAX_DENSITY, MIN_DENSITY, as_array, as_scalar, broadcast, check_range,
                         labelled)

__all__ = ["AVO_CLASSES", "AVO_CLASS_CODES", "AVO_THRESHOLD", "MAX_VELOCITY", "AVOTerms",
           "Scattering", "zoeppritz_pp", "zoeppritz_scattering", "aki_richards_pp", "shuey_pp",
           "intercept_gradient", "avo_class", "critical_angle"]

#: Names of the AVO classes, in the order of :data:`AVO_CLASS_CODES` (0 is no class).
AVO_CLASSES = ("I", "IIp", "II", "III", "IV")
#: Codes :func:`avo_class` returns for :data:`AVO_CLASSES` (CF ``flag_values``).
AVO_CLASS_CODES = (1, 2, 3, 4, 5)
#: Default ``threshold`` of :func:`avo_class`: the largest ``|A|`` of a "near-zero" intercept.
AVO_THRESHOLD = 0.03
#: Largest velocity accepted, km/s: above any rock's (diamond: 18 km/s), below a velocity in m/s.
MAX_VELOCITY = 25.0

#: Elements per block of the exact solution: its ~16 temporary arrays stay in the cache (256 KiB
#: each), and the memory of a call is its result's (benchmarks/results/reflectivity_speed.md).
_BLOCK = 1 << 14


class AVOTerms(NamedTuple):
    """Shuey's intercept ``A``, gradient ``B`` and curvature ``C`` (dimensionless)."""

    intercept: np.ndarray
    gradient: np.ndarray
    curvature: np.ndarray


class Scattering(NamedTuple):
    """Coefficients of the four waves a P wave incident from above scatters into (complex).

    Displacement amplitudes relative to the incident one, with the polarities of
    :func:`zoeppritz_scattering`; ``*_flux`` are the vertical energy fluxes relative to the
    incident one (real, zero for an evanescent wave).
    """

    rpp: np.ndarray
    rps: np.ndarray
    tpp: np.ndarray
    tps: np.ndarray
    rpp_flux: np.ndarray
    rps_flux: np.ndarray
    tpp_flux: np.ndarray
    tps_flux: np.ndarray


# --- input checks -----------------------------------------------------------------------------

def _velocity(name, value):
    v = as_array(name, value)
    bad = ~((v > 0.0) & (v <= MAX_VELOCITY))
    if np.any(bad):
        worst = v[bad].flat[0]
        hint = "; a velocity in m/s? (give km/s)" if worst > MAX_VELOCITY else ""
        raise ValueError(f"{name} must lie in (0, {MAX_VELOCITY:g}] km/s; got {worst:g}{hint}")
    return v


def _density(name, value):
    return check_range(name, as_array(name, value), MIN_DENSITY, MAX_DENSITY)


def _angle(value, name="angle"):
    return check_range(name, as_array(name, value), 0.0, 90.0, high_open=True)


def _solid(vp_name, vp, vs_name, vs):
    """Refuse ``vs >= vp * sqrt(3)/2`` (a negative bulk modulus)."""
    vp_, vs_ = broadcast(**{vp_name: vp, vs_name: vs})
    bad = vs_ >= vp_ * (np.sqrt(3.0) / 2.0)
    if np.any(bad):
        i = np.flatnonzero(bad.ravel())[0]
        raise ValueError(f"{vs_name} must be below {vp_name} * sqrt(3)/2 (a positive bulk "
                         f"modulus of an isotropic solid); got {vs_name} = "
                         f"{vs_.ravel()[i]:g} km/s with {vp_name} = {vp_.ravel()[i]:g} km/s")


def _media(vp1, vs1, rho1, vp2, vs2, rho2):
    vp1, vs1, vp2, vs2 = (_velocity(n, v) for n, v in
                          (("vp1", vp1), ("vs1", vs1), ("vp2", vp2), ("vs2", vs2)))
    rho1, rho2 = _density("rho1", rho1), _density("rho2", rho2)
    _solid("vp1", vp1, "vs1", vs1)
    _solid("vp2", vp2, "vs2", vs2)
    return vp1, vs1, rho1, vp2, vs2, rho2


def _vertical_slowness(s2):
    """:math:`\\sqrt{s^2}` of ``s2 = 1/V**2 - p**2`` with a non-negative imaginary part."""
    r = np.sqrt(np.abs(s2))
    out = np.empty(s2.shape, dtype=complex)
    out.real = np.where(s2 >= 0.0, r, 0.0)
    out.imag = np.where(s2 < 0.0, r, 0.0)
    return out


# --- the exact solution -----------------------------------------------------------------------

def _rpp_block(vp1, vs1, rho1, vp2, vs2, rho2, sin1, cos1, out):
    """The explicit R_PP of Aki & Richards (1980), eq. 5.40, on one block (arrays of one shape).

    With ``d = 2 (rho2 vs2**2 - rho1 vs1**2)`` the coefficients of eq. 5.40 read
    ``a = (rho2 - rho1) - d p**2``, ``b = rho2 - d p**2``, ``c = rho1 + d p**2``.
    """
    p = sin1 / vp1
    p2 = p * p
    xi1 = cos1 / vp1                  # not sqrt(1/vp1**2 - p2): that rounds below 0 near 90°
    eta1 = np.sqrt(1.0 / (vs1 * vs1) - p2)             # real: vs1 < vp1
    xi2 = _vertical_slowness(1.0 / (vp2 * vp2) - p2)
    eta2 = _vertical_slowness(1.0 / (vs2 * vs2) - p2)
    d = 2.0 * (rho2 * vs2 * vs2 - rho1 * vs1 * vs1)
    dp2 = d * p2
    a = (rho2 - rho1) - dp2
    b = rho2 - dp2
    c = rho1 + dp2
    E = b * xi1 + c * xi2
    F = b * eta1 + c * eta2
    G = a - d * xi1 * eta2
    H = a - d * xi2 * eta1
    D = E * F + G * H * p2
    out[...] = ((b * xi1 - c * xi2) * F - (a + d * xi1 * eta2) * H * p2) / D


def _blockwise(kernel, arrays, shape, out):
    """Call ``kernel(*blocks, out_block)`` on blocks of at most about :data:`_BLOCK` elements of
    the broadcast ``arrays`` (views: nothing is copied to the full shape).

    The blocks are slices along one axis ``k`` (all of the axes after it, single indices of the
    ones before it), ``k`` the last axis after which fewer than :data:`_BLOCK` elements remain.
    """
    views = np.broadcast_arrays(*arrays)
    if out.size <= _BLOCK:
        kernel(*views, out)
        return
    k = len(shape) - 1
    while k > 0 and int(np.prod(shape[k:])) <= _BLOCK:
        k -= 1
    step = max(1, _BLOCK // int(np.prod(shape[k + 1:])))
    for idx in np.ndindex(*shape[:k]):
        for s in range(0, shape[k], step):
            sl = (*idx, slice(s, s + step))
            kernel(*(v[sl] for v in views), out[sl])


@labelled(units="1")
def zoeppritz_pp(vp1, vs1, rho1, vp2, vs2, rho2, angle):
    """Exact PP reflection coefficient of a plane P wave at a solid-solid interface.

    The solution of the four boundary conditions of a welded interface (continuity of the two
    displacement and the two traction components; [Zoeppritz1919]_), in the explicit form of
    eq. 5.40 of [AkiRichards1980]_ (section 5.2.4):

    .. math::

        R_{PP} = \\frac{(b\\,\\xi_1 - c\\,\\xi_2) F - (a + d\\,\\xi_1 \\eta_2) H p^2}{D}

    with :math:`\\xi_k = \\cos i_k / \\alpha_k`, :math:`\\eta_k = \\cos j_k / \\beta_k` the
    vertical slownesses of P and S in medium :math:`k`, :math:`a = \\rho_2(1 - 2\\beta_2^2p^2) -
    \\rho_1(1 - 2\\beta_1^2p^2)`, :math:`b = \\rho_2(1 - 2\\beta_2^2p^2) + 2\\rho_1\\beta_1^2p^2`,
    :math:`c = \\rho_1(1 - 2\\beta_1^2p^2) + 2\\rho_2\\beta_2^2p^2`, :math:`d = 2(\\rho_2\\beta_2^2
    - \\rho_1\\beta_1^2)`, :math:`E = b\\xi_1 + c\\xi_2`, :math:`F = b\\eta_1 + c\\eta_2`,
    :math:`G = a - d\\xi_1\\eta_2`, :math:`H = a - d\\xi_2\\eta_1`, :math:`D = EF + GHp^2`.
    Beyond a critical angle the vertical slowness of the evanescent wave is imaginary with a
    positive imaginary part (see the module's conventions); the result is complex and finite.
    The same coefficient as the first element of :func:`zoeppritz_scattering` (a numerical
    solution of the 4x4 system), a few times faster.

    Beyond the P critical angle :math:`|R_{PP}| < 1` in general: the transmitted P wave carries
    no energy, but the reflected and (before its own critical angle) the transmitted S waves
    do, so :math:`|R_{PP}|^2` is 1 less their energy fluxes (:func:`zoeppritz_scattering`);
    only in the acoustic limit (both S velocities going to 0) does :math:`|R_{PP}| \\to 1`, with
    :math:`1 - |R_{PP}|` proportional to the S velocities.

    Parameters
    ----------
    vp1, vs1, rho1 : float or array_like
        P and S velocities (km/s) and density (g/cm³) of the upper medium, the one the wave comes
        from: ``0 < vs1 < vp1 * sqrt(3)/2``, velocities up to :data:`MAX_VELOCITY`, density in
        [:data:`rockcem.validation.MIN_DENSITY`, :data:`rockcem.validation.MAX_DENSITY`].
    vp2, vs2, rho2 : float or array_like
        P and S velocities (km/s) and density (g/cm³) of the lower medium, in the same
        ranges.
    angle : float or array_like
        Angle of incidence from the vertical, degrees, in [0, 90).

    Returns
    -------
    ndarray of complex128
        :math:`R_{PP}`, broadcast over the inputs (real part and modulus are the reflection
        amplitude before any critical angle; never NaN).

    Examples
    --------
    >>> r = zoeppritz_pp(2.0, 1.0, 2.2, 3.0, 1.5, 2.3, [0.0, 30.0, 60.0])
    >>> z1, z2 = 2.0 * 2.2, 3.0 * 2.3                 # normal incidence: the impedance contrast
    >>> bool(abs(r[0] - (z2 - z1) / (z2 + z1)) < 1e-15)
    True
    >>> round(float(abs(r[2])), 4)   # beyond the critical angle arcsin(2/3) = 41.8 degrees
    0.8382
    """
    vp1, vs1, rho1, vp2, vs2, rho2 = _media(vp1, vs1, rho1, vp2, vs2, rho2)
    rad = np.radians(_angle(angle))
    arrays = broadcast(vp1=vp1, vs1=vs1, rho1=rho1, vp2=vp2, vs2=vs2, rho2=rho2,
                       angle=np.sin(rad), cos=np.cos(rad))
    shape = arrays[0].shape
    out = np.empty(shape, dtype=complex)
    _blockwise(_rpp_block, arrays, shape, out)
    return out


@labelled(units="1")
def zoeppritz_scattering(vp1, vs1, rho1, vp2, vs2, rho2, angle) -> Scattering:
    """The four waves scattered by a P wave incident from above: a numerical solution of the 4x4
    system of boundary conditions ([Zoeppritz1919]_; eq. 5.39 of [AkiRichards1980]_), and their
    energy fluxes.

    Each wave is :math:`A\\,\\mathbf{d}\\exp[i\\omega(\\mathbf{s}\\cdot\\mathbf{x} - t)]` with
    slowness :math:`\\mathbf{s} = (p, \\pm\\eta)` (``+`` down). Polarisations: P along
    :math:`V\\mathbf{s}` (incident, reflected and transmitted), reflected S along
    :math:`\\beta_1(\\eta_1, p)`, transmitted S along :math:`\\beta_2(\\eta_2, -p)`; the PP
    coefficients are those of Aki & Richards, the PS ones may differ from theirs in sign. The
    continuity of :math:`u_x, u_z, \\sigma_{xz}, \\sigma_{zz}` at :math:`z = 0`, with
    :math:`\\sigma_{xz} = \\mu(d_x s_z + d_z s_x)` and
    :math:`\\sigma_{zz} = \\lambda\\,\\mathbf{d}\\cdot\\mathbf{s} + 2\\mu d_z s_z` (the common
    factor :math:`i\\omega` dropped), is solved for the four amplitudes. The vertical energy flux
    of each wave relative to the incident one is :math:`\\rho V^2 \\mathrm{Re}(\\eta)|A|^2 /
    (\\rho_1\\alpha_1^2\\xi_1)` (Aki & Richards 1980, section 5.2): zero for an evanescent
    wave, and the four sum to 1 for every angle (energy conservation).

    Parameters
    ----------
    vp1, vs1, rho1, vp2, vs2, rho2, angle
        P and S velocities (km/s) and densities (g/cm³) of the upper (1) and lower (2)
        medium, and the angle of incidence (degree), as :func:`zoeppritz_pp`.

    Returns
    -------
    Scattering
        Complex ``rpp, rps, tpp, tps`` and real ``*_flux``, broadcast over the inputs.
    """
    vp1, vs1, rho1, vp2, vs2, rho2 = _media(vp1, vs1, rho1, vp2, vs2, rho2)
    rad = np.radians(_angle(angle))
    vp1, vs1, rho1, vp2, vs2, rho2, sin1, cos1 = broadcast(
        vp1=vp1, vs1=vs1, rho1=rho1, vp2=vp2, vs2=vs2, rho2=rho2, angle=np.sin(rad),
        cos=np.cos(rad))
    p = sin1 / vp1
    p2 = p * p
    xi1 = cos1 / vp1 + 0j
    eta1 = np.sqrt(1.0 / vs1**2 - p2) + 0j
    xi2 = _vertical_slowness(1.0 / vp2**2 - p2)
    eta2 = _vertical_slowness(1.0 / vs2**2 - p2)
    mu1, mu2 = rho1 * vs1**2, rho2 * vs2**2
    lam1, lam2 = rho1 * vp1**2 - 2.0 * mu1, rho2 * vp2**2 - 2.0 * mu2

    def column(d, s, lam, mu):
        """(u_x, u_z, sigma_xz, sigma_zz) of a unit-amplitude wave."""
        dx, dz = d
        sx, sz = s
        return np.stack([dx, dz, mu * (dx * sz + dz * sx),
                         lam * (dx * sx + dz * sz) + 2.0 * mu * dz * sz], axis=-1)

    inc = column((vp1 * p, vp1 * xi1), (p, xi1), lam1, mu1)
    rp = column((vp1 * p, -vp1 * xi1), (p, -xi1), lam1, mu1)
    rs = column((vs1 * eta1, vs1 * p), (p, -eta1), lam1, mu1)
    tp = column((vp2 * p, vp2 * xi2), (p, xi2), lam2, mu2)
    ts = column((vs2 * eta2, -vs2 * p), (p, eta2), lam2, mu2)
    M = np.stack([rp, rs, -tp, -ts], axis=-1)
    x = np.linalg.solve(M, -inc[..., None])[..., 0]
    rpp, rps, tpp, tps = (x[..., i] for i in range(4))
    incident = rho1 * vp1**2 * xi1.real

    def flux(rho, v, eta, amp):
        return rho * v**2 * eta.real * np.abs(amp)**2 / incident

    return Scattering(rpp, rps, tpp, tps, flux(rho1, vp1, xi1, rpp), flux(rho1, vs1, eta1, rps),
                      flux(rho2, vp2, xi2, tpp), flux(rho2, vs2, eta2, tps))


# --- linearisations ---------------------------------------------------------------------------

def _contrasts(vp1, vs1, rho1, vp2, vs2, rho2):
    vp, vs, rho = 0.5 * (vp1 + vp2), 0.5 * (vs1 + vs2), 0.5 * (rho1 + rho2)
    return vp, vs, (vp2 - vp1) / vp, (vs2 - vs1) / vs, (rho2 - rho1) / rho


@labelled(units="1")
def aki_richards_pp(vp1, vs1, rho1, vp2, vs2, rho2, angle):
    """PP reflection coefficient linearised in the contrasts, eq. 5.44 of [AkiRichards1980]_.

    .. math::

        R(\\theta) = \\tfrac12\\left(1 - 4\\beta^2p^2\\right)\\frac{\\Delta\\rho}{\\rho}
            + \\frac{1}{2\\cos^2\\theta}\\frac{\\Delta\\alpha}{\\alpha}
            - 4\\beta^2p^2\\frac{\\Delta\\beta}{\\beta}

    with :math:`\\alpha, \\beta, \\rho` the means of the two media, :math:`\\Delta` the lower
    minus the upper value, :math:`p = \\sin\\theta_1/\\alpha_1` and :math:`\\theta` the mean of
    the incidence angle :math:`\\theta_1` and the transmission angle :math:`\\theta_2`
    (:math:`\\sin\\theta_2 = p\\alpha_2`), as in Aki & Richards. Beyond the P critical angle,
    where no transmission angle exists, :math:`\\theta_2` is held at 90 degrees: the result is
    real, finite and continuous there, but the linearisation does not describe the reflection
    (use :func:`zoeppritz_pp`). Its error against the exact coefficient is of second order in the
    contrasts.

    Parameters
    ----------
    vp1, vs1, rho1, vp2, vs2, rho2, angle
        P and S velocities (km/s) and densities (g/cm³) of the upper (1) and lower (2)
        medium, and the angle of incidence (degree), as :func:`zoeppritz_pp`.

    Returns
    -------
    ndarray of float64
        :math:`R(\\theta)`, broadcast over the inputs.
    """
    vp1, vs1, rho1, vp2, vs2, rho2 = _media(vp1, vs1, rho1, vp2, vs2, rho2)
    th1 = np.radians(_angle(angle))
    vp, vs, dvp, dvs, drho = _contrasts(vp1, vs1, rho1, vp2, vs2, rho2)
    sin1 = np.sin(th1)
    p = sin1 / vp1
    th2 = np.arcsin(np.minimum(p * vp2, 1.0))
    theta = 0.5 * (th1 + th2)
    k = 4.0 * (vs * p) ** 2
    out = 0.5 * (1.0 - k) * drho + 0.5 * dvp / np.cos(theta) ** 2 - k * dvs
    return np.asarray(out, dtype=float)


def _shuey_terms(vp1, vs1, rho1, vp2, vs2, rho2):
    vp, vs, dvp, dvs, drho = _contrasts(vp1, vs1, rho1, vp2, vs2, rho2)
    A = 0.5 * (dvp + drho)
    B = 0.5 * dvp - 2.0 * (vs / vp) ** 2 * (drho + 2.0 * dvs)
    C = 0.5 * dvp
    return A, B, C


@labelled(units={"intercept": "1", "gradient": "1", "curvature": "1"})
def intercept_gradient(vp1, vs1, rho1, vp2, vs2, rho2) -> AVOTerms:
    """Shuey's intercept, gradient and curvature of the Aki-Richards linearisation.

    [Shuey1985]_, in the form in P and S velocities and density that eq. 5.44 of
    [AkiRichards1980]_ takes when its mean angle is replaced by the incidence angle and
    :math:`p` by :math:`\\sin\\theta/\\alpha` (as in [Castagna1998]_):

    .. math::

        A = \\tfrac12\\left(\\frac{\\Delta\\alpha}{\\alpha} + \\frac{\\Delta\\rho}{\\rho}\\right),
        \\quad
        B = \\tfrac12\\frac{\\Delta\\alpha}{\\alpha}
            - 2\\frac{\\beta^2}{\\alpha^2}\\left(\\frac{\\Delta\\rho}{\\rho}
            + 2\\frac{\\Delta\\beta}{\\beta}\\right), \\quad
        C = \\tfrac12\\frac{\\Delta\\alpha}{\\alpha}

    (means and differences as in :func:`aki_richards_pp`), so that
    :math:`R(\\theta) \\approx A + B\\sin^2\\theta + C(\\tan^2\\theta - \\sin^2\\theta)`.

    Parameters
    ----------
    vp1, vs1, rho1, vp2, vs2, rho2
        P and S velocities (km/s) and densities (g/cm³) of the upper (1) and lower (2)
        medium, as :func:`zoeppritz_pp`.

    Returns
    -------
    AVOTerms
        ``intercept`` A, ``gradient`` B, ``curvature`` C, dimensionless, broadcast.

    Examples
    --------
    >>> t = intercept_gradient(2.0, 1.0, 2.2, 3.0, 1.5, 2.3)
    >>> round(float(t.intercept), 4), round(float(t.gradient), 4), round(float(t.curvature), 4)
    (0.2222, -0.2222, 0.2)
    """
    vp1, vs1, rho1, vp2, vs2, rho2 = _media(vp1, vs1, rho1, vp2, vs2, rho2)
    A, B, C = _shuey_terms(*broadcast(vp1=vp1, vs1=vs1, rho1=rho1, vp2=vp2, vs2=vs2, rho2=rho2))
    return AVOTerms(A, B, C)


@labelled(units="1")
def shuey_pp(vp1, vs1, rho1, vp2, vs2, rho2, angle, terms=3):
    """Shuey's approximation of the PP reflection coefficient ([Shuey1985]_), two or three terms.

    .. math:: R(\\theta) = A + B\\sin^2\\theta + C(\\tan^2\\theta - \\sin^2\\theta)

    with A, B, C of :func:`intercept_gradient` and :math:`\\theta` the incidence angle; with
    ``terms=2`` the last term is left out. The three-term form equals Aki & Richards (1980)
    eq. 5.44 with the incidence angle in place of the mean angle.

    Parameters
    ----------
    vp1, vs1, rho1, vp2, vs2, rho2, angle
        P and S velocities (km/s) and densities (g/cm³) of the upper (1) and lower (2)
        medium, and the angle of incidence (degree), as :func:`zoeppritz_pp`.
    terms : {2, 3}
        Number of terms.

    Returns
    -------
    ndarray of float64
        :math:`R(\\theta)`, broadcast over the inputs.
    """
    if isinstance(terms, bool) or terms not in (2, 3):
        raise ValueError(f"terms must be 2 or 3; got {terms!r}")
    vp1, vs1, rho1, vp2, vs2, rho2 = _media(vp1, vs1, rho1, vp2, vs2, rho2)
    th = np.radians(_angle(angle))
    A, B, C = _shuey_terms(vp1, vs1, rho1, vp2, vs2, rho2)
    s2 = np.sin(th) ** 2
    out = A + B * s2
    if terms == 3:
        out = out + C * (np.tan(th) ** 2 - s2)
    return np.asarray(out, dtype=float)


@labelled(units="1", input_units={"gradient": "1"})      # the AVO gradient, not a thermal one
def avo_class(intercept, gradient, *, threshold=AVO_THRESHOLD):
    """AVO class of an interface from its intercept A and gradient B.

    The classes of [RutherfordWilliams1989]_ (I, II, III by the normal-incidence contrast),
    with II split into IIp (positive intercept, polarity reversal) and II (negative intercept) by
    [RossKinman1995]_, and class IV of [CastagnaSwan1997]_, placed in the A-B plane as by
    [CastagnaSwan1997]_ and [Castagna1998]_:

    ======  ====================  ===================
    code    class                 rule
    ======  ====================  ===================
    1       I                     ``B < 0``, ``A >= threshold``
    2       IIp                   ``B < 0``, ``0 <= A < threshold``
    3       II                    ``B < 0``, ``-threshold < A < 0``
    4       III                   ``B < 0``, ``A <= -threshold``
    5       IV                    ``B >= 0``, ``A < 0``
    0       none                  ``B >= 0``, ``A >= 0`` (no contrast, or the quadrant the
                                  classes leave out)
    ======  ====================  ===================

    Parameters
    ----------
    intercept, gradient : float or array_like
        A and B (dimensionless, finite), e.g. from :func:`intercept_gradient`.
    threshold : float, keyword-only
        The largest ``|A|`` of a "near-zero" intercept (classes IIp and II), in (0, 1). The
        sources describe class II as a near-zero impedance contrast and give no number; the
        default :data:`AVO_THRESHOLD` (0.03) is this project's choice: it puts the class II gas
        sand of [Hilterman2001]_ (A = -0.023) in class II and his class I sand (A = 0.09) in I.

    Returns
    -------
    ndarray of int8
        Codes of :data:`AVO_CLASS_CODES` (0 for none), broadcast over the inputs.

    Examples
    --------
    >>> avo_class([0.1, 0.01, -0.01, -0.1, -0.1, 0.0], [-0.2, -0.2, -0.2, -0.2, 0.1, 0.0])
    array([1, 2, 3, 4, 5, 0], dtype=int8)
    """
    t = as_scalar("threshold", threshold)
    if not 0.0 < t < 1.0:
        raise ValueError(f"threshold must lie in (0, 1); got {t:g}")
    A = check_range("intercept", as_array("intercept", intercept), -np.inf, np.inf,
                    low_open=True, high_open=True)
    B = check_range("gradient", as_array("gradient", gradient), -np.inf, np.inf,
                    low_open=True, high_open=True)
    A, B = broadcast(intercept=A, gradient=B)
    neg = B < 0.0
    out = np.zeros(A.shape, dtype=np.int8)
    out[neg & (A >= t)] = 1
    out[neg & (A >= 0.0) & (A < t)] = 2
    out[neg & (A < 0.0) & (A > -t)] = 3
    out[neg & (A <= -t)] = 4
    out[~neg & (A < 0.0)] = 5
    return out


@labelled(units="degree")
def critical_angle(v1, v2):
    """Critical angle of a wave of velocity ``v1`` incident on a medium of velocity ``v2``.

    :math:`\\theta_c = \\arcsin(v_1/v_2)` where :math:`v_2 > v_1` (Snell's law with a grazing
    transmitted wave; [AkiRichards1980]_, section 5.2.4), and 90 degrees where :math:`v_2 \\le
    v_1`: there is then no critical angle, and every angle of incidence below 90 transmits. Never
    NaN. For the PP critical angle give ``vp1, vp2``; for the one beyond which the transmitted S
    wave is evanescent ``vp1, vs2``.

    Parameters
    ----------
    v1, v2 : float or array_like
        Velocities above and below the interface, km/s, in (0, :data:`MAX_VELOCITY`].

    Returns
    -------
    ndarray
        Degrees, in (0, 90], broadcast.

    Examples
    --------
    >>> critical_angle([2.0, 3.0], [4.0, 2.0])
    array([30., 90.])
    """
    v1, v2 = broadcast(v1=_velocity("v1", v1), v2=_velocity("v2", v2))
    return np.degrees(np.arcsin(np.minimum(v1 / v2, 1.0)))
