"""The campaign's oracles that a battery engineer checks by hand: each summary figure
against the same quantity derived from the recorded samples alone (scripts/campaign.py,
docs/hardening.md "Generated scenarios"). None of them calls packsim's summary code.

  cells         each series group's cells carry the pack current plus its balancing
                current, at every recorded sample (Kirchhoff at the group's terminals)
  cell charge   each cell's SOC moved by its own recorded current integrated (coulombic
                efficiency on charge, self-discharge), within what the samples resolve;
                each group's cells' SOC moved by the counter's charge plus the group's
                balancing charge (exact)
  bled          the summary's balancing charge = the recorded balancing currents integrated
  energy out    the summary's energy (net, and back in) = the recorded V*I integrated
  extremes      the summary's lowest / hottest cell: which cell, its value and when, is a
                recorded sample holding the record's minimum / maximum, the first cell
                holding it there
  trip          the trip time is the first sample whose relay command is open with a fault
                latched, its reason the latched faults' names there (packsim's core); a
                library firmware's is its own `trip:` event
  stranded      energy at the start, left and stranded by imbalance, by hand from each
                cell's recorded SOC and its OCV table (docs/results.md's definition)
  states        final SOC range, relay closed, charger on/off and balancing start/balanced
                times against the recorded flags

A sample k holds the truth at t_k and the BMS's decision at t_k (acting from t_k on).
Between two samples the record does not resolve the current: a load step, a relay
closing or a BMS decision inside an interval. The integrals are trapezoids with an
error bound per interval of half its width times the change across it (exact for a
current monotone inside it, which holds with at most one step in it); intervals with
more than one scripted change inside get the whole swing.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import yaml

ROOT = Path(__file__).resolve().parents[1]
FAULT_NAMES = ["cell_overvoltage", "cell_undervoltage", "overcurrent_discharge", "overcurrent_charge",
               "overtemperature", "overtemperature_charge", "undertemperature", "undertemperature_charge",
               "board_overtemperature", "comm_loss", "cell_sum_plausibility", "thermistor_fault",
               "current_sensor_fault", "estop", "monitor_fault", "relay_welded", "precharge_failed",
               "temperature_warning", "cell_imbalance", "fet_overtemperature"]  # docs/results.md


def cell_table(scen: dict) -> dict | None:
    """The scenario's cell as its YAML gives it (a bundled preset's file, with any field
    stated beside `preset:` over it); None for a cell this module cannot read."""
    cell = scen.get("pack", {}).get("cell", {})
    if "preset" in cell:
        base = yaml.safe_load((ROOT / "scenarios" / "cells" / f"{cell['preset']}.yaml").read_text())
        return {**base, **{k: v for k, v in cell.items() if k != "preset"}}
    return cell if "ocv_V" in cell else None


class Cells:
    """Each cell's capacity (As), self-discharge (A) and coulombic efficiency, and the
    OCV table: the nominal cell's, or the values a spread drew (read from a batch case's
    /inputs, which records them)."""

    def __init__(self, table: dict, n: int, drawn=None):
        cap = float(table["capacity_Ah"])
        x, y = np.asarray(table["ocv_V"]["x"], float), np.asarray(table["ocv_V"]["y"], float)
        if table["ocv_V"].get("axis", "soc") == "discharged_Ah":  # Ah out of the nominal cell: SOC = 1 - x / Q
            x, y = (1.0 - x / cap)[::-1], y[::-1]
        self.ocv_x, self.ocv_y = x, y
        sd = float(table.get("self_discharge_A", 0.0))
        self.cap_As = 3600.0 * (np.asarray(drawn["inputs/cell_capacity_Ah"]) if drawn is not None else np.full(n, cap))
        self.sd_A = np.asarray(drawn["inputs/cell_self_discharge_A"]) if drawn is not None else np.full(n, sd)
        self.eta = float(table.get("coulombic_efficiency", 1.0))
        self.v_min = float(table.get("v_min_V", 0.0))

    def energy_Wh(self, soc: np.ndarray) -> np.ndarray:
        """Q_i * integral of OCV from 0 to soc_i (clamped to [0, 1]), exactly: the table is
        piecewise linear, held flat beyond its ends."""
        out = np.empty(len(soc))
        for i, s in enumerate(np.clip(soc, 0.0, 1.0)):
            pts = np.unique(np.concatenate(([0.0, s], self.ocv_x[(self.ocv_x > 0.0) & (self.ocv_x < s)])))
            ys = np.interp(pts, self.ocv_x, self.ocv_y)
            out[i] = float(np.sum(0.5 * (ys[1:] + ys[:-1]) * np.diff(pts)))
        return out * self.cap_As / 3600.0


def trapezoid(t: np.ndarray, y: np.ndarray, busy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(integral, error bound) over the samples, per column of y: half each interval's
    width times its change, the whole swing where `busy` (>1 scripted change inside)."""
    dt = np.diff(t)[:, None] if y.ndim == 2 else np.diff(t)
    mid = 0.5 * (y[1:] + y[:-1]) * dt
    change = np.abs(y[1:] - y[:-1])
    swing = np.maximum(np.abs(y[1:]), np.abs(y[:-1]))
    b = busy[:, None] if y.ndim == 2 else busy
    bound = np.where(b, 2.0 * swing + change, 0.5 * change) * dt
    return mid.sum(axis=0), bound.sum(axis=0)


