"""One self-contained HTML page for deciding on a run or a sweep: ``packsim report``.

    packsim.report("race.h5", "race.html")            # verdict, margins, energy, figure, events
    packsim.report("results/sweep/", "sweep.html")    # a batch folder: responses + the cases

The run page says first what happened and how close every protection came
(packsim.run_facts, all from the result file), then one interactive figure
(packsim.run_figure), the filterable events table and the scenario as it ran. The sweep
page plots every output against the swept inputs (packsim.sweep_figure).

The figures are Plotly: zoom, a shared time cursor, legend toggles, hover values, and
one figure format for the page and for Jupyter (``packsim.plot.run_figure``). Plotly's
JavaScript (about 4.6 MB) is inlined, with the page's few lines of script: the page
opens offline, from a mail attachment or a file share, with nothing beside it.
"""
from __future__ import annotations

import argparse
import html
import os
import sys
from typing import Any

import numpy as np

from ._atomic import replaced_when_done
from ._inputs_kept import refuse_overwriting
from .result import Result, load

__all__ = ["report", "result_html", "batch_html"]

_STYLE = """
body{font-family:system-ui,sans-serif;margin:2em auto;max-width:1100px;color:#222}
h1{font-size:1.5em} h2{font-size:1.2em;margin-top:2em;border-bottom:1px solid #ccc}
table{border-collapse:collapse;font-size:.85em;margin:.5em 0}
td,th{border:1px solid #ddd;padding:2px 8px;text-align:left;vertical-align:top}
th{background:#f2f2f2} table.sortable th{cursor:pointer} img{max-width:100%}
.bad{color:#b00;font-weight:bold} pre{background:#f7f7f7;padding:1em;overflow-x:auto;font-size:.8em}
.verdict{border-left:6px solid #2a2;padding:.3em 1em;background:#f3fbf3} .verdict.bad{border-color:#b00;background:#fdf2f2}
.verdict .headline{font-size:1.25em;margin:.3em 0} .verdict ul{margin:.2em 0;font-weight:normal;color:#222}
.note{font-size:.8em;color:#555} .grid{display:grid;grid-template-columns:repeat(auto-fill,minmax(520px,1fr));gap:8px}
.grid .plotly-graph-div{margin:0} .grid .wide{grid-column:1/-1} .scroll{overflow:auto;max-height:32em;border:1px solid #ddd}
.scroll table{margin:0;font-size:.75em} .scroll th{position:sticky;top:0} #events{width:100%} .plotly-graph-div{margin:0 -200px 0 0}
"""
# Click a header to sort by it (numbers as numbers); click again to reverse.
_SORT_JS = """
document.querySelectorAll('table.sortable th').forEach(function(th, col){
  th.addEventListener('click', function(){
    var table = th.closest('table'), body = table.tBodies[0], rows = Array.from(body.rows);
    var dir = th.dataset.dir === 'asc' ? -1 : 1; th.dataset.dir = dir === 1 ? 'asc' : 'desc';
    rows.sort(function(a, b){
      var x = a.cells[col].textContent, y = b.cells[col].textContent, nx = parseFloat(x), ny = parseFloat(y);
      if (!isNaN(nx) && !isNaN(ny)) return dir * (nx - ny);
      return dir * x.localeCompare(y);
    });
    rows.forEach(function(r){ body.appendChild(r); });
  });
});
"""


def _table(header: list[str], rows: list[list[Any]], *, sortable: bool = False, table_id: str = "") -> str:
    e = html.escape
    head = "".join(f"<th>{e(str(h))}</th>" for h in header)
    body = "".join("<tr>" + "".join(f"<td>{e(_fmt(v))}</td>" for v in row) + "</tr>" for row in rows)
    cls = (' class="sortable"' if sortable else "") + (f' id="{table_id}"' if table_id else "")
    return f"<table{cls}><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"


def _fmt(v: Any) -> str:
    if isinstance(v, float):
        return f"{v:.6g}"
    return str(v)


