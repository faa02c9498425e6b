"""Speed and memory of rockcem.reflectivity against bruges over 10^4 depths x 40 angles x 4 models
x 3 fluids (4.8 million reflection coefficients), and the block size of the exact solution.

* The interfaces: random shale-over-sand media of shape (3 fluids, 4 models, 10^4 depths, 1) and
  40 angles from 0 to 45 degrees on the last axis (rockcem), or the same media of shape
  (3, 4, 10^4) and the 40 angles (bruges, which puts the angle on a new first axis).
* Each case runs ``--repeat`` times, the libraries interleaved (ours, bruges, ours, ...), after
  one warm-up; the best time is reported. The peak memory of one call is measured with
  ``tracemalloc`` (numpy reports its allocations to it), the inputs excluded.
* The agreement of the two libraries on these inputs: the largest difference (rockcem's exact
  coefficient against the complex conjugate of bruges's: its time convention, see the module
  docstring of rockcem.reflectivity).
* The block size of rockcem's exact solution (:data:`rockcem.reflectivity._BLOCK`), swept.

Output: ``benchmarks/results/reflectivity_speed.{csv,md}``. Run:
``python benchmarks/reflectivity_speed.py`` (``--depths 1000`` for a quick look).
"""

from _common import ROOT, best_of, environment_attrs, markdown, result_path, write_csv

import argparse  # noqa: E402
import tracemalloc  # noqa: E402

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402


def media(n_depth, rng):
    shape = (3, 4, n_depth)
    vp1 = rng.uniform(2.2, 3.6, shape)
    vp2 = rng.uniform(1.8, 4.2, shape)
    return (vp1, vp1 * rng.uniform(0.40, 0.55, shape), rng.uniform(2.2, 2.5, shape),
            vp2, vp2 * rng.uniform(0.45, 0.65, shape), rng.uniform(2.0, 2.5, shape))


