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
    # Was "expected str, bytes or os.PathLike object, not int": which argument?
    with pytest.raises(TypeError, match="output must be a path, got int"):
        packsim.export(stored, "csv", 3)
    with pytest.raises(TypeError, match="result must be a packsim.Result or a result file path, got int"):
        packsim.export(5, "csv")
    assert not [p for p in tmp_path.iterdir()]


def test_the_format_comes_from_the_output_file_or_the_error_says_what_to_give(cli, stored, tmp_path):
    pytest.importorskip("scipy")
    out = tmp_path / "bench.mat"
    done = subprocess.run([str(cli), "export", str(stored), "-o", str(out)], capture_output=True, text=True, env=_env())
    assert done.returncode == 0, done.stderr
    assert out.is_file()
    done = subprocess.run([str(cli), "export", str(stored), "-o", str(tmp_path / "bench.csv")], capture_output=True,
                          text=True, env=_env())
    assert done.returncode == 2
    assert "a CSV export writes a folder" in done.stderr and "-o bench_csv" in done.stderr, done.stderr
    done = subprocess.run([str(cli), "export", str(stored)], capture_output=True, text=True, env=_env())
    assert done.returncode == 2 and "--format missing: csv, mat or parquet" in done.stderr, done.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bench.mat"]


@pytest.fixture(scope="module")
def with_tables(tmp_path_factory):
    """Results with tables besides the events: the vehicle's laps (two, one complete) and
    the monitor-bus trace (2 s of it)."""
    d = tmp_path_factory.mktemp("export_tables")
    packsim.run("vehicle/eco_marathon_12s_circuit", {"run.duration_s": 260}).save(d / "laps.h5")
    packsim.run("bench_6s_ncr18650_2C", {"run.duration_s": 2, "output.bus_trace": True}).save(d / "trace.h5")
    return {"vehicle/laps": d / "laps.h5", "bus_trace": d / "trace.h5"}


def _same_table(got: dict, want: np.ndarray, where: str) -> None:
    assert sorted(got) == sorted(want.dtype.names), where
    for n in want.dtype.names:
        if want.dtype[n].kind == "O":
            assert [str(x) for x in got[n]] == [str(x) for x in want[n]], (where, n)
        else:
            np.testing.assert_array_equal(np.asarray(got[n], dtype=want.dtype[n]), want[n], err_msg=f"{where} {n}")


@pytest.mark.parametrize("path", ["vehicle/laps", "bus_trace"])
def test_every_table_is_exported_in_each_format(with_tables, path, tmp_path):
    stored = with_tables[path]
    r = packsim.load(stored)
    want = r.datasets[path]
    assert len(want) >= 2 and want.dtype.names  # the case: a table the samples do not hold
    name = path.replace("/", "_")
    files = packsim.export(stored, "csv", tmp_path / "csv")
    assert sorted(os.path.basename(f) for f in files) == sorted(["samples.csv", "events.csv", "summary.csv", name + ".csv"])
    df = pd.read_csv(tmp_path / "csv" / f"{name}.csv", keep_default_na=False)
    _same_table({n: df[n].to_numpy() for n in df.columns}, want, "csv")

    sio = pytest.importorskip("scipy.io")
    packsim.export(stored, "mat", tmp_path / "t.mat")
    m = sio.loadmat(tmp_path / "t.mat", squeeze_me=True, simplify_cells=True)
    _same_table({n: np.atleast_1d(v) for n, v in m[name].items()}, want, "mat")

    pq = pytest.importorskip("pyarrow.parquet")
    packsim.export(stored, "parquet", tmp_path / "t.parquet")
    tables = json.loads(pq.read_schema(tmp_path / "t.parquet").metadata[b"packsim.tables"])
    assert list(tables) == [path]
    _same_table({n: [row[n] for row in tables[path]] for n in want.dtype.names}, want, "parquet")


@pytest.fixture(scope="module")
def not_results(tmp_path_factory):
    """Files a user may hand to export/plot/report by mistake: a CSV (not HDF5) and an
    HDF5 file packsim did not write (no /time_s, no packsim_version)."""
    h5py = pytest.importorskip("h5py")
    d = tmp_path_factory.mktemp("not_results")
    (d / "summary.csv").write_text("name,value\nduration_s,1\n")
    with h5py.File(d / "other.h5", "w") as f:
        f.create_dataset("x", data=[1.0, 2.0])
    return [d / "summary.csv", d / "other.h5"]


