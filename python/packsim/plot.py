"""Figures of a packsim result (matplotlib; no pyplot state, so safe in scripts,
threads and notebooks alike).

    from packsim import plot
    plot.cells(r, "voltage")        # lines for <= 24 cells, a heatmap above
    plot.current_soc(r)
    plot.bms_timeline(r)            # state, commanded vs hardware actuators, faults, events
    plot.measured_vs_truth(r)       # what the BMS read vs the simulated truth, SOC estimate
    plot.balancing(r)               # None when the result has no balance mask
    plot.vehicle(r)                 # a vehicle run over distance (None without load.vehicle)
    plot.balance_time(packsim.balance_time(resistor=[22, 33, 47]))   # time to balance vs R
    plot.plot_all(r, "figures/")    # all of them as PNG; what `packsim plot` writes
    plot.run_figure(r)              # interactive (Plotly): the figure of `packsim report`'s run page

Every function takes a Result (or a path to a result file) and returns a
matplotlib Figure. Every time plot marks the run's fault injections and trips
(python/packsim/_plot_marks.py); voltage, temperature and current plots draw the BMS's
protection limits. ``python -m packsim.plot RESULT.h5 -o DIR`` writes the PNGs.
"""
from __future__ import annotations

import argparse
import math
import os
import sys
from typing import Any

import numpy as np

from ._plot_marks import draw_limits, mark_events
from .result import NotAResultError, Result, load

__all__ = ["cells", "current_soc", "bms_timeline", "measured_vs_truth", "balancing", "vehicle", "balance_time", "plot_all",
           "main", "LINE_LIMIT", "timeline_rows", "run_figure"]

LINE_LIMIT = 24  # more cells than this: a heatmap instead of one line per cell

_QUANTITIES = {
    "voltage": ("truth/cell_voltage_V", "cell voltage (V)"),
    "temperature": ("truth/cell_temp_C", "cell temperature (°C)"),
    "soc": ("truth/cell_soc", "cell SOC (-)"),
    "current": ("truth/cell_current_A", "cell current (A)"),
}
# Protection limits drawn on each quantity's plot: (limit name, label, sign).
_LIMITS = {
    "voltage": [("cell_overvoltage_V", "over-voltage", 1.0), ("cell_undervoltage_V", "under-voltage", 1.0)],
    "temperature": [("overtemperature_C", "over-temperature", 1.0)],
}


def _figure(width: float = 10.0, height: float = 5.0):
    try:
        from matplotlib.figure import Figure
    except ImportError as e:
        raise ImportError("packsim.plot needs matplotlib (pip install matplotlib)") from e
    return Figure(figsize=(width, height), layout="constrained")


def _result(r: Result | str | os.PathLike) -> Result:
    if isinstance(r, Result):
        return r
    if isinstance(r, (str, os.PathLike)):
        return load(r)
    raise TypeError(f"expected a packsim.Result or a result file path, got {type(r).__name__}")


def _time(r: Result) -> tuple[np.ndarray, str, float]:
    """Time axis in s, min or h, whichever reads best; (values, label, scale)."""
    t = r.time_s
    span = float(t[-1] - t[0]) if t.size else 0.0
    if span > 3 * 3600:
        return t / 3600.0, "time (h)", 3600.0
    if span > 30 * 60:
        return t / 60.0, "time (min)", 60.0
    return t, "time (s)", 1.0


def _title(r: Result, what: str) -> str:
    return f"{r.scenario_name} (seed {r.seed}): {what}"


def _intervals(mask: np.ndarray, t: np.ndarray) -> list[tuple[float, float]]:
    """(start, width) of each run of True in mask; a sample holds until the next."""
    if mask.size == 0:
        return []
    edges = np.diff(np.concatenate(([0], mask.astype(np.int8), [0])))
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    dt = float(np.median(np.diff(t))) if t.size > 1 else 1.0
    t_end = np.append(t, t[-1] + dt)
    return [(float(t_end[s]), float(t_end[e] - t_end[s])) for s, e in zip(starts, ends)]


