#!/usr/bin/env python3
"""Generative campaign: random *valid* scenarios, judged by oracles that need no
expected output (docs/hardening.md, "Generated scenarios").

    scripts/campaign.py [--cases N] [--seed S] [--out DIR] [--max-s S] [--keep]

Each case is drawn from its own seed (case i of campaign seed S has seed S*1_000_003+i,
so any case can be replayed alone with --only I). A case is a pack (1-250 series x 1-20
parallel, a bundled or an inline "fitted" cell, spread, the monitor chain of a named TI
part at one of several bus speeds), a load (constant, segments,
points or a CSV with breakpoints at arbitrary decimals, step or linear, laps, power or
current, a CC-CV charger), faults at random times (some after the run's end), passive
balancing (a case in four), per-cell self-discharge (a spread case in three), either
integrator, packsim's core or the example C firmware; it is written as a base file and
an `extends:` child, with part of it given as --set style overrides. Oracles:

  runs          the run completes (a generated scenario is valid: any error is a finding)
  finite        no NaN/inf in any dataset or summary value
  determinism   the same scenario and seed twice: every dataset byte-identical
  extends       the extends chain + overrides equals the inlined scenario, byte for byte
  charge        summary charge = the load's exact integral from the relay closing, plus
                an over-current injection and the precharged bus capacitor (check_charge)
  soc           the cells' SOC fell by the charge the counter delivered: sum over cells of
                (SOC at 0 - SOC at the end) x capacity = series x charge delivered, where
                that is exact (no capacity spread, no charging current: check_soc)
  record        the summary's figures against the record alone (scripts/campaign_record.py):
                per-cell and per-group charge, balancing bled, energy out and in, lowest
                and hottest cell (which, value, when), trip time and reason, energy
                stranded by imbalance
  summary       lowest / hottest cell, duration and trip flag follow from truth and events;
                a cell past 80 C is a cell_model_range event; the last event says why the
                run ended, and not "the scenario's end time" for a run that ended early
  faults        every scripted fault was injected, or reported as not reached
  firmware      a case in eight runs the example C firmware (examples/firmware) on system
                C's bench pack through a three-file extends chain
  solvers       fast and CVODE agree on cell voltages to 5 mV, SOC to 2e-5 and temperature
                to 0.05 K while both decided alike
                (up to the first instant either integrator's run changed the relay), over
                the case's first 30 s (the other integrator runs that prefix)

Exit status 1 when any case fails; findings go to DIR/findings.jsonl with the case's
files kept under DIR/case-N.
"""
from __future__ import annotations

import argparse
import json
import math
import os
import random
import re
import shutil
import sys
import tempfile
import time
import traceback
from pathlib import Path

import numpy as np
import yaml

HERE = Path(__file__).resolve().parent
sys.path[:0] = [str(HERE.parent / "build" / "python"), str(HERE.parent / "python"), str(HERE)]
import packsim  # noqa: E402
import campaign_record as rec  # noqa: E402

PRESETS = {  # bundled cell: (capacity_Ah, v_min_V, v_max_V)
    "lipo_5Ah": (5.0, 3.0, 4.2),
    "ncr18650_3p1Ah": (3.1, 2.5, 4.2),
    "nmc_40Ah": (40.0, 2.8, 4.2),
    "lto_20Ah": (20.0, 1.5, 2.8),
}
FAULT_KINDS = ["overcurrent", "hot_cell", "estop", "thermistor_open", "channel_gain", "key_off", "welded_relay"]


def fitted_cell(rng: random.Random) -> dict:
    """An inline cell as `packsim fit` writes one: OCV and R0 tables over SOC, RC pairs."""
    cap = round(rng.uniform(1.5, 50.0), 3)
    soc = [0.0, 0.1, 0.3, 0.5, 0.7, 0.9, 1.0]
    v = [3.0, 3.45, 3.62, 3.72, 3.88, 4.05, 4.18]
    r0 = round(rng.uniform(0.5, 3.0) * 0.06 / cap ** 0.5, 6)
    pairs = [{"r_ohm": round(r0 * rng.uniform(0.2, 0.8), 6), "tau_s": round(rng.uniform(5, 400), 2)}
             for _ in range(rng.randint(1, 2))]
    return {"capacity_Ah": cap, "ocv_V": {"x": soc, "y": v},
            "r0_ohm": {"x": [0.0, 0.5, 1.0], "y": [round(r0 * 1.6, 6), r0, round(r0 * 1.1, 6)]},
            "rc_pairs": pairs, "v_min_V": 2.8, "v_max_V": 4.2}


def decimal_time(rng: random.Random, lo: float, hi: float) -> float:
    """A time as a user or a logger writes it: a few decimals, rarely a tick multiple in binary."""
    return round(rng.uniform(lo, hi), rng.choice([1, 2, 3, 4]))