SWITCHING = ("relay_contact", "precharge_contact", "fuse", "fault_injected", "fault_removed")


def busy_intervals(t: np.ndarray, changes: list[float], events=(), ramps: bool = False) -> np.ndarray:
    """Intervals (t_k, t_k+1] whose current the samples do not bound: more than one change
    strictly inside (scripted load breakpoints and faults, and the contacts and fuse
    switching, from the events), or with `ramps` (a linear load) any one: a contact closing
    onto a ramp jumps and then ramps back (a 1 s tick, a contact closing 0.3 ms after the
    tick onto a charge current ramping to 0 A: the samples held a fifth of the energy in)."""
    changes = list(changes) + [e["time_s"] for e in events if e["kind"] in SWITCHING]
    k = np.searchsorted(t, np.asarray(sorted(changes)), side="left") - 1
    counts = np.bincount(k[(k >= 0) & (k < len(t) - 1)], minlength=len(t) - 1) if len(changes) else \
        np.zeros(len(t) - 1, int)
    return counts > (0 if ramps else 1)


def check_groups(r, series: int, parallel: int) -> list:
    """Kirchhoff at each group's terminals, at every sample: its cells' currents sum to the
    pack current plus its balancing current (a resistor across the group)."""
    i = np.asarray(r["truth/cell_current_A"]).reshape(-1, series, parallel).sum(axis=2)
    pack = np.asarray(r["truth/pack_current_A"])[:, None]
    bal = np.asarray(r["truth/balance_current_A"]) if "truth/balance_current_A" in r.keys() else 0.0
    err = np.abs(i - pack - bal)
    k, g = np.unravel_index(int(np.argmax(err)), err.shape)
    if err[k, g] > 1e-9 * (1.0 + float(np.max(np.abs(pack)))) * parallel:
        t = float(np.asarray(r["time_s"])[k])
        return [f"cells: group {g + 1}'s cells carry {i[k, g]:.9f} A at {t} s, the pack "
                f"{float(pack[k, 0]):.9f} A + balancing {float(np.asarray(bal)[k, g]) if np.ndim(bal) else 0.0:.9f} A"]
    return []


def check_cell_charge(r, cells: Cells, series: int, parallel: int, busy: np.ndarray, cvode: bool) -> list:
    """Each cell: capacity x SOC lost = its recorded current integrated (coulombic
    efficiency on charge) + self-discharge x time, within the trapezoid's bound. Each
    group: its cells' capacity x SOC lost = the counter's charge + its balancing charge
    (+ self-discharge, less the coulombic loss), exact but for that loss's trapezoid."""
    t = np.asarray(r["time_s"])
    if t.size < 2:
        return []
    soc = np.asarray(r["truth/cell_soc"])
    cur = np.asarray(r["truth/cell_current_A"])
    taken = cells.cap_As * (soc[0] - soc[-1])
    span = float(t[-1] - t[0])
    soc_tol = (2e-6 if cvode else 1e-9) * cells.cap_As  # CVODE holds each SOC to its own bound
    eff = np.where(cur < 0.0, cells.eta * cur, cur)
    q, bound = trapezoid(t, eff, busy)
    q += cells.sd_A * span
    out = []
    miss = np.abs(taken - q) - (bound + soc_tol + 1e-9 * np.abs(q) + 1e-9)
    if np.max(miss) > 0.0:
        c = int(np.argmax(miss))
        out.append(f"cell charge: cell {c + 1}'s SOC fell by {taken[c]:.6f} As of charge, its recorded current "
                   f"integrates to {q[c]:.6f} As (bound {bound[c]:.6f} As)")
    loss, loss_bound = trapezoid(t, np.minimum(cur, 0.0) * (1.0 - cells.eta), busy)  # charge not stored
    counter = 3600.0 * r.summary["charge_delivered_Ah"]
    bal, bal_bound = (trapezoid(t, np.asarray(r["truth/balance_current_A"]), busy)
                      if "truth/balance_current_A" in r.keys() else (np.zeros(series), np.zeros(series)))
    g_taken = taken.reshape(series, parallel).sum(axis=1)
    g_want = counter + bal + (cells.sd_A * span - loss).reshape(series, parallel).sum(axis=1)
    # The counter is a CVODE state too: 1e-4 of it there (scripts/campaign.py's check_charge).
    g_tol = bal_bound + loss_bound.reshape(series, parallel).sum(axis=1) + \
        soc_tol.reshape(series, parallel).sum(axis=1) + (1e-4 if cvode else 1e-6) * abs(counter) + 2e-3
    g_miss = np.abs(g_taken - g_want) - g_tol
    if np.max(g_miss) > 0.0:
        g = int(np.argmax(g_miss))
        out.append(f"group charge: group {g + 1}'s cells' SOC fell by {g_taken[g]:.6f} As, the counter delivered "
                   f"{counter:.6f} As and its resistor bled {bal[g]:.6f} As (bound {g_tol[g]:.6f} As)")
    return out