def cells(r: Result | str | os.PathLike, quantity: str = "voltage", *, line_limit: int = LINE_LIMIT):
    """Every cell's voltage / temperature / soc / current over time: one line per cell
    up to `line_limit` cells (min and max cell named), a time x cell heatmap above."""
    r = _result(r)
    if quantity not in _QUANTITIES:
        raise ValueError(f"quantity must be one of {', '.join(_QUANTITIES)}, not {quantity!r}")
    path, label = _QUANTITIES[quantity]
    a = r[path]
    t, tlabel, _ = _time(r)
    n = a.shape[1]
    fig = _figure()
    ax = fig.add_subplot()
    if n <= line_limit:
        marked = _highlighted_cells(r, a)
        for j in range(n):
            if j not in marked:
                ax.plot(t, a[:, j], color="0.65", lw=0.7, label="other cells" if j == min(set(range(n)) - set(marked),
                                                                                          default=-1) else None)
        for k, (j, why) in enumerate(marked.items()):
            ax.plot(t, a[:, j], color=f"C{k}", lw=1.6, label=_marked_label(r, j, why))
        draw_limits(ax, r, [lim for lim in _LIMITS.get(quantity, []) if _near(lim, r, a)])
        ax.legend(fontsize="small", loc="lower left")
        ax.set_ylabel(label)
    else:
        dt = t[1] - t[0] if t.size > 1 else 1.0
        extent = (float(t[0]), float(t[-1] + dt), 0.5, n + 0.5)
        im = ax.imshow(a.T, aspect="auto", origin="lower", extent=extent, interpolation="nearest",
                       cmap="inferno" if quantity == "temperature" else "viridis")
        fig.colorbar(im, ax=ax, label=label)
        ax.set_ylabel("cell")
        for j, why in _highlighted_cells(r, a).items():
            ax.annotate(_marked_label(r, j, why), (1.0, j + 1), xycoords=("axes fraction", "data"), xytext=(-4, 0),
                        textcoords="offset points", ha="right", va="center", fontsize=7, color="w")
    ax.set_xlabel(tlabel)
    ax.set_title(_title(r, f"{quantity} of {n} cells"))
    if n <= line_limit:
        ax.grid(alpha=0.3)
    mark_events(ax, r, _time(r)[2])
    return fig


def _marked_label(r: Result, j: int, why: str) -> str:
    """'cell 5 (min)', or in a parallel pack 'cell 21 (group 11, min)': the cell named as
    the summary and the events name it (run_facts.cell_name)."""
    from .run_facts import cell_name
    name = cell_name(r, j)
    return f"{name[:-1]}, {why})" if name.endswith(")") else f"{name} ({why})"


def _near(lim: tuple[str, str, float], r: Result, a: np.ndarray) -> bool:
    """A limit worth drawing: within the data's range widened by its own span (a
    far-away limit would only squash the curves)."""
    from ._plot_marks import limit
    v = limit(r, lim[0])
    if v is None or a.size == 0:
        return False
    lo, hi = float(np.nanmin(a)), float(np.nanmax(a))
    pad = max(hi - lo, 0.05 * max(abs(lo), abs(hi), 1.0))
    return lo - pad <= lim[2] * v <= hi + pad


def _faulted_cells(r: Result) -> set[int]:
    """0-based cells a fault injection names ("hot_cell cell 5, 25 W")."""
    import re
    out = set()
    for ev in r.events:
        if ev["kind"] == "fault_injected":
            out |= {int(m) - 1 for m in re.findall(r"\bcell (\d+)", str(ev["detail"]))}
    return out


def _highlighted_cells(r: Result, a: np.ndarray) -> dict[int, str]:
    """{cell index: why} for the cell reaching the lowest value, the one reaching the
    highest, and every cell a fault injection names."""
    if a.size == 0:
        return {}
    marked: dict[int, str] = {}
    for j in sorted(_faulted_cells(r)):
        if 0 <= j < a.shape[1]:
            marked[j] = "fault injected"
    lo, hi = int(np.argmin(np.nanmin(a, axis=0))), int(np.argmax(np.nanmax(a, axis=0)))
    marked[lo] = marked[lo] + ", min" if lo in marked else "min"
    if hi != lo:
        marked[hi] = marked[hi] + ", max" if hi in marked else "max"
    return marked


