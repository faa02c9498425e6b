"""The four petro-elastic models of Carcione et al. (2022), as compositions of the building blocks.

Each model takes the rock state as arrays that broadcast together — porosity, the fractions of
the solids (per unit volume of *solid*, phases on the last axis), and for Model 4 the cement
fraction and effective pressure — plus the materials, and returns a :class:`RockProperties`.
Units: GPa, g/cm³, km/s, MPa, fractions.

========================  ======================================  =============================
label                     model                                   eqs. of [Carcione2022]_
========================  ======================================  =============================
``hs_gassmann``           1: HS mineral + Krief frame + Gassmann  3–7, C.1–C.3
``self_consistent``       2: self-consistent, spheroidal pores    8–9
``generalized_gassmann``  3: multi-mineral Krief + generalized    10–14
                          Gassmann
``patchy_cement``         4: patchy cement (CCT + Hertz–Mindlin,  15–21, D.1–D.2, 4–6
                          HS upper, SC, Hill) + Gassmann
========================  ======================================  =============================
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

from .validation import (BLOCK, MAX_DENSITY, as_array, broadcast, broadcast_phases,
                          check_fractions, check_modulus, check_range, stack_phases, sum_phases)
from .bounds import _hs_average
from .elastic import velocities
from .fluids import _gassmann, _generalized_gassmann
from .frames import MAX_KRIEF_EXPONENT, krief, krief_multimineral
from .granular import _cement_radius, _patchy_cement, _shapes
from .inclusions import _check_engine, _self_consistent, check_aspect_ratio
from .materials import Fluid, Mineral
from .validation import FIELD_UNITS, labelled

__all__ = [
    "RockProperties",
    "hs_gassmann",
    "self_consistent_model",
    "generalized_gassmann_model",
    "patchy_cement_model",
    "MODELS",
    "bulk_density",
]


#: Largest relative excess of Model 4's dry bulk modulus over its mineral's that is capped at
#: the mineral (the two end members' definitions differ by < 1e-4 for quartz cement); beyond it
#: :func:`patchy_cement_model` refuses.
MAX_FRAME_EXCESS = 1e-3


class RockProperties(NamedTuple):
    """Elastic properties of a rock: moduli GPa, density g/cm³, velocities km/s."""

    K_dry: np.ndarray
    G_dry: np.ndarray
    K_sat: np.ndarray
    G_sat: np.ndarray
    density: np.ndarray
    vp: np.ndarray
    vs: np.ndarray


def _solids(minerals: Sequence[Mineral], solid_fractions, porosity):
    if len(minerals) == 0 or not all(isinstance(m, Mineral) for m in minerals):
        raise ValueError("minerals must be a non-empty sequence of rockcem.materials.Mineral")
    beta = as_array("solid_fractions", solid_fractions)
    if beta.ndim == 0 or beta.shape[-1] != len(minerals):
        raise ValueError(f"solid_fractions must have {len(minerals)} phases on its last axis "
                         f"(one per mineral); got shape {beta.shape}")
    check_fractions("solid_fractions", beta)
    phi = check_range("porosity", as_array("porosity", porosity), 0.0, 1.0, high_open=True)
    K = np.array([m.K for m in minerals])
    G = np.array([m.G for m in minerals])
    rho = np.array([m.rho for m in minerals])
    beta, phi_b = broadcast(solid_fractions=beta, porosity=phi[..., None])
    return K, G, rho, beta, phi_b[..., 0]


def _by_points(block, points, **const):
    """``block(**points, **const)`` over blocks of :data:`rockcem.validation.BLOCK` points.

    ``points`` maps a name to ``(array, tail)``: an array over the points with ``tail``
    trailing axes of its own (1 for phases). The block function sees the same arguments, cut
    along the points (flattened), so that its temporaries stay in cache; it returns a
    :class:`RockProperties` over its points. All arithmetic and checks are those of ``block``
    on each point; it runs on the whole input at once where the points are few, or where their
    shapes do not broadcast (its own checks then name them).
    """
    arrays = {k: np.asarray(v) for k, (v, _) in points.items()}
    tails = {k: t for k, (_, t) in points.items()}
    try:
        shape = np.broadcast_shapes(*(a.shape[:a.ndim - tails[k]] for k, a in arrays.items()))
    except ValueError:
        shape = ()
    size = int(np.prod(shape))
    if size <= 2 * BLOCK:
        return block(**arrays, **const)
    flat = {}
    for k, a in arrays.items():
        lead = a.shape[:a.ndim - tails[k]]
        if int(np.prod(lead)) == 1:
            flat[k] = a.reshape(a.shape[a.ndim - tails[k]:])     # one value for every point
        else:
            tail = a.shape[a.ndim - tails[k]:]
            flat[k] = np.broadcast_to(a, shape + tail).reshape((size,) + tail)
    out = None
    for i in range(0, size, BLOCK):
        part = block(**{k: a if a.ndim == tails[k] else a[i:i + BLOCK] for k, a in flat.items()},
                     **const)
        if out is None:
            out = [np.empty(size) for _ in part]
        for o, p in zip(out, part):
            o[i:i + BLOCK] = p
    return RockProperties(*(o.reshape(shape) for o in out))


def _fluid(fluid) -> Fluid:
    if not isinstance(fluid, Fluid):
        raise ValueError("fluid must be a rockcem.materials.Fluid")
    return fluid


@labelled(units="g cm-3", phases=("mineral_density", "solid_fractions"))
def bulk_density(mineral_density, solid_fractions, porosity, fluid_density):
    r"""Bulk density, eq. 24 of [Carcione2022]_.

    .. math:: \rho = (1-\phi)\sum_i \beta_i \rho_i + \phi \rho_f

    Parameters
    ----------
    mineral_density : array_like, shape (n,) or (..., n)
        Densities of the solids, g/cm³, in (0, :data:`rockcem.validation.MAX_DENSITY`].
    solid_fractions : array_like, shape (..., n)
        :math:`\beta_i`, fractions per unit volume of solid (each in [0, 1], summing to 1), one
        per solid.
    porosity : array_like, shape (...)
        Porosity, in [0, 1].
    fluid_density : float or array_like, shape (...)
        Pore-fluid density, g/cm³, in [0, :data:`rockcem.validation.MAX_DENSITY`] (0: empty
        pores).

    Returns
    -------
    ndarray, shape (...)
        Bulk density, g/cm³, between the fluid's and the densest solid's.

    Raises
    ------
    ValueError
        Naming the argument: a value out of its range, NaN, text, fractions that do not sum to
        1 or whose number of phases differs from ``mineral_density``'s, shapes that do not
        broadcast.

    Examples
    --------
    Quartz (2.65) and water at 20 % porosity:

    >>> round(float(bulk_density([2.65], [1.0], 0.2, 1.0)), 4)
    2.32
    """
    rho = check_range("mineral_density", as_array("mineral_density", mineral_density), 0.0,
                      MAX_DENSITY, low_open=True)
    beta = check_fractions("solid_fractions", as_array("solid_fractions", solid_fractions))
    phi = check_range("porosity", as_array("porosity", porosity), 0.0, 1.0)
    rho_f = check_range("fluid_density", as_array("fluid_density", fluid_density), 0.0,
                        MAX_DENSITY)
    broadcast(porosity=phi, fluid_density=rho_f)        # named with their own shapes
    beta, rho, phi, rho_f = broadcast_phases(("solid_fractions", beta), mineral_density=rho,
                                             porosity=phi[..., None],
                                             fluid_density=rho_f[..., None])
    return _bulk_density(rho, [beta[..., i] for i in range(beta.shape[-1])], phi[..., 0],
                         rho_f[..., 0])


def _check_densities(mineral_density, fluid_density, porosity):
    """The density checks of :func:`bulk_density` (a few numbers, or one per depth for a
    fluid), with the same messages, for a model whose fractions and porosity are checked
    already; returns the mineral densities as an array."""
    rho = check_range("mineral_density", as_array("mineral_density", mineral_density), 0.0,
                      MAX_DENSITY, low_open=True)
    rho_f = check_range("fluid_density", as_array("fluid_density", fluid_density), 0.0,
                        MAX_DENSITY)
    broadcast(porosity=porosity, fluid_density=rho_f)
    return rho


def _bulk_density(rho, beta, phi, rho_f):
    """Eq. 24 of [Carcione2022]_ (:func:`bulk_density`) on checked inputs that broadcast:
    ``rho`` with the phases last, ``beta`` one array per phase (a sequence), ``phi`` and
    ``rho_f`` without phases. The sum over the phases is :func:`rockcem.validation.sum_phases`'
    (the same additions in the same order)."""
    solid = beta[0] * rho[..., 0]
    for i in range(1, len(beta)):
        solid = solid + beta[i] * rho[..., i]
    return (1.0 - phi) * solid + phi * rho_f


def _finish(K_dry, G_dry, K_sat, G_sat, density) -> RockProperties:
    v = velocities(K_sat, G_sat, density)
    K_dry, G_dry, K_sat, G_sat, density = broadcast(K_dry=K_dry, G_dry=G_dry, K_sat=K_sat,
                                                    G_sat=G_sat, density=density)
    return RockProperties(K_dry, G_dry, K_sat, G_sat, density, v.vp, v.vs)


@labelled(units=FIELD_UNITS, phases=("solid_fractions",))
def hs_gassmann(minerals, solid_fractions, porosity, fluid, *, A=3.0) -> RockProperties:
    r"""Model 1 of [Carcione2022]_: Hashin–Shtrikman mineral, Krief frame, Gassmann fluid.

    The minerals are mixed with the HS average (eqs. C.1–C.3) into :math:`K_s, \mu_s`; Krief's
    law (eq. 3) gives the dry frame; Gassmann's equation (eqs. 4–6) saturates it; density by
    eq. 24 and velocities by eqs. 22–25. Porosity typically comes from Athy's law (eq. 7) or IGV
    compaction; this function takes it as given.

    Parameters
    ----------
    minerals : sequence of Mineral
        The ``n`` solids (e.g. smectite and illite; quartz grain and cement).
    solid_fractions : array_like, shape (..., n)
        Fraction of each solid per unit volume of solid, summing to 1.
    porosity : array_like, shape (...)
        Porosity, in [0, 1).
    fluid : Fluid
        Pore fluid.
    A : float, optional
        Krief exponent; default 3 (as in [Carcione2022]_).

    Returns
    -------
    RockProperties
        Broadcast over the rock-state arrays.
    """
    K, G, rho, beta, phi = _solids(minerals, solid_fractions, porosity)
    broadcast(porosity=phi, A=as_array("A", A))      # named before Krief's phi
    fluid = _fluid(fluid)
    K_f, rho = _checked_once(("K", K, True), ("G", G, True), A, fluid, phi, rho)
    return _by_points(_hs_gassmann, {"beta": (beta, 1), "phi": (phi, 0), "K_f": (K_f, 0),
                                     "rho_f": (fluid.rho, 0), "A": (A, 0)}, K=K, G=G, rho=rho)


def _checked_once(K, G, A, fluid, phi, rho):
    """The checks of the public steps of Models 1 and 3 that their blocks skip, once, with
    those steps' messages and in their order: the minerals' moduli ``K``, ``G`` (each a name,
    the moduli and whether 0 is allowed: as the first step that checks them), Krief's exponent
    ``A``, the fluid's modulus (Gassmann's ``K_fluid``) and the densities
    (:func:`bulk_density`'s). Returns the fluid's modulus and the minerals' densities as
    arrays."""
    for name, value, allow_zero in (K, G):
        check_modulus(name, value, allow_zero=allow_zero)
    check_range("A", as_array("A", A), 0.0, MAX_KRIEF_EXPONENT, low_open=True)
    K_f = check_modulus("K_fluid", as_array("K_fluid", fluid.K), allow_zero=True)
    return K_f, _check_densities(rho, fluid.rho, phi)


def _hs_gassmann(beta, phi, K_f, rho_f, A, K, G, rho):
    """Model 1 on a block of points (:func:`hs_gassmann`); its inputs checked by it (the
    mineral's moduli by :func:`rockcem.frames.krief`; Krief's frame is never stiffer than its
    mineral, as Gassmann's equation requires)."""
    columns = [beta[..., i] for i in range(beta.shape[-1])]
    K_s, G_s = _hs_average(K, G, columns)
    dry = krief(K_s, G_s, phi, A)
    K_sat = _gassmann(dry.K, K_s, K_f, phi)
    return _finish(dry.K, dry.G, K_sat, dry.G, _bulk_density(rho, columns, phi, rho_f))


@labelled(units=FIELD_UNITS, phases=("solid_fractions",))
def self_consistent_model(minerals, solid_fractions, porosity, fluid, *, aspect_ratio,
                          tol=1e-12, engine="auto") -> RockProperties:
    r"""Model 2 of [Carcione2022]_: Berryman's self-consistent scheme, eqs. 8–9.

    The solids are spheres and the pores spheroids of the given aspect ratio, in volume
    proportions :math:`(1-\phi)\beta_i` and :math:`\phi`. With the pore fluid in the pores the
    result is the (high-frequency, unrelaxed) saturated rock; the dry moduli are the same
    scheme with empty pores. Both solves are :func:`rockcem.inclusions.self_consistent` (from
    5·10^4 points on its numba kernel, fastest along an ordered depth profile).

    Parameters
    ----------
    minerals, solid_fractions, porosity, fluid
        As in :func:`hs_gassmann`.
    aspect_ratio : float or array_like, shape (...)
        Pore aspect ratio :math:`\gamma`, in [:data:`rockcem.inclusions.MIN_ASPECT_RATIO`,
        :data:`rockcem.inclusions.MAX_ASPECT_RATIO`] (0.17 for the shale and 0.108 for the
        sandstone of [Carcione2022]_; 1 for spherical pores).
    tol : float, optional
        Tolerance of the Newton solver of :func:`rockcem.inclusions.self_consistent`.
    engine : {"auto", "numpy", "numba"}, optional
        Solver implementation, as in :func:`rockcem.inclusions.self_consistent` (``"numpy"``
        never imports numba).

    Returns
    -------
    RockProperties
    """
    _check_engine(engine)
    K, G, rho, beta, phi = _solids(minerals, solid_fractions, porosity)
    fluid = _fluid(fluid)
    gamma = check_aspect_ratio(as_array("aspect_ratio", aspect_ratio))
    broadcast(porosity=phi, aspect_ratio=gamma)
    if not tol > 0.0:
        raise ValueError(f"tol must be > 0; got {tol:g}")
    rho = _check_densities(rho, fluid.rho, phi)
    # The phases' volume fractions, solids then pores, written into one array, column by
    # column (a product with a short last axis runs row by row in numpy, twice as slow).
    frac = np.empty(beta.shape[:-1] + (beta.shape[-1] + 1,))
    solid = 1.0 - phi
    for i in range(beta.shape[-1]):
        np.multiply(solid, beta[..., i], out=frac[..., i])
    frac[..., -1] = phi
    aspect = stack_phases(*([np.ones_like(gamma)] * len(K)), gamma)

    def solve(K_pore, G_pore):
        # The inputs are checked (minerals, fluid, fractions built from checked solid fractions
        # and porosity), so the solver's own checks are skipped; the phase moduli go in as one
        # row (n + 1,), or one per depth for a fluid that varies with depth, and are broadcast
        # against the fractions there.
        if np.ndim(K_pore) == 0:
            return _self_consistent(np.append(K, K_pore), np.append(G, G_pore), frac, aspect,
                                    tol, engine=engine)
        K_pore = broadcast(porosity=phi, fluid_K=K_pore)[1]
        rows = np.broadcast_to(K, K_pore.shape + K.shape)
        return _self_consistent(np.concatenate([rows, K_pore[..., None]], axis=-1),
                                np.append(G, G_pore), frac, aspect, tol, engine=engine)

    sat = solve(fluid.K, 0.0)
    dry = solve(0.0, 0.0) if np.any(np.asarray(fluid.K) > 0.0) else sat
    return _finish(dry.K, dry.G, sat.K, sat.G,
                   _bulk_density(rho, [beta[..., i] for i in range(len(K))], phi, fluid.rho))


@labelled(units=FIELD_UNITS, phases=("solid_fractions",))
def generalized_gassmann_model(minerals, solid_fractions, porosity, fluid, *,
                               A=3.0) -> RockProperties:
    r"""Model 3 of [Carcione2022]_: multi-mineral Krief frame and generalized Gassmann.

    Frame moduli of each solid by eqs. 13–14 (:func:`rockcem.frames.krief_multimineral`), the
    saturated bulk modulus by eqs. 10–12 (:func:`rockcem.fluids.generalized_gassmann`), and
    :math:`\mu = \sum_i \mu_{mi}`.

    Parameters and returns as in :func:`hs_gassmann`.
    """
    K, G, rho, beta, phi = _solids(minerals, solid_fractions, porosity)
    broadcast(porosity=phi, A=as_array("A", A))      # named before Krief's phi
    fluid = _fluid(fluid)
    K_f, rho = _checked_once(("K_solid", K, False), ("G_solid", G, True), A, fluid, phi, rho)
    return _by_points(_model3, {"beta": (beta, 1), "phi": (phi, 0), "K_f": (K_f, 0),
                                "rho_f": (fluid.rho, 0), "A": (A, 0)}, K=K, G=G, rho=rho)


def _model3(beta, phi, K_f, rho_f, A, K, G, rho):
    r"""Model 3 on a block of points (:func:`generalized_gassmann_model`); its inputs checked
    by it (each solid's Biot coefficient is :math:`\beta_i (1 - K_s F / V_K) \ge 0`, with
    the HS average :math:`K_s` at most the Voigt average :math:`V_K` and Krief's factor
    :math:`F \le 1`, as the generalized Gassmann equation requires).

    The solid fractions go to Krief's frame in column order (Fortran): its arithmetic with a
    short last axis then runs along the points, not row by row (the same values)."""
    beta = np.asfortranarray(beta)
    K_i = np.broadcast_to(K, beta.shape)
    frames = krief_multimineral(K_i, np.broadcast_to(G, beta.shape), beta, phi, A)
    K_sat = _generalized_gassmann(frames.K, K, beta, K_f, phi)
    G_dry = sum_phases(frames.G)
    return _finish(sum_phases(frames.K), G_dry, K_sat, G_dry,
                   _bulk_density(rho, [beta[..., i] for i in range(len(K))], phi, rho_f))


@labelled(units=FIELD_UNITS)
def patchy_cement_model(grain, cement, porosity, cement_fraction, pressure, fluid, *,
                        critical_porosity=0.36, coordination_number=9.0,
                        contact_cement_limit=0.05, delta=100.0, scheme=1, thickness=0.0,
                        f=1.0) -> RockProperties:
    r"""Model 4 of [Carcione2022]_: patchy cement dry rock (eqs. 15–21, D.1–D.2) and Gassmann.

    The dry frame is :func:`rockcem.granular.patchy_cement`. The mineral modulus in Gassmann's
    equation is the HS average of grain and cement in their solid proportions
    :math:`(1-\phi-\phi_p)/(1-\phi)` and :math:`\phi_p/(1-\phi)`, as for Models 1 and 3
    (the paper does not say which mineral modulus it uses there). The dry frame's
    zero-porosity end member is another mix of the same two solids (self-consistent, in
    proportions :math:`1-\phi_0 : \phi_0`), so near zero porosity the frame can come out
    stiffer than that mineral modulus: by less than :data:`MAX_FRAME_EXCESS` it is capped at
    it (quartz cement: < 1e-4), beyond it the model is refused (a cement much softer than the
    grain, up to 30 %).

    Parameters
    ----------
    grain, cement : Mineral
        Grain and cement materials.
    porosity : array_like
        Porosity :math:`\phi`, in [0, ``critical_porosity``].
    cement_fraction : array_like
        Cement volume fraction :math:`\phi_p`, in [0, ``critical_porosity``], with
        :math:`\phi + \phi_p \le 1`.
    pressure : array_like
        Effective pressure, MPa, in [0, :data:`rockcem.granular.MAX_PRESSURE_MPA`].
    fluid : Fluid
        Pore fluid.
    critical_porosity : float, optional
        :math:`\phi_0`, in (0, 1); default 0.36.
    coordination_number : float, optional
        :math:`C`, in (0, :data:`rockcem.granular.MAX_COORDINATION_NUMBER`]; default 9.
    contact_cement_limit : float, optional
        :math:`\phi_{p0}`, in (0, ``critical_porosity``]; default 0.05.
    delta : float, optional
        Bonding pre-stress, MPa, in [0, :data:`rockcem.granular.MAX_PRESSURE_MPA`]; default 100
        (40 is the alternative of Fig. 17).
    scheme : {1, 2}
        Cement at contacts (eq. 16) or coating the grains (eq. 18).
    thickness : float, optional
        MCCT contact thickness :math:`\varepsilon`, ``>= 0``; default 0 (CCT).
    f : float, optional
        Hertz–Mindlin no-slip fraction, in [0, 1]; default 1.

    Returns
    -------
    RockProperties
    """
    if not isinstance(grain, Mineral) or not isinstance(cement, Mineral):
        raise ValueError("grain and cement must be rockcem.materials.Mineral")
    fluid = _fluid(fluid)
    # Checked here under the names a scene gives them ([models.patchy_cement] keys), so that
    # no message speaks of the building blocks' symbols (n, phic, phi); the ranges are the
    # building blocks' own (rockcem.granular._RANGES).
    phi, phic, n, pressure, phip, limit, eps, f, delta = _shapes(
        _labels={"phi": "porosity", "phic": "critical_porosity", "n": "coordination_number"},
        phi=porosity, phic=critical_porosity, n=coordination_number, pressure=pressure,
        cement_fraction=cement_fraction, contact_cement_limit=contact_cement_limit,
        thickness=thickness, f=f, delta=delta)
    if scheme not in (1, 2) or isinstance(scheme, bool):
        raise ValueError(f"scheme must be 1 (cement at contacts) or 2 (coating); got {scheme!r}")
    # Shapes named together; critical_porosity is kept as given (usually one number), so that
    # the frame's zero-porosity end member is solved once, not once per point.
    phi, phip, _ = broadcast(porosity=phi, cement_fraction=phip, critical_porosity=phic)
    if np.any(phi + phip > 1.0 + 1e-12):
        raise ValueError("porosity + cement_fraction must not exceed 1")
    one_phic = np.size(phic) == 1
    phic_1 = float(np.reshape(phic, ())) if one_phic else None
    for name, value in (("porosity", phi), ("cement_fraction", phip),
                        ("contact_cement_limit", limit)):
        # One number phic (the usual case): one reduction, no temporary of the value's size.
        if (np.size(value) and np.max(value) > phic_1 * (1.0 + 1e-12)) if one_phic \
                else np.any(value > phic * (1.0 + 1e-12)):
            raise ValueError(f"{name} must not exceed critical_porosity (the model holds for "
                             f"{name} in [0, critical_porosity])")
    # The contact cement's radius, checked here to name the scene's keys, and passed on to
    # patchy_cement's contact cement. Its arguments are checked above (phic - min(phip, limit)
    # lies in [0, phic]), so are patchy_cement's but the minerals' moduli, checked next: the
    # building blocks' checks are skipped.
    alpha = _cement_radius(phic - np.minimum(phip, limit), phic, n, scheme, eps)
    if np.size(alpha) and np.max(alpha) > 1.0:
        raise ValueError(f"the cement at the grain contacts (cement_fraction up to "
                         f"contact_cement_limit) is more than the contact model holds at this "
                         f"coordination_number and critical_porosity: its radius a/R reaches "
                         f"{float(np.max(alpha)):.3g} > 1")
    K0, G0, Kc, Gc = _shapes(K0=grain.K, G0=grain.G, Kc=cement.K, Gc=cement.G)
    # A porosity the check lets a rounding above phic (the IGV at zero pressure, computed, is
    # phi0 + 1 ulp) is phic for the frame: its Hill weight 1 - phi/phic would be -1 ulp, and a
    # frame of zero moduli (no pressure, no delta) would come out at -4e-15 GPa.
    phi_frame = phi if one_phic and (phi.size == 0 or np.max(phi) <= phic_1) \
        else np.minimum(phi, phic)
    dry = _patchy_cement(K0, G0, Kc, Gc, phi_frame, phic, n, pressure, phip, limit, scheme, eps,
                         f, delta, alpha=alpha)
    # Gassmann's and the bulk density's checks (the rest of their inputs are checked above).
    K_f = check_modulus("K_fluid", as_array("K_fluid", fluid.K), allow_zero=True)
    rho = _check_densities([grain.rho, cement.rho], fluid.rho, phi)
    K = np.array([grain.K, cement.K])
    G = np.array([grain.G, cement.G])
    most = []
    rock = _by_points(_model4_rock, {"K_dry": (dry.K, 0), "G_dry": (dry.G, 0), "phi": (phi, 0),
                                     "phip": (phip, 0), "K_f": (K_f, 0),
                                     "rho_f": (fluid.rho, 0)}, K=K, G=G, rho=rho, most=most)
    if max(most, default=0.0) > 1.0 + MAX_FRAME_EXCESS:
        _refuse_frame_stiffer(dry.K, phi, phip, K, G)
    return rock


def _model4_rock(K_dry, G_dry, phi, phip, K_f, rho_f, K, G, rho, most):
    """Model 4 on a block of points, from its dry frame on: the mineral modulus (the HS
    average of grain and cement in the rock's proportions), the frame capped at it,
    Gassmann's equation, the bulk density (:func:`patchy_cement_model`; inputs checked by
    it). Appends the block's largest ratio of frame to mineral bulk modulus to ``most``.

    The dry frame's zero-porosity end member is the self-consistent mix of grain and cement
    in proportions 1 - critical_porosity : critical_porosity, the mineral modulus the HS
    average in the rock's own proportions: near zero porosity the frame may exceed the
    mineral, by < 1e-4 for quartz cement (capped here), by up to 30 % for a cement much
    softer than the grain (refused by the caller: the model does not hold there)."""
    beta = _model4_solids(phi, phip)
    K_s, = _hs_average(K, G, beta, shear=False)
    if np.size(K_dry):
        most.append(float(np.max(K_dry / K_s)))
    K_dry = np.minimum(K_dry, K_s)
    K_sat = _gassmann(K_dry, K_s, K_f, phi)
    return _finish(K_dry, G_dry, K_sat, G_dry, _bulk_density(rho, beta, phi, rho_f))


def _model4_solids(phi, phip):
    r"""Model 4's solid fractions, grain and cement: :math:`1 - \beta_c` and
    :math:`\beta_c = \phi_p / (1 - \phi)` (clipped to [0, 1])."""
    beta_c = np.clip(phip / (1.0 - phi), 0.0, 1.0)
    return [1.0 - beta_c, beta_c]


def _refuse_frame_stiffer(K_dry, phi, phip, K, G):
    """Refuse Model 4 where its dry frame ``K_dry`` exceeds its mineral's bulk modulus by more
    than :data:`MAX_FRAME_EXCESS`, naming the point of the largest excess."""
    beta = _model4_solids(phi, phip)
    K_s, = _hs_average(K, G, np.broadcast_arrays(*beta), shear=False)
    excess = K_dry / K_s
    i = np.unravel_index(np.argmax(excess), excess.shape)
    raise ValueError(
        f"Model 4 does not hold at porosity {float(np.broadcast_to(phi, excess.shape)[i]):g}"
        f", cement_fraction {float(np.broadcast_to(phip, excess.shape)[i]):g}: its dry "
        f"frame ({float(K_dry[i]):.4g} GPa) is stiffer than the grain and cement it is made "
        f"of ({float(np.broadcast_to(K_s, excess.shape)[i]):.4g} GPa), as happens near zero "
        "porosity with a cement much softer than the grain")


#: The petro-elastic models by their label in datasets (coordinate ``model``).
MODELS = {
    "hs_gassmann": hs_gassmann,
    "self_consistent": self_consistent_model,
    "generalized_gassmann": generalized_gassmann_model,
    "patchy_cement": patchy_cement_model,
}