def check_bled(r, busy: np.ndarray) -> list:
    """The summary's balancing charge against the recorded balancing currents integrated."""
    if "truth/balance_current_A" not in r.keys() or "balance_bled_Ah" not in r.summary:
        return []
    t = np.asarray(r["time_s"])
    q, bound = trapezoid(t, np.asarray(r["truth/balance_current_A"]), busy)
    got = 3600.0 * r.summary["balance_bled_Ah"]
    if abs(got - float(q.sum())) > float(bound.sum()) + 1e-6 * abs(got) + 1e-4:
        return [f"bled: the summary says {got:.6f} As bled, the recorded balancing currents integrate to "
                f"{float(q.sum()):.6f} As (bound {float(bound.sum()):.6f})"]
    return []


def check_energy_out(r, busy: np.ndarray, cvode: bool = False) -> list:
    """The summary's energy delivered (net) = the recorded pack V*I integrated; its energy
    back in is at most the negative part of that, and out = net + in is not negative.
    CVODE integrates the energy as a state at its relative tolerance, so its error grows
    with the energy (bundled eco_marathon_12s_charging: 1.3e-5 of 139 Wh after 6,000 s of
    CC charge, where the fast integrator's trapezoid matches the record): 5e-5 of the
    energy that flowed either way on that solver."""
    t = np.asarray(r["time_s"])
    if t.size < 2:
        return []
    p = np.asarray(r["truth/pack_voltage_V"]) * np.asarray(r["truth/pack_current_A"])
    e, bound = trapezoid(t, p, busy)
    solver_J = 5e-5 * float(trapezoid(t, np.abs(p), busy)[0]) if cvode else 0.0
    bound = bound + solver_J
    s = r.summary
    got = 3600.0 * s["energy_delivered_Wh"]
    out = []
    if abs(got - float(e)) > float(bound) + 1e-6 * abs(got) + 1e-3:
        out.append(f"energy out: the summary says {s['energy_delivered_Wh']:.6f} Wh net, the recorded pack V*I "
                   f"integrates to {float(e) / 3600:.6f} Wh (bound {float(bound) / 3600:.6f} Wh)")
    back, back_bound = trapezoid(t, np.minimum(p, 0.0), busy)
    back_bound = back_bound + solver_J
    if s.get("energy_in_Wh", 0.0) < 0.0 or 3600.0 * s.get("energy_in_Wh", 0.0) > -float(back) + float(back_bound) + \
            1e-6 * abs(got) + 1e-3:
        out.append(f"energy in: the summary says {s.get('energy_in_Wh')} Wh back in, the recorded V*I had "
                   f"{-float(back) / 3600:.6f} Wh going in")
    return out


