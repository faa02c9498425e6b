"""The pore fluid of a scene at each present-day depth (``[fluid]``; private to the runner).

``model = "constant"`` keeps the catalogue fluid (:func:`rockcem.materials.fluid`) at every depth,
as the sources do; ``"batzle_wang"`` computes brine from each depth's temperature and pore
pressure (:func:`rockcem.pore_fluids.brine`; the path's pore pressure is gauge, 0 at the surface,
so one standard atmosphere is added). A hydrocarbon (:mod:`rockcem.pore_fluids`) shares the pores
in the interval ``[top, base]`` with saturation ``saturation``: mixed into one fluid by Wood's or
Brie's law, or kept in patches, each model run once with brine and once with the hydrocarbon and
the two rocks combined by :func:`patchy_rock`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["SceneFluid", "scene_fluid", "fluid_outputs", "patchy_rock"]


@dataclass(frozen=True)
class SceneFluid:
    """What the models get: ``fluid`` (one :class:`~rockcem.materials.Fluid`, arrays over depth),
    or, for patchy saturation, ``patches`` (brine and hydrocarbon fluids) with ``saturation`` (the
    hydrocarbon's, per depth); ``brine`` the brine alone (the templates' fluid); ``outputs``
    are the fluid variables per depth; ``warnings`` the validity lines of the fluid
    correlations."""

    brine: object
    fluid: object
    patches: tuple | None
    saturation: np.ndarray
    outputs: dict
    warnings: list


def scene_fluid(section, catalogue_fluid, depth, temperature, pore_pressure) -> SceneFluid:
    """The scene's pore fluid at the present-day ``depth`` (m), ``temperature`` (°C) and gauge
    ``pore_pressure`` (MPa).

    ``section`` is the scene's validated ``[fluid]`` table, ``catalogue_fluid`` the name of
    ``[materials] fluid``. Raises ``ValueError`` naming the fluid where a correlation has no
    answer (an oil below its bubble point, a gas below its pseudo-critical temperature), or
    where CO2 or methane needs CoolProp and it is absent or fails to import (one line that says
    which). Where a fluid is computed outside its source's range (Batzle & Wang's fitted data,
    an equation of state's stated range) ``warnings`` says so, depth by depth.
    """
    from . import pore_fluids as pf
    from .constants import STANDARD_ATMOSPHERE
    from .materials import Fluid, fluid

    depth = np.asarray(depth, dtype=float)
    T = np.broadcast_to(np.asarray(temperature, dtype=float), depth.shape)
    P = np.broadcast_to(np.asarray(pore_pressure, dtype=float), depth.shape) \
        + STANDARD_ATMOSPHERE
    warnings = []
    if section["model"] == "batzle_wang":
        salinity = section["salinity"] or 0.0
        with _named("fluid.model = 'batzle_wang'"):
            b = pf.brine(T, P, salinity)
        brine = Fluid(b.K, b.rho, name=f"brine {salinity:g} NaCl", source="BatzleWang1992")
        warnings += pf.validity_warnings("brine", T, P, salinity=salinity, depth=depth)
    else:
        c = fluid(catalogue_fluid)
        brine = Fluid(np.full(depth.shape, c.K), np.full(depth.shape, c.rho), name=c.name,
                      source=c.source)
    kind = section["hydrocarbon"]
    S = np.zeros(depth.shape)
    if kind == "none":
        return SceneFluid(brine, brine, None, S, fluid_outputs(brine, S), warnings)
    top = section["top"] if section["top"] is not None else -np.inf
    base = section["base"] if section["base"] is not None else np.inf
    inside = (depth >= top) & (depth <= base)
    if not np.any(inside):
        raise ValueError(f"scene section [fluid]: the hydrocarbon interval {top:g}-{base:g} m "
                         f"holds no depth of the profile ({depth.min():g}-{depth.max():g} m)")
    S[inside] = section["saturation"]
    # The hydrocarbon where it is (its correlation may have no answer at shallower depths, an oil
    # below its bubble point); the brine's values fill the rest, where its saturation is 0.
    K_h, rho_h = brine.K.copy(), brine.rho.copy()
    gravity = section["gas_gravity"] if section["gas_gravity"] is not None else 0.6
    with _named(f"fluid.hydrocarbon = {kind!r}"):
        if kind == "gas":
            h = pf.gas(T[inside], P[inside], gravity)
        elif kind == "oil":
            h = pf.oil(T[inside], P[inside],
                       api=section["oil_api"] if section["oil_api"] is not None else 30.0,
                       gas_oil_ratio=section["gas_oil_ratio"] or 0.0, gas_gravity=gravity)
        else:
            from .pore_fluids.reference import _coolprop_problem

            problem = _coolprop_problem()     # absent or broken: one line, not a traceback
            if problem is not None:
                raise ValueError(problem)
            h = getattr(pf, kind)(T[inside], P[inside])
    K_h[inside], rho_h[inside] = h.K, h.rho
    extra = {"gravity": gravity} if kind == "gas" else \
        {"api": section["oil_api"] if section["oil_api"] is not None else 30.0} \
        if kind == "oil" else {}
    warnings += pf.validity_warnings(kind, T[inside], P[inside], depth=depth[inside], **extra)
    hydrocarbon = Fluid(K_h, rho_h, name=kind)
    mixing = section["mixing"]
    if mixing == "patchy":
        rho = (1.0 - S) * brine.rho + S * hydrocarbon.rho
        outputs = {"fluid_density": rho, "hydrocarbon_saturation": S}
        return SceneFluid(brine, None, (brine, hydrocarbon), S, outputs, warnings)
    if mixing == "brie":
        exponent = section["brie_exponent"] if section["brie_exponent"] is not None else 3.0
        m = pf.brie(1.0 - S, brine.K, hydrocarbon.K, brine.rho, hydrocarbon.rho,
                    exponent=exponent)
    else:
        m = pf.wood(np.stack([1.0 - S, S], axis=-1), np.stack([brine.K, hydrocarbon.K], -1),
                    np.stack([brine.rho, hydrocarbon.rho], -1))
    mixed = Fluid(m.K, m.rho, name=f"brine and {kind} ({mixing})")
    return SceneFluid(brine, mixed, None, S, fluid_outputs(mixed, S), warnings)


def fluid_outputs(fluid, saturation):
    """The fluid variables per depth: ``fluid`` (numbers or arrays) broadcast to the shape of
    ``saturation``, the hydrocarbon's."""
    shape = np.shape(saturation)
    K = np.broadcast_to(np.asarray(fluid.K, dtype=float), shape)
    rho = np.broadcast_to(np.asarray(fluid.rho, dtype=float), shape)
    vp = np.sqrt(np.divide(K, rho, out=np.zeros(shape), where=rho > 0.0))
    return {"fluid_density": rho, "fluid_bulk_modulus": K, "fluid_velocity": vp,
            "hydrocarbon_saturation": saturation}