def make_load(rng: random.Random, case_dir: Path, duration_s: float, i_1c: float, series: int, v_max: float):
    """(load section, files written). Currents scale with the pack's 1C current."""
    kind = rng.choice(["current", "segments", "segments", "points", "csv", "csv", "power", "charger"])
    amps = lambda: round(rng.uniform(-0.5, 2.0) * i_1c, 3)  # noqa: E731
    files = {}
    if kind == "current":
        return {"current_A": round(rng.uniform(0.05, 1.5) * i_1c, 3)}, files
    if kind == "power":
        return {"power_W": round(rng.uniform(0.05, 1.0) * i_1c * 3.6 * series, 2)}, files
    if kind == "charger":
        return {"charger": {"current_A": round(rng.uniform(0.1, 0.7) * i_1c, 3),
                            "voltage_V": round(series * (v_max - 0.02), 3)}}, files
    n = rng.randint(2, 12)
    if kind == "segments":
        segs = [{"duration_s": decimal_time(rng, 0.05, max(0.1, duration_s / n)), "current_A": amps()} for _ in range(n)]
        load = {"segments": segs}
        if rng.random() < 0.3:
            load["laps"] = rng.randint(2, 4)
        return load, files
    times = sorted({0.0} | {decimal_time(rng, 0.01, duration_s) for _ in range(n)})
    if kind == "points":
        load = {"points": {"time_s": times, "current_A": [amps() for _ in times]}}
    else:
        hz = rng.choice([None, 10, 100])
        if hz:
            times = [round(k / hz, 3) for k in range(int(min(duration_s, 120) * hz) + 1)]
        rows = "\n".join(f"{t},{amps()}" for t in times)
        name = "load.csv"
        files["base/" + name] = "time_s,current_A\n" + rows + "\n"
        load = {"csv": {"file": name, "time_column": "time_s", "current_column": "current_A"}} \
            if rng.random() < 0.5 else {"csv": name}
    load["interpolation"] = rng.choice(["step", "linear"])
    if rng.random() < 0.3:
        load["laps"] = rng.randint(2, 4)
    return load, files


def make_faults(rng: random.Random, duration_s: float, series: int, parallel: int, i_1c: float) -> list:
    faults = []
    for _ in range(rng.choice([0, 0, 1, 1, 2, 3])):
        kind = rng.choice(FAULT_KINDS)
        at = decimal_time(rng, 0.0, duration_s * 1.2)  # some after the end: must be reported
        f = {"kind": kind, "at_s": at}
        if kind == "overcurrent":
            f["current_A"] = round(rng.uniform(0.2, 3.0) * i_1c, 3)
            if rng.random() < 0.5:
                f["duration_s"] = decimal_time(rng, 0.05, 30)
        elif kind == "hot_cell":
            f["cell"] = rng.randint(1, series * parallel)
            f["heat_W"] = round(rng.uniform(1, 30), 2)
        elif kind == "estop":
            f["switch"] = rng.choice(["internal", "external"])
        elif kind == "thermistor_open":
            f["thermistor"] = 1
        elif kind == "channel_gain":
            f["group"] = rng.randint(1, series)
            f["gain_error"] = round(rng.uniform(-0.08, 0.08), 4)
        faults.append(f)
    return faults


EXAMPLE_FIRMWARE = HERE.parent / "scenarios" / "firmware" / "c_example_firmware.yaml"


def make_firmware_case(rng: random.Random, case_seed: int, case_dir: Path, max_s: float) -> dict:
    """System C's 6s bench pack run by the example C firmware (examples/firmware), a
    chain of three files (bundled -> base -> child): random load, faults, start, solver."""
    duration_s = round(rng.uniform(5, min(600, max_s)), 2)
    load, files = make_load(rng, case_dir, duration_s, 3.1, 6, 4.2)
    scen = {
        "extends": str(EXAMPLE_FIRMWARE),
        "name": f"case{case_seed}",
        "seed": rng.randint(1, 10**6),
        "pack": {"initial_soc": round(rng.uniform(0.3, 1.0), 3)},
        "run": {"duration_s": duration_s, "solver": rng.choice(["cvode", "fast"])},
        "output": {"interval_s": 0.01},
        "load": load,
        "faults": make_faults(rng, duration_s, 6, 1, 3.1),
        "expect": {},
    }
    for f in scen["faults"]:  # the bench stack: two thermistors
        if f["kind"] == "thermistor_open":
            f["thermistor"] = rng.randint(1, 2)
    child_keys = rng.sample(["seed", "run", "faults"], rng.randint(0, 2))
    base_values = {"seed": scen["seed"] + 1, "faults": [],
                   "run": {"duration_s": duration_s, "solver": "cvode" if scen["run"]["solver"] == "fast" else "fast"}}
    overrides = {"pack.initial_soc": round(rng.uniform(0.3, 1.0), 3)} if rng.random() < 0.5 else {}
    return {"scenario": scen, "files": files, "child_keys": child_keys, "base_values": base_values,
            "overrides": overrides}


