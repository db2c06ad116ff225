"""packsim.batch: the sweep expands as documented, the local run is the CLI's `packsim
batch` byte for byte, a Dask cluster gives the very same files and table, finished cases
are skipped on a rerun, and a failing case is recorded while the others finish."""
from __future__ import annotations

import csv
import math
import os
import pickle
import subprocess
import sys
from pathlib import Path

import pytest

import packsim

SPREAD = "  spread: {capacity_rel_sd: 0.05, r0_rel_sd: 0.05, initial_soc_sd: 0.01}\n"

SWEEP = """\
name: capsweep
base: base.yaml
grid:
  pack.cell.capacity_Ah: [2.0, 3.0]
monte_carlo: {samples: 2, master_seed: 7}
"""


def splitmix64_seed(master: int, sample: int) -> int:
    """The documented Monte Carlo seed, written out independently of the C++."""
    mask = (1 << 64) - 1
    z = (master + 0x9E3779B97F4A7C15 * (sample + 1)) & mask
    z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & mask
    z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & mask
    return (z ^ (z >> 31)) & 0x7FFFFFFF


@pytest.fixture
def sweep_file(tmp_path, simple_yaml) -> Path:
    # A cell spread, so the Monte Carlo seed changes the physics.
    (tmp_path / "base.yaml").write_text(simple_yaml.replace("  cell:\n", SPREAD + "  cell:\n", 1)
                                        .replace("duration_s: 600", "duration_s: 300"))
    p = tmp_path / "sweep.yaml"
    p.write_text(SWEEP)
    return p


def _files(d: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(d.iterdir())}


def test_sweep_expands_as_documented(sweep_file):
    sw = packsim.load_sweep(sweep_file)
    assert sw.name == "capsweep" and len(sw) == 4
    assert sw.keys == ["pack.cell.capacity_Ah", "seed"]
    assert Path(sw.output_dir) == sweep_file.parent / "capsweep-results"
    seeds = [splitmix64_seed(7, i) for i in range(2)]
    assert [packsim.monte_carlo_seed(7, i) for i in range(2)] == seeds
    # The first grid key varies slowest, the seed fastest.
    want = [("2.0", seeds[0]), ("2.0", seeds[1]), ("3.0", seeds[0]), ("3.0", seeds[1])]
    for (index, cid, params), (cap, seed) in zip(sw.cases, want):
        assert params == [("pack.cell.capacity_Ah", cap), ("seed", str(seed))]
        assert cid == f"{index:04d}" and sw.result_path(index).endswith(f"case_{cid}.h5")
        text = sw.case_yaml(index)
        assert f"capacity_Ah: {cap}" in text and f"seed: {seed}" in text
    back = pickle.loads(pickle.dumps(sw))  # what Dask ships to its workers
    assert (back.cases, back.keys, back.base_text, back.output_dir) == (sw.cases, sw.keys, sw.base_text, sw.output_dir)


def test_local_batch_is_the_cli_batch(cli, sweep_file, tmp_path):
    done = subprocess.run([str(cli), "batch", str(sweep_file), "-o", str(tmp_path / "cli"), "-q"],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    res = packsim.batch(sweep_file, output_dir=tmp_path / "py", threads=2)
    assert res.ok and (res.n_ok, res.n_failed, res.n_skipped, res.threads) == (4, 0, 0, 2)
    assert _files(tmp_path / "py") == _files(tmp_path / "cli")  # every result and summary.csv, byte for byte

    # The table holds what summary.csv and the result files hold.
    with open(res.csv_path, newline="") as f:
        rows = list(csv.DictReader(f))
    table = res.table
    assert list(table["case"]) == [r["case"] for r in rows] == ["0000", "0001", "0002", "0003"]
    assert list(table["status"]) == ["ok"] * 4 and list(table["error"]) == [None] * 4
    for i, path in enumerate(res.paths):
        r = packsim.load(path)
        assert Path(path) == tmp_path / "py" / f"case_{i:04d}.h5"
        assert table["seed"][i] == r.seed == packsim.monte_carlo_seed(7, i % 2)
        assert table["pack.cell.capacity_Ah"][i] == [2.0, 2.0, 3.0, 3.0][i]
        assert f"capacity_Ah: {table['pack.cell.capacity_Ah'][i]}" in r.scenario_yaml
        for k, v in r.summary.items():
            assert float(rows[i][k]) == pytest.approx(v, rel=1e-9, abs=1e-12) if not isinstance(v, str) \
                else rows[i][k] == v
            assert table[k][i] == pytest.approx(v, rel=1e-9, abs=1e-12) if not isinstance(v, str) else table[k][i] == v
    # The spread and the capacity both change the physics.
    assert len(set(table["energy_stranded_Wh"])) == 4
    assert res.load("0003").summary == packsim.load(res.paths[3]).summary


def _cluster(processes: bool):
    distributed = pytest.importorskip("distributed")
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=processes,
                                       dashboard_address=":0", silence_logs=40)
    return cluster, distributed.Client(cluster)