def check_extremes(r) -> list:
    """The lowest cell (voltage) and the hottest (temperature): the named cell at the named
    time holds the value, and it is the record's extreme; it is the first cell at it there."""
    t = np.asarray(r["time_s"])
    s = r.summary
    out = []
    for what, key, cell_key, time_key, pick in (
            ("lowest cell", "truth/cell_voltage_V", "min_cell", "min_cell_time_s", np.min),
            ("hottest cell", "truth/cell_temp_C", "hottest_cell", "hottest_time_s", np.max)):
        a = np.asarray(r[key])
        if a.size == 0:
            continue
        value = s["min_cell_V" if cell_key == "min_cell" else "max_temp_C"]
        extreme = float(pick(a))
        k = np.flatnonzero(np.abs(t - s[time_key]) < 1e-9)
        c = int(s[cell_key]) - 1
        if k.size == 0 or not 0 <= c < a.shape[1]:
            out.append(f"extremes: the {what} is cell {s[cell_key]} at {s[time_key]} s: no such sample")
            continue
        held = float(a[k[0], c])
        if abs(held - value) > 1e-9 * max(1.0, abs(value)) or abs(extreme - value) > 1e-9 * max(1.0, abs(value)):
            out.append(f"extremes: the summary's {what} is cell {c + 1} at {s[time_key]} s, {value:.9f}; that sample "
                       f"holds {held:.9f}, the record's extreme is {extreme:.9f}")
            continue
        # When: a sample holding the extreme (the first one within 1e-9 is not asked for: a
        # value at rest wanders by an ulp, and the summary keeps the strictly lowest).
        same = np.flatnonzero(a[k[0]] == held)  # exactly: two cells an ulp apart are not tied
        if int(same[0]) != c:  # cells at one value (a parallel group's voltage): the first is named
            out.append(f"extremes: the {what} is cell {int(same[0]) + 1} (the first at {value:.9f} at "
                       f"{s[time_key]} s), the summary says cell {c + 1}")
    return out


def check_trip(r, library_firmware: bool) -> list:
    """packsim's core: the trip is the first sample whose relay command is open with a
    fault latched; its reason names the latched faults there. A library firmware: its
    first `trip:` event, with its reason."""
    s = r.summary
    t = np.asarray(r["time_s"])
    if library_firmware:
        trips = [e for e in r.events if e["kind"] == "firmware" and e["detail"].startswith("trip:")]
        if bool(s["tripped"]) != bool(trips):
            return [f"trip: summary tripped={s['tripped']}, {len(trips)} firmware trip events"]
        if trips and (abs(trips[0]["time_s"] - s["trip_time_s"]) > 1e-9 or
                      trips[0]["detail"][len("trip:"):].strip() != s["trip_reason"]):
            return [f"trip: summary {s['trip_time_s']} s '{s['trip_reason']}', first event {trips[0]}"]
        return []
    latched = np.asarray(r["bms/fault_latched"])
    opened = (np.asarray(r["bms/relay_closed"]) == 0) & (latched != 0)
    k = np.flatnonzero(opened)
    if not k.size:
        return [f"trip: summary says TRIP at {s['trip_time_s']} s, no sample has the relay open on a latched fault"] \
            if s["tripped"] else []
    names = ", ".join(n for b, n in enumerate(FAULT_NAMES) if int(latched[k[0]]) >> b & 1)
    if not s["tripped"] or abs(float(t[k[0]]) - s["trip_time_s"]) > 1e-9 or names != s["trip_reason"]:
        return [f"trip: the relay command was open on latched {names} first at {float(t[k[0]])} s; the summary "
                f"says tripped={s['tripped']} at {s['trip_time_s']} s: '{s['trip_reason']}'"]
    first_latch = min((e["time_s"] for e in r.events if e["kind"] == "fault_latched"), default=math.inf)
    if first_latch > s["trip_time_s"] + 1e-9:
        return [f"trip: TRIP at {s['trip_time_s']} s but the first fault_latched event is at {first_latch} s"]
    return []


