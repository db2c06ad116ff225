"""The figures of a sweep's summary.csv (Plotly): every output against the swept inputs.

    from packsim import sweep_figure
    t = sweep_figure.read("results/sweep/")     # SweepTable: inputs, outputs, rows
    for title, fig in sweep_figure.figures(t):  # plotly Figures (show themselves in Jupyter)
        ...

- one swept input: each output as a line over it, tripped cases marked;
- a 2-D grid: each output as a heat-map over the two inputs, tripped cases marked;
- more inputs: each output against each input (points);
- a Monte Carlo (the seed is an input): each output's distribution; its sensitivity to
  each random input -- the cell values each case drew, the ``drawn_*`` columns
  (core/batch/drawn_inputs.hpp, docs/batch.md) -- and to any other swept input, as a
  rank correlation (Spearman) table and heat-map, and each output against each input (a
  scatter per output, the input chosen from a menu, the strongest first); the rank
  correlation between outputs.

Plotted are the outputs that vary over the cases that ran: the case id, status, error,
file, the cell/group numbers (identifiers, not quantities) and the columns that are the
same in every case are not. A random input that is the same in every case was not drawn
(its spread is 0): it is listed as such and has no sensitivity.
"""
from __future__ import annotations

import csv
import os
from dataclasses import dataclass, field

import numpy as np

__all__ = ["SweepTable", "read", "figures", "rank_correlation", "sensitivity", "Sensitivity", "IDENTIFIERS",
           "DRAWN"]

# Columns that name things rather than measure them.
IDENTIFIERS = frozenset({"case", "status", "error", "file", "seed", "min_cell", "hottest_cell", "limit_cell",
                         "soc_error_ekf_group", "trip_reason", "limit_unseen_longest", "soc_estimator",
                         "drawn_weakest_group"})
# The prefix of the random inputs a case drew (summary.csv columns; core/batch/drawn_inputs.hpp).
DRAWN = "drawn_"
TRIP = "tripped"
# Times the summary writes as -1 for "never" (balancing never started or never done, no
# pack limit on the vehicle), and the trip time of a case that did not trip (0): not times
# of anything, so not plotted (NaN). The cases' table on the page still shows them.
NEVER = frozenset({"balance_started_s", "balance_balanced_s", "vehicle_limit_time_s"})
TRIP_TIME = "trip_time_s"
# Times that are times of something only where a flag says it happened: the trip time of
# a case that tripped; the time the first cell reached its limit (limit_reached 1) -- a
# case whose cells never did carries the run's end there (the summary accounts the
# energy left at the end), which is no time the limit was reached.
WHEN_FLAG = {TRIP_TIME: TRIP, "limit_time_s": "limit_reached"}
# Outputs a team looks at first, in this order; the others follow in summary.csv's order.
FIRST = ("energy_delivered_Wh", "energy_stranded_Wh", "min_cell_V", "max_temp_C", "trip_time_s", "tripped",
         "duration_s", "heat_Wh", "energy_left_Wh")


@dataclass
class SweepTable:
    path: str
    header: list[str]
    rows: list[list[str]]
    inputs: list[str]              # the varied values (between `case` and `status`)
    outputs: list[str]             # numeric outputs that vary over the cases that ran
    left_out: dict[str, str] = field(default_factory=dict)  # column -> why it is not plotted
    drawn: list[str] = field(default_factory=list)  # random inputs that vary (drawn_* columns)

    def column(self, name: str, ok_only: bool = True) -> np.ndarray:
        j = self.header.index(name)
        vals = [row[j] if j < len(row) else "" for row in self.ok_rows()] if ok_only else \
            [row[j] if j < len(row) else "" for row in self.rows]
        out = np.full(len(vals), np.nan)
        for i, v in enumerate(vals):
            try:
                out[i] = float(v)
            except ValueError:
                pass
        if name in NEVER:
            out[out == -1.0] = np.nan
        elif name in WHEN_FLAG and WHEN_FLAG[name] in self.header:
            out[~(self.column(WHEN_FLAG[name], ok_only) > 0.5)] = np.nan
        return out

    def ok_rows(self) -> list[list[str]]:
        j = self.header.index("status") if "status" in self.header else None
        return [row for row in self.rows if j is None or (j < len(row) and row[j] == "ok")]

    @property
    def monte_carlo(self) -> bool:
        return "seed" in self.inputs

    @property
    def swept(self) -> list[str]:
        """Inputs other than the seed that vary and are numbers."""
        return [c for c in self.inputs if c != "seed" and c not in self.left_out]


