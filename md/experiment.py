"""MD scenes: settle (and compact) a pack, cement it by each scheme to a series of saturations,
and measure its velocity by the pulse test (García & Medina, Sects. III–IV).

A scene is a TOML table ``[md]`` (see :data:`MD_SCHEMA`, printed by :func:`schema_lines`);
``rockcem run`` hands such files here. Every stage is saved in the scene's work folder —
``pack/settle.nc``, ``pack/compact.nc`` and one file per pulse test under ``pulse/`` — so an
interrupted run resumes from the last saved stage. The pulse tests are independent and can run
on several processes. SI units inside; the scene file gives the compaction stress in MPa.
"""

from __future__ import annotations

import difflib
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path

import numpy as np

from .interface import INTERFACES

__all__ = ["MD_SCHEMA", "md_scene_from_dict", "run_md_scene", "schema_lines"]

_CEMENTS = ("hard", "soft")
_SCHEMES = ("contact", "coating", "pore_body", "pendular")

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
    "resolution_check": (0.0, "number", "cells per radius",
                         "coarser Omega every cemented member is also run at, for the "
                         "resolution error (0 = none)"),
    "schemes": (list(_SCHEMES[:3]), "strings", "",
                "cementation schemes: the source's contact, coating, pore_body; pendular"),
    "interface": (INTERFACES[0], "string", "",
                  "grain-cement interface: 'facet' (converges in Omega), 'patch' or 'paper' "
                  "(per cell)"),
    "cements": (list(_CEMENTS), "strings", "", "hard and/or soft cement of Table II"),
    "saturations": ([0.0, 0.02, 0.05, 0.1, 0.2], "numbers", "1",
                    "cement saturations S_c (fraction of pore cells)"),
    "wave": ("p", "string", "", "'p' or 's'"),
    "rotations": (True, "boolean", "",
                  "grains and cement particles rotate in the linearised sample (false: the "
                  "source's translations only, eqs. 4-6)"),
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
        elif kind == "boolean":
            if not isinstance(v, bool):
                raise _bad(k, f"must be true or false; got {v!r}")
        elif kind == "string":
            if not isinstance(v, str):
                raise _bad(k, f"must be a string; got {v!r}")
        elif not (isinstance(v, list) and v and all(isinstance(x, str) for x in v)):
            raise _bad(k, f"must be a list of names; got {v!r}")
    lo, hi = (p["radius_range"] + [0.0])[:2]
    if len(p["radius_range"]) != 2 or not 0 < lo <= hi:
        raise _bad("radius_range", f"must be [smallest, largest] with 0 < smallest <= largest; "
                                   f"got {p['radius_range']}")
    from .deposit import check_size

    check_size(p["size"], p["radius_range"], name="scene key md.size")
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
    if p["resolution_check"] != 0 and not 1 <= p["resolution_check"] < p["resolution"]:
        raise _bad("resolution_check", f"must be 0 (none) or lie in [1, resolution = "
                                       f"{p['resolution']:g}); got {p['resolution_check']:g}")
    if p["interface"] not in INTERFACES:
        names = ", ".join(map(repr, INTERFACES[:-1])) + f" or {INTERFACES[-1]!r}"
        raise _bad("interface", f"must be {names}; got {p['interface']!r}")
    if p["wave"] not in ("p", "s"):
        raise _bad("wave", f"must be 'p' or 's'; got {p['wave']!r}")
    if not 0 < p["time_step_factor"] <= 1:
        raise _bad("time_step_factor", f"must lie in (0, 1]; got {p['time_step_factor']}")
    if not 0 < p["fall_stiffness_factor"] <= 1:
        raise _bad("fall_stiffness_factor", f"must lie in (0, 1]; got "
                                            f"{p['fall_stiffness_factor']}")
    from rockcem._atomic import check_scene_name

    head = {"name": "md", "description": "", "output": None, **{k: raw[k] for k in raw
                                                                 if k != "md"}}
    for key, value in head.items():
        if value is not None and not isinstance(value, str):
            raise ValueError(f"scene key {key} must be a string; got {value!r}")
    check_scene_name(head["name"])
    if head["output"] is not None and not head["output"].strip():
        raise ValueError("scene key output must name a file (leave it out for <name>.nc); "
                         "got ''")
    return {"name": head["name"], "description": head["description"],
            "output": head["output"] or f"{head['name']}.nc", "md": p}


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


