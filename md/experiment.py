"""MD scenes: settle (and compact) a pack, cement it by each scheme to a series of saturations,
and measure its velocity by the pulse test (García & Medina, Sects. III–IV).

A scene is a TOML table ``[md]`` (see :data:`MD_SCHEMA`, printed by :func:`schema_lines`);
``rockcem run`` hands such files here. Every stage is saved in the scene's work folder —
``loose/settle.nc``, ``compacted/compact.nc`` and one ``pulse_<sample>_<cement>.nc`` per sample
and cement — so an interrupted run resumes from the last saved stage. SI units inside; the scene
file gives the compaction stress in MPa.
"""

from __future__ import annotations

import difflib
from functools import cached_property
from pathlib import Path

import numpy as np

__all__ = ["MD_SCHEMA", "md_scene_from_dict", "run_md_scene", "schema_lines"]

_CEMENTS = ("hard", "soft")
_SCHEMES = ("contact", "coating", "pore_body", "pendular")
_INTERFACES = ("patch", "paper")

#: key: (default, type, unit, description)
MD_SCHEMA = {
    "size": ([4.0, 4.0, 12.0], "numbers", "largest diameters",
             "box width, depth and height of the pack (the paper: 8, 8, 32)"),
    "radius_range": ([1.8e-4, 2.0e-4], "numbers", "m", "smallest and largest grain radius"),
    "seed": (0, "integer", "", "random seed of settling and pore-body cement"),
    "fall_stiffness_factor": (1e-3, "number", "",
                              "contact softening while grains fall (1 = faithful settling)"),
    "samples": (["loose", "compacted"], "strings", "", "loose and/or compacted pack"),
    "compaction_stress": (10.0, "number", "MPa", "stress the compacted sample is taken to"),
    "resolution": (3.0, "number", "cells per radius", "cement lattice resolution Omega"),
    "schemes": (list(_SCHEMES[:3]), "strings", "",
                "cementation schemes: the source's contact, coating, pore_body; pendular"),
    "interface": ("patch", "string", "",
                  "grain-cement interface: 'patch' (converges in Omega) or 'paper' (per cell)"),
    "cements": (list(_CEMENTS), "strings", "", "hard and/or soft cement of Table II"),
    "saturations": ([0.0, 0.02, 0.05, 0.1, 0.2], "numbers", "1",
                    "cement saturations S_c (fraction of pore cells)"),
    "wave": ("p", "string", "", "'p' or 's'"),
    "time_step_factor": (0.5, "number", "", "pulse-test time step / stability limit"),
    "workdir": ("", "string", "", "folder for stage files (default: <output stem>_work)"),
}


def schema_lines():
    """The MD scene keys with type, unit, default and description, one line each."""
    return [f"md.{k:<24}{t:<9}{u:<18}{d!r:<28}{doc}"
            for k, (d, t, u, doc) in MD_SCHEMA.items()]


def _bad(key, msg):
    return ValueError(f"scene key md.{key} {msg}")