def read(folder: str | os.PathLike) -> SweepTable:
    folder = os.fspath(folder)
    path = os.path.join(folder, "summary.csv")
    if not os.path.isfile(path):
        raise FileNotFoundError(f"{folder}: no summary.csv (not a packsim batch folder)")
    with open(path, newline="", encoding="utf-8") as f:
        rows = list(csv.reader(f))
    if not rows or not rows[0]:
        raise ValueError(f"{path}: empty summary.csv")
    header = rows[0]
    if header[0] != "case" or "status" not in header:
        raise ValueError(f"{path}: not a packsim summary.csv (its first column must be 'case' and it needs a "
                         f"'status' column)")
    inputs = header[1:header.index("status")]
    t = SweepTable(path, header, rows[1:], inputs, [])
    for name in header:
        if name in IDENTIFIERS and name not in inputs:
            t.left_out[name] = "identifier"
            continue
        col = t.column(name)
        if col.size == 0 or np.all(np.isnan(col)):
            if name not in IDENTIFIERS:
                t.left_out[name] = "not a number"
            continue
        finite = col[np.isfinite(col)]
        is_drawn = name.startswith(DRAWN)
        if np.unique(finite).size < 2:
            t.left_out[name] = "not drawn: the same in every case" if is_drawn else "the same in every case"
            continue
        if is_drawn:
            if t.monte_carlo:
                t.drawn.append(name)
            else:  # one seed: the drawn values follow the swept ones, they are not random here
                t.left_out[name] = "drawn from one seed: follows the swept inputs"
        elif name not in inputs:
            t.outputs.append(name)
    t.outputs.sort(key=lambda n: FIRST.index(n) if n in FIRST else len(FIRST))
    return t


def rank_correlation(a: np.ndarray, b: np.ndarray) -> float:
    """Spearman's rank correlation of two columns over the cases where both are numbers."""
    try:
        from scipy.stats import spearmanr
    except ImportError as e:
        raise ImportError("the rank correlation of a Monte Carlo needs scipy (pip install scipy)") from e
    ok = np.isfinite(a) & np.isfinite(b)
    if ok.sum() < 3 or np.unique(a[ok]).size < 2 or np.unique(b[ok]).size < 2:
        return float("nan")
    return float(spearmanr(a[ok], b[ok]).statistic)


@dataclass
class Sensitivity:
    """Spearman's rank correlation of one output with each random input, strongest first."""
    output: str
    rho: dict[str, float]      # input -> rank correlation (NaN: too few cases or a constant)
    p_value: dict[str, float]  # input -> two-sided p-value of no correlation

    @property
    def ranked(self) -> list[str]:
        return sorted(self.rho, key=lambda k: -abs(self.rho[k]) if np.isfinite(self.rho[k]) else 0.0)

    @property
    def strongest(self) -> str | None:
        r = self.ranked
        return r[0] if r and np.isfinite(self.rho[r[0]]) else None


def sensitivity(t: SweepTable) -> list[Sensitivity]:
    """For each output of a Monte Carlo, its rank correlation with each random input
    (t.drawn) and each other swept input (t.swept: a Monte Carlo at several ambient
    temperatures, say) over the cases that ran."""
    try:
        from scipy.stats import spearmanr
    except ImportError as e:
        raise ImportError("the rank correlation of a Monte Carlo needs scipy (pip install scipy)") from e
    out = []
    for name in t.outputs:
        y = t.column(name)
        rho, p = {}, {}
        for x_name in t.drawn + t.swept:
            x = t.column(x_name)
            ok = np.isfinite(x) & np.isfinite(y)
            if ok.sum() < 3 or np.unique(x[ok]).size < 2 or np.unique(y[ok]).size < 2:
                rho[x_name] = p[x_name] = float("nan")
                continue
            r = spearmanr(x[ok], y[ok])
            rho[x_name], p[x_name] = float(r.statistic), float(r.pvalue)
        out.append(Sensitivity(name, rho, p))
    return out


