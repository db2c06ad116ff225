#!/usr/bin/env python3
"""Combines the two sides of the peer comparison (argv: packsim .npz, peers .npz, out
.json): CPU cost per cell-hour of simulated racing, the ratios peer / packsim, and the
voltage difference (mV RMS and max) on the common 1 s samples, so the speed is for the
same answer. Needs only numpy; prints a summary table."""
from __future__ import annotations

import json
import os
import platform
import subprocess
import sys
import time

import numpy as np

import common as c


def vdiff_mV(a: np.ndarray, b: np.ndarray) -> dict:
    n = min(len(a), len(b))
    d = (np.asarray(a[:n], float) - np.asarray(b[:n], float)) * 1e3
    return {"rms_mV": float(np.sqrt(np.mean(d ** 2))), "max_mV": float(np.max(np.abs(d))),
            "median_abs_mV": float(np.median(np.abs(d))), "samples": int(n)}


def machine() -> str:
    model = ""
    try:
        with open("/proc/cpuinfo") as f:
            model = next((l.split(":", 1)[1].strip() for l in f if l.startswith("model name")), "")
    except OSError:
        pass
    return f"{model or platform.processor() or platform.machine()}, {os.cpu_count()} cores"


def main() -> None:
    ps, pe, out = np.load(sys.argv[1]), np.load(sys.argv[2]), sys.argv[3]
    pmeta, emeta = json.loads(str(ps["meta"])), json.loads(str(pe["meta"]))
    race_h = c.LAPS * 100.0 / 3600.0
    rest = int(c.REST_S)  # packsim sample REST_S + k is the peers' sample k

    def per_cell_hour(cpu_s: float, cells: int) -> float:
        return cpu_s / (cells * race_h)

    res = {"date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), "machine": machine(),
           "packsim_commit": subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True,
                                            text=True, cwd=c.HERE).stdout.strip(),
           "versions": {"packsim": pmeta["packsim_version"], "pybamm": emeta["pybamm_version"],
                        "liionpack": emeta["liionpack_version"]},
           "race": {"laps": c.LAPS, "sim_s": c.LAPS * 100.0, "cell": "40 Ah NMC, OCV and R0 tables, one RC pair",
                    "time": "CPU time of the process, minimum of the repeats"},
           "cell_1s1p": {}, "pack_16s4p": {}}

    # (1) One cell: PyBaMM's Thevenin model, each solver, against packsim's runs.
    peers = {k: v for k, v in emeta["solvers"].items() if k.startswith("pybamm_")}
    best_peer = min(peers, key=lambda k: peers[k]["cpu_s"])
    for name, m in peers.items():
        res["cell_1s1p"][name] = {"cpu_s": m["cpu_s"], "build_cpu_s": m["build_cpu_s"],
                                  "cpu_s_per_cell_hour": per_cell_hour(m["cpu_s"], 1), "solver": m.get("solver", "")}
    ref_V = pe[f"{best_peer}_V"]
    for label, m in pmeta["runs"].items():
        if not label.startswith("cell_"):
            continue
        v = ps[f"{label}_cell_V"][rest:, 0]
        n = min(len(v), len(ref_V)) - 1  # the last instant: the load's end, where the two differ in convention
        res["cell_1s1p"][f"packsim_{label[5:]}"] = {
            "cpu_s": m["cpu_s"], "cpu_s_per_cell_hour": per_cell_hour(m["cpu_s"], 1),
            "speed_vs_" + best_peer: peers[best_peer]["cpu_s"] / m["cpu_s"],
            "voltage_vs_" + best_peer: vdiff_mV(v[:n], ref_V[:n])}

    # (2) 16s4p: liionpack (Thevenin cells through its CasADi manager) against packsim.
    lm = emeta["solvers"]["liionpack"]
    cells = c.PACK_SERIES * c.PACK_PARALLEL
    res["pack_16s4p"]["liionpack"] = {"cpu_s": lm["cpu_s"], "cpu_s_per_cell_hour": per_cell_hour(lm["cpu_s"], cells),
                                      "cell_model": lm["cell_model"], "manager": lm["manager"]}
    lp_pack, lp_cell = pe["liionpack_pack_V"], pe["liionpack_cell_V"]
    for label, m in pmeta["runs"].items():
        if not label.startswith("pack_"):
            continue
        pv, cv = ps[f"{label}_pack_V"], ps[f"{label}_cell_V"]
        res["pack_16s4p"][f"packsim_{label[5:]}"] = {
            "cpu_s": m["cpu_s"], "cpu_s_per_cell_hour": per_cell_hour(m["cpu_s"], cells),
            "speed_vs_liionpack": lm["cpu_s"] / m["cpu_s"],
            # liionpack's record k at k s (its record_times)
            "pack_voltage_vs_liionpack": vdiff_mV(pv[rest:], lp_pack),
            "cell_voltage_vs_liionpack": vdiff_mV(cv[rest:].ravel(), lp_cell[: len(cv) - rest].ravel()),
            # the same with liionpack's cell voltages one record earlier (its record k is the
            # voltage with step k's current at the step's start)
            "cell_voltage_vs_liionpack_shifted_1": vdiff_mV(cv[rest - 1:rest - 1 + len(lp_cell)].ravel(),
                                                            lp_cell.ravel())}
    with open(out, "w") as f:
        json.dump(res, f, indent=2)

    print(f"{res['date']} | {res['machine']} | packsim {res['packsim_commit']} | "
          f"PyBaMM {emeta['pybamm_version']}, liionpack {emeta['liionpack_version']}")
    print("1 cell, 20-minute race (PyBaMM Thevenin vs packsim):")
    for k, v in res["cell_1s1p"].items():
        extra = ""
        if k.startswith("packsim_"):
            vd = v["voltage_vs_" + best_peer]
            extra = f"  {v['speed_vs_' + best_peer]:7.1f}x faster than {best_peer}; ΔV {vd['rms_mV']:.3f} mV RMS, {vd['max_mV']:.3f} max"
        print(f"  {k:22s} {v['cpu_s']:8.3f} s CPU  {v['cpu_s_per_cell_hour']:8.3f} s/cell-h{extra}")
    print("16s4p, 20-minute race (liionpack vs packsim):")
    for k, v in res["pack_16s4p"].items():
        extra = ""
        if k.startswith("packsim_"):
            pvd, cvd = v["pack_voltage_vs_liionpack"], v["cell_voltage_vs_liionpack"]
            extra = (f"  {v['speed_vs_liionpack']:7.1f}x faster; pack ΔV {pvd['rms_mV']:.0f} mV RMS "
                     f"({pvd['max_mV']:.0f} max), cell ΔV {cvd['rms_mV']:.1f} mV RMS")
        print(f"  {k:22s} {v['cpu_s']:8.3f} s CPU  {v['cpu_s_per_cell_hour']:8.4f} s/cell-h{extra}")


if __name__ == "__main__":
    main()