def _page(title: str, body: str, *, plotly: bool = False) -> str:
    """The whole page; with plotly, the library inlined in the head (the page opens
    offline) and the cursor and filter scripts after the body."""
    lib = f"<script>{_plotly_js()}</script>" if plotly else ""
    extra = _CURSOR_JS + _FILTER_JS if plotly else ""
    return (f"<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>{html.escape(title)}</title>"
            f"<style>{_STYLE}</style>{lib}</head><body>\n{body}\n<script>{_SORT_JS}{extra}</script></body></html>\n")


def _plotly_js() -> str:
    try:
        from plotly.offline import get_plotlyjs
    except ImportError as e:
        raise ImportError("packsim report needs plotly (pip install plotly)") from e
    return get_plotlyjs()


# The shared time cursor: a vertical line (the figure's shape named 'cursor') across every
# panel, moved to the time under the mouse; the panels share one x axis, so zoom and pan
# are shared too.
_CURSOR_JS = """
document.querySelectorAll('.packsim-figure').forEach(function(gd){
  var pending = null;
  function cursorIndex(){ return (gd.layout.shapes || []).findIndex(function(s){ return s.name === 'cursor'; }); }
  gd.on('plotly_hover', function(ev){
    if (!ev.points || !ev.points.length) return;
    pending = ev.points[0].x;
    window.requestAnimationFrame(function(){
      var i = cursorIndex(); if (i < 0 || pending === null) return;
      var u = {}; u['shapes[' + i + '].x0'] = pending; u['shapes[' + i + '].x1'] = pending;
      u['shapes[' + i + '].visible'] = true; pending = null;
      Plotly.relayout(gd, u);
    });
  });
});
"""
# The events table: a text filter and a kind filter; rows that match both stay.
_FILTER_JS = """
(function(){
  var table = document.getElementById('events'); if (!table) return;
  var text = document.getElementById('event-filter'), kind = document.getElementById('event-kind');
  var count = document.getElementById('event-count');
  function apply(){
    var q = text.value.toLowerCase(), k = kind.value, shown = 0;
    Array.from(table.tBodies[0].rows).forEach(function(row){
      var ok = (!k || row.cells[1].textContent === k) && (!q || row.textContent.toLowerCase().indexOf(q) >= 0);
      row.style.display = ok ? '' : 'none'; if (ok) shown++;
    });
    count.textContent = shown + ' of ' + table.tBodies[0].rows.length + ' events';
  }
  text.addEventListener('input', apply); kind.addEventListener('change', apply); apply();
})();
"""


def _figure_div(fig, div_id: str, *, mode_bar: bool = True) -> str:
    return fig.to_html(full_html=False, include_plotlyjs=False, div_id=div_id,
                       config={"displaylogo": False, "responsive": True, "scrollZoom": False,
                               "displayModeBar": "hover" if mode_bar else False}
                       ).replace('class="plotly-graph-div"', 'class="plotly-graph-div packsim-figure"')


def _num(v: float | None, unit: str = "", digits: int = 4) -> str:
    if v is None or not np.isfinite(v):
        return "-"
    return f"{v:.{digits}g} {unit}".strip()


def _verdict_html(v) -> str:
    e = html.escape
    cls = "verdict bad" if v.tripped else "verdict ok"
    lines = "".join(f"<li>{e(x)}</li>" for x in v.lines)
    return f'<div class="{cls}" id="verdict"><p class="headline">{e(v.headline)}</p><ul>{lines}</ul></div>'


def _margins_html(r: Result) -> str:
    from .run_facts import margins
    rows = []
    for m in margins(r):
        u = m.channel.unit
        row = [m.channel.label, _num(m.limit, u)]
        for a in (m.truth, m.measured):
            if a is None:
                row += ["-", "-", "-", "-"]
                continue
            past = f" (past for {a.past_s:.3g} s)" if a.past_s > 0 else ""
            row += [_num(a.value, u), _num(a.margin, u, 3) + past, f"{a.time_s:.2f} s", a.where]
        row.append("-" if m.tripped_s is None else f"{m.tripped_s:.2f} s")
        rows.append(row)
    if not rows:
        return "<p>The BMS had no protection limit (no limit attributes in /bms).</p>"
    head = ["protection", "limit", "truth: closest", "truth: margin", "when", "where",
            "measured: closest", "measured: margin", "when", "where", "latched at"]
    return (_table(head, rows, table_id="margins")
            + "<p class=\"note\">margin: how far inside the limit the closest approach stayed (negative: past "
              "it, with the time spent past it); truth over every cell, measured over what the BMS read "
              "(groups, thermistors, its current sensor), both over the recorded samples."
            + _tick_extremes(r) + "</p>")


