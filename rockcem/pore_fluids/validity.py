"""Where a pore fluid is computed outside the range its source was fitted to."""

from __future__ import annotations

import numpy as np

from ..constants import ZERO_CELSIUS_IN_KELVIN
from ..validation import as_array, broadcast
from ._common import _GAS_GRAVITY_FIT, _P_FIT, _RHO0_FIT, _S_FIT
from .batzle_wang import _reference_density
from .reference import _limits as _eos_limits

__all__ = ["validity_warnings"]


# --- validity --------------------------------------------------------------------------------

def _saturation_pressure(T):
    """Vapour pressure of water, MPa (eq. 30 of [IAPWS1997]_, region 4), T in °C, 0–373.9 °C."""
    n = (0.11670521452767e4, -0.72421316703206e6, -0.17073846940092e2, 0.12020824702470e5,
         -0.32325550322333e7, 0.14915108613530e2, -0.48232657361591e4, 0.40511340542057e6,
         -0.23855557567849, 0.65017534844798e3)
    Tk = np.minimum(np.asarray(T, dtype=float), 373.9) + ZERO_CELSIUS_IN_KELVIN
    v = Tk + n[8] / (Tk - n[9])
    A = v * v + n[0] * v + n[1]
    B = n[2] * v * v + n[3] * v + n[4]
    C = n[5] * v * v + n[6] * v + n[7]
    return (2.0 * C / (-B + np.sqrt(B * B - 4.0 * A * C))) ** 4


def _where(mask, depth, T, P):
    """Where a rule applies: a depth interval if depths are given, else the (T, P) span."""
    from ..validity import _interval

    mask = np.asarray(mask, dtype=bool)
    if depth is not None:                   # as the rock's warnings write it
        return _interval(np.broadcast_to(np.asarray(depth, dtype=float), mask.shape), mask)
    t, p = T[mask], P[mask]
    return f"{_span(t)} °C, {_span(p)} MPa"


def _span(x):
    """``min–max``, or the one value where they are equal."""
    lo, hi = f"{x.min():.4g}", f"{x.max():.4g}"
    return lo if lo == hi else f"{lo}–{hi}"


