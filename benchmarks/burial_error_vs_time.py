"""Error against run time of the burial kinetics: exact scheme vs explicit Euler vs Radau.

Two paths, two kinetics:

* ``worked_example`` — the linear basin model of Carcione et al. (2022, Sect. 6): G = 30 degC/km,
  S = 40 m/Myr, T0 = 15 degC, to 5 km (125 Myr).
* ``fast_heating`` — burial to 2 km at 1.2 degC/Myr, then a heating event of 100 degC/Myr to 230 degC
  (an intrusion), 2 Myr at that temperature and cooling back at 20 degC/Myr.

For quartz cement (Walderhaug, App. B) and the smectite fraction (Pytte & Reynolds, App. A) each
method gives the value at the end of the path, compared with the exact scheme of ``burial``
(closed-form integrals over each linear piece; checked here against Radau at rtol 1e-13):

* ``exact``: ``burial.quartz_cement`` / ``burial.smectite_fraction`` on the path's own nodes;
* ``euler``: explicit Euler at dt = 10 … 0.001 Myr (the source steps eq. B.1 at dt = 0.1 Myr);
* ``radau``: ``scipy.integrate.solve_ivp(method="Radau")`` at rtol = 1e-2 … 1e-12.

Output: ``benchmarks/results/burial_error_vs_time.{csv,nc,png}``; also the wall time of the exact
scheme for 10^4 depths x 10^3 nodes. Run: ``python benchmarks/burial_error_vs_time.py``
"""

from _common import (best_of, environment_attrs, result_path, save_figure, use_agg, write_csv,
                     write_netcdf)

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
import xarray as xr  # noqa: E402
from scipy.integrate import solve_ivp  # noqa: E402

import burial  # noqa: E402
from rockcem.constants import GAS_CONSTANT_CAL, SECONDS_PER_MYR  # noqa: E402

PHI0, D_MM, F = 0.36, 0.3, 0.65
K_Q = 60.09 * 1.98e-22 * (6 * F / (D_MM / 10)) / (2.65 * PHI0) * SECONDS_PER_MYR   # 1/Myr
B = 0.022
E_R = 36.0e3 / GAS_CONSTANT_CAL
C, R0, ORDER = 1.217e23, 0.99, 5

PATHS = {
    "worked_example": (np.array([0.0, 125.0]), np.array([0.0, 5000.0]), np.array([15.0, 165.0])),
    "fast_heating": (np.array([0.0, 62.5, 63.4, 65.4, 73.4]),
                     np.array([0.0, 2500.0, 2500.0, 2500.0, 2500.0]),
                     np.array([15.0, 90.0, 180.0, 180.0, 20.0])),
}
EULER_DT = [10.0, 3.0, 1.0, 0.3, 0.1, 0.03, 0.01, 0.003, 0.001]
RADAU_RTOL = [1e-2, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12]


def rates(kind, t_nodes, T_nodes):
    if kind == "quartz":
        return lambda t, y: K_Q * (PHI0 - y) * 10.0 ** (B * np.interp(t, t_nodes, T_nodes))
    return lambda t, y: -C * np.maximum(y, 0.0) ** ORDER * np.exp(
        -E_R / (np.interp(t, t_nodes, T_nodes) + 273.15))


def exact(kind, path):
    if kind == "quartz":
        return float(burial.quartz_cement(path, PHI0, D_MM, F)[-1])
    return float(burial.smectite_fraction(path, R0, ORDER)[-1])


def euler(kind, t_nodes, T_nodes, dt):
    f = rates(kind, t_nodes, T_nodes)
    n = int(np.ceil(t_nodes[-1] / dt))
    h = t_nodes[-1] / n
    y = 0.0 if kind == "quartz" else R0
    with np.errstate(all="ignore"):
        for i in range(n):
            y = y + h * f(i * h, y)
    return float(y)


def radau(kind, t_nodes, T_nodes, rtol):
    f = rates(kind, t_nodes, T_nodes)
    y0 = 0.0 if kind == "quartz" else R0
    sol = solve_ivp(lambda t, y: [f(t, y[0])], (0.0, t_nodes[-1]), [y0], method="Radau",
                    rtol=rtol, atol=rtol * 1e-6, max_step=float(np.min(np.diff(t_nodes))))
    return float(sol.y[0, -1])


