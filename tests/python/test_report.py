"""`packsim report`: one self-contained HTML page of a run (verdict, margins, energy, the
interactive figure, filterable events, the scenario) or of a batch folder (responses to
the swept inputs, the cases as a sortable table)."""
from __future__ import annotations

import csv
import json
import os
import re
import subprocess
import sys
from html.parser import HTMLParser

import numpy as np
import pytest

import packsim
from packsim import run_facts, sweep_figure
from packsim.report import result_html

pytest.importorskip("plotly")


class _Page(HTMLParser):
    def __init__(self):
        super().__init__()
        self.images, self.links, self.cells, self.tables, self.ids = [], [], [], 0, {}
        self._in = None

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "img":
            self.images.append(a.get("src", ""))
        if tag in ("link", "script", "iframe") and (a.get("href") or a.get("src")):
            self.links.append(a.get("href") or a.get("src"))
        if tag == "table":
            self.tables += 1
        if a.get("id"):
            self.ids[a["id"]] = tag

    def handle_data(self, data):
        self.cells.append(data)


def _parse(path) -> tuple[_Page, str]:
    text = open(path, encoding="utf-8").read()
    p = _Page()
    p.feed(text)
    return p, text


def _figure_json(text: str, div_id: str) -> dict:
    """The data and layout plotly's to_html passes to Plotly.newPlot for div_id."""
    m = re.search(r'Plotly\.newPlot\(\s*"' + div_id + r'",\s*(\[.*?\]),\s*(\{.*?\}),\s*\{', text, re.S)
    assert m, f"no Plotly.newPlot for {div_id}"
    return {"data": json.loads(m.group(1)), "layout": json.loads(m.group(2))}


@pytest.fixture(scope="module")
def hot(tmp_path_factory):
    path = tmp_path_factory.mktemp("hot") / "hot.h5"
    packsim.run("a_hot_cell").save(path)
    return path


def test_run_page_is_self_contained_and_says_the_verdict_first(cli, hot, tmp_path):
    out = tmp_path / "share" / "report.html"
    done = subprocess.run([str(cli), "report", str(hot), "-o", str(out)], capture_output=True, text=True,
                          env=dict(os.environ, PACKSIM_PYTHON=sys.executable))
    assert done.returncode == 0, done.stderr
    assert "Warning" not in done.stderr  # no runpy RuntimeWarning (or any other)
    page, text = _parse(out)
    assert not page.links and not page.images  # nothing fetched from elsewhere, no PNG
    assert "Plotly.newPlot" in text and len(text) > 3_000_000  # the library is inlined
    r = packsim.load(hot)
    v = run_facts.verdict(r)
    assert v.tripped and v.protection == "overtemperature"  # the scenario's hot cell
    body = " ".join(page.cells)
    # the verdict comes before the margins, the figure, the events and the scenario
    order = [text.index(x) for x in ('id="verdict"', 'id="margins"', 'id="energy"', 'id="run-figure"',
                                     'id="events"', 'id="scenario"')]
    assert order == sorted(order)
    assert v.headline in body and all(line in body for line in v.lines)
    for ev in r.events:  # every event is in the table
        assert str(ev["detail"]) in body
    assert "<details>" not in text  # the scenario is shown, not collapsed
    assert r.scenario_yaml.splitlines()[2] in body


def test_run_page_margins_table_has_a_row_per_limit_with_the_data_extremes(hot):
    r = packsim.load(hot)
    page_text = result_html(r)
    rows = re.search(r'<table id="margins">(.*?)</table>', page_text, re.S).group(1)
    body_rows = re.findall(r"<tr>(.*?)</tr>", rows.split("<tbody>")[1])
    limits = [k for k in r.attrs["bms"] if k.startswith("limit_")]
    assert len(body_rows) == len(limits) == 6
    hot_row = next(x for x in body_rows if "over-temperature" in x and "under" not in x)
    t_max = float(r["truth/cell_temp_C"].max())
    assert f"{t_max:.4g} °C" in hot_row and "past for" in hot_row and "510.94 s" in hot_row
    cell = int(np.argmax(r["truth/cell_temp_C"].max(axis=0))) + 1
    assert f"cell {cell}" in hot_row


