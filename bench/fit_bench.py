"""`packsim fit` speed on a 36,000-row HPPC beside a plain SciPy least-squares baseline.

    PYTHONPATH=build/python python3 bench/fit_bench.py [--csv HPPC.csv] [--repeats 3] [--json out.json]

Without --csv the test is recorded by packsim's own simulator: the made-up 5 Ah cell of
examples/fit/make_test_data.py at 25 °C, per 10 % of SOC a 1C discharge pulse, a 0.75C
charge pulse, 10 % of capacity at C/2 and a 3,100 s rest (35,342 rows, one a second, 2 mV
and 5 mA RMS sensor noise).

Both fits are the same model on the same file — OCV and R0 tables over packsim's SOC grid
(25 nodes), 2 RC pairs with constant R and tau, the capacity given — and both simulate
it with the exact zero-order hold:

* packsim.fit: variable projection (least_squares over log tau only, the tables and
  resistances solved linearly), RC responses and their analytic derivatives in C++.
* baseline: scipy.optimize.least_squares over all 54 parameters, the RC responses by
  scipy.signal.lfilter (exact for a uniform sampling), the Jacobian by finite differences
  (SciPy's default): what one writes with SciPy alone.

Figures: the CPU time of the process (all threads; minimum of the repeats), the wall time,
the RMS voltage error of each fit and the ratio. Not a test: no thresholds.
"""
from __future__ import annotations

import argparse
import importlib.util
import json
import os
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))


def _example():
    spec = importlib.util.spec_from_file_location("make_test_data",
                                                  os.path.join(HERE, "..", "examples", "fit", "make_test_data.py"))
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def record_hppc(path: str) -> str:
    ex = _example()
    return ex.write_csv(ex.record(25.0, ex.hppc_segments(rest_s=3100.0), seed=1), path)


def baseline_fit(path: str, capacity_Ah: float) -> tuple[float, int]:
    """SciPy alone: all parameters in one least_squares, finite-difference Jacobian. Returns
    (RMS error in mV, function evaluations)."""
    from scipy.optimize import least_squares
    from scipy.signal import lfilter

    from packsim.fit import DEFAULT_SOC_GRID
    data = np.loadtxt(path, delimiter=",", skiprows=1)
    t, i, v = data[:, 0], data[:, 1], data[:, 2]
    dt = float(np.median(np.diff(t)))
    u = np.append(0.5 * (i[1:] + i[:-1]), i[-1])
    soc = 1.0 - np.concatenate(([0.0], np.cumsum(u[:-1] * np.diff(t)))) / 3600.0 / capacity_Ah
    grid = DEFAULT_SOC_GRID
    n = grid.size
    rest = np.abs(i) < 0.05
    ocv0 = np.interp(grid, soc[rest][::-1], v[rest][::-1])

    def model(x):
        ocv = np.interp(soc, grid, x[:n])
        r0 = np.interp(soc, grid, x[n:2 * n])
        out = ocv - i * r0
        for r, log_tau in x[2 * n:].reshape(-1, 2):
            a = np.exp(-dt / np.exp(log_tau))
            out -= lfilter([0.0, 1.0 - a], [1.0, -a], r * u)  # v[k+1] = a v[k] + (1 - a) R u[k]
        return out

    x0 = np.concatenate([ocv0, np.full(n, 0.02), [0.005, np.log(10.0), 0.005, np.log(200.0)]])
    res = least_squares(lambda x: model(x) - v, x0, method="trf")
    return 1e3 * float(np.sqrt(np.mean(res.fun ** 2))), int(res.nfev)


def timed(f, repeats: int):
    best_cpu, best_wall, out = np.inf, np.inf, None
    for _ in range(repeats):
        c, w = time.process_time(), time.perf_counter()
        out = f()
        best_cpu = min(best_cpu, time.process_time() - c)
        best_wall = min(best_wall, time.perf_counter() - w)
    return best_cpu, best_wall, out


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--csv", help="an HPPC test (time_s,current_A,voltage_V); default: recorded by packsim")
    p.add_argument("--capacity-Ah", type=float, default=5.0)
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--json", help="write the figures here")
    args = p.parse_args()
    import packsim
    with tempfile.TemporaryDirectory() as d:
        path = args.csv or record_hppc(os.path.join(d, "hppc_36k.csv"))
        rows = sum(1 for _ in open(path)) - 1
        cpu, wall, f = timed(lambda: packsim.fit(path, rc_pairs=2, capacity_Ah=args.capacity_Ah), args.repeats)
        b_cpu, b_wall, (b_rms, b_nfev) = timed(lambda: baseline_fit(path, args.capacity_Ah), args.repeats)
    figures = {"rows": rows, "packsim_fit_cpu_s": cpu, "packsim_fit_wall_s": wall,
               "packsim_fit_rms_mV": f.files[0].rms_mV, "packsim_fit_evaluations": f.evaluations,
               "baseline_cpu_s": b_cpu, "baseline_wall_s": b_wall, "baseline_rms_mV": b_rms,
               "baseline_evaluations": b_nfev, "speedup_cpu": b_cpu / cpu}
    print(f"{rows} rows, 2 RC pairs, OCV and R0 tables over {len(f.soc_grid)} SOC nodes")
    print(f"{'':<28}{'CPU s':>8}{'wall s':>8}{'RMS mV':>8}{'evals':>7}")
    print(f"{'packsim.fit (incl. CSV)':<28}{cpu:8.3f}{wall:8.3f}{f.files[0].rms_mV:8.2f}{f.evaluations:7d}")
    print(f"{'scipy least_squares':<28}{b_cpu:8.3f}{b_wall:8.3f}{b_rms:8.2f}{b_nfev:7d}")
    print(f"packsim.fit is {b_cpu / cpu:.1f}x faster (CPU)")
    if args.json:
        with open(args.json, "w") as out:
            json.dump(figures, out, indent=1)


if __name__ == "__main__":
    sys.exit(main())