def md_scene_from_dict(raw: dict) -> dict:
    """Validate an MD scene (the parsed TOML) and return its parameters with defaults filled in.

    Top-level keys ``name``, ``description``, ``output`` and the table ``[md]``.
    """
    top = {"name", "description", "output", "md"}
    unknown = [k for k in raw if k not in top]
    if unknown:
        close = difflib.get_close_matches(unknown[0], top, n=1)
        raise ValueError(f"unknown scene key {unknown[0]}"
                         + (f"; did you mean {close[0]!r}?" if close else ""))
    given = raw.get("md")
    if not isinstance(given, dict):
        raise ValueError("an MD scene needs a table [md]")
    for k in given:
        if k not in MD_SCHEMA:
            close = difflib.get_close_matches(k, MD_SCHEMA, n=1)
            raise ValueError(f"unknown scene key md.{k}"
                             + (f"; did you mean {close[0]!r}?" if close else ""))
    p = {k: given.get(k, d) for k, (d, *_rest) in MD_SCHEMA.items()}
    for k, (_d, kind, _u, _doc) in MD_SCHEMA.items():
        v = p[k]
        if kind == "numbers":
            if not (isinstance(v, list) and v and all(
                    isinstance(x, (int, float)) and not isinstance(x, bool) and np.isfinite(x)
                    for x in v)):
                raise _bad(k, f"must be a list of finite numbers; got {v!r}")
            p[k] = [float(x) for x in v]
        elif kind == "number":
            if not (isinstance(v, (int, float)) and not isinstance(v, bool) and np.isfinite(v)):
                raise _bad(k, f"must be a finite number; got {v!r}")
            p[k] = float(v)
        elif kind == "integer":
            if not (isinstance(v, int) and not isinstance(v, bool)):
                raise _bad(k, f"must be an integer; got {v!r}")
        elif kind == "string":
            if not isinstance(v, str):
                raise _bad(k, f"must be a string; got {v!r}")
        elif not (isinstance(v, list) and v and all(isinstance(x, str) for x in v)):
            raise _bad(k, f"must be a list of names; got {v!r}")
    if len(p["size"]) != 3 or min(p["size"]) < 2:
        raise _bad("size", f"must be three numbers >= 2; got {p['size']}")
    lo, hi = (p["radius_range"] + [0.0])[:2]
    if len(p["radius_range"]) != 2 or not 0 < lo <= hi:
        raise _bad("radius_range", f"must be [smallest, largest] with 0 < smallest <= largest; "
                                   f"got {p['radius_range']}")
    for key, valid in (("samples", ("loose", "compacted")), ("schemes", _SCHEMES),
                       ("cements", _CEMENTS)):
        bad = [x for x in p[key] if x not in valid]
        if bad:
            raise _bad(key, f"has {bad[0]!r}; valid: {', '.join(valid)}")
    for key in ("samples", "schemes", "cements", "saturations"):
        repeated = sorted({x for x in p[key] if p[key].count(x) > 1})
        if repeated:        # a repeated label would give the output a repeated coordinate
            raise _bad(key, f"lists {repeated[0]!r} more than once")
    if not all(0.0 <= s <= 1.0 for s in p["saturations"]):
        raise _bad("saturations", f"must lie in [0, 1]; got {p['saturations']}")
    if p["seed"] < 0:
        raise _bad("seed", f"must be an integer >= 0; got {p['seed']}")
    if not p["compaction_stress"] > 0:
        raise _bad("compaction_stress", f"must be > 0 MPa; got {p['compaction_stress']}")
    if not p["resolution"] >= 1:
        raise _bad("resolution", f"must be >= 1; got {p['resolution']}")
    if p["interface"] not in _INTERFACES:
        raise _bad("interface", f"must be 'patch' or 'paper'; got {p['interface']!r}")
    if p["wave"] not in ("p", "s"):
        raise _bad("wave", f"must be 'p' or 's'; got {p['wave']!r}")
    if not 0 < p["time_step_factor"] <= 1:
        raise _bad("time_step_factor", f"must lie in (0, 1]; got {p['time_step_factor']}")
    if not 0 < p["fall_stiffness_factor"] <= 1:
        raise _bad("fall_stiffness_factor", f"must lie in (0, 1]; got "
                                            f"{p['fall_stiffness_factor']}")
    return {"name": str(raw.get("name", "md")), "description": str(raw.get("description", "")),
            "output": str(raw.get("output", f"{raw.get('name', 'md')}.nc")), "md": p}


class _Cementation:
    """The cement lattice of one pack and its cemented cells per (scheme, S_c), built on first
    use and shared by the cements (hard and soft cement fill the same cells)."""

    def __init__(self, pack, params):
        self.pack, self.params, self._cells = pack, params, {}

    @cached_property
    def lattice(self):
        from .cement import cement_lattice

        return cement_lattice(self.pack, self.params["resolution"])

    def cells(self, scheme, saturation):
        """Cemented cells of ``scheme`` at ``saturation`` (one of the scene's saturations);
        one growth per scheme serves the whole saturation sweep (:func:`md.cement_sweep`)."""
        from .cement import cement_sweep

        if scheme not in self._cells:
            sats = self.params["saturations"]
            self._cells[scheme] = dict(zip(sats, cement_sweep(self.lattice, sats, scheme,
                                                              seed=self.params["seed"])))
        return self._cells[scheme][saturation]


#: Pulse-test results kept per (scheme, saturation): stage-file name -> pulse_test variable.
_PULSE_VARIABLES = {"v": "velocity", "err": "velocity_error",
                    "err_half_slab": "velocity_error_half_slab", "fit": "velocity_fit",
                    "static": "velocity_static", "density": "density"}

