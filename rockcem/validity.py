r"""Where a scene applies a model outside the range its source supports: one line of text each.

The scene runner writes these lines into the Dataset (global attribute ``validity_warnings``,
lines joined by newlines) and ``rockcem run`` prints them under its summary. The results there
are still computed as the sources prescribe; the lines say where not to read them as a rock's
properties.

Rules (each returns the depth interval where it applies):

- Krief's dry frame (Models 1 and 3, eq. 3 of [Carcione2022]_) is an empirical fit to
  consolidated rocks, with no dependence on effective pressure ([Krief1990]_). At the depositional
  porosity it keeps :math:`(1-\phi)^{3/(1-\phi)}` = 12 % of the mineral moduli at
  :math:`\phi = 0.36`, where a loose pack at a few MPa has contact moduli two orders of
  magnitude smaller (Hertz–Mindlin), so near the surface these models give a loose sand the
  velocities of a rock (Vp ≈ 2.75 km/s, Vp/Vs ≈ 1.8 in the sandstone example). Flagged where the
  porosity exceeds :data:`KRIEF_LOOSE_FRACTION` of the depositional porosity — this project's
  threshold for "still loose", not a number of the source. Checked against an independent
  measure (``tests/rockcem/test_validity.py``): over the interval it flags in the sandstone
  example (0–1400 m at a 100 m step) the sand holds less than 0.5 % cement, yet Krief's dry
  shear modulus exceeds that of the stiff-sand model — the stiffest uncemented pack at the
  depth's effective pressure ([Mavko2009]_ Sect. 7.9, :func:`rockcem.granular.stiff_sand`) —
  by a factor of 1.4 at its base and 3.8 at 100 m.
- Walderhaug's quartz-cement kinetics (eq. B.1 of [Carcione2022]_) has no limit at the pore
  space. Where it would overfill the intergranular volume the cement is capped there and the
  porosity is 0 (:func:`burial.sandstone_porosity`); flagged over that depth interval.
"""

from __future__ import annotations

import numpy as np

__all__ = ["KRIEF_LOOSE_FRACTION", "KRIEF_MODELS", "validity_warnings"]

#: Porosity above this fraction of the depositional porosity counts as loose (unconsolidated)
#: for the Krief-based models.
KRIEF_LOOSE_FRACTION = 0.9
#: Model labels whose dry frame is Krief's relation.
KRIEF_MODELS = ("hs_gassmann", "generalized_gassmann")


def _interval(depth, mask) -> str | None:
    """``"a–b m"`` spanning the depths where ``mask`` holds (``None`` if nowhere)."""
    if not np.any(mask):
        return None
    z = np.asarray(depth, dtype=float)[np.asarray(mask, dtype=bool)]
    return f"{z.min():g}–{z.max():g} m" if z.size > 1 else f"{z.min():g} m"


def validity_warnings(depth, porosity, *, porosity0, models=(), pore_filled=None) -> list[str]:
    """Lines that say where a scene's models run outside the range their sources support.

    Parameters
    ----------
    depth : array_like, shape (n,)
        Present-day depth, m.
    porosity : array_like, shape (n,)
        Porosity at those depths, fraction.
    porosity0 : float
        Depositional (initial, critical) porosity of the scene, fraction in (0, 1).
    models : sequence of str, optional
        Model labels the scene computes (``"hs_gassmann"``, …).
    pore_filled : array_like of bool or 0/1, shape (n,), optional
        Where the cement kinetics would overfill the intergranular volume (sandstone).

    Returns
    -------
    list of str
        One line per rule that applies somewhere; empty if none.

    Examples
    --------
    >>> depth = [0.0, 500.0, 1000.0, 1500.0]
    >>> validity_warnings(depth, [0.36, 0.34, 0.32, 0.30], porosity0=0.36,
    ...                   models=["hs_gassmann", "patchy_cement"])[0][:52]
    'Model 1 (Krief frame) at 0–500 m: porosity above 0.3'
    """
    if not 0.0 < float(porosity0) < 1.0:
        raise ValueError(f"porosity0 must lie in (0, 1); got {porosity0!r}")
    depth = np.asarray(depth, dtype=float)
    porosity = np.asarray(porosity, dtype=float)
    if depth.shape != porosity.shape or depth.ndim != 1:
        raise ValueError(f"depth {depth.shape} and porosity {porosity.shape} must be 1-D and "
                         "of one shape")
    lines = []
    krief = [m for m in models if m in KRIEF_MODELS]
    if krief:
        limit = KRIEF_LOOSE_FRACTION * float(porosity0)
        where = _interval(depth, porosity > limit)
        if where:
            numbers = [str(1 if m == "hs_gassmann" else 3) for m in krief]
            names = ("Models " if len(numbers) > 1 else "Model ") + " and ".join(numbers)
            lines.append(
                f"{names} (Krief frame) at {where}: porosity above {limit:.3g} "
                f"({KRIEF_LOOSE_FRACTION:g} of the depositional {float(porosity0):g}); Krief's "
                "relation is a fit to consolidated rocks with no pressure dependence and gives "
                "a loose sediment the stiffness of a rock (velocities too high, Vp/Vs too low)")
    if pore_filled is not None:
        where = _interval(depth, np.asarray(pore_filled).astype(bool))
        if where:
            lines.append(
                f"quartz cement at {where}: Walderhaug's kinetics would overfill the "
                "intergranular volume; cement capped at it and porosity 0 there")
    return lines
