"""Progress of a long run: a bar on a terminal for `packsim run` (nothing when stdout is
a file or a pipe), a callback or tqdm bar for packsim.run, and in Jupyter a widget that
leaks no line to the kernel's stdout. A run with progress is the same run."""
from __future__ import annotations

import os
import pty
import subprocess
import sys

import numpy as np
import pytest

import packsim

SCENARIO = "eco_marathon_12s"


def test_callback_sees_simulated_time_and_the_run_is_unchanged():
    calls = []
    r = packsim.run(SCENARIO, progress=lambda t, end: calls.append((t, end)))
    plain = packsim.run(SCENARIO)
    for k in plain.keys():
        if plain[k].dtype.names is None:
            assert r[k].tobytes() == plain[k].tobytes(), k
    times = [t for t, _ in calls]
    end = calls[0][1]
    assert end == pytest.approx(plain.time_s[-1], abs=plain.attrs[""]["tick_s"] * 2)
    assert times == sorted(times) and times[0] == 0.0
    assert 90 <= len(calls) <= 101  # every 1 % of the run
    assert np.all(np.diff(times) >= 0.01 * end - 1e-9)


def test_progress_true_writes_nothing_to_stdout(capsys):
    pytest.importorskip("tqdm")
    packsim.run(SCENARIO, progress=True)
    assert capsys.readouterr().out == ""
    with pytest.raises(TypeError, match="progress"):
        packsim.run(SCENARIO, progress="yes")


def test_cli_draws_a_bar_on_a_terminal_only(cli, tmp_path):
    out = tmp_path / "r.h5"
    leader, follower = pty.openpty()
    proc = subprocess.Popen([str(cli), "run", SCENARIO, "-o", str(out)], stdout=follower, stderr=subprocess.PIPE)
    os.close(follower)
    chunks = []
    while True:
        try:
            data = os.read(leader, 4096)
        except OSError:
            break
        if not data:
            break
        chunks.append(data)
    assert proc.wait() == 0
    os.close(leader)
    text = b"".join(chunks).decode()
    import re
    shown = [int(p) for p in re.findall(r"\]\s+(\d+)%", text)]
    assert shown and shown == sorted(shown) and shown[0] == 0 and shown[-1] >= 98, shown
    assert "\x1b[K" in text and "energy" in text  # the bar is cleared before the summary
    piped = subprocess.run([str(cli), "run", SCENARIO, "-o", str(out)], capture_output=True, text=True)
    assert piped.returncode == 0 and "simulated" not in piped.stdout and "\r" not in piped.stdout


def test_jupyter_progress_is_a_widget_not_stdout_lines(tmp_path):
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    pytest.importorskip("ipywidgets")
    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_code_cell(f"import packsim\nr = packsim.run({SCENARIO!r}, progress=True)\n"
                                          "r.summary['duration_s'] > 0")]
    env_path = os.pathsep.join(p for p in sys.path if p)
    os.environ["PYTHONPATH"] = env_path
    nbclient.NotebookClient(nb, timeout=120, kernel_name="python3", resources={"metadata": {"path": str(tmp_path)}}).execute()
    outputs = nb.cells[0].outputs
    assert not [o for o in outputs if o.get("output_type") == "stream" and o.get("name") == "stdout"], outputs
    assert any(o.get("output_type") == "display_data" and "application/vnd.jupyter.widget-view+json" in o.get("data", {})
               for o in outputs), outputs
    assert any(o.get("output_type") == "execute_result" for o in outputs)


def test_a_run_to_its_end_reports_its_end():
    """A 60 s run at a 10 ms tick reported 59.4 s of 60 last (the run loop does not ask
    its condition at the last tick), so a callback's bar stopped at 99 % on a run that
    had finished. The run's last tick is now reported once after it."""
    calls = []
    scen = {"pack": {"series": 2, "cell": {"preset": "lipo_5Ah"}}, "load": {"current_A": 2.0},
            "run": {"duration_s": 60.0}}
    r = packsim.run(scen, progress=lambda t, end: calls.append((t, end)))
    assert r.time_s[-1] == 60.0
    assert calls[-1] == (60.0, 60.0)
    assert len(calls) == 101  # 0 %, 1 %, ..., 100 %
