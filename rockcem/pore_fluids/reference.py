"""Carbon dioxide and methane from reference equations of state ([SpanWagner1996]_,
[SetzmannWagner1991]_) through CoolProp, the optional ``fluids`` extra."""

from __future__ import annotations

import numpy as np

from ..constants import ZERO_CELSIUS_IN_KELVIN
from ..validation import as_array, broadcast, check_range
from ._common import _G_CM3_PER_KG_M3, _HINT, _PA_PER_MPA, KM_PER_M, _finished
from ..validation import FIELD_UNITS, labelled

__all__ = ["co2", "methane"]


# --- reference equations of state (CoolProp) -----------------------------------------------------

def _coolprop(name, fluid, temperature, pressure):
    T = check_range("temperature", as_array("temperature", temperature),
                    -ZERO_CELSIUS_IN_KELVIN, 1e4, low_open=True)
    P = check_range("pressure", as_array("pressure", pressure), 0.0, 1e4, low_open=True)
    T, P = broadcast(temperature=T, pressure=P)
    try:
        import CoolProp.CoolProp as CP
    except ImportError:
        raise ImportError(f"{name}() needs CoolProp (reference equations of state): "
                          f"{_HINT}") from None
    state = CP.AbstractState("HEOS", fluid)
    rho = np.empty(T.shape)
    c = np.empty(T.shape)
    for k, (t, p) in enumerate(zip(T.flat, P.flat)):
        try:
            state.update(CP.PT_INPUTS, p * _PA_PER_MPA, t + ZERO_CELSIUS_IN_KELVIN)
            rho.flat[k], c.flat[k] = state.rhomass(), state.speed_sound()
        except ValueError as err:
            raise ValueError(f"{name}: no state at temperature {t:g} °C, pressure {p:g} MPa "
                             f"(outside the equation of state: {err})") from None
    rho = rho * _G_CM3_PER_KG_M3
    vp = c * KM_PER_M
    return _finished(name, rho * vp * vp, rho, vp, "the equation of state returned no finite "
                     "state at this temperature and pressure")


@labelled(units=FIELD_UNITS)
def co2(temperature, pressure):
    """Carbon dioxide from the Span–Wagner equation of state ([SpanWagner1996]_) via CoolProp.

    Density (PropsSI ``'D'``) and speed of sound (``'A'``), ``K = rho vp^2`` (the adiabatic
    modulus). Gas, liquid or supercritical as the state is. Span–Wagner's stated range runs
    from the triple point (−56.6 °C) to 1100 K and 800 MPa; states CoolProp refuses are
    reported as ``ValueError``.
    Needs the optional extra: ``pip install 'rockcem[fluids]'``.

    Parameters
    ----------
    temperature : float or array_like
        °C.
    pressure : float or array_like
        Absolute pressure, MPa, ``> 0``.

    Returns
    -------
    FluidProperties

    Examples
    --------
    NIST Chemistry WebBook (Span–Wagner), 50 °C and 20 MPa: 784.29 kg/m³.

    >>> round(float(co2(50.0, 20.0).rho), 4)
    0.7843
    """
    return _coolprop("co2", "CO2", temperature, pressure)


@labelled(units=FIELD_UNITS)
def methane(temperature, pressure):
    """Methane from the Setzmann–Wagner equation of state ([SetzmannWagner1991]_) via CoolProp.

    As :func:`co2` (valid from the triple point, −182.5 °C, to 625 K and 1000 MPa).

    Parameters
    ----------
    temperature : float or array_like
        °C.
    pressure : float or array_like
        Absolute pressure, MPa, ``> 0``.

    Returns
    -------
    FluidProperties

    Examples
    --------
    At 15 °C and 0.101325 MPa methane is nearly ideal: 0.6785 kg/m³ × 1/Z (Z = 0.998).

    >>> round(float(methane(15.0, 0.101325).rho) * 1000, 3)
    0.68
    """
    return _coolprop("methane", "Methane", temperature, pressure)