def test_a_file_that_is_no_result_is_one_error_naming_it(not_results):
    # Was: the CSV an OSError without the file's name ("file signature not found"), the
    # other HDF5 file loaded as an empty Result whose export died in a KeyError 'time_s'.
    for path in not_results:
        with pytest.raises(packsim.NotAResultError, match=f"{path.name}: not a packsim result file"):
            packsim.load(path)
        with pytest.raises(ValueError, match=f"{path.name}: not a packsim result file"):
            packsim.export(path, "csv", path.parent / "out")
        assert not (path.parent / "out").exists()


@pytest.mark.parametrize("command", [["export", "--format", "csv"], ["plot"]])
def test_the_commands_refuse_a_file_that_is_no_result_with_exit_2(cli, not_results, command, tmp_path):
    # Was: export exited 1 (a CSV) or 1 with a Python traceback (another HDF5 file); plot
    # printed a traceback for the HDF5 file.
    for path in not_results:
        args = [str(cli), command[0], str(path), *command[1:], "-o", str(tmp_path / "out")]
        done = subprocess.run(args, capture_output=True, text=True, env=_env())
        assert done.returncode == 2, (command, path.name, done.stderr)
        assert f"{path}: not a packsim result file" in done.stderr, done.stderr
        assert "Traceback" not in done.stderr, done.stderr
        assert not (tmp_path / "out").exists()


