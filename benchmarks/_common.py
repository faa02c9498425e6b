"""Shared helpers for the benchmarks: single-threaded setup, timing, the rock state, atomic output.

Import this module *first* in every benchmark script: it pins the BLAS/OpenMP thread pools to one
thread before numpy is imported, and puts the repository root on ``sys.path`` so that the
benchmarks always measure the checkout they live in.

Results land in ``benchmarks/results/`` as CSV (metadata in ``#`` comment lines, read with
``pandas.read_csv(path, comment="#")``), netCDF (xarray, engine ``netcdf4``) and PNG. Every file is
written atomically: to a temporary file in the same folder, then :func:`os.replace`.
"""

from __future__ import annotations

import os

# Single-threaded: must happen before numpy (or anything importing it) is imported.
_THREAD_VARS = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS",
                "NUMEXPR_NUM_THREADS", "VECLIB_MAXIMUM_THREADS", "NUMBA_NUM_THREADS")
for _var in _THREAD_VARS:
    os.environ[_var] = "1"

import datetime  # noqa: E402
import functools  # noqa: E402
import platform  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402
from pathlib import Path  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
# ROCKCEM_BENCH_PATH: benchmark another copy of the package (e.g. a `git archive` of a commit).
_SRC = os.environ.get("ROCKCEM_BENCH_PATH", str(ROOT))
if _SRC not in sys.path:
    sys.path.insert(0, _SRC)

import numpy as np  # noqa: E402

RESULTS = Path(__file__).resolve().parent / "results"

__all__ = ["ROOT", "RESULTS", "result_path", "best_of", "environment_attrs", "sandstone_profile",
           "write_csv", "write_netcdf", "save_figure", "relative_difference", "markdown",
           "md_source_attrs", "cct_vp"]


# ----------------------------------------------------------------------------- timing
def best_of(fn, repeat=3, *, budget_s=None):
    """Time ``fn()`` with :func:`time.perf_counter`; best of ``repeat`` runs.

    Parameters
    ----------
    fn : callable
        Called with no arguments.
    repeat : int
        Number of timed runs (at least one).
    budget_s : float, optional
        Stop repeating once the runs so far took more than this many seconds in total (the first
        run always happens), so that slow cases fit the time budget of a benchmark.

    Returns
    -------
    best : float
        Shortest wall time, s.
    times : list of float
        All wall times, s.
    result
        The return value of the last call.
    caught : list of str
        Warnings raised by ``fn`` (category and message, de-duplicated), so that a benchmark
        can report warnings on valid input.
    """
    times = []
    result = None
    caught = []
    for _ in range(max(1, int(repeat))):
        with warnings.catch_warnings(record=True) as w:
            warnings.simplefilter("always")
            t0 = time.perf_counter()
            result = fn()
            times.append(time.perf_counter() - t0)
        for item in w:
            text = f"{item.category.__name__}: {item.message}"
            if text not in caught:
                caught.append(text)
        if budget_s is not None and sum(times) > budget_s:
            break
    return min(times), times, result, caught


def relative_difference(a, b):
    """``|a - b| / |b|`` elementwise (``|a - b|`` where ``b == 0``)."""
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    scale = np.where(b != 0.0, np.abs(b), 1.0)
    return np.abs(a - b) / scale


# ----------------------------------------------------------------------------- rock state
def sandstone_profile(n):
    """A realistic quartz-cemented sandstone rock state at ``n`` depth points.

    Depth 0–5000 m, porosity falling linearly from the critical porosity 0.36 to 0.02, quartz
    cement fraction growing from 0 as ``0.20 (z/z_max)^2`` (cementation sets in with depth),
    effective pressure 0–60 MPa (12 MPa/km). Porosity plus cement stays below 0.36, as for
    intergranular volume lost to compaction and cement.

    Returns
    -------
    dict of ndarray, shape (n,)
        ``depth`` (m), ``porosity``, ``cement_fraction``, ``effective_pressure`` (MPa) and
        ``solid_fractions`` (shape (n, 2): quartz grain, quartz cement per unit volume of solid).
    """
    s = np.linspace(0.0, 1.0, int(n))
    porosity = 0.36 - 0.34 * s
    cement = 0.20 * s**2
    beta_c = cement / (1.0 - porosity)
    return {
        "depth": 5000.0 * s,
        "porosity": porosity,
        "cement_fraction": cement,
        "effective_pressure": 60.0 * s,
        "solid_fractions": np.stack([1.0 - beta_c, beta_c], axis=-1),
    }


# ----------------------------------------------------------------------------- metadata
def environment_attrs(**extra):
    """Provenance as netCDF-safe attributes (str, int or float only)."""
    import scipy

    import rockcem

    attrs = {
        "date_utc": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
        "python_version": platform.python_version(),
        "numpy_version": np.__version__,
        "scipy_version": scipy.__version__,
        "rockcem_version": rockcem.__version__,
        "platform": platform.platform(),
        "processor": _cpu_name(),
        "cpu_count": int(os.cpu_count() or 0),
        "threads": "single-threaded: " + ", ".join(f"{v}=1" for v in _THREAD_VARS),
        "command": " ".join([Path(sys.argv[0]).name] + sys.argv[1:]),
        **source_attrs(),
    }
    for key, value in extra.items():
        if isinstance(value, (bool, np.bool_)):
            value = int(value)
        elif value is None:
            value = ""
        elif not isinstance(value, (str, int, float, np.integer, np.floating)):
            value = str(value)
        attrs[key] = value
    return attrs


