"""`packsim report`: one self-contained HTML page of a run (summary, events, figures as
embedded PNG) or of a batch folder (summary.csv as a sortable table, distributions)."""
from __future__ import annotations

import base64
import csv
import os
import re
import subprocess
import sys
from html.parser import HTMLParser

import packsim


class _Page(HTMLParser):
    def __init__(self):
        super().__init__()
        self.images, self.links, self.cells, self.tables = [], [], [], 0

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "img":
            self.images.append(a.get("src", ""))
        if tag in ("link", "script") and (a.get("href") or a.get("src")):
            self.links.append(a.get("href") or a.get("src"))
        if tag == "table":
            self.tables += 1

    def handle_data(self, data):
        self.cells.append(data)


def _parse(path) -> _Page:
    p = _Page()
    p.feed(open(path, encoding="utf-8").read())
    return p


def test_report_of_a_run_is_self_contained(cli, tmp_path):
    src = tmp_path / "hd.h5"
    packsim.run("a_host_dead").save(src)
    out = tmp_path / "share" / "report.html"
    done = subprocess.run([str(cli), "report", str(src), "-o", str(out)], capture_output=True, text=True,
                          env=dict(os.environ, PACKSIM_PYTHON=sys.executable))
    assert done.returncode == 0, done.stderr
    page = _parse(out)
    assert not page.links  # nothing fetched from elsewhere
    assert len(page.images) >= 5
    for src_ in page.images:
        assert src_.startswith("data:image/png;base64,")
        assert base64.b64decode(src_.split(",", 1)[1])[:8] == b"\x89PNG\r\n\x1a\n"
    text = " ".join(page.cells)
    r = packsim.load(src)
    assert "a_host_dead" in text and "energy_delivered_Wh" in text
    for ev in r.events:  # every event is in the table
        assert ev["detail"] in text


def test_report_of_a_batch_folder_has_the_sorted_table_and_distributions(tmp_path):
    sweep = {"base": packsim.bundled_scenarios("bench_6s_ncr18650_2C.yaml")[0],
             "output_dir": str(tmp_path / "sweep"),
             "grid": {"pack.cell.capacity_Ah": [2.8, 3.0, 3.2]}}
    res = packsim.batch(sweep)
    assert res.ok
    out = packsim.report(tmp_path / "sweep", tmp_path / "sweep.html")
    page = _parse(out)
    html_text = open(out, encoding="utf-8").read()
    assert 'class="sortable"' in html_text and "addEventListener" in html_text
    with open(res.csv_path, newline="") as f:
        rows = list(csv.reader(f))
    for name in rows[0]:
        assert name in page.cells  # every summary.csv column is a header
    assert len(re.findall(r"<tr>", html_text)) == len(rows)  # header + one row per case
    assert page.images and all(s.startswith("data:image/png;base64,") for s in page.images)


def test_report_errors_are_clear(cli, tmp_path):
    done = subprocess.run([str(cli), "report", str(tmp_path / "none.h5"), "-o", str(tmp_path / "x.html")],
                          capture_output=True, text=True)
    assert done.returncode == 2 and "no such result file or batch folder" in done.stderr
    assert not (tmp_path / "x.html").exists()