def test_run_figure_has_every_panel_on_one_time_axis_with_events_and_a_cursor(hot):
    fig = packsim.plot.run_figure(hot)
    layout = fig.layout.to_plotly_json()
    assert all(tr.xaxis in (None, "x") for tr in fig.data)  # one x axis: zoom and cursor shared
    yaxes = [k for k in layout if k.startswith("yaxis")]
    assert len(yaxes) >= 8
    shapes = layout["shapes"]
    assert [s["name"] for s in shapes if s["name"] == "cursor"] == ["cursor"]
    r = packsim.load(hot)
    marks = {round(s["x0"], 6) for s in shapes if s["name"] != "cursor"}
    assert 300.0 in marks and 510.94 in marks  # the injection and the trip (time in s: a 10-minute run)
    heat = [tr for tr in fig.data if tr.type == "heatmap"]
    assert len(heat) == 2 and np.asarray(heat[0].z).shape[0] == r.n_series


def _sweep(tmp_path, **axes):
    sweep = {"base": packsim.bundled_scenarios("bench_6s_ncr18650_2C.yaml")[0],
             "output_dir": str(tmp_path / "sweep")}
    sweep.update(axes)
    res = packsim.batch(sweep)
    assert res.ok
    return tmp_path / "sweep", res


def test_sweep_page_plots_outputs_over_a_2d_grid_and_leaves_identifiers_out(tmp_path):
    folder, res = _sweep(tmp_path, grid={"pack.cell.capacity_Ah": [2.8, 3.2], "ambient.temp_C": [10, 40]})
    t = sweep_figure.read(folder)
    assert t.inputs == ["pack.cell.capacity_Ah", "ambient.temp_C"] and t.swept == t.inputs
    for ident in ("case", "status", "file", "min_cell", "hottest_cell", "trip_reason"):
        assert ident not in t.outputs and t.left_out[ident] == "identifier"
    assert t.left_out.get("limit_reached") == "the same in every case"  # every case ran to its limit
    assert "energy_delivered_Wh" in t.outputs
    xs, ys, z = sweep_figure.grid_z(t, "pack.cell.capacity_Ah", "ambient.temp_C", "energy_delivered_Wh")
    with open(res.csv_path, newline="") as f:
        rows = list(csv.DictReader(f))
    for row in rows:  # z[i, j] is the case at (ys[i], xs[j])
        i = list(ys).index(float(row["ambient.temp_C"]))
        j = list(xs).index(float(row["pack.cell.capacity_Ah"]))
        assert z[i, j] == float(row["energy_delivered_Wh"])
    out = packsim.report(folder, tmp_path / "sweep.html")
    page, text = _parse(out)
    assert len(re.findall(r'<div class="cell">', text)) == len(t.outputs)  # a heat-map per output
    assert 'id="cases"' in text and 'class="sortable"' in text
    assert len(re.findall(r"<tr>", text)) == len(rows) + 1
    figs = [_figure_json(text, f"sweep-{k}") for k in range(len(t.outputs))]
    assert all(f["data"][0]["type"] == "heatmap" for f in figs)


def test_monte_carlo_sweep_shows_distributions_and_rank_correlation(tmp_path):
    folder, _ = _sweep(tmp_path, monte_carlo={"samples": 6, "master_seed": 3})
    t = sweep_figure.read(folder)
    assert t.monte_carlo and t.swept == []
    titles = [title for title, _ in sweep_figure.figures(t)]
    assert titles[: len(t.outputs)] == [f"distribution of {o}" for o in t.outputs]
    assert titles[-1] == "rank correlation between outputs"
    a, b = t.column("energy_delivered_Wh"), t.column("charge_delivered_Ah")
    ra, rb = np.argsort(np.argsort(a)), np.argsort(np.argsort(b))  # no ties in these
    expect = np.corrcoef(ra, rb)[0, 1]
    assert sweep_figure.rank_correlation(a, b) == pytest.approx(expect)


def test_a_1d_sweep_draws_lines_in_input_order(tmp_path):
    folder, _ = _sweep(tmp_path, grid={"pack.cell.capacity_Ah": [3.2, 2.8, 3.0]})
    t = sweep_figure.read(folder)
    title, fig = sweep_figure.figures(t)[0]
    assert title == f"{t.outputs[0]} vs pack.cell.capacity_Ah"
    assert list(fig.data[0].x) == [2.8, 3.0, 3.2]


