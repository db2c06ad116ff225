"""packsim.run + Result.save and `packsim run` produce the same HDF5 file, byte for
byte, for the same scenario and seed; `packsim plot` draws packsim.plot's figures."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np

import packsim
from stored import assert_as_stored


def test_python_equals_cli_bit_for_bit(cli, default_scenario, tmp_path):
    out_cli = tmp_path / "cli.h5"
    subprocess.run([str(cli), "run", default_scenario, "-o", str(out_cli), "--seed", "7", "-q"], check=True)
    r = packsim.run(default_scenario, seed=7)
    out_py = tmp_path / "py.h5"
    r.save(out_py)
    assert out_py.read_bytes() == out_cli.read_bytes()
    # And the CLI's file holds the arrays held in memory (float channels to their
    # stated resolution).
    f = packsim.load(out_cli)
    assert_as_stored(f, r)
    assert f.seed == 7 and f.attrs[""] == r.attrs[""]


def test_different_seed_differs(cli, default_scenario, tmp_path):
    out = tmp_path / "cli.h5"
    subprocess.run([str(cli), "run", default_scenario, "-o", str(out), "--seed", "8", "-q"], check=True)
    r = packsim.run(default_scenario, seed=7)
    assert not np.array_equal(packsim.load(out)["measured/cell_voltage_mV"], r["measured/cell_voltage_mV"])


def _pythonpath() -> str:
    return os.pathsep.join(p for p in sys.path if p)


def test_cli_plot_writes_the_figures(cli, race, tmp_path):
    src = tmp_path / "race.h5"
    race.save(src)
    env = dict(os.environ, PACKSIM_PYTHON=sys.executable)
    done = subprocess.run([str(cli), "plot", str(src), "-o", str(tmp_path / "png")], env=env,
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    written = sorted(Path(p).name for p in done.stdout.split())
    expected = sorted(Path(p).name for p in packsim.plot.plot_all(race, tmp_path / "py"))
    assert written == expected and len(written) >= 4
    for name in written:
        data = (tmp_path / "png" / name).read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 10_000


def test_cli_plot_errors_are_clear(cli, tmp_path):
    missing = subprocess.run([str(cli), "plot", str(tmp_path / "none.h5")], capture_output=True, text=True)
    assert missing.returncode == 2 and "no such result file" in missing.stderr
    junk = tmp_path / "junk.h5"
    junk.write_text("not hdf5")
    env = dict(os.environ, PACKSIM_PYTHON=sys.executable)
    bad = subprocess.run([str(cli), "plot", str(junk)], capture_output=True, text=True, env=env)
    assert bad.returncode == 2 and "not a packsim result file" in bad.stderr
    env = dict(os.environ, PACKSIM_PYTHON="/nonexistent/python3")
    nopy = subprocess.run([str(cli), "plot", str(junk)], capture_output=True, text=True, env=env)
    assert nopy.returncode == 1
    assert "needs Python 3 with numpy, h5py and matplotlib" in nopy.stderr and "PACKSIM_PYTHON" in nopy.stderr