def make_case(case_seed: int, case_dir: Path, max_s: float = 900.0) -> dict:
    """The case's scenario (a dict), its files, overrides and the base/child split;
    max_s caps the simulated time (the test command's smoke run keeps cases short)."""
    rng = random.Random(case_seed)
    if rng.random() < 0.12:
        return make_firmware_case(rng, case_seed, case_dir, max_s)
    big = rng.random() < 0.1
    series = rng.randint(25, 250) if big else rng.randint(1, 24)
    parallel = rng.choice([1, 1, 1, 2, 3, 4, 6, 10, 20]) if not big else rng.choice([1, 2, 4])
    tick_ms = rng.choice([10, 20, 50, 100, 1000])
    budget = 4e5 if not big else 2e6  # cell-ticks: keeps a case well under a second
    duration_s = round(min(rng.uniform(5, max(5.0, max_s)), budget * tick_ms / 1000 / (series * parallel)), 2)
    duration_s = max(duration_s, 5 * tick_ms / 1000)
    if rng.random() < 0.25:
        cell = fitted_cell(rng)
        cap, vmin, vmax = cell["capacity_Ah"], cell["v_min_V"], cell["v_max_V"]
    else:
        preset = rng.choice(sorted(PRESETS))
        cap, vmin, vmax = PRESETS[preset]
        cell = {"preset": preset}
    i_1c = cap * parallel
    scen = {
        "name": f"case{case_seed}",
        "seed": rng.randint(1, 10**6),
        "pack": {"series": series, "parallel": parallel, "initial_soc": round(rng.uniform(0.3, 1.0), 3),
                 "initial_temp_C": round(rng.uniform(0, 40), 1), "cell": cell},
        "ambient": {"temp_C": round(rng.uniform(-10, 40), 1)},
        "bms": {"tick_ms": tick_ms},
        "run": {"duration_s": duration_s, "solver": rng.choice(["cvode", "fast"])},
        "output": {"interval_s": tick_ms / 1000},
    }
    if rng.random() < 0.5:
        scen["pack"]["spread"] = {"capacity_rel_sd": round(rng.uniform(0, 0.03), 4),
                                  "r0_rel_sd": round(rng.uniform(0, 0.08), 4),
                                  "initial_soc_sd": round(rng.uniform(0, 0.02), 4)}
    scen["hardware"] = {"current_sense": {"shunt_ohm": round(0.05 / max(3 * i_1c, 1.0), 6), "amp_gain": 20}}
    load, files = make_load(rng, case_dir, duration_s, i_1c, series, vmax)
    scen["load"] = load
    scen["faults"] = make_faults(rng, duration_s, series, parallel, i_1c)
    scen["bms"]["protections"] = {
        "overcurrent_discharge": {"threshold_A": round(2.5 * i_1c, 3)},
        "overcurrent_charge": {"threshold_A": round(1.0 * i_1c, 3)},
    }
    # the monitor chain users build on: a TI part at its default or another bus speed
    # (drawn last: the draws above stay those of earlier campaigns)
    if rng.random() < 0.4:
        models = ["bq76pl536a", "bq76pl455a"] + (["bq76952"] if series <= 16 else [])
        afe = {"model": rng.choice(models)}
        if rng.random() < 0.3 and afe["model"] != "bq76952":
            afe["baud"] = rng.choice([125000, 500000, 1000000])
        scen["hardware"]["afe"] = afe
    # Passive balancing on a pack whose cells start apart (drawn after the monitor chain:
    # earlier campaigns' draws stay theirs), so the group charge oracle sees a resistor bleed.
    if rng.random() < 0.25:
        scen["hardware"]["balancing"] = {"resistor_ohm": round(rng.uniform(5, 100), 1)}
        scen["bms"]["balancing"] = {"when": rng.choice(["always", "charging_or_rest"]),
                                    "start_delta_mV": rng.randint(2, 20), "stop_delta_mV": 1,
                                    "min_cell_V": round(vmin + 0.1, 2)}
        scen["pack"].setdefault("spread", {})["initial_soc_sd"] = round(rng.uniform(0.01, 0.05), 4)
    # Self-discharge drawn per cell (a leak of up to 0.1 % of C per hour, sd; drawn last too):
    # each cell's SOC falls by its own leak, which the cell charge oracle adds.
    if "spread" in scen["pack"] and rng.random() < 0.3:
        scen["pack"]["spread"]["self_discharge_A_sd"] = round(rng.uniform(0, 1e-3) * cap, 6)
    # the child overrides some keys of the base; others come as --set overrides
    # The base is a whole scenario of its own (the loader validates it alone); the child
    # replaces some of its keys: the base holds other values there, which must not leak.
    child_keys = rng.sample(["seed", "ambient", "run", "faults"], rng.randint(0, 3))
    base_values = {"seed": scen["seed"] + 1, "ambient": {"temp_C": 20.0},
                   "run": {"duration_s": duration_s, "solver": "cvode" if scen["run"]["solver"] == "fast" else "fast"},
                   "faults": []}
    overrides = {}
    if rng.random() < 0.5:
        overrides["pack.initial_soc"] = round(rng.uniform(0.3, 1.0), 3)
    if rng.random() < 0.3:
        overrides["ambient.temp_C"] = round(rng.uniform(-10, 40), 1)
    return {"scenario": scen, "files": files, "child_keys": child_keys, "base_values": base_values,
            "overrides": overrides}


def set_dotted(d: dict, key: str, value) -> None:
    parts = key.split(".")
    for p in parts[:-1]:
        d = d.setdefault(p, {})
    d[parts[-1]] = value


