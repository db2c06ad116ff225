"""What a run page says first, computed from the result file alone: the verdict (from
the events), the margin to every protection limit (from the truth and the measured
channels), and the energy account (from the summary).

    from packsim import run_facts
    run_facts.verdict(r)     # Verdict: tripped or not, which protection, when, measured vs truth
    run_facts.margins(r)     # [Margin]: closest approach to each limit, truth and measured
    run_facts.energy(r)      # [(label, Wh, what it counts)]

Every number comes from the result: the events say what happened, the datasets say how
close it came, the /bms limit attributes say where the limits were (a protection the
scenario switched off has no attribute and no row). Nothing is re-simulated.
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field

import numpy as np

from .result import Result

__all__ = ["Verdict", "Margin", "verdict", "margins", "energy", "CHANNELS", "cell_name"]

INVALID_DC = -32768  # /measured/temperature_dC: open or shorted sensor


@dataclass(frozen=True)
class Channel:
    """One protection channel: the limit attribute of /bms, the fault bit that trips on
    it, which side of the limit is outside ('above' or 'below'), and its unit."""
    limit: str
    fault: str
    side: str
    unit: str
    label: str


# The protections of /bms with a limit attribute (docs/results.md), in page order.
CHANNELS = (
    Channel("cell_overvoltage_V", "cell_overvoltage", "above", "V", "cell over-voltage"),
    Channel("cell_undervoltage_V", "cell_undervoltage", "below", "V", "cell under-voltage"),
    Channel("overtemperature_C", "overtemperature", "above", "°C", "over-temperature"),
    Channel("undertemperature_C", "undertemperature", "below", "°C", "under-temperature"),
    Channel("overcurrent_discharge_A", "overcurrent_discharge", "above", "A", "discharge over-current"),
    Channel("overcurrent_charge_A", "overcurrent_charge", "below", "A", "charge over-current"),
)
_BY_FAULT = {c.fault: c for c in CHANNELS}


def _parallel(r: Result) -> int:
    return max(1, r.n_cells // max(1, r.n_series))


def cell_name(r: Result, cell0: int) -> str:
    """'cell 5', or 'cell 74 (group 19)' in a parallel pack (1-based, as the summary)."""
    p = _parallel(r)
    return f"cell {cell0 + 1}" if p == 1 else f"cell {cell0 + 1} (group {cell0 // p + 1})"


def _thermistor_name(r: Result, k0: int) -> str:
    where = str(r.attrs.get("measured", {}).get("thermistor_groups", "")).split(",")
    at = where[k0].strip() if k0 < len(where) and where[k0].strip() else ""
    if not at:
        return f"thermistor {k0 + 1}"
    return f"thermistor {k0 + 1} (group {at})" if at.isdigit() else f"thermistor {k0 + 1} ({at})"


def _limit_value(r: Result, ch: Channel) -> float | None:
    v = r.attrs.get("bms", {}).get(f"limit_{ch.limit}")
    if v is None:
        return None
    v = float(v)
    return -abs(v) if ch.limit == "overcurrent_charge_A" else v  # charge current is negative


def _truth(r: Result, ch: Channel) -> tuple[np.ndarray, str] | None:
    """[n, k] array of the truth the channel protects, and what its columns are."""
    if ch.unit == "V":
        return r["truth/cell_voltage_V"], "cell"
    if ch.unit == "°C":
        return r["truth/cell_temp_C"], "cell"
    return r["truth/pack_current_A"][:, None], "pack"


def _measured(r: Result, ch: Channel) -> tuple[np.ndarray, str] | None:
    """[n, k] float array of what the BMS read for the channel (NaN: no valid reading)."""
    if ch.unit == "V" and "measured/cell_voltage_mV" in r:
        return r["measured/cell_voltage_mV"].astype(float) / 1000.0, "group"
    if ch.unit == "°C" and "measured/temperature_dC" in r and r["measured/temperature_dC"].size:
        d = r["measured/temperature_dC"].astype(float)
        d[d == INVALID_DC] = np.nan
        return d / 10.0, "thermistor"
    if ch.unit == "A" and "measured/current_mA" in r:
        return r["measured/current_mA"].astype(float)[:, None] / 1000.0, "pack"
    return None


def _column_name(r: Result, kind: str, j: int) -> str:
    if kind == "cell":
        return cell_name(r, j)
    if kind == "group":
        return f"group {j + 1}"
    if kind == "thermistor":
        return _thermistor_name(r, j)
    return "pack"


@dataclass(frozen=True)
class Approach:
    """The closest a channel came to its limit: the extreme value, its margin (positive:
    inside the limit, negative: past it), when and where."""
    value: float
    margin: float
    time_s: float
    where: str
    past_s: float  # samples past the limit, in s (each sample holds until the next)


def _approach(r: Result, a: np.ndarray, kind: str, side: str, lim: float) -> Approach | None:
    if a.size == 0 or np.all(np.isnan(a)):
        return None
    flat = np.where(np.isnan(a), -np.inf if side == "above" else np.inf, a)
    idx = int(np.argmax(flat)) if side == "above" else int(np.argmin(flat))
    i, j = divmod(idx, a.shape[1])
    v = float(a[i, j])
    margin = lim - v if side == "above" else v - lim
    t = r.time_s
    with np.errstate(invalid="ignore"):
        past = np.any(a > lim if side == "above" else a < lim, axis=1)
    dt = np.diff(t, append=t[-1] + (t[-1] - t[-2] if t.size > 1 else 0.0))
    return Approach(v, margin, float(t[i]), _column_name(r, kind, j), float(np.sum(dt[past])))


@dataclass(frozen=True)
class Margin:
    """One protection limit: where it was and how close truth and measurement came."""
    channel: Channel
    limit: float
    truth: Approach | None
    measured: Approach | None
    tripped_s: float | None  # first time this protection's fault latched, None if never


def margins(r: Result) -> list[Margin]:
    """The closest approach to every protection limit the BMS had (one row per /bms
    limit attribute), in the truth and in what the BMS measured."""
    latched = _first_latched(r)
    out = []
    for ch in CHANNELS:
        lim = _limit_value(r, ch)
        if lim is None:
            continue
        tr = _truth(r, ch)
        me = _measured(r, ch)
        out.append(Margin(ch, lim, _approach(r, tr[0], tr[1], ch.side, lim) if tr else None,
                          _approach(r, me[0], me[1], ch.side, lim) if me else None,
                          latched.get(ch.fault)))
    return out


def _first_latched(r: Result) -> dict[str, float]:
    out: dict[str, float] = {}
    for ev in r.events:
        if ev["kind"] == "fault_latched":
            out.setdefault(str(ev["detail"]).split(":")[0].strip(), ev["time_s"])
    return out


@dataclass
class Verdict:
    """What happened, from the events: the first protection that latched (the trip),
    when, what opened, and the BMS's reading against the truth at that moment."""
    tripped: bool
    headline: str
    trip_time_s: float | None = None
    protection: str | None = None
    lines: list[str] = field(default_factory=list)  # what opened, measured vs truth, unseen limits


