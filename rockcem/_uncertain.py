"""Uncertain scene inputs: distributions in ``[uncertain]``, members sampled, quantiles out.

A scene's ``[uncertain]`` section gives numeric scene keys (``"section.key"``, as ``[sweep]``
names them) as probability distributions. :func:`rockcem._uncertain_keys.validate_uncertain`
checks it when the scene is loaded; :func:`sample_inputs` draws the members; :func:`evaluate_uncertain` runs them and
returns one Dataset whose variables carry a ``quantile`` dimension (and, with
``members = true``, every member as ``<name>_members`` along ``member``).

The TOML (``docs/user_guide/scenes.md``, section "Uncertain inputs")::

    [uncertain]
    samples = 1000             # members
    seed = 1                   # integer >= 0 (default 0)
    design = "lhs"             # "lhs" (default), "sobol" (samples a power of two), "random"
    quantiles = [0.1, 0.5, 0.9]
    members = false            # true: keep every member
    sensitivity = false        # true: Sobol' indices, samples the base N (_sobol_members)
    rank_correlations = [["path.gradient", "sandstone.grain_size", -0.3]]

    [uncertain."path.gradient"]
    distribution = "normal"    # normal: mean, sd; lognormal: median, sigma (sd of ln x);
    mean = 30.0                # uniform: lower, upper; triangular: lower, mode, upper
    sd = 2.0
    truncate = false           # true: cut the distribution at the key's valid range

Designs are those of :mod:`scipy.stats.qmc` (Latin hypercube, McKay et al. 1979; scrambled
Sobol', Owen 1998) or independent uniform draws, mapped to each distribution by the inverse of
its cumulative distribution function truncated to the key's valid range (Devroye 1986, ch. II.2,
inversion). Rank correlations are imposed by the method of Iman & Conover (1982), which
reorders each input's sampled values and so keeps its marginal sample (and a Latin hypercube's
stratification) exactly.

Members are evaluated in chunks (serially, or one chunk per dask task as sweep members are).
Within a chunk the burial kinetics of a linear path run once for all members (the burial
functions take per-member parameters as arrays: one path per member on the shared depth nodes;
a table path of horizons runs member by member) and the petro-elastic models, which are
pointwise in depth, run once on all the chunk's (member, depth) points; a scene whose pore
fluid varies with depth or holds a hydrocarbon runs each member through the scene runner
instead (:func:`rockcem.runner.evaluate`).

References
----------
Devroye, L. (1986). *Non-Uniform Random Variate Generation*. Springer, ch. II.2.

Hyndman, R. J. & Fan, Y. (1996). Sample quantiles in statistical packages. *The American
Statistician* 50(4), 361-365.

Iman, R. L. & Conover, W. J. (1982). A distribution-free approach to inducing rank correlation
among input variables. *Communications in Statistics - Simulation and Computation* 11(3),
311-334.

Jansen, M. J. W. (1999). Analysis of variance designs for model output. *Computer Physics
Communications* 117(1-2), 35-43.

McKay, M. D., Beckman, R. J. & Conover, W. J. (1979). A comparison of three methods for selecting
values of input variables in the analysis of output from a computer code. *Technometrics*
21(2), 239-245.

Owen, A. B. (1998). Scrambling Sobol' and Niederreiter-Xing points. *Journal of Complexity*
14(4), 466-489.

Rao, C. R. (1973). *Linear Statistical Inference and its Applications*, 2nd ed. Wiley,
sect. 6f.2.

Saltelli, A., Annoni, P., Azzini, I., Campolongo, F., Ratto, M. & Tarantola, S. (2010). Variance
based sensitivity analysis of model output. Design and estimator for the total sensitivity
index. *Computer Physics Communications* 181(2), 259-270.

Walker, A. M. (1968). A note on the asymptotic distribution of sample quantiles. *Journal of the
Royal Statistical Society B* 30(3), 570-575.
"""

from __future__ import annotations

import dataclasses
import inspect
import json
import re

import numpy as np

__all__ = ["DISTRIBUTIONS", "DESIGNS", "DEFAULT_QUANTILES", "MAX_OUTSIDE_MASS",
           "MAX_UNCERTAIN_BYTES", "sample_inputs", "evaluate_uncertain",
           "quantile_standard_error"]

#: Distributions and their parameters.
DISTRIBUTIONS = {"normal": ("mean", "sd"), "lognormal": ("median", "sigma"),
                 "uniform": ("lower", "upper"), "triangular": ("lower", "mode", "upper")}
#: Sampling designs (scipy.stats.qmc, or independent uniform draws).
DESIGNS = ("lhs", "sobol", "random")
#: Quantiles written when ``quantiles`` is not given.
DEFAULT_QUANTILES = (0.1, 0.5, 0.9)
#: Largest probability a distribution may put outside its key's valid range without
#: ``truncate = true``; below it the distribution is truncated there without a word (the
#: quantiles move by less than this in probability).
MAX_OUTSIDE_MASS = 1e-6
#: Most bytes the members' values may take in memory (every member of every variable is kept
#: until the quantiles are taken); a larger run is refused before any work.
MAX_UNCERTAIN_BYTES = 4 * 2 ** 30
#: Members per chunk (one task on a dask worker; the models run on all its points at once).
CHUNK_MEMBERS = 256


def _scipy_rng_keyword(cls):
    """The keyword a :mod:`scipy.stats.qmc` engine takes its generator by (``rng`` from SciPy
    1.15, ``seed`` before)."""
    return "rng" if "rng" in inspect.signature(cls).parameters else "seed"


def _range_text(rng):
    low, high, low_open, high_open, unit = rng
    text = f"{'(' if low_open else '['}{low:g}, {high:g}{')' if high_open else ']'}"
    return f"{text} {unit}".rstrip() if unit not in ("", "1") else text


def _frozen(dist, params):
    """The scipy.stats distribution of a validated entry."""
    from scipy import stats

    if dist == "normal":
        return stats.norm(loc=params["mean"], scale=params["sd"])
    if dist == "lognormal":
        return stats.lognorm(s=params["sigma"], scale=params["median"])
    if dist == "uniform":
        return stats.uniform(loc=params["lower"], scale=params["upper"] - params["lower"])
    width = params["upper"] - params["lower"]
    return stats.triang(c=(params["mode"] - params["lower"]) / width, loc=params["lower"],
                        scale=width)