def test_parquet_refuses_a_table_too_big_for_its_footer(with_tables, tmp_path, monkeypatch):
    # The tables go into the Parquet footer as JSON, which Arrow refuses beyond 100 MB:
    # a 40-minute race's bus trace (eco_marathon_12s_circuit, output.bus_trace) made a
    # 432 MB file that pyarrow could not open ("Couldn't deserialize thrift: ...
    # Exceeded size limit"), with exit 0. The limit is lowered here so the 2-s trace
    # passes it; the export must then say so and write nothing.
    export_module = sys.modules["packsim.export"]  # packsim.export is the function
    pq = pytest.importorskip("pyarrow.parquet")
    stored = with_tables["bus_trace"]
    out = tmp_path / "t.parquet"
    packsim.export(stored, "parquet", out)  # as it is: within the limit, and readable
    footer = sum(len(k) + len(v) for k, v in pq.read_schema(out).metadata.items())
    out.unlink()
    monkeypatch.setattr(export_module, "_PARQUET_METADATA_LIMIT", footer // 2, raising=False)
    rows = len(packsim.load(stored).datasets["bus_trace"])
    with pytest.raises(ValueError, match=rf"bus_trace \({rows:,} rows\).*nothing written; export it as csv"):
        packsim.export(stored, "parquet", out)
    assert sorted(os.listdir(tmp_path)) == []


@pytest.fixture(scope="module")
def batch_case(tmp_path_factory):
    """A batch case's file, which holds the drawn cell values (/inputs, on the `cell`
    axis), recorded for 11 s at 1 s: 12 samples of a 12-cell pack."""
    d = tmp_path_factory.mktemp("export_inputs")
    res = packsim.batch({"base": packsim.default_scenario(), "grid": {"run.duration_s": [11]}}, output_dir=d)
    r = packsim.load(res.paths[0])
    assert r.n_samples == r.n_cells == 12  # the case: as many samples as cells
    return res.paths[0]


def test_a_batch_cases_drawn_inputs_are_exported_per_cell_not_as_samples(batch_case, tmp_path):
    # Was: csv and parquet left /inputs out (the samples table takes channels over time
    # only) -- and with as many samples as cells, wrote each per-cell value as a column
    # over time ('inputs/cell_capacity_Ah' at t = 0, 1, 2 ... s).
    r = packsim.load(batch_case)
    inputs = {k.split("/", 1)[1]: a for k, a in r.datasets.items() if k.startswith("inputs/")}
    assert sorted(inputs) == ["cell_capacity_Ah", "cell_initial_soc", "cell_r0_scale", "cell_self_discharge_A"]
    assert not [c for c in r.to_dataframe("samples").columns if c.startswith("inputs")]

    files = packsim.export(batch_case, "csv", tmp_path / "csv")
    assert os.path.basename(files[-1]) == "inputs.csv"
    samples = pd.read_csv(tmp_path / "csv" / "samples.csv")
    assert not [c for c in samples.columns if c.startswith("inputs")]
    got = pd.read_csv(tmp_path / "csv" / "inputs.csv")
    assert list(got.columns) == ["cell", *sorted(inputs)]
    np.testing.assert_array_equal(got["cell"], np.arange(1, 13))
    for name, a in inputs.items():
        np.testing.assert_array_equal(got[name].to_numpy(), a, err_msg=name)

    pq = pytest.importorskip("pyarrow.parquet")
    packsim.export(batch_case, "parquet", tmp_path / "t.parquet")
    assert not [c for c in pq.read_schema(tmp_path / "t.parquet").names if c.startswith("inputs")]
    rows = json.loads(pq.read_schema(tmp_path / "t.parquet").metadata[b"packsim.tables"])["inputs"]
    assert [row["cell"] for row in rows] == list(range(1, 13))
    for name, a in inputs.items():
        assert [row[name] for row in rows] == a.tolist(), name


def test_a_csv_export_never_deletes_the_users_files(cli, stored, tmp_path):
    # Was: a CSV export replaced whatever folder -o named, whole: `-o data` deleted
    # data/notes.txt and data/logs/, and `-o .` deleted the current folder's files, the
    # result file among them, then failed ("Invalid argument: '.'", exit 1).
    data = tmp_path / "data"
    (data / "logs").mkdir(parents=True)
    (data / "notes.txt").write_text("mine")
    (data / "logs" / "cycler.csv").write_text("time_s,current_A\n")
    done = subprocess.run([str(cli), "export", str(stored), "--format", "csv", "-o", str(data)],
                          capture_output=True, text=True, env=_env())
    assert done.returncode == 2, done.stderr
    assert "is not an earlier CSV export (it holds logs, notes.txt): nothing written" in done.stderr, done.stderr
    assert sorted(p.name for p in data.rglob("*")) == ["cycler.csv", "logs", "notes.txt"]

    here = tmp_path / "here"
    here.mkdir()
    result = here / "race.h5"
    result.write_bytes(stored.read_bytes())
    (here / "notes.txt").write_text("mine")
    done = subprocess.run([str(cli), "export", "race.h5", "--format", "csv", "-o", "."], cwd=here,
                          capture_output=True, text=True, env=_env())
    assert done.returncode == 2 and "is the current folder or holds it" in done.stderr, done.stderr
    assert sorted(p.name for p in here.iterdir()) == ["notes.txt", "race.h5"]
    assert result.read_bytes() == stored.read_bytes()

    # A folder of other CSV files (a user's cycler logs) is no export either.
    with pytest.raises(ValueError, match=r"logs exists and is not an earlier CSV export \(no samples.csv, events.csv, summary.csv\)"):
        packsim.export(stored, "csv", data / "logs")
    assert sorted(p.name for p in (data / "logs").iterdir()) == ["cycler.csv"]


def test_an_earlier_csv_export_is_replaced_whole(stored, tmp_path):
    out = tmp_path / "csv"
    packsim.export(stored, "csv", out)
    (out / "bus_trace.csv").write_text("from another run\n")  # a table this result lacks
    packsim.export(stored, "csv", out)
    assert sorted(p.name for p in out.iterdir()) == ["events.csv", "samples.csv", "summary.csv"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["csv"]  # no temporary left


def test_an_export_never_replaces_the_result_file(stored, tmp_path):
    # Was: `packsim export race.h5 --format mat -o race.h5` wrote the .mat over the result.
    result = tmp_path / "race.h5"
    result.write_bytes(stored.read_bytes())
    for fmt in ("mat", "parquet"):
        with pytest.raises(ValueError, match=r"-o .*race.h5 is an input \(.*race.h5\): writing it would destroy it"):
            packsim.export(result, fmt, result)
    assert result.read_bytes() == stored.read_bytes()
    with pytest.raises(ValueError, match="is a folder: a mat export is one file"):
        packsim.export(result, "mat", tmp_path)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["race.h5"]
