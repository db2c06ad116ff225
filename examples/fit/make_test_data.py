"""Example cell-test data for `packsim fit`: HPPC tests of a made-up 5 Ah NMC-like cell,
recorded by packsim's own simulator with sensor noise, one CSV per chamber temperature.

    PYTHONPATH=build/python python3 examples/fit/make_test_data.py fit-data/ --temps 0,25,45

Per temperature two tests, each starting with the cell rested full in its chamber:
hppc_<T>C.csv, per 10 % of SOC a 10 s 1C discharge pulse, a 10 s 0.75C charge pulse, 10 %
of capacity at C/2 and a rest; cc_<T>C.csv, a C/3 discharge to the 2.8 V cut-off and a
rest (it measures the capacity). Columns
time_s,current_A,voltage_V,temp_C (positive current discharges), one row per second.
The cell's resistances rise in the cold as an Arrhenius law (4000 K, 25 °C reference).
"""
from __future__ import annotations

import argparse
import math
import os

import numpy as np

import packsim

SOC = [round(0.05 * k, 2) for k in range(21)]
OCV_V = [3.00, 3.28, 3.42, 3.50, 3.55, 3.58, 3.61, 3.63, 3.65, 3.68, 3.71, 3.75, 3.79, 3.83, 3.87, 3.91, 3.95,
         3.99, 4.04, 4.10, 4.18]
R0_OHM = [0.040, 0.034, 0.030, 0.027, 0.025, 0.024, 0.023, 0.0225, 0.022, 0.0215, 0.021, 0.021, 0.021, 0.0205,
          0.0205, 0.0205, 0.0205, 0.021, 0.021, 0.0215, 0.022]
RC = [(0.008, 12.0), (0.012, 300.0)]   # (r_ohm, tau_s)
CAPACITY_AH = 5.0
ARRHENIUS_K = 4000.0


def cell_at(temp_C: float) -> dict:
    """The cell's parameters at one chamber temperature (held there by a strong cooling path)."""
    scale = math.exp(ARRHENIUS_K * (1.0 / (temp_C + 273.15) - 1.0 / 298.15))
    return {"capacity_Ah": CAPACITY_AH, "ocv_V": {"x": [-0.02] + SOC, "y": [2.70] + OCV_V},  # a knee below empty
            "r0_ohm": {"x": SOC, "y": [scale * r for r in R0_OHM]},
            "rc_pairs": [{"r_ohm": scale * r, "tau_s": tau} for r, tau in RC], "g_ambient_W_per_K": 2.0}


def hppc_segments(rest_s: float = 1500.0) -> list[dict]:
    c = CAPACITY_AH
    seg = [(60.5, 0.0)]
    for _ in range(9):
        seg += [(10.0, c), (40.0, 0.0), (10.0, -0.75 * c), (40.0, 0.0), (720.0, 0.5 * c), (rest_s, 0.0)]
    return [{"duration_s": d, "current_A": i} for d, i in seg]


def cc_segments() -> list[dict]:
    """C/3 until the BMS opens the relay at 2.8 V (the rest follows), for at most 4 h."""
    return [{"duration_s": 60.5, "current_A": 0.0}, {"duration_s": 4 * 3600.0, "current_A": CAPACITY_AH / 3}]


def record(temp_C: float, load: list[dict], seed: int, cutoff_V: float | None = None) -> np.ndarray:
    """Rows of time_s, current_A, voltage_V, temp_C (2 mV and 5 mA RMS sensor noise)."""
    off = {"enabled": False}  # no protection may interrupt the test, but the cut-off
    uv = off if cutoff_V is None else {"threshold_V": cutoff_V, "delay_ms": 500}
    r = packsim.run({"name": "test", "seed": seed,
                     "pack": {"series": 1, "initial_soc": 1.0, "initial_temp_C": temp_C, "cell": cell_at(temp_C)},
                     "ambient": {"temp_C": temp_C}, "load": {"segments": load},
                     "bms": {"tick_ms": 100, "protections": {"cell_overvoltage": off, "cell_undervoltage": uv}},
                     "run": {"duration_s": sum(s["duration_s"] for s in load), "stop_after_trip_s": 1800}})
    rng = np.random.default_rng(seed)
    t = r.time_s
    return np.column_stack([t, r["truth/cell_current_A"][:, 0] + rng.normal(0, 0.005, t.size),
                            r["truth/cell_voltage_V"][:, 0] + rng.normal(0, 0.002, t.size),
                            r["truth/cell_temp_C"][:, 0]])


def write_csv(rows: np.ndarray, path: str) -> str:
    np.savetxt(path, rows, delimiter=",", header="time_s,current_A,voltage_V,temp_C", comments="",
               fmt=["%.1f", "%.4f", "%.4f", "%.2f"])
    return path


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("folder")
    p.add_argument("--temps", default="25", help="chamber temperatures in °C, comma-separated (default 25)")
    args = p.parse_args()
    os.makedirs(args.folder, exist_ok=True)
    for k, t in enumerate(float(x) for x in args.temps.split(",")):
        print(write_csv(record(t, hppc_segments(), seed=2 * k + 1), os.path.join(args.folder, f"hppc_{t:g}C.csv")))
        print(write_csv(record(t, cc_segments(), seed=2 * k + 2, cutoff_V=2.8),
                        os.path.join(args.folder, f"cc_{t:g}C.csv")))


if __name__ == "__main__":
    main()
