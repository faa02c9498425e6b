"""Carbon dioxide and methane from reference equations of state ([SpanWagner1996]_,
[SetzmannWagner1991]_) through CoolProp, the optional ``fluids`` extra."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..constants import ZERO_CELSIUS_IN_KELVIN
from ..validation import as_array, broadcast, check_range
from ._common import _G_CM3_PER_KG_M3, _HINT, _PA_PER_MPA, KM_PER_M, _finished
from ..validation import FIELD_UNITS, labelled

__all__ = ["co2", "methane"]


# --- reference equations of state (CoolProp) -----------------------------------------------------

class _Eos(NamedTuple):
    fluid: str          # CoolProp's name
    source: str         # the equation of state, as the messages name it
    t_max_k: float      # upper temperature of its stated range of validity, K
    p_max: float        # upper pressure of its stated range of validity, MPa


#: The stated ranges of validity: [SpanWagner1996]_, "from the triple-point temperature to
#: 1100 K at pressures up to 800 MPa" (their title); [SetzmannWagner1991]_, from the melting
#: line to 625 K at pressures up to 1000 MPa. The lower ends (triple point, melting line) are
#: CoolProp's own refusals.
_EOS = {"co2": _Eos("CO2", "Span–Wagner", 1100.0, 800.0),
        "methane": _Eos("Methane", "Setzmann–Wagner", 625.0, 1000.0)}
#: Beyond its stated range an equation of state is extrapolated: computed, and reported by
#: :func:`rockcem.pore_fluids.validity_warnings`, up to half as far again as the stated upper
#: bound (temperature in kelvin, pressure in MPa) — the allowance the package gives
#: Batzle & Wang's pressure, fitted to 100 MPa and computed with a warning to 150 — and refused
#: beyond, where the number would not be the fluid's property.
_EXTRAPOLATION = 1.5


def _limits(name):
    """Stated (validity) and refused (hard) upper bounds: T in °C, P in MPa."""
    e = _EOS[name]
    return (e.t_max_k - ZERO_CELSIUS_IN_KELVIN, e.p_max,
            _EXTRAPOLATION * e.t_max_k - ZERO_CELSIUS_IN_KELVIN, _EXTRAPOLATION * e.p_max)


def _coolprop_problem():
    """Why CoolProp cannot be used here, in one line, or ``None`` if it imports.

    Tells an absent CoolProp (install the ``fluids`` extra) from a broken install, one that
    :func:`importlib.util.find_spec` finds but whose import fails (reinstall it), which the first
    advice would not mend.
    """
    try:
        import CoolProp.CoolProp  # noqa: F401
    except Exception as err:        # a broken build raises what it raises (OSError, ...)
        import importlib.util

        try:
            spec = importlib.util.find_spec("CoolProp")
        except (ImportError, ValueError):
            spec = None
        if spec is None:
            return f"CoolProp (reference equations of state) is not installed: {_HINT}"
        where = spec.submodule_search_locations or [spec.origin]
        where = f" at {where[0]}" if where and where[0] else ""
        return (f"CoolProp is installed{where} but fails to import ({type(err).__name__}: "
                f"{err}); reinstall it: pip install --force-reinstall 'CoolProp>=6.6'")
    return None


def _coolprop(name, temperature, pressure):
    eos = _EOS[name]
    t_valid, p_valid, t_hard, p_hard = _limits(name)
    T = check_range("temperature", as_array("temperature", temperature),
                    -ZERO_CELSIUS_IN_KELVIN, np.inf, low_open=True)
    P = check_range("pressure", as_array("pressure", pressure), 0.0, np.inf, low_open=True)
    T, P = broadcast(temperature=T, pressure=P)
    for label, x, valid, hard, unit in (("temperature", T, t_valid, t_hard, "°C"),
                                        ("pressure", P, p_valid, p_hard, "MPa")):
        if np.any(x > hard):
            raise ValueError(
                f"{name}: {label} must be at most {hard:.6g} {unit}, half as far again as the "
                f"{valid:.6g} {unit} to which {eos.source}'s equation of state is stated valid "
                f"(between the two it is extrapolated, with a validity warning); got "
                f"{np.max(x):g} {unit}")
    problem = _coolprop_problem()
    if problem is not None:
        raise ImportError(f"{name}() needs CoolProp: {problem}")
    import CoolProp.CoolProp as CP

    state = CP.AbstractState("HEOS", eos.fluid)
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
    from the triple point (−56.6 °C) to 1100 K (826.85 °C) and 800 MPa. Above 1100 K the
    equation is extrapolated: computed, and reported by
    :func:`~rockcem.pore_fluids.validity_warnings`, to 1650 K (1376.85 °C), half as far again;
    hotter is refused (``ValueError`` naming ``temperature``), as the Batzle–Wang functions
    refuse what lies beyond their extrapolation. States CoolProp refuses (below the triple
    point or the melting line, above about 823 MPa) are reported as ``ValueError``.
    Needs the optional extra: ``pip install 'rockcem[fluids]'``; without CoolProp, or with an
    install that fails to import, ``ImportError`` says which.

    Parameters
    ----------
    temperature : float or array_like
        °C, above −273.15 and at most 1376.85 (1650 K).
    pressure : float or array_like
        Absolute pressure, MPa, ``> 0``; at most 800 (the stated range; CoolProp refuses
        above the melting line's last pressure, about 823 MPa).

    Returns
    -------
    FluidProperties

    Examples
    --------
    NIST Chemistry WebBook (Span–Wagner), 50 °C and 20 MPa: 784.29 kg/m³.

    >>> round(float(co2(50.0, 20.0).rho), 4)
    0.7843
    """
    return _coolprop("co2", temperature, pressure)


@labelled(units=FIELD_UNITS)
def methane(temperature, pressure):
    """Methane from the Setzmann–Wagner equation of state ([SetzmannWagner1991]_) via CoolProp.

    As :func:`co2`. Setzmann–Wagner's stated range runs from the melting line (triple point
    −182.46 °C) to 625 K (351.85 °C) and 1000 MPa; beyond it the equation is extrapolated,
    computed and reported by :func:`~rockcem.pore_fluids.validity_warnings`, to 937.5 K
    (664.35 °C) and 1500 MPa, and refused (``ValueError`` naming ``temperature`` or ``pressure``) beyond that.

    Parameters
    ----------
    temperature : float or array_like
        °C, above −273.15 and at most 664.35 (937.5 K).
    pressure : float or array_like
        Absolute pressure, MPa, ``> 0`` and at most 1500.

    Returns
    -------
    FluidProperties

    Examples
    --------
    At 15 °C and 0.101325 MPa methane is nearly ideal: 0.6785 kg/m³ × 1/Z (Z = 0.998).

    >>> round(float(methane(15.0, 0.101325).rho) * 1000, 3)
    0.68
    """
    return _coolprop("methane", temperature, pressure)