def check_stranded(r, cells: Cells) -> list:
    """Energy at the start, left and stranded by imbalance (docs/results.md): E_i(soc) =
    Q_i * integral of OCV from 0 to soc; left = sum E_i(soc_i) at the limit (the first
    sample a cell is at or below v_min_V, the BMS's under-voltage trip, else the end);
    stranded = sum max(0, E_i(soc_i) - E_i(soc_w)), w the limiting cell (the first at its
    limit; at the end, the lowest in SOC)."""
    s = r.summary
    t = np.asarray(r["time_s"])
    soc = np.asarray(r["truth/cell_soc"])
    v = np.asarray(r["truth/cell_voltage_V"])
    out = []
    at = np.flatnonzero(np.any(v <= cells.v_min, axis=1))
    if s["limit_reached"] and not s["limit_by_bms_trip"]:
        if not at.size:
            return [f"stranded: the summary says a cell reached its limit at {s['limit_time_s']} s; none is at or "
                    f"below v_min {cells.v_min} V in the record"]
        k = int(at[0])
        w = int(np.flatnonzero(v[k] <= cells.v_min)[0])
    elif s["limit_reached"]:
        k = int(np.flatnonzero(np.abs(t - s["limit_time_s"]) < 1e-9)[0])
        w = int(np.argmin(v[k]))
    else:
        if at.size:
            return [f"stranded: cell {int(np.flatnonzero(v[at[0]] <= cells.v_min)[0]) + 1} is at "
                    f"{float(v[at[0]].min()):.4f} V (v_min {cells.v_min}) at {t[at[0]]} s; the summary says no "
                    f"cell reached its limit"]
        k, w = len(t) - 1, int(np.argmin(soc[-1]))
    if abs(float(t[k]) - s["limit_time_s"]) > 1e-9 or w + 1 != int(s["limit_cell"]):
        out.append(f"stranded: the limit is cell {w + 1} at {float(t[k])} s in the record; the summary says cell "
                   f"{s['limit_cell']} at {s['limit_time_s']} s")
    e = cells.energy_Wh(soc[k])
    e_w = cells.energy_Wh(np.full(len(e), soc[k][w]))  # each cell's own capacity at the limiting cell's SOC
    left, stranded, start = float(e.sum()), float(np.maximum(0.0, e - e_w).sum()), float(cells.energy_Wh(soc[0]).sum())
    tol = 1e-5 * start + 1e-6  # the summary's Simpson rule on the OCV table's kinks
    for name, mine in (("energy_start_Wh", start), ("energy_left_Wh", left), ("energy_stranded_Wh", stranded)):
        if abs(s[name] - mine) > tol:
            out.append(f"stranded: summary {name} {s[name]:.6f} Wh, by hand from the recorded SOCs {mine:.6f} Wh")
    return out


def _first(t: np.ndarray, mask: np.ndarray) -> float:
    k = np.flatnonzero(mask)
    return float(t[k[0]]) if k.size else -1.0


def check_states(r) -> list:
    """Figures that name a sample, against the recorded flags: the final SOC range (the
    last row), whether the relay contact ever closed, when the BMS first enabled the
    charger and when it switched it off for good, when balancing first ran and when the
    firmware first said balanced after it, and an under-voltage trip that came first."""
    s = r.summary
    t = np.asarray(r["time_s"])
    out = []
    soc = np.asarray(r["truth/cell_soc"])[-1]
    if abs(float(soc.min()) - s["final_soc_min"]) > 1e-12 or abs(float(soc.max()) - s["final_soc_max"]) > 1e-12:
        out.append(f"states: final SOC {s['final_soc_min']}..{s['final_soc_max']}, the last sample holds "
                   f"{float(soc.min())}..{float(soc.max())}")
    closed = bool(np.any(np.asarray(r["hardware/relay_closed"]) != 0)) or \
        any(e["kind"] == "relay_contact" and e["detail"] == "closed" for e in r.events)
    if bool(s["relay_closed"]) != closed:
        out.append(f"states: summary relay_closed={s['relay_closed']}, the record's contact closed: {closed}")
    if "charge_on_s" in s and "bms/charger_enable" in r.keys():
        en = np.asarray(r["bms/charger_enable"]) != 0
        on = _first(t, en)
        ends = np.flatnonzero(en[:-1] & ~en[1:])
        off = float(t[ends[-1] + 1]) if ends.size and not en[-1] else -1.0
        if abs(on - s["charge_on_s"]) > 1e-9 or abs(off - s["charge_off_s"]) > 1e-9:
            out.append(f"states: charger on {s['charge_on_s']} off {s['charge_off_s']} s; the recorded enable: on "
                       f"{on}, off for good {off}")
    if "balance_started_s" in s and "bms/balance_status" in r.keys():
        st = np.asarray(r["bms/balance_status"])
        started = _first(t, st == 4)  # 4=balancing, 3=balanced (the names attribute)
        balanced = _first(t, (st == 3) & (t > started)) if started >= 0 else -1.0
        if abs(started - s["balance_started_s"]) > 1e-9 or abs(balanced - s["balance_balanced_s"]) > 1e-9:
            out.append(f"states: balancing started {s['balance_started_s']} balanced {s['balance_balanced_s']} s; "
                       f"the recorded status: {started}, {balanced}")
    if s["limit_by_bms_trip"] and ("cell_undervoltage" not in s["trip_reason"] or
                                   abs(s["limit_time_s"] - s["trip_time_s"]) > 1e-9):
        out.append(f"states: limit by the BMS trip at {s['limit_time_s']} s, the trip: {s['trip_time_s']} s "
                   f"'{s['trip_reason']}'")
    return out
