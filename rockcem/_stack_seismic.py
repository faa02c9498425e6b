"""The seismic join of a stack scene (``[seismic]``; issue 31): reflectivity against angle,
intercept, gradient and AVO class at every interface, depth, model and fluid, and the
synthetics of the layered column.

Private to the scene runner. The physics is :mod:`rockcem.reflectivity` ([Zoeppritz1919]_ in
the form of eq. 5.40 of [AkiRichards1980]_; [Shuey1985]_; the classes of
[RutherfordWilliams1989]_, [RossKinman1995]_ and [CastagnaSwan1997]_) and
:mod:`rockcem.synthetics` (depth to two-way time, the wavelet of [Ricker1953]_, the
convolutional model of [Yilmaz2001]_); this module only feeds them both sides of each interface
(:func:`rockcem._stack_dataset.interface_properties`) and the column, and names the results.

The interface is swept along depth ([AvsethLehocki2016]_): at depth ``z`` the upper layer's
rock and the lower layer's rock are both the rock their burial models give at ``z``, as if the
interface lay at ``z``. A depth where either side has no value (a model that is out of its
range there) gets NaN, counted in the variable's ``missing_inputs`` attribute.
"""

from __future__ import annotations

import numpy as np

__all__ = ["ANGLE_ATTRS", "add_seismic", "reflect", "seismic_attrs"]

_SIDES = ("vp1", "vs1", "rho1", "vp2", "vs2", "rho2")


def _angles(seismic):
    step, top = seismic["angle_step"], seismic["max_angle"]
    n = int(np.floor(top / step + 1e-9))
    return np.round(np.arange(n + 1) * step, 12)


def _valid(arrays):
    """Where both sides hold a rock the reflectivity functions take (finite, positive, a
    solid's S velocity)."""
    ok = np.ones(arrays[0].shape, dtype=bool)
    for a in arrays:
        ok &= np.isfinite(a) & (a > 0)
    return ok


#: Attributes of the ``angle`` coordinate.
ANGLE_ATTRS = {"units": "degree", "long_name": "angle of incidence"}


def reflect(arrays, angles, threshold):
    """The reflectivity variables of interface samples: both sides ``arrays`` (``vp1, vs1,
    rho1, vp2, vs2, rho2``, each of one shape S) at ``angles`` (degrees).

    The exact PP coefficient (:func:`rockcem.reflectivity.zoeppritz_pp`: [Zoeppritz1919]_,
    eq. 5.40 of [AkiRichards1980]_), Shuey's A, B and C of the Aki-Richards linearisation
    (:func:`rockcem.reflectivity.intercept_gradient`: [Shuey1985]_, eq. 5.44 of
    [AkiRichards1980]_) and the AVO class (:func:`rockcem.reflectivity.avo_class`); a sample
    where either side has no rock (:func:`_valid`) gets NaN and class 0.

    Returns
    -------
    dict
        ``reflectivity_pp`` and ``reflectivity_pp_magnitude`` (S + (angle,)),
        ``avo_intercept``, ``avo_gradient``, ``avo_curvature`` (S), ``avo_class`` (S, int8)
        and ``missing`` (the count of samples without a rock on one side, and of all).
    """
    from .reflectivity import avo_class, intercept_gradient, zoeppritz_pp

    ok = _valid(arrays)
    picked = [a[ok] for a in arrays]
    shape = ok.shape
    r = np.full(shape + (angles.size,), np.nan + 0j)
    r[ok] = zoeppritz_pp(*(p[:, None] for p in picked), angles[None, :])
    terms = intercept_gradient(*picked)
    out = {"reflectivity_pp": r.real, "reflectivity_pp_magnitude": np.abs(r)}
    for name, values in (("avo_intercept", terms.intercept), ("avo_gradient", terms.gradient),
                         ("avo_curvature", terms.curvature)):
        full = np.full(shape, np.nan)
        full[ok] = values
        out[name] = full
    codes = np.zeros(shape, dtype=np.int8)
    codes[ok] = avo_class(terms.intercept, terms.gradient, threshold=threshold)
    out["avo_class"] = codes
    out["missing"] = (int(np.count_nonzero(~ok)), ok.size)
    return out


def seismic_attrs(missing, threshold):
    """The attributes of the variables of :func:`reflect`; ``missing`` its count of samples
    without a rock on one side, and of all."""
    from .reflectivity import AVO_CLASS_CODES, AVO_CLASSES

    count, size = missing
    note = (f"{count} of {size} interface samples have no rock on one side (NaN)"
            if count else "every interface sample computed")
    common = {"missing_inputs": note}
    attrs = {
        "reflectivity_pp": {
            "units": "1", "long_name": "PP reflection coefficient (real part), exact Zoeppritz",
            "references": "Zoeppritz (1919); Aki & Richards (1980), eq. 5.40", **common},
        "reflectivity_pp_magnitude": {
            "units": "1", "long_name": "modulus of the PP reflection coefficient, exact "
            "Zoeppritz (equal to |real part| before any critical angle)", **common},
        "avo_class": {
            "units": "1", "long_name": "AVO class of the interface (Rutherford & Williams "
            "1989; Ross & Kinman 1995; Castagna & Swan 1997)",
            "flag_values": np.array(AVO_CLASS_CODES, dtype=np.int8),
            "flag_meanings": " ".join(AVO_CLASSES),
            "threshold": float(threshold),
            "comment": "0: no class (no contrast, A >= 0 with B >= 0, or no rock on one side)",
            **common}}
    for name, what in (("avo_intercept", "intercept A"), ("avo_gradient", "gradient B"),
                       ("avo_curvature", "curvature C")):
        attrs[name] = {
            "units": "1", "long_name": f"AVO {what} (Shuey 1985, of the Aki-Richards "
            "linearisation)", "references": "Shuey (1985); Aki & Richards (1980), eq. 5.44",
            **common}
    return attrs