def main():
    rows = []
    for pname, (t, z, T) in PATHS.items():
        path = burial.path_from_nodes(t, z, T)
        for kind in ("quartz", "smectite"):
            ref = exact(kind, path)
            check = radau(kind, t, T, 1e-13)
            best, _, val, _ = best_of(lambda: exact(kind, path), repeat=20)
            rows.append(dict(path=pname, kinetics=kind, method="exact", knob=np.nan, value=val,
                             reference=ref, rel_error=abs(val / ref - 1), seconds=best,
                             radau_1e13_rel=abs(check / ref - 1)))
            for dt in EULER_DT:
                best, _, val, _ = best_of(lambda: euler(kind, t, T, dt), repeat=3, budget_s=10.0)
                err = abs(val / ref - 1) if np.isfinite(val) else np.inf
                rows.append(dict(path=pname, kinetics=kind, method="euler", knob=dt, value=val,
                                 reference=ref, rel_error=err, seconds=best, radau_1e13_rel=np.nan))
            for rtol in RADAU_RTOL:
                best, _, val, _ = best_of(lambda: radau(kind, t, T, rtol), repeat=3, budget_s=10.0)
                rows.append(dict(path=pname, kinetics=kind, method="radau", knob=rtol, value=val,
                                 reference=ref, rel_error=abs(val / ref - 1), seconds=best,
                                 radau_1e13_rel=np.nan))
    table = pd.DataFrame(rows)
    # The exact scheme on the Pareto front: no other run is both cheaper and more accurate.
    pareto = {}
    for (pname, kind), grp in table.groupby(["path", "kinetics"]):
        ex = grp[grp.method == "exact"].iloc[0]
        others = grp[grp.method != "exact"]
        pareto[f"{pname}/{kind}"] = bool(not np.any((others.seconds <= ex.seconds)
                                                    & (others.rel_error <= ex.rel_error)))
    # Throughput: 10^4 depths x 10^3 nodes.
    tt = np.linspace(0.0, 100.0, 1000)
    zz = np.linspace(500.0, 5000.0, 10_000)[:, None] * (tt / 100.0)
    big = burial.path_from_nodes(tt, zz, 15.0 + 0.03 * zz)
    t_q, *_ = best_of(lambda: burial.quartz_cement(big, PHI0, D_MM, F), repeat=3)
    t_s, *_ = best_of(lambda: burial.smectite_fraction(big, R0, ORDER), repeat=3)
    attrs = environment_attrs(
        benchmark="burial_error_vs_time", knobs="euler: dt (Myr); radau: rtol",
        exact_on_pareto_front=" ".join(f"{k}={v}" for k, v in pareto.items()),
        throughput_quartz_s_1e4x1e3=t_q, throughput_smectite_s_1e4x1e3=t_s)
    write_csv(table, result_path("burial_error_vs_time", "csv"), attrs)
    ds = xr.Dataset.from_dataframe(table.reset_index(drop=True))
    ds.attrs.update(attrs)
    ds["seconds"].attrs["units"] = "s"
    ds["rel_error"].attrs["units"] = "1"
    write_netcdf(ds, result_path("burial_error_vs_time", "nc"))
    use_agg()
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 2, figsize=(10, 8), sharex=True)
    floor = 1e-17
    for ax, ((pname, kind), grp) in zip(axes.ravel(), table.groupby(["path", "kinetics"])):
        for method, mk in (("euler", "o-"), ("radau", "s-"), ("exact", "*")):
            g = grp[grp.method == method]
            err = np.where(np.isfinite(g.rel_error), np.maximum(g.rel_error, floor), 1e3)
            ax.loglog(g.seconds, err, mk, ms=10 if method == "exact" else 5, label=method)
        ax.set_title(f"{kind}, {pname.replace('_', ' ')}")
        ax.grid(True, which="both", ls=":")
        ax.set_ylabel("relative error at end of path")
    for ax in axes[-1]:
        ax.set_xlabel("wall time (s)")
    axes[0, 0].legend()
    fig.suptitle(f"Burial kinetics: error vs run time (errors below {floor:g} drawn at it; "
                 "non-finite at 1e3)", fontsize=10)
    save_figure(fig, result_path("burial_error_vs_time", "png"))
    print(table.to_string(index=False))
    print("exact scheme on the Pareto front:", pareto)
    print(f"10^4 depths x 10^3 nodes: quartz {t_q:.2f} s, smectite {t_s:.2f} s")


if __name__ == "__main__":
    main()
