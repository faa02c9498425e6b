"""Speed of rockcem's granular-medium functions against rockphypy's on the same 10^6 inputs.

rockphypy (``rockphypy.GM``, version 0.0.2; a peer for this benchmark only, never a dependency of
rockcem) implements the same closed forms without input checks: ``hertzmindlin``, ``softsand``,
``stiffsand``, ``contactcement``, ``constantcement`` and ``MUHS`` (increasing cement). Every
pair is first checked to give the same values (relative difference at most 1e-12 on every
point), then timed.

The peer gets its best settings: float64 contiguous numpy arrays where its docstrings take
arrays, plain Python floats for everything else (its docstrings' "float"), one warm-up call,
single-threaded numpy, no warning filtering in the timed call (it raises none on these inputs).
rockcem is called the way a user calls it (its public functions with every input check).

Timing: ``--rounds`` rounds (default 7); in each round every case is timed once for each
library, the two interleaved and their order swapped from round to round, so that a load
change on the (shared) machine hits both alike; the best time of each is kept. The ratio is
the peer's best time over rockcem's best time (> 1: rockcem faster). Run on one core, e.g.
``taskset -c 0 python benchmarks/granular_vs_rockphypy.py``.

Output: ``benchmarks/results/granular_vs_rockphypy.{csv,md}``.
"""

from __future__ import annotations

import _common  # noqa: I001  (first: pins threads before numpy is imported)

import argparse  # noqa: E402
import os  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402

import numpy as np  # noqa: E402

TARGET_RATIO = 1.0     # every granular function at least as fast as rockphypy's
VALUE_RTOL = 1e-12     # values must agree to this before timing


def cases(n):
    """The six pairs over ``n`` points: (name, rockcem call, rockphypy call, array inputs)."""
    from rockphypy import GM

    from rockcem import granular
    from rockcem.materials import mineral

    quartz, cement = mineral("quartz"), mineral("quartz_cement")
    K0, G0, Kc, Gc = float(quartz.K), float(quartz.G), float(cement.K), float(cement.G)
    phic, cn, f, phib = 0.4, 8.6, 0.5, 0.37
    s = np.linspace(0.0, 1.0, int(n))
    pressure = 1.0 + 59.0 * s             # MPa, 1-60 (rockphypy's soft sand is 0/0 at 0 MPa)
    phi = 0.02 + (phic - 0.02) * s        # soft and stiff sand: 0.02 .. phic
    phi_cct = 0.3 + (phic - 0.3) * s      # contact cement: 0.3 .. phic (a/R up to 0.6)
    phi_b = 0.02 + (phib - 0.02) * s      # constant and increasing cement: 0.02 .. phib
    return [
        ("hertz_mindlin", "pressure",
         lambda: granular.hertz_mindlin(K0, G0, phic, cn, pressure, f),
         lambda: GM.hertzmindlin(K0, G0, phic, cn, pressure, f)),
        ("soft_sand", "porosity, pressure",
         lambda: granular.soft_sand(K0, G0, phi, phic, cn, pressure, f),
         lambda: GM.softsand(K0, G0, phi, phic, cn, pressure, f)),
        ("stiff_sand", "porosity, pressure",
         lambda: granular.stiff_sand(K0, G0, phi, phic, cn, pressure, f),
         lambda: GM.stiffsand(K0, G0, phi, phic, cn, pressure, f)),
        ("contact_cement", "porosity",
         lambda: granular.contact_cement(K0, G0, Kc, Gc, phi_cct, phic, cn, 1),
         lambda: GM.contactcement(K0, G0, Kc, Gc, phi_cct, phic, cn, 1)),
        ("constant_cement", "porosity",
         lambda: granular.constant_cement(K0, G0, Kc, Gc, phi_b, phic, cn, phib, 1),
         lambda: GM.constantcement(phib, K0, G0, Kc, Gc, phi_b, phic, cn, 1)),
        ("increasing_cement", "porosity",
         lambda: granular.increasing_cement(K0, G0, Kc, Gc, phi_b, phic, cn, phib, 1),
         lambda: GM.MUHS(K0, G0, Kc, Gc, phi_b, phib, phic, cn, 1)),
    ]