def _tick_extremes(r: Result) -> str:
    """The summary's extremes, tracked every tick (between recorded samples too)."""
    from .run_facts import cell_name
    s, out = r.summary, []
    if "min_cell_V" in s and "min_cell" in s:
        out.append(f"lowest cell {s['min_cell_V']:.4g} V, {cell_name(r, int(s['min_cell']) - 1)} at "
                   f"{s.get('min_cell_time_s', 0.0):.2f} s")
    if "max_temp_C" in s and "hottest_cell" in s:
        out.append(f"hottest cell {s['max_temp_C']:.4g} °C, {cell_name(r, int(s['hottest_cell']) - 1)} at "
                   f"{s.get('hottest_time_s', 0.0):.2f} s")
    return (" The run's summary, tracked every tick: " + "; ".join(out) + ".") if out else ""


def _energy_html(r: Result) -> str:
    from .run_facts import energy
    rows = [[label, f"{wh:.2f} Wh", what] for label, wh, what in energy(r)]
    return _table(["energy", "Wh", "what it counts"], rows, table_id="energy") if rows else ""


def _events_html(r: Result) -> str:
    e = html.escape
    kinds = sorted({str(ev["kind"]) for ev in r.events})
    options = "".join(f"<option>{e(k)}</option>" for k in kinds)
    controls = (f'<p><input id="event-filter" type="search" placeholder="filter events" size="30"> '
                f'<select id="event-kind"><option value="">every kind</option>{options}</select> '
                f'<span id="event-count"></span></p>')
    table = _table(["time_s", "kind", "detail"], [[f"{ev['time_s']:.2f}", ev["kind"], ev["detail"]]
                                                  for ev in r.events], sortable=True, table_id="events")
    return controls + table


def result_html(r: Result | str | os.PathLike, *, points: int | None = None) -> str:
    """The page of one run: the verdict, the margin to every protection limit, the energy
    account, the interactive figure (run_figure), the events table and the scenario as it
    ran. Every line is derived from the result (run_facts)."""
    from .run_facts import verdict
    from .run_figure import DISPLAY_POINTS, run_figure
    r = r if isinstance(r, Result) else load(r)
    e = html.escape
    fig = run_figure(r, points=points or DISPLAY_POINTS)
    parts = [f"<h1>{e(r.scenario_name)} (seed {r.seed})</h1>",
             f"<p>packsim {e(str(r.version))}; {r.n_samples} samples over {r.time_s[-1]:.2f} s; "
             f"{r.n_cells} cells in {r.n_series} series groups"
             + (f"; from {e(str(r.source))}" if r.source else "") + "</p>",
             _verdict_html(verdict(r)),
             "<h2>Margin to every protection limit</h2>", _margins_html(r),
             "<h2>Energy</h2>", _energy_html(r),
             "<h2>Figures</h2><p class=\"note\">Drag to zoom (double-click resets), every panel follows; the "
             "grey line is the time under the mouse in every panel; click a legend entry to hide or show it "
             "(event marks too); hover over a mark's diamond on the BMS state panel for the event. Curves "
             "are thinned for display to the min and max of each time bucket; every number above uses every "
             "recorded sample.</p>",
             _figure_div(fig, "run-figure"),
             *_distance_html(r),
             f"<h2>Events ({len(r.events)})</h2>", _events_html(r),
             "<h2>Scenario as it ran</h2>", f"<pre id=\"scenario\">{e(r.scenario_yaml)}</pre>"]
    return _page(f"packsim: {r.scenario_name}", "\n".join(parts), plotly=True)


def _distance_html(r: Result) -> list[str]:
    """A vehicle run's figure over the distance it drove (packsim.vehicle_figure)."""
    from .vehicle_figure import distance_figure, has_vehicle
    if not has_vehicle(r):
        return []
    return ["<h2>Over distance</h2><p class=\"note\">The vehicle's speed, the pack's power, the cells' SOC and "
            "the lowest cell against the km it drove (a stop shows as a vertical run at one place); the dashed "
            "line: where the pack first limited the vehicle.</p>",
            _figure_div(distance_figure(r), "distance-figure"),
            *_vehicle_tables_html(r)]


