r"""Water, brine, oil and hydrocarbon gas of [BatzleWang1992]_ (see :mod:`rockcem.pore_fluids`
for the units).

Where the sources disagree
--------------------------
The equations below were written from [BatzleWang1992]_; each place where public
implementations (bruges, rockphypy, Equinor's open_petro_elastic and rock-physics-open, rppy, and
MATLAB scripts) read the printed paper differently was settled against independent values, in
``tests/rockcem/test_pore_fluids.py``:

1. **Brine velocity, eq. 29, the S² term.** Printed (and used by rppy and several scripts) as
   :math:`-1820\,S^2`; bruges, rockphypy and Equinor use :math:`-820\,S^2`. Against the NaCl
   sound-speed correlation of [KleisSanchez1990]_ (fitted to measurements, 7–88 °C, up to 21 %
   NaCl) −820 agrees within 0.6 % up to S = 0.2 and −1820 falls 1.7–2.6 % low at S = 0.2;
   −820 also reproduces the brine moduli of the paper's Fig. 14 (4.13 GPa at S = 0.3, 50 °C)
   where −1820 gives 10 % less. **−820 is used.** rppy also writes −9.8 T for −9.6 T in the
   S term (0.2 % at 80 °C, S = 0.2; not resolved by the data): the printed −9.6 is kept; one
   MATLAB script writes −0.476 P² for −0.0476 P² (7 % slower at S = 0.1 and 50 MPa).
2. **Water velocity, eq. 28 / Table 1.** The table is 5 × 4 (T⁰…T⁴ × P⁰…P³), m/s with T in °C
   and P in MPa; two public scripts sum only 4 × 3 terms and one drops the exponent of
   −4.614e−13. All 20 terms are used; the result is within 0.4 % of IAPWS-95 below 100 °C and
   1.4 % to 250 °C (liquid, 5–100 MPa).
3. **Water and brine density, eqs. 27a–b.** All implementations agree on the printed
   coefficients (the 10⁻⁶ factor multiplies the whole bracket); they match IAPWS-95 within
   0.6 % (20–250 °C, 5–100 MPa) and the tabulated NaCl solution densities within 0.5 %.
4. **Gas, eqs. 9–11.** Eq. 10b is read :math:`Z = aP_r + b + c\,d` with
   :math:`d = \exp\{-[0.45 + 8(0.56 - 1/T_r)^2] P_r^{1.2}/T_r\}`; the paper gives no
   :math:`\partial Z/\partial P_r`, which is differentiated analytically here (as in rockphypy,
   rppy and Equinor). At methane's gravity the density and the isothermal modulus match
   Setzmann–Wagner methane within 3 and 4.3 %; but eq. 11b's :math:`\gamma_0` depends on
   :math:`P_r` only and runs from 17 % below to 53 % above methane's :math:`c_p/c_v`
   (15–250 °C, 5–50 MPa), so the adiabatic K differs from methane's by −16 % to +52 % (vp by
   −9 % to +22 %). That is the paper's correlation, kept as printed; for a gas that is mostly
   methane, :func:`methane` is the reference.
5. **Live oil density, eq. 24.** :math:`\rho_G = (\rho_0 + 0.0012GR_G)/B_0` is the density of
   the oil *at saturation*, at its bubble point :math:`P_b` (eq. 21a solved for P): :math:`B_0`
   (eq. 23, Standing's) is the saturated oil's volume factor, and :math:`\rho_G` has no
   pressure term. Equinor and rockphypy use it as is at every pressure (2–5 % below the dead
   oil at 50 MPa as the gas–oil ratio vanishes); rppy adds eq. 18 with :math:`\rho_G` for
   :math:`\rho_0` and then divides by eq. 19 again, counting the thermal expansion twice.
   Here the oil above its bubble point is compressed as its gas-free oil is (B&W give no
   compressibility for the dissolved gas): eq. 18's increment from :math:`P_b` to P,
   :math:`[\rho_P(P) - \rho_P(P_b)]` with :math:`\rho_P` eq. 18 of :math:`\rho_0`, over eq. 19's
   denominator, is added to :math:`\rho_G`. So the density is eq. 24's exactly at the bubble
   point, and tends to the dead oil's (eqs. 18–19, within 0.1 %) as the gas–oil ratio
   vanishes (:math:`P_b \to 0`). The dead oil's increment from 0 to P, used before, counted the
   compression from 0 to :math:`P_b` twice — once inside eq. 24 — and made the live oil
   0.1–3.6 % denser (20–150 °C, 10–100 MPa, :math:`\rho_0` 0.75–0.95, :math:`R_G` 10–200 L/L).
6. **Live oil at vanishing gas–oil ratio.** Eq. 22's pseudo-density tends to
   :math:`\rho_0/B_0`, not :math:`\rho_0`, so eq. 20 with :math:`\rho'` does not tend to the
   dead-oil velocity (the same at 20 °C; 2–3 % lower at 60 °C, 4–7 % at 100 °C, 5–13 % at
   150 °C). Gas–oil ratio 0 uses the dead-oil equations;
   any positive ratio the live ones. Equinor blends the two between 0 and 1 L/L; no blend here.
7. **Eq. 23.** :math:`B_0` is Standing's formation volume factor converted to °C and L/L; the
   exact conversion of Standing's field-unit form gives 2.50 where the paper prints 2.4 for the
   coefficient of :math:`R_G\sqrt{G/\rho_0}`. The printed 2.4 is used (every implementation does).

Eqs. 20a (API) and 20b (density) are the same relation (to 0.1 %): eq. 20b is used for both
``api`` and ``reference_density`` input, with API = 141.5/ρ0 − 131.5.
"""

