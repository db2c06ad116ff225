"""`packsim export result.h5 --format csv|mat|parquet` and packsim.export: each format
read back with its own reader holds exactly the stored values."""
from __future__ import annotations

import json
import os
import subprocess
import sys

import numpy as np
import pandas as pd
import pytest

import packsim


@pytest.fixture(scope="module")
def stored(tmp_path_factory):
    out = tmp_path_factory.mktemp("export") / "bench.h5"
    packsim.run("bench_6s_ncr18650_2C", seed=4).save(out)
    return out


def _env():
    return dict(os.environ, PACKSIM_PYTHON=sys.executable)


def test_csv_holds_the_samples_events_and_summary(cli, stored, tmp_path):
    done = subprocess.run([str(cli), "export", str(stored), "--format", "csv", "-o", str(tmp_path / "csv")],
                          capture_output=True, text=True, env=_env())
    assert done.returncode == 0, done.stderr
    r = packsim.load(stored)
    samples = pd.read_csv(tmp_path / "csv" / "samples.csv", index_col="time_s")
    np.testing.assert_array_equal(samples.index.to_numpy(), r.time_s)
    np.testing.assert_array_equal(samples["truth/cell_voltage_V[6]"].to_numpy(), r["truth/cell_voltage_V"][:, 5])
    np.testing.assert_array_equal(samples["measured/current_mA"].to_numpy(), r["measured/current_mA"])
    events = pd.read_csv(tmp_path / "csv" / "events.csv")
    assert list(events["kind"]) == [e["kind"] for e in r.events]
    summary = pd.read_csv(tmp_path / "csv" / "summary.csv")
    got = dict(zip(summary["name"], summary["value"]))
    assert float(got["energy_delivered_Wh"]) == r.summary["energy_delivered_Wh"]


def test_mat_holds_every_dataset(stored, tmp_path):
    sio = pytest.importorskip("scipy.io")
    out = tmp_path / "bench.mat"
    assert packsim.export(stored, "mat", out) == [str(out)]
    m = sio.loadmat(out, squeeze_me=False)
    r = packsim.load(stored)
    for path, a in r.datasets.items():
        if path == "events":
            continue
        got = m[path.replace("/", "_")]
        want = a.reshape(-1, 1) if a.ndim == 1 else a
        np.testing.assert_array_equal(got, want, err_msg=path)
    assert str(m["attrs"]["scenario_name"][0, 0][0]) == r.scenario_name


def test_parquet_holds_the_samples_and_the_metadata(cli, stored, tmp_path):
    pq = pytest.importorskip("pyarrow.parquet")
    out = tmp_path / "bench.parquet"
    done = subprocess.run([str(cli), "export", str(stored), "--format", "parquet", "-o", str(out)],
                          capture_output=True, text=True, env=_env())
    assert done.returncode == 0, done.stderr
    r = packsim.load(stored)
    df = pd.read_parquet(out)
    want = r.to_dataframe("samples")
    assert list(df.columns) == list(want.columns)
    np.testing.assert_array_equal(df.to_numpy(), want.to_numpy())
    meta = pq.read_schema(out).metadata
    assert json.loads(meta[b"packsim.summary"]) == r.summary
    assert [e["kind"] for e in json.loads(meta[b"packsim.events"])] == [e["kind"] for e in r.events]


def test_bad_format_and_missing_file_are_clear_errors(cli, stored, tmp_path):
    done = subprocess.run([str(cli), "export", str(stored), "--format", "xlsx"], capture_output=True, text=True)
    assert done.returncode != 0 and "xlsx" in done.stderr and "csv" in done.stderr
    done = subprocess.run([str(cli), "export", str(tmp_path / "none.h5"), "--format", "csv"], capture_output=True,
                          text=True)
    assert done.returncode == 2 and "no such result file" in done.stderr
    with pytest.raises(ValueError, match="csv, mat, parquet"):
        packsim.export(stored, "xlsx")
    assert not [p for p in tmp_path.iterdir()]