def _scatter_menu(t: SweepTable, s: Sensitivity):
    """One output against each random input: a menu picks the input (the strongest first)."""
    y, trip = t.column(s.output), _trip_marks(t)
    order = s.ranked
    fig = _small(f"{s.output} against the inputs", 340)
    colors = np.where(trip, "#d62728", "#1f77b4")
    for k, x_name in enumerate(order):
        fig.add_scatter(x=t.column(x_name), y=y, mode="markers", name=x_name, visible=k == 0,
                        marker=dict(color=list(colors), size=7),
                        hovertemplate=f"{x_name} %{{x:.5g}}<br>{s.output} %{{y:.5g}}<extra></extra>")

    def label(x_name: str) -> str:
        r = s.rho[x_name]
        return f"{x_name} (ρ {r:+.2f})" if np.isfinite(r) else f"{x_name} (ρ -)"
    buttons = [dict(label=label(x_name), method="update",
                    args=[{"visible": [j == k for j in range(len(order))]}, {"xaxis.title.text": x_name}])
               for k, x_name in enumerate(order)]
    fig.update_layout(xaxis_title=order[0], yaxis_title=s.output, showlegend=False,
                      updatemenus=[dict(buttons=buttons, direction="down", x=1.0, xanchor="right", y=1.18,
                                        yanchor="top", showactive=True, font=dict(size=10))],
                      margin=dict(l=60, r=20, t=70, b=50))
    return fig


def _trip_marks(t: SweepTable) -> np.ndarray:
    return t.column(TRIP) > 0.5 if TRIP in t.header else np.zeros(len(t.ok_rows()), dtype=bool)


def _small(title: str, height: int = 300):
    import plotly.graph_objects as go
    return go.Figure(layout=dict(title=dict(text=title, font=dict(size=12)), height=height,
                                 margin=dict(l=60, r=20, t=50, b=50), plot_bgcolor="white",
                                 xaxis=dict(gridcolor="#e5e5e5"), yaxis=dict(gridcolor="#e5e5e5")))


def _line(t: SweepTable, x_name: str, y_name: str):
    x, y, trip = t.column(x_name), t.column(y_name), _trip_marks(t)
    order = np.argsort(x, kind="stable")
    fig = _small(f"{y_name} vs {x_name}")
    fig.add_scatter(x=x[order], y=y[order], mode="lines+markers", name=y_name, marker=dict(color="#1f77b4"))
    if trip.any():
        fig.add_scatter(x=x[trip], y=y[trip], mode="markers", name="tripped",
                        marker=dict(symbol="x", size=11, color="#d62728"))
    fig.update_layout(xaxis_title=x_name, yaxis_title=y_name, showlegend=bool(trip.any()))
    return fig


def grid_z(t: SweepTable, x_name: str, y_name: str, z_name: str):
    """(xs, ys, z) of a 2-D grid: z[i, j] is z_name's value at ys[i], xs[j] (NaN: no case)."""
    x, y, z = t.column(x_name), t.column(y_name), t.column(z_name)
    xs, ys = np.unique(x[np.isfinite(x)]), np.unique(y[np.isfinite(y)])
    out = np.full((ys.size, xs.size), np.nan)
    for xi, yi, zi in zip(x, y, z):
        if np.isfinite(xi) and np.isfinite(yi):
            out[np.searchsorted(ys, yi), np.searchsorted(xs, xi)] = zi
    return xs, ys, out