def write_case(case: dict, case_dir: Path) -> tuple[Path, Path]:
    """base/base.yaml + child.yaml (extends it) and inline.yaml (the same, merged and edited)."""
    scen = case["scenario"]
    (case_dir / "base").mkdir(parents=True, exist_ok=True)
    for rel, text in case["files"].items():
        (case_dir / rel).write_text(text)
    base = {k: (case["base_values"][k] if k in case["child_keys"] else v) for k, v in scen.items()}
    child = {"extends": "base/base.yaml", **{k: scen[k] for k in case["child_keys"]}}
    (case_dir / "base" / "base.yaml").write_text(yaml.safe_dump(base, sort_keys=False))
    (case_dir / "child.yaml").write_text(yaml.safe_dump(child, sort_keys=False))
    inline = json.loads(json.dumps(scen))
    for k, v in case["overrides"].items():
        set_dotted(inline, k, v)
    csv = inline["load"].get("csv")
    if isinstance(csv, dict):
        csv["file"] = "base/" + csv["file"]
    elif csv:
        inline["load"]["csv"] = "base/" + csv
    (case_dir / "inline.yaml").write_text(yaml.safe_dump(inline, sort_keys=False))
    return case_dir / "child.yaml", case_dir / "inline.yaml"


# ---- oracles ---------------------------------------------------------------------------

def arrays(r) -> dict:
    return {k: np.asarray(r[k]) for k in r.keys() if k != "events"}


def same_bytes(a, b, ignore_lines: bool = False) -> str:
    """'' when the two results hold the same datasets, events and summary, byte for byte
    (ignore_lines: event texts may name other files and lines, as an extends chain's do)."""
    da, db = arrays(a), arrays(b)
    if sorted(da) != sorted(db):
        return f"datasets differ: {sorted(set(da) ^ set(db))}"
    for k in da:
        if da[k].dtype != db[k].dtype or da[k].shape != db[k].shape or da[k].tobytes() != db[k].tobytes():
            return f"dataset {k} differs"
    # Where a value came from differs by construction (a file's line, or the --set that
    # gave it): compared as "L"; the values and the rest of the text must agree.
    ev = lambda r: [(e["time_s"], e["kind"], re.sub(r"(line \d+|\S+\.yaml:\d+(:\d+)?|\(--set [^)]*)", "L", e["detail"])  # noqa: E731
                    if ignore_lines else e["detail"]) for e in r.events]
    if ev(a) != ev(b):
        return "events differ: " + next(f"{x} vs {y}" for x, y in zip(ev(a) + [None], ev(b) + [None]) if x != y)
    if json.dumps(a.summary, sort_keys=True, default=str) != json.dumps(b.summary, sort_keys=True, default=str):
        return "summary differs"
    return ""


def check_finite(r) -> list:
    bad = []
    for k, v in arrays(r).items():
        if v.dtype.kind == "f" and not np.all(np.isfinite(v)):
            bad.append(f"non-finite values in {k}")
    for k, v in r.summary.items():
        if isinstance(v, float) and not math.isfinite(v):
            bad.append(f"non-finite summary {k}")
    return bad


def load_pieces(load: dict, case_dir: Path):
    """The generated current load as (times, currents, linear, laps): None for a power
    load or a charger (their current depends on the pack)."""
    if "current_A" in load:
        return [0.0, math.inf], [load["current_A"], load["current_A"]], False, 1
    if "segments" in load:
        t, i = [0.0], []
        for seg in load["segments"]:
            t.append(t[-1] + seg["duration_s"])
            i.append(seg["current_A"])
        return t, i + [i[-1]], False, load.get("laps", 1)
    if "points" in load:
        t, i = load["points"]["time_s"], load["points"]["current_A"]
    elif "csv" in load:
        csv = load["csv"]["file"] if isinstance(load["csv"], dict) else load["csv"]
        rows = (case_dir / "base" / csv).read_text().split()[1:]
        t = [float(x.split(",")[0]) for x in rows]
        i = [float(x.split(",")[1]) for x in rows]
    else:
        return None
    return t, i, load.get("interpolation", "step") == "linear", load.get("laps", 1)


def load_charge_As(pieces, t0: float, t1: float) -> float:
    """Integral of the load's current over [t0, t1], exactly (the loader's own rule:
    step holds a point's value to the next, linear ramps, laps repeat, zero after)."""
    t, i, linear, laps = pieces
    if math.isinf(t[-1]):
        return i[0] * (t1 - t0)
    lap = t[-1]
    q = 0.0
    for n in range(laps):
        off = n * lap
        for k in range(len(t) - 1):
            a, b = max(t0, off + t[k]), min(t1, off + t[k + 1])
            if b <= a:
                continue
            if linear:
                slope = (i[k + 1] - i[k]) / (t[k + 1] - t[k])
                q += (i[k] + slope * (0.5 * (a + b) - off - t[k])) * (b - a)
            else:
                q += i[k] * (b - a)
    return q