def nominal_value(entry):
    """The median of an entry's (truncated) distribution: the value the scene's sections hold
    for an uncertain key (its fixed-value checks run on it)."""
    frozen = _frozen(entry["distribution"], entry)
    lo, hi = entry["cdf_range"]
    return _in_range(float(frozen.ppf(lo + 0.5 * (hi - lo))), entry["range"])


def _in_range(x, rng):
    """``x`` clipped into the closed or open range (rounding of the inverse CDF at its ends)."""
    low, high, low_open, high_open = rng
    lo = np.nextafter(low, np.inf) if low_open else low
    hi = np.nextafter(high, -np.inf) if high_open else high
    return np.clip(x, lo, hi)


def _design(spec):
    """``samples`` x ``len(keys)`` points in the unit hypercube, open at both ends."""
    from scipy.stats import qmc

    n, d = spec["samples"], len(spec["keys"])
    rng = np.random.default_rng(spec["seed"])
    if spec["design"] == "lhs":
        engine = qmc.LatinHypercube
        u = engine(d, **{_scipy_rng_keyword(engine): rng}).random(n)
    elif spec["design"] == "sobol":
        engine = qmc.Sobol
        u = engine(d, scramble=True, **{_scipy_rng_keyword(engine): rng}).random_base2(
            int(np.log2(n)))
    else:
        u = rng.random((n, d))
    tiny = np.finfo(float).tiny
    return np.clip(u, tiny, 1.0 - np.finfo(float).epsneg), rng


def iman_conover(x, target, rng):
    """Reorder the columns of ``x`` so that their rank correlation approaches ``target``.

    The method of Iman & Conover (1982), eqs. 3-4: van der Waerden scores
    :math:`\\Phi^{-1}(i/(n+1))`, independently permuted per column (``S``), are given the
    target correlation exactly, :math:`T = S (P^{-1})^T Q^T` with :math:`P P^T` the
    correlation of ``S`` and :math:`Q Q^T` the target (Cholesky factors); each column of
    ``x`` is then reordered to the ranks of the matching column of ``T``. The marginal samples
    are unchanged.

    Parameters
    ----------
    x : ndarray, shape (n, d)
    target : ndarray, shape (d, d)
        Target rank correlation matrix, positive definite.
    rng : numpy.random.Generator

    Returns
    -------
    ndarray, shape (n, d)
    """
    from scipy.stats import norm

    n, d = x.shape
    scores = norm.ppf(np.arange(1, n + 1) / (n + 1.0))
    S = np.column_stack([rng.permutation(scores) for _ in range(d)])
    P = np.linalg.cholesky(np.corrcoef(S, rowvar=False))
    Q = np.linalg.cholesky(np.asarray(target, dtype=float))
    T = S @ np.linalg.inv(P).T @ Q.T
    out = np.empty_like(x)
    for j in range(d):
        ranks = np.argsort(np.argsort(T[:, j]))
        out[:, j] = np.sort(x[:, j])[ranks]
    return out


def sample_inputs(spec):
    """The members' values of the uncertain keys: ``{dotted: ndarray (samples,)}``.

    Each key's design column :math:`u \\in (0, 1)` maps to
    :math:`x = F^{-1}(F(a) + u\\,[F(b) - F(a)])`, the inverse CDF of its distribution truncated
    to its valid range :math:`[a, b]` (inversion, Devroye 1986, ch. II.2); rank correlations,
    if any, by :func:`iman_conover`.
    """
    u, rng = _design(spec)
    cols = []
    for j, entry in enumerate(spec["keys"].values()):
        frozen = _frozen(entry["distribution"], entry)
        lo, hi = entry["cdf_range"]
        cols.append(_in_range(frozen.ppf(lo + u[:, j] * (hi - lo)), entry["range"]))
    x = np.column_stack(cols)
    if spec["correlation"] is not None:
        x = iman_conover(x, spec["correlation"], rng)
    return {k: x[:, j].copy() for j, k in enumerate(spec["keys"])}


def quantile_standard_error(p, n, density):
    """Asymptotic standard error of the sample ``p``-quantile of ``n`` independent draws.

    .. math:: \\mathrm{SE}(\\hat x_p) = \\frac{\\sqrt{p (1 - p) / n}}{f(x_p)}

    (Walker 1968, the asymptotic normality of a sample quantile; Rao 1973, sect. 6f.2), with
    :math:`f(x_p)` the probability density at the true quantile. A Latin hypercube of a
    monotone function of one input does far better (its error falls as :math:`1/n`).
    """
    p = np.asarray(p, dtype=float)
    return np.sqrt(p * (1.0 - p) / n) / np.asarray(density, dtype=float)


# ----------------------------------------------------------------------------- evaluation
def member_names(scene):
    """The member coordinate name of each uncertain key: the key (``grain_size``), or
    ``<section>_<key>`` where two keys share it (``hs_gassmann_A``)."""
    from .variables import sweep_dimension

    keys = list(scene.uncertain["keys"])
    short = [sweep_dimension(k) for k in keys]
    taken = {sweep_dimension(k) for k in scene.sweep} | {"quantile", "member"}
    return {k: (f"{k.rpartition('.')[0].rpartition('.')[2]}_{k.rpartition('.')[2]}"
                if short.count(s) > 1 or s in taken else s) for k, s in zip(keys, short)}


def _member_scene(scene, values):
    """The scene of one member: the uncertain keys set to ``values`` (floats), no
    ``[uncertain]`` (its sections are checked; the values lie in their keys' ranges)."""
    sections = {name: dict(sec) for name, sec in scene.sections.items()}
    for dotted, value in values.items():
        section, _, key = dotted.rpartition(".")
        sections[section][key] = float(value)
    return dataclasses.replace(scene, sections=sections, uncertain={}, sweep={})


def _describe(values, i):
    return ", ".join(f"{k} = {v[i]:.6g}" for k, v in values.items())


def _fast(scene):
    """Whether the members' models can run as one array of (member, depth) points: the pore
    fluid is one catalogue fluid (no [fluid] model that varies along depth, no hydrocarbon)."""
    f = scene.sections["fluid"]
    return f["model"] == "constant" and f["hydrocarbon"] == "none" and not scene.layers


def evaluate_chunk(scene, values):
    """Evaluate the members of one chunk.

    Parameters
    ----------
    scene : Scene
        A scene with ``[uncertain]`` and no sweep left.
    values : dict
        ``{dotted: ndarray (m,)}``, the chunk's members.

    Returns
    -------
    data : dict
        ``{name: (dims, ndarray (m, ...))}`` with dims ending in those of one member.
    warnings : list of list of str
        Each member's validity lines.
    """
    m = len(next(iter(values.values())))
    if not _fast(scene):
        return _evaluate_each(scene, values, m)
    try:
        return _evaluate_together(scene, values, m)
    except ValueError:       # find the member it concerns and say so
        return _evaluate_each(scene, values, m)