from __future__ import annotations

import numpy as np

from ..constants import GAS_CONSTANT_J, GPA_PER_MPA, ZERO_CELSIUS_IN_KELVIN
from ..validation import as_array, broadcast, check_range
from ._common import _AIR_MOLAR_MASS, _S_MAX, _T_MAX, KM_PER_M, _finished, _state
from ..validation import FIELD_UNITS, labelled

__all__ = ["water", "brine", "oil", "max_gas_oil_ratio", "bubble_point_pressure", "gas"]


# --- water and brine -----------------------------------------------------------------------------

_W = np.array([[1402.85, 1.524, 3.437e-3, -1.197e-5],
               [4.871, -0.0111, 1.739e-4, -1.628e-6],
               [-0.04783, 2.747e-4, -2.135e-6, 1.237e-8],
               [1.487e-4, -6.503e-7, -1.455e-8, 1.327e-10],
               [-2.197e-7, 7.987e-10, 5.230e-11, -4.614e-13]])   # Table 1, m/s (T °C, P MPa)


def _water_velocity(T, P):
    """Eq. 28 (m/s), nested Horner over T (rows) and P (columns)."""
    out = np.zeros(np.broadcast(T, P).shape)
    for i in range(4, -1, -1):
        row = _W[i, 3]
        for j in range(2, -1, -1):
            row = row * P + _W[i, j]
        out = out * T + row
    return out


def _water_density(T, P):
    """Eq. 27a, g/cm³."""
    return 1.0 + 1e-6 * (-80.0 * T - 3.3 * T**2 + 0.00175 * T**3 + 489.0 * P - 2.0 * T * P
                         + 0.016 * T**2 * P - 1.3e-5 * T**3 * P - 0.333 * P**2
                         - 0.002 * T * P**2)