def check_charge(scen: dict, r, case_dir: Path) -> list:
    """Charge out of the pack = the load's exact integral from the relay closing, in
    runs where nothing else acts on the current: no BMS fault, the relay closed once
    and never opened, no balancing, no fault but an over-current (which adds its own
    current over its own events' span) or one the current does not see. CVODE's charge
    quadrature is error-controlled (absolute 1e-3 As a step): 1e-4 relative + 0.02 As."""
    pieces = load_pieces(scen["load"], case_dir)
    if pieces is None or any(e["kind"] == "fault_active" for e in r.events):
        return []
    if [e["detail"] for e in r.events if e["kind"] == "relay_contact"] != ["closed"]:
        return []
    if any(f["kind"] not in ("overcurrent", "thermistor_open", "channel_gain") for f in scen.get("faults", [])):
        return []
    t_close = next(e["time_s"] for e in r.events if e["kind"] == "relay_contact")
    t_end = r.summary["duration_s"]
    q = load_charge_As(pieces, t_close, t_end)
    starts = [e for e in r.events if e["kind"] == "fault_injected" and e["detail"].startswith("overcurrent")]
    ends = [e["time_s"] for e in r.events if e["kind"] == "fault_removed" and e["detail"].startswith("overcurrent")]
    oc = [f for f in scen.get("faults", []) if f["kind"] == "overcurrent"]
    if len(starts) > 1 or len(oc) > 1:
        return []
    for e in starts:
        a, b = max(e["time_s"], t_close), min(ends[0] if ends else t_end, t_end)
        q += oc[0]["current_A"] * max(0.0, b - a)
    # Before the relay closes, the precharge path charges the load bus's capacitor from
    # the pack: C * v_bus at the close (the example firmware precharges; no bus leak in
    # a generated case). Past the close the bus follows the pack in the model.
    if any(e["kind"] == "precharge_contact" for e in r.events):
        vals = packsim.show(str(case_dir / "inline.yaml"))["values"]
        c_uF = float(vals["hardware.precharge.bus_capacitance_uF"]["value"]) \
            if "hardware.precharge.bus_capacitance_uF" in vals else 1000.0  # docs/scenario.md's default
        t = np.asarray(r["time_s"])
        k = int(np.searchsorted(t, t_close - 1e-9)) - 1  # the last sample before the close
        if k >= 0:
            q += 1e-6 * c_uF * float(np.asarray(r["hardware/bus_voltage_V"])[k])
    got = 3600.0 * r.summary["charge_delivered_Ah"]
    # CVODE restarts at every breakpoint at first order, and on a ramp each restart's
    # charge is good to its local error bound: a 10 Hz linear log of 1,200 rows came
    # out 0.46 As high (rtol 1e-9: 0.006 As). Step pieces integrate exactly.
    t_pts = pieces[0]
    n_breaks = sum(1 for k in range(pieces[3]) for tp in t_pts if t_close < k * t_pts[-1] + tp < t_end) \
        if not math.isinf(t_pts[-1]) else 0
    # Each restart's charge is good to CVODE's local error bound, atol + rtol * |q|
    # (1e-3 As + 1e-6 of the charge so far): a 21s20p pack on a 100 Hz linear log of
    # 3,549 rows came out 6 As (8.6e-4) high.
    per_restart = 1e-3 + 1e-6 * abs(q)
    tol = 1e-4 * abs(q) + 0.02 + (per_restart * n_breaks if pieces[2] and scen["run"]["solver"] == "cvode" else 0.0)
    return [f"charge: {got:.6f} As out of the pack, the load's integral from the contact closing is {q:.6f} As"] \
        if abs(got - q) > tol else []


def check_soc(scen: dict, r) -> list:
    """Charge conservation inside the pack: each series group carries the pack current, so
    the cells' SOC loss times their capacity is the series count times the charge the
    counter delivered. Judged where that is exact: every cell of one capacity (no
    capacity spread) and no charging current (the coulombic efficiency applies to
    charge only). A 1 s tick on a ramping load once lost 0.8 % of it from the SOC (the fast
    integrator's Euler step against the counter's trapezoid)."""
    pack = scen.get("pack", {})
    cell = pack.get("cell", {})
    cap = cell.get("capacity_Ah", PRESETS.get(cell.get("preset"), (None,))[0])
    if cap is None or "series" not in pack or pack.get("spread", {}).get("capacity_rel_sd", 0.0) != 0.0:
        return []
    current = np.asarray(r["truth/cell_current_A"])
    if current.size == 0 or float(current.min()) < -1e-6 or "truth/balance_current_A" in r.keys():
        return []  # a resistor's bleed: the record oracle's group charge (campaign_record.check_cell_charge)
    soc = np.asarray(r["truth/cell_soc"])
    taken = float(np.sum(soc[0] - soc[-1])) * cap * 3600.0
    q = 3600.0 * r.summary["charge_delivered_Ah"] * pack["series"]
    # The fast integrator keeps it to rounding. CVODE holds each SOC to its own error
    # bound (rtol 1e-6 of the SOC: up to ~2e-6 of a cell's capacity, each cell apart; a
    # 10s10p case came out 0.011 of 130 As apart), while the counter is exact.
    tol = 1e-5 * abs(q) + 1e-3
    if scen.get("run", {}).get("solver", "cvode") == "cvode":
        tol += soc.shape[-1] * 2e-6 * cap * 3600.0
    if abs(taken - q) > tol:
        return [f"soc: the cells' SOC fell by {taken:.6f} As of charge, the counter delivered {q:.6f} As "
                f"(series x charge delivered)"]
    return []


def _integral_pl(x, y, a: float, b: float) -> float:
    """The integral from a to b of the piecewise-linear table (x, y), held flat beyond its
    ends (how packsim evaluates a 1-D table): exact, by the trapezoid on its own knots."""
    lo, hi = min(a, b), max(a, b)
    pts = np.unique(np.concatenate(([lo, hi], [v for v in x if lo < v < hi])))
    ys = np.interp(pts, x, y)
    val = float(np.sum(0.5 * (ys[1:] + ys[:-1]) * np.diff(pts)))
    return val if b >= a else -val