def _evaluate_each(scene, values, m):
    """Each member through the scene runner (one Dataset per member)."""
    from .runner import evaluate

    data, warnings = {}, []
    for i in range(m):
        member = _member_scene(scene, {k: v[i] for k, v in values.items()})
        try:
            ds = evaluate(member)
        except ValueError as exc:
            raise ValueError(f"uncertain member ({_describe(values, i)}): {exc}") from None
        for name, var in ds.data_vars.items():
            data.setdefault(name, (var.dims, []))[1].append(var.values)
        warnings.append([w for w in ds.attrs.get("validity_warnings", "").split("\n") if w])
    return {k: (dims, np.stack(v)) for k, (dims, v) in data.items()}, warnings


def _member_sections(scene, values):
    """The scene's sections with each uncertain key holding its members' values, an array."""
    sections = {name: dict(sec) for name, sec in scene.sections.items()}
    for dotted, v in values.items():
        section, _, key = dotted.rpartition(".")
        sections[section][key] = np.asarray(v, dtype=float)
    return sections


def _member_pipeline(scene, values):
    """A :class:`rockcem.runner._Pipeline` whose rock state holds every member of a chunk:
    arrays of shape (member, depth), from one call of each burial function on per-member
    parameters (the path of :func:`burial.linear_path` has the members on its leading axis)."""
    from functools import cached_property

    import burial

    from .runner import _Pipeline, _section

    class Members(_Pipeline):
        def _column(self, value):
            """A per-member parameter against the (member, depth) points."""
            return np.asarray(value, dtype=float)[..., None] if np.ndim(value) else value

        @cached_property
        def path(self):
            p = self.sec["path"]
            rate = p["sedimentation_rate"]
            if p["heating_rate"] is not None:
                G, H = np.asarray(p["gradient"]), np.asarray(p["heating_rate"])
                if np.any(H <= 0):
                    raise ValueError("scene key path.heating_rate must be > 0")
                rate = np.where(G > 0, H / np.where(G > 0, G, 1.0) * 1000.0, -1.0)
            members = np.broadcast_to(p["gradient"], (self.members,))   # a path per member
            with _section("path"):
                return burial.linear_path(members, rate, p["surface_temperature"],
                                          p["max_depth"], depth_step=p["depth_step"])

        def now(self, values):
            return values                   # every node of each member's path is its profile

        @cached_property
        def sandstone(self):
            s = self.lith
            with _section("sandstone"):
                igv = burial.intergranular_volume(
                    self._column(s["porosity0"]), self.pressures.max_effective,
                    self._column(s["igv_final"]), self._column(s["beta"]))
            return burial.sandstone_porosity(igv, self.quartz)

        @cached_property
        def shale_porosity(self):
            with _section("shale"):
                return burial.athy_porosity(self._column(self.lith["porosity0"]),
                                            self.pressures.max_effective,
                                            self._column(self.lith["beta"]))

    pipe = Members(dataclasses.replace(scene, sections=_member_sections(scene, values),
                                       uncertain={}, sweep={}))
    pipe.members = len(next(iter(values.values())))
    return pipe


class _Stacked:
    """The rock states of members run one by one (a table path), stacked along a leading
    member axis: what :func:`_member_pipeline` gives for a linear path."""

    def __init__(self, scene, values, m):
        from burial import Pressures
        from burial.compaction import SandstonePorosity

        pipes = [_plain_pipeline(_member_scene(scene, {k: v[i] for k, v in values.items()}))
                 for i in range(m)]
        self.pipes, p0 = pipes, pipes[0]
        self.lith = dict(p0.lith)
        self.lith["porosity0"] = np.array([p.lith["porosity0"] for p in pipes])
        self.path, self.materials, self.pore_fluid = p0.path, p0.materials, p0.pore_fluid
        self.porosity = np.stack([p.porosity for p in pipes])
        self.solid_fractions = np.stack([p.solid_fractions for p in pipes])
        self.pressures = Pressures(*(np.stack([getattr(p.pressures, f) for p in pipes])
                                     for f in Pressures._fields))
        if scene.lithology == "sandstone":
            self.sandstone = SandstonePorosity(*(np.stack([getattr(p.sandstone, f)
                                                           for p in pipes])
                                                 for f in SandstonePorosity._fields))

    def now(self, values):
        return self.pipes[0].now(values)

    def state_variable(self, name):
        return np.stack([np.asarray(p.state_variable(name)) for p in self.pipes])


def _plain_pipeline(scene):
    """The scene runner's pipeline of one scene (:class:`rockcem.runner._Pipeline`)."""
    from .runner import _Pipeline

    return _Pipeline(scene)


def _evaluate_together(scene, values, m):
    """The members' rock states in one pass of the burial functions (a linear path; member by
    member for a table path), their models once on all (member, depth) points."""
    data, checks = _chunk_arrays(scene, values, m)
    return data, _member_lines(checks)