@labelled(units=FIELD_UNITS)
def brine(temperature, pressure, salinity):
    r"""NaCl brine, eqs. 27–29 of [BatzleWang1992]_ (eq. 29 read with −820 S²; see the module
    notes).

    .. math::

        \rho_B = \rho_W + S\{0.668 + 0.44S + 10^{-6}[300P - 2400PS
                 + T(80 + 3T - 3300S - 13P + 47PS)]\}

        V_B = V_W + S(1170 - 9.6T + 0.055T^2 - 8.5\times10^{-5}T^3 + 2.6P - 0.0029TP
              - 0.0476P^2) + S^{1.5}(780 - 10P + 0.16P^2) - 820S^2

    with :math:`\rho_W` eq. 27a, :math:`V_W = \sum_{i\le4,j\le3} w_{ij}T^iP^j` eq. 28 and
    Table 1 (m/s), and :math:`K = \rho_B V_B^2`.

    Parameters
    ----------
    temperature : float or array_like
        °C, in [0, 350] (the range of the paper's data).
    pressure : float or array_like
        Absolute pressure, MPa, in [0, 150]; fitted to 100 MPa (beyond it eq. 28 errs by 5–40 %
        at 150 MPa). The liquid is assumed: below the saturation pressure (boiling) the result is
        a liquid extrapolation (see :func:`validity_warnings`).
    salinity : float or array_like
        NaCl mass fraction, in [0, 0.35); the paper's figures reach 0.3.

    Returns
    -------
    FluidProperties
        ``K`` GPa, ``rho`` g/cm³, ``vp`` km/s, broadcast over the inputs.

    Examples
    --------
    Fig. 14 of [BatzleWang1992]_: K of a 300 000 ppm brine at 50 °C and 0.1 MPa, 4.13 GPa.

    >>> round(float(brine(50.0, 0.1, 0.3).K), 2)
    4.13
    """
    T, P = _state(temperature, pressure)
    S = check_range("salinity", as_array("salinity", salinity), 0.0, _S_MAX, high_open=True)
    T, P, S = broadcast(temperature=T, pressure=P, salinity=S)
    rho = _water_density(T, P) + S * (0.668 + 0.44 * S + 1e-6 * (
        300.0 * P - 2400.0 * P * S + T * (80.0 + 3.0 * T - 3300.0 * S - 13.0 * P + 47.0 * P * S)))
    v = (_water_velocity(T, P)
         + S * (1170.0 - 9.6 * T + 0.055 * T**2 - 8.5e-5 * T**3 + 2.6 * P - 0.0029 * T * P
                - 0.0476 * P**2)
         + S * np.sqrt(S) * (780.0 - 10.0 * P + 0.16 * P**2) - 820.0 * S**2) * KM_PER_M
    return _finished("brine", rho * v * v, rho, v, "non-physical result at this temperature, "
                     "pressure and salinity")


@labelled(units=FIELD_UNITS)
def water(temperature, pressure):
    """Pure water, eqs. 27a and 28 of [BatzleWang1992]_: :func:`brine` at ``salinity = 0``.

    Parameters
    ----------
    temperature, pressure : float or array_like
        °C in [0, 350] and absolute MPa in [0, 150], as in :func:`brine`.

    Returns
    -------
    FluidProperties

    Examples
    --------
    IAPWS-95 at 20 °C and 0.1 MPa: 0.99821 g/cm³ and 1.4822 km/s (eqs. 27a and 28 give 0.1 %
    less density and the same velocity to 0.05 %).

    >>> w = water(20.0, 0.1)
    >>> round(float(w.rho), 3), round(float(w.vp), 3)
    (0.997, 1.482)
    """
    return brine(temperature, pressure, 0.0)


# --- oil -----------------------------------------------------------------------------------------

def _reference_density(api, reference_density):
    if (api is None) == (reference_density is None):
        raise ValueError("give exactly one of api and reference_density (the oil's gravity)")
    if api is not None:
        api = check_range("api", as_array("api", api), 0.0, 150.0)
        return 141.5 / (api + 131.5)                     # eq. 14
    return check_range("reference_density", as_array("reference_density", reference_density),
                       0.5, 1.076)


def _gas_gravity(name, value):
    return check_range(name, as_array(name, value), 0.5, 2.0)


@labelled(units="1")
def max_gas_oil_ratio(temperature, pressure, *, api=None, reference_density=None,
                      gas_gravity=0.6):
    r"""Largest gas–oil ratio the oil holds in solution at (T, P): eq. 21a of
    [BatzleWang1992]_ (Standing's bubble-point relation),

    .. math:: R_G^{max} = 0.02123\,G\,[P\exp(4.072/\rho_0 - 0.00377\,T)]^{1.205}

    Parameters
    ----------
    temperature, pressure : float or array_like
        °C and absolute MPa, as in :func:`oil`.
    api, reference_density, gas_gravity
        As in :func:`oil`.

    Returns
    -------
    ndarray
        L/L (litres of gas at 15.6 °C and 0.1 MPa per litre of oil).
    """
    T, P = _state(temperature, pressure)
    rho0 = _reference_density(api, reference_density)
    G = _gas_gravity("gas_gravity", gas_gravity)
    T, P, rho0, G = broadcast(temperature=T, pressure=P, reference_density=rho0, gas_gravity=G)
    return _max_gas_oil_ratio(T, P, rho0, G)


def _max_gas_oil_ratio(T, P, rho0, G):
    """Eq. 21a, L/L."""
    return 0.02123 * G * (P * np.exp(4.072 / rho0 - 0.00377 * T)) ** 1.205