#: Scene keys a pulse stage file is valid for (recorded in its attributes, checked on resume).
_PULSE_KEYS = ("interface", "resolution", "wave", "time_step_factor", "seed")


def _pulse_sweep(cementation, cement, path, progress):
    """Vp(scheme, saturation) of one pack and cement, saved to ``path`` (resumed if there)."""
    import xarray as xr
    from tqdm.auto import tqdm

    from .acoustic import acoustic_system, pulse_test
    from .state import _atomic_netcdf

    pack, params = cementation.pack, cementation.params
    if path.exists():
        with xr.open_dataset(path, engine="netcdf4") as ds:
            done = ds.load()
        # A stage file from before a variable was added, or for another interface, resolution,
        # wave, time step factor, seed, schemes or saturations than the scene's now, is redone.
        if set(_PULSE_VARIABLES.values()) <= set(done.data_vars) \
                and all(done.attrs.get(k) == params[k] for k in _PULSE_KEYS) \
                and list(done.scheme.values) == list(params["schemes"]) \
                and np.array_equal(done.saturation.values, params["saturations"]):
            return done
    lat = cementation.lattice
    schemes, sats = params["schemes"], params["saturations"]
    shape = (len(schemes), len(sats))
    out = {k: np.full(shape, np.nan) for k in _PULSE_VARIABLES}
    bar = tqdm(total=len(schemes) * len(sats), disable=not progress,
               desc=f"pulse tests {path.stem}")
    for a, scheme in enumerate(schemes):
        for b, s in enumerate(sats):
            system = acoustic_system(pack, lat, cementation.cells(scheme, s), cement,
                                     interface=params["interface"])
            ds = pulse_test(system, params["wave"], time_step_factor=params["time_step_factor"])
            for key, var in _PULSE_VARIABLES.items():
                out[key][a, b] = float(ds[var])
            bar.update()
    bar.close()
    dims = ("scheme", "saturation")
    result = xr.Dataset(
        {var: (dims, out[key]) for key, var in _PULSE_VARIABLES.items()},
        coords={"scheme": list(schemes), "saturation": sats},
        attrs={"cell_width_m": lat.cell_width, "n_pore_cells": int(lat.index.size),
               **{k: params[k] for k in _PULSE_KEYS}})
    _atomic_netcdf(result, path)
    return result


def run_md_scene(scene: dict, *, workdir=None, progress=False):
    """Run an MD scene: packs → cement → pulse tests → one ``xarray.Dataset``.

    Parameters
    ----------
    scene : dict
        From :func:`md_scene_from_dict`.
    workdir : path, optional
        Stage files; default the scene's ``workdir`` or ``<output stem>_work``.
    progress : bool

    Returns
    -------
    xarray.Dataset
        ``vp`` (or ``vs``) with its eq. 11 error for ΔL = R and for half a slab,
        the all-detector fit and the static velocity (km/s; their difference is the
        pulse-minus-static bias), ``porosity`` and ``density`` (g/cm³) over ``sample`` ×
        ``cement`` × ``scheme`` × ``saturation``; per sample the uncemented porosity,
        coordination number, vertical and mean stress. CF-1.10 attributes.
    """
    import xarray as xr

    from .cement import HARD_CEMENT, SOFT_CEMENT
    from .observe import coordination_number, pack_stress, porosity
    from .protocols import prepare_pack

    p = scene["md"]
    folder = Path(workdir or p["workdir"] or Path(scene["output"]).with_suffix("").name + "_work")
    folder.mkdir(parents=True, exist_ok=True)
    settle_opts = {"size": tuple(p["size"]), "radius_range": tuple(p["radius_range"]),
                   "seed": p["seed"], "fall_stiffness_factor": p["fall_stiffness_factor"]}
    cements = {"hard": HARD_CEMENT, "soft": SOFT_CEMENT}
    per_sample, phi0, coord, stress, stress_mean = [], [], [], [], []
    for sample in p["samples"]:
        compact_opts = ({"target_stress": p["compaction_stress"] * 1e6}
                        if sample == "compacted" else None)
        pack = prepare_pack(folder / "pack", settle_options=settle_opts,
                            compact_options=compact_opts, progress=progress)
        phi = porosity(pack)                 # the core window between the end slabs
        sig = pack_stress(pack)              # same window, normal and tangential forces
        phi0.append(phi)
        coord.append(coordination_number(pack))
        stress.append(float(sig[2, 2]) / 1e6)
        stress_mean.append(float(np.trace(sig)) / 3e6)
        cementation = _Cementation(pack, p)
        runs = [_pulse_sweep(cementation, cements[c], folder / f"pulse_{sample}_{c}.nc",
                             progress) for c in p["cements"]]
        per_sample.append(xr.concat(runs, dim=xr.DataArray(p["cements"], dims="cement")))
    ds = xr.concat(per_sample, dim=xr.DataArray(p["samples"], dims="sample"))
    return _scene_dataset(scene, ds, {"porosity_uncemented": phi0, "coordination_number": coord,
                                      "stress": stress, "stress_mean": stress_mean})