def _chunk_arrays(scene, values, m, depths=slice(None)):
    """The outputs of a chunk's members at the depths ``depths`` (a slice of the depth axis;
    the rock states run down the whole path, the models only there), and what their validity
    rules look at there.

    Returns
    -------
    data : dict
        ``{name: (dims, ndarray (m, ..., k))}``, k the depths of the slice.
    checks : dict
        The inputs of :func:`rockcem.validity.validity_warnings` per member: ``depth`` (k,),
        ``porosity`` (m, k), ``porosity0`` (m,), ``pore_filled`` (m, k) or None, ``shear``
        ``{label: (G, G_supported)}`` each (m, k), ``models`` and the fluid's ``warnings``.
    """
    from burial import Pressures
    from burial.compaction import SandstonePorosity

    from .variables import MODEL_OUTPUTS

    if scene.sections["path"]["kind"] == "linear":
        states = _member_pipeline(scene, values)
    else:
        states = _Stacked(scene, values, m)
    state = [n for n in scene.outputs if n not in MODEL_OUTPUTS]
    wanted = [n for n in scene.outputs if n in MODEL_OUTPUTS]
    shape = states.porosity.shape
    data = {name: (("depth",), np.broadcast_to(states.state_variable(name), shape)[:, depths])
            for name in state}
    porosity = states.porosity[:, depths]
    n = porosity.shape[-1]
    sandstone = scene.lithology == "sandstone"
    results = {}
    flat = None
    if wanted:
        flat_sections = {name: dict(sec) for name, sec in scene.sections.items()}
        for dotted, v in values.items():          # one value per (member, depth) point
            section, _, key = dotted.rpartition(".")
            flat_sections[section][key] = np.repeat(np.asarray(v, dtype=float), n)
        flat = _plain_pipeline(dataclasses.replace(scene, sections=flat_sections, uncertain={}))
        points = (lambda a: np.ascontiguousarray(np.asarray(a)[:, depths]).reshape(m * n))
        flat.__dict__.update(
            porosity=points(states.porosity),
            solid_fractions=np.ascontiguousarray(
                states.solid_fractions[:, depths]).reshape(m * n, -1),
            pressures=Pressures(*(points(getattr(states.pressures, f))
                                  for f in Pressures._fields)),
            pore_fluid=states.pore_fluid, materials=states.materials)
        if sandstone:
            flat.__dict__["sandstone"] = SandstonePorosity(
                *(points(getattr(states.sandstone, f)) for f in SandstonePorosity._fields))
        results = {label: flat.model(label) for label in scene.models}
        for name in wanted:
            data[name] = (("model", "depth"), np.stack(
                [getattr(results[label], name).reshape(m, n) for label in scene.models],
                axis=1))
    # Validity, member by member, on what the member computed (rockcem.runner
    # _validity_warnings): Model 2's and 4's shear moduli sliced from the points.
    shear = {}
    if "self_consistent" in results:
        r = results["self_consistent"]
        shear["self_consistent"] = (r.G_sat.reshape(m, n), r.G_dry.reshape(m, n))
    if "patchy_cement" in results:
        shear["patchy_cement"] = (results["patchy_cement"].G_dry.reshape(m, n),
                                  flat._model("patchy_cement", flat.pore_fluid.fluid,
                                              delta=0.0).G_dry.reshape(m, n))
    depth = np.asarray(states.now(states.path.depth))
    depth = depth[0] if depth.ndim == 2 else depth          # the depths every member shares
    return data, {
        "depth": depth[depths], "porosity": porosity,
        "porosity0": np.broadcast_to(states.lith["porosity0"], (m,)),
        "pore_filled": states.sandstone.pore_filled[:, depths] if sandstone else None,
        "shear": shear, "models": tuple(scene.models) if wanted else (),
        "warnings": list(states.pore_fluid.warnings)}


def _member_lines(checks):
    """Each member's validity lines (:func:`rockcem.validity.validity_warnings`) from the
    ``checks`` of :func:`_chunk_arrays` (or :func:`_unmasked`)."""
    from .validity import validity_warnings

    lines = []
    for i in range(len(checks["porosity0"])):
        lines.append(validity_warnings(
            checks["depth"], checks["porosity"][i], porosity0=float(checks["porosity0"][i]),
            models=checks["models"],
            pore_filled=None if checks["pore_filled"] is None else checks["pore_filled"][i],
            shear_moduli={k: (a[i], b[i]) for k, (a, b) in checks["shear"].items()})
            + checks["warnings"])
    return lines


def _masked(checks):
    """The ``checks`` of :func:`_chunk_arrays` reduced to where each validity rule holds, one
    bit per (member, depth): ``{rule: packed bits (m, ceil(k / 8))}`` and the rest as is.

    The rules are those of :func:`rockcem.validity.validity_warnings` (with its constants):
    Krief's frame where the porosity exceeds :data:`rockcem.validity.KRIEF_LOOSE_FRACTION` of
    the depositional porosity, Models 2 and 4 where the supported shear modulus is below
    ``1 - ASSUMPTION_SHEAR_FRACTION`` of the model's, the cement where it fills the pores.
    """
    from .validity import ASSUMPTION_SHEAR_FRACTION, KRIEF_LOOSE_FRACTION

    limit = KRIEF_LOOSE_FRACTION * np.asarray(checks["porosity0"], dtype=float)[:, None]
    rules = {"krief": checks["porosity"] > limit}
    for label, (G, supported) in checks["shear"].items():
        rules[label] = supported < (1.0 - ASSUMPTION_SHEAR_FRACTION) * G
    if checks["pore_filled"] is not None:
        rules["pore_filled"] = np.asarray(checks["pore_filled"]).astype(bool)
    return {"depths": checks["porosity"].shape[-1],
            "bits": {rule: np.packbits(mask, axis=-1) for rule, mask in rules.items()},
            **{k: checks[k] for k in ("depth", "porosity0", "models", "warnings")}}


def _unmasked(parts):
    """The ``checks`` of the whole depth axis from the :func:`_masked` parts of its slices (in
    depth order): arrays that meet each rule exactly where the masks hold (porosity 1 or 0
    against the Krief limit below 1; shear moduli 1 and 0 or 1; the pore-filled flags), so
    :func:`_member_lines` gives each member's lines as its own values would."""
    masks = {rule: np.concatenate([np.unpackbits(p["bits"][rule], axis=-1,
                                                 count=p["depths"]).astype(bool)
                                   for p in parts], axis=-1) for rule in parts[0]["bits"]}
    ones = np.ones(masks["krief"].shape)
    return {"depth": np.concatenate([p["depth"] for p in parts]),
            "porosity": np.where(masks["krief"], 1.0, 0.0),
            "porosity0": parts[0]["porosity0"], "models": parts[0]["models"],
            "pore_filled": masks.get("pore_filled"),
            "shear": {label: (ones, np.where(masks[label], 0.0, 1.0))
                      for label in masks if label not in ("krief", "pore_filled")},
            "warnings": parts[0]["warnings"]}


#: A number in a validity line: a member's depths, and thresholds that follow its inputs
#: (Krief's porosity limit is a fraction of the member's depositional porosity).
_NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")


def _merge_member_warnings(per_member, total):
    """Each validity rule once, with the number of members it concerns.

    Two members' lines belong to one rule when they name the same models and differ only in
    the numbers after the " at ": the depth interval, and a threshold that follows the member's inputs (Krief's porosity limit, a
    fraction of the member's ``sandstone.porosity0``). The line shown is that of the first
    member the rule concerns, named, with its own depths and values."""
    groups = {}
    for i, lines in enumerate(per_member):
        for line in lines:
            head, at, tail = line.partition(" at ")  # the head names the model: kept whole
            where, colon, why = tail.partition(":")  # one depth or an interval
            key = head + at + colon + _NUMBER.sub("#", why) if colon else line
            groups.setdefault(key, []).append((i, line))
    return [f"[{len(hits)} of {total} members; depths and values of member {hits[0][0]}] "
            f"{hits[0][1]}" for hits in groups.values()]