@labelled(units="MPa")
def bubble_point_pressure(temperature, gas_oil_ratio, *, api=None, reference_density=None,
                          gas_gravity=0.6):
    """Pressure (MPa) below which gas leaves solution: eq. 21a solved for P.

    Parameters
    ----------
    temperature : float or array_like
        °C, in [0, 350].
    gas_oil_ratio : float or array_like
        L/L, in [0, 1e4].
    api, reference_density, gas_gravity
        As in :func:`oil`.

    Returns
    -------
    ndarray
        Bubble-point pressure, absolute MPa.

    Examples
    --------
    Standing's example (1947): 350 ft³/bbl of 0.75-gravity gas in a 30 °API oil at 200 °F has
    its bubble point at 1930 psia (13.3 MPa); the rounded eq. 21a gives 2 % less.

    >>> round(float(bubble_point_pressure(93.33, 62.34, api=30.0, gas_gravity=0.75)), 1)
    13.1
    """
    T = check_range("temperature", as_array("temperature", temperature), 0.0, _T_MAX)
    R = check_range("gas_oil_ratio", as_array("gas_oil_ratio", gas_oil_ratio), 0.0, 1e4)
    rho0 = _reference_density(api, reference_density)
    G = _gas_gravity("gas_gravity", gas_gravity)
    T, R, rho0, G = broadcast(temperature=T, gas_oil_ratio=R, reference_density=rho0,
                              gas_gravity=G)
    return _bubble_point(T, R, rho0, G)


def _bubble_point(T, R, rho0, G):
    """Eq. 21a solved for P, MPa."""
    return (R / (0.02123 * G)) ** (1.0 / 1.205) / np.exp(4.072 / rho0 - 0.00377 * T)


def _oil_velocity(rho, T, P):
    """Eq. 20b, m/s, with ``rho`` the reference density (dead) or pseudo-density (live)."""
    return (2096.0 * np.sqrt(rho / (2.6 - rho)) - 3.7 * T + 4.64 * P
            + 0.0115 * (4.12 * np.sqrt(1.08 / rho - 1.0) - 1.0) * T * P)


def _compressed(rho, P):
    """Eq. 18: the density ``rho`` (at 0.1 MPa) at pressure P."""
    return rho + (0.00277 * P - 1.71e-7 * P**3) * (rho - 1.15) ** 2 + 3.49e-4 * P