@pytest.mark.parametrize("processes", [False, True], ids=["threads", "processes"])
def test_dask_gives_the_local_files_and_table(sweep_file, tmp_path, processes, monkeypatch):
    if processes:  # worker processes import packsim as this process does
        monkeypatch.setenv("PYTHONPATH", os.pathsep.join(p for p in sys.path if p))
    local = packsim.batch(sweep_file, output_dir=tmp_path / "local")
    cluster, client = _cluster(processes)
    with cluster, client:
        on_dask = packsim.batch(sweep_file, client, output_dir=tmp_path / "dask")
        again = packsim.batch(sweep_file, client, output_dir=tmp_path / "dask")
        with pytest.raises(ValueError, match="threads applies to local runs"):
            packsim.batch(sweep_file, client, threads=2)
    assert on_dask.engine == "dask" and on_dask.ok and on_dask.n_skipped == 0
    assert _files(tmp_path / "dask") == _files(tmp_path / "local")
    pd = pytest.importorskip("pandas")
    pd.testing.assert_frame_equal(on_dask.table.drop(columns="path"), local.table.drop(columns="path"))
    assert again.n_skipped == 4 and _files(tmp_path / "dask") == _files(tmp_path / "local")


def test_resume_skips_complete_results_only(sweep_file, tmp_path):
    out = tmp_path / "out"
    first = packsim.batch(sweep_file, output_dir=out)
    before = _files(out)
    second = packsim.batch(sweep_file, output_dir=out)
    assert second.n_skipped == 4 and _files(out) == before
    assert second.columns == first.columns
    # A truncated result is not complete: only that case runs again, to the same bytes.
    (out / "case_0002.h5").write_bytes(before["case_0002.h5"][:1000])
    third = packsim.batch(sweep_file, output_dir=out)
    assert third.n_skipped == 3 and [o["skipped"] for o in third.outcomes] == [True, True, False, True]
    assert _files(out) == before
    fresh = packsim.batch(sweep_file, output_dir=out, resume=False)
    assert fresh.n_skipped == 0 and _files(out) == before


@pytest.mark.parametrize("engine", ["threads", "dask"])
def test_a_failing_case_is_recorded_and_the_others_finish(sweep_file, tmp_path, engine):
    # Each value is valid on the base; the second pair is not (v_max_V below v_min_V).
    sweep = {"name": "soc", "base": str(sweep_file.parent / "base.yaml"),
             "zip": {"pack.cell.v_min_V": [3.0, 3.9, 3.0], "pack.cell.v_max_V": [4.3, 3.5, 4.3]}}
    if engine == "threads":
        res = packsim.batch(sweep, output_dir=tmp_path / "out")
    else:
        cluster, client = _cluster(False)
        with cluster, client:
            res = packsim.batch(sweep, client, output_dir=tmp_path / "out")
    assert (res.n_ok, res.n_failed) == (2, 1) and not res.ok
    assert list(res.table["status"]) == ["ok", "failed", "ok"]
    assert res.paths[1] is None and res.paths[0] and res.paths[2]
    err = res.errors["0001"]
    assert "v_max_V" in err and "(sweep soc, case 0001)" in err
    assert res.table["error"][1] == err
    assert math.isnan(res.table["energy_delivered_Wh"][1])
    with pytest.raises(ValueError, match="case 0001 failed"):
        res.load(1)
    with open(res.csv_path, newline="") as f:
        rows = list(csv.DictReader(f))
    assert [r["status"] for r in rows] == ["ok", "failed", "ok"] and rows[1]["error"] == err
    assert sorted(os.listdir(tmp_path / "out")) == ["case_0000.h5", "case_0002.h5", "summary.csv"]


