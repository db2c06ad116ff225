"""The interactive figure of one run (Plotly): every panel on one time axis, so zoom
and the time cursor are shared; legend entries toggle traces, limits and event marks.

    from packsim import plot
    fig = plot.run_figure(r)    # a plotly Figure: shows itself in Jupyter, fig.write_html(...)

Panels, top to bottom: per-group SOC and voltage deviation from the pack mean
(heat-maps: imbalance without the load pulses every cell shares), cell voltage, the
temperatures and the pack current as the BMS measured them next to the truth, with
their protection limits, the SOC, the BMS state, and the actuator commands next to what
the hardware did, with every fault that was active. Event marks (injections, latched
faults, contacts opening) cross every panel.

Large runs stay light: each trace is decimated for display (the min and max of each of
about DISPLAY_POINTS time buckets, so a spike is never lost; heat-maps keep the largest
deviation of each bucket). The numbers of the page (run_facts) use every sample.
"""
from __future__ import annotations

import warnings

import numpy as np

from ._plot_marks import marked_events
from .result import Result
from .run_facts import CHANNELS, INVALID_DC, _limit_value

__all__ = ["run_figure", "DISPLAY_POINTS", "display_indices", "group_deviation"]

DISPLAY_POINTS = 1500  # time buckets per trace for display

# matplotlib's default cycle, so the PNG figures and these share colours
COLOURS = {"C0": "#1f77b4", "C1": "#ff7f0e", "C2": "#2ca02c", "C3": "#d62728", "C4": "#9467bd",
           "C5": "#8c564b", "k": "#000000"}
_MARK_COLOURS = {"fault_injected": "C4", "fault_latched": "C3", "relay_contact": "k", "fuse": "C1",
                 "monitor_fault_line": "C5"}


def display_indices(y: np.ndarray, points: int = DISPLAY_POINTS) -> np.ndarray:
    """Sample indices to draw y [n] or [n, k] with about 2 × points samples: the first and
    last sample and, in each of `points` equal buckets, the samples holding each column's
    minimum and maximum. All indices when n is small already."""
    n = y.shape[0]
    if n <= 2 * points:
        return np.arange(n)
    y2 = y.reshape(n, -1)
    edges = np.linspace(0, n, points + 1).astype(int)
    keep = [np.array([0, n - 1])]
    for a, b in zip(edges[:-1], edges[1:]):
        if b <= a:
            continue
        seg = np.nan_to_num(y2[a:b], nan=0.0)
        keep.append(a + np.argmin(seg, axis=0))
        keep.append(a + np.argmax(seg, axis=0))
    return np.unique(np.concatenate(keep))


def _bucket_extreme(t: np.ndarray, a: np.ndarray, points: int) -> tuple[np.ndarray, np.ndarray]:
    """Heat-map columns: for each of `points` time buckets, each row's value of largest
    magnitude in it (a [n, k] array -> ([buckets], [k, buckets]))."""
    n = a.shape[0]
    if n <= points:
        return t, a.T
    edges = np.linspace(0, n, points + 1).astype(int)
    cols, times = [], []
    for s, e in zip(edges[:-1], edges[1:]):
        seg = a[s:e]
        pick = np.argmax(np.abs(seg), axis=0)
        cols.append(seg[pick, np.arange(a.shape[1])])
        times.append(t[s])
    return np.asarray(times), np.asarray(cols).T