#: Outputs given Sobol' indices with ``sensitivity = true`` (those of the scene's outputs).
SOBOL_OUTPUTS = ("temperature", "porosity", "density", "vp", "vs")
#: An output whose standard deviation among the members is below this fraction of its mean
#: magnitude does not vary: its indices are undefined and written as NaN.
SOBOL_MIN_RELATIVE_SD = 1e-12


class _TruncatedInverse:
    """The inverse CDF of an entry's distribution truncated to its key's valid range, the map
    :func:`sample_inputs` uses (Devroye 1986, ch. II.2): the ``dists`` item
    :func:`scipy.stats.sobol_indices` draws its design through."""

    def __init__(self, entry):
        self.frozen = _frozen(entry["distribution"], entry)
        self.lo, self.hi = entry["cdf_range"]
        self.range = entry["range"]

    def ppf(self, u):
        u = np.clip(u, np.finfo(float).tiny, 1.0 - np.finfo(float).epsneg)
        return _in_range(self.frozen.ppf(self.lo + u * (self.hi - self.lo)), self.range)


def _sobol_members(scene, scheduler, progress):
    """The members of the Saltelli design and the Sobol' indices of :data:`SOBOL_OUTPUTS`.

    :func:`scipy.stats.sobol_indices` draws two independent matrices A and B of ``samples``
    = N members each (the halves of one scrambled Sobol' sequence in 2d dimensions, mapped
    through :class:`_TruncatedInverse`) and the d matrices A_B^(i) (A with its i-th input
    taken from B): N (d + 2) members in all, run by :func:`_run_members`. The first-order
    index is Saltelli et al. (2010)'s estimator (their Table 2 (b)),
    :math:`S_i = \\frac{1}{N} \\sum_j f(B)_j [f(A_B^{(i)})_j - f(A)_j] / V`, and the total
    index Jansen (1999)'s (Saltelli et al. 2010, Table 2 (f)),
    :math:`S_{Ti} = \\frac{1}{2N} \\sum_j [f(A)_j - f(A_B^{(i)})_j]^2 / V`, with V the variance
    of the 2N members of A and B.

    Returns
    -------
    values : dict
        ``{dotted: ndarray (2N,)}``, the inputs of the members of A and B.
    data, warnings
        Those members' outputs and validity lines, as :func:`_run_members` gives them.
    sobol : dict
        ``{name: (dims, first, total, first_se, total_se)}``, the indices and their standard
        errors (:func:`_sobol_standard_errors`), each of shape ``(d, ...)`` over the output's
        dims: NaN where the output does not vary among the members of A and B (relative
        standard deviation below :data:`SOBOL_MIN_RELATIVE_SD`).
    """
    spec = scene.uncertain
    keys = list(spec["keys"])
    d, N = len(keys), spec["samples"]
    runs = []

    def func(x):                        # x: (d, n) inputs; (s, n) outputs
        values = {k: np.asarray(x[j], dtype=float) for j, k in enumerate(keys)}
        data, warnings = _run_members(scene, values, scheduler, progress, planned=N * (d + 2))
        runs.append((values, data, warnings))
        n = x.shape[1]
        return np.concatenate([np.asarray(data[name][1], dtype=float).reshape(n, -1)
                               for name in names], axis=1).T

    names = [n for n in SOBOL_OUTPUTS if n in scene.outputs]
    if not names:
        raise ValueError("scene key uncertain.sensitivity = true needs one of the outputs "
                         f"{', '.join(SOBOL_OUTPUTS)} in [output]")
    first, total, first_se, total_se = saltelli_indices(func, list(spec["keys"].values()), N,
                                                        spec["seed"])
    (va, da, wa), (vb, db, wb) = runs[0], runs[1]
    values = {k: np.concatenate([va[k], vb[k]]) for k in keys}
    data = {name: (dims, np.concatenate([a, db[name][1]])) for name, (dims, a) in da.items()}
    sobol, at = {}, 0
    for name in names:
        dims, a = data[name]
        shape = a.shape[1:]
        size = int(np.prod(shape))
        flat = np.asarray(a, dtype=float).reshape(2 * N, size)
        still = flat.std(axis=0) <= SOBOL_MIN_RELATIVE_SD * np.abs(flat.mean(axis=0))
        parts = []
        for block in (first, total, first_se, total_se):
            part = block[at:at + size].copy()
            part[still] = np.nan
            parts.append(np.moveaxis(part, -1, 0).reshape((d,) + shape))
        sobol[name] = (dims, *parts)
        at += size
    return values, data, wa + wb, sobol


def saltelli_indices(func, entries, N, seed):
    """First-order and total Sobol' indices of ``func``'s outputs and their standard errors:
    the estimator every scene with ``sensitivity = true`` runs (:func:`_sobol_members`).

    :func:`scipy.stats.sobol_indices` evaluates ``func`` on A, B (N rows each, the halves of
    one scrambled Sobol' sequence in 2d dimensions, mapped through :class:`_TruncatedInverse`)
    and the d matrices A_B^(i), N (d + 2) rows; the first-order index is Saltelli et al.
    (2010)'s estimator (Table 2 (b)), the total index Jansen (1999)'s (Saltelli et al. 2010,
    Table 2 (f)); the standard errors are :func:`_sobol_standard_errors`'.

    Parameters
    ----------
    func : callable
        ``func(x)`` with ``x`` of shape (d, n), the inputs of n rows, returns (s, n): s outputs.
    entries : list of dict
        The d inputs' checked ``[uncertain]`` entries (distribution, parameters, ``cdf_range``,
        ``range``).
    N : int
        Base sample size, a power of two.
    seed : int
        Seed of the design's generator.

    Returns
    -------
    first, total, first_se, total_se : ndarray, shape (s, d)
    """
    from scipy.stats import sobol_indices

    outs = []

    def kept(x):
        outs.append(np.asarray(func(x), dtype=float))
        return outs[-1]

    d = len(entries)
    # the generator's keyword: rng from SciPy 1.15, random_state before
    keyword = "rng" if "rng" in inspect.signature(sobol_indices).parameters else "random_state"
    result = sobol_indices(func=kept, n=N, dists=[_TruncatedInverse(e) for e in entries],
                           **{keyword: np.random.default_rng(seed)})
    first = np.reshape(result.first_order, (-1, d))
    total = np.reshape(result.total_order, (-1, d))
    return (first, total, *_sobol_standard_errors(outs[0], outs[1], outs[2]))