#: Pulse-test results kept per member: key -> :func:`md.pulse_test` variable.
_PULSE_VARIABLES = {"v": "velocity", "err": "velocity_error",
                    "err_half_slab": "velocity_error_half_slab", "fit": "velocity_fit",
                    "static": "velocity_static", "density": "density"}

#: Scene keys a cemented member's stage file is valid for (recorded in its attributes, checked
#: on resume); the uncemented member depends on the pack, the wave and the time step only.
_PULSE_KEYS = ("interface", "wave", "time_step_factor", "seed", "rotations")
_UNCEMENTED_KEYS = ("wave", "time_step_factor", "rotations")


@dataclass(frozen=True)
class _Member:
    """One pulse test of a study: a pack (sample), cement, scheme, saturation and resolution.
    The uncemented member (S_c = 0) does not depend on the cement, scheme or resolution: those
    are None, so it is one member per sample (:meth:`of`)."""

    sample: str
    cement: str | None
    scheme: str | None
    saturation: float
    resolution: float | None

    @classmethod
    def of(cls, sample, cement, scheme, saturation, resolution):
        if saturation == 0:
            return cls(sample, None, None, 0.0, None)
        return cls(sample, cement, scheme, float(saturation), float(resolution))

    def file(self, folder):
        if self.cement is None:
            return Path(folder) / "pulse" / f"{self.sample}_uncemented.nc"
        return (Path(folder) / "pulse" / f"{self.sample}_{self.cement}_{self.scheme}"
                f"_sc{self.saturation:g}_omega{self.resolution:g}.nc")

    def attrs(self, params, pack_id):
        keys = _UNCEMENTED_KEYS if self.cement is None else _PULSE_KEYS
        out = {k: int(params[k]) if isinstance(params[k], bool) else params[k] for k in keys}
        out["pack_id"] = pack_id
        if self.cement is not None:
            out["resolution"] = self.resolution
        return out

    def cost(self):
        """Relative cost for scheduling: particles ~ S_c Omega^3, steps ~ Omega."""
        return 0.0 if self.cement is None else self.saturation * self.resolution**4


def _pack_id(pack) -> str:
    """A fingerprint of a pack's grains (positions and radii): a stage file made on another
    pack (another seed, size or compaction) is redone."""
    import hashlib

    h = hashlib.sha1(np.ascontiguousarray(pack.positions).tobytes())
    h.update(np.ascontiguousarray(pack.radii).tobytes())
    return h.hexdigest()[:16]


def _load_member(path, attrs):
    """The saved result of a member, or None when there is none or it was made for other
    settings (another interface, resolution, wave, time step, seed or pack) or before a
    variable was added."""
    import xarray as xr

    if not path.exists():
        return None
    with xr.open_dataset(path, engine="netcdf4") as ds:
        done = ds.load()
    if not set(_PULSE_VARIABLES.values()) | {"wall_time"} <= set(done.data_vars):
        return None
    if any(done.attrs.get(k) != v for k, v in attrs.items()):
        return None
    return {var: float(done[var]) for var in (*_PULSE_VARIABLES.values(), "wall_time")}


#: Per-process cache of cement lattices and growths: (pack file, resolution) -> _Cementation.
_CACHE: dict = {}


def _cementation(pack_file, params, resolution):
    from .state import load_pack

    key = (str(pack_file), float(resolution))
    if key not in _CACHE:
        while len(_CACHE) >= 2:                   # at most two lattices held at a time
            _CACHE.pop(next(iter(_CACHE)))
        _CACHE[key] = _Cementation(load_pack(pack_file), {**params, "resolution": resolution})
    return _CACHE[key]