def energy_balance(scen: dict, r):
    """(given_J, out_J, stored_J, through_J) for check_energy, or None where the balance is
    not exact (through_J: the energy that flowed either way, the cells' |V*I| integrated).
    Energy conservation, from the cells' own states: the energy the cells gave up (their
    OCV integrated over the SOC each one moved, times its capacity) is the energy delivered
    at the terminals, plus the heat, plus what sits in the RC pairs at the end (C*V^2/2,
    from the recorded voltage, current and SOC). Judged where every term is known exactly:
    an inline cell with OCV and R0 tables over SOC only (no temperature law, hysteresis or
    entropic term), one RC pair, no parameter spread and no coulombic loss on charge."""
    pack = scen.get("pack", {})
    cell = pack.get("cell", {})
    if "ocv_V" not in cell or len(cell.get("rc_pairs", [])) != 1 or "series" not in pack:
        return None
    spread = pack.get("spread", {})
    if spread.get("capacity_rel_sd", 0.0) != 0.0 or spread.get("r0_rel_sd", 0.0) != 0.0:
        return None
    if any(k in cell for k in ("hysteresis", "docv_dT_V_per_K", "r0_arrhenius_K", "temperature")) or \
            cell.get("coulombic_efficiency", 1.0) != 1.0:
        return None
    ox, oy = cell["ocv_V"]["x"], cell["ocv_V"]["y"]
    rx, ry = cell["r0_ohm"]["x"], cell["r0_ohm"]["y"]
    cap_As = cell["capacity_Ah"] * 3600.0
    soc = np.asarray(r["truth/cell_soc"])
    v = np.asarray(r["truth/cell_voltage_V"])[-1]
    i = np.asarray(r["truth/cell_current_A"])[-1]
    given_J = sum(cap_As * _integral_pl(ox, oy, float(e), float(s0)) for s0, e in zip(soc[0], soc[-1]))
    pair = cell["rc_pairs"][0]
    c_F = pair["tau_s"] / pair["r_ohm"]
    v_rc = np.interp(soc[-1], ox, oy) - i * np.interp(soc[-1], rx, ry) - v
    stored_J = float(np.sum(0.5 * c_F * v_rc ** 2))
    s = r.summary
    out_J = 3600.0 * (s["energy_delivered_Wh"] + s["heat_Wh"]) + stored_J
    t = np.asarray(r["time_s"])
    p_W = np.sum(np.abs(np.asarray(r["truth/cell_current_A"]) * np.asarray(r["truth/cell_voltage_V"])), axis=1)
    through_J = float(np.sum(0.5 * (p_W[1:] + p_W[:-1]) * np.diff(t))) if t.size > 1 else 0.0
    return given_J, out_J, stored_J, through_J


def check_energy(scen: dict, r) -> list:
    """Energy conservation where it is exact (energy_balance)."""
    b = energy_balance(scen, r)
    if b is None:
        return []
    given_J, out_J, stored_J, through_J = b
    s = r.summary
    # The SOC path is exact here; the load-energy and heat quadratures are the integrator's:
    # their error scales with the energy that flowed either way, so the tolerance is a
    # share of that throughput. On the fast integrator it shrinks with the tick: a 1 s tick
    # on a ramping log missed by 5.3e-5 of the throughput, 2.6e-5 at 0.5 s, 8.6e-6 at
    # 0.25 s, 2.1e-6 at 0.1 s (the same case); a 50 ms tick on a 100 Hz linear log
    # charging and discharging by 1.3e-5. CVODE holds each SOC to its own error bound (as
    # in check_soc) and its quadratures to its tolerance: 1.4e-5 at worst. Measured over
    # 126 generated cases; each figure here is at least 3x the worst seen.
    scale_J = through_J + abs(given_J)
    if scen.get("run", {}).get("solver", "cvode") == "cvode":
        cells = np.asarray(r["truth/cell_soc"]).shape[-1]
        tol = 6e-5 * scale_J + cells * 2e-6 * scen["pack"]["cell"]["capacity_Ah"] * 3600.0 * \
            max(scen["pack"]["cell"]["ocv_V"]["y"])
    else:
        tol = (2e-5 + 1e-4 * scen.get("bms", {}).get("tick_ms", 10) / 1000.0) * scale_J
    tol += 0.01
    if abs(given_J - out_J) > tol:
        return [f"energy: the cells gave up {given_J / 3600:.6f} Wh (OCV over the SOC they moved); delivered "
                f"{s['energy_delivered_Wh']:.6f} + heat {s['heat_Wh']:.6f} + RC {stored_J / 3600:.6f} Wh "
                f"= {out_J / 3600:.6f} Wh"]
    return []