def _sample(r: Result, t: float) -> int:
    """Index of the recorded sample at time t (the last one at or before it)."""
    return max(0, min(r.n_samples - 1, int(np.searchsorted(r.time_s, t, side="right")) - 1))


def _reading_at(r: Result, fault: str, i: int) -> str | None:
    ch = _BY_FAULT.get(fault)
    if ch is None:
        return None
    tr, me = _truth(r, ch), _measured(r, ch)
    pick = np.nanmax if ch.side == "above" else np.nanmin
    which = "highest" if ch.side == "above" else "lowest"
    what = {"V": "cell voltage", "°C": "temperature", "A": "pack current"}[ch.unit]
    parts = []
    if me is not None and not np.all(np.isnan(me[0][i])):
        parts.append(f"the BMS measured {which} {what} {pick(me[0][i]):.4g} {ch.unit}")
    truth_v = pick(tr[0][i])
    parts.append(f"the truth was {truth_v:.4g} {ch.unit}")
    lim = _limit_value(r, ch)
    if lim is not None:
        parts.append(f"limit {lim:g} {ch.unit}")
    return "; ".join(parts)


_OPENED = {"relay_contact": "opened", "fuse": "blown", "monitor_fault_line": "asserted"}


_CELL_IN_GROUP = re.compile(r"\bcell (\d+) \(group (\d+)\)")


