"""The quantile estimator of uncertain scenes against exact quantiles, N = 10^4 members.

Three outputs whose quantiles are known exactly, each driven by one normal input:

* ``temperature`` at 1, 2 and 3 km with ``path.gradient`` ~ N(30, 2.5) degC/km:
  :math:`T = T_0 + G z` is linear in G, so :math:`T_p = T_0 + (\\mu + \\sigma z_p) z`;
* ``pressure_effective`` at 1, 2 and 3 km with ``pressure.sediment_density`` ~ N(2.4, 0.05):
  :math:`p_e = 10^{-3} g (\\rho - \\rho_w) z` (Carcione et al. 2022, eq. 1) is linear in rho;
* ``vp`` of Model 1 (hs_gassmann) at 3 km with the normal gradient: a monotone function f of
  one input has the quantiles :math:`f(G_p)` (or :math:`f(G_{1-p})` where f falls), so the
  exact quantile is the scene run with the gradient fixed at :math:`G_p`; its density at the
  quantile, :math:`\\varphi(z_p) / (\\sigma |f'(G_p)|)`, with f' by central differences.

Each against its standard error as a sample quantile of N independent members,
:math:`\\sqrt{p (1 - p) / N} / f(x_p)` (Walker 1968; Rao 1973, sect. 6f.2), for the designs
``random`` (independent draws: the error should be of that size, |error| / SE mostly < 2) and
``lhs`` (a Latin hypercube: far smaller for a monotone response).

Output: ``benchmarks/results/uncertainty_quantiles.{csv,nc}``. Run:
``python benchmarks/uncertainty_quantiles.py`` (``--samples`` for another N).
"""

from _common import announce_source, environment_attrs, result_path, write_csv, write_netcdf

import argparse  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
import xarray as xr  # noqa: E402
from scipy import stats  # noqa: E402

QUANTILES = [0.1, 0.5, 0.9]
DEPTHS = [1000.0, 2000.0, 3000.0]
G_MEAN, G_SD = 30.0, 2.5
RHO_MEAN, RHO_SD = 2.4, 0.05


def base(outputs, uncertain):
    return {"name": "quantile_check", "lithology": "sandstone", "outputs": outputs,
            "path": {"sedimentation_rate": 40.0, "max_depth": 4000.0, "depth_step": 100.0},
            "models": {"hs_gassmann": {}}, "uncertain": uncertain}


def run(raw):
    from rockcem.scene import run_scene, scene_from_dict

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        t = time.perf_counter()
        ds = run_scene(scene_from_dict(raw), max_members=10**6)
        return ds, time.perf_counter() - t


def model1_vp(gradient, z):
    """Model 1's vp at depth z of the scene run with a fixed gradient."""
    from rockcem.scene import run_scene, scene_from_dict

    raw = base(["vp"], None)
    del raw["uncertain"]
    raw["path"]["gradient"] = float(gradient)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return float(run_scene(scene_from_dict(raw))["vp"].sel(model="hs_gassmann",
                                                                  depth=z))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=10_000)
    args = parser.parse_args(argv)
    n = args.samples
    import rockcem  # noqa: F401

    announce_source()
    from rockcem._uncertain import quantile_standard_error

    p = np.array(QUANTILES)
    zp = stats.norm.ppf(p)
    rows = []
    for design in ("random", "lhs"):
        grad = {"samples": n, "seed": 1, "design": design, "path.gradient": {
            "distribution": "normal", "mean": G_MEAN, "sd": G_SD}}
        ds, seconds = run(base(["temperature", "vp"], grad))
        for z in DEPTHS:
            exact = 15.0 + (G_MEAN + G_SD * zp) * z / 1000.0
            density = stats.norm.pdf(zp) / (G_SD * z / 1000.0)
            got = ds["temperature"].sel(depth=z).values
            rows += [dict(design=design, output="temperature", depth=z, quantile=q,
                          exact=e, estimate=g, error=g - e,
                          standard_error=quantile_standard_error(q, n, d), seconds=seconds)
                     for q, e, g, d in zip(p, exact, got, density)]
        z, h = 3000.0, 0.01
        grid = np.array([model1_vp(g, z) for g in G_MEAN + G_SD * np.linspace(-4, 4, 33)])
        rising = bool(np.all(np.diff(grid) > 0))
        if not (rising or np.all(np.diff(grid) < 0)):
            raise SystemExit("Model 1's vp at 3 km is not monotone in the gradient: no exact "
                             "quantile this way")
        for q in p:
            gq = G_MEAN + G_SD * stats.norm.ppf(q if rising else 1.0 - q)
            exact = model1_vp(gq, z)
            slope = (model1_vp(gq + h, z) - model1_vp(gq - h, z)) / (2 * h)
            density = stats.norm.pdf((gq - G_MEAN) / G_SD) / (G_SD * abs(slope))
            got = float(ds["vp"].sel(model="hs_gassmann", depth=z, quantile=q))
            rows.append(dict(design=design, output="vp_hs_gassmann", depth=z, quantile=q,
                             exact=exact, estimate=got, error=got - exact,
                             standard_error=quantile_standard_error(q, n, density),
                             seconds=seconds))
        rho = {"samples": n, "seed": 2, "design": design, "pressure.sediment_density": {
            "distribution": "normal", "mean": RHO_MEAN, "sd": RHO_SD}}
        ds, seconds = run(base(["pressure_effective"], rho))
        from rockcem.constants import STANDARD_GRAVITY

        for z in DEPTHS:
            k = 1e-3 * STANDARD_GRAVITY * z
            exact = k * (RHO_MEAN + RHO_SD * zp - 1.04)
            density = stats.norm.pdf(zp) / (RHO_SD * k)
            got = ds["pressure_effective"].sel(depth=z).values
            rows += [dict(design=design, output="pressure_effective", depth=z, quantile=q,
                          exact=e, estimate=g, error=g - e,
                          standard_error=quantile_standard_error(q, n, d), seconds=seconds)
                     for q, e, g, d in zip(p, exact, got, density)]
    table = pd.DataFrame(rows)
    table["error_over_se"] = table["error"] / table["standard_error"]
    attrs = environment_attrs(benchmark="uncertainty_quantiles", samples=n,
                              standard_error="sqrt(p (1 - p) / N) / f(x_p), Walker 1968",
                              quantile_estimator="numpy.quantile linear (Hyndman & Fan type 7)")
    write_csv(table, result_path("uncertainty_quantiles", "csv"), attrs)
    out = xr.Dataset.from_dataframe(table)
    out.attrs.update(attrs)
    write_netcdf(out, result_path("uncertainty_quantiles", "nc"))
    with pd.option_context("display.width", 160):
        print(table.drop(columns="seconds").to_string(index=False))
    for design, part in table.groupby("design"):
        print(f"{design}: largest |error| / SE = {part['error_over_se'].abs().max():.3g}, "
              f"share within 2 SE {np.mean(part['error_over_se'].abs() < 2):.2f}")


if __name__ == "__main__":
    main()
