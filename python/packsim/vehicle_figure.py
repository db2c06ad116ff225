"""A vehicle run over the distance it drove (``load.vehicle``; docs/vehicle.md): speed,
pack power, cell SOC and the lowest cell voltage against km along the route, with the
place the pack first limited the vehicle. Two forms of the same four panels:
``distance_series`` (the arrays), drawn by ``packsim.plot.vehicle`` (PNG, matplotlib)
and ``distance_figure`` (Plotly, the report's "Over distance" figure)."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .result import Result

__all__ = ["has_vehicle", "distance_series", "distance_figure"]


def has_vehicle(r: Result) -> bool:
    return "vehicle/distance_m" in r


@dataclass
class DistanceSeries:
    km: np.ndarray             # distance driven [km], every sample
    speed_kmh: np.ndarray
    pack_W: np.ndarray         # delivered: pack voltage × pack current (+ discharges)
    request_W: np.ndarray      # what the vehicle asked of the pack over the next tick
    soc_min: np.ndarray
    soc_mean: np.ndarray
    soc_max: np.ndarray
    min_cell_V: np.ndarray
    undervoltage_V: float | None   # the BMS's cell under-voltage limit
    limit_km: float | None         # where a pack limit first cut the drive (None: never)


def distance_series(r: Result) -> DistanceSeries:
    if not has_vehicle(r):
        raise ValueError(f"{r.scenario_name}: not a vehicle run (no /vehicle group; docs/vehicle.md)")
    km = r["vehicle/distance_m"] / 1000.0
    soc = r["truth/cell_soc"]
    uv = r.attrs.get("bms", {}).get("limit_cell_undervoltage_V")
    t_lim = float(r.summary.get("vehicle_limit_time_s", -1.0))
    limit_km = float(np.interp(t_lim, r.time_s, km)) if t_lim >= 0.0 else None
    return DistanceSeries(km=km, speed_kmh=r["vehicle/speed_m_per_s"] * 3.6,
                          pack_W=r["truth/pack_voltage_V"] * r["truth/pack_current_A"],
                          request_W=r["vehicle/pack_request_W"], soc_min=soc.min(axis=1), soc_mean=soc.mean(axis=1),
                          soc_max=soc.max(axis=1), min_cell_V=r["truth/cell_voltage_V"].min(axis=1),
                          undervoltage_V=float(uv) if uv is not None else None, limit_km=limit_km)


PANELS = ("speed (km/h)", "pack power (W, + discharges)", "cell SOC", "lowest cell (V)")


def distance_figure(r: Result, *, points: int | None = None):
    """The four panels over distance as a Plotly figure (curves thinned for display to
    the min and max of each sample bucket, as the run figure)."""
    import plotly.graph_objects as go
    from plotly.subplots import make_subplots

    from .run_figure import COLOURS, DISPLAY_POINTS, display_indices
    d = distance_series(r)
    fig = make_subplots(rows=4, cols=1, shared_xaxes=True, vertical_spacing=0.04, subplot_titles=PANELS)
    stack = np.column_stack([d.speed_kmh, d.pack_W, d.request_W, d.soc_min, d.soc_max, d.min_cell_V])
    idx = display_indices(stack, points or DISPLAY_POINTS)
    x = d.km[idx]

    def line(row: int, y: np.ndarray, name: str, colour: str, dash: str | None = None, width: float = 1.2) -> None:
        fig.add_trace(go.Scatter(x=x, y=y[idx], name=name, mode="lines",
                                 line=dict(color=COLOURS[colour], dash=dash, width=width),
                                 hovertemplate="km %{x:.3f}: %{y:.5g}<extra>" + name + "</extra>"), row=row, col=1)

    line(1, d.speed_kmh, "speed", "C0")
    line(2, d.pack_W, "pack power (delivered)", "C3")
    line(2, d.request_W, "asked by the vehicle", "C1", dash="dot", width=1.0)
    line(3, d.soc_max, "highest cell SOC", "C2", width=0.8)
    line(3, d.soc_mean, "mean cell SOC", "C2")
    line(3, d.soc_min, "lowest cell SOC", "C2", dash="dot", width=0.8)
    line(4, d.min_cell_V, "lowest cell voltage", "C0")
    if d.undervoltage_V is not None:
        fig.add_hline(y=d.undervoltage_V, line=dict(color=COLOURS["C3"], dash="dot", width=1), row=4, col=1,
                      annotation_text=f"under-voltage limit {d.undervoltage_V:g} V", annotation_font_size=10)
    if d.limit_km is not None:
        fig.add_vline(x=d.limit_km, line=dict(color=COLOURS["C3"], dash="dash", width=1),
                      annotation_text=f"first pack limit, km {d.limit_km:.3f}", annotation_font_size=10)
    fig.update_xaxes(title_text="distance (km)", row=4, col=1)
    fig.update_layout(title=dict(text=f"{r.scenario_name} (seed {r.seed}): over distance", x=0.01), height=820,
                      plot_bgcolor="white", hovermode="x", margin=dict(l=70, r=40, t=70, b=50))
    fig.update_xaxes(gridcolor="#e5e5e5")
    fig.update_yaxes(gridcolor="#e5e5e5", zeroline=False)
    return fig
