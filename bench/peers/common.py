"""What both sides of the peer comparison share: the cell, the pack and the load.

The cell is system D's 40 Ah NMC cell (scenarios/cells/nmc_40Ah.yaml) reduced to what
PyBaMM's Thevenin model holds with the same meaning: its OCV table and its R0 table over
SOC (linear interpolation, no temperature dependence), one RC pair (its 20 s one),
coulombic efficiency 1 and no entropic heat, so the terminal voltage does not depend on
temperature in either simulator. The load is system D's road-race lap
(scenarios/profiles/roadrace_lap.csv, 100 s, linear between rows), 12 laps, as cell
current (1p) or pack current (16s4p: x4 for the same C-rate).
"""
from __future__ import annotations

import csv
import os

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
LAP_CSV = os.path.join(REPO, "scenarios", "profiles", "roadrace_lap.csv")

CAPACITY_AH = 40.0
OCV_SOC = [0.0, 0.05, 0.10, 0.20, 0.30, 0.40, 0.50, 0.60, 0.70, 0.80, 0.90, 1.00]
OCV_V = [3.00, 3.42, 3.50, 3.58, 3.63, 3.68, 3.74, 3.82, 3.90, 3.98, 4.07, 4.18]
R0_SOC = [0.0, 0.1, 0.2, 0.5, 1.0]
R0_OHM = [0.0018, 0.0011, 0.0009, 0.0008, 0.0008]
R1_OHM = 0.0004
TAU1_S = 20.0
INITIAL_SOC = 0.9
LAPS = 12
AMBIENT_C = 25.0
PACK_SERIES, PACK_PARALLEL = 16, 4
# packsim's BMS closes the main relay 2 s after start (init, standby, normal): its runs
# rest REST_S at 0 A first, so its time REST_S + t is the peers' time t.
REST_S = 5.0


def lap_profile() -> tuple[list[float], list[float]]:
    """(time_s, current_A) breakpoints of one lap, per cell."""
    t, i = [], []
    with open(LAP_CSV, newline="") as f:
        rows = [r for r in f if not r.lstrip().startswith("#")]
    for row in csv.DictReader(rows):
        t.append(float(row["time_s"]))
        i.append(float(row["current_A"]))
    return t, i


def race_profile() -> tuple[list[float], list[float]]:
    """(time_s, current_A) breakpoints of the whole race (LAPS laps back to back), per cell."""
    t1, i1 = lap_profile()
    period = t1[-1]
    t, i = [], []
    for lap in range(LAPS):
        for k, (tk, ik) in enumerate(zip(t1, i1)):
            if lap > 0 and k == 0:
                continue  # the lap's first row is the previous lap's last instant
            t.append(lap * period + tk)
            i.append(ik)
    return t, i


def race_per_second() -> list[float]:
    """Cell current of each 1 s step of the race (linear profile sampled at its start):
    the step-wise load liionpack applies (one current per time step)."""
    t, i = race_profile()
    out, k = [], 0
    for s in range(int(t[-1])):
        while t[k + 1] < s:
            k += 1
        w = (s - t[k]) / (t[k + 1] - t[k])
        out.append(i[k] + w * (i[k + 1] - i[k]))
    return out