def _finish_soc_axis(ax, r: Result, t: np.ndarray, tlabel: str) -> None:
    """The BMS's SOC estimate (when recorded) over the truth already drawn on `ax`, then
    the axis labels and legend every SOC panel has."""
    if "bms/soc_estimate_permille" in r:
        ax.step(t, r["bms/soc_estimate_permille"] / 1000.0, where="post", color="C1", lw=1.0,
                label="BMS estimate")
    ax.set_ylabel("SOC (-)")
    ax.set_xlabel(tlabel)
    ax.legend(fontsize="small", loc="best")


def current_soc(r: Result | str | os.PathLike):
    """Pack current (truth and what the BMS measured) and voltage above; cell SOC
    (min..max band and mean) below."""
    r = _result(r)
    t, tlabel, _ = _time(r)
    fig = _figure(10, 6.5)
    ax_i, ax_s = fig.subplots(2, 1, sharex=True)
    ax_i.plot(t, r["truth/pack_current_A"], lw=1.0, color="C0", label="pack current (truth)")
    if "measured/current_mA" in r:
        ax_i.plot(t, r["measured/current_mA"] / 1000.0, lw=0.6, color="C1", alpha=0.7, label="measured by the BMS")
    ax_i.set_ylabel("current (A, + discharges)")
    ax_i.grid(alpha=0.3)
    ax_v = ax_i.twinx()
    ax_v.plot(t, r["truth/pack_voltage_V"], lw=1.0, color="C3", label="pack voltage")
    ax_v.set_ylabel("pack voltage (V)", color="C3")
    draw_limits(ax_i, r, [lim for lim in [("overcurrent_discharge_A", "over-current", 1.0),
                                          ("overcurrent_charge_A", "charge over-current", -1.0)]
                          if _near(lim, r, r["truth/pack_current_A"])])
    lines = ax_i.get_legend_handles_labels()
    more = ax_v.get_legend_handles_labels()
    ax_i.legend(lines[0] + more[0], lines[1] + more[1], fontsize="small", loc="best")
    ax_i.set_title(_title(r, "current, voltage and state of charge"))

    soc = r["truth/cell_soc"]
    ax_s.fill_between(t, soc.min(axis=1), soc.max(axis=1), color="C2", alpha=0.3, label="min..max cell")
    ax_s.plot(t, soc.mean(axis=1), color="C2", lw=1.2, label="mean cell")
    _finish_soc_axis(ax_s, r, t, tlabel)
    ax_s.grid(alpha=0.3)
    mark_events(ax_s, r, _time(r)[2], labels=False)
    mark_events(ax_i, r, _time(r)[2])
    return fig


def _state_names(r: Result) -> dict[int, str]:
    names = r.attrs.get("bms/state", {}).get("names", "")
    out = {}
    for item in str(names).split(","):
        if "=" in item:
            k, v = item.split("=", 1)
            try:
                out[int(k)] = v.strip()
            except ValueError:
                pass
    return out


def _is_flag(r: Result, a: np.ndarray) -> bool:
    return a.ndim == 1 and a.shape[0] == r.n_samples and a.dtype.kind in "biu" and a.size > 0 \
        and a.max() <= 1 and a.min() >= 0