def _run_member(pack_file, params, member, pack_id, folder):
    """Run one member's pulse test and save it (atomically) to its stage file; the result is
    returned as a dict of floats (SI) with its wall time, s."""
    import time

    import xarray as xr

    from .acoustic import acoustic_system, pulse_test
    from .cement import HARD_CEMENT, SOFT_CEMENT
    from .state import _atomic_netcdf, load_pack

    t0 = time.perf_counter()
    if member.cement is None:
        system = acoustic_system(load_pack(pack_file), rotations=params["rotations"])
    else:
        cem = _cementation(pack_file, params, member.resolution)
        material = {"hard": HARD_CEMENT, "soft": SOFT_CEMENT}[member.cement]
        system = acoustic_system(cem.pack, cem.lattice,
                                 cem.cells(member.scheme, member.saturation), material,
                                 interface=params["interface"], rotations=params["rotations"])
    ds = pulse_test(system, params["wave"], time_step_factor=params["time_step_factor"])
    out = {var: float(ds[var]) for var in _PULSE_VARIABLES.values()}
    out["wall_time"] = time.perf_counter() - t0
    stage = xr.Dataset({k: ((), v) for k, v in out.items()},
                       attrs={**member.attrs(params, pack_id), "sample": member.sample,
                              "cement": member.cement or "none",
                              "scheme": member.scheme or "none",
                              "saturation": member.saturation})
    _atomic_netcdf(stage, member.file(folder))
    return out


def _run_members(todo, pack_files, params, pack_ids, folder, jobs, progress, scheduler=None):
    """Run the members not yet saved, serially, on ``jobs`` local processes or on dask
    (:func:`md._tasks.run_tasks`; each member is independent, a process keeps the lattice and
    growth of its last packs). Returns {member: result}."""
    from ._tasks import run_tasks

    # The compacted sample first (a run stopped early has it whole), then by resolution, finest
    # first, so a process reuses its lattice; within those, longest first (the
    # longest-processing-time rule).
    todo = sorted(todo, key=lambda m: (m.sample != "compacted", m.sample,
                                       -(m.resolution or 0.0), -m.cost()))
    tasks = [(pack_files[m.sample], params, m, pack_ids[m.sample], folder) for m in todo]
    return {task[2]: result for task, result in run_tasks(
        _run_member, tasks, scheduler=scheduler, jobs=jobs, progress=progress,
        desc="pulse tests")}


def run_md_scene(scene: dict, *, workdir=None, jobs=1, scheduler=None, progress=False):
    """Run an MD scene: packs → cement → pulse tests → one ``xarray.Dataset``.

    Every pulse test (a *member*: sample, cement, scheme, saturation, resolution) is saved to
    its own stage file under ``<workdir>/pulse`` as soon as it is done, so an interrupted run
    resumes from the last finished member; members are independent and run on ``jobs``
    processes. The uncemented pack (S_c = 0) is one member per sample, shared by every cement
    and scheme. With ``resolution_check`` set, every cemented member is also run at that coarser
    resolution and the difference gives the resolution error (first-order Richardson estimate).

    Parameters
    ----------
    scene : dict
        From :func:`md_scene_from_dict`.
    workdir : path, optional
        Stage files; default the scene's ``workdir`` or ``<output stem>_work``.
    jobs : int
        Processes for the pulse tests (default 1: in this process); with
        ``scheduler="local"`` the number of dask workers.
    scheduler : str, optional
        Run the pulse tests on dask: ``"local"`` or a scheduler address
        (:func:`md._tasks.run_tasks`).
    progress : bool

    Returns
    -------
    xarray.Dataset
        ``vp`` (or ``vs``) with its eq. 11 error for ΔL = R and for half a slab,
        the all-detector fit and the static velocity (km/s; their difference is the
        pulse-minus-static bias), ``porosity`` and ``density`` (g/cm³) over ``sample`` ×
        ``cement`` × ``scheme`` × ``saturation``; per sample the uncemented porosity,
        coordination number, vertical and mean stress; the wall time of each member; with a
        resolution check, the velocity at the coarser resolution and the resolution error.
        CF-1.10 attributes.
    """
    import xarray as xr

    from .observe import coordination_number, pack_stress, porosity
    from .protocols import prepare_pack

    from rockcem._scheduler import check_scheduler

    if not (isinstance(jobs, int) and jobs >= 1):
        raise ValueError(f"jobs must be an integer >= 1; got {jobs!r}")
    check_scheduler(scheduler)
    p = scene["md"]
    folder = Path(workdir or p["workdir"] or Path(scene["output"]).with_suffix("").name + "_work")
    folder.mkdir(parents=True, exist_ok=True)
    settle_opts = {"size": tuple(p["size"]), "radius_range": tuple(p["radius_range"]),
                   "seed": p["seed"], "fall_stiffness_factor": p["fall_stiffness_factor"]}
    pack_files, pack_ids = {}, {}
    phi0, coord, stress, stress_mean = [], [], [], []
    for sample in p["samples"]:
        compact_opts = ({"target_stress": p["compaction_stress"] * 1e6}
                        if sample == "compacted" else None)
        pack = prepare_pack(folder / "pack", settle_options=settle_opts,
                            compact_options=compact_opts, progress=progress)
        pack_files[sample] = folder / "pack" / ("compact.nc" if compact_opts else "settle.nc")
        pack_ids[sample] = _pack_id(pack)
        phi0.append(porosity(pack))                 # the core window between the end slabs
        sig = pack_stress(pack)                     # same window, normal and tangential forces
        coord.append(coordination_number(pack))
        stress.append(float(sig[2, 2]) / 1e6)
        stress_mean.append(float(np.trace(sig)) / 3e6)
    resolutions = [p["resolution"]] + ([p["resolution_check"]] if p["resolution_check"] else [])
    grid = {(sample, c, scheme, s, res): _Member.of(sample, c, scheme, s, res)
            for sample in p["samples"] for c in p["cements"] for scheme in p["schemes"]
            for s in p["saturations"] for res in resolutions}
    results, todo = {}, []
    for m in set(grid.values()):
        done = _load_member(m.file(folder), m.attrs(p, pack_ids[m.sample]))
        if done is None:
            todo.append(m)
        else:
            results[m] = done
    results.update(_run_members(todo, pack_files, p, pack_ids, folder, jobs, progress,
                                scheduler))

    dims = ("sample", "cement", "scheme", "saturation")
    shape = tuple(len(p[f"{d}s"]) for d in dims)

    def table(res, var):
        out = np.empty(shape)
        for idx in np.ndindex(shape):
            sample, c, scheme, s = (p[f"{d}s"][i] for d, i in zip(dims, idx))
            out[idx] = results[grid[(sample, c, scheme, s, res)]][var]
        return out

    fine = p["resolution"]
    ds = xr.Dataset({var: (dims, table(fine, var))
                     for var in (*_PULSE_VARIABLES.values(), "wall_time")})
    if p["resolution_check"]:
        ds["velocity_check"] = (dims, table(p["resolution_check"], "velocity"))
    wall = sum(r["wall_time"] for r in results.values())
    return _scene_dataset(scene, ds, {"porosity_uncemented": phi0, "coordination_number": coord,
                                      "stress": stress, "stress_mean": stress_mean},
                          member_seconds=wall)