def test_a_sweep_does_not_plot_never_as_a_time(tmp_path):
    """A case that did not trip has trip_time_s 0, one that never balanced
    balance_balanced_s -1: neither is a time, so neither is plotted (NaN)."""
    (tmp_path / "summary.csv").write_text(
        "case,hardware.balancing.resistor_ohm,status,tripped,trip_time_s,balance_balanced_s,energy_delivered_Wh\n"
        "0000,33,ok,0,0,-1,10.5\n0001,47,ok,1,120.5,5000,9.5\n0002,68,ok,0,0,7000,9.0\n")
    t = sweep_figure.read(tmp_path)
    assert np.isnan(t.column("trip_time_s")[[0, 2]]).all() and t.column("trip_time_s")[1] == 120.5
    bal = t.column("balance_balanced_s")
    assert np.isnan(bal[0]) and list(bal[1:]) == [5000.0, 7000.0]
    title, fig = [f for f in sweep_figure.figures(t) if f[0] == "balance_balanced_s vs hardware.balancing.resistor_ohm"][0]
    assert [y for y in fig.data[0].y if y == y] == [5000.0, 7000.0]  # the -1 is not on the line


def test_a_sweep_does_not_plot_the_run_end_as_the_time_a_limit_was_reached(tmp_path):
    """A case whose cells never reached their limit (limit_reached 0) carries the run's
    end in limit_time_s (the energy left is accounted there): not a time the limit was
    reached, so not plotted. Was: plotted at the run's end (7200 s in a resistor sweep of
    2-hour charges, none reaching a limit), reading as 'reached at 7200 s'."""
    (tmp_path / "summary.csv").write_text(
        "case,pack.cell.capacity_Ah,status,limit_reached,limit_time_s,energy_delivered_Wh\n"
        "0000,4,ok,1,3000.5,10.5\n0001,5,ok,0,7200,11.5\n0002,6,ok,1,6000,12.0\n")
    t = sweep_figure.read(tmp_path)
    got = t.column("limit_time_s")
    assert got[0] == 3000.5 and np.isnan(got[1]) and got[2] == 6000.0
    title, fig = [f for f in sweep_figure.figures(t) if f[0] == "limit_time_s vs pack.cell.capacity_Ah"][0]
    assert [y for y in fig.data[0].y if y == y] == [3000.5, 6000.0]


def test_a_report_never_writes_over_what_it_reads(cli, tmp_path):
    # Was: `packsim report r.h5 -o r.h5` wrote the page over the result file, exit 0.
    import shutil
    src = tmp_path / "r.h5"
    packsim.run("bench_6s_ncr18650_2C", {"run.duration_s": 5}).save(src)
    kept = src.read_bytes()
    done = subprocess.run([str(cli), "report", str(src), "-o", str(src)], capture_output=True, text=True,
                          env=dict(os.environ, PACKSIM_PYTHON=sys.executable))
    assert done.returncode == 2 and "is an input" in done.stderr, done.stderr
    assert src.read_bytes() == kept
    sweep = tmp_path / "sweep"
    sweep.mkdir()
    shutil.copy(src, sweep / "case_0000.h5")
    (sweep / "summary.csv").write_text("case,status,energy_delivered_Wh\n0000,ok,1.0\n")
    for target in ("summary.csv", "case_0000.h5"):
        with pytest.raises(ValueError, match="is an input"):
            packsim.report(sweep, sweep / target)
    assert (sweep / "case_0000.h5").read_bytes() == kept


def test_report_errors_are_clear(cli, tmp_path):
    done = subprocess.run([str(cli), "report", str(tmp_path / "none.h5"), "-o", str(tmp_path / "x.html")],
                          capture_output=True, text=True)
    assert done.returncode == 2 and "no such result file or batch folder" in done.stderr
    assert not (tmp_path / "x.html").exists()
    (tmp_path / "notabatch").mkdir()
    done = subprocess.run([str(cli), "report", str(tmp_path / "notabatch"), "-o", str(tmp_path / "y.html")],
                          capture_output=True, text=True, env=dict(os.environ, PACKSIM_PYTHON=sys.executable))
    assert done.returncode == 2 and "no summary.csv" in done.stderr


def test_bad_arguments_name_themselves(tmp_path):
    """packsim.report(3, "x.html") was "TypeError: expected str, bytes or os.PathLike
    object, not int" from deep inside os.fspath, naming neither argument."""
    with pytest.raises(TypeError, match=r"^source must be a Result, a result file or a batch folder, got int$"):
        packsim.report(3, tmp_path / "x.html")
    with pytest.raises(TypeError, match=r"^output must be a path, got int$"):
        packsim.report(str(tmp_path), 5)