def test_mistakes_raise_before_anything_runs(sweep_file, tmp_path):
    bad_key = {"base": str(sweep_file.parent / "base.yaml"), "grid": {"pack.cell.capacity_ah": [2.0]}}
    with pytest.raises(packsim.ScenarioError, match="did you mean 'capacity_Ah'"):
        packsim.batch(bad_key, output_dir=tmp_path / "never")
    assert not (tmp_path / "never").exists()
    out_of_range = {"base": str(sweep_file.parent / "base.yaml"), "grid": {"pack.initial_soc": [0.9, 1.5]}}
    with pytest.raises(packsim.ScenarioError, match=r"grid\.pack\.initial_soc: .*1\.5 is out of range; allowed \[0, 1\]"):
        packsim.batch(out_of_range, output_dir=tmp_path / "never")
    assert not (tmp_path / "never").exists()
    text = SWEEP.replace("grid:", "gird:")
    with pytest.raises(packsim.ScenarioError) as ei:
        packsim.batch(text, base_dir=sweep_file.parent)
    assert (ei.value.file, ei.value.line, ei.value.field) == ("<string>", 3, "gird")
    with pytest.raises(packsim.ScenarioError, match="has 1 values but zip"):
        packsim.load_sweep({"base": str(sweep_file.parent / "base.yaml"),
                            "zip": {"pack.series": [2, 3], "load.current_A": [1.0]}})


def test_sweep_spellings_agree(sweep_file):
    import yaml
    from_file = packsim.load_sweep(sweep_file)
    from_text = packsim.load_sweep(SWEEP, base_dir=sweep_file.parent)
    from_dict = packsim.load_sweep(yaml.safe_load(SWEEP), base_dir=sweep_file.parent)
    for other in (from_text, from_dict):
        assert other.cases == from_file.cases and other.base_text == from_file.base_text
        assert other.output_dir == from_file.output_dir
    assert packsim.load_sweep(from_file) is from_file


def test_table_without_pandas_is_a_dict_of_columns(sweep_file, tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "pandas", None)
    res = packsim.batch(sweep_file, output_dir=tmp_path / "out")
    assert isinstance(res.table, dict) and res.table is res.columns
    assert res.table["case"] == ["0000", "0001", "0002", "0003"] and res.table["pack.cell.capacity_Ah"][2] == 3.0


def test_bad_arguments(sweep_file):
    with pytest.raises(TypeError, match="sweep must be"):
        packsim.batch(42)
    with pytest.raises(FileNotFoundError):
        packsim.batch("no_such_sweep.yaml")
    with pytest.raises(TypeError, match="dask.distributed.Client"):
        packsim.batch(sweep_file, client="tcp://127.0.0.1:8786")
    with pytest.raises(TypeError, match="threads must be an int"):
        packsim.batch(sweep_file, threads=2.0)
    with pytest.raises(ValueError, match="threads must be >= 1"):
        packsim.batch(sweep_file, threads=0)
    with pytest.raises(TypeError, match="resume must be a bool"):
        packsim.batch(sweep_file, resume="yes")
    with pytest.raises(TypeError, match="output_dir must be a path"):
        packsim.batch(sweep_file, output_dir=3)
    with pytest.raises(ValueError, match="master_seed must be >= 0"):
        packsim.monte_carlo_seed(-1, 0)
    sw = packsim.load_sweep(sweep_file)
    with pytest.raises(IndexError, match="out of range"):
        sw.result_path(4)