def _scene_dataset(scene, ds, per_sample):
    """The MD scene's output Dataset (CF attributes) from the pulse tests ``ds`` over
    sample × cement × scheme × saturation (SI units) and the per-sample pack measures."""
    import json

    import xarray as xr

    p = scene["md"]
    w = p["wave"]
    kms = {"units": "km s-1"}
    phi0 = np.asarray(per_sample["porosity_uncemented"], dtype=float)

    def label(name, long_name):
        return (name, list(p[f"{name}s"]), {"long_name": long_name})

    out = xr.Dataset(
        {
            f"v{w}": (ds.velocity / 1e3).assign_attrs(
                kms, long_name=f"{w.upper()} velocity of the pulse test (eq. 11)"),
            f"v{w}_error": (ds.velocity_error / 1e3).assign_attrs(
                kms, long_name="eq. 11 error of the pulse velocity, Delta L = R"),
            f"v{w}_error_half_slab": (ds.velocity_error_half_slab / 1e3).assign_attrs(
                kms, long_name="eq. 11 error of the pulse velocity, Delta L = half a slab"),
            f"v{w}_fit": (ds.velocity_fit / 1e3).assign_attrs(
                kms, long_name="velocity from the arrival times of all detectors"),
            f"v{w}_static": (ds.velocity_static / 1e3).assign_attrs(
                kms, long_name="long-wave velocity of the static modulus"),
            "density": (ds.density / 1e3).assign_attrs(
                units="g cm-3", long_name="bulk density of the dry cemented pack"),
            "porosity": (("sample", "saturation"),
                         np.outer(phi0, 1.0 - np.asarray(p["saturations"])),
                         {"units": "1", "long_name": "porosity after cementation, "
                                                     "phi0 (1 - S_c)"}),
            "porosity_uncemented": (("sample",), phi0, {
                "units": "1", "long_name": "porosity of the uncemented pack in its core window "
                                           "between the end slabs"}),
            "coordination_number": (("sample",), per_sample["coordination_number"], {
                "units": "1", "long_name": "mean number of contacts per grain"}),
            "stress": (("sample",), per_sample["stress"], {
                "units": "MPa", "long_name": "vertical contact stress sigma_zz of the pack's core "
                                             "(virial, normal and tangential forces)"}),
            "stress_mean": (("sample",), per_sample["stress_mean"], {
                "units": "MPa", "long_name": "mean contact stress trace(sigma)/3 of the pack's "
                                             "core"}),
        },
        coords={"sample": label("sample", "grain pack (settled, or compacted)"),
                "cement": label("cement", "cement material (García & Medina, Table II)"),
                "scheme": label("scheme", "cementation scheme"),
                "saturation": ("saturation", p["saturations"], {
                    "units": "1", "long_name": "cement saturation S_c (fraction of the pore "
                                               "cells)"})},
        attrs={"Conventions": "CF-1.10", "title": f"rockcem MD scene {scene['name']}",
               "scene_name": scene["name"], "description": scene["description"],
               "scene_json": json.dumps(scene), "resolution": p["resolution"],
               "interface": p["interface"],
               "references": "García & Medina (MD), Sects. III-IV, eqs. 4-11, Table II"},
    )
    for name in out.coords:           # CF 1.10 sect. 2.5.1: coordinates have no missing values
        out[name].encoding["_FillValue"] = None
    return out