def timeline_rows(r: Result) -> list[tuple[str, np.ndarray, str]]:
    """The on/off rows of the BMS timeline, top to bottom: (label, mask, source) with
    source "commanded" (what the firmware asked for, bms/) or "hardware" (what the
    relay, FETs, fuse and FAULT line did, hardware/). Each actuator's command sits
    right above its hardware state, so a relay that opened without the firmware (a
    hung MCU, a FAULT line) or stayed closed though commanded open (a weld) shows."""
    rows: list[tuple[str, np.ndarray, str]] = []
    hw = r.group("hardware")
    done = set()
    for name, a in r.bms.items():
        if name == "state" or name.startswith("fault") or "balanc" in name or not _is_flag(r, a) \
                or "names" in r.attrs.get(f"bms/{name}", {}):  # an enum that happens to stay 0 or 1
            continue
        if name not in hw or not _is_flag(r, hw[name]):  # a flag the firmware sets (monitor_fault, ...)
            rows.append((f"{name.replace('_', ' ')} (firmware)", a.astype(bool), "commanded"))
            continue
        thing = name.removesuffix("_closed").removesuffix("_on").replace("_", " ")
        rows.append((f"{thing}: commanded", a.astype(bool), "commanded"))
        rows.append((f"{thing}: {'contact' if name.endswith('_closed') else 'conducting'} (hardware)",
                     hw[name].astype(bool), "hardware"))
        done.add(name)
    for name, a in hw.items():
        if name not in done and "balanc" not in name and _is_flag(r, a):
            rows.append((f"{name.replace('_', ' ')} (hardware)", a.astype(bool), "hardware"))
    return rows


def bms_timeline(r: Result | str | os.PathLike):
    """What the BMS did: its state, each relay/FET command next to what the hardware
    did (timeline_rows), each fault that was ever active (dark) or latched (light),
    and the injections and trips as vertical lines."""
    r = _result(r)
    t, tlabel, scale = _time(r)
    actuators = timeline_rows(r)
    faults: list[tuple[str, np.ndarray, np.ndarray]] = []
    if "bms/fault_active" in r and r.fault_names:
        act, lat = r.faults("active"), r.faults("latched")
        for name in r.fault_names:
            if act[name].any() or lat[name].any():
                faults.append((name, act[name], lat[name]))
    n_rows = len(actuators) + len(faults)
    fig = _figure(10, 2.6 + 0.32 * max(n_rows, 3))
    ax_state, ax_bars = fig.subplots(2, 1, sharex=True, height_ratios=[1.0, max(1.2, 0.32 * max(n_rows, 3))])

    state = r["bms/state"].astype(int)
    names = _state_names(r)
    ax_state.step(t, state, where="post", color="C0", lw=1.5)
    ticks = sorted(set(names) | set(np.unique(state).tolist()))
    ax_state.set_yticks(ticks, [names.get(k, str(k)) for k in ticks])
    ax_state.set_ylim(min(ticks) - 0.5, max(ticks) + 0.5)
    ax_state.set_ylabel("BMS state")
    ax_state.grid(alpha=0.3)
    ax_state.set_title(_title(r, "BMS timeline"))

    labels = []
    y = 0
    for label, on, source in actuators:
        ax_bars.broken_barh(_intervals(on, t), (y - 0.35, 0.7), color="C2" if source == "commanded" else "C0",
                            label=label)
        labels.append(label)
        y += 1
    for name, act, lat in faults:
        ax_bars.broken_barh(_intervals(lat, t), (y - 0.35, 0.7), color="C3", alpha=0.3)
        ax_bars.broken_barh(_intervals(act, t), (y - 0.35, 0.7), color="C3")
        labels.append(f"fault: {name}")
        y += 1
    ax_bars.set_yticks(range(len(labels)), labels)
    ax_bars.set_ylim(-0.6, max(len(labels), 1) - 0.4)
    ax_bars.invert_yaxis()
    ax_bars.set_xlabel(tlabel)
    ax_bars.grid(axis="x", alpha=0.3)
    if not labels:
        ax_bars.text(0.5, 0.5, "no commands or faults recorded", transform=ax_bars.transAxes, ha="center")

    mark_events(ax_state, r, scale)
    mark_events(ax_bars, r, scale, labels=False)
    return fig