@labelled(units=FIELD_UNITS)
def oil(temperature, pressure, *, api=None, reference_density=None, gas_oil_ratio=0.0,
        gas_gravity=0.6):
    r"""Dead or live oil, eqs. 18–24 of [BatzleWang1992]_.

    Dead oil (``gas_oil_ratio = 0``): eq. 18 (pressure), eq. 19 (temperature,
    :math:`\rho = \rho_P / [0.972 + 3.81\times10^{-4}(T + 17.78)^{1.175}]`) and eq. 20b
    (velocity, m/s),

    .. math::

        V = 2096\sqrt{\rho_0/(2.6-\rho_0)} - 3.7T + 4.64P
            + 0.0115\,[4.12\sqrt{1.08/\rho_0 - 1} - 1]\,TP

    Live oil (``gas_oil_ratio`` :math:`R_G > 0`): eq. 23 :math:`B_0 = 0.972 + 0.00038
    [2.4R_G\sqrt{G/\rho_0} + T + 17.8]^{1.175}`, the velocity of eq. 20b with the
    pseudo-density :math:`\rho' = \rho_0 / [B_0 (1 + 0.001R_G)]` (eq. 22) for :math:`\rho_0`, and
    the density of eq. 24, :math:`\rho_G = (\rho_0 + 0.0012GR_G)/B_0` (at the bubble point
    :math:`P_b`, eq. 21a), plus the dead oil's compression from :math:`P_b` to P,
    :math:`[\rho_P(P) - \rho_P(P_b)] / [0.972 + 3.81\times10^{-4}(T + 17.78)^{1.175}]` with
    :math:`\rho_P` eq. 18 of :math:`\rho_0` (module notes 5–6). :math:`K = \rho V^2`.

    Below the bubble point: B&W assume all the gas in solution, which holds only where
    :math:`R_G \le R_G^{max}(T, P)` (eq. 21a, :func:`max_gas_oil_ratio`). Where the given ratio
    exceeds it, free gas would form and the pore fluid would be oil *and* gas — a two-phase
    mixture this function does not model. It therefore raises ``ValueError`` (naming
    ``gas_oil_ratio``) rather than return the saturated oil, which would silently drop the free
    gas that dominates the mixture's modulus. For a saturated oil pass
    ``np.minimum(gas_oil_ratio, max_gas_oil_ratio(...))`` and mix the liberated gas
    (:func:`gas`) with :func:`wood` or :func:`brie`.

    Parameters
    ----------
    temperature : float or array_like
        °C, in [0, 350] (velocity must stay positive: a light oil at high temperature and low
        pressure is refused).
    pressure : float or array_like
        Absolute MPa, in [0, 150]; eq. 18 stops increasing near 100 MPa.
    api, reference_density : float or array_like, keyword-only
        Exactly one: API gravity in [0, 150], or the density at 15.6 °C and 0.1 MPa,
        :math:`\rho_0`, g/cm³ in [0.5, 1.076] (eq. 20b needs :math:`\rho < 1.08`). Fitted on
        0.70–1.00 g/cm³.
    gas_oil_ratio : float or array_like, keyword-only
        :math:`R_G`, L/L, ``>= 0``, at most :func:`max_gas_oil_ratio`.
    gas_gravity : float or array_like, keyword-only
        Gravity of the dissolved gas, in [0.5, 2]; default 0.6, a typical associated gas.

    Returns
    -------
    FluidProperties

    Examples
    --------
    Fig. 7 of [BatzleWang1992]_: a dead oil of 0.88 g/cm³ (29 °API) at 100 °C and 0.1 MPa,
    about 1.05 GPa (1.045 as read from the figure in open_petro_elastic's tests).

    >>> round(float(oil(100.0, 0.1, reference_density=0.88).K), 2)
    1.04
    """
    T, P = _state(temperature, pressure)
    rho0 = _reference_density(api, reference_density)
    R = check_range("gas_oil_ratio", as_array("gas_oil_ratio", gas_oil_ratio), 0.0, 1e4)
    G = _gas_gravity("gas_gravity", gas_gravity)
    T, P, rho0, R, G = broadcast(temperature=T, pressure=P, reference_density=rho0,
                                 gas_oil_ratio=R, gas_gravity=G)
    r_max = _max_gas_oil_ratio(T, P, rho0, G)
    if np.any(R > r_max * (1.0 + 1e-12)):
        k = np.flatnonzero((R > r_max * (1.0 + 1e-12)).ravel())[0]
        raise ValueError(
            f"gas_oil_ratio {R.flat[k]:g} L/L exceeds the {r_max.flat[k]:.4g} L/L the oil holds "
            f"in solution at {T.flat[k]:g} °C and {P.flat[k]:g} MPa (below the bubble point, "
            "eq. 21a of Batzle & Wang 1992): free gas would form; cap it with "
            "max_gas_oil_ratio() and mix the gas explicitly")
    live = R > 0.0
    B0 = 0.972 + 0.00038 * (2.4 * R * np.sqrt(G / rho0) + T + 17.8) ** 1.175      # eq. 23
    rho_pseudo = np.where(live, rho0 / (B0 * (1.0 + 0.001 * R)), rho0)             # eq. 22
    thermal = 0.972 + 3.81e-4 * (T + 17.78) ** 1.175                                # eq. 19
    rho_dead = _compressed(rho0, P) / thermal
    # Eq. 24 is the density at the bubble point P_b (eq. 21a solved for P); above it the oil is
    # compressed as its gas-free oil is, from P_b to P (eq. 18's increment, over eq. 19).
    P_b = np.minimum(np.where(live, _bubble_point(T, R, rho0, G), 0.0), P)
    rho_live = ((rho0 + 0.0012 * G * R) / B0
                + (_compressed(rho0, P) - _compressed(rho0, P_b)) / thermal)
    rho = np.where(live, rho_live, rho_dead)
    v = _oil_velocity(rho_pseudo, T, P) * KM_PER_M
    return _finished("oil", rho * v * v, rho, v, "temperature too high for this light an oil at "
                     "this pressure (eq. 20 gives a velocity <= 0)")


# --- hydrocarbon gas -----------------------------------------------------------------------------