def add_seismic(ds, scene):
    """Add the ``[seismic]`` variables of a stack to its Dataset ``ds`` (in place).

    Variables (the contract of issue 31): ``reflectivity_pp`` and
    ``reflectivity_pp_magnitude`` (interface, fluid, model, depth, angle), the real part and
    modulus of the exact PP coefficient; ``avo_intercept``, ``avo_gradient``, ``avo_curvature``
    and ``avo_class`` (interface, fluid, model, depth); with the synthetic column (thicknesses),
    ``twt_of_depth`` (fluid, model, depth), ``synthetic`` (fluid, model, twt) at normal
    incidence and ``angle_gather`` (fluid, model, angle, gather_twt) around ``gather_depth``.
    """
    import xarray as xr

    from ._stack_dataset import interface_properties

    seismic = scene.sections["seismic"]
    angles = _angles(seismic)
    sides = interface_properties(ds)
    arrays = [np.asarray(getattr(sides, n).values, dtype=float) for n in _SIDES]
    dims = ("interface", "fluid", "model", "depth")
    out = reflect(arrays, angles, seismic["class_threshold"])
    ds.coords["angle"] = ("angle", angles, ANGLE_ATTRS)
    attrs = seismic_attrs(out.pop("missing"), seismic["class_threshold"])
    for name, values in out.items():
        ds[name] = xr.Variable(dims + (("angle",) if values.ndim > len(dims) else ()),
                               values, attrs[name])
    keys = ["AvsethLehocki2016", "Zoeppritz1919", "AkiRichards1980", "Shuey1985",
            "RutherfordWilliams1989", "RossKinman1995", "CastagnaSwan1997"]
    if "column_vp" in ds:
        _add_synthetics(ds, seismic, angles)
        keys += ["Ricker1953", "Yilmaz2001"]
    _cite(ds, keys)
    from .variables import no_coordinate_fill

    return no_coordinate_fill(ds)


def _add_synthetics(ds, seismic, angles):
    """Normal-incidence synthetic of the column per fluid and model, its depth-to-time
    relation, and the angle gather around ``gather_depth``."""
    import xarray as xr

    from .synthetics import angle_gather, depth_to_twt, synthetic_trace

    depth = ds["depth"].values
    vp = ds["column_vp"].transpose("fluid", "model", "depth").values
    vs = ds["column_vs"].transpose("fluid", "model", "depth").values
    rho = ds["column_density"].transpose("fluid", "model", "depth").values
    good = np.all(np.isfinite(vp) & np.isfinite(vs) & np.isfinite(rho), axis=-1)
    dt = seismic["dt"]
    if seismic["wavelet"] is not None:          # the user's, read when the scene was loaded
        f = (np.asarray(seismic["wavelet_time"]), np.asarray(seismic["wavelet_amplitude"]))
        what = f"the wavelet of {seismic['wavelet']}"
    else:
        f = seismic["frequency"]
        what = f"Ricker {f:g} Hz"
    twt = np.full(vp.shape, np.nan)
    twt[good] = depth_to_twt(depth, vp[good])
    ds["twt_of_depth"] = xr.Variable(("fluid", "model", "depth"), twt, {
        "units": "s", "long_name": "two-way time of the depth in the synthetic column, from "
        "its own P velocity"})
    if not good.any():
        return
    s = synthetic_trace(depth, vp[good], vs[good], rho[good], dt=dt, wavelet=f)
    trace = np.full(vp.shape[:2] + (s.twt.size,), np.nan)
    trace[good] = s.trace
    ds.coords["twt"] = ("twt", s.twt, {"units": "s", "long_name": "two-way time"})
    ds["synthetic"] = xr.Variable(("fluid", "model", "twt"), trace, {
        "units": "1", "long_name": f"normal-incidence synthetic of the column, {what} "
        "(convolutional model: primaries, no transmission losses)",
        "references": "Ricker (1953); Yilmaz (2001), sect. 2.1"})
    at = seismic["gather_depth"]
    if at is None:
        at = float(_layer_tops(ds)[0])
    g = angle_gather(depth, vp[good], vs[good], rho[good], at=at, angles=angles, dt=dt,
                     wavelet=f)
    gather = np.full(vp.shape[:2] + (angles.size, g.twt.size), np.nan)
    gather[good] = g.gather
    ds.coords["gather_twt"] = ("gather_twt", g.twt, {"units": "s",
                                                     "long_name": "two-way time of the gather"})
    ds["angle_gather"] = xr.Variable(("fluid", "model", "angle", "gather_twt"), gather, {
        "units": "1", "long_name": f"angle gather of the column around {at:g} m (exact PP "
        f"coefficient at each angle, {what}, no moveout)", "gather_depth": at})


def _layer_tops(ds):
    """The depths where each layer of the column after the first begins (``column_layer``)."""
    names = ds["column_layer"].values
    depth = ds["depth"].values
    change = np.flatnonzero(names[1:] != names[:-1]) + 1
    return depth[change]


def _cite(ds, keys):
    """Add the seismic sources to the Dataset's ``references`` attribute (one line a key)."""
    from .references import REFERENCES

    lines = [line for line in ds.attrs.get("references", "").split("\n") if line]
    lines += [f"[{k}] {REFERENCES[k]}" for k in keys
              if not any(line.startswith(f"[{k}]") for line in lines)]
    ds.attrs["references"] = "\n".join(lines)