def peak_mib(fn):
    tracemalloc.start()
    try:
        fn()
        return tracemalloc.get_traced_memory()[1] / 2**20
    finally:
        tracemalloc.stop()


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--depths", type=int, default=10_000)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args(argv)
    import bruges
    from bruges.reflection import reflection as B

    from rockcem import reflectivity as R

    rng = np.random.default_rng(31)
    m = media(args.depths, rng)
    ours_args = [x[..., None] for x in m]
    angles = np.linspace(0.0, 45.0, 40)
    n = m[0].size * angles.size
    cases = {
        "exact (Zoeppritz)": (lambda: R.zoeppritz_pp(*ours_args, angles),
                              lambda: B.zoeppritz_rpp(*m, angles)),
        "Aki-Richards": (lambda: R.aki_richards_pp(*ours_args, angles),
                         lambda: B.akirichards(*m, angles)),
        "Shuey, 3 terms": (lambda: R.shuey_pp(*ours_args, angles),
                           lambda: B.shuey(*m, angles)),
    }
    rows = []
    agreement = {}
    for case, (ours, theirs) in cases.items():
        ours(), theirs()                                        # warm-up
        t_ours, t_theirs = [], []
        for _ in range(args.repeat):                            # interleaved
            t_ours.append(best_of(ours, 1)[0])
            t_theirs.append(best_of(theirs, 1)[0])
        a, b = ours(), np.moveaxis(theirs(), 0, -1)
        if np.iscomplexobj(a):
            diff = np.abs(a - np.conj(b))
        else:      # the linearisations: before the P critical angle (bruges: complex beyond)
            before = np.sin(np.radians(angles)) * ours_args[3] / ours_args[0] < 1.0
            diff = np.where(before, np.abs(a - b.real), 0.0)
        agreement[case] = float(diff.max())
        for lib, times, fn in (("rockcem", t_ours, ours), ("bruges", t_theirs, theirs)):
            rows.append(dict(case=case, library=lib, coefficients=n, best_s=min(times),
                             median_s=float(np.median(times)), peak_mib=peak_mib(fn),
                             block=R._BLOCK if lib == "rockcem" else 0))
    def everything():
        """What a stack scene asks of the library for these interfaces."""
        R.zoeppritz_pp(*ours_args, angles)
        R.aki_richards_pp(*ours_args, angles)
        R.shuey_pp(*ours_args, angles, terms=2)
        R.shuey_pp(*ours_args, angles)
        t = R.intercept_gradient(*m)
        R.avo_class(t.intercept, t.gradient)

    rows.append(dict(case="all: exact, A-R, Shuey 2 and 3, A/B/C, class", library="rockcem",
                     coefficients=n, best_s=best_of(everything, args.repeat)[0],
                     median_s=np.nan, peak_mib=peak_mib(everything), block=R._BLOCK))
    default = R._BLOCK
    for block in (1 << 10, 1 << 12, 1 << 14, 1 << 16, 1 << 30):
        R._BLOCK = block
        best = best_of(lambda: R.zoeppritz_pp(*ours_args, angles), args.repeat)[0]
        rows.append(dict(case="exact, block sweep", library="rockcem", coefficients=n,
                         best_s=best, median_s=np.nan,
                         peak_mib=peak_mib(lambda: R.zoeppritz_pp(*ours_args, angles)),
                         block=block))
    R._BLOCK = default
    frame = pd.DataFrame(rows)
    attrs = environment_attrs(depths=args.depths, angles=40, models=4, fluids=3,
                              repeat=args.repeat, bruges_version=bruges.__version__,
                              default_block=default)
    write_csv(frame, result_path("reflectivity_speed", "csv"), attrs)
    table = markdown(frame, {"case": ("case", "s"), "library": ("library", "s"),
                             "block": ("block", "d"), "best_s": ("best s", ".3f"),
                             "median_s": ("median s", ".3f"), "peak_mib": ("peak MiB", ".0f")})
    def ratio(column):
        exact = frame[frame.case == "exact (Zoeppritz)"].set_index("library")[column]
        return exact["bruges"] / exact["rockcem"]

    lines = [
        "# Reflectivity: rockcem against bruges, 10^4 depths x 40 angles x 4 models x 3 fluids",
        "",
        f"Written by `benchmarks/reflectivity_speed.py` on {attrs['date_utc']} "
        f"(Python {attrs['python_version']}, numpy {attrs['numpy_version']}, bruges "
        f"{bruges.__version__}, {attrs['processor']}, {attrs['cpu_count']} cores shared with "
        f"other work, single-threaded; commit {attrs.get('git_commit', '?')}). {n:,} "
        f"coefficients a call ({args.depths} depths); best and median of {args.repeat} runs, "
        "rockcem and bruges interleaved; peak memory of one call by tracemalloc, inputs "
        "excluded. `block` is rockcem's block size of the exact solution (0: bruges).",
        "",
        table,
        "",
        "Largest difference on these inputs (rockcem against bruges; the exact coefficient "
        "against the complex conjugate of bruges's, its time convention; the linearisations "
        "before the P critical angle, beyond which bruges's are complex):",
        "",
        *[f"- {case}: {value:.1e}" for case, value in agreement.items()],
        "",
        "## Decision: bruges is not used at run time",
        "",
        f"- Speed and memory of the exact coefficient: bruges took {ratio('best_s'):.1f} times "
        f"rockcem's best time and {ratio('peak_mib'):.0f} times its peak memory (it evaluates "
        "complex arcsines and sines of every angle on the full array; rockcem works on "
        "vertical slownesses, complex only where a wave is evanescent, in cache-sized blocks, "
        "so that a call needs little more than its result).",
        "- Layout: bruges puts the angles on a new first axis and takes one 1-D angle array; "
        "rockcem broadcasts all arguments (angles last, as the stack's Dataset has them) and "
        "takes labelled inputs.",
        "- Inputs: bruges adds 1e-12 km/s to both S velocities and checks only the angle; its "
        "`critical_angles` takes scalars only; beyond a critical angle its coefficients are "
        "those of the exp(+i omega t) convention (the complex conjugates of Aki & Richards').",
        "- The Ricker wavelet is one line of Ricker (1953).",
        "",
        "bruges stays in the `test` extra: tests/test_reflectivity.py and "
        "tests/test_synthetics.py compare against it to 1e-10.",
        "",
        "The machine was shared with other jobs while this ran: a call's median time was up to "
        f"{(frame.median_s / frame.best_s).max():.1f} times its best, hence best-of and "
        "interleaving.",
        "",
    ]
    from rockcem._atomic import atomic_write

    path = result_path("reflectivity_speed", "md")
    atomic_write(path, lambda tmp: open(tmp, "w", encoding="utf-8").write("\n".join(lines)))
    print("\n".join(lines))
    print(f"wrote {path.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