def validity_warnings(fluid, temperature, pressure, *, salinity=0.0, gravity=0.6,
                      reference_density=None, api=None, depth=None) -> list[str]:
    """Lines that say where a pore fluid is computed outside the range its source supports.

    The results there are computed all the same (as the sources prescribe); these lines,
    written like those of :func:`rockcem.validity.validity_warnings`, tell the scene where not
    to read them as the fluid's properties. Rules, by ``fluid``:

    (Temperatures above 350 °C and pressures above 150 MPa are refused by the B&W functions.)

    - ``"water"``, ``"brine"``: pressure above 100 MPa (the data [BatzleWang1992]_ fitted;
      eq. 28 errs by 5–40 % at 150 MPa), salinity above 0.3 (the
      paper's Fig. 14), and pressure below the vapour pressure of water (IAPWS-IF97), where the
      water boils and the liquid correlation is extrapolated.
    - ``"oil"``: pressure above 100 MPa (eq. 18 turns over), a
      reference density outside 0.70–1.00 g/cm³ (API 70–10).
    - ``"gas"``: gravity outside 0.55–1.8 (this module's bracket: methane to a rich gas; the
      paper shows 0.6 and 1.2), pressure above 100 MPa (the paper's figures reach 50), a
      pseudo-reduced temperature below 1 (the gas may be liquid), and pseudo-reduced temperature
      and pressure both within 0.1 of 1, where B&W say the approximation fails.
    - ``"co2"``, ``"methane"``: temperature or pressure above the equation of state's stated
      range (Span–Wagner: 1100 K, 800 MPa; Setzmann–Wagner: 625 K, 1000 MPa), where it is
      extrapolated (:func:`co2` and :func:`methane` refuse what lies half as far again beyond);
      and within 3 °C and 1 MPa of the critical point, where the modulus changes steeply with
      temperature and pressure (the equation of state holds; the inputs' errors matter).

    Parameters
    ----------
    fluid : str
        ``"water"``, ``"brine"``, ``"oil"``, ``"gas"``, ``"co2"`` or ``"methane"``.
    temperature, pressure : array_like
        °C and absolute MPa.
    salinity, gravity, reference_density, api : optional
        As in :func:`brine`, :func:`gas` and :func:`oil` (the oil's gravity, one or neither).
    depth : array_like, optional
        Depths (m) of the points, to report intervals as :mod:`rockcem.validity` does.

    Returns
    -------
    list of str
        One line per rule that applies somewhere; empty if none.

    Examples
    --------
    >>> validity_warnings("brine", [100.0, 200.0], [30.0, 120.0], depth=[3000.0, 6000.0])[0][:48]
    'brine (Batzle & Wang 1992) at 6000 m: pressure a'
    """
    T, P = broadcast(temperature=as_array("temperature", temperature),
                     pressure=as_array("pressure", pressure))
    src = {"water": "water (Batzle & Wang 1992)", "brine": "brine (Batzle & Wang 1992)",
           "oil": "oil (Batzle & Wang 1992)", "gas": "gas (Batzle & Wang 1992)",
           "co2": "CO2 (Span–Wagner)", "methane": "methane (Setzmann–Wagner)"}
    if fluid not in src:
        raise ValueError(f"unknown fluid {fluid!r} (known: {', '.join(src)})")
    rules = []
    if fluid in ("water", "brine", "oil"):
        rules.append((P > _P_FIT, f"pressure above {_P_FIT:g} MPa, beyond the fitted data"))
    if fluid in ("water", "brine"):
        S = np.broadcast_to(as_array("salinity", salinity), T.shape)
        rules += [(S > _S_FIT, f"salinity above {_S_FIT:g}, beyond the paper's figures"),
                  ((T > 0.0) & (P < _saturation_pressure(T)),
                   ("pressure below the vapour pressure of water: it boils there, and the "
                    "liquid correlation is extrapolated"))]
    if fluid == "oil" and (api is not None or reference_density is not None):
        rho0 = np.broadcast_to(_reference_density(api, reference_density), T.shape)
        rules.append(((rho0 < _RHO0_FIT[0]) | (rho0 > _RHO0_FIT[1]),
                      (f"reference density outside {_RHO0_FIT[0]:g}–{_RHO0_FIT[1]:g} g/cm3 "
                       "(API 70–10), beyond the fitted oils")))
    if fluid == "gas":
        G = np.broadcast_to(as_array("gravity", gravity), T.shape)
        Tr = (T + ZERO_CELSIUS_IN_KELVIN) / (94.72 + 170.75 * G)
        Pr = P / (4.892 - 0.4048 * G)
        rules += [((G < _GAS_GRAVITY_FIT[0]) | (G > _GAS_GRAVITY_FIT[1]),
                   f"gravity outside {_GAS_GRAVITY_FIT[0]:g}–{_GAS_GRAVITY_FIT[1]:g}"),
                  (P > _P_FIT, f"pressure above {_P_FIT:g} MPa (the paper's figures reach 50)"),
                  (Tr < 1.0, "below the pseudo-critical temperature: the gas may be liquid"),
                  ((np.abs(Tr - 1.0) <= 0.1) & (np.abs(Pr - 1.0) <= 0.1),
                   ("pseudo-reduced temperature and pressure both within 0.1 of 1, where the "
                    "approximation fails"))]
    if fluid in ("co2", "methane"):
        t_valid, p_valid, _, _ = _eos_limits(fluid)
        rules += [(T > t_valid, (f"temperature above {t_valid:.6g} °C, the end of the equation "
                                 "of state's stated range: extrapolated")),
                  (P > p_valid, (f"pressure above {p_valid:g} MPa, the end of the equation of "
                                 "state's stated range: extrapolated"))]
        Tc, Pc = (30.978, 7.3773) if fluid == "co2" else (-82.586, 4.5992)
        rules.append(((np.abs(T - Tc) <= 3.0) & (np.abs(P - Pc) <= 1.0),
                      (f"near the critical point ({Tc:g} °C, {Pc:g} MPa): the modulus "
                       "changes steeply with temperature and pressure")))
    return [f"{src[fluid]} at {_where(mask, depth, T, P)}: {text}"
            for mask, text in rules if np.any(mask)]