@functools.lru_cache(maxsize=None)
def source_attrs():
    """Which rockcem was measured: its path, the git commit of the repository, the package files
    that differ from that commit, and a SHA-256 over the package's ``.py`` sources.

    Other people edit the checkout while benchmarks run; the source hash identifies the code
    exactly. It is taken at the first call and cached: call it right after the benchmark imports
    rockcem, so that it describes the code that runs.
    """
    import hashlib
    import subprocess

    import rockcem

    pkg = Path(rockcem.__file__).resolve().parent
    digest = hashlib.sha256()
    for file in sorted(pkg.rglob("*.py")):
        digest.update(file.relative_to(pkg).as_posix().encode())
        digest.update(file.read_bytes())

    def git(*cmd):
        try:
            return subprocess.run(["git", "-C", str(pkg), *cmd], capture_output=True, text=True,
                                  timeout=20, check=True).stdout
        except (OSError, subprocess.SubprocessError):
            return ""

    dirty = [line[3:] for line in git("status", "--porcelain", "--", ".").splitlines() if line]
    return {
        "rockcem_path": str(pkg),
        "rockcem_source_sha256": digest.hexdigest(),
        "git_commit": git("rev-parse", "HEAD").strip() or "not a git checkout",
        "git_uncommitted_rockcem_files": " ".join(dirty) or "none",
    }


def announce_source():
    """Fingerprint the rockcem just imported (others may edit the checkout) and print it."""
    src = source_attrs()
    print(f"rockcem from {src['rockcem_path']}, commit {src['git_commit'][:10]}, uncommitted: "
          f"{src['git_uncommitted_rockcem_files']}, sources sha256 "
          f"{src['rockcem_source_sha256'][:12]}", flush=True)
    return src


def result_path(name, ext, tag=""):
    """``benchmarks/results/<name>[_<tag>].<ext>``."""
    return RESULTS / (f"{name}_{tag}.{ext}" if tag else f"{name}.{ext}")


def _cpu_name():
    try:
        with open("/proc/cpuinfo") as fh:
            for line in fh:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


# ----------------------------------------------------------------------------- atomic output
def _atomic(path, write):
    """Call ``write(tmp_path)`` on a temporary file next to ``path``, then rename it."""
    from rockcem._atomic import atomic_write

    return atomic_write(path, write)


def write_csv(frame, path, attrs=None):
    """Write a pandas DataFrame as CSV, with ``attrs`` as leading ``# key: value`` lines."""
    def write(tmp):
        with open(tmp, "w", newline="") as fh:
            for key, value in (attrs or {}).items():
                fh.write(f"# {key}: {value}\n")
            frame.to_csv(fh, index=False)
    return _atomic(path, write)


def write_netcdf(ds, path):
    """Write an xarray Dataset with the netCDF4 engine."""
    return _atomic(path, lambda tmp: ds.to_netcdf(tmp, engine="netcdf4"))


def save_figure(fig, path, dpi=120):
    """Save a matplotlib figure as PNG and close it."""
    import matplotlib.pyplot as plt

    try:
        return _atomic(path, lambda tmp: fig.savefig(tmp, format="png", dpi=dpi,
                                                     bbox_inches="tight"))
    finally:
        plt.close(fig)


def use_agg():
    """Select the non-interactive Agg backend (call before importing pyplot)."""
    import matplotlib

    matplotlib.use("Agg")


# ----------------------------------------------------------------------------- SC baseline
def sandstone_sc_phases(profile, pore_fluid_K, aspect_ratio=0.108):
    """The three SC phases of the sandstone: quartz spheres, cement spheres, fluid spheroids.

    Returns ``K, G, fractions, aspect`` of shape (n, 3) (GPa, GPa, fractions, aspect ratio), with
    the moduli of Table 1 of Carcione et al. (2022) from the rockcem catalogue.
    """
    from rockcem.materials import mineral

    q, c = mineral("quartz"), mineral("quartz_cement")
    phi = profile["porosity"]
    beta = profile["solid_fractions"]
    frac = np.concatenate([(1.0 - phi)[:, None] * beta, phi[:, None]], axis=-1)
    shape = frac.shape
    K = np.broadcast_to(np.array([q.K, c.K, pore_fluid_K]), shape)
    G = np.broadcast_to(np.array([q.G, c.G, 0.0]), shape)
    aspect = np.broadcast_to(np.array([1.0, 1.0, aspect_ratio]), shape)
    return K, G, frac, aspect


