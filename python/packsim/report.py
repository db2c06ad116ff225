"""One self-contained HTML page for sharing a run or a sweep: ``packsim report``.

    packsim.report("race.h5", "race.html")            # summary, events, every figure
    packsim.report("results/sweep/", "sweep.html")    # a batch folder: summary.csv as a
                                                      # sortable table + distributions

The page embeds its figures as base64 PNG and its few lines of table sorting as inline
JavaScript: it opens from a mail attachment or a file share with nothing beside it.
"""
from __future__ import annotations

import argparse
import base64
import csv
import html
import io
import os
import sys
from typing import Any

import numpy as np

from ._atomic import replaced_when_done
from .result import Result, load

__all__ = ["report", "result_html", "batch_html"]

_STYLE = """
body{font-family:system-ui,sans-serif;margin:2em auto;max-width:1100px;color:#222}
h1{font-size:1.5em} h2{font-size:1.2em;margin-top:2em;border-bottom:1px solid #ccc}
table{border-collapse:collapse;font-size:.85em;margin:.5em 0}
td,th{border:1px solid #ddd;padding:2px 8px;text-align:left;vertical-align:top}
th{background:#f2f2f2} table.sortable th{cursor:pointer} img{max-width:100%}
.bad{color:#b00;font-weight:bold} pre{background:#f7f7f7;padding:1em;overflow-x:auto;font-size:.8em}
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


def _png(fig, dpi: int = 100) -> str:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi)
    return "data:image/png;base64," + base64.b64encode(buf.getvalue()).decode("ascii")


def _table(header: list[str], rows: list[list[Any]], *, sortable: bool = False) -> str:
    e = html.escape
    head = "".join(f"<th>{e(str(h))}</th>" for h in header)
    body = "".join("<tr>" + "".join(f"<td>{e(_fmt(v))}</td>" for v in row) + "</tr>" for row in rows)
    cls = ' class="sortable"' if sortable else ""
    return f"<table{cls}><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"


def _fmt(v: Any) -> str:
    if isinstance(v, float):
        return f"{v:.6g}"
    return str(v)


def _page(title: str, body: str) -> str:
    return (f"<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>{html.escape(title)}</title>"
            f"<style>{_STYLE}</style></head><body>\n{body}\n<script>{_SORT_JS}</script></body></html>\n")


def result_html(r: Result | str | os.PathLike, *, dpi: int = 100) -> str:
    """The page of one run: what ran, its summary, its events and every figure."""
    from . import plot
    r = r if isinstance(r, Result) else load(r)
    e = html.escape
    s = r.summary
    verdict = (f"<p class=\"bad\">tripped at {s.get('trip_time_s', 0):.2f} s: {e(str(s.get('trip_reason')))}</p>"
               if s.get("tripped") else "<p>no trip</p>")
    parts = [f"<h1>{e(r.scenario_name)} (seed {r.seed})</h1>",
             f"<p>packsim {e(str(r.version))}, {r.n_samples} samples, {r.n_cells} cells"
             + (f", from {e(str(r.source))}" if r.source else "") + "</p>", verdict,
             "<h2>Summary</h2>", _table(["quantity", "value"], [[k, v] for k, v in s.items()]),
             f"<h2>Events ({len(r.events)})</h2>",
             _table(["time_s", "kind", "detail"], [[ev["time_s"], ev["kind"], ev["detail"]] for ev in r.events],
                    sortable=True),
             "<h2>Figures</h2>"]
    figures = [plot.bms_timeline(r), plot.cells(r, "voltage"), plot.cells(r, "temperature"), plot.current_soc(r),
               plot.measured_vs_truth(r), plot.balancing(r)]
    parts += [f"<p><img alt=\"figure {i + 1}\" src=\"{_png(f, dpi)}\"></p>" for i, f in enumerate(figures) if f]
    parts += ["<h2>Scenario</h2>", f"<details><summary>scenario YAML</summary><pre>{e(r.scenario_yaml)}</pre>"
                                   "</details>"]
    return _page(f"packsim: {r.scenario_name}", "\n".join(parts))


def _read_summary_csv(path: str) -> tuple[list[str], list[list[Any]]]:
    with open(path, newline="", encoding="utf-8") as f:
        rows = list(csv.reader(f))
    if not rows:
        raise ValueError(f"{path}: empty summary.csv")

    def value(x: str) -> Any:
        try:
            return float(x) if x.strip() else x
        except ValueError:
            return x
    return rows[0], [[value(x) for x in row] for row in rows[1:]]


def batch_html(folder: str | os.PathLike, *, dpi: int = 100) -> str:
    """The page of a sweep: its summary.csv as a sortable table and the distribution of
    every numeric column over the cases that ran."""
    from .plot import _figure
    folder = os.fspath(folder)
    path = os.path.join(folder, "summary.csv")
    if not os.path.isfile(path):
        raise FileNotFoundError(f"{folder}: no summary.csv (not a packsim batch folder)")
    header, rows = _read_summary_csv(path)
    numeric = [j for j, h in enumerate(header)
               if rows and all(isinstance(row[j], float) for row in rows if j < len(row) and row[j] != "")
               and any(j < len(row) and row[j] != "" for row in rows)]
    figs = []
    for j in numeric:
        values = np.array([row[j] for row in rows if j < len(row) and row[j] != ""], dtype=float)
        if np.unique(values).size < 2:
            continue
        fig = _figure(5, 3)
        ax = fig.subplots()
        ax.hist(values, bins=min(20, max(5, values.size // 2)), color="C0", alpha=0.8)
        ax.set_xlabel(header[j])
        ax.set_ylabel("cases")
        ax.set_title(f"{header[j]} over {values.size} cases", fontsize=9)
        figs.append(fig)
    e = html.escape
    parts = [f"<h1>Sweep {e(os.path.basename(os.path.abspath(folder)))}</h1>",
             f"<p>{len(rows)} cases from {e(path)}; click a column to sort.</p>",
             _table(header, rows, sortable=True), f"<h2>Distributions ({len(figs)})</h2>"]
    parts += [f"<img alt=\"{e(f.axes[0].get_xlabel())}\" src=\"{_png(f, dpi)}\" style=\"max-width:49%\">"
              for f in figs]
    return _page("packsim sweep", "\n".join(parts))


def report(source: Result | str | os.PathLike, output: str | os.PathLike, *, dpi: int = 100) -> str:
    """Write the HTML page of a result (a Result or a result file) or of a batch folder
    (holding summary.csv) to output; returns its path. Written under a temporary name
    and renamed when complete."""
    is_batch = not isinstance(source, Result) and os.path.isdir(os.fspath(source))
    page = batch_html(source, dpi=dpi) if is_batch else result_html(source, dpi=dpi)
    output = os.fspath(output)
    os.makedirs(os.path.dirname(os.path.abspath(output)), exist_ok=True)
    with replaced_when_done(output) as tmp, open(tmp, "w", encoding="utf-8") as f:
        f.write(page)
    return output


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="packsim report", description="one self-contained HTML page of a run or sweep")
    ap.add_argument("source", help="result HDF5 file, or a batch output folder (with summary.csv)")
    ap.add_argument("-o", "--output", required=True, help="HTML file to write")
    ap.add_argument("--dpi", type=int, default=100)
    a = ap.parse_args(argv)
    from .plot import _matplotlib_or_error
    if not _matplotlib_or_error("packsim report"):
        return 1
    if not os.path.exists(a.source):
        print(f"packsim report: error: {a.source}: no such result file or batch folder", file=sys.stderr)
        return 2
    try:
        print(report(a.source, a.output, dpi=a.dpi))
    except (OSError, ValueError, KeyError) as e:
        print(f"packsim report: error: {e}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
