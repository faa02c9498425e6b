"""What the pore-fluid modules share: the result type, units, domains and checks."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..constants import KM_PER_M, STANDARD_ATMOSPHERE  # noqa: F401  (the package's units)
from ..validation import as_array, check_range

_PA_PER_MPA = 1.0e6
_G_CM3_PER_KG_M3 = 1.0e-3
#: Molar mass of air, g/mol, as in eq. 10a (28.8 G is the gas's molar mass).
_AIR_MOLAR_MASS = 28.8
_HINT = "pip install 'rockcem[fluids]'"

# Hard domains (ValueError outside): where the formulas stay defined, finite and positive.
_T_MAX = 350.0           # °C: the paper's data and figures end here; eq. 28 turns negative
_P_MAX = 150.0           # MPa: beyond 100 MPa eq. 28 diverges (negative near 350 °C, 200 MPa)
_S_MAX = 0.35            # NaCl mass fraction, open
# Calibration ranges (validity_warnings), from the paper's data and figures.
_P_FIT, _S_FIT = 100.0, 0.30
_RHO0_FIT = (0.70, 1.00)                 # API 70 to 10
_GAS_GRAVITY_FIT = (0.55, 1.8)


class FluidProperties(NamedTuple):
    """Bulk modulus ``K`` (GPa), density ``rho`` (g/cm³) and P-wave velocity ``vp`` (km/s)."""

    K: np.ndarray
    rho: np.ndarray
    vp: np.ndarray


def _state(temperature, pressure, *, t_min=0.0):
    T = check_range("temperature", as_array("temperature", temperature), t_min, _T_MAX)
    P = check_range("pressure", as_array("pressure", pressure), 0.0, _P_MAX)
    return T, P


def _finished(name, K, rho, vp, reason):
    """Refuse non-physical output (a correlation used far outside its range)."""
    bad = ~(np.isfinite(K) & np.isfinite(vp) & (K >= 0.0) & (rho >= 0.0) & (vp >= 0.0))
    if np.any(bad):
        raise ValueError(f"{name}: {reason}")
    return FluidProperties(*(np.asarray(x, dtype=float) for x in (K, rho, vp)))