@labelled(units=FIELD_UNITS)
def gas(temperature, pressure, gravity):
    r"""Hydrocarbon gas, eqs. 9–11 of [BatzleWang1992]_ (after Thomas et al. 1970).

    .. math::

        P_r = \frac{P}{4.892 - 0.4048G}, \quad T_r = \frac{T_a}{94.72 + 170.75G}, \quad
        \rho = \frac{28.8\,G\,P}{Z R T_a}, \quad
        K = \frac{P\,\gamma_0}{1 - \frac{P_r}{Z}\frac{\partial Z}{\partial P_r}}

        Z = [0.03 + 0.00527(3.5 - T_r)^3]P_r + (0.642T_r - 0.007T_r^4 - 0.52)
            + 0.109(3.85 - T_r)^2 \exp\{-[0.45 + 8(0.56 - 1/T_r)^2] P_r^{1.2}/T_r\}

        \gamma_0 = 0.85 + \frac{5.6}{P_r + 2} + \frac{27.1}{(P_r + 3.5)^2}
                   - 8.7\exp[-0.65(P_r + 1)]

    (eqs. 9a–b, 10a–b, 11a–b; :math:`T_a` in K, ∂Z/∂P_r analytic, K converted from MPa by
    :data:`rockcem.constants.GPA_PER_MPA`). ``vp`` is :math:`\sqrt{K/\rho}` with P cancelled,
    so it is finite at zero pressure (the ideal-gas sound speed).

    Parameters
    ----------
    temperature : float or array_like
        °C, above −273.15 and up to 350. Below the pseudo-critical temperature
        (:math:`T_r < 1`) the gas may be liquid; where the correlation then turns non-physical
        (negative Z or compressibility) a ``ValueError`` names ``temperature``.
    pressure : float or array_like
        Absolute MPa, in [0, 150]; the paper's figures reach 50 MPa.
    gravity : float or array_like
        Gas gravity (molar mass / 28.8 g/mol), in [0.5, 2]; methane is 0.554.

    Returns
    -------
    FluidProperties

    Examples
    --------
    Figs. 2–3 of [BatzleWang1992]_, G = 0.6 at 50 °C and 25 MPa: 0.18 g/cm³ and 57 MPa (as
    read in open_petro_elastic's tests).

    >>> g = gas(50.0, 25.0, 0.6)
    >>> round(float(g.rho), 2), round(float(g.K) * 1000)
    (0.18, 57)
    """
    T, P = _state(temperature, pressure, t_min=-ZERO_CELSIUS_IN_KELVIN)
    if np.any(T <= -ZERO_CELSIUS_IN_KELVIN):
        raise ValueError("temperature must be above absolute zero (-273.15 °C)")
    G = _gas_gravity("gravity", gravity)
    T, P, G = broadcast(temperature=T, pressure=P, gravity=G)
    Ta = T + ZERO_CELSIUS_IN_KELVIN
    Pr = P / (4.892 - 0.4048 * G)
    Tr = Ta / (94.72 + 170.75 * G)
    a = 0.03 + 0.00527 * (3.5 - Tr) ** 3
    c = 0.109 * (3.85 - Tr) ** 2
    q = (0.45 + 8.0 * (0.56 - 1.0 / Tr) ** 2) / Tr
    d = np.exp(-q * Pr**1.2)
    Z = a * Pr + (0.642 * Tr - 0.007 * Tr**4 - 0.52) + c * d
    dZ = a - 1.2 * c * q * Pr**0.2 * d
    gamma0 = 0.85 + 5.6 / (Pr + 2.0) + 27.1 / (Pr + 3.5) ** 2 - 8.7 * np.exp(-0.65 * (Pr + 1.0))
    if np.any(Z <= 0.0):
        raise ValueError("temperature too low for this gravity: the gas correlation gives Z <= 0 "
                         f"(pseudo-reduced temperature {Tr[Z <= 0.0].flat[0]:.3g}; it is fitted "
                         "for a gas, T_r >= 1)")
    denom = 1.0 - Pr / Z * dZ
    if np.any(denom <= 0.0):
        raise ValueError("temperature too low for this gravity: the gas correlation gives a "
                         "non-positive compressibility (pseudo-reduced temperature "
                         f"{Tr[denom <= 0.0].flat[0]:.3g}; it is fitted for a gas, T_r >= 1)")
    rho = _AIR_MOLAR_MASS * G * P / (Z * GAS_CONSTANT_J * Ta)
    K = gamma0 * P / denom * GPA_PER_MPA
    # vp^2 = K/rho with P cancelled: 1e-3 km^2/s^2 per J/g (R T / M in J/g).
    vp = np.sqrt(GPA_PER_MPA * gamma0 * Z * GAS_CONSTANT_J * Ta / (_AIR_MOLAR_MASS * G * denom))
    return _finished("gas", K, rho, vp, "non-physical result at this temperature, pressure and "
                     "gravity")