def _scene_dataset(scene, ds, per_sample, member_seconds=None):
    """The MD scene's output Dataset (CF attributes) from the pulse tests ``ds`` over
    sample × cement × scheme × saturation (SI units; optional ``wall_time`` of each member, s,
    and ``velocity_check`` at the scene's ``resolution_check``) and the per-sample pack
    measures; ``member_seconds`` is the summed wall time of the study's distinct members."""
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
               "interface": p["interface"], "rotations": int(p["rotations"]),
               "references": "García & Medina (MD), Sects. III-IV, eqs. 4-11, Table II"},
    )
    if "wall_time" in ds:
        out["wall_time"] = ds.wall_time.assign_attrs(
            units="s", long_name="wall time of the member's pulse test (lattice, growth and "
                                 "linear system included; the uncemented member is shared)")
    if "velocity_check" in ds:
        fine, coarse = p["resolution"], p["resolution_check"]
        out[f"v{w}_resolution_check"] = (ds.velocity_check / 1e3).assign_attrs(
            kms, long_name=f"pulse velocity at the coarser resolution Omega = {coarse:g}")
        # First-order Richardson estimate of the distance to the Omega -> infinity limit,
        # |v(Omega) - v(Omega_c)| / (Omega/Omega_c - 1): the larger of the orders 1-1.6 that
        # md_omega_convergence measured on a cemented pack (docs/studies/md_omega_convergence.md).
        out[f"v{w}_error_resolution"] = (abs(ds.velocity - ds.velocity_check) / 1e3
                                         / (fine / coarse - 1.0)).assign_attrs(
            kms, long_name=f"resolution error of the pulse velocity: first-order Richardson "
                           f"estimate from Omega = {coarse:g} and {fine:g}")
    if member_seconds is not None:
        out.attrs["member_wall_time_s"] = float(member_seconds)
    for name in out.coords:           # CF 1.10 sect. 2.5.1: coordinates have no missing values
        out[name].encoding["_FillValue"] = None
    return out