def _vehicle_tables_html(r: Result) -> list[str]:
    """The lap and stage tables of the result file (/vehicle/laps, /vehicle/stages), as the
    summary prints them: per lap its time, distance, the pack's and the array's energy."""
    parts: list[str] = []
    if "vehicle/laps" in r:
        laps = r["vehicle/laps"]
        rows = [[int(l["lap"]), "yes" if l["complete"] else "no (the run ended in it)", float(l["start_s"]),
                 float(l["time_s"]), float(l["distance_m"]) / 1000.0, float(l["pack_Wh"]), float(l["array_Wh"]),
                 float(l["pack_Wh"]) / (float(l["distance_m"]) / 1000.0) if l["distance_m"] > 0 else float("nan")]
                for l in laps]
        parts += [f"<h3>Laps ({len(rows)})</h3>",
                  _table(["lap", "complete", "start_s", "time_s", "distance_km", "pack_Wh", "array_Wh", "pack_Wh_per_km"],
                         rows, sortable=True, table_id="laps")]
    if "vehicle/stages" in r:
        st = r["vehicle/stages"]
        rows = [[int(g["stage"]), "yes" if g["complete"] else "no (the run ended in it)", float(g["depart_s"]),
                 float(g["time_s"]), float(g["distance_m"]) / 1000.0, float(g["pack_Wh"]), float(g["array_Wh"]),
                 float(g["parked_s"]), float(g["parked_pack_Wh"]), float(g["parked_array_Wh"])] for g in st]
        parts += [f"<h3>Stages ({len(rows)})</h3>",
                  _table(["stage", "complete", "depart_s", "time_s", "distance_km", "pack_Wh", "array_Wh", "parked_s",
                          "parked_pack_Wh", "parked_array_Wh"], rows, sortable=True, table_id="stages")]
    return parts


def batch_html(folder: str | os.PathLike) -> str:
    """The page of a sweep: each output against the swept inputs (sweep_figure), then
    summary.csv as a sortable table that scrolls inside the page."""
    from .sweep_figure import figures, read
    t = read(folder)
    e = html.escape
    figs = figures(t)
    n_ok = len(t.ok_rows())
    kind = ("Monte Carlo over " + ", ".join(t.inputs)) if t.monte_carlo else \
        ("swept: " + ", ".join(t.swept) if t.swept else "nothing varies over the cases that ran")
    left = ", ".join(f"{k} ({v})" for k, v in t.left_out.items())
    parts = [f"<h1>Sweep {e(os.path.basename(os.path.abspath(os.fspath(folder))))}</h1>",
             f"<p>{len(t.rows)} cases ({n_ok} ran) from {e(t.path)}; {e(kind)}.</p>",
             _sensitivity_html(t),
             f"<h2>Responses ({len(figs)})</h2>",
             "<p class=\"note\">Outputs that vary over the cases that ran; not plotted: " + e(left or "none") + ".</p>",
             '<div class="grid">' + "".join(f'<div class="{"wide" if "correlation" in title or "sensitivity" in title else "cell"}">{_figure_div(f, f"sweep-{i}", mode_bar=False)}</div>'
                     for i, (title, f) in enumerate(figs)) + "</div>",
             f"<h2>Cases ({len(t.rows)})</h2><p class=\"note\">click a column to sort.</p>",
             '<div class="scroll">' + _table(t.header, t.rows, sortable=True,
                                             table_id="cases") + "</div>"]
    return _page("packsim sweep", "\n".join(parts), plotly=True)