def measured_vs_truth(r: Result | str | os.PathLike):
    """What the BMS read next to the simulated truth: the lowest and highest cell voltage
    (monitor ICs vs truth), the hottest temperature (thermistors vs cells), and the
    pack SOC (the firmware's estimate vs the mean cell SOC)."""
    r = _result(r)
    t, tlabel, scale = _time(r)
    fig = _figure(10, 8)
    ax_v, ax_t, ax_s = fig.subplots(3, 1, sharex=True)
    v = r["truth/cell_voltage_V"]
    ax_v.plot(t, v.min(axis=1), color="C0", lw=1.2, label="truth min cell")
    ax_v.plot(t, v.max(axis=1), color="C3", lw=1.2, label="truth max cell")
    if "measured/cell_voltage_mV" in r:
        m = r["measured/cell_voltage_mV"] / 1000.0
        ax_v.plot(t, m.min(axis=1), color="C0", lw=0.8, ls="--", label="measured min")
        ax_v.plot(t, m.max(axis=1), color="C3", lw=0.8, ls="--", label="measured max")
    draw_limits(ax_v, r, [lim for lim in _LIMITS["voltage"] if _near(lim, r, v)])
    ax_v.set_ylabel("cell voltage (V)")
    ax_v.legend(fontsize="small", loc="lower left")
    ax_v.set_title(_title(r, "measured vs truth"))
    temp = r["truth/cell_temp_C"]
    ax_t.plot(t, temp.max(axis=1), color="C3", lw=1.2, label="truth hottest cell")
    if "measured/temperature_dC" in r and r["measured/temperature_dC"].size:
        d = r["measured/temperature_dC"].astype(float)
        d[d == -32768] = np.nan  # open or shorted sensor
        with np.errstate(all="ignore"):
            hottest = np.nanmax(d, axis=1) / 10.0 if not np.all(np.isnan(d)) else np.full(len(t), np.nan)
        ax_t.plot(t, hottest, color="C3", lw=0.8, ls="--", label="measured hottest thermistor")
    draw_limits(ax_t, r, [lim for lim in _LIMITS["temperature"] if _near(lim, r, temp)])
    ax_t.set_ylabel("temperature (°C)")
    ax_t.legend(fontsize="small", loc="upper left")
    ax_s.plot(t, r["truth/cell_soc"].mean(axis=1), color="C2", lw=1.2, label="truth (mean cell)")
    _finish_soc_axis(ax_s, r, t, tlabel)
    for ax in (ax_v, ax_t, ax_s):
        ax.grid(alpha=0.3)
        mark_events(ax, r, scale, labels=ax is ax_v)
    return fig


def _balance_mask(r: Result) -> tuple[str, np.ndarray] | None:
    """[samples, series] bool from the first bms/ dataset named like a balance mask:
    a bit mask per sample (bit i = series cell i+1) or one column per cell."""
    for name, a in r.bms.items():
        if "balanc" not in name or "mask" not in name and a.ndim != 2:
            continue
        if a.ndim == 2 and a.shape[0] == r.n_samples:
            return name, a.astype(bool)
        if a.ndim == 1 and a.shape[0] == r.n_samples and a.dtype.kind in "iu":
            n = r.n_series
            bits = a.astype(np.uint64)[:, None] >> np.arange(n, dtype=np.uint64)[None, :]
            return name, (bits & np.uint64(1)).astype(bool)
    return None


def balancing(r: Result | str | os.PathLike):
    """Which cells balanced when (a time x cell map) and each cell's share of time
    balancing. None when the result has no balance mask dataset."""
    r = _result(r)
    found = _balance_mask(r)
    if found is None:
        return None
    name, mask = found
    t, tlabel, _ = _time(r)
    n = mask.shape[1]
    fig = _figure(10, 5)
    ax, ax_duty = fig.subplots(1, 2, sharey=True, width_ratios=[4, 1])
    dt = t[1] - t[0] if t.size > 1 else 1.0
    ax.imshow(mask.T, aspect="auto", origin="lower", interpolation="nearest", cmap="Greys", vmin=0, vmax=1,
              extent=(float(t[0]), float(t[-1] + dt), 0.5, n + 0.5))
    ax.set_xlabel(tlabel)
    ax.set_ylabel("cell (series position)")
    ax.set_title(_title(r, f"balancing ({name})"))
    duty = mask.mean(axis=0) * 100.0
    ax_duty.barh(np.arange(1, n + 1), duty, color="C1")
    ax_duty.set_xlabel("time balancing (%)")
    ax_duty.grid(axis="x", alpha=0.3)
    mark_events(ax, r, _time(r)[2])
    return fig