def _sobol_standard_errors(f_A, f_B, f_AB_columns):
    """Standard errors of the Saltelli and Jansen estimators, ``(first, total)`` of shape
    ``(s, d)``.

    Each index is a mean over the N rows of the design divided by the variance V of the outputs
    of A and B (:func:`_sobol_members`): :math:`S_i = \\bar y_i / V` with
    :math:`y_{ij} = f(B)_j [f(A_B^{(i)})_j - f(A)_j]`, :math:`S_{Ti} = \\bar z_i / V` with
    :math:`z_{ij} = [f(A)_j - f(A_B^{(i)})_j]^2 / 2` (outputs centred on their mean over A and
    B, as :func:`scipy.stats.sobol_indices` does). The standard error given is that of the mean,
    :math:`s_y / (\\sqrt{N}\\, V)` with :math:`s_y` the sample standard deviation of the
    :math:`y_{ij}` (the central limit theorem for independent rows), V taken as exact. The
    design's rows are scrambled Sobol' points, not independent: their mean errs less, and this
    is then an upper estimate (at N = 256 the temperature's indices, an additive closed form,
    lay within 0.35 of it from the exact values over 20 seeds; tests/test_uncertain_sobol.py).

    Parameters
    ----------
    f_A, f_B : ndarray, shape (s, N)
        The outputs of A and B.
    f_AB_columns : ndarray, shape (s, N d)
        The outputs of the matrices A_B^(i) in the column order
        :func:`scipy.stats.sobol_indices` evaluates them (row j of page i at column j d + i).
    """
    s, N = f_A.shape
    f_AB = np.moveaxis(f_AB_columns.reshape(s, N, -1), -1, 0)           # (d, s, N)
    mean = np.mean([f_A, f_B], axis=(0, -1))[:, None]
    f_A, f_B, f_AB = f_A - mean, f_B - mean, f_AB - mean
    V = np.var([f_A, f_B], axis=(0, -1))
    y = f_B * (f_AB - f_A)
    z = 0.5 * (f_A - f_AB) ** 2
    with np.errstate(divide="ignore", invalid="ignore"):
        first = y.std(axis=-1, ddof=1) / (np.sqrt(N) * V)
        total = z.std(axis=-1, ddof=1) / (np.sqrt(N) * V)
    return first.T, total.T


def _quantiles(a, q):
    """``numpy.quantile(a, q, axis=0)`` (linear, Hyndman & Fan 1996 type 7) of the members on
    the first axis, taken on a copy with the members last (contiguous: the partition runs
    along memory, a quarter faster; the same numbers)."""
    members_last = np.ascontiguousarray(np.moveaxis(np.asarray(a, dtype=float), 0, -1))
    return np.quantile(members_last, q, axis=-1)


#: Most bytes of members' values one depth slice holds on a dask worker
#: (:func:`_quantiles_by_depth`); more slices are made for a larger run.
SLICE_BYTES = 256 * 2 ** 20


def _slice_quantiles(scene, values, depths, q, members_per_call=CHUNK_MEMBERS, bottom=None):
    """Every member at the depths ``depths`` (a slice of the depth axis): the quantiles ``q``
    of each output there, and the member's validity masks there (:func:`_masked`).

    The members run ``members_per_call`` at a time (:func:`_chunk_arrays`: the rock states
    down to the slice, the models at its depths only); with ``bottom``, the depth of the
    slice's last node, a linear path is made down to there only (the same nodes and, the
    kinetics being integrals from the surface, the same values above it). A quantile at a
    depth is a function of all members' values at that depth alone, so the slice's quantiles
    are exactly those of the whole run there.
    """
    if bottom is not None and scene.sections["path"]["kind"] == "linear":
        sections = dict(scene.sections, path=dict(scene.sections["path"], max_depth=bottom))
        scene = dataclasses.replace(scene, sections=sections)
    N = len(next(iter(values.values())))
    out, parts = {}, []
    for a in range(0, N, members_per_call):
        b = min(a + members_per_call, N)
        data, checks = _chunk_arrays(scene, {k: v[a:b] for k, v in values.items()}, b - a,
                                     depths)
        for name, (dims, arr) in data.items():
            out.setdefault(name, (dims, np.empty((N,) + arr.shape[1:])))[1][a:b] = arr
        parts.append(_masked(checks))
    quantiles = {name: (dims, _quantiles(a, q)) for name, (dims, a) in out.items()}
    masks = dict(parts[0], porosity0=np.concatenate([p["porosity0"] for p in parts]),
                 bits={rule: np.concatenate([p["bits"][rule] for p in parts])
                       for rule in parts[0]["bits"]})
    return quantiles, masks