def _time(fn):
    t0 = time.perf_counter()
    fn()
    return time.perf_counter() - t0


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--n", type=int, default=10**6, help="points (default 1e6)")
    parser.add_argument("--rounds", type=int, default=7, help="interleaved rounds (default 7)")
    parser.add_argument("--tag", default="", help="suffix of the result file names")
    args = parser.parse_args(argv)

    import importlib.metadata

    import pandas as pd

    _common.announce_source()
    load_before = os.getloadavg()[0]
    rows = []
    all_cases = cases(args.n)
    for name, arrays, ours, peer in all_cases:         # values first, and the warm-up calls
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            a, b = ours(), peer()
        diff = max(float(np.max(_common.relative_difference(x, np.broadcast_to(y, np.shape(x)))))
                   for x, y in zip(a, b))
        if not diff <= VALUE_RTOL:
            raise SystemExit(f"{name}: rockcem and rockphypy differ by {diff:.3g} > {VALUE_RTOL}")
        rows.append({"function": name, "array_inputs": arrays, "n_points": args.n,
                     "max_rel_diff": diff, "rockcem": [], "rockphypy": []})
    for r in range(args.rounds):
        for row, (_, _, ours, peer) in zip(rows, all_cases):
            order = [("rockcem", ours), ("rockphypy", peer)]
            for lib, fn in order if r % 2 == 0 else order[::-1]:
                row[lib].append(_time(fn))
    out = []
    for row in rows:
        ours, peer = min(row.pop("rockcem")), min(row.pop("rockphypy"))
        out.append({**row, "rockcem_best_s": ours, "rockphypy_best_s": peer,
                    "speed_ratio": peer / ours, "rounds": args.rounds,
                    "meets_target": bool(peer / ours >= TARGET_RATIO)})
        print(f"{row['function']:18s} rockcem {ours * 1e3:8.2f} ms  rockphypy {peer * 1e3:8.2f} ms"
              f"  ratio {peer / ours:5.2f}  (values within {row['max_rel_diff']:.1e})", flush=True)
    frame = pd.DataFrame(out)
    attrs = _common.environment_attrs(
        title="rockcem granular functions against rockphypy, same inputs, one core",
        benchmark="granular_vs_rockphypy", n_points=args.n, rounds=args.rounds,
        rockphypy_version=importlib.metadata.version("rockphypy"),
        timing="interleaved rounds, order swapped each round, best of rounds per library",
        ratio="rockphypy best time / rockcem best time (> 1: rockcem faster)",
        target_ratio=TARGET_RATIO, value_rtol=VALUE_RTOL,
        load_average_1min=f"{load_before:.2f} before, {os.getloadavg()[0]:.2f} after "
                          f"(on {os.cpu_count()} cores, shared with other work)")
    _common.write_csv(frame, _common.result_path("granular_vs_rockphypy", "csv", args.tag), attrs)
    table = _common.markdown(frame.assign(
        rockcem_ms=frame["rockcem_best_s"] * 1e3, rockphypy_ms=frame["rockphypy_best_s"] * 1e3),
        {"function": ("function", "s"), "array_inputs": ("arrays of 10^6", "s"),
         "rockcem_ms": ("rockcem, ms", ".1f"), "rockphypy_ms": ("rockphypy, ms", ".1f"),
         "speed_ratio": ("ratio (rockphypy / rockcem time)", ".2f"),
         "max_rel_diff": ("max rel. difference of values", ".1e")})
    md = _common.result_path("granular_vs_rockphypy", "md", args.tag)
    commit = attrs["git_commit"]
    source = (f"commit {commit[:10]} (uncommitted: {attrs['git_uncommitted_rockcem_files']})"
              if commit != "not a git checkout" else f"rockcem from {attrs['rockcem_path']}")
    text = (f"{attrs['date_utc']}, {source}, rockcem sources sha256 "
            f"{attrs['rockcem_source_sha256'][:12]}, {attrs['processor']}, "
            f"load average {attrs['load_average_1min']}, "
            f"rockphypy {attrs['rockphypy_version']}, numpy {attrs['numpy_version']}; "
            f"{args.n} points, best of {args.rounds} interleaved rounds, one core\n\n{table}\n")
    _common._atomic(md, lambda tmp: open(tmp, "w").write(text))
    print(f"wrote {md}")


if __name__ == "__main__":
    main()