def self_consistent_scipy(K, G, fractions, aspect, *, xtol=1e-13, ftol=1e-13):
    """Per-point baseline of Berryman's SC scheme: eq. 8 of Carcione et al. (2022) solved with
    :func:`scipy.optimize.root` (``method="hybr"``) point by point.

    .. math:: \\sum_i \\phi_i (K_i - K) P_i = 0, \\qquad \\sum_i \\phi_i (\\mu_i - \\mu) Q_i = 0

    with P, Q from :func:`rockcem.inclusions.berryman_pq`. Independent of the library's solver:
    MINPACK's hybrid Powell method, the Voigt average as starting point, unknowns and equations
    scaled by the largest phase bulk modulus. Outside ``K, G > 0`` (where P, Q are undefined)
    the residual is a large constant, which makes hybr shorten its step.

    Returns
    -------
    K, G : ndarray, shape (n,)
        Effective moduli, GPa.
    success : ndarray of bool, shape (n,)
        MINPACK reported success, or stopped with "xtol is too small" at a scaled residual
        below ``ftol`` (rounding level: the root is found to machine precision).
    nfev : ndarray of int, shape (n,)
        Function evaluations per point.
    """
    from scipy.optimize import root

    from rockcem.inclusions import berryman_pq

    n = fractions.shape[0]
    K_out = np.empty(n)
    G_out = np.empty(n)
    success = np.zeros(n, dtype=bool)
    nfev = np.zeros(n, dtype=int)
    for i in range(n):
        Ki, Gi, fi, ai = K[i], G[i], fractions[i], aspect[i]
        scale = float(np.max(Ki))

        def equations(x, Ki=Ki, Gi=Gi, fi=fi, ai=ai, scale=scale):
            k, g = x[0] * scale, x[1] * scale
            if not (k > 0.0 and g > 0.0):
                return np.array([1e3, 1e3])
            P, Q = berryman_pq(k, g, Ki, Gi, ai)
            return np.array([np.sum(fi * (Ki - k) * P), np.sum(fi * (Gi - g) * Q)]) / scale

        x0 = np.array([np.sum(fi * Ki), np.sum(fi * Gi)]) / scale
        sol = root(equations, x0, method="hybr", options={"xtol": xtol})
        K_out[i], G_out[i] = sol.x * scale
        success[i] = bool(sol.success) or bool(np.max(np.abs(sol.fun)) < ftol)
        nfev[i] = int(sol.nfev)
    return K_out, G_out, success, nfev

def md_source_attrs():
    """SHA-256 over the ``md`` package's ``.py`` sources and its uncommitted files (the
    ``_common`` provenance covers ``rockcem`` only)."""
    import hashlib
    import subprocess

    import md

    pkg = Path(md.__file__).resolve().parent
    digest = hashlib.sha256()
    for file in sorted(pkg.rglob("*.py")):
        digest.update(file.relative_to(pkg).as_posix().encode())
        digest.update(file.read_bytes())
    try:
        out = subprocess.run(["git", "-C", str(pkg), "status", "--porcelain", "--", "."],
                             capture_output=True, text=True, timeout=20, check=True).stdout
    except (OSError, subprocess.SubprocessError):
        out = ""
    dirty = [line[3:] for line in out.splitlines() if line]
    return {"md_path": str(pkg), "md_source_sha256": digest.hexdigest(),
            "git_uncommitted_md_files": " ".join(dirty) or "none"}

def cct_vp(porosity, coordination, cement, saturation, scheme, *, stiffness="fit"):
    """P velocity (km/s) of contact cement theory (``rockcem.granular.contact_cement``, scheme 1:
    cement at the contacts, 2: as a layer on the grains) for quartz of García & Medina's Table I
    cemented by ``cement`` (an ``md.CementMaterial``) filling ``saturation`` (array-like) of the
    pore space of a pack of ``porosity`` and ``coordination``; density of grains and cement."""
    from md.contact import QUARTZ
    from rockcem.granular import contact_cement

    G0, K0 = QUARTZ.shear_modulus / 1e9, QUARTZ.bulk_modulus / 1e9
    Gc = cement.shear_modulus / 1e9
    Kc = cement.p_modulus / 1e9 - 4.0 / 3.0 * Gc
    phi = porosity * (1.0 - np.asarray(saturation, dtype=float))
    m = contact_cement(K0, G0, Kc, Gc, phi, porosity, coordination, scheme=scheme,
                       stiffness=stiffness)
    rho = ((1.0 - porosity) * QUARTZ.density + (porosity - phi) * cement.density) / 1e3
    return np.sqrt((m.K + 4.0 / 3.0 * m.G) / rho)


def markdown(frame, columns):
    """A markdown table of ``columns`` (name -> (header, format)) of ``frame``."""
    head = "| " + " | ".join(h for h, _ in columns.values()) + " |"
    rule = "|" + "|".join("---:" for _ in columns) + "|"
    lines = [head, rule]
    for _, r in frame.iterrows():
        cells = []
        for col, (_, fmt) in columns.items():
            v = r[col]
            cells.append("" if (isinstance(v, float) and np.isnan(v)) else format(v, fmt))
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)