def _quantiles_by_depth(scene, values, q, scheduler, progress):
    """The quantiles of every output on dask without every member's values coming back: one
    task per slice of the depth axis runs all members there (:func:`_slice_quantiles`) and
    returns the quantiles of its depths and one bit per (member, depth, validity rule).

    Quantiles of member chunks do not merge into those of all members; quantiles of depth
    slices put side by side are those of the whole run, exactly. Each task recomputes the
    members' rock states down to its slice (the kinetics integrate from the surface) and runs
    the models only at its depths. There are twice as many
    slices as the cluster has worker threads (to balance the load), more if a slice would
    hold more than :data:`SLICE_BYTES` of members' values.

    Returns
    -------
    quantiles : dict
        ``{name: (dims, ndarray (len(q), ..., depth))}``.
    warnings : list of list of str
        Each member's validity lines, as the serial run gives them.
    """
    import math

    from ._scheduler import dask_client

    N = len(next(iter(values.values())))
    first = _chunk_arrays(scene, {k: v[:1] for k, v in values.items()}, 1)[0]
    depth = _template(scene)["depth"][1]
    n = len(depth)
    per_depth = sum(a.size for _dims, a in first.values()) / n
    if 8 * per_depth * N > MAX_UNCERTAIN_BYTES:
        raise ValueError(f"scene [uncertain]: {N} members take {8 * per_depth * N / 2 ** 30:.3g}"
                         f" GiB at one depth, above {MAX_UNCERTAIN_BYTES / 2 ** 30:g} GiB on a "
                         "worker; lower uncertain.samples or ask fewer outputs")
    with dask_client(scheduler, 2, what="running uncertain members on dask") as client:
        from dask.distributed import as_completed

        threads = max(1, sum(client.nthreads().values()))
        k = min(n, max(2 * threads, math.ceil(8 * per_depth * N * n / SLICE_BYTES)))
        bounds = np.linspace(0, n, k + 1).round().astype(int)
        slices = [slice(int(a), int(b)) for a, b in zip(bounds, bounds[1:])]
        # As many (member, depth) points per call of the models as the serial run's chunks
        # (Model 2's numba kernel takes over from 5e4 points), and each path only down to
        # its slice.
        per_call = [max(CHUNK_MEMBERS, CHUNK_MEMBERS * n // (sl.stop - sl.start))
                    for sl in slices]
        bottoms = [float(depth[sl.stop - 1]) for sl in slices]
        futures = client.map(_slice_quantiles, [scene] * k, [values] * k, slices, [q] * k,
                             per_call, bottoms, pure=False)
        where = {f.key: i for i, f in enumerate(futures)}
        if progress:
            from dask.distributed import progress as dask_progress

            dask_progress(futures)
        parts = [None] * k
        for future, part in as_completed(futures, with_results=True):
            parts[where[future.key]] = part
            future.release()
    quantiles = {name: (dims, np.concatenate([p[0][name][1] for p in parts], axis=-1))
                 for name, (dims, _a) in parts[0][0].items()}
    return quantiles, _member_lines(_unmasked([p[1] for p in parts]))


def _run_members(scene, values, scheduler, progress, planned=None):
    """Evaluate the members ``values`` (``{dotted: ndarray (N,)}``) in chunks of
    :data:`CHUNK_MEMBERS`, serially or on dask: ``({name: (dims, ndarray (N, ...))}``, each
    member's validity lines). A run whose ``planned`` members (default N) would take more
    than :data:`MAX_UNCERTAIN_BYTES` is refused after one member."""
    N = len(next(iter(values.values())))
    planned = N if planned is None else planned
    bounds = list(range(0, N, CHUNK_MEMBERS)) + [N]
    chunks = [{k: v[a:b] for k, v in values.items()} for a, b in zip(bounds, bounds[1:])]
    first = evaluate_chunk(scene, {k: v[:1] for k, v in values.items()})
    per_member = sum(a.size for _dims, a in first[0].values())
    if 8 * per_member * planned > MAX_UNCERTAIN_BYTES:
        raise ValueError(f"scene [uncertain]: {planned} members of {per_member} values each "
                         f"take "
                         f"{8 * per_member * planned / 2 ** 30:.3g} GiB, above "
                         f"{MAX_UNCERTAIN_BYTES / 2 ** 30:g} GiB; lower uncertain.samples, "
                         "raise path.depth_step or ask fewer outputs")
    # Every member's values go straight into one array per variable (no copy of them all).
    data = {name: (dims, np.empty((N,) + a.shape[1:], dtype=a.dtype))
            for name, (dims, a) in first[0].items()}
    warnings = [None] * N

    def put(index, part):
        lo, hi = bounds[index], bounds[index + 1]
        for name, (_dims, a) in part[0].items():
            data[name][1][lo:hi] = a
        warnings[lo:hi] = part[1]

    if scheduler is None:
        order = range(len(chunks))
        if progress:
            from tqdm.auto import tqdm

            order = tqdm(order, desc=scene.name, unit="chunk")
        for index in order:
            put(index, evaluate_chunk(scene, chunks[index]))
    else:
        from ._scheduler import dask_client

        with dask_client(scheduler, 2, what="running uncertain members on dask") as client:
            from dask.distributed import as_completed

            futures = client.map(evaluate_chunk, [scene] * len(chunks), chunks, pure=False)
            where = {f.key: i for i, f in enumerate(futures)}
            if progress:
                from dask.distributed import progress as dask_progress

                dask_progress(futures)
            for future, part in as_completed(futures, with_results=True):
                put(where[future.key], part)
                future.release()
    return data, warnings


def evaluate_uncertain(scene, *, scheduler=None, progress=False):
    """Run the members of a scene with ``[uncertain]``: one Dataset of quantiles.

    Every output variable gains a leading ``quantile`` dimension (the sample quantiles of the
    members, ``numpy.quantile``'s default linear interpolation between order statistics,
    Hyndman & Fan 1996 type 7); with ``members = true`` each is kept too, as
    ``<name>_members`` along ``member``, with the sampled inputs as ``member`` coordinates.
    With ``sensitivity = true`` the members are those of the Saltelli design
    (:func:`_sobol_members`, N (d + 2) of them), the quantiles those of its 2N members A and
    B, and the Sobol' indices of :data:`SOBOL_OUTPUTS` are added as ``<name>_sobol_first``
    and ``<name>_sobol_total`` along ``input``.

    Parameters
    ----------
    scene : Scene
    scheduler : None, "local" or str, keyword-only
        Where the members run (:func:`rockcem.scene.run_scene`): on dask without ``members``
        or ``sensitivity``, one task per slice of the depth axis that returns its quantiles
        only (:func:`_quantiles_by_depth`), else one task per chunk of members.
    progress : bool, keyword-only
        A progress bar over the chunks (or slices).

    Returns
    -------
    xarray.Dataset
        The quantiles (and members) of every output, with the scene's attributes.

    Raises
    ------
    ValueError
        A member outside a model's range (naming its sampled inputs), or a run whose members
        would take more than :data:`MAX_UNCERTAIN_BYTES` of memory.
    """
    import xarray as xr

    from .runner import _global_attrs
    from .variables import build_dataset, no_coordinate_fill

    spec = scene.uncertain
    sobol = None
    q = np.asarray(spec["quantiles"])
    by_depth = (scheduler is not None and not spec.get("sensitivity") and not spec["members"]
                and _fast(scene))                 # on dask, only the quantiles come back
    if spec.get("sensitivity"):
        values, data, warnings, sobol = _sobol_members(scene, scheduler, progress)
    elif by_depth:
        values = sample_inputs(spec)
        quantiles, warnings = _quantiles_by_depth(scene, values, q, scheduler, progress)
    else:
        values = sample_inputs(spec)
        data, warnings = _run_members(scene, values, scheduler, progress)
    N = len(warnings)
    template = _template(scene)
    if not by_depth:
        quantiles = {name: (dims, _quantiles(a, q)) for name, (dims, a) in data.items()}
    out = {name: (("quantile",) + dims, a) for name, (dims, a) in quantiles.items()}
    names = member_names(scene)
    if spec["members"]:
        out.update({f"{name}_members": (("member",) + dims, a)
                    for name, (dims, a) in data.items()})
    coords = dict(template)
    coords["quantile"] = (("quantile",), q)
    if spec["members"]:
        coords["member"] = (("member",), np.arange(N))
        for dotted, name in names.items():
            coords[name] = (("member",), values[dotted])
    attrs = _global_attrs(scene)
    attrs.update(_uncertain_attrs(scene, names))
    lines = _merge_member_warnings(warnings, N)
    if lines:
        attrs["validity_warnings"] = "\n".join(lines)
    ds = build_dataset({}, coords, attrs)
    for name, (dims, a) in out.items():
        base = name.removesuffix("_members")
        ds[name] = xr.Variable(dims, a, attrs=_variable_attrs(base, name != base))
    ds["quantile"].attrs.update(QUANTILE_ATTRS)
    if sobol is not None:
        _add_sobol(ds, scene, sobol)
    if spec["members"]:
        ds["member"].attrs["long_name"] = "member of the uncertain inputs"
        for dotted, name in names.items():
            ds[name].attrs.update(_input_attrs(dotted, scene.uncertain["keys"][dotted]))
    if "model" in ds.coords:
        from .runner import _MODEL_LABELS_LONG

        ds["model"].attrs["description"] = "; ".join(
            f"{m}: {_MODEL_LABELS_LONG[m]}" for m in scene.models)
    return no_coordinate_fill(ds)


def _add_sobol(ds, scene, sobol):
    """``<name>_sobol_first`` and ``<name>_sobol_total`` along ``input`` (the dotted keys)."""
    import xarray as xr

    spec = scene.uncertain
    d, N = len(spec["keys"]), spec["samples"]
    ds.coords["input"] = ("input", np.array(list(spec["keys"]), dtype=object))
    ds["input"].attrs["long_name"] = "uncertain input (scene key)"
    note = (f"{N * (d + 2)} members: the Saltelli design of base N = {N} (A, B and the {d} "
            "matrices A_B^(i), scipy.stats.sobol_indices); NaN where the output does not vary "
            "among the members")
    for name, (dims, first, total, first_se, total_se) in sobol.items():
        for kind, a, se, what, source in (
                ("first", first, first_se, "first-order", "Saltelli et al. (2010), Table 2 (b)"),
                ("total", total, total_se, "total",
                 "Jansen (1999); Saltelli et al. (2010), Table 2 (f)")):
            ds[f"{name}_sobol_{kind}"] = xr.Variable(("input",) + dims, a, attrs={
                "long_name": f"{what} Sobol' index of {name}",
                "units": "1",
                "description": f"estimator of {source}; {note}; its standard error is "
                               f"{name}_sobol_{kind}_se"})
            ds[f"{name}_sobol_{kind}_se"] = xr.Variable(("input",) + dims, se, attrs={
                "long_name": f"standard error of the {what} Sobol' index of {name}",
                "units": "1",
                "description": "standard deviation of the estimator's N summands over sqrt(N), "
                               "divided by the output's variance (central limit theorem for "
                               "independent rows, the variance taken as exact); the design's "
                               "scrambled Sobol' rows err less (tests/test_uncertain_sobol.py)"})


#: Attributes of the quantile coordinate: what the numbers mean, and the industry's P-names.
QUANTILE_ATTRS = {
    "long_name": "quantile of the members",
    "units": "1",
    "description": (
        "probability of non-exceedance: at quantile 0.1 a tenth of the members lie below the "
        "value (the sample quantile of the members, numpy.quantile linear, Hyndman & Fan 1996 "
        "type 7). The industry's P90 often means 90 % probability of exceedance, the low "
        "case: that is quantile 0.1 here; its P10, the high case, is quantile 0.9"),
}


def _variable_attrs(name, members):
    from .variables import variable_attrs

    try:
        attrs = dict(variable_attrs(name))
    except ValueError:
        attrs = {}
    attrs.pop("flag_values", None)
    attrs.pop("flag_meanings", None)
    attrs["cell_methods"] = "member: point" if members else "member: quantile"
    return attrs


def _input_attrs(dotted, entry):
    """Attributes of a sampled input's member coordinate: its unit and description as the
    scene's schema gives them (recorded in the entry when the section was checked)."""
    return {"long_name": f"sampled {dotted}: {entry['doc']}", "units": entry["unit"] or "1"}


def _template(scene):
    """The depth (and horizon, model) coordinates every member shares."""
    from .runner import _Pipeline
    from .variables import MODEL_OUTPUTS

    pipe = _Pipeline(_member_scene(scene, {k: nominal_value(e)
                                           for k, e in scene.uncertain["keys"].items()}))
    coords = {"depth": (("depth",), pipe.now(pipe.path.depth))}
    if scene.sections["path"]["kind"] == "horizons":
        coords["horizon"] = (("depth",), pipe.history.horizon.astype(object))
    if any(n in MODEL_OUTPUTS for n in scene.outputs):
        coords["model"] = (("model",), np.array(scene.models, dtype=object))
    return coords


def _uncertain_attrs(scene, names):
    spec = scene.uncertain
    design = {"lhs": "Latin hypercube (scipy.stats.qmc.LatinHypercube)",
              "sobol": "scrambled Sobol' (scipy.stats.qmc.Sobol)",
              "random": "independent uniform draws"}[spec["design"]]
    keys = "; ".join(
        f"{k} ({names[k]}): {e['distribution']}("
        + ", ".join(f"{p} {e[p]:g}" for p in DISTRIBUTIONS[e["distribution"]])
        + f") in {_range_text((*e['range'], ''))}"
        + (f", truncated ({e['outside']:.3g} of its probability cut)" if e["outside"] > 0 else "")
        for k, e in spec["keys"].items())
    return {
        "uncertain": ((f"{spec['samples']} members, {design}, seed {spec['seed']}; the "
                       if not spec.get("sensitivity") else
                       f"{2 * spec['samples']} members (A and B of the Saltelli design of "
                       f"base N = {spec['samples']}, scrambled Sobol' points), seed "
                       f"{spec['seed']}; the ") +
                      "variables are quantiles of the members along 'quantile' (probability "
                      "of non-exceedance: quantile 0.1 is the industry's P90, the low case, "
                      f"when P means probability of exceedance); inputs: {keys}"
                      + ("; rank correlations by Iman & Conover (1982)"
                         if spec["correlation"] is not None else "")),
        "uncertain_json": json.dumps({k: v for k, v in spec.items()}, sort_keys=True),
    }