def check_physics(scen: dict, r) -> list:
    out = []
    t = np.asarray(r["time_s"])
    s = r.summary
    v = np.asarray(r["truth/cell_voltage_V"])
    if v.size and abs(float(v.min()) - s["min_cell_V"]) > 1e-6:
        out.append(f"summary lowest cell {s['min_cell_V']:.6f} V, truth {float(v.min()):.6f} V")
    temps = np.asarray(r["truth/cell_temp_C"])
    if temps.size and abs(float(temps.max()) - s["max_temp_C"]) > 1e-6:
        out.append(f"summary hottest cell {s['max_temp_C']:.6f} C, truth {float(temps.max()):.6f} C")
    if abs(s["duration_s"] - float(t[-1])) > 1e-9:
        out.append(f"summary duration {s['duration_s']} vs last sample {float(t[-1])}")
    if s["tripped"]:  # packsim's core latches a fault; a library firmware reports "trip: <reason>"
        latched = [e["time_s"] for e in r.events if e["kind"] == "fault_latched" or
                   e["kind"] == "firmware" and e["detail"].startswith("trip:")]
        if not latched or min(latched) > s["trip_time_s"] + 1e-9:
            out.append(f"summary says TRIP at {s['trip_time_s']} s without a latched fault by then")
    # A cell past 80 C (the self-heating onset) is a cell_model_range event, and only then.
    beyond = [e for e in r.events if e["kind"] == "cell_model_range" and "above 80 C" in e["detail"]]
    if (s["max_temp_C"] > 80.0) != bool(beyond):
        out.append(f"hottest cell {s['max_temp_C']:.3f} C but {len(beyond)} cell_model_range events above 80 C")
    # The run's last event says why it ended; a run that ended before its end time says
    # it was not the scheduled end.
    last = r.events[-1] if len(r.events) else None
    if last is None or last["kind"] != "run" or not last["detail"].startswith("end: "):
        out.append(f"the last event is not the run's end: {last}")
    elif last["detail"] == "end: the scenario's end time" and "duration_s" in scen.get("run", {}) and \
            s["duration_s"] < scen["run"]["duration_s"] - scen.get("bms", {}).get("tick_ms", 10) / 1000.0 - 1e-9:
        out.append(f"run ended at {s['duration_s']} s of {scen['run']['duration_s']} but says the scenario's end time")
    return out


def check_faults(scen: dict, r) -> list:
    out = []
    injected = [e for e in r.events if e["kind"] == "fault_injected"]
    reported = [e for e in r.events if e["kind"] in ("fault_not_reached", "fault_unreached")]
    for f in scen.get("faults", []):
        n_same = sum(1 for g in scen["faults"] if g["kind"] == f["kind"])
        got = sum(1 for e in injected + reported if e["detail"].startswith(f["kind"]))
        if got < n_same:
            out.append(f"fault {f['kind']} at {f['at_s']} s neither injected nor reported as not reached")
    return out


def relay_change_time(r) -> float:
    """The first instant after the start at which the firmware opened the relay (a
    decision both integrators must share before their trajectories can be compared)."""
    for e in r.events:
        if e["kind"] in ("relay", "fault_active", "fault_latched") and e["time_s"] > 0.05 and (
                e["kind"] != "relay" or "open" in e["detail"]):
            return e["time_s"]
    return math.inf


SOLVER_PREFIX_S = 30.0  # the other integrator's run: the case's first 30 s (the same inputs up to there)


def check_solvers(path: Path, r_a, solver_a: str) -> list:
    other = "fast" if solver_a == "cvode" else "cvode"
    t_last = float(np.asarray(r_a["time_s"])[-1])
    over = {"run.solver": other}
    if t_last > SOLVER_PREFIX_S:  # a prefix of the same run: the same load, faults and seed up to its end
        over["run.duration_s"] = SOLVER_PREFIX_S
    r_b = packsim.run(str(path), over)
    ta = np.asarray(r_a["time_s"])
    tb = np.asarray(r_b["time_s"])
    t_end = min(relay_change_time(r_a), relay_change_time(r_b))
    n = min(len(ta), len(tb))
    k = int(np.searchsorted(ta[:n], t_end - 1e-9))  # samples before either decided differently
    if k == 0:
        return []
    out = []
    # Voltage to 5 mV; the SOC each cell holds to 2e-5 (0.002 %) and its temperature to
    # 0.05 K: the states the integrators carry, not only the terminal voltage they give.
    for key, tol, unit, scale in (("truth/cell_voltage_V", 5e-3, "mV", 1000.0), ("truth/cell_soc", 2e-5, "%", 100.0),
                                  ("truth/cell_temp_C", 0.05, "K", 1.0)):
        d = float(np.max(np.abs(np.asarray(r_a[key])[:k] - np.asarray(r_b[key])[:k])))
        if d > tol:
            out.append(f"solvers: {key} differs by {scale * d:.4g} {unit} before t={ta[k - 1]:.3f} s")
    return out


def scripted_changes(scen: dict, case_dir: Path, t_end: float) -> list:
    """Every instant the scenario changes the load inside the run: load breakpoints (each
    lap's), fault starts and ends; the record's intervals holding more than one are not
    resolved by its samples (campaign_record.busy_intervals)."""
    out = []
    pieces = load_pieces(scen["load"], case_dir)
    if pieces is not None and not math.isinf(pieces[0][-1]):
        lap = pieces[0][-1]
        out += [n * lap + tp for n in range(pieces[3]) for tp in pieces[0] if 0 < n * lap + tp < t_end]
    for f in scen.get("faults", []):
        out += [f["at_s"]] + ([f["at_s"] + f["duration_s"]] if "duration_s" in f else [])
    return out


