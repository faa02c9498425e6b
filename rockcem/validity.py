r"""Where a scene applies a model outside the range its source supports: one line of text each.

The scene runner writes these lines into the Dataset (global attribute ``validity_warnings``,
lines joined by newlines), issues each once per run as a :class:`RockcemValidityWarning` (a
``UserWarning``: ``warnings.simplefilter("ignore", rockcem.RockcemValidityWarning)`` silences
them, ``"error"`` makes them stop a run), and ``rockcem run`` prints them under its summary. The
results there are still computed as the sources prescribe; the lines say where not to read them
as a rock's properties.

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
- Model 2 (self-consistent, eqs. 8–9 of [Carcione2022]_) holds the pore fluid in isolated
  spheroidal inclusions: its saturated moduli are the high-frequency (unrelaxed) limit, as the
  source says of it ([Carcione2022]_ Sect. 4.2, "the inclusions are isolated, so that pore
  pressures are not equilibrated"; [Berryman1980]_). At seismic frequencies the connected
  pores of a sand are relaxed and the fluid adds no shear stiffness: :math:`\mu_{sat} =
  \mu_{dry}` ([Gassmann1951]_; [Mavko2009]_ Sect. 6.3). Above the scheme's percolation
  porosity for the pores' aspect ratio the dry frame has no shear modulus at all (a suspension;
  about 0.29 for :math:`\gamma = 0.108`), yet the saturated one gives a loose sand at the surface
  Vs ≈ 1.15 km/s. Flagged where more than :data:`ASSUMPTION_SHEAR_FRACTION` of the saturated
  shear modulus is the isolated fluid's: :math:`\mu_{dry} < (1 - 0.5)\,\mu_{sat}`.
- Model 4 (patchy cement, eqs. 15–21 and D.1–D.2 of [Carcione2022]_) takes the uncemented
  contacts as a Hertz–Mindlin pack at :math:`p_e + \delta`, with a bonding pre-stress
  :math:`\delta` (100 MPa in the source, after [GangiCarlson1996]_): App. D assumes the grains
  are not "floating" in the fluid at the beginning of burial. The patchy-cement
  model it modifies ([Avseth2016]_) has the uncemented pack at the effective pressure alone,
  where a loose sand at :math:`p_e \to 0` has no contact stiffness (Hertz–Mindlin,
  [Mavko2009]_ Sect. 5.4); so at the surface the source's sand has the frame of a pack under
  100 MPa (Vs ≈ 1.5 km/s where a loose sand has Vs ≲ 0.3 km/s). Flagged where more than
  :data:`ASSUMPTION_SHEAR_FRACTION` of the dry frame's shear modulus is owed to
  :math:`\delta`: the same frame with :math:`\delta = 0` (Avseth's, with the same cement and
  pressure) is less than half of it.
- Walderhaug's quartz-cement kinetics (eq. B.1 of [Carcione2022]_) has no limit at the pore
  space. Where it would overfill the intergranular volume the cement is capped there and the
  porosity is 0 (:func:`burial.sandstone_porosity`); flagged over that depth interval.
"""

from __future__ import annotations

import numpy as np

__all__ = ["ASSUMPTION_SHEAR_FRACTION", "KRIEF_LOOSE_FRACTION", "KRIEF_MODELS",
           "RockcemValidityWarning", "issue_warnings", "validity_warnings"]