def _cells_text(cells: list[int], group: str) -> str:
    """'cells 37-40 (group 10)' for a run of numbers, else 'cells 37, 39 (group 10)'."""
    run = cells == list(range(cells[0], cells[0] + len(cells)))
    listed = f"{cells[0]}-{cells[-1]}" if run else ", ".join(str(c) for c in cells)
    return f"cells {listed} (group {group})"


def _merged_unseen(evs) -> dict[int, str]:
    """The limit_unseen events' lines by event index: the cells of one parallel group whose
    events say the same thing at the same time (a group's cells share its voltage) as one
    line at the first of them naming them all; the others are left out."""
    first: dict[tuple[float, str], int] = {}
    cells: dict[int, list[int]] = {}
    lines: dict[int, str] = {}
    for i, ev in enumerate(evs):
        if ev["kind"] != "limit_unseen":
            continue
        d = str(ev["detail"])
        lines[i] = d
        m = _CELL_IN_GROUP.search(d)
        if not m:
            continue
        key = (float(ev["time_s"]), _CELL_IN_GROUP.sub(f"cell # (group {m.group(2)})", d, count=1))
        if key in first:
            cells[first[key]].append(int(m.group(1)))
            del lines[i]
        else:
            first[key] = i
            cells[i] = [int(m.group(1))]
    for i, cs in cells.items():
        if len(cs) > 1:
            m = _CELL_IN_GROUP.search(lines[i])
            lines[i] = lines[i][:m.start()] + _cells_text(sorted(cs), m.group(2)) + lines[i][m.end():]
    return lines


def _contact_stayed_closed(r: Result, t: float) -> str | None:
    """The line for a trip whose relay contact was closed and never opened from then on
    (a welded relay): the summary's TRIP line says so, and a page that listed only what
    opened read as if the trip had isolated the pack. None otherwise."""
    closed = False
    for ev in r.events:
        if ev["kind"] != "relay_contact":
            continue
        if ev["time_s"] < t - 1e-9:
            closed = str(ev["detail"]) == "closed"
        elif str(ev["detail"]) == "opened":
            return None
    if not closed:
        return None
    end = float(r.time_s[-1])
    weld = next((ev for ev in r.events if ev["kind"] == "fault_injected"
                 and str(ev["detail"]).startswith("welded_relay")), None)
    why = f" (welded_relay injected at {weld['time_s']:.2f} s)" if weld is not None else ""
    line = f"the relay contact stayed closed after the trip, to the run's end at {end:.2f} s{why}"
    if "truth/pack_current_A" in r:
        line += f"; the pack current at the end: {float(r['truth/pack_current_A'][-1]):.3g} A"
    return line


