"""Test data for the packsim.fit tests, made by packsim's own simulator (the plant of the
C++ core, not the fitter's model): a known cell driven by a test profile, recorded, with
seeded sensor noise added, written as a cell-test CSV."""
from __future__ import annotations

from pathlib import Path

import numpy as np

import packsim

SOC_GRID = [round(0.05 * k, 2) for k in range(21)]
# An NMC-like 5 Ah cell: OCV and R0 over SOC, two RC pairs.
KNOWN_OCV_V = [3.00, 3.28, 3.42, 3.50, 3.55, 3.58, 3.61, 3.63, 3.65, 3.68, 3.71, 3.75, 3.79, 3.83, 3.87,
               3.91, 3.95, 3.99, 4.04, 4.10, 4.18]
KNOWN_R0_OHM = [0.040, 0.034, 0.030, 0.027, 0.025, 0.024, 0.023, 0.0225, 0.022, 0.0215, 0.021, 0.021, 0.021,
                0.0205, 0.0205, 0.0205, 0.0205, 0.021, 0.021, 0.0215, 0.022]
KNOWN_RC = [{"r_ohm": 0.008, "tau_s": 12.0}, {"r_ohm": 0.012, "tau_s": 300.0}]
KNOWN_CELL = {"capacity_Ah": 5.0, "ocv_V": {"x": SOC_GRID, "y": KNOWN_OCV_V},
              "r0_ohm": {"x": SOC_GRID, "y": KNOWN_R0_OHM}, "rc_pairs": KNOWN_RC, "v_min_V": 2.8}

# Protections off: the BMS must not interrupt the test (charge pulses near full, deep steps).
_NO_PROTECTIONS = {name: {"enabled": False} for name in
                   ("cell_overvoltage", "cell_undervoltage", "overcurrent_charge", "overcurrent_discharge")}


def hppc_segments(capacity_Ah: float, steps: int = 9, rest_s: float = 1800.0) -> list[tuple[float, float]]:
    """(duration_s, current_A): a rested start, then per SOC step a 1C discharge pulse, a
    0.75C charge pulse, and 10 % of capacity at C/2 followed by a long rest."""
    c = capacity_Ah
    seg = [(60.5, 0.0)]  # steps at half seconds: never on a 1 s sample
    for _ in range(steps):
        seg += [(10.0, c), (40.0, 0.0), (10.0, -0.75 * c), (40.0, 0.0), (720.0, 0.5 * c), (rest_s, 0.0)]
    return seg


def cc_segments(current_A: float, discharge_s: float, rest_s: float = 600.0) -> list[tuple[float, float]]:
    return [(120.5, 0.0), (discharge_s, current_A), (rest_s, 0.0)]


def simulate(cell: dict, segments: list[tuple[float, float]], *, initial_soc: float = 1.0,
             protections: dict | None = None, ambient_C: float = 25.0, base_dir=None,
             stop_after_trip_s: float = 600.0, interval_s: float = 1.0) -> packsim.Result:
    duration = sum(d for d, _ in segments)
    scenario = {"name": "fit_data", "seed": 1,
                "pack": {"series": 1, "initial_soc": initial_soc, "initial_temp_C": ambient_C, "cell": cell},
                "ambient": {"temp_C": ambient_C},
                "load": {"segments": [{"duration_s": d, "current_A": i} for d, i in segments]},
                "bms": {"tick_ms": 100, "protections": _NO_PROTECTIONS if protections is None else protections},
                "run": {"duration_s": duration, "stop_after_trip_s": stop_after_trip_s},
                "output": {"interval_s": interval_s}}
    return packsim.run(scenario, base_dir=base_dir)


def write_test_csv(result: packsim.Result, path: Path, *, noise_V: float = 0.002, noise_A: float = 0.005,
                   seed: int = 1, end_s: float | None = None) -> Path:
    """The recorded truth plus Gaussian sensor noise, as a cell-test CSV."""
    t = result.time_s
    i = result["truth/cell_current_A"][:, 0]
    v = result["truth/cell_voltage_V"][:, 0]
    temp = result["truth/cell_temp_C"][:, 0]
    keep = t <= (end_s if end_s is not None else t[-1])
    rng = np.random.default_rng(seed)
    i = i + rng.normal(0.0, noise_A, i.size)
    v = v + rng.normal(0.0, noise_V, v.size)
    rows = np.column_stack([t, i, v, temp])[keep]
    np.savetxt(path, rows, delimiter=",", header="time_s,current_A,voltage_V,temp_C", comments="",
               fmt=["%.3f", "%.5f", "%.5f", "%.3f"])
    return path


# The known cell "at" other temperatures: the plant on this branch has no temperature
# dependence, so each temperature's test is made with that temperature's parameters
# (R0 and RC resistances scaled, as cold cells are more resistive) at that ambient.
RESISTANCE_SCALE_AT_C = {0.0: 2.5, 25.0: 1.0, 45.0: 0.8}


def known_cell_at(temp_C: float) -> dict:
    scale = RESISTANCE_SCALE_AT_C[temp_C]
    return dict(KNOWN_CELL, r0_ohm={"x": SOC_GRID, "y": [scale * r for r in KNOWN_R0_OHM]},
                rc_pairs=[{"r_ohm": scale * p["r_ohm"], "tau_s": p["tau_s"]} for p in KNOWN_RC],
                g_ambient_W_per_K=2.0)  # held near its chamber temperature


def pulse_frame(rest: bool = True):
    """A small synthetic test in closed form (not the plant): a 2 Ah cell with linear OCV
    3.4 + 0.8·soc, R0 = 50 mΩ and one 20 mΩ / 20 s RC pair under 1 A pulses, with rests
    between them or (rest=False) a 0.5 A base load; sampled each second, the current held
    between samples."""
    import pandas as pd
    t = np.arange(0.0, 600.0, 1.0)
    i = np.where((t % 100) < 30, 1.0, 0.0 if rest else 0.5)
    soc = 1.0 - np.concatenate(([0.0], np.cumsum(i[:-1]))) / 3600.0 / 2.0
    v_rc = np.zeros_like(t)
    for k in range(1, t.size):
        v_rc[k] = v_rc[k - 1] * np.exp(-1 / 20) + 0.020 * (1 - np.exp(-1 / 20)) * i[k - 1]
    return pd.DataFrame({"time_s": t, "current_A": i, "voltage_V": 3.4 + 0.8 * soc - 0.05 * i - v_rc})