def group_deviation(r: Result, path: str) -> np.ndarray:
    """[n, series] deviation of each series group from the pack mean of a truth per-cell
    dataset (the group's value: the mean of its parallel cells)."""
    a = r[path]
    s = r.n_series
    p = max(1, a.shape[1] // s)
    g = a[:, : s * p].reshape(a.shape[0], s, p).mean(axis=2)
    return g - g.mean(axis=1, keepdims=True)


def _time_unit(r: Result) -> tuple[float, str]:
    t = r.time_s
    span = float(t[-1] - t[0]) if t.size else 0.0
    if span > 3 * 3600:
        return 3600.0, "h"
    if span > 30 * 60:
        return 60.0, "min"
    return 1.0, "s"


class _Panels:
    """Stacked panels on one shared x axis ('x'), each with its own y axis and legend."""

    def __init__(self, r: Result, scale: float, points: int) -> None:
        self.r, self.scale, self.points = r, scale, points
        self.t = r.time_s / scale
        self.traces: list[dict] = []
        self.panels: list[tuple[str, float, dict]] = []  # (title, relative height, yaxis extras)

    def add_panel(self, heading: str, height: float = 1.0, **yaxis) -> str:
        self.panels.append((heading, height, yaxis))
        k = len(self.panels)
        return "y" if k == 1 else f"y{k}"

    def line(self, y_axis: str, y: np.ndarray, name: str, colour: str, *, dash: str | None = None,
             width: float = 1.2, shape: str = "linear", group: str | None = None) -> None:
        idx = display_indices(y, self.points)
        if np.all(np.isnan(y[idx])):
            return
        self.traces.append(dict(type="scatter", mode="lines", x=self.t[idx], y=y[idx], name=name, yaxis=y_axis,
                                xaxis="x", legend=self._legend(y_axis), legendgroup=group or name,
                                line=dict(color=COLOURS.get(colour, colour), width=width, dash=dash, shape=shape),
                                hovertemplate="%{y:.5g}<extra>" + name + "</extra>"))

    def limit(self, y_axis: str, value: float, name: str) -> None:
        self.traces.append(dict(type="scatter", mode="lines", x=[self.t[0], self.t[-1]], y=[value, value],
                                name=f"{name} limit {value:g}", yaxis=y_axis, xaxis="x",
                                legend=self._legend(y_axis), line=dict(color=COLOURS["C3"], width=1, dash="dot"),
                                hovertemplate=f"{name} limit {value:g}<extra></extra>"))

    def event_points(self, y_axis: str, y: float) -> None:
        """A diamond per marked event at height y of a panel, its text on hover; in the
        legend group of its kind's lines, so one click hides both."""
        by_kind: dict[str, list[dict]] = {}
        for ev in marked_events(self.r):
            by_kind.setdefault(ev["kind"], []).append(ev)
        for kind, evs in by_kind.items():
            self.traces.append(dict(type="scatter", mode="markers", x=[e["time_s"] / self.scale for e in evs],
                                    y=[y] * len(evs), yaxis=y_axis, xaxis="x", legendgroup=f"event {kind}",
                                    showlegend=False, name=kind.replace("_", " "),
                                    marker=dict(symbol="diamond", size=8, color=COLOURS[_MARK_COLOURS[kind]]),
                                    text=[f"{e['time_s']:.2f} s {kind}: {e['detail']}" for e in evs],
                                    hovertemplate="%{text}<extra></extra>"))

    def heatmap(self, y_axis: str, a: np.ndarray, name: str, unit: str) -> None:
        tb, z = _bucket_extreme(self.t, a, self.points)
        m = float(np.nanmax(np.abs(z))) if z.size else 1.0
        self.traces.append(dict(type="heatmap", x=tb, y=np.arange(1, z.shape[0] + 1), z=z, xaxis="x", yaxis=y_axis,
                                name=name, colorscale="RdBu", reversescale=True, zmid=0.0, zmin=-m, zmax=m,
                                colorbar=dict(title=dict(text=unit), thickness=12, len=0.1),
                                hovertemplate="group %{y}<br>%{z:.4g} " + unit + "<extra>" + name + "</extra>"))

    def _legend(self, y_axis: str) -> str:
        k = 1 if y_axis == "y" else int(y_axis[1:])
        return "legend" if k == 1 else f"legend{k}"

    def figure(self, title: str):
        import plotly.graph_objects as go
        weights = np.array([h for _, h, _ in self.panels], dtype=float)
        gap = 0.035
        usable = 1.0 - gap * (len(self.panels) - 1)
        heights = usable * weights / weights.sum()
        layout: dict = dict(title=dict(text=title, x=0.01), hovermode="x", hoversubplots="axis",
                            height=int(190 * weights.sum() + 140), margin=dict(l=70, r=260, t=60, b=50),
                            plot_bgcolor="white", uirevision="packsim")
        top = 1.0
        annotations = []
        for k, ((ptitle, _, extra), h) in enumerate(zip(self.panels, heights), start=1):
            name = "yaxis" if k == 1 else f"yaxis{k}"
            dom = [max(0.0, top - h), top]
            layout[name] = dict(domain=dom, anchor="x", gridcolor="#e5e5e5", zeroline=False, **extra)
            layout["legend" if k == 1 else f"legend{k}"] = dict(x=1.08, xanchor="left", y=dom[1], yanchor="top",
                                                                font=dict(size=10), bgcolor="rgba(255,255,255,0)")
            annotations.append(dict(text=f"<b>{ptitle}</b>", x=0, xref="paper", xanchor="left", y=dom[1],
                                    yref="paper", yanchor="bottom", showarrow=False, font=dict(size=11)))
            for tr in self.traces:
                if tr.get("type") == "heatmap" and tr["yaxis"] == ("y" if k == 1 else f"y{k}"):
                    tr["colorbar"].update(y=(dom[0] + dom[1]) / 2, len=dom[1] - dom[0], yanchor="middle", x=1.0)
            top = dom[0] - gap
        unit = {1.0: "s", 60.0: "min", 3600.0: "h"}[self.scale]
        layout["xaxis"] = dict(anchor=f"y{len(self.panels)}" if len(self.panels) > 1 else "y",
                               title=dict(text=f"time ({unit})"), showspikes=True, spikemode="across",
                               spikesnap="cursor", spikethickness=1, spikecolor="#555", gridcolor="#e5e5e5")
        layout["annotations"] = annotations
        layout["shapes"] = self._event_shapes() + [self._cursor()]
        return go.Figure(data=self.traces, layout=layout)

    def _event_shapes(self) -> list[dict]:
        """A dashed line across every panel per marked event; one legend entry per kind
        (clicking it hides or shows every mark of that kind)."""
        shapes, seen = [], set()
        for ev in sorted(marked_events(self.r), key=lambda e: e["time_s"]):
            kind = ev["kind"]
            x = ev["time_s"] / self.scale
            shapes.append(dict(type="line", xref="x", yref="paper", x0=x, x1=x, y0=0, y1=1, layer="above",
                               line=dict(color=COLOURS[_MARK_COLOURS[kind]], width=1, dash="dash"), opacity=0.7,
                               name=f"event: {kind.replace('_', ' ')}", legendgroup=f"event {kind}",
                               showlegend=kind not in seen, legend="legend"))
            seen.add(kind)
        return shapes

    def _cursor(self) -> dict:
        """The shared time cursor: one line across every panel, moved by the page's script
        to the time under the mouse (name 'cursor')."""
        return dict(type="line", name="cursor", xref="x", yref="paper", x0=self.t[0], x1=self.t[0], y0=0, y1=1,
                    line=dict(color="#444", width=1), visible=False, layer="above")


def _state_names(r: Result, path: str) -> dict[int, str]:
    out = {}
    for item in str(r.attrs.get(path, {}).get("names", "")).split(","):
        if "=" in item:
            k, v = item.split("=", 1)
            if k.strip().lstrip("-").isdigit():
                out[int(k)] = v.strip()
    return out


def run_figure(r, *, points: int = DISPLAY_POINTS):
    """The interactive figure of a run (a Result or a result file path): a plotly Figure."""
    from .plot import _result, timeline_rows
    r = _result(r)
    scale, _ = _time_unit(r)
    p = _Panels(r, scale, points)

    ya = p.add_panel("SOC of each series group minus the pack mean (truth)", 1.0, title=dict(text="group"))
    p.heatmap(ya, 100.0 * group_deviation(r, "truth/cell_soc"), "SOC deviation", "% pts")
    ya = p.add_panel("cell voltage of each series group minus the pack mean (truth)", 1.0, title=dict(text="group"))
    p.heatmap(ya, 1000.0 * group_deviation(r, "truth/cell_voltage_V"), "voltage deviation", "mV")

    lim = {c.limit: _limit_value(r, c) for c in CHANNELS}
    ya = p.add_panel("cell voltage: measured by the BMS vs truth", 1.2, title=dict(text="V"))
    v = r["truth/cell_voltage_V"]
    p.line(ya, v.max(axis=1), "truth highest cell", "C3")
    p.line(ya, v.min(axis=1), "truth lowest cell", "C0")
    if "measured/cell_voltage_mV" in r:
        m = r["measured/cell_voltage_mV"].astype(float) / 1000.0
        p.line(ya, m.max(axis=1), "measured highest group", "C3", dash="dash", width=1)
        p.line(ya, m.min(axis=1), "measured lowest group", "C0", dash="dash", width=1)
    for key, name in (("cell_overvoltage_V", "over-voltage"), ("cell_undervoltage_V", "under-voltage")):
        if lim[key] is not None:
            p.limit(ya, lim[key], name)

    ya = p.add_panel("temperature: thermistors vs cells", 1.2, title=dict(text="°C"))
    temp = r["truth/cell_temp_C"]
    p.line(ya, temp.max(axis=1), "truth hottest cell", "C3")
    p.line(ya, temp.min(axis=1), "truth coldest cell", "C0")
    if "measured/temperature_dC" in r and r["measured/temperature_dC"].size:
        d = r["measured/temperature_dC"].astype(float)
        d[d == INVALID_DC] = np.nan
        with np.errstate(all="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)  # a sample with every thermistor open: NaN
            p.line(ya, np.nanmax(d, axis=1) / 10.0, "measured hottest thermistor", "C3", dash="dash", width=1)
            p.line(ya, np.nanmin(d, axis=1) / 10.0, "measured coldest thermistor", "C0", dash="dash", width=1)
    if "truth/board_temp_C" in r:
        p.line(ya, r["truth/board_temp_C"], "balancing board", "C4")
    for key, name in (("overtemperature_C", "over-temperature"), ("undertemperature_C", "under-temperature")):
        if lim[key] is not None:
            p.limit(ya, lim[key], name)

    ya = p.add_panel("pack current (+ discharges): measured vs truth", 1.0, title=dict(text="A"))
    p.line(ya, r["truth/pack_current_A"], "truth pack current", "C0")
    if "measured/current_mA" in r:
        p.line(ya, r["measured/current_mA"].astype(float) / 1000.0, "measured by the BMS", "C1", dash="dash", width=1)
    for key, name in (("overcurrent_discharge_A", "discharge over-current"),
                      ("overcurrent_charge_A", "charge over-current")):
        if lim[key] is not None:
            p.limit(ya, lim[key], name)

    ya = p.add_panel("state of charge", 1.0, title=dict(text="SOC"))
    soc = r["truth/cell_soc"]
    p.line(ya, soc.max(axis=1), "truth highest cell", "C2", width=0.8)
    p.line(ya, soc.min(axis=1), "truth lowest cell", "C2", width=0.8, dash="dot")
    p.line(ya, soc.mean(axis=1), "truth mean cell", "C2")
    if "bms/soc_estimate_permille" in r:
        p.line(ya, r["bms/soc_estimate_permille"].astype(float) / 1000.0, "BMS estimate", "C1", shape="hv")

    names = _state_names(r, "bms/state")
    state = r["bms/state"].astype(int)
    ticks = sorted(set(names) | set(np.unique(state).tolist()))
    ya = p.add_panel("BMS state", 0.7, tickvals=ticks, ticktext=[names.get(k, str(k)) for k in ticks],
                     range=[min(ticks) - 0.5, max(ticks) + 0.6])
    p.line(ya, state.astype(float), "BMS state", "C0", shape="hv", width=1.5)
    p.event_points(ya, max(ticks) + 0.3)

    rows = [(label, on.astype(float), "C2" if src == "commanded" else "C0") for label, on, src in timeline_rows(r)]
    if "bms/fault_active" in r and r.fault_names:
        act = r.faults("active")
        rows += [(f"fault: {k}", act[k].astype(float), "C3") for k in r.fault_names if act[k].any()]
    if rows:
        ya = p.add_panel("commands (green), hardware (blue) and active faults (red)", 0.13 * len(rows) + 0.3,
                         tickvals=list(range(len(rows))), ticktext=[label for label, _, _ in rows],
                         range=[len(rows) - 0.1, -0.9], tickfont=dict(size=9))
        for k, (label, on, colour) in enumerate(rows):
            p.line(ya, k - 0.7 * on, label, colour, shape="hv", width=2)
    fig = p.figure(f"{r.scenario_name} (seed {r.seed})")
    for tr in fig.data:  # the timeline's rows are named by their tick labels
        if tr.yaxis == ya and len(rows) and tr.name in {label for label, _, _ in rows}:
            tr.showlegend = False
    return fig