def verdict(r: Result) -> Verdict:
    """Tripped or not, from the events: the first fault_latched is the trip (the
    protection and when); the contact, fuse and FAULT-line events say what acted; the
    recorded sample at the trip gives the BMS's reading next to the truth.
    limit_unseen, firmware_fault, fault_not_reached, fault_no_effect, monitor_unread, cell_model_range, false_fault,
    load_limited and load_end events, the BMS switching a charger off,
    and a relay that never closed, are listed whether or not it tripped."""
    evs = r.events
    latched = [ev for ev in evs if ev["kind"] == "fault_latched"]
    lines: list[str] = []
    if latched:
        first = latched[0]
        fault = str(first["detail"]).split(":")[0].strip()
        t = first["time_s"]
        v = Verdict(True, f"TRIPPED at {t:.2f} s: {fault}", t, fault, lines)
        for ev in evs:
            if ev["kind"] == "fault_active" and str(ev["detail"]).startswith(fault) and ev["time_s"] <= t:
                lines.append(f"the BMS's reason: {ev['detail']}")
        i = _sample(r, t)
        reading = _reading_at(r, fault, i)
        if reading:
            # Samples are output.interval_s apart: the one before the trip may predate
            # what tripped it (a fault injected since), so its time is said.
            ts = float(r.time_s[i])
            when = ("at the trip" if abs(ts - t) < 1e-6 else
                    f"at the last recorded sample before the trip ({ts:.2f} s, {t - ts:.2f} s earlier)")
            lines.append(f"{when} {reading}")
        for ev in latched[1:]:
            lines.append(f"then latched at {ev['time_s']:.2f} s: {ev['detail']}")
        stayed = _contact_stayed_closed(r, t)
        if stayed:
            lines.append(stayed)
    else:
        v = Verdict(False, "NO TRIP: no protection latched", None, None, lines)
    unseen = _merged_unseen(evs)
    for i, ev in enumerate(evs):
        k = ev["kind"]
        if k in _OPENED and _OPENED[k] in str(ev["detail"]):
            lines.append(f"{ev['time_s']:.2f} s: {k.replace('_', ' ')} {ev['detail']}")
        elif k == "limit_unseen":  # one line per group of parallel cells saying the same
            if i in unseen:
                lines.append(f"{ev['time_s']:.2f} s: limit unseen: {unseen[i]}")
        elif k in ("firmware_fault", "fault_not_reached", "fault_no_effect", "monitor_unread",
                   "cell_model_range", "load_limited", "load_end", "false_fault"):
            lines.append(f"{ev['time_s']:.2f} s: {k.replace('_', ' ')}: {ev['detail']}")
        elif k == "charger" and str(ev["detail"]).startswith("disabled by the BMS"):
            # the charge ended by the BMS, with the truth then (the summary's `charge` line)
            lines.append(f"{ev['time_s']:.2f} s: charger {ev['detail']}")
        elif k == "fault_injected" and (str(ev["detail"]) == "host_dead"
                                        or str(ev["detail"]).startswith("host_dead (when ")):
            # the pack host hung: nothing decided from then on (the summary's BMS line)
            lines.append(f"{ev['time_s']:.2f} s: the pack host's MCU hung (host_dead): "
                         "no BMS decision after it while it lasted")
    s = r.summary
    if "relay_closed" in s and not int(s["relay_closed"]):  # the summary's `relay` line
        lines.append(f"the relay never closed in the run: {float(s.get('charge_delivered_Ah', 0.0)):.3f} Ah delivered")
    return v


# (summary key, label, what it counts)
_ENERGY = (
    ("energy_start_Wh", "in the cells at the start", "Σ over cells of capacity × ∫ OCV dSOC from SOC 0"),
    ("energy_delivered_Wh", "delivered at the terminals, net", "∫ pack voltage × pack current dt (out less in)"),
    ("energy_in_Wh", "back in at the terminals",
     "regeneration and charging: the ticks whose pack current flowed in, their ∫ V·I dt"),
    ("heat_Wh", "heat in the cells", "Joule heat dissipated inside the cells"),
    ("energy_left_Wh", "left in the cells", "Σ over cells of capacity × ∫ OCV dSOC from SOC 0, when the first "
                                            "cell reached its limit (or at the end)"),
    ("energy_stranded_Wh", "stranded by imbalance",
     "of that, what the other cells held above the level of the cell that stopped the pack"),
)


def energy(r: Result) -> list[tuple[str, float, str]]:
    """The energy account of the run from its summary: (label, Wh, what it counts) for
    each energy the summary holds."""
    s = r.summary
    return [(label, float(s[key]), what) for key, label, what in _ENERGY if key in s]