def _heatmap(t: SweepTable, x_name: str, y_name: str, z_name: str):
    xs, ys, z = grid_z(t, x_name, y_name, z_name)
    fig = _small(f"{z_name} over {x_name} × {y_name}", 320)
    fig.add_heatmap(x=[f"{v:g}" for v in xs], y=[f"{v:g}" for v in ys], z=z, colorscale="Viridis",
                    colorbar=dict(thickness=10), texttemplate="%{z:.4g}", textfont=dict(size=9),
                    hovertemplate=f"{x_name} %{{x}}<br>{y_name} %{{y}}<br>{z_name} %{{z:.5g}}<extra></extra>")
    if TRIP in t.header and z_name != TRIP:
        _, _, tr = grid_z(t, x_name, y_name, TRIP)
        ii, jj = np.nonzero(tr > 0.5)
        if ii.size:
            fig.add_scatter(x=[f"{xs[j]:g}" for j in jj], y=[f"{ys[i]:g}" for i in ii], mode="markers",
                            name="tripped", marker=dict(symbol="x-open", size=16, color="#d62728"))
    fig.update_layout(xaxis_title=x_name, yaxis_title=y_name, xaxis_type="category", yaxis_type="category")
    return fig


def _histogram(t: SweepTable, name: str):
    v = t.column(name)
    v = v[np.isfinite(v)]
    fig = _small(f"{name}: {v.size} cases, median {np.median(v):.4g}, 5–95 % "
                 f"{np.percentile(v, 5):.4g} … {np.percentile(v, 95):.4g}")
    fig.add_histogram(x=v, nbinsx=min(30, max(5, v.size // 3)), marker=dict(color="#1f77b4"), name=name)
    fig.update_layout(xaxis_title=name, yaxis_title="cases", bargap=0.05)
    return fig


def _correlation(t: SweepTable, rows: list[str], cols: list[str], title: str):
    z = np.array([[rank_correlation(t.column(a), t.column(b)) for b in cols] for a in rows])
    fig = _small(title, 220 + 22 * len(rows))
    fig.add_heatmap(x=cols, y=rows, z=z, zmin=-1, zmax=1, zmid=0, colorscale="RdBu", reversescale=True,
                    texttemplate="%{z:.2f}", textfont=dict(size=9), colorbar=dict(thickness=10),
                    hovertemplate="%{y} vs %{x}: %{z:.3f}<extra></extra>")
    fig.update_layout(yaxis=dict(autorange="reversed"), margin=dict(l=200, r=20, t=40, b=160))
    return fig


def figures(t: SweepTable) -> list[tuple[str, object]]:
    """(title, plotly Figure) for the sweep, as the module docstring says."""
    swept = t.swept
    out: list[tuple[str, object]] = []
    if t.monte_carlo:
        for name in t.outputs:
            out.append((f"distribution of {name}", _histogram(t, name)))
        if t.drawn and t.outputs:
            out.append(("sensitivity to the inputs",
                        _correlation(t, t.outputs, t.drawn + swept,
                                     "sensitivity: rank correlation (Spearman) of each output with each input")))
            for s in sensitivity(t):
                out.append((f"{s.output} against the inputs", _scatter_menu(t, s)))
        if len(t.outputs) >= 2:
            out.append(("rank correlation between outputs",
                        _correlation(t, t.outputs, t.outputs, "rank correlation (Spearman) between outputs")))
        if swept and not t.drawn:
            out.append(("sensitivity to the varied inputs",
                        _correlation(t, t.outputs, swept, "rank correlation of each output with each input")))
        return out
    if len(swept) == 2 and _is_grid(t, swept):
        for name in t.outputs:
            out.append((f"{name} over {swept[0]} × {swept[1]}", _heatmap(t, swept[0], swept[1], name)))
        return out
    for x in swept:
        for name in t.outputs:
            out.append((f"{name} vs {x}", _line(t, x, name)))
    return out


def _is_grid(t: SweepTable, names: list[str]) -> bool:
    a, b = t.column(names[0]), t.column(names[1])
    pairs = {(x, y) for x, y in zip(a, b) if np.isfinite(x) and np.isfinite(y)}
    return len(pairs) == len(a) and len(pairs) == np.unique(a).size * np.unique(b).size