def _named(what):
    """Prefix a ValueError with the scene key that chose the fluid."""
    from .validation import prefixed_errors

    return prefixed_errors(f"scene section [fluid] ({what})")


def patchy_rock(brine_rock, hydrocarbon_rock, saturation):
    r"""A rock whose pores hold patches of brine and of hydrocarbon, each patch larger than the
    pores and smaller than the wavelength (White's patchy limit, [Mavko2009]_ Sect. 6.17): the
    P-wave modulus is the volume average of the patches' P-wave compliances,

    .. math:: \frac{1}{M} = \frac{1 - S_h}{M_b} + \frac{S_h}{M_h},

    exact by Hill's theorem when the patches share one shear modulus (Gassmann models, whose
    fluid leaves it unchanged); the shear moduli are averaged the same way (Reuss), which is
    that shared modulus then. Density is linear in the saturation.

    Parameters
    ----------
    brine_rock, hydrocarbon_rock : RockProperties
        The model's rock with brine and with the hydrocarbon in every pore.
    saturation : array_like
        Hydrocarbon saturation :math:`S_h` per depth, in [0, 1].

    Returns
    -------
    RockProperties
    """
    from .elastic import velocities
    from .models import RockProperties

    S = np.asarray(saturation, dtype=float)
    b, h = brine_rock, hydrocarbon_rock
    M = _reuss(b.K_sat + 4.0 / 3.0 * b.G_sat, h.K_sat + 4.0 / 3.0 * h.G_sat, S)
    G = _reuss(b.G_sat, h.G_sat, S)
    rho = (1.0 - S) * b.density + S * h.density
    K = M - 4.0 / 3.0 * G
    # NaN where the model has no rock (the MD member between its depths) stays NaN.
    ok = np.isfinite(K) & np.isfinite(G) & np.isfinite(rho)
    v = velocities(np.where(ok, K, 1.0), np.where(ok, G, 0.0), np.where(ok, rho, 1.0))
    return RockProperties(b.K_dry, b.G_dry, K, G, rho, np.where(ok, v.vp, np.nan),
                          np.where(ok, v.vs, np.nan))


def _reuss(a, b, S):
    """``1 / ((1 - S) / a + S / b)``; 0 where a patch that is present has a zero modulus, NaN
    where either is NaN (a depth a model did not run at, such as the MD member's)."""
    a, b, S = np.broadcast_arrays(np.asarray(a, float), np.asarray(b, float), S)
    missing = np.isnan(a) | np.isnan(b)
    a, b = np.where(missing, 1.0, a), np.where(missing, 1.0, b)
    zero = ((a <= 0.0) & (S < 1.0)) | ((b <= 0.0) & (S > 0.0))
    c = (1.0 - S) / np.where(a > 0.0, a, 1.0) * (a > 0.0) + S / np.where(b > 0.0, b, 1.0) \
        * (b > 0.0)
    out = np.where(zero | (c <= 0.0), 0.0, 1.0 / np.where(c > 0.0, c, 1.0))
    return np.where(missing, np.nan, out)