def balance_time_figure(cols, *, title: str = "", board_max_C: float = math.nan):
    """Time to balance (left) and peak board temperature (right) against the resistor from
    the columns of a balance-time table (resistor_ohm, const_I_to_target_h,
    droop_to_target_h, firmware_h, true_h, board_steady_C, peak_board_C, paused_fraction,
    fastest). The analytic lines and true_h share one end criterion: the rest voltages
    within the target. The fastest resistor within
    limits is ringed; the paused percentage labels resistors the board pause slowed."""
    order = np.argsort(np.asarray(cols["resistor_ohm"], dtype=float))
    keys = ("resistor_ohm", "const_I_to_target_h", "droop_to_target_h", "firmware_h", "true_h", "board_steady_C",
            "peak_board_C", "paused_fraction", "fastest")
    col = {k: np.asarray(cols[k], dtype=float)[order] for k in keys}
    r_ohm = col["resistor_ohm"]
    fig = _figure(11, 4.5)
    ax, temp = fig.subplots(1, 2)
    ax.plot(r_ohm, col["const_I_to_target_h"], "o--", color="C0", label="analytic, constant current, to the target")
    ax.plot(r_ohm, col["droop_to_target_h"], "o:", color="C2", label="analytic with OCV droop, to the target")
    if np.any(np.isfinite(col["true_h"])) or np.any(np.isfinite(col["firmware_h"])):
        ax.plot(r_ohm, col["true_h"], "s-", color="C3", label="simulated: true rest voltages within target")
        ax.plot(r_ohm, col["firmware_h"], "^-", color="C1", label="simulated: firmware declared balanced")
        for x, y, p in zip(r_ohm, col["true_h"], col["paused_fraction"]):
            if np.isfinite(y) and p > 0.005:
                ax.annotate(f"{100 * p:.0f} % paused", (x, y), textcoords="offset points", xytext=(4, 6),
                            fontsize=8, color="C3")
        best = col["fastest"] > 0.5
        if np.any(best):
            ax.plot(r_ohm[best], col["true_h"][best], "o", ms=14, mfc="none", color="k",
                    label="fastest within limits")
    ax.set_xlabel("balancing resistor (Ω)")
    ax.set_ylabel("time to balance (h)")
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    if np.any(np.isfinite(col["board_steady_C"])):
        temp.plot(r_ohm, col["board_steady_C"], "o--", color="C0", label="steady state T_amb + P/G (analytic)")
    if np.any(np.isfinite(col["peak_board_C"])):
        temp.plot(r_ohm, col["peak_board_C"], "s-", color="C4", label="peak board temperature (simulated)")
    if math.isfinite(board_max_C):
        temp.axhline(board_max_C, color="0.5", ls="--", label=f"board pause {board_max_C:.0f} °C")
    temp.set_xlabel("balancing resistor (Ω)")
    temp.set_ylabel("board temperature (°C)")
    temp.grid(alpha=0.3)
    temp.legend(fontsize=8)
    if title:
        fig.suptitle(title)
    return fig


def balance_time(bt):
    """Time to balance and peak board temperature vs balancing resistor from
    ``packsim.balance_time`` (the figure ``packsim balance-time --plot`` writes)."""
    from .balance import BalanceTimeResult
    if not isinstance(bt, BalanceTimeResult):
        raise TypeError(f"expected the result of packsim.balance_time, got {type(bt).__name__}")
    if not bt.rows:
        raise ValueError("the balance-time result has no rows")
    s = "" if bt.high_cells == 1 else "s"
    return balance_time_figure(bt.columns, board_max_C=bt.board_max_C,
                               title=f"{bt.scenario}: {bt.delta_Ah:.3f} Ah to remove on {bt.high_cells} cell{s}")