def _sensitivity_html(t) -> str:
    """A Monte Carlo's sensitivity table: each output's rank correlation with each random
    input the cases drew (sweep_figure.sensitivity), the strongest named first."""
    from .sweep_figure import DRAWN, sensitivity
    if not t.monte_carlo:
        return ""
    e = html.escape
    not_drawn = [k for k, why in t.left_out.items() if k.startswith(DRAWN) and why.startswith("not drawn")]
    note = ("<p class=\"note\">Random inputs: each case's cell values as drawn from its seed, per series "
            "group (docs/batch.md); beside them any other input the sweep varies. ρ is Spearman's rank correlation over the cases that ran (+1: the output "
            "rises with the input; 0: no monotonic relation); p the chance of a correlation this strong with "
            "none at all — with few cases only a large |ρ| means something. Bold: p < 0.05."
            + (" Not drawn (spread 0, the same in every case): " + e(", ".join(not_drawn)) + "." if not_drawn else "")
            + "</p>")
    if not t.drawn:
        return ("<h2>Sensitivity to the inputs</h2><p>No random input varies over the cases that ran "
                "(summary.csv has no varying drawn_* column).</p>" + note)
    rows = []
    for sv in sensitivity(t):
        best = sv.strongest
        cells = []
        for name in t.drawn + t.swept:
            r, p = sv.rho[name], sv.p_value[name]
            txt = "-" if not np.isfinite(r) else f"{r:+.2f}"
            cells.append(f"<b>{txt}</b>" if np.isfinite(p) and p < 0.05 else txt)
        lead = [e(sv.output), e(best or "-"),
                "-" if best is None else f"{sv.rho[best]:+.2f}", "-" if best is None else f"{sv.p_value[best]:.2g}"]
        rows.append("<tr>" + "".join(f"<td>{c}</td>" for c in lead + cells) + "</tr>")
    head = "".join(f"<th>{e(h)}</th>" for h in ["output", "strongest input", "ρ", "p"] + t.drawn + t.swept)
    return ("<h2>Sensitivity to the inputs</h2>" + note
            + f'<div class="scroll"><table class="sortable" id="sensitivity"><thead><tr>{head}</tr></thead>'
            + f"<tbody>{''.join(rows)}</tbody></table></div>")


def _input_files(source: Result | str | os.PathLike, is_batch: bool) -> list[str]:
    """The files a report reads: the result file, or a batch folder's summary.csv and cases."""
    if isinstance(source, Result):
        return [source.source] if source.source else []
    if not is_batch:
        return [os.fspath(source)]
    import glob
    folder = os.fspath(source)
    return [os.path.join(folder, "summary.csv")] + glob.glob(os.path.join(folder, "*.h5"))


def report(source: Result | str | os.PathLike, output: str | os.PathLike) -> str:
    """Write the HTML page of a result (a Result or a result file) or of a batch folder
    (holding summary.csv) to output; returns its path. Written under a temporary name
    and renamed when complete."""
    if not isinstance(source, (Result, str, os.PathLike)):
        raise TypeError(f"source must be a Result, a result file or a batch folder, got {type(source).__name__}")
    if not isinstance(output, (str, os.PathLike)):
        raise TypeError(f"output must be a path, got {type(output).__name__}")
    is_batch = not isinstance(source, Result) and os.path.isdir(os.fspath(source))
    output = os.fspath(output)
    refuse_overwriting({"-o": output}, _input_files(source, is_batch))
    page = batch_html(source) if is_batch else result_html(source)
    os.makedirs(os.path.dirname(os.path.abspath(output)), exist_ok=True)
    with replaced_when_done(output) as tmp, open(tmp, "w", encoding="utf-8") as f:
        f.write(page)
    return output


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="packsim report", description="one self-contained HTML page of a run or sweep")
    ap.add_argument("source", help="result HDF5 file, or a batch output folder (with summary.csv)")
    ap.add_argument("-o", "--output", required=True, help="HTML file to write")
    a = ap.parse_args(argv)
    try:
        import plotly  # noqa: F401
    except ImportError:
        print("packsim report: error: plotly is not installed (pip install plotly)", file=sys.stderr)
        return 1
    if not os.path.exists(a.source):
        print(f"packsim report: error: {a.source}: no such result file or batch folder", file=sys.stderr)
        return 2
    try:
        print(report(a.source, a.output))
    except ImportError as e:  # scipy for a Monte Carlo's rank correlation
        print(f"packsim report: error: {e}", file=sys.stderr)
        return 1
    except (OSError, ValueError, KeyError) as e:
        print(f"packsim report: error: {e}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
