#!/usr/bin/env python3
"""packsim's side of the peer comparison (run by the system Python with packsim
importable; bench/peers/run.sh does it): the 1-cell race and the 16s4p race on each
solver, CPU time of a whole `packsim.run` (load, run, recording), minimum of the
repeats, and the voltages for the comparison. Writes one .npz (argv[1]).
`--time-cell SOLVER TICK_MS REPEATS` times the 1-cell race alone (one_cell.py's child)."""
from __future__ import annotations

import json
import sys
import time

import numpy as np

import packsim

import common as c


def scenario(series: int, parallel: int, solver: str, tick_ms: int, step_load: bool) -> dict:
    rest = c.REST_S
    if step_load:  # one current per second, held (what liionpack applies)
        amps = [a * parallel for a in c.race_per_second()]
        load = {"points": {"time_s": [0.0] + [rest + s for s in range(len(amps) + 1)],
                           "current_A": [0.0] + amps + [amps[-1]]}, "interpolation": "step"}
    else:  # linear between the lap's rows; 1 ms from the rest to the first row
        t, i = c.race_profile()
        load = {"points": {"time_s": [0.0, rest - 1e-3] + [rest + x for x in t],
                           "current_A": [0.0, 0.0] + [a * parallel for a in i]}, "interpolation": "linear"}
    big = 3000.0  # A, within the current sensor range set below
    return {
        "name": f"peer_{series}s{parallel}p",
        "seed": 1,
        "pack": {"series": series, "parallel": parallel, "initial_soc": c.INITIAL_SOC, "initial_temp_C": c.AMBIENT_C,
                 "cell": {"capacity_Ah": c.CAPACITY_AH,
                          "ocv_V": {"x": c.OCV_SOC, "y": c.OCV_V},
                          "r0_ohm": {"x": c.R0_SOC, "y": c.R0_OHM},
                          "rc_pairs": [{"r_ohm": c.R1_OHM, "tau_s": c.TAU1_S}],
                          "coulombic_efficiency": 1.0, "v_min_V": 2.5, "v_max_V": 4.3,
                          "heat_capacity_J_per_K": 850.0, "g_ambient_W_per_K": 0.25}},
        "ambient": {"temp_C": c.AMBIENT_C},
        "hardware": {"thermistors": {"at_groups": [1]}, "current_sense": {"shunt_ohm": 2e-5, "amp_gain": 20}},
        # Protections out of the way: the comparison is the plant, not a trip.
        "bms": {"tick_ms": tick_ms, "protections": {
            "overcurrent_discharge": {"threshold_A": big}, "overcurrent_charge": {"threshold_A": big},
            "cell_undervoltage": {"threshold_V": 2.0}, "cell_overvoltage": {"threshold_V": 4.5},
            "overtemperature": {"threshold_C": 150.0}}},
        "load": load,
        "run": {"solver": solver, "duration_s": rest + c.LAPS * 100.0},
        "output": {"interval_s": 1.0},
    }


def timed(sc: dict, repeats: int):
    best, res = float("inf"), None
    for _ in range(repeats):
        t0 = time.process_time()
        res = packsim.run(sc)
        best = min(best, time.process_time() - t0)
    return best, res


def time_cell(solver: str, tick_ms: int, repeats: int) -> None:
    """One_cell.py's child: the 1-cell race on one solver and tick, repeated; prints the
    minimum CPU time of `packsim.run` and the end of the run as one JSON line."""
    cpu_s, r = timed(scenario(1, 1, solver, tick_ms, False), repeats)
    if r.summary.get("tripped") or r.time_s[-1] < c.REST_S + c.LAPS * 100.0 - 1.0:
        raise SystemExit(f"cell_{solver}_{tick_ms}ms: the race ended early ({r.summary.get('trip_reason')})")
    print(json.dumps({"cpu_s": cpu_s, "sim_s": float(r.time_s[-1]), "final_V": float(r["/truth/cell_voltage_V"][-1, 0])}))


def main() -> None:
    if len(sys.argv) == 5 and sys.argv[1] == "--time-cell":
        return time_cell(sys.argv[2], int(sys.argv[3]), int(sys.argv[4]))
    out, repeats = sys.argv[1], int(sys.argv[2]) if len(sys.argv) > 2 else 3
    arrays, meta = {}, {"packsim_version": getattr(packsim, "__version__", "?"), "runs": {}}
    cases = [  # (label, series, parallel, solver, tick_ms, step load)
        ("cell_fast_10ms", 1, 1, "fast", 10, False),
        ("cell_fast_1s", 1, 1, "fast", 1000, False),
        ("cell_cvode_10ms", 1, 1, "cvode", 10, False),
        ("cell_cvode_1s", 1, 1, "cvode", 1000, False),
        ("pack_fast_10ms", c.PACK_SERIES, c.PACK_PARALLEL, "fast", 10, True),
        ("pack_fast_1s", c.PACK_SERIES, c.PACK_PARALLEL, "fast", 1000, True),
        ("pack_cvode_1s", c.PACK_SERIES, c.PACK_PARALLEL, "cvode", 1000, True),
    ]
    rest_end = c.REST_S + c.LAPS * 100.0 - 1.0
    for label, s, p, solver, tick, step in cases:
        cpu_s, r = timed(scenario(s, p, solver, tick, step), repeats)
        if r.summary.get("tripped") or r.time_s[-1] < rest_end:
            raise SystemExit(f"{label}: the race ended early ({r.summary.get('trip_reason')}): "
                             "the comparison needs the whole race")
        arrays[f"{label}_t"] = r.time_s
        arrays[f"{label}_cell_V"] = r["/truth/cell_voltage_V"]
        arrays[f"{label}_pack_V"] = r["/truth/pack_voltage_V"]
        meta["runs"][label] = {"cells": s * p, "solver": solver, "tick_ms": tick, "cpu_s": cpu_s,
                               "sim_s": float(r.time_s[-1]), "repeats": repeats}
        print(f"packsim {label}: {cpu_s:.3f} s CPU", flush=True)
    np.savez(out, meta=json.dumps(meta), **arrays)


if __name__ == "__main__":
    main()