def drawn_cells(path: Path, overrides: dict, out_dir: Path):
    """A spread pack's drawn cells: a one-tick batch case records them (/inputs)."""
    res = packsim.batch({"base": str(path), "grid": {"run.duration_s": [0.1]}}, output_dir=str(out_dir))
    if res.n_failed:
        raise RuntimeError(f"the one-tick batch of the drawn cells failed: {res.errors}")
    return res.load(0)


def check_record(scen: dict, r, inline: Path, case_dir: Path) -> list:
    """The summary's figures against the record (scripts/campaign_record.py)."""
    vals = packsim.show(str(inline))["values"]
    series, parallel = int(vals["pack.series"]["value"]), int(vals["pack.parallel"]["value"])
    library = "bms.firmware.library" in vals and vals["bms.firmware.library"]["value"] not in ("", "''", '""')
    out = rec.check_groups(r, series, parallel) + rec.check_extremes(r) + rec.check_trip(r, library) + \
        rec.check_states(r)
    t = np.asarray(r["time_s"])
    busy = rec.busy_intervals(t, scripted_changes(scen, case_dir, float(t[-1])), r.events,
                              ramps=scen["load"].get("interpolation") == "linear")
    cvode = r.attrs[""]["solver"] == "cvode"  # the root attribute: what ran
    out += rec.check_energy_out(r, busy, cvode) + rec.check_bled(r, busy)
    table = rec.cell_table(scen)
    if table is None:
        return out
    spread = scen["pack"].get("spread", {})
    drawn = drawn_cells(inline, {}, case_dir / "drawn") \
        if spread.get("capacity_rel_sd", 0.0) or spread.get("self_discharge_A_sd", 0.0) else None
    cells = rec.Cells(table, series * parallel, drawn)
    out += rec.check_cell_charge(r, cells, series, parallel, busy, cvode)
    out += rec.check_stranded(r, cells)
    return out


def run_case(index: int, campaign_seed: int, out_dir: Path, keep: bool, max_s: float = 900.0) -> dict:
    case_seed = campaign_seed * 1_000_003 + index
    case_dir = out_dir / f"case-{index}"
    shutil.rmtree(case_dir, ignore_errors=True)
    case_dir.mkdir(parents=True)
    t0 = time.perf_counter()
    case = make_case(case_seed, case_dir, max_s)
    findings = []
    oracle = "runs"
    try:
        child, inline = write_case(case, case_dir)
        r = packsim.run(str(child), case["overrides"])
        oracle = "finite"
        findings += check_finite(r)
        oracle = "determinism"
        if (d := same_bytes(r, packsim.run(str(child), case["overrides"]))):
            findings.append("determinism: " + d)
        oracle = "extends"
        if (d := same_bytes(r, packsim.run(str(inline)), ignore_lines=True)):
            findings.append("extends chain + overrides vs inlined: " + d)
        oracle = "physics"
        findings += check_physics(case["scenario"], r)
        oracle = "charge"
        findings += check_charge(case["scenario"], r, case_dir)
        oracle = "soc"
        findings += check_soc(case["scenario"], r)
        oracle = "energy"
        findings += check_energy(case["scenario"], r)
        oracle = "record"
        findings += check_record(case["scenario"], r, inline, case_dir)
        oracle = "faults"
        findings += check_faults(case["scenario"], r)
        oracle = "solvers"
        findings += check_solvers(inline, r, case["scenario"]["run"]["solver"])
    except Exception as e:  # noqa: BLE001 -- any error on a valid scenario is a finding
        findings.append(f"{oracle}: {type(e).__name__}: {e}".strip()[:2000])
        if os.environ.get("CAMPAIGN_TRACE"):
            traceback.print_exc()
    if not findings and not keep:
        shutil.rmtree(case_dir, ignore_errors=True)
    return {"case": index, "seed": case_seed, "findings": findings, "dir": str(case_dir),
            "seconds": round(time.perf_counter() - t0, 2)}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cases", type=int, default=200)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--first", type=int, default=0, help="index of the first case")
    ap.add_argument("--only", type=int, help="replay one case")
    ap.add_argument("--out", default=None, help="folder for findings (default: a temp folder)")
    ap.add_argument("--keep", action="store_true", help="keep every case's files")
    ap.add_argument("--max-s", type=float, default=900.0,
                    help="cap on each case's simulated time (default 900 s)")
    a = ap.parse_args(argv)
    out = Path(a.out) if a.out else Path(tempfile.mkdtemp(prefix="packsim-campaign-"))
    out.mkdir(parents=True, exist_ok=True)
    cases = [a.only] if a.only is not None else range(a.first, a.first + a.cases)
    failed = 0
    with open(out / "findings.jsonl", "a") as log:
        for n, i in enumerate(cases, 1):
            res = run_case(i, a.seed, out, a.keep, a.max_s)
            if res["findings"]:
                failed += 1
                log.write(json.dumps(res) + "\n")
                log.flush()
                print(f"case {i}: FAIL  " + " | ".join(res["findings"])[:400], flush=True)
            if n % 50 == 0:
                print(f"{n} cases, {failed} failed", flush=True)
    print(f"campaign seed {a.seed}: {len(cases)} cases, {failed} failed; findings in {out / 'findings.jsonl'}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
