"""packsim.batch on a 2-worker Dask LocalCluster at the scale of a real sweep (20 cases):
every case finishes to the bytes a serial run writes, with at most `max_in_flight` cases
submitted at once; a killed batch resumes computing only the cases it had not finished
(a result file is trusted by its content, the case's scenario text with its seed, not by
its name); a failing case is reported and the others finish."""
from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

import packsim

distributed = pytest.importorskip("distributed")

SPREAD = "  spread: {capacity_rel_sd: 0.05, r0_rel_sd: 0.05, initial_soc_sd: 0.01}\n"
SWEEP = """\
name: mc20
base: base.yaml
grid:
  pack.initial_soc: [0.9, 0.8]
monte_carlo: {samples: 10, master_seed: 11}
"""
N = 20


@pytest.fixture
def sweep_file(tmp_path, simple_yaml) -> Path:
    (tmp_path / "base.yaml").write_text(simple_yaml.replace("  cell:\n", SPREAD + "  cell:\n", 1)
                                        .replace("duration_s: 600", "duration_s: 120"))
    p = tmp_path / "sweep.yaml"
    p.write_text(SWEEP)
    return p


@pytest.fixture
def client():
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False,
                                       dashboard_address=":0", silence_logs=40)
    with cluster, distributed.Client(cluster) as c:
        yield c


def _files(d: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(d.iterdir())}


def test_twenty_cases_match_a_serial_run_bit_for_bit(sweep_file, tmp_path, client):
    serial = packsim.batch(sweep_file, output_dir=tmp_path / "serial", threads=1)
    assert serial.ok and len(serial) == N

    seen_in_flight = []
    real_submit = client.submit

    def counting_submit(*args, **kwargs):  # cases submitted and not yet finished, at each submit
        seen_in_flight.append(len(seen_in_flight) - len(_journal(tmp_path / "dask")))
        return real_submit(*args, **kwargs)

    client.submit = counting_submit
    try:
        res = packsim.batch(sweep_file, client, output_dir=tmp_path / "dask", max_in_flight=3)
    finally:
        del client.submit
    assert res.ok and (res.n_ok, res.n_skipped, res.engine) == (N, 0, "dask")
    assert len(seen_in_flight) == N and max(seen_in_flight) <= 2  # the 3rd is submitted with 2 held
    # Same result files and summary.csv as the serial run; the journal is gone once done.
    assert _files(tmp_path / "dask") == _files(tmp_path / "serial")
    # 10 spread draws at two initial SOCs: 20 different races.
    assert len(set(res.table["seed"])) == N // 2
    assert len(set(res.table["energy_stranded_Wh"])) == N


KILLER = """\
import sys, distributed, packsim
cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False,
                                   dashboard_address=":0", silence_logs=40)
client = distributed.Client(cluster)
packsim.batch(sys.argv[1], client, output_dir=sys.argv[2], max_in_flight=2)
print("FINISHED")
"""


def _journal(out: Path) -> list[dict]:
    path = out / "summary.running.jsonl"
    if not path.exists():
        return []
    return [json.loads(line) for line in path.read_text().splitlines() if line.endswith("}")]


def test_a_killed_batch_resumes_with_only_the_rest(sweep_file, tmp_path, client):
    serial = packsim.batch(sweep_file, output_dir=tmp_path / "serial", threads=1)
    out = tmp_path / "dask"
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in sys.path if p))
    proc = subprocess.Popen([sys.executable, "-c", KILLER, str(sweep_file), str(out)], env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.monotonic() + 300  # a guard against a hang, not a timing check
        while len(_journal(out)) < 5 and proc.poll() is None and time.monotonic() < deadline:
            time.sleep(0.05)
        proc.send_signal(signal.SIGKILL)  # no clean-up of any kind: a lost machine
    finally:
        stdout, stderr = proc.communicate()
    assert "FINISHED" not in stdout, "the batch ended before it could be killed"
    journal = _journal(out)
    assert len(journal) >= 5 and all(j["ok"] for j in journal)
    complete = sorted(p.name for p in out.glob("case_*.h5"))
    assert len(complete) < N and not (out / "summary.csv").exists()

    # A stale file under a case's name (another case's result: another seed) is not trusted.
    stale = complete[0]
    other = f"case_{(int(stale[5:9]) + 1) % N:04d}.h5"
    (out / stale).write_bytes((tmp_path / "serial" / other).read_bytes())

    res = packsim.batch(sweep_file, client, output_dir=out)
    assert res.ok
    skipped = sorted(f"case_{c[1]}.h5" for c, o in zip(res.sweep.cases, res.outcomes) if o["skipped"])
    assert skipped == [c for c in complete if c != stale]
    assert res.n_skipped == len(complete) - 1
    assert all(o["wall_s"] > 0 for o in res.outcomes if not o["skipped"])
    assert _files(out) == _files(tmp_path / "serial")


def test_one_failing_case_is_reported_and_the_others_finish(sweep_file, tmp_path, client):
    # v_max_V below v_min_V in 10 cases (each value alone is valid: the cases fail, not the sweep)
    sweep = sweep_file.read_text().replace("grid:\n  pack.initial_soc: [0.9, 0.8]",
                                           "zip: {pack.cell.v_min_V: [3.0, 3.9], pack.cell.v_max_V: [4.3, 3.5]}")
    res = packsim.batch(sweep, client, output_dir=tmp_path / "out", base_dir=sweep_file.parent, max_in_flight=4)
    assert (res.n_ok, res.n_failed) == (10, 10)
    assert list(res.table["status"]) == ["ok"] * 10 + ["failed"] * 10
    for i in range(10, 20):
        assert "v_max_V" in res.errors[f"{i:04d}"]
    assert sorted(os.listdir(tmp_path / "out")) == [f"case_{i:04d}.h5" for i in range(10)] + ["summary.csv"]


def test_an_interrupted_batch_writes_what_finished(sweep_file, tmp_path, client, monkeypatch):
    from packsim import _dask_batch
    real = _dask_batch._journal_line
    calls = []

    def interrupt_at_the_fourth(index, case_id, outcome):  # Ctrl-C while the 4th outcome is journalled
        calls.append(case_id)
        if len(calls) == 4:
            raise KeyboardInterrupt
        return real(index, case_id, outcome)

    monkeypatch.setattr(_dask_batch, "_journal_line", interrupt_at_the_fourth)
    with pytest.raises(KeyboardInterrupt):
        packsim.batch(sweep_file, client, output_dir=tmp_path / "out", max_in_flight=2)
    monkeypatch.undo()
    import csv
    with open(tmp_path / "out" / "summary.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == N
    finished = set(calls)
    assert [r["case"] for r in rows if r["status"] == "ok"] == sorted(finished)
    assert all(r["error"] == "not run (interrupted)" for r in rows if r["case"] not in finished)
    assert len(_journal(tmp_path / "out")) == 3


def test_max_in_flight_is_checked(sweep_file, client):
    with pytest.raises(ValueError, match="max_in_flight must be >= 1"):
        packsim.batch(sweep_file, client, max_in_flight=0)
    with pytest.raises(ValueError, match="max_in_flight applies to Dask runs"):
        packsim.batch(sweep_file, max_in_flight=2)
