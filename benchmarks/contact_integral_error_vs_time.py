"""Error against run time of the cemented-contact integral equation (knob: ``panels``).

Sweeps the number of collocation panels of :func:`rockcem.contact_integral.
cemented_contact_stiffness` over a grid of cement radius, stiffness ratio and contact thickness,
and records the error against a fine reference (1024 panels, itself checked against its
Richardson extrapolation from 512 panels) together with the wall time per point, excluding and
including the one-off build of the kernel matrix. It also records the error and cost of the
handbook polynomial fit of Dvorkin & Nur (the other ``stiffness`` option of
``contact_cement``) against the same reference, at zero thickness where the fit applies.

Output: ``benchmarks/results/contact_integral_error_vs_time.{csv,nc,png}``.

Run: ``python benchmarks/contact_integral_error_vs_time.py``
"""

from _common import (best_of, environment_attrs, relative_difference, result_path, save_figure,
                     use_agg, write_csv, write_netcdf)

import time  # noqa: E402

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
import xarray as xr  # noqa: E402

from rockcem import contact_integral  # noqa: E402
from rockcem.granular import _cct_stiffness  # noqa: E402

PANELS = [8, 16, 24, 32, 48, 64, 96, 128, 192, 256]
REFERENCE_PANELS = 1024


def grid():
    alpha, lam, eps = np.meshgrid(np.linspace(0.05, 0.5, 6), np.geomspace(0.02, 5.0, 6),
                                  [0.0, 0.005, 0.02, 0.05], indexing="ij")
    return alpha.ravel(), lam.ravel(), eps.ravel()


def main():
    alpha, lam, eps = grid()
    npts = alpha.size
    S = contact_integral.cemented_contact_stiffness
    ref = S(alpha, lam, eps, panels=REFERENCE_PANELS)
    half = S(alpha, lam, eps, panels=REFERENCE_PANELS // 2)
    richardson = ref + (ref - half) / 3.0           # second-order convergence
    ref_err = float(np.max(relative_difference(ref, richardson)))
    rows = []
    for n in PANELS:
        contact_integral._unit_matrix.cache_clear()
        t0 = time.perf_counter()
        contact_integral._unit_matrix(n)
        build = time.perf_counter() - t0
        best, _, val, _ = best_of(lambda: S(alpha, lam, eps, panels=n), repeat=5, budget_s=5.0)
        err = relative_difference(val, ref)
        rows.append(dict(method="integral", panels=n, max_rel_error=float(err.max()),
                         median_rel_error=float(np.median(err)), seconds_per_point=best / npts,
                         build_seconds=build))
    zero = eps == 0.0
    best, _, fit, _ = best_of(lambda: _cct_stiffness(alpha[zero], lam[zero], 1.0, 0.1)[0],
                              repeat=20)
    err_fit = relative_difference(fit, ref[zero])
    in_range = (lam[zero] >= 0.1) & (lam[zero] <= 1.0)
    rows.append(dict(method="handbook_fit", panels=0, max_rel_error=float(err_fit.max()),
                     median_rel_error=float(np.median(err_fit)),
                     seconds_per_point=best / zero.sum(), build_seconds=0.0))
    rows.append(dict(method="handbook_fit_0.1<=Lambda<=1", panels=0,
                     max_rel_error=float(err_fit[in_range].max()),
                     median_rel_error=float(np.median(err_fit[in_range])),
                     seconds_per_point=best / zero.sum(), build_seconds=0.0))
    table = pd.DataFrame(rows)
    attrs = environment_attrs(
        benchmark="contact_integral_error_vs_time", knob="panels", points=npts,
        reference_panels=REFERENCE_PANELS, reference_richardson_max_rel=ref_err,
        grid="alpha 0.05-0.5 (6) x Lambda 0.02-5 geometric (6) x eps {0, 0.005, 0.02, 0.05}")
    write_csv(table, result_path("contact_integral_error_vs_time", "csv"), attrs)
    integral = table[table.method == "integral"]
    ds = xr.Dataset(
        {k: ("panels", integral[k].to_numpy()) for k in
         ("max_rel_error", "median_rel_error", "seconds_per_point", "build_seconds")},
        coords={"panels": integral.panels.to_numpy()}, attrs=attrs)
    for k, u in (("max_rel_error", "1"), ("median_rel_error", "1"), ("seconds_per_point", "s"),
                 ("build_seconds", "s")):
        ds[k].attrs["units"] = u
    write_netcdf(ds, result_path("contact_integral_error_vs_time", "nc"))
    use_agg()
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4.5))
    ax.loglog(integral.seconds_per_point, integral.max_rel_error, "o-", label="integral, max")
    ax.loglog(integral.seconds_per_point, integral.median_rel_error, "s--", label="integral, median")
    for (_, r), n in zip(integral.iterrows(), integral.panels):
        ax.annotate(str(n), (r.seconds_per_point, r.max_rel_error), fontsize=7,
                    xytext=(3, 3), textcoords="offset points")
    for _, r in table[table.method != "integral"].iterrows():
        ax.loglog(r.seconds_per_point, r.max_rel_error, "x", ms=9, label=r.method.replace("_", " "))
    ax.set_xlabel("wall time per point (s)")
    ax.set_ylabel("relative error of S against 1024 panels")
    ax.set_title("Cemented-contact stiffness: error vs run time (labels: panels)")
    ax.grid(True, which="both", ls=":")
    ax.legend(fontsize=8)
    save_figure(fig, result_path("contact_integral_error_vs_time", "png"))
    print(table.to_string(index=False))
    print(f"reference vs its Richardson extrapolation: max rel {ref_err:.2e}")


if __name__ == "__main__":
    main()
