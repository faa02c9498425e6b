"""Walderhaug quartz cementation along any burial path (Carcione et al. 2022, App. B)."""

from __future__ import annotations

import numpy as np

from rockcem.constants import SECONDS_PER_MYR
from rockcem.validation import as_array, broadcast, check_range

from ._integrals import cumulative_power10
from ._members import member_values
from .path import MAX_TEMPERATURE_C, MIN_TEMPERATURE_C, BurialPath

__all__ = ["quartz_cement", "QUARTZ_MOLAR_MASS", "QUARTZ_DENSITY", "MAX_RATE_EXPONENT",
           "MIN_GRAIN_SIZE_MM"]

#: Molar mass of quartz, g/mol (Carcione et al. 2022, Sect. 6.2).
QUARTZ_MOLAR_MASS = 60.09
#: Density of quartz, g/cm³ (Carcione et al. 2022, Sect. 6.2).
QUARTZ_DENSITY = 2.65
#: Smallest grain size accepted, mm: a nanometre, below any clay platelet.
MIN_GRAIN_SIZE_MM = 1e-6
#: Largest Walderhaug exponent b accepted, 1/°C: five times Walderhaug's 0.022, and small enough
#: that 10^(bT) stays finite over the whole temperature range of a path.
MAX_RATE_EXPONENT = 0.1


def quartz_cement(path: BurialPath, porosity0, grain_size, quartz_fraction, clay_coating=0.0, *,
                  rate_constant=1.98e-22, rate_exponent=0.022, start_temperature=None):
    r"""Quartz cement volume fraction :math:`\phi_p` at every node of a burial path.

    Walderhaug (1996) precipitation, eqs. B.1–B.6 of Carcione et al. (2022): the rate per unit
    quartz surface is :math:`a\,10^{bT}` (mol cm⁻² s⁻¹, T in °C), the surface of a unit volume
    (:math:`V` = 1 cm³) is :math:`A = A_0 \phi/\phi_0` with
    :math:`A_0 = (1 - \mathcal C)\,6 f V / D` (eqs. B.2, B.5, B.6) and
    :math:`\phi = \phi_0 - \phi_p` (B.4), so

    .. math::

        \frac{d\phi_p}{dt} = \frac{M_q a A_0}{\rho_q \phi_0}(\phi_0 - \phi_p)\,10^{bT(t)}
        \;\Rightarrow\;
        \phi_p(t) = \phi_0\Big[1 - \exp\Big(-\frac{M_q a A_0}{\rho_q \phi_0}
                    \int_0^t 10^{bT}\,dt'\Big)\Big].

    The integral is carried exactly over each linear piece of T(t) (see
    ``burial._integrals.cumulative_power10``), so the result does not depend on the node spacing;
    for a constant heating rate it is eq. B.1 (step by step, the same expression).

    Parameters
    ----------
    path : BurialPath
    porosity0 : float or array_like
        Initial porosity :math:`\phi_0`, in (0, 1).
    grain_size : float or array_like
        Grain diameter :math:`D`, mm, ``>=`` :data:`MIN_GRAIN_SIZE_MM` (0.3 in the worked
        example).
    quartz_fraction : float or array_like
        Fraction :math:`f` of detrital quartz, in [0, 1].
    clay_coating : float or array_like
        Clay-coating factor :math:`\mathcal C`, in [0, 1] (1: no precipitation).
    rate_constant : float or array_like, keyword-only
        :math:`a`, mol cm⁻² s⁻¹, ``> 0``; default 1.98e-22.
    rate_exponent : float or array_like, keyword-only
        :math:`b`, °C⁻¹, in (0, :data:`MAX_RATE_EXPONENT`]; default 0.022.
    start_temperature : float or array_like, keyword-only, optional
        °C below which no cement forms (the integral only counts the hotter parts of the path),
        in [:data:`burial.path.MIN_TEMPERATURE_C`, :data:`burial.path.MAX_TEMPERATURE_C`].

    Every parameter may be an array with one value per path: its shape broadcasts against the
    path's leading axes (e.g. the members of :func:`burial.linear_path` given arrays), and an
    element refused is named by its index (``start_temperature[3]``).

    Returns
    -------
    ndarray, shape of ``path.temperature`` broadcast with the parameters
        :math:`\phi_p`, cm³ of cement per cm³ of rock, in :math:`[0, \phi_0]`.

    Raises
    ------
    ValueError
        Naming the argument: a value that is not real (complex, text, None), NaN, out of its
        range, or parameters whose shapes do not broadcast with each other and the path's
        leading axes.

    Examples
    --------
    The sandstone of Carcione et al. (2022), Sect. 6.2, at 4 km:

    >>> from burial.path import linear_path
    >>> p = linear_path(30.0, 40.0, 15.0, 4000.0, depth_step=1000.0)
    >>> quartz_cement(p, 0.36, 0.3, 0.65).round(4).tolist()
    [0.0, 0.0023, 0.0127, 0.0563, 0.1956]
    """
    if not isinstance(path, BurialPath):
        raise ValueError("path must be a burial.BurialPath (see linear_path, path_from_nodes)")
    phi0 = check_range("porosity0", as_array("porosity0", porosity0), 0.0, 1.0, low_open=True,
                       high_open=True)
    D_cm = check_range("grain_size", as_array("grain_size", grain_size), MIN_GRAIN_SIZE_MM,
                       np.inf, high_open=True) / 10.0
    f = check_range("quartz_fraction", as_array("quartz_fraction", quartz_fraction), 0.0, 1.0)
    C = check_range("clay_coating", as_array("clay_coating", clay_coating), 0.0, 1.0)
    a = member_values("rate_constant", rate_constant, 0.0, np.inf, low_open=True,
                      high_open=True)
    b = member_values("rate_exponent", rate_exponent, 0.0, MAX_RATE_EXPONENT, low_open=True)
    per_path = {"rate_constant": a, "rate_exponent": b}
    if start_temperature is not None:
        start_temperature = member_values("start_temperature", start_temperature,
                                          MIN_TEMPERATURE_C, MAX_TEMPERATURE_C)
        per_path["start_temperature"] = start_temperature
    broadcast(porosity0=phi0, grain_size=D_cm, quartz_fraction=f, clay_coating=C, **per_path,
              **{"path (leading axes)": path.temperature[..., 0]})
    A0 = (1.0 - C) * 6.0 * f / D_cm                                   # cm², V = 1 cm³
    # Extreme but valid inputs (a tiny grain size or porosity0, a huge rate constant, a path of
    # 10^300 Myr) may overflow k or the integral to inf: that is the limit of a pore space filled
    # at once, phi_p = phi0, reached through the exp below; a zero integral or k adds no cement.
    with np.errstate(over="ignore", invalid="ignore"):
        k = np.asarray(QUARTZ_MOLAR_MASS * a * A0 / (QUARTZ_DENSITY * phi0))[..., None]  # 1/s
        integral = cumulative_power10(path.time, path.temperature, b,
                                      start_temperature=start_temperature) * SECONDS_PER_MYR
        x = np.where((k > 0.0) & (integral > 0.0), k * integral, 0.0)
    # phi0 * (1 - exp(-x)) = -phi0 * expm1(-x): accurate for tiny x, exactly < phi0 for any x.
    return -np.asarray(phi0)[..., None] * np.expm1(-x)