def vehicle(r: Result | str | os.PathLike):
    """A vehicle run (load.vehicle) over the distance it drove: speed, pack power, cell
    SOC and the lowest cell voltage against km, the first pack limit marked
    (packsim.vehicle_figure). None for a run without a vehicle."""
    from .vehicle_figure import PANELS, distance_series, has_vehicle
    r = _result(r)
    if not has_vehicle(r):
        return None
    d = distance_series(r)
    fig = _figure(10, 9)
    axes = fig.subplots(4, 1, sharex=True)
    axes[0].plot(d.km, d.speed_kmh, color="C0", lw=1.0)
    axes[1].plot(d.km, d.pack_W, color="C3", lw=1.0, label="delivered (pack V × I)")
    axes[1].plot(d.km, d.request_W, color="C1", lw=0.8, ls=":", label="asked by the vehicle")
    axes[1].legend(fontsize="small", loc="best")
    axes[2].fill_between(d.km, d.soc_min, d.soc_max, color="C2", alpha=0.3, label="min..max cell")
    axes[2].plot(d.km, d.soc_mean, color="C2", lw=1.2, label="mean cell")
    axes[2].legend(fontsize="small", loc="best")
    axes[3].plot(d.km, d.min_cell_V, color="C0", lw=1.0)
    if d.undervoltage_V is not None:
        axes[3].axhline(d.undervoltage_V, color="C3", ls=":", lw=1.0, label=f"under-voltage limit {d.undervoltage_V:g} V")
        axes[3].legend(fontsize="small", loc="best")
    for ax, label in zip(axes, PANELS):
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
        if d.limit_km is not None:
            ax.axvline(d.limit_km, color="C3", ls="--", lw=0.8)
    if d.limit_km is not None:
        axes[0].annotate(f"first pack limit, km {d.limit_km:.3f}", (d.limit_km, 1.0), xycoords=("data", "axes fraction"),
                         fontsize="small", color="C3", va="top")
    axes[3].set_xlabel("distance (km)")
    axes[0].set_title(_title(r, "over distance"))
    return fig


def plot_all(r: Result | str | os.PathLike, outdir: str | os.PathLike = ".", *, dpi: int = 120) -> list[str]:
    """Every figure of the result as PNG in outdir; returns the written paths."""
    from . import _int_arg, _path_arg
    r = _result(r)
    outdir = _path_arg("outdir", outdir)
    if outdir is None:
        raise TypeError("outdir must be a path, got NoneType")
    _int_arg("dpi", dpi, 1)
    os.makedirs(outdir, exist_ok=True)
    figures: list[tuple[str, Any]] = [
        ("cell_voltages", cells(r, "voltage")),
        ("cell_temperatures", cells(r, "temperature")),
        ("current_soc", current_soc(r)),
        ("bms_timeline", bms_timeline(r)),
        ("measured_vs_truth", measured_vs_truth(r)),
        ("balancing", balancing(r)),
        ("vehicle_distance", vehicle(r)),
    ]
    written = []
    for name, fig in figures:
        if fig is None:
            continue
        path = os.path.join(os.fspath(outdir), f"{r.scenario_name or 'result'}_{name}.png")
        fig.savefig(path, dpi=dpi)
        written.append(path)
    return written


def run_figure(r: Result | str | os.PathLike, **kw):
    """The interactive figure of the run page (Plotly; shows itself in Jupyter):
    packsim.run_figure.run_figure."""
    from .run_figure import run_figure as make
    return make(r, **kw)


def _matplotlib_or_error(prog: str) -> bool:
    """Whether matplotlib can be imported; if not, says so on stderr as `prog` (the CLI
    then exits 1)."""
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        print(f"{prog}: error: matplotlib is not installed (pip install matplotlib)", file=sys.stderr)
        return False
    return True


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="packsim plot", description="Write the figures of a packsim result as PNG.")
    p.add_argument("result", help="result HDF5 file")
    p.add_argument("-o", "--output", default=".", help="folder for the PNG files (default: .)")
    p.add_argument("--dpi", type=int, default=120, help="resolution (default: 120)")
    a = p.parse_args(argv)
    if not _matplotlib_or_error("packsim plot"):
        return 1
    if not os.path.isfile(a.result):
        print(f"packsim plot: error: {a.result}: no such result file", file=sys.stderr)
        return 2
    try:
        r = load(a.result)
    except NotAResultError as e:
        print(f"packsim plot: error: {e}", file=sys.stderr)
        return 2
    for path in plot_all(r, a.output, dpi=a.dpi):
        print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