#: Porosity above this fraction of the depositional porosity counts as loose (unconsolidated)
#: for the Krief-based models.
KRIEF_LOOSE_FRACTION = 0.9
#: Model labels whose dry frame is Krief's relation.
KRIEF_MODELS = ("hs_gassmann", "generalized_gassmann")
#: Models 2 and 4 are flagged where more than this fraction of their shear modulus comes from
#: an assumption outside a loose sand's domain (Model 2: the isolated pores' fluid; Model 4: the
#: bonding pre-stress delta). One half: where the assumption, not the rock, sets most of Vs.
ASSUMPTION_SHEAR_FRACTION = 0.5
#: The text of each rule for Models 2 and 4: (model number, what, what the rock has instead).
_ASSUMPTIONS = {
    "self_consistent": (
        2, "self-consistent",
        "more than half of the saturated shear modulus is the pore fluid's, held in isolated "
        "pores (a high-frequency limit); the rock's connected pores at seismic frequencies leave "
        "it the dry frame's (Gassmann), less than half (Vs too high, Vp/Vs too low)"),
    "patchy_cement": (
        4, "patchy cement",
        "more than half of the dry frame's shear modulus comes from the bonding pre-stress "
        "delta, not from cement or the effective pressure; an uncemented sand there is a "
        "Hertz-Mindlin pack at its effective pressure, far softer (velocities too high)"),
}


class RockcemValidityWarning(UserWarning):
    """A scene's model run outside the range its source supports (one line of
    :func:`validity_warnings`, or of the pore fluids' or the MD engine's): issued once per run
    by :func:`rockcem.scene.run_scene`, and kept in the Dataset's ``validity_warnings``."""


def issue_warnings(lines, *, prefix="") -> None:
    """Issue each distinct line of ``lines`` once as a :class:`RockcemValidityWarning`,
    attributed to the first caller outside the ``rockcem`` package (the user's line, as
    pandas' ``find_stack_level`` does).

    Parameters
    ----------
    lines : iterable of str
        Warning lines (empty ones are skipped).
    prefix : str, optional
        Text put before each line (``"scene NAME: "``).
    """
    import os
    import sys
    import warnings

    here = os.path.dirname(os.path.abspath(__file__)) + os.sep
    frame, level = sys._getframe(1), 2          # level 2: the caller of this function
    while frame is not None and os.path.abspath(frame.f_code.co_filename).startswith(here):
        frame, level = frame.f_back, level + 1
    for line in dict.fromkeys(line for line in lines if line):
        warnings.warn(prefix + line, RockcemValidityWarning, stacklevel=level)


def _interval(depth, mask) -> str | None:
    """``"a–b m"`` spanning the depths where ``mask`` holds (``None`` if nowhere)."""
    if not np.any(mask):
        return None
    z = np.asarray(depth, dtype=float)[np.asarray(mask, dtype=bool)]
    return f"{z.min():g}–{z.max():g} m" if z.size > 1 else f"{z.min():g} m"


def validity_warnings(depth, porosity, *, porosity0, models=(), pore_filled=None,
                      shear_moduli=None) -> list[str]:
    r"""Lines that say where a scene's models run outside the range their sources support.

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
    shear_moduli : mapping, optional
        ``{label: (G, G_supported)}``, GPa, each shape (n,), for the models of the Models 2
        and 4 rules: ``"self_consistent"`` its saturated and dry shear moduli,
        ``"patchy_cement"`` its dry frame's and that of the same frame with
        :math:`\delta = 0`. A model is flagged where ``G_supported`` is below
        ``(1 - ASSUMPTION_SHEAR_FRACTION) * G``.

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
    for label, (number, name, why) in _ASSUMPTIONS.items():
        if label not in (shear_moduli or {}):
            continue
        G, supported = (np.asarray(a, dtype=float) for a in shear_moduli[label])
        if G.shape != depth.shape or supported.shape != depth.shape:
            raise ValueError(f"shear_moduli[{label!r}] must be two arrays of the depth's shape "
                             f"{depth.shape}; got {G.shape} and {supported.shape}")
        where = _interval(depth, supported < (1.0 - ASSUMPTION_SHEAR_FRACTION) * G)
        if where:
            lines.append(f"Model {number} ({name}) at {where}: {why}")
    if pore_filled is not None:
        where = _interval(depth, np.asarray(pore_filled).astype(bool))
        if where:
            lines.append(
                f"quartz cement at {where}: Walderhaug's kinetics would overfill the "
                "intergranular volume; cement capped at it and porosity 0 there")
    return lines
